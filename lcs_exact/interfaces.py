"""The system (4.1) as the layers below :mod:`lcs_exact.system` see it: a typing protocol.

Modes, mode selection, impacts, phases and the driver take the system as an argument but sit
below :class:`~lcs_exact.system.LCS` in the import order (imports point down only), so they
cannot name the class.  :class:`SystemLike` states what they use of it; ``LCS`` satisfies it.
It is a static description (``typing.Protocol``), never checked at run time.
"""
from __future__ import annotations

from typing import Any, Iterable, Protocol

from flint import fmpq_mat

__all__ = ["SystemLike"]


class SystemLike(Protocol):
    """x' = A x + B u, y = C x + D u, 0 <= y ⊥ u >= 0 (4.1) with rational data: n states, k
    complementarity pairs, Markov parameters (5.8), leading indices and matrices (6.1), modes
    (section 4) built on demand, the well-posedness report of Theorem 6.3."""

    n: int
    k: int
    A: fmpq_mat
    B: fmpq_mat
    C: fmpq_mat
    D: fmpq_mat

    def markov(self, i: int) -> fmpq_mat: ...

    def leading_column_indices(self) -> tuple: ...

    def leading_column_matrix(self) -> fmpq_mat: ...

    def well_posedness(self) -> Any: ...

    def mode(self, I: Iterable[int]) -> Any: ...
