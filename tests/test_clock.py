"""Event times in absolute time through the sources' clock (lcs_exact.phases.clock).

Hand solutions derived here, independently of the engine:

* RL half-wave rectifier (V = sin t, ideal diode, R = L = 1, i(0) = 0): while the diode conducts
  i' = sin t - i, so i = (sin t - cos t + e^{-t}) / 2; it turns off at t1, the first t > 0 with
  sin t - cos t + e^{-t} = 0 (found here by mpmath), and stays off (i = 0) until the source turns
  positive again at 2 pi; from there i = (sin s - cos s + e^{-s}) / 2 with s = t - 2 pi, off again
  at 2 pi + t1, on at 4 pi.
* RC half-wave rectifier (R = C = 1, v(0) = 0): v = sin t while the diode conducts, off where the
  diode current cos t + sin t vanishes (3 pi / 4), then v = sin(3pi/4) e^{3pi/4 - t} until
  sin t = v (t2, mpmath), v = sin t again until cos t + sin t = 0 at 11 pi / 4.
* Full-wave bridge (R = C = 1): v = |sin t| while conducting, off at 3pi/4 + k pi, then
  v = (sqrt 2 / 2) e^{3pi/4 + k pi - t}: at t = 3 pi (all diodes blocking since 11 pi / 4),
  v = (sqrt 2 / 2) e^{-pi/4}, sin = 0, cos = -1.
"""
from __future__ import annotations

import mpmath
import pytest
import sympy
from flint import fmpq_mat

from lcs_exact import LimitExceeded, simulate
from lcs_exact.phases.clock import SourceClock, autonomous_block
from lcs_exact.examples import sine_rectifier
from lcs_exact.models import circuit

mpmath.mp.dps = 40


def rl_rectifier():
    return circuit("V1 1 0 sine(1,1)\nD1 1 2\nR1 2 3 1\nL1 3 0 1")


def t1_rl():
    return mpmath.findroot(lambda t: mpmath.sin(t) - mpmath.cos(t) + mpmath.exp(-t), 3.94)


def agrees(real, value, digits=30):
    """The certified ball of ``real`` at ``digits`` digits contains the mpmath value."""
    b = real.ball(digits)
    return abs(mpmath.mpf(b.mid().str(45, radius=False)) - value) < mpmath.mpf(10) ** (-digits + 1) * max(1, abs(value))


def test_the_autonomous_block_is_the_sources_states():
    lcs = rl_rectifier()
    assert lcs.state_names[1:] == ("sin(t)", "cos(t)")
    assert autonomous_block(lcs.A, lcs.B) == [1, 2]
    clock = SourceClock.of(lcs, lcs.embed([0]))
    assert [[clock.S[i, j] for j in range(2)] for i in range(2)] == [[0, 1], [-1, 0]]
    assert [clock.z0[i, 0] for i in range(2)] == [0, 1]
    # a block that feeds the rest but is fed by it is not autonomous
    assert autonomous_block(fmpq_mat([[0, 1], [1, 0]]), fmpq_mat([[1], [0]])) == []


def test_an_rl_rectifier_switching_on_exactly_at_the_horizon_2pi_ends_there():
    lcs = rl_rectifier()
    tr = simulate(lcs, lcs.embed([0]), 2 * sympy.pi)  # was UnresolvedSign: no ball separates 2 pi
    assert len(tr.events) == 2
    assert agrees(tr.events[0].time, t1_rl())
    assert tr.events[0].time.closed_form is None
    assert tr.events[1].time.closed_form == 2 * sympy.pi
    x = tr.state(2 * sympy.pi)
    assert [x[i].ball(30).contains(v) for i, v in enumerate((0, 0, 1))] == [True] * 3
    assert x[0].decimal(20) == "0"  # i = 0 on the blocking phase, proven: an exact zero prints as one


def test_source_driven_events_get_closed_forms_in_absolute_time():
    lcs = rl_rectifier()
    tr = simulate(lcs, lcs.embed([0]), 15)
    times = [e.time for e in tr.events]
    assert [t.closed_form for t in times] == [None, 2 * sympy.pi, None, 4 * sympy.pi]
    assert agrees(times[2], 2 * mpmath.pi + t1_rl())


def test_a_half_wave_rc_rectifier_turning_off_at_the_horizon_11pi_over_4():
    rect = sine_rectifier()
    T = sympy.Rational(11, 4) * sympy.pi
    tr = simulate(rect, rect.embed([0]), T)
    t2 = mpmath.findroot(lambda t: mpmath.sin(t) - mpmath.sqrt(2) / 2 * mpmath.exp(3 * mpmath.pi / 4 - t), 6.3)
    assert [e.time.closed_form for e in tr.events] == [3 * sympy.pi / 4, None, T]
    assert agrees(tr.events[1].time, t2)
    x = tr.state(T)
    r = mpmath.sqrt(2) / 2
    assert agrees(x[0], r) and agrees(x[1], r) and agrees(x[2], -r)


def test_a_full_wave_bridge_at_odd_multiples_of_pi():
    rect = sine_rectifier(full_wave=True)
    want = mpmath.sqrt(2) / 2 * mpmath.exp(-mpmath.pi / 4)
    for k in (3, 5):  # an event (the floating source's sign) exactly at t_end = k pi
        tr = simulate(rect, rect.embed([0]), k * sympy.pi)
        x = tr.state(k * sympy.pi)
        assert agrees(x[0], want)
        assert x[1].ball(30).contains(0) and agrees(x[2], -1)
        assert tr.events[-1].time.closed_form == k * sympy.pi


