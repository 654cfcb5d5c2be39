"""The standard scenes of lcs_exact.examples (DESIGN.md section 7), each against an answer derived
here: free fall and Newton's law by hand, the generalised Newton law's impact LCP solved by hand,
oscillations about the spring's equilibrium, the rectifier's conduction and decay, and a grounded
twin of the floating full-wave bridge."""
from __future__ import annotations

import mpmath
import pytest
import sympy
from flint import arb, fmpq, fmpq_mat

from lcs_exact import simulate
from lcs_exact.errors import ZenoDetected
from lcs_exact.numbers.balls import workprec
from lcs_exact.builders.circuits import circuit
from lcs_exact.examples import ball_column, ball_on_spring, newtons_cradle, sine_rectifier
from lcs_exact.sources import sine


def mp(x, digits=40):
    return mpmath.mpf(x.ball(digits).mid().str(digits + 10, radius=False))


def test_ball_on_a_spring_keeps_hitting_the_floor():
    """q'' = -(q - 12) - 10 + u: oscillation about q_eq = 2.  From q = 6 at rest: q = 2 + 4 cos t
    reaches the floor when cos t = -1/2, t = 2 pi/3, at speed 4 sin(2 pi/3) = 2 sqrt 3.  From
    the floor at speed v: q = 2 - 2 cos t + v sin t vanishes again at t = 2 pi - 2 atan(v/2)
    (sin(t/2) (2 sin(t/2) + v cos(t/2)) = 0), landing at speed v; e = 1/2 halves it."""
    spring = ball_on_spring()
    tr = simulate(spring, spring.embed([6, 0]), 25)
    assert tr.certified
    t, v = sympy.Rational(0), 2 * sympy.sqrt(3)
    t = 2 * sympy.pi / 3
    assert sympy.simplify(tr.events[0].time.closed_form - t) == 0
    with mpmath.workdps(50):
        tt, vv = mpmath.mpf(2) * mpmath.pi / 3, 2 * mpmath.sqrt(3)
        for ev in tr.events:
            assert abs(mp(ev.time) - tt) < mpmath.mpf(10) ** -35
            assert abs(mp(ev.state_before[1]) + vv) < mpmath.mpf(10) ** -35
            vv /= 2
            assert abs(mp(ev.state_after[1]) - vv) < mpmath.mpf(10) ** -35
            tt += 2 * mpmath.pi - 2 * mpmath.atan(vv / 2)
    assert len(tr.events) == 5  # 2.09, 6.95, 12.4, 18.3, 24.3 in [0, 25]


def test_the_column_of_beads():
    """Beads 0 and 1 rest on the floor (r = 1/20: q0 = 1/20, q1 = 3/20); bead 2 falls from 1/2 and
    touches bead 1 at q2 = 1/4 after t1 = sqrt(2 (1/4) / 10) = sqrt(5)/10, at speed sqrt 5.  All
    three contacts are closed: with W = E E^T = [[1, -1, 0], [-1, 2, -1], [0, -1, 2]] and
    q = (1 + e) y'(-) = (0, 0, -3 sqrt(5)/2), lambda = (3 sqrt(5)/2)(1, 1, 1) solves the impact
    LCP (W lambda = -q), so only bead 2 rebounds, at e sqrt 5: a bouncing ball on a resting
    stack, accumulating at 3 t1 and resting at (1/20, 3/20, 1/4) after it."""
    col = ball_column(3)
    tr = simulate(col, col.embed(["1/20", "3/20", "1/2", 0, 0, 0]), 3)
    assert tr.certified
    t1 = sympy.sqrt(5) / 10
    want = [t1, t1 + t1, t1 + t1 + t1 / 2]
    assert all(sympy.simplify(e.time.closed_form - w) == 0 for e, w in zip(tr.events, want))
    ev = tr.events[0]
    assert sympy.simplify(ev.state_after.closed_form()[5] - sympy.sqrt(5) / 2) == 0
    assert ev.state_after.closed_form()[3:5] == [0, 0] and ev.modes == (frozenset({0, 1, 2}),)
    (acc,) = tr.accumulations
    assert sympy.simplify(acc.time.closed_form - 3 * t1) == 0
    rest = fmpq_mat([[fmpq(1, 20)], [fmpq(3, 20)], [fmpq(1, 4)], [0], [0], [0], [1]])
    assert tr.state(3).known_rational() == rest


