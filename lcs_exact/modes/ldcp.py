"""LDCP_kappa(x0) (5.10)-(5.12) by the LCP sequence of Theorems 6.8-6.10, as linear forms in x0.

When the leading column matrix N is a P-matrix, the unknowns u^j enter in stages i = 1..kappa
(Theorem 6.9): with I (u lexicographically positive), J (y positive) and K (undecided) from the
earlier stages, y_I = 0 and u_J = 0 leave an LCP on K with the Schur complement
N_KK - N_KI N_II^{-1} N_IK, a P-matrix (the proof of Theorem 6.8), solved by Murty's method on
forms (:func:`lcs_exact.lcp.murty`).  The solution is built as forms in the state; a state
enters only through :func:`~lcs_exact.rational.sign_of_form`.  Results:
:func:`ldcp` -> :class:`LDCPSolution`; :func:`ldcp_modes` -> S^n_LDCP(x0) (Theorem 6.10);
:func:`impulse_forms` -> the impulse of the unique initial solution (3.6).
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from itertools import combinations
from typing import Any

from flint import fmpq_mat

from ..errors import IllPosed
from ..interfaces import SystemLike
from ..algebra import basis_inputs, murty_signs
from .mode import format_mode
from ..algebra import MAX_KAPPA, hstack, is_zero, selection_matrix, sign_of_form, submatrix, to_int, zeros
from ..numbers import as_state

__all__ = ["LDCPSolution", "ldcp", "ldcp_modes", "impulse_forms", "lcp_sequence", "stage_lcp", "require_N_P"]


def _rational(x0) -> bool:
    """Whether a solution's x0 is held as Q^n (its values computed) or as an exact vector (forms)."""
    return isinstance(x0, fmpq_mat) and x0.ncols() == 1


def _evaluate(forms: fmpq_mat, x0):
    """forms . x0 for a rational x0 (a value); the forms themselves for an exact x0."""
    return forms * x0 if _rational(x0) else forms


@dataclass(frozen=True)
class LDCPSolution:
    """The solution of LDCP_kappa(x0) (unique up to ``undetermined`` entries, Theorem 6.9).

    ``u[j]``, ``y[i]`` (j, i = -n+1 .. kappa) are k x 1 vectors for a rational x0, or k x n
    forms (value = form . x0) for an exact-real x0.  ``undetermined`` lists the (index, j) of
    entries u^j_index that LDCP_kappa leaves free (set to 0 here).  ``modes`` is S^kappa_LDCP(x0).
    """

    lcs: Any
    x0: Any
    kappa: int
    u: dict
    y: dict
    active: frozenset  # I: u lexicographically positive
    inactive: frozenset  # J: y lexicographically positive
    undecided: frozenset  # K: u and y zero so far
    undetermined: frozenset
    modes: frozenset = field(default_factory=frozenset)

    @property
    def impulse(self) -> dict:
        """{i: u^{-i}} for i = 0..n-1: the impulsive part sum u^{-i} delta^{(i)} (3.6)."""
        return {i: self.u[-i] for i in range(self.lcs.n)}

    def equations(self) -> list[tuple]:
        """The equations (5.10): a list of (i, c_i, {j: H_{i-j}}) meaning y^i = c_i + sum H_{i-j} u^j.

        c_i = C A^{i-1} x0 for i >= 1 (k x 1, or k x n forms) and 0 for i <= 0; only nonzero
        H_{i-j} are listed.
        """
        lcs, n = self.lcs, self.lcs.n
        out = []
        apow = None
        for i in range(-n + 1, self.kappa + 1):
            if i >= 1:
                apow = lcs.C if i == 1 else apow * lcs.A
                c = _evaluate(apow, self.x0)
            else:
                c = zeros(lcs.k, 1 if _rational(self.x0) else n)
            coeffs = {j: lcs.markov(i - j) for j in range(-n + 1, i + 1) if not is_zero(lcs.markov(i - j))}
            out.append((i, c, coeffs))
        return out

    def equations_text(self) -> str:
        """The equations (5.10) as text, as printed in section 7 for k = 1."""
        lines = []
        for i, c, coeffs in self.equations():
            terms = []
            if _rational(self.x0) and self.lcs.k == 1:
                if c[0, 0] != 0:
                    terms.append(str(c[0, 0]))
                for j in sorted(coeffs, reverse=True):
                    h = coeffs[j][0, 0]
                    mono = f"u^{j}"
                    terms.append(mono if h == 1 else f"-{mono}" if h == -1 else f"{h}*{mono}")
            else:
                if not is_zero(c):
                    terms.append("C A^%d x0" % (i - 1))
                terms += [f"H{i - j} u^{j}" for j in sorted(coeffs, reverse=True)]
            rhs = " + ".join(terms).replace("+ -", "- ") if terms else "0"
            lines.append(f"y^{i} = {rhs}")
        return "\n".join(lines)

    def __repr__(self):
        return (f"<LDCP_{self.kappa} solution: I = {format_mode(self.active)}, undecided K = "
                f"{format_mode(self.undecided)}, S = {sorted(format_mode(m) for m in self.modes)}>")


