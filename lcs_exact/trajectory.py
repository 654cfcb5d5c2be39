"""Results of a simulation: :class:`Event` and :class:`Trajectory` (Algorithm 7.1's output).

Every number is an exact real (:mod:`lcs_exact.reals`): ``.closed_form`` where proven,
``.ball(digits)`` / ``.decimal(digits)`` certified to any number of digits.  Indices are 0-based.
A trajectory stopped early (limit, accumulation of events, deadlock, unresolved sign) is
``partial`` and says why in ``stop_reason``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from flint import fmpq_mat

from .modes import format_mode
from .reals import ExactVector, ProjectedVector, Real, as_real

__all__ = ["Event", "Trajectory", "PhaseRecord"]

SCHEMA = "lcs-exact/trajectory/1"


@dataclass(frozen=True)
class Event:
    """An event (section 4.5): a phase ends or the state jumps.

    ``modes`` is the re-initialization chain (4.9): the modes I_1, I_2, ... whose projections
    were applied, ``multiplicity`` their number m(τ); ``mode_after`` is the mode of the next
    continuous phase (the smallest admissible mode, Remark 4.8); ``mode_before`` is None at
    t = 0.  ``impulse`` maps i to u^{-i} (the coefficient of δ^{(i)}) of the first jump.
    ``triggers`` names the constraints whose sign change ended the phase (``"y_0"``, ``"u_1"``).
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
        chain = " -> ".join(format_mode(m) for m in self.modes) or "no jump"
        return (f"Event(t={_short(self.time)}, {mb} => {format_mode(self.mode_after)}, jumps: {chain}, "
                f"x- = {self.state_before!r}, x+ = {self.state_after!r})")

    def _repr_latex_(self):
        import sympy
        t = sympy.latex(self.time.closed_form) if self.time.closed_form is not None else self.time.decimal(15)
        return rf"$t = {t}:\ {_latex_mode(self.mode_before or frozenset())} \to {_latex_mode(self.mode_after)}$"


@dataclass(frozen=True)
class PhaseRecord:
    """A continuous phase on [t0, t1] (t1 None while open) in mode ``phase.mode``."""

    t0: Real
    t1: Real
    phase: Any


def _short(r: Real) -> str:
    if r.closed_form is not None:
        return str(r.closed_form)
    return r.decimal(15).split(" +/-")[0]


