"""The scaling symmetries of an LCS, the first half of the proof of an accumulation
(:mod:`lcs_exact.accumulations.accumulation`, whose docstring states the symmetry and the law).

An LCS is invariant under t -> rho t, x_i -> rho^{e_i} x_i, u_j -> rho^{a_j} u_j,
y_i -> rho^{b_i} y_i (rho > 0) when every nonzero entry of A, B, C, D is balanced:
A_ij != 0 => e_j = e_i - 1, B_ij != 0 => a_j = e_i - 1, C_ij != 0 => b_i = e_j,
D_ij != 0 => b_i = a_j.  :func:`symmetry_exponents` solves these difference constraints on a
graph exactly (one free shift per connected component), after moving constant offsets onto the
states when the system has a constant state (an exosystem constant).
"""
from __future__ import annotations

from collections import deque
from typing import Sequence

from flint import fmpq_mat

from ..algebra import solve_any, submatrix

__all__ = ["symmetry_exponents"]


def symmetry_exponents(lcs, active: Sequence[int] | None = None) -> dict | None:
    """Exponents of the scaling symmetries of the LCS (see the module docstring):
    ``{"x": [...], "u": [...], "y": [...], "component": {node: id}, "T": T}`` with one solution
    per connected component (add any integer to a whole component), or None when the nonzero
    pattern admits none.  ``T`` (None, or an n x n rational matrix) is a change of coordinates
    x~ = T x in which the symmetry holds: constant offsets (a gap y = q - r, a floor at height r)
    are moved onto the states by x~ = x - alpha c, c a state that never changes (an exosystem
    constant), alpha chosen so that y no longer reads c (:func:`_offset_transform`).

    >>> from lcs_exact import LCS
    >>> s = symmetry_exponents(LCS([[0, -1], [0, 0]], [[1], [0]], [[1, 0]], [[0]]))  # x' = u - c
    >>> s["x"], s["u"], s["y"]          # up to a shift: x like t, c constant, u like c, y like x
    ([0, -1], [-1], [0])

    ``active``: the symmetry of the system restricted to these constraints (the others dropped:
    their rows of C, D and columns of B, D), for a cycle in which the others never act; their
    u and y get exponent 0 (unused: u = 0 there, and y is recomputed from x).
    """
    A, B, C, D = lcs.A, lcs.B, lcs.C, lcs.D
    if active is not None:
        J = sorted(set(active))
        B, C, D = submatrix(B, None, J), submatrix(C, J, None), submatrix(D, J, J)
    out = _symmetry(lcs.n, A, B, C, D)
    if out is None or active is None:
        return out
    full = {"u": [0] * lcs.k, "y": [0] * lcs.k}
    comp = dict(out["component"])
    for r, j in enumerate(J):
        full["u"][j], full["y"][j] = out["u"][r], out["y"][r]
        comp[("u", j)], comp[("y", j)] = out["component"][("u", r)], out["component"][("y", r)]
    for j in range(lcs.k):
        if j not in J:
            comp[("u", j)] = comp[("y", j)] = -1  # no component: its shift is 0
    return {"x": out["x"], "u": full["u"], "y": full["y"], "component": comp, "T": out["T"], "active": J}


def _symmetry(n: int, A, B, C, D) -> dict | None:
    plain = _pattern_exponents(A, B, C, D)
    if plain is not None:
        return {**plain, "T": None}
    moved = _offset_transform(n, A, B, C)
    if moved is None:
        return None
    T, At, Ct = moved
    shifted = _pattern_exponents(At, B, Ct, D)
    return None if shifted is None else {**shifted, "T": T}


def _offset_transform(n: int, A, B, C):
    """(T, A~, C~) for x~ = T x = x - alpha c, with c the constant states (zero rows of A and B)
    and alpha (zero on the constant states) solving C alpha_c = -C_{.c}: in x~, y = C~ x~ has no
    constant term.  None when there is no constant state or no such alpha."""
    k = B.ncols()
    consts = [i for i in range(n) if all(A[i, j] == 0 for j in range(n)) and all(B[i, j] == 0 for j in range(k))]
    others = [i for i in range(n) if i not in consts]
    if not consts or not others:
        return None
    Co = submatrix(C, None, others)
    T = fmpq_mat(n, n)
    for i in range(n):
        T[i, i] = 1
    At, Ct = fmpq_mat(A), fmpq_mat(C)
    for c in consts:
        a = solve_any(Co, -submatrix(C, None, [c]))
        if a is None:
            return None
        alpha = fmpq_mat(n, 1)
        for r, i in enumerate(others):
            alpha[i, 0] = a[r, 0]
            T[i, c] = -a[r, 0]
        col_A = A * alpha
        col_C = C * alpha
        for i in range(n):
            At[i, c] = A[i, c] + col_A[i, 0]
        for i in range(C.nrows()):
            Ct[i, c] = C[i, c] + col_C[i, 0]
    return T, At, Ct


def _pattern_exponents(A, B, C, D) -> dict | None:
    """The difference constraints of the nonzero pattern of (A, B, C, D), solved (module docstring)."""
    n, k = A.nrows(), B.ncols()
    edges: dict = {}

    def link(a, b, w):  # value(b) = value(a) + w
        edges.setdefault(a, []).append((b, w))
        edges.setdefault(b, []).append((a, -w))

    for i in range(n):
        for j in range(n):
            if A[i, j] != 0:
                link(("x", i), ("x", j), -1)
        for j in range(k):
            if B[i, j] != 0:
                link(("x", i), ("u", j), -1)
    for i in range(k):
        for j in range(n):
            if C[i, j] != 0:
                link(("x", j), ("y", i), 0)
        for j in range(k):
            if D[i, j] != 0:
                link(("u", j), ("y", i), 0)
    nodes = [("x", i) for i in range(n)] + [("u", j) for j in range(k)] + [("y", i) for i in range(k)]
    value: dict = {}
    comp: dict = {}
    for c, start in enumerate(nodes):
        if start in value:
            continue
        value[start], comp[start] = 0, c
        queue = deque([start])
        while queue:
            a = queue.popleft()
            for b, w in edges.get(a, ()):
                if b not in value:
                    value[b], comp[b] = value[a] + w, c
                    queue.append(b)
                elif value[b] != value[a] + w:
                    return None
    return {"x": [value[("x", i)] for i in range(n)], "u": [value[("u", j)] for j in range(k)],
            "y": [value[("y", i)] for i in range(k)], "component": comp}