def require_N_P(lcs: SystemLike):
    wp = lcs.well_posedness()
    if not wp.N_is_P:
        why = "; ".join(wp.reasons) or "N is not a P-matrix"
        raise IllPosed("LDCP_kappa is solved by the LCP sequence of Theorem 6.9, which needs the "
                       f"leading column matrix N to be a P-matrix: {why}. Use select_modes(x0, method='rcp').")


def ldcp(lcs: SystemLike, x0: Any, kappa: int) -> LDCPSolution:
    """Solve LDCP_kappa(x0) (5.10)-(5.12) when N is a P-matrix (Theorems 6.9, 6.10).

    Theorem 6.9 gives y^i = 0 for i <= 0 and u_l^j = 0 for j <= -eta_l.  The remaining unknowns
    enter in stages i = 1..kappa: v_l = u_l^{i - eta_l} with column N_{.l}, so
    y^i = z^i + N v with z^i known.  With I (u lexicographically positive), J (y positive) and
    K (undecided) from the earlier stages, y_I = 0 and v_J = 0 leave an LCP on K with the Schur
    complement N_KK - N_KI N_II^{-1} N_IK, a P-matrix (the proof of Theorem 6.8).

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    kappa : int
        The number of stages (LDCP_kappa, (5.10)-(5.12)).
    """
    kappa = to_int(kappa, "kappa", -lcs.n + 1, MAX_KAPPA)
    require_N_P(lcs)
    x = as_state(lcs, x0)
    n, k = lcs.n, lcs.k
    eta = lcs.leading_column_indices()
    U: dict[int, fmpq_mat] = {j: zeros(k, n) for j in range(-n + 1, kappa + 1)}  # u^j as forms
    Y: dict[int, fmpq_mat] = {i: zeros(k, n) for i in range(-n + 1, kappa + 1)}
    I: set[int] = set()
    J: set[int] = set()
    for i, urows, y in lcp_sequence(lcs, x, kappa, I, J):
        for (l, j), row in urows.items():
            if j == i - eta[l]:
                for c in range(n):
                    U[j][l, c] = row[0, c]
        Y[i] = y
    K = frozenset(range(k)) - I - J
    undetermined = frozenset((l, j) for l in range(k) for j in range(max(kappa - eta[l] + 1, -n + 1), kappa + 1))
    modes = frozenset(frozenset(I) | frozenset(c) for r in range(len(K) + 1) for c in combinations(sorted(K), r))
    q = x.known_rational()
    x0 = q if q is not None else x  # a rational x0 is shown (and its values computed) as Q^n
    return LDCPSolution(lcs, x0, kappa, {j: _evaluate(f, x0) for j, f in U.items()},
                        {i: _evaluate(f, x0) for i, f in Y.items()}, frozenset(I), frozenset(J), K,
                        undetermined, modes)


