"""Algorithm 7.1: mode selection, re-initialization, continuous phases and events, exactly.

    Initialization  z := x0, t := 0
    Step one        select I in S(z) (the smallest admissible mode, Remark 4.8)
    Step two        z in V_I ?  yes: step four;  no: step three
    Step three      z := P_I z, go to step one          (the re-initialization chain (4.9))
    Step four       x(t) = e^{A_I t} z, u_I = F_I x      (flow.Phase)
    Step five       θ(z, I) by certified root isolation; t := t + θ, z := x(θ-); repeat

Stops: deadlock (S(z) = ∅) -> :class:`Deadlock`; a re-initialization chain that does not end ->
:class:`ZenoDetected`; event times accumulating (geometrically shrinking phases with the limit
before t_end, Remark 4.11) -> :class:`ZenoDetected`; ``max_events`` / ``time_limit`` ->
:class:`LimitExceeded`; an undecidable sign -> :class:`UnresolvedSign`.  Each such error carries
the partial :class:`~lcs_exact.trajectory.Trajectory` in ``.trajectory``.
"""
from __future__ import annotations

import time as _time
from typing import Any

from flint import arb

from .errors import Deadlock, LCSError, LimitExceeded, ZenoDetected
from .flow import Phase, next_event, state_closed_form
from .reals import (DEFAULT_MAX_PREC, ExactVector, ExpVector, ProjectedVector, RationalReal,
                    RationalVector, as_exact_vector, as_real, assumption_policy, deadline,
                    digits_to_bits)
from .rational import vstack
from .selection import _rcp_data, select_modes
from .trajectory import Event, PhaseRecord, Trajectory

__all__ = ["simulate"]

_ZENO_WINDOW = 24


def simulate(lcs, x0: Any, t_end: Any, digits: int = 30, *, max_events: int = 1000,
             time_limit: float | None = None, allow_unresolved: bool = False,
             closed_forms: bool = True, max_prec: int | None = None) -> Trajectory:
    """Run Algorithm 7.1 from x0 on [0, t_end] and return the exact :class:`Trajectory`.

    Parameters
    ----------
    lcs : LCS
    x0 : vector
        Rational (any input LCS accepts) or an exact vector such as ``expm_action(A, -1, v)``.
    t_end : rational or exact real, >= 0
    digits : int
        Correct significant digits promised for every reported number (evaluation is on demand;
        sign decisions refine up to ``max_prec`` bits, by default max(4096, 8 * digits bits)).
    max_events, time_limit : limits; reaching one raises :class:`LimitExceeded` with the
        partial trajectory in ``.trajectory``.
    allow_unresolved : if True, an undecidable sign is assumed zero, recorded in
        ``traj.assumptions``, and the result is not ``certified``; otherwise UnresolvedSign.
    closed_forms : try to prove closed forms of event times and states (SymPy).

    Examples
    --------
    >>> from lcs_exact.models import two_carts
    >>> tr = simulate(two_carts(), [0, 1, -1, 0], 1)
    >>> tr.events[0].state_after
    (0, 1, 0, 0)
    """
    if isinstance(digits, bool) or not isinstance(digits, int) or digits < 1:
        raise ValueError(f"digits must be a positive integer, got {digits!r}")
    if x0 is None:
        raise ValueError("x0 is required: a vector of length n (rational entries or an exact vector)")
    try:
        T = as_real(t_end)
    except (LCSError, TypeError, ValueError) as e:
        raise type(e)(f"t_end: {e}") from e
    if T.sign() < 0:
        raise ValueError(f"t_end must be >= 0, got {t_end}")
    z0 = as_exact_vector(x0, lcs.n)
    if z0.n != lcs.n:
        from .errors import ShapeError
        raise ShapeError(f"x0 has length {z0.n}, expected {lcs.n}")
    mp = max_prec or max(DEFAULT_MAX_PREC, 8 * digits_to_bits(digits))
    traj = Trajectory(lcs, z0, T, digits)
    started = _time.monotonic()
    with assumption_policy(allow_unresolved, mp) as record, deadline(time_limit):
        try:
            _run(lcs, traj, z0, T, max_events, time_limit, started, closed_forms)
        except LCSError as e:
            traj.partial = True
            traj.stop_reason = f"{type(e).__name__}: {e}"
            traj.assumptions = list(record)
            traj.elapsed = _time.monotonic() - started
            e.trajectory = traj
            raise
        traj.assumptions = list(record)
    traj.elapsed = _time.monotonic() - started
    return traj


def _selection_point(z: ExactVector):
    q = z.rational()
    return q if q is not None else z


def _in_consistent_subspace(mode, z: ExactVector) -> bool:
    """Step two: z in V_I, decided form by form on the annihilator of V_I (exact or certified)."""
    W = mode._annihilator()
    q = z.rational()
    if q is not None:
        return all(v == 0 for v in (W * q).entries()) if W.nrows() else True
    from .rational import submatrix
    return all(z.sign_of_form(submatrix(W, [r], None)) == 0 for r in range(W.nrows()))


