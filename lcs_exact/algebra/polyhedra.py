"""Exact feasibility of systems of rational linear equalities and (strict) inequalities.

A *constraint* is ``(a, b, rel)``: the affine form a . z + b (a a sequence of rationals, b a
rational) with ``rel`` one of ``"="``, ``">"``, ``">="``.  :func:`find_point` decides whether a
system of constraints has a solution and returns one, exactly: it is the emptiness test the mode
map (:mod:`lcs_exact.modemap`) uses to prune regions, where a wrong answer would add or drop a
region, so nothing here is floating point.

Method.  Homogenize z = w / lam with lam > 0: the system becomes a cone in (w, lam) whose strict
rows (and lam > 0) may be scaled to ``>= 1``; its feasibility is then phase 1 of the simplex
method on ``fmpq`` (free variables split as w = p - q, a slack per inequality, an artificial
per row), with Bland's rule, which cannot cycle.  A returned point is checked against every
constraint before it is given back.  Sizes here are small (tens of rows); no attempt is made at
sparsity.
"""
from __future__ import annotations

from typing import Any, Iterable, Sequence

from flint import fmpq

from ..errors import InvalidArgument, LCSError
from .rational import pivot_tableau, to_fmpq

__all__ = ["Constraint", "find_point", "is_feasible", "RELATIONS", "eliminate"]

RELATIONS = ("=", ">", ">=")

Constraint = tuple  # (coefficients, constant, relation)


def _read(constraints: Iterable[Any], nvars: int) -> list[tuple[list[fmpq], fmpq, str]]:
    out = []
    for c in constraints:
        try:
            a, b, rel = c
        except (TypeError, ValueError):
            raise InvalidArgument(f"a constraint is (coefficients, constant, relation), got {c!r}") from None
        if rel not in RELATIONS:
            raise InvalidArgument(f"relation must be one of {RELATIONS}, got {rel!r}")
        a = [to_fmpq(v, "coefficient") for v in a]
        if len(a) != nvars:
            raise InvalidArgument(f"constraint has {len(a)} coefficients, expected {nvars}")
        out.append((a, to_fmpq(b, "constant"), rel))
    return out


def _phase_one(rows: list[list[fmpq]], rhs: list[fmpq], ncols: int) -> list[fmpq] | None:
    """A point x >= 0 with rows . x = rhs (rhs >= 0), or None: phase 1 with Bland's rule."""
    m = len(rows)
    if m == 0:
        return [fmpq(0)] * ncols
    width = ncols + m  # original columns, then one artificial per row
    T = [list(r) + [fmpq(1) if j == i else fmpq(0) for j in range(m)] + [rhs[i]] for i, r in enumerate(rows)]
    basis = [ncols + i for i in range(m)]
    # reduced costs of "minimize the sum of the artificials": c_j = -sum_i T[i][j] off the basis
    cost = [-sum((T[i][j] for i in range(m)), fmpq(0)) for j in range(width + 1)]
    for i in range(m):
        cost[ncols + i] = fmpq(0)
    while True:
        enter = next((j for j in range(width) if cost[j] < 0), None)
        if enter is None:
            break
        best = None
        for i in range(m):
            a = T[i][enter]
            if a > 0:
                ratio = T[i][width] / a
                if best is None or ratio < best[0] or (ratio == best[0] and basis[i] < basis[best[1]]):
                    best = (ratio, i)
        if best is None:  # unbounded direction: impossible in phase 1 (objective >= 0)
            raise LCSError("internal inconsistency: phase-1 simplex is unbounded")
        r = best[1]
        pivot_tableau(T, r, enter)
        if cost[enter] != 0:
            f = cost[enter]
            cost = [v - f * w for v, w in zip(cost, T[r])]
        basis[r] = enter
    if cost[width] != 0:  # -(sum of artificials) at the optimum
        return None
    x = [fmpq(0)] * width
    for i, j in enumerate(basis):
        x[j] = T[i][width]
    return x[:ncols]