def ldcp_modes(lcs: SystemLike, x: fmpq_mat) -> set:
    """S_LDCP^n(x0) of Theorem 6.10 (N a P-matrix, x a state column): the LCP sequence of
    :func:`ldcp`, stopped at the first stage after which every index is in I or J - I and J
    only grow, so later stages cannot change the modes {I ∪ K' : K' ⊆ K}."""
    require_N_P(lcs)
    k = lcs.k
    I: set[int] = set()
    J: set[int] = set()
    for _ in lcp_sequence(lcs, x, lcs.n, I, J, outputs=False):
        if len(I) + len(J) == k:
            break
    K = sorted(set(range(k)) - I - J)
    return {frozenset(I) | frozenset(c) for r in range(len(K) + 1) for c in combinations(K, r)}


def impulse_forms(lcs: SystemLike, x) -> list[fmpq_mat]:
    """[U_0, ..., U_{n-1}]: the impulse u^{-p} = U_p x0 of the unique initial solution at x
    (Theorem 6.9, N a P-matrix) as k x n forms, valid at x (the LCP stages fix their branches
    there).  u_l^j = 0 for j <= -eta_l, so the stages i <= max(eta) hold the whole impulse: no
    rational-function data of any mode is built.

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x : ExactVector
        The state at which the forms hold.
    """
    require_N_P(lcs)
    n, k = lcs.n, lcs.k
    eta = lcs.leading_column_indices()
    U = [zeros(k, n) for _ in range(n)]
    I: set[int] = set()
    J: set[int] = set()
    for i, urows, _ in lcp_sequence(lcs, x, max(max(eta), 1), I, J, outputs=False):
        for (l, j), row in urows.items():
            if j == i - eta[l] and j <= 0:
                for c in range(n):
                    U[-j][l, c] = row[0, c]
    return U


def lcp_sequence(lcs: SystemLike, x: fmpq_mat, kappa: int, I: set, J: set, outputs: bool = True):
    """The stages i = 1..kappa of Theorem 6.9 (see :func:`ldcp`), growing I and J in place.

    Yields (i, u, y^i): u maps (l, j) to the row u_l^j (a 1 x n form) for the nonzero unknowns
    found so far (a mapping read on demand: mode selection never reads it), y^i is k x n.  Stage s
    finds the unknowns v_l = u_l^{s - eta_l} as the rows of one k x n matrix V_s, so the known
    part of a later stage, y^i = C A^{i-1} x + sum_j H_{i-j} u^j, is C A^{i-1} + sum_s H'_{i-s} V_s
    with H'_d the k x k matrix whose column l is column l of H_{d + eta_l}: one product a stage,
    not one a row (on long runs of large systems most of the columns are zero).  ``outputs``
    False: y^i is not formed (None; mode selection and the impulse read only I, J and u)."""
    n, k = lcs.n, lcs.k
    eta = lcs.leading_column_indices()
    wp = lcs.well_posedness()  # N, computed once with the report
    N = wp.N if wp.N is not None else lcs.leading_column_matrix()
    shifted: dict[int, fmpq_mat | None] = {}  # d -> H'_d, None if zero

    def h_shifted(d: int):
        if d not in shifted:
            if len(set(eta)) == 1:  # one relative degree (a mechanical system's contacts): H_{d + eta}
                H = lcs.markov(d + eta[0])
            else:
                H = hstack(*[submatrix(lcs.markov(d + eta[l]), None, [l]) for l in range(k)], nrows=k)
            shifted[d] = None if is_zero(H) else H
        return shifted[d]

    stages: list[tuple[int, fmpq_mat]] = []  # (s, V_s); row l of V_s is u_l^{s - eta_l}
    for i in range(1, kappa + 1):
        z = lcs.output_map(i - 1)  # C A^{i-1}
        for s, V in stages:
            H = h_shifted(i - s)
            if H is not None:
                z = z + H * V
        v, signs = _stage(N, z, x, sorted(I), sorted(J))
        # rows whose unknown u_l^{i - eta_l} precedes the window -n+1 .. of (5.10) are not unknowns
        low = [l for l in range(k) if i - eta[l] < -n + 1]
        stages.append((i, v if not low else _zero_rows(v, low)))
        y = z + N * v if outputs else None
        # I and J grow by the rows of K = rest whose v or y the stage's LCP certified positive
        vpos = {l for l, (sv, _) in signs.items() if sv > 0}
        I.update(vpos)
        J.update(l for l, (_, sy) in signs.items() if sy > 0 and l not in vpos)
        yield i, _StageRows(list(stages), eta, n), y


