"""The well-posedness report of Theorem 6.3 (with Lemma 6.6): the leading row and column indices
(Definition 6.2), the leading coefficient matrices M and N (6.1), whether each is a P-matrix and
why not (a principal minor <= 0).  ``LCS.well_posedness()`` builds it (duck-typed on the LCS:
its leading indices and matrices)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from flint import fmpq_mat

from ..errors import IllPosed
from ..algebra import p_matrix_violation
from ..algebra import mat_rows, submatrix

__all__ = ["WellPosedness", "leading_indices"]


def leading_indices(lcs: Any, rows: bool) -> tuple:
    """The leading row indices rho_j = inf{i : H^i_{j.} != 0} (``rows``), or the column indices
    eta_j = inf{i : H^i_{.j} != 0}, of Definition 6.2: ``math.inf`` when there is none.

    Parameters
    ----------
    lcs : LCS
        Read through ``k``, ``n`` and its Markov parameters ``markov(i)`` (duck-typed).
    rows : bool
        Row indices (rho) or column indices (eta).
    """
    out = []
    for j in range(lcs.k):
        idx: float | int = math.inf
        for i in range(lcs.n + 1):  # Cayley-Hamilton: rho_j, eta_j <= n when finite
            h = lcs.markov(i)
            vals = [h[j, l] for l in range(lcs.k)] if rows else [h[l, j] for l in range(lcs.k)]
            if any(v != 0 for v in vals):
                idx = i
                break
        out.append(idx)
    return tuple(out)


@dataclass(frozen=True)
class WellPosedness:
    """Report of Theorem 6.3 (with Lemma 6.6).  ``bool(report)`` is ``report.well_posed``.

    Attributes
    ----------
    rho : tuple
        The leading row indices rho_1, ..., rho_k of G(s) (Definition 6.2; ``math.inf`` for a zero row).
    eta : tuple
        The leading column indices eta_1, ..., eta_k (Definition 6.2).
    M : fmpq_mat or None
        The leading row coefficient matrix (6.1); None when some rho_j is infinite.
    N : fmpq_mat or None
        The leading column coefficient matrix (6.1); None when some eta_j is infinite.
    M_is_P : bool
        M is defined and a P-matrix.
    N_is_P : bool
        N is defined and a P-matrix.
    M_violation : tuple or None
        Indices of a principal minor of M that is <= 0, or None.
    N_violation : tuple or None
        Indices of a principal minor of N that is <= 0, or None.
    reasons : tuple of str
        Why the report is not well-posed (empty when it is).
    """

    rho: tuple
    eta: tuple
    M: fmpq_mat | None
    N: fmpq_mat | None
    M_is_P: bool
    N_is_P: bool
    M_violation: tuple | None
    N_violation: tuple | None
    reasons: tuple = field(default=())

    @property
    def well_posed(self) -> bool:
        return self.M_is_P and self.N_is_P

    def __bool__(self):
        return self.well_posed

    @classmethod
    def of(cls, lcs: Any) -> "WellPosedness":
        """The report of an LCS (what ``LCS.well_posedness()`` returns).

        Parameters
        ----------
        lcs : LCS
            Read through its leading indices and matrices (duck-typed).
        """
        rho, eta = lcs.leading_row_indices(), lcs.leading_column_indices()
        reasons = []
        M = N = None
        mv = nv = None
        try:
            M = lcs.leading_row_matrix()
            mv = p_matrix_violation(M)
            if mv is not None:
                reasons.append(f"M is not a P-matrix: principal minor on {set(mv)} is "
                               f"{submatrix(M, mv, mv).det()} <= 0")
        except IllPosed as e:
            reasons.append(str(e))
        try:
            N = lcs.leading_column_matrix()
            nv = p_matrix_violation(N)
            if nv is not None:
                reasons.append(f"N is not a P-matrix: principal minor on {set(nv)} is "
                               f"{submatrix(N, nv, nv).det()} <= 0")
        except IllPosed as e:
            reasons.append(str(e))
        return cls(rho, eta, M, N, M is not None and mv is None, N is not None and nv is None, mv, nv,
                   tuple(reasons))

    def __str__(self):
        def fm(m):
            return "undefined" if m is None else "[" + "; ".join(" ".join(str(e) for e in r) for r in mat_rows(m)) + "]"
        lines = [f"Theorem 6.3 well-posedness: {'WELL-POSED' if self.well_posed else 'NOT ESTABLISHED'}",
                 f"  leading row indices rho = {self._idx(self.rho)}, M = {fm(self.M)}: "
                 f"{'P-matrix' if self.M_is_P else 'not a P-matrix'}",
                 f"  leading column indices eta = {self._idx(self.eta)}, N = {fm(self.N)}: "
                 f"{'P-matrix' if self.N_is_P else 'not a P-matrix'}"]
        if self.well_posed:
            lines.append("  every mode is autonomous (Lemma 6.6); each event has multiplicity <= 1")
        lines += [f"  why not: {r}" for r in self.reasons]
        return "\n".join(lines)

    @staticmethod
    def _idx(t):
        return "(" + ", ".join("oo" if v == math.inf else str(v) for v in t) + ")"

    def __repr__(self):
        return f"<WellPosedness well_posed={self.well_posed} rho={self._idx(self.rho)} eta={self._idx(self.eta)}>"

    def _repr_pretty_(self, p, cycle):
        p.text(str(self))