@pytest.mark.slow
def test_a_long_column_run_leaves_the_growing_field_for_certified_numerics():
    """Siconos' column (g = 9.81, e = 9/10, r = 1/10), bead 0 on the floor, beads 1 and 2 falling
    from 1/2 and 1: bead 1 lands on bead 0 at t1 = sqrt(2 (1/5) / g) = sqrt(40/981).  Every exact
    event adjoins a square root to the field of the times; past polyroots.MAX_EXACT_SIZE the
    phases are searched numerically (certified) instead of costing seconds per sign test.  Bead 1
    then bounces to rest on bead 0 while bead 2 flies: each flight 2v/g, v' = e v, so from the last
    listed impact (time t_k, bead 1 leaving at v_k) T* = t_k + 2 v_k / (g (1 - e)); the accumulation
    is proven (lcs_exact.accumulations.bounces: it used to stop the run), crossed, and beads 0 and 1 rest
    (q = 1/10, 3/10; the floor carries 2 m g, the beads' contact m g) while bead 2 bounces on them."""
    col = ball_column(3, g="981/100", e="9/10", radius="1/10")
    tr = simulate(col, col.embed(["1/10", "1/2", 1, 0, 0, 0]), 3, max_events=300, time_limit=60)
    assert tr.certified and not tr.partial and len(tr.accumulations) == 1
    assert sympy.simplify(tr.events[0].time.closed_form - sympy.sqrt(sympy.Rational(40, 981))) == 0
    assert tr.events[0].modes == (frozenset({0, 1}),)
    assert len(tr.events) > 90
    times = [e.time.ball(20) for e in tr.events]
    assert all(a < b for a, b in zip(times, times[1:]))  # certified, strictly increasing
    acc = tr.accumulations[0]
    last = tr.events[acc.first_event]  # the last impact listed before the window (bead 2 lands after T*)
    with mpmath.workdps(50):
        num = lambda r: mpmath.mpf(r.ball(35).mid().str(40, radius=False))  # noqa: E731
        t_star = num(last.time) + 2 * num(last.state_after[4]) / (mpmath.mpf("9.81") * (1 - mpmath.mpf("0.9")))
        assert abs(num(acc.time) - t_star) < mpmath.mpf(10) ** -30
        end, u = tr.state(3), tr.u(3)
        assert abs(num(end[0]) - mpmath.mpf("0.1")) < 1e-30 and abs(num(end[1]) - mpmath.mpf("0.3")) < 1e-30
        assert abs(num(u[0]) - mpmath.mpf("19.62")) < 1e-28 and abs(num(u[1]) - mpmath.mpf("9.81")) < 1e-28
    assert tr.phases[-1].mode == frozenset({0, 1}) and float(end[2]) > 0.5  # bead 2 still in flight


def test_newtons_cradle_touching_and_spaced():
    """Three unit balls touching, ball 0 at speed 1, e = 1: W = [[2, -1], [-1, 2]] and
    q = 2 y'(-) = (-2, 0) give lambda = (4/3, 2/3): v(+) = (-1/3, 2/3, 2/3) (momentum 1 and energy
    1/2 kept; the generalised Newton law is not the 'ideal' cradle).  Spaced by 1 instead, the
    impacts are single: the speeds are exchanged at t = 1 and t = 2."""
    cradle = newtons_cradle(3)
    tr = simulate(cradle, [0, 0, 0, 1, 0, 0], 3)
    (ev,) = tr.events
    v = [ev.state_after.known_rational()[3 + i, 0] for i in range(3)]
    assert v == [fmpq(-1, 3), fmpq(2, 3), fmpq(2, 3)]
    assert sum(v) == 1 and sum(x * x for x in v) / 2 == fmpq(1, 2)
    spaced = simulate(cradle, [0, 1, 2, 1, 0, 0], 3)
    assert [e.time.known_rational() for e in spaced.events] == [1, 2]
    assert spaced.state(3).known_rational() == fmpq_mat([[1], [2], [3], [0], [0], [1]])  # each stops where hit