@pytest.mark.slow
def test_closed_forms_of_a_long_driven_run_are_derived_without_recursion():
    """760 events of the RL rectifier: the off-events at 2k pi + t1 and the on-events at 2k pi
    (k = 1..380); the last on-event's closed form 760 pi is derived through the chain of the 759
    earlier event times in a loop (a recursion would pass Python's limit of 1000 frames)."""
    lcs = rl_rectifier()
    with pytest.raises(LimitExceeded) as info:
        simulate(lcs, lcs.embed([0]), 2400, max_events=760)
    events = info.value.trajectory.events
    assert len(events) == 760
    assert events[-1].time.closed_form == 760 * sympy.pi
    assert events[-2].time.closed_form is None and agrees(events[-2].time, 758 * mpmath.pi + t1_rl(), 15)


def test_the_closed_form_of_an_event_time_does_not_depend_on_what_was_read_before():
    """A driven 3-state system (source 2 sin 2t) whose last event before 71/10 is u_1 switching at
    2 pi (checked independently by a fuzzer with mpmath's expm of the mode's dynamics from the
    event state before it, to 1e-28): on a fresh run its closed form was None, and 2 pi only once
    its digits had been asked for (the candidates were sifted against an unrefined ball)."""
    from lcs_exact import sources
    from lcs_exact.models import driven
    A = [[-1, 0, 0], [0, -1, -2], [0, 0, -1]]
    B = [[0, 0], [-1, 2], [0, 0]]
    C = [[-1, -1, -1], [0, 0, 0]]
    D = [["1/2", -1], [1, 2]]
    lcs = driven(A, B, C, D, [[-1], [-1], [-1]], [[1], [1]], w=[sources.sine(2, 2)])
    x0, T = lcs.embed([0, 2, "-1/2"]), sympy.Rational(71, 10)
    fresh = simulate(lcs, x0, T).events[-1].time
    assert fresh.closed_form == 2 * sympy.pi
    again = simulate(lcs, x0, T).events[-1].time
    assert agrees(again, 2 * mpmath.pi) and again.closed_form == 2 * sympy.pi


def test_a_source_zero_with_no_rational_multiple_of_pi_gets_its_closed_form_in_absolute_time():
    """V = sin t - 2 cos t = sqrt5 sin(t - a), a = atan 2, into the RL load: blocked from i(0) = 0
    until a; then i = (sqrt5 / 2)(sin s - cos s + e^{-s}), s = t - a, off at a + t1 (t1 the RL
    rectifier's root), blocked until V turns positive at a + 2 pi exactly, off at a + 2 pi + t1.
    The zero a + 2 pi comes from the source's own function of absolute time (SymPy's candidates,
    proven by Calcium), not from the phase that starts at a + t1; a run to that t_end ends on it."""
    lcs = circuit("V1 1 0 sine(1,1) + cosine(1,-2)\nD1 1 2\nR1 2 3 1\nL1 3 0 1")
    a, t1 = mpmath.atan(2), t1_rl()
    tr = simulate(lcs, lcs.embed([0]), 12)
    times = [e.time for e in tr.events]
    assert [t.closed_form for t in times] == [sympy.atan(2), None, sympy.atan(2) + 2 * sympy.pi, None]
    assert all(agrees(t, v) for t, v in zip(times, (a, a + t1, a + 2 * mpmath.pi, a + 2 * mpmath.pi + t1)))
    T = sympy.atan(2) + 2 * sympy.pi
    end = simulate(lcs, lcs.embed([0]), T)
    assert len(end.events) == 3 and end.events[-1].time.closed_form == T
    assert end.state(T)[0].decimal(20) == "0"


def test_a_contact_force_driven_by_a_source_touches_zero_at_pi_over_2_after_an_impact():
    """q'' + q = -2 + sin t + u against the stop q >= -1 (inelastic), from q = 1/2 at rest:
    q = -2 + (5/2) cos t + (1/2) sin t - (t/2) cos t (resonance) until it hits q = -1 at t_i
    (mpmath); then it rests on the stop with the contact force u = 1 - sin t >= 0, which touches 0
    at pi/2 and 5 pi/2 without leaving it.  The touches are at closed-form *absolute* times after
    an impact at a time with no closed form: proven through the sources' clock (was
    UnresolvedSign: 'a tangential touch?' at 4096 bits)."""
    from lcs_exact import sources
    from lcs_exact.models import mechanical
    lcs = mechanical([[1]], [[1]], [[1]], damping=[[0]], force=[sources.constant(-2) + sources.sine(1, 1)], gap=[1])
    tr = simulate(lcs, lcs.embed(["1/2", 0]), 10)
    t_i = mpmath.findroot(lambda t: -1 + mpmath.cos(t) * (mpmath.mpf(5) / 2 - t / 2) + mpmath.sin(t) / 2, 1.29)
    assert len(tr.events) == 1 and agrees(tr.events[0].time, t_i)
    q, v = tr.state(10)[:2]
    assert agrees(q, -1) and v.ball(30).contains(0)
    u = tr.u(3)[0]  # 1 - sin 3 on the stop
    assert agrees(u, 1 - mpmath.sin(3))
