"""What a run records (section 4.5): how it ended (:class:`Status`), its events
(:class:`Event`) and its continuous phases (:class:`PhaseRecord`); a :class:`~lcs_exact.Trajectory`
holds them (:mod:`lcs_exact.phases.trajectory`, which exports these names too).
"""
from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any

from ..modes import format_mode, latex_mode
from ..numbers import ExactVector, Real

__all__ = ["Status", "Event", "PhaseRecord"]


class Status(str, enum.Enum):
    """How a run ended (diffrax's ``RESULTS``): only ``COMPLETE`` covers [0, t_end]."""

    COMPLETE = "complete"
    EVENT_LIMIT = "event limit"
    TIME_LIMIT = "time limit"
    HORIZON_LIMIT = "horizon limit"
    DEADLOCK = "deadlock"
    ZENO = "accumulation of events"
    UNRESOLVED = "unresolved sign"
    ILL_POSED = "ill-posed"
    INTERRUPTED = "interrupted"
    FAILED = "failed"


@dataclass(frozen=True)
class Event:
    """An event (section 4.5) at time tau: a phase ends or the state jumps (``traj.events``).

    Attributes
    ----------
    time : Real
        tau.
    mode_before : frozenset or None
        The mode of the phase that ends (None at t = 0).
    modes : tuple of frozenset
        The re-initialization chain (4.9): the modes I_1, I_2, ... whose projections were applied.
    mode_after : frozenset
        The mode of the next continuous phase (the smallest admissible mode, Remark 4.8).
    state_before : ExactVector
        x(tau-).
    state_after : ExactVector
        x(tau+).
    multiplicity : int
        m(tau), the number of modes in ``modes``.
    impulse : dict
        i -> u^{-i} (the coefficient of delta^{(i)}) of the first jump.
    triggers : tuple of str
        The constraints whose sign change ended the phase (``"y_0"``, ``"u_1"``).
    """

    time: Real
    mode_before: frozenset | None
    modes: tuple
    mode_after: frozenset
    state_before: ExactVector
    state_after: ExactVector
    multiplicity: int
    impulse: dict = field(default_factory=dict)
    triggers: tuple = ()

    def __repr__(self):
        mb = "—" if self.mode_before is None else format_mode(self.mode_before)
        chain = " -> ".join(format_mode(m) for m in self.modes) or \
            ("reset (schedule)" if "schedule" in self.triggers and self.state_before is not self.state_after else "no jump")
        return (f"Event(t={self.time.label()}, {mb} => {format_mode(self.mode_after)}, jumps: {chain}, "
                f"x- = {self.state_before!r}, x+ = {self.state_after!r})")

    def _repr_latex_(self):
        cf = self.time.closed_form
        if cf is not None:
            import sympy
            t = sympy.latex(cf)
        else:
            t = self.time.decimal(15).replace(" +/- ", r" \pm ")
        return rf"$t = {t}:\ {latex_mode(self.mode_before or frozenset())} \to {latex_mode(self.mode_after)}$"


@dataclass(frozen=True)
class PhaseRecord:
    """A continuous phase on [t0, t1] in ``mode`` (``phase`` evaluates x(t - t0)).
    ``undetermined``: the inputs u_j that the state does not determine on it (a floating
    network, docs/extensions.md); they are reported as undetermined, never chosen."""

    t0: Real
    t1: Real
    mode: frozenset
    phase: Any
    undetermined: frozenset = frozenset()