def _project(mode, z: ExactVector) -> ExactVector:
    """Step three: z := P_I z (rational stays rational)."""
    P = mode.projection()
    q = z.rational()
    if q is not None:
        return RationalVector(P * q)
    return ProjectedVector(P, z)


def _impulse(mode, z: ExactVector) -> dict:
    """{i: u^{-i}} of the initial solution in mode I from z (nonzero terms only)."""
    out = {}
    for i, U in enumerate(_rcp_data(mode)["impulse"]):
        if any(e != 0 for e in U.entries()):
            q = z.rational()
            out[i] = RationalVector(U * q) if q is not None else ProjectedVector(U, z)
    return out


def _select_and_reinitialize(lcs, z: ExactVector, t):
    """Steps one to three; returns (mode, chain of jump modes, state after, impulse)."""
    chain, impulse = [], {}
    cap = 2 ** lcs.k + lcs.n + 1
    for _ in range(cap):
        S = select_modes(lcs, _selection_point(z))
        if not S:
            raise Deadlock(f"deadlock at t = {_label(t)}: S(z) is empty at z = {z!r} (Remark 7.2)")
        I = min(S, key=lambda m: (len(m), sorted(m)))
        mode = lcs.mode(I)
        if _in_consistent_subspace(mode, z):
            return mode, chain, z, impulse
        if not chain:
            impulse = _impulse(mode, z)
        z = _project(mode, z)
        chain.append(I)
    raise ZenoDetected(f"re-initialization at t = {_label(t)} did not end after {cap} jumps "
                       "(infinite multiplicity, Remark 7.2 (2))")


def _run(lcs, traj: Trajectory, z: ExactVector, T, max_events, time_limit, started, closed_forms):
    t = RationalReal(0)
    mode_before = None
    triggers: tuple = ()
    durations: list = []
    while True:
        state_before = z
        mode, chain, z, impulse = _select_and_reinitialize(lcs, z, t)
        if chain or mode_before is not None:
            if len(traj.events) >= max_events:
                raise LimitExceeded(f"max_events = {max_events} reached: the next event is at "
                                    f"t = {_label(t)}")
            traj.events.append(Event(t, mode_before, tuple(chain), mode.index_set, state_before, z,
                                     len(chain), impulse, triggers))
        if time_limit is not None and _time.monotonic() - started > time_limit:
            raise LimitExceeded(f"time_limit = {time_limit} s reached at t = {_label(t)}")
        phase = Phase(mode, z)
        H = T - t
        if H.sign() == 0:
            traj.phases.append(PhaseRecord(t, T, phase))
            return
        hit = next_event(phase, H, closed_forms)
        if hit is None:
            traj.phases.append(PhaseRecord(t, T, phase))
            return
        theta, cons = hit
        t_new = t + theta
        z = _state_at_event(phase, theta, cons, closed_forms)
        traj.phases.append(PhaseRecord(t, t_new, phase))
        durations.append(theta)
        _check_accumulation(durations, t_new, T)
        mode_before, triggers, t = mode.index_set, tuple(c.name for c in cons), t_new


def _label(t) -> str:
    if t.closed_form is not None:
        return str(t.closed_form)
    return t.decimal(15).split(" +/-")[0]


def _state_at_event(phase: Phase, theta, cons, closed_forms: bool) -> ExactVector:
    """x(τ-) = e^{A_I θ} z, with the triggering constraints as proven-zero forms."""
    x = phase.state(theta)
    extra = vstack(*[c.g for c in cons])
    if closed_forms and not isinstance(x, RationalVector):
        cf = state_closed_form(phase, theta)
        if cf is not None and isinstance(x, ExpVector):
            x._closed = cf
            q = x.rational()
            if q is not None:
                return RationalVector(q)
    if isinstance(x, RationalVector):
        return x
    x.zero_forms = vstack(x.zero_forms, extra)
    return x


def _check_accumulation(durations: list, t_now, T) -> None:
    """Right-Zeno (Remark 4.11): phases shrinking geometrically with the limit before t_end."""
    if len(durations) < _ZENO_WINDOW:
        return
    window = durations[-_ZENO_WINDOW:]
    balls = [d.arb(64) for d in window]
    ratios = []
    for a, b in zip(balls, balls[1:]):
        if not (a > 0 and b > 0):
            return
        ratios.append(b / a)
    rho = max(ratios, key=lambda r: r.mid())
    if not rho < arb("0.95"):
        return
    if not all(r < arb("0.95") for r in ratios):
        return
    tail = balls[-1] * rho / (1 - rho)
    limit = t_now.arb(64) + tail
    if limit < T.arb(64):
        raise ZenoDetected(f"event times accumulate: {_ZENO_WINDOW} phases shrinking geometrically "
                           f"(ratio <= {float(rho.mid()):.3g}); accumulation point near t ≈ "
                           f"{float(limit.mid()):.15g} < t_end (Remark 4.11)")