def test_half_wave_rectifier_with_a_sine_source():
    """Conducting, v(C) = sin t and the diode current C v' + v/R = cos t + sin t vanishes at
    3 pi / 4; blocking, v = sin(3 pi/4) e^{-(t - 3 pi/4)} until the source catches up with it,
    sin t = v (found by mpmath)."""
    rect = sine_rectifier()
    tr = simulate(rect, rect.embed([0]), 9)
    assert tr.events[0].time.closed_form == 3 * sympy.pi / 4
    with mpmath.workdps(50):
        t0 = 3 * mpmath.pi / 4
        t_on = mpmath.findroot(lambda t: mpmath.sin(t) - mpmath.sin(t0) * mpmath.exp(-(t - t0)), 6.4)
        assert abs(mp(tr.events[1].time) - t_on) < mpmath.mpf(10) ** -35
        # conducting again: v = sin t there, so the next turn-off is 2 pi after the first
        assert abs(mp(tr.events[2].time) - (t0 + 2 * mpmath.pi)) < mpmath.mpf(10) ** -35


def test_full_wave_bridge_with_a_floating_sine_source():
    """The source floats between a and b: while the four diodes block, its potential is free.
    The same bridge with b tied to ground by 10^12 ohm is autonomous in every mode; the states
    agree to the leak's effect."""
    floating = sine_rectifier(full_wave=True)
    src = sine(1)
    net = [("V1", "a", "b", src), ("D1", "a", "p"), ("D2", "b", "p"), ("D3", "0", "a"), ("D4", "0", "b"),
           ("R1", "p", "0", 1), ("C1", "p", "0", 1), ("Rg", "b", "0", 10 ** 12)]
    grounded = circuit(net)
    ta = simulate(floating, floating.embed([0]), 12)
    tb = simulate(grounded, grounded.embed([0]), 12)
    assert ta.certified and tb.certified and any(p.undetermined for p in ta.phases)
    for k in range(1, 13):
        a, b = ta.state(k).ball(30), tb.state(k).ball(30)
        with workprec(128):
            assert all(abs(x - y) <= arb("1e-9") for x, y in zip(a, b))
    # the bridge rectifies both half-waves: v(C1) = |sin t| while a pair conducts, so the first
    # turn-off is where the current cos t + sin t of the load and C vanishes, at 3 pi / 4
    assert ta.events[0].time.closed_form == 3 * sympy.pi / 4


def _elastic_column_reference(q, v, T, floor, g=10):
    """Event times and the final (q, v) of beads above a floor (the lowest bead reflects at height
    ``floor``), equal masses and e = 1 (a collision exchanges the two velocities), in mpmath at
    the working precision: free fall between events, so a gap between neighbours changes
    linearly (same acceleration) and the lowest bead's height quadratically."""
    times, t = [], mpmath.mpf(0)
    gap = mpmath.mpf(1) / 10
    while True:
        cands = []
        h, w = q[0] - floor, v[0]  # the lowest bead: h + w s - g s^2 / 2 = 0
        s = (w + mpmath.sqrt(w * w + 2 * g * h)) / g
        cands.append((s, "floor"))
        for i in range(len(q) - 1):
            dgap, dv = q[i + 1] - q[i] - gap, v[i + 1] - v[i]
            if dv < 0:
                cands.append((-dgap / dv, i))
        s, who = min(cands, key=lambda c: c[0])
        if t + s > T + mpmath.mpf(10) ** -40:
            s = T - t
            return times, [x + y * s - g * s * s / 2 for x, y in zip(q, v)], [y - g * s for y in v]
        q = [x + y * s - g * s * s / 2 for x, y in zip(q, v)]
        v = [y - g * s for y in v]
        t += s
        times.append(t)
        if who == "floor":
            v[0] = -v[0]
        else:
            v[who], v[who + 1] = v[who + 1], v[who]