class _StageRows(Mapping):
    """(l, j) -> the row u_l^j (1 x n) of the stages so far, nonzero rows only, read on demand."""

    def __init__(self, stages: list, eta: list, n: int):
        self._stages, self._eta, self._n = stages, eta, n
        self._rows: dict | None = None

    def _data(self) -> dict:
        if self._rows is None:
            self._rows = {}
            n = self._n
            for s, V in self._stages:
                e = V.entries()
                for l in range(V.nrows()):
                    if any(e[l * n:(l + 1) * n]):
                        self._rows[l, s - self._eta[l]] = fmpq_mat(1, n, e[l * n:(l + 1) * n])
        return self._rows

    def __getitem__(self, key):
        return self._data()[key]

    def __iter__(self):
        return iter(self._data())

    def __len__(self):
        return len(self._data())


def _zero_rows(v: fmpq_mat, rows: list[int]) -> fmpq_mat:
    """v with ``rows`` set to 0 (a copy)."""
    v = fmpq_mat(v)
    for l in rows:
        for c in range(v.ncols()):
            v[l, c] = 0
    return v


def stage_lcp(N: fmpq_mat, z: fmpq_mat, x, I: list[int], J: list[int]) -> fmpq_mat:
    """One stage of the LCP sequence: v with v_J = 0, (z + N v)_I = 0, LCP on K (forms, k x n)."""
    return _stage(N, z, x, I, J)[0]


def _stage(N: fmpq_mat, z: fmpq_mat, x, I: list[int], J: list[int]) -> tuple[fmpq_mat, dict]:
    """(v, signs) of :func:`stage_lcp`: ``signs`` maps each l in K to the certified signs at x
    of (v_l, y_l), y = z + N v, as the LCP on K read them (on K, y_K = q + M v_K of the Schur
    complement LCP; v_l = 0 off its basis and y_l = 0 on it): the stage's new I and J without
    evaluating any form again."""
    k, n = z.nrows(), z.ncols()
    K = [l for l in range(k) if l not in I and l not in J]
    v = zeros(k, n)
    vK = zeros(0, n)
    signs: dict = {}
    if K:
        if I:
            # eliminate v_I = -N_II^{-1} (z_I + N_IK v_K): Schur complement LCP on K
            NII = submatrix(N, I, I)
            a = NII.solve(submatrix(z, I, None))  # N_II^{-1} z_I
            b = NII.solve(submatrix(N, I, K))  # N_II^{-1} N_IK
            q = submatrix(z, K, None) - submatrix(N, K, I) * a
            M = submatrix(N, K, K) - submatrix(N, K, I) * b
        elif len(K) == k:  # the whole LCP (the first stage): no copies
            q, M = z, N
        else:
            q, M = submatrix(z, K, None), submatrix(N, K, K)
        if len(K) == 1:  # a 1 x 1 LCP (M > 0): Murty's first step decides it (no pivoting tableau)
            sq = sign_of_form(q, x)
            vK = -q / M[0, 0] if sq < 0 else zeros(1, n)
            signs[K[0]] = (1, 0) if sq < 0 else (0, sq)
        else:
            basis, ss = murty_signs(M, q, x)
            vK = basis_inputs(M, q, sorted(basis))
            signs = {l: ((ss[r], 0) if r in basis else (0, ss[r])) for r, l in enumerate(K)}
        v = vK if len(K) == k else selection_matrix(K, k).transpose() * vK
    if I:
        NII = submatrix(N, I, I)
        rhs = submatrix(z, I, None) + (submatrix(N, I, K) * vK if K else zeros(len(I), n))
        v = v - selection_matrix(I, k).transpose() * NII.solve(rhs)
    return v, signs