class Trajectory:
    """The solution of an LCS on [0, t_end] produced by Algorithm 7.1."""

    def __init__(self, lcs, x0: ExactVector, t_end: Real, digits: int):
        self.lcs, self.x0, self.t_end, self.digits = lcs, x0, t_end, digits
        self.events: list[Event] = []
        self.phases: list[PhaseRecord] = []
        self.assumptions: list[str] = []
        self.partial = False
        self.stop_reason: str | None = None
        self.elapsed = 0.0

    @property
    def certified(self) -> bool:
        """True iff no unresolved zero was assumed (every sign decision is proven)."""
        return not self.assumptions

    # --- evaluation ---------------------------------------------------------------------------
    def _phase_at(self, t: Real) -> PhaseRecord:
        if not self.phases:
            raise ValueError("the trajectory has no continuous phase")
        if t < self.phases[0].t0:
            raise ValueError(f"t = {_short(t)} is before the start of the trajectory")
        for rec in self.phases:
            if t is rec.t1 or t <= rec.t1:
                return rec
        raise ValueError(f"t = {_short(t)} is after the last computed time {_short(self.phases[-1].t1)}"
                         + (" (the trajectory is partial)" if self.partial else ""))

    def state(self, t: Any) -> ExactVector:
        """x(t), exact (t rational or an exact real); at an event time, the state after it."""
        t = as_real(t)
        for ev in self.events:  # an event exactly at t: the right limit
            if ev.time is t or (ev.time.closed_form is not None and t.closed_form is not None
                                and ev.time.closed_form == t.closed_form):
                return ev.state_after
        rec = self._phase_at(t)
        return rec.phase.state(t - rec.t0)

    def u(self, t: Any) -> ExactVector:
        """u(t) on a continuous phase (u_I = F_I x, zero off I)."""
        t = as_real(t)
        rec = self._phase_at(t)
        return ProjectedVector(_full_feedback(rec.phase.mode), rec.phase.state(t - rec.t0))

    def y(self, t: Any) -> ExactVector:
        """y(t) = C x + D u on a continuous phase."""
        t = as_real(t)
        rec = self._phase_at(t)
        lcs = self.lcs
        return ProjectedVector(lcs.C + lcs.D * _full_feedback(rec.phase.mode), rec.phase.state(t - rec.t0))

    def sample(self, ts, digits: int = 17) -> list[list]:
        """[[x_1(t), ..., x_n(t)] for t in ts] as mpmath numbers correct to ``digits`` digits."""
        import mpmath
        out = []
        with mpmath.mp.workdps(digits + 5):
            for t in ts:
                x = self.state(t)
                out.append([mpmath.mpf(c.ball(digits).mid().str(digits + 3, radius=False)) for c in x])
        return out

    # --- export -------------------------------------------------------------------------------
    def to_fixture(self, digits: int | None = None) -> dict:
        """A dict in the fixture schema ``lcs-exact/trajectory/1`` (DESIGN.md section 5)."""
        d = digits or self.digits
        lcs = self.lcs

        def num(r: Real, cf=None) -> dict:
            text = r.decimal(d)
            value, _, err = text.partition(" +/- ")
            cf = r.closed_form if cf is None else cf
            return {"value": value, "error": err or "0", "exact": None if cf is None else str(cf)}

        def vec(v: ExactVector) -> list:
            cf = v.closed_form()  # derived with SymPy where possible (fixtures are written once)
            return [num(c, None if cf is None else cf[i]) for i, c in enumerate(v)]

        def mat(m: fmpq_mat) -> list:
            return [[str(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())]

        final = self.state(self.phases[-1].t1) if self.phases else self.x0
        return {
            "schema": SCHEMA,
            "system": {"A": mat(lcs.A), "B": mat(lcs.B), "C": mat(lcs.C), "D": mat(lcs.D),
                       "name": lcs.name},
            "x0": vec(self.x0),
            "t_end": num(self.t_end),
            "digits": d,
            "events": [{"time": num(e.time),
                        "mode_before": None if e.mode_before is None else sorted(e.mode_before),
                        "modes": [sorted(m) for m in e.modes], "mode_after": sorted(e.mode_after),
                        "state_before": vec(e.state_before), "state_after": vec(e.state_after),
                        "multiplicity": e.multiplicity} for e in self.events],
            "final_state": vec(final),
            "certified": self.certified,
            "assumptions": list(self.assumptions),
            "partial": self.partial,
        }

    def plot(self, **kw):
        """States and u/y against t, events and jumps marked (see lcs_exact.plotting.plot_trajectory)."""
        from .plotting import plot_trajectory
        return plot_trajectory(self, **kw)

    # --- display ------------------------------------------------------------------------------
    def __repr__(self):
        status = "certified" if self.certified else f"NOT certified ({len(self.assumptions)} assumptions)"
        head = f"<Trajectory on [0, {_short(self.t_end)}]: {len(self.events)} events, {status}"
        if self.partial:
            head += f", PARTIAL: {self.stop_reason}"
        return head + ">"

    def __str__(self):
        lines = [repr(self)] + [f"  {e!r}" for e in self.events]
        return "\n".join(lines)

    def _repr_latex_(self):
        rows = []
        for e in self.events[:50]:
            import sympy
            t = sympy.latex(e.time.closed_form) if e.time.closed_form is not None else e.time.decimal(12)
            mb = "-" if e.mode_before is None else _latex_mode(e.mode_before)
            rows.append(rf"{t} & {mb} & {_latex_mode(e.mode_after)} & {e.multiplicity} \\")
        body = "\n".join(rows)
        return (r"$\begin{array}{llll} t & I^- & I^+ & m \\ \hline " + body + r"\end{array}$")


def _latex_mode(m) -> str:
    return r"\{" + ", ".join(str(i) for i in sorted(m)) + r"\}" if m else r"\emptyset"


def _full_feedback(mode) -> fmpq_mat:
    """k x n matrix with rows F_I on I and zero rows elsewhere."""
    lcs = mode.lcs
    F = mode.feedback()
    out = fmpq_mat(lcs.k, lcs.n)
    for r, i in enumerate(mode.I):
        for j in range(lcs.n):
            out[i, j] = F[r, j]
    return out