def test_elastic_column_of_four_beads_reaches_an_event_exactly_at_the_horizon():
    """Beads evenly spaced by 4/10 above a bead resting on the floor, e = 1: bead 1 lands on bead
    0 at sqrt(2/25) = sqrt(2)/5, the beads exchange speeds in turn, and after 21 more impacts
    bead 1 lands on bead 0 again exactly at t = 2, at speed 4.
    Every time against an independent mpmath event loop at 60 digits; the event at the
    horizon is proven to lie on it (the state at 2 is x(2+)), and the energy 32 is kept exactly.
    (The times' exact forms stay of degree <= 4 over Q: Ca.compact keeps them small.)"""
    col = ball_column(4, e="1")
    q0 = [fmpq(1, 20) + fmpq(i, 10) + fmpq(4 * i, 10) for i in range(4)]
    tr = simulate(col, col.embed(q0 + [0] * 4), 2, digits=40)
    assert tr.certified and tr.status.name == "COMPLETE"
    with mpmath.workdps(60):
        ref, _, _ = _elastic_column_reference([mpmath.mpf(int(x.p)) / int(x.q) for x in q0[1:]], [mpmath.mpf(0)] * 3, 2,
                                              floor=mpmath.mpf(3) / 20)
        assert len(tr.events) == len(ref) == 22
        for ev, t in zip(tr.events, ref):
            assert abs(mp(ev.time) - t) < mpmath.mpf(10) ** -38
    last = tr.events[-1]
    assert last.time.rational() == 2 and last.modes == (frozenset({0, 1}),)
    assert last.state_before.known_ca()[5].to_fmpq() == -4 and last.state_after.known_ca()[5].to_fmpq() == 4
    x = tr.state(2).known_ca()
    energy = sum(((x[4 + i] * x[4 + i]) / 2 + x[i] * 10 for i in range(4)), x[8] * 0)
    assert (energy - 32).is_zero() is True


@pytest.mark.slow
def test_elastic_column_of_five_beads_with_an_impact_exactly_at_the_horizon():
    """Five beads in the air, evenly spaced, e = 1: equal masses exchange velocities, so the beads
    move as five independent balls bouncing on the floor ("ghosts" passing through each other)
    in the coordinates q_i - i/10, dropped from 5, 5.5, 6, 6.5 and 7 above the floor.  The
    lowest ghost lands at t = sqrt(2 h / g) = 1 and again at exactly t = 3: bead 0's velocity
    jumps from -10 to +10 there.  The event times and x(3) against the independent mpmath event
    loop; the times of such a run are algebraic of degree <= 8 over Q, but their Calcium
    expressions would need minimal polynomials of degree 360 on the way (Ca.compact)."""
    col = ball_column(5, e="1")
    q0 = [fmpq(101, 20) + fmpq(3 * i, 5) for i in range(5)]
    tr = simulate(col, col.embed(q0 + [0] * 5), 3, digits=30)
    assert tr.certified and tr.status.name == "COMPLETE"
    with mpmath.workdps(60):
        ref, q, v = _elastic_column_reference([mpmath.mpf(int(x.p)) / int(x.q) for x in q0], [mpmath.mpf(0)] * 5, 3,
                                              floor=mpmath.mpf(1) / 20)
        assert len(tr.events) == len(ref) == 26
        for ev, t in zip(tr.events, ref):
            assert abs(mp(ev.time, 30) - t) < mpmath.mpf(10) ** -28
        x = tr.state(3)
        for i in range(5):
            assert abs(mp(x[i], 30) - q[i]) < mpmath.mpf(10) ** -28
            assert abs(mp(x[5 + i], 30) - v[i]) < mpmath.mpf(10) ** -28
    last = tr.events[-1]
    assert last.time.rational() == 3
    assert last.state_before.known_ca()[5].to_fmpq() == -10 and last.state_after.known_ca()[5].to_fmpq() == 10