def find_point(nvars: int, constraints: Iterable[Any]) -> tuple[fmpq, ...] | None:
    """A rational point z satisfying every constraint ``a . z + b rel 0``, or None if none exists.

    Parameters
    ----------
    nvars : int
        Number of variables (>= 0).
    constraints : iterable of (coefficients, constant, relation)
        ``relation`` is ``"="``, ``">"`` or ``">="``; coefficients and constant are rationals
        (any input :func:`lcs_exact.rational.to_fmpq` reads).

    Examples
    --------
    >>> find_point(2, [([1, 0], 0, ">"), ([0, 1], 0, ">"), ([-1, -1], 1, ">")])  # open triangle
    (1/3, 1/3)
    >>> find_point(1, [([1], 0, ">"), ([1], 0, "=")]) is None
    True
    """
    cons = _read(constraints, nvars)
    nv = nvars + 1  # (w, lam)
    # columns: p_0..p_nv-1, q_0..q_nv-1, then one slack per inequality row
    n_ineq = sum(1 for _, _, rel in cons if rel != "=") + 1  # + the row lam >= 1
    ncols = 2 * nv + n_ineq
    homog = [(a + [b], rel) for a, b, rel in cons] + [([fmpq(0)] * nvars + [fmpq(1)], ">")]  # lam > 0
    rows, rhs = [], []
    slack = 2 * nv
    for coeff, rel in homog:
        row = coeff + [-v for v in coeff] + [fmpq(0)] * n_ineq
        if rel != "=":
            row[slack] = fmpq(-1)
            slack += 1
        rows.append(row)
        rhs.append(fmpq(1) if rel == ">" else fmpq(0))  # strict rows of a cone scale to >= 1
    x = _phase_one(rows, rhs, ncols)
    if x is None:
        return None
    v = [x[i] - x[nv + i] for i in range(nv)]
    lam = v[nvars]
    if lam <= 0:
        raise LCSError("internal inconsistency: homogenized point has lam <= 0")
    z = tuple(w / lam for w in v[:nvars])
    for a, b, rel in cons:  # the exact check that makes the answer trustworthy
        val = sum((ai * zi for ai, zi in zip(a, z)), fmpq(0)) + b
        if not (val == 0 if rel == "=" else val > 0 if rel == ">" else val >= 0):
            raise LCSError(f"internal inconsistency: simplex point violates {a} . z + {b} {rel} 0")
    return z


def is_feasible(nvars: int, constraints: Sequence[Any]) -> bool:
    """True iff the system ``a . z + b rel 0`` has a solution (exact).

    >>> is_feasible(2, [([1, 1], 0, ">="), ([-1, -1], 0, ">"), ([1, -1], 0, "=")])
    False
    """
    return find_point(nvars, constraints) is not None


def eliminate(rows: Sequence[tuple], d: int) -> list[tuple]:
    """Fourier-Motzkin elimination over Q of d variables b from the inequalities
    g_r . x + h_r . b >= 0: the rows (g, label) with g . x >= 0 iff some b satisfies them all.

    ``rows`` are (g, h, label): g a sequence of rationals (the x part), h a sequence of d
    rationals, label a frozenset naming the original rows (combined rows carry the union).  A
    positive combination of valid inequalities is valid, and conversely over any ordered field
    the largest lower bound of b_j is below its smallest upper bound when the eliminated rows
    hold, so the answer is exact.  Duplicate and trivial (0 >= 0) rows are dropped.

    Parameters
    ----------
    rows : sequence of (g, h, label)
        The inequalities (above).
    d : int
        The number of variables b eliminated.

    Examples
    --------
    >>> # b >= -x0, b <= x1 (i.e. x1 - b >= 0): feasible iff x0 + x1 >= 0
    >>> [(g, sorted(label)) for g, label in eliminate([([1, 0], [1], {"a"}), ([0, 1], [-1], {"b"})], 1)]
    [([1, 1], ['a', 'b'])]
    """
    cur = []
    for g, h, label in rows:
        cur.append(([to_fmpq(x) for x in g], [to_fmpq(x) for x in h], frozenset(label)))
    for j in range(d):
        pos = [r for r in cur if r[1][j] > 0]
        neg = [r for r in cur if r[1][j] < 0]
        nxt = [r for r in cur if r[1][j] == 0]
        for gp, hp, lp in pos:
            for gn, hn, ln in neg:
                a, b = -hn[j], hp[j]  # positive multipliers: a row_p + b row_n has no b_j
                nxt.append(([a * x + b * y for x, y in zip(gp, gn)], [a * x + b * y for x, y in zip(hp, hn)], lp | ln))
        cur = _dedupe(nxt)
    return [(g, label) for g, _, label in cur if any(x != 0 for x in g)]


def _dedupe(rows: list) -> list:
    """Rows scaled to a leading entry of absolute value 1, duplicates (by coefficients) dropped."""
    seen: dict = {}
    for g, h, label in rows:
        lead = next((x for x in list(g) + list(h) if x != 0), None)
        if lead is None:
            continue  # 0 >= 0
        sc = 1 / abs(lead)
        key = tuple(x * sc for x in list(g) + list(h))
        if key not in seen:
            seen[key] = ([x * sc for x in g], [x * sc for x in h], label)
    return list(seen.values())
