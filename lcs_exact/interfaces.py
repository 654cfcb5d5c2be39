"""The system (4.1) as the layers below :mod:`lcs_exact.system` see it: a typing protocol.

Modes, mode selection, impacts, phases and the driver take the system as an argument but sit
below :class:`~lcs_exact.system.LCS` in the import order (imports point down only), so they
cannot name the class.  :class:`SystemLike` states what they use of it; ``LCS`` satisfies it.
It is a static description (``typing.Protocol``), never checked at run time.

:class:`AccumulationWindow` is the other way round: a base class checked at run time.  The
motion on [t_k, T*) of a proven accumulation is kept among a trajectory's phases but is not a
:class:`~lcs_exact.phases.phase.Phase`; the trajectory, the driver and the drawing code tell
the two apart by ``isinstance(phase, AccumulationWindow)``.  The windows live in ``dynamics``,
which the drawing code (``display``) sits below, so the class that names them lives here, below
both.
"""
from __future__ import annotations

from typing import Any, Iterable, Protocol

from flint import fmpq_mat

__all__ = ["SystemLike", "AccumulationWindow"]


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

    def output_map(self, i: int) -> fmpq_mat: ...

    def leading_column_indices(self) -> tuple: ...

    def leading_column_matrix(self) -> fmpq_mat: ...

    def well_posedness(self) -> Any: ...

    def mode(self, I: Iterable[int]) -> Any: ...


class AccumulationWindow:
    """The motion on [t_k, T*) of a proven accumulation of infinitely many events, kept as a
    phase: a geometric law's scaled cycles (``accumulations.accumulation.ScaledCycle``) or a bounce
    accumulation's iterated cycle map (``accumulations.bounces.BounceWindow``).  Unlike a continuous
    phase it has no spectrum and no mode of its own over the window: it gives its states and
    inputs itself (``state(dt)``, ``output(dt, kind)``, ``ball_state(dt, prec)``), its implied
    event times (``offsets``, ``event_times``), and it has no value at T* itself."""

    def flight_mode(self, t: float) -> Any:
        """The mode of the flight holding the time t (a float: a plot's sample), or None when it
        cannot be placed.  Here the window's ``mode`` (its flights share one); a geometric law's
        window maps t into its reference cycle (``ScaledCycle.flight_mode``).

        Parameters
        ----------
        t : float
        """
        return getattr(self, "mode", None)
