"""schedule.py: LCS data that switch at scheduled times (models.scheduled) and sampled-data control
(models.sampled), run by simulate.  Expected values are derived here: closed forms of the RC
phases, exact polynomials of the sampled loop, and an independent mpmath integration (matrix
exponentials and root finding) of a buck converter in discontinuous conduction."""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest
import sympy as sp
from flint import fmpq

import lcs_exact as L
from lcs_exact import models


def rc_pwm():
    """v' = 1 - v while the switch is on (1/2 of each period 1), v' = -v while it is off; a second
    state is the constant 1 of the source; the pair y = v >= 0 never acts (v > 0 after t = 0)."""
    on = L.LCS([[-1, 1], [0, 0]], [[1], [0]], [[1, 0]], [[0]], state_names=["v", "1"])
    off = L.LCS([[-1, 0], [0, 0]], [[1], [0]], [[1, 0]], [[0]], state_names=["v", "1"])
    return models.scheduled([("1/2", on), ("1/2", off)], period=1)


def test_pwm_rc_switches_at_exact_times_with_closed_form_states():
    tr = L.simulate(rc_pwm(), [0, 1], 2, digits=30)
    assert [e.time.known_rational() for e in tr.events] == [fmpq(1, 2), fmpq(1), fmpq(3, 2)]
    assert all(e.triggers == ("schedule",) and e.modes == () for e in tr.events)
    # on: v -> 1 - (1 - v) e^{-1/2}; off: v -> v e^{-1/2} (derived by hand)
    q = sp.exp(sp.Rational(-1, 2))
    v = sp.Integer(0)
    for k, t in enumerate(["1/2", "1", "3/2", "2"]):
        v = 1 - (1 - v) * q if k % 2 == 0 else v * q
        got = tr.state(t)[0].closed_form
        assert sp.simplify(got - v) == 0, (t, got, v)
    between = (1 - q) * sp.exp(sp.Rational(-1, 4))  # t = 3/4: off for 1/4 after v(1/2) = 1 - e^{-1/2}
    assert abs(sp.Float(tr.state("3/4")[0].decimal(30).split()[0], 30) - between.evalf(40)) < sp.Float("1e-28")
    assert "ScheduledLCS" in repr(tr.lcs) and tr.certified


def buck():
    """A buck converter (E = 2, L = 1/10, C = 1, R = 1) with a PWM switch on for 1/4 of each period 1
    and a freewheeling diode: state (i, v, 1); the diode's pair is y = i >= 0 ⊥ u = reverse voltage
    (L i' = E s(t) - v + u); when i reaches 0 with the switch off the diode blocks (discontinuous
    conduction) until the switch closes again."""
    on = L.LCS([[0, -10, 20], [1, -1, 0], [0, 0, 0]], [[10], [0], [0]], [[1, 0, 0]], [[0]], state_names=["i", "v", "1"],
               constraint_names=["D"])
    off = L.LCS([[0, -10, 0], [1, -1, 0], [0, 0, 0]], [[10], [0], [0]], [[1, 0, 0]], [[0]], state_names=["i", "v", "1"],
                constraint_names=["D"])
    return models.scheduled([("1/4", on), ("3/4", off)], period=1)


def buck_reference(t_end: int):
    """(events, state) of the buck converter by an independent integration at 50 digits: x(t) =
    expm(A (t - s)) x(s) on each piece; in the off phase the diode turns off where i = 0
    (findroot), then i stays 0 and v' = -v."""
    with mp.workdps(50):
        A_on = mp.matrix([[0, -10, 20], [1, -1, 0], [0, 0, 0]])
        A_off = mp.matrix([[0, -10, 0], [1, -1, 0], [0, 0, 0]])
        A_blk = mp.matrix([[0, 0, 0], [0, -1, 0], [0, 0, 0]])  # i held at 0 by the blocking diode
        x = mp.matrix([0, 0, 1])
        events = []
        for k in range(t_end):
            x = mp.expm(A_on * mp.mpf(1) / 4) * x
            events.append((mp.mpf(k) + mp.mpf(1) / 4, "schedule", x.copy()))
            i_off = lambda s: (mp.expm(A_off * s) * x)[0]  # noqa: E731
            s0 = mp.findroot(i_off, 0.4)
            assert 0 < s0 < mp.mpf(3) / 4
            x = mp.expm(A_off * s0) * x
            x[0] = 0
            events.append((k + mp.mpf(1) / 4 + s0, "y_0", x.copy()))
            x = mp.expm(A_blk * (mp.mpf(3) / 4 - s0)) * x
            if k + 1 < t_end:
                events.append((mp.mpf(k + 1), "schedule", x.copy()))
        return events, x


def test_buck_converter_in_discontinuous_conduction_against_an_independent_integration():
    tr = L.simulate(buck(), [0, 0, 1], 3, digits=30)
    ref, x_end = buck_reference(3)
    assert len(tr.events) == len(ref) == 8
    with mp.workdps(50):
        for e, (t, trig, x) in zip(tr.events, ref):
            assert trig in e.triggers
            assert abs(mp.mpf(e.time.decimal(30).split()[0]) - t) < mp.mpf(10) ** -25
            for c, v in zip(e.state_after, x):
                assert abs(mp.mpf(c.decimal(30).split()[0]) - v) < mp.mpf(10) ** -25
        assert [e.mode_after for e in tr.events[:3]] == [frozenset(), frozenset({0}), frozenset()]
        for c, v in zip(tr.state(3), x_end):
            assert abs(mp.mpf(c.decimal(30).split()[0]) - v) < mp.mpf(10) ** -25
    assert tr.events[0].time.closed_form == sp.Rational(1, 4)


def sampled_loop():
    """x'' = u + w against a stop y = x >= 0, w = -x(t_k) held for 1/2."""
    plant = L.LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]], state_names=["x", "v"])
    return models.sampled(plant, [[0], [1]], [[-1, 0]], "1/2")


def test_sampled_control_with_a_stop_exact_events():
    """From x = 1, v = 0: w = -1 on [0, 1/2] (x = 1 - t^2/2: 7/8, v = -1/2), w = -7/8 on [1/2, 1]
    (x(1) = 33/64, v(1) = -15/16), w = -33/64 on [1, 3/2]: x = 33/64 - 15 s/16 - 33 s^2/128 = 0 at
    s = (-20 + sqrt 642)/11, an inelastic impact; the force holds the mass on the stop until 3/2,
    where w = -x = 0: at rest from there."""
    loop = sampled_loop()
    assert loop.embed([1, 0]).transpose().tolist() == [[1, 0, -1]]
    tr = L.simulate(loop, loop.embed([1, 0]), "5/2")
    impact = 1 + (-20 + sp.sqrt(642)) / 11
    assert [e.time.closed_form for e in tr.events] == [sp.Rational(1, 2), 1, sp.nsimplify(impact), sp.Rational(3, 2), 2]
    assert sp.simplify(tr.events[2].time.closed_form - impact) == 0
    assert [e.triggers for e in tr.events] == [("schedule",), ("schedule",), ("y_0",), ("schedule",), ("schedule",)]
    as_q = lambda m: [Fraction(int(c.p), int(c.q)) for c in m.entries()]  # noqa: E731
    assert as_q(tr.events[0].state_before.rational()) == [Fraction(7, 8), Fraction(-1, 2), -1]
    assert as_q(tr.events[0].state_after.rational()) == [Fraction(7, 8), Fraction(-1, 2), Fraction(-7, 8)]
    assert as_q(tr.events[1].state_after.rational()) == [Fraction(33, 64), Fraction(-15, 16), Fraction(-33, 64)]
    assert tr.events[2].modes == (frozenset({0}),) and tr.events[2].mode_after == frozenset({0})
    assert as_q(tr.events[3].state_after.rational()) == [0, 0, 0] and as_q(tr.state("5/2").rational()) == [0, 0, 0]


def test_a_switch_exactly_at_a_constraint_event_and_a_jump_at_a_switch():
    """x' = v, v' = u (a mass) moving at -2 from x = 1: in phase 1 the stop is at x = -1 (y = x + c,
    c = 1 a constant state), in phase 2 at x = 0 (y = x).  At the switch t = 1/2 the mass is at
    x = 0 exactly with v = -2: the new phase's stop closes with an inelastic impact at the switch
    (P_I: v -> 0), Algorithm 7.1's jump at the switch time.  Then at rest on the stop."""
    far = L.LCS([[0, 1, 0], [0, 0, 0], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 1]], [[0]], state_names=["x", "v", "c"])
    near = L.LCS([[0, 1, 0], [0, 0, 0], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 0]], [[0]], state_names=["x", "v", "c"])
    tr = L.simulate(models.scheduled([("1/2", far), (None, near)]), [1, -2, 1], 2)
    (e,) = tr.events
    assert e.time.known_rational() == fmpq(1, 2) and e.triggers == ("schedule",)
    assert e.modes == (frozenset({0}),) and e.state_before.rational().transpose().tolist() == [[0, -2, 1]]
    assert e.state_after.rational().transpose().tolist() == [[0, 0, 1]]
    # a constraint reaching 0 exactly at the switch: the same mass from x = 3/2 hits the far stop
    # (x = -1) exactly at t = 5/4 = the switch time of a schedule of phases 5/4, then free
    tr2 = L.simulate(models.scheduled([("5/4", far), (None, far)]), [fmpq(3, 2), -2, 1], 2)
    (e2,) = tr2.events
    assert e2.time.known_rational() == fmpq(5, 4) and e2.triggers == ("y_0", "schedule")
    assert e2.state_after.rational().transpose().tolist() == [[-1, 0, 1]]


def test_scheduled_runs_round_trip_through_fixtures():
    for system, x0, T in ((buck(), [0, 0, 1], 2), (sampled_loop(), sampled_loop().embed([1, 0]), 2)):
        tr = L.simulate(system, x0, T, digits=20)
        fx = L.read_fixture(tr.to_fixture(20, sample="1/8"))
        assert type(fx.lcs).__name__ == "ScheduledLCS" and fx.can_recompute
        fx.verify()  # the run repeated from the fixture's schedule agrees with every event and sample
        assert len(fx.exact.events) == len(tr.events)


@pytest.mark.parametrize("phases, period, err, fragment", [
    ([], None, L.InvalidArgument, "at least one phase"),
    ([(0, "x")], None, L.InvalidArgument, "must be an LCS"),
    ([(0, L.LCS([[0]], [[1]], [[1]], [[0]]))], None, L.InvalidArgument, "must be > 0"),
    ([(1, L.LCS([[0]], [[1]], [[1]], [[0]])), (1, L.LCS([[0, 0], [0, 0]], [[1], [0]], [[1, 0]], [[0]]))], None,
     L.ShapeError, "every phase shares"),
    ([(1, L.LCS([[0]], [[1]], [[1]], [[0]])), (1, L.LCS([[0]], [[1]], [[1]], [[0]]))], 3, L.InvalidArgument,
     "not the sum"),
    ([(None, L.LCS([[0]], [[1]], [[1]], [[0]])), (1, L.LCS([[0]], [[1]], [[1]], [[0]]))], None, L.InvalidArgument,
     "only the last phase"),
])
def test_bad_schedules_are_refused(phases, period, err, fragment):
    with pytest.raises(err, match=fragment):
        models.scheduled(phases, period)


def test_period_true_repeats_with_the_phases_total():
    assert rc_pwm().schedule.period == 1
    on, off = (p.lcs for p in rc_pwm().schedule.phases)
    assert models.scheduled([("1/2", on), ("1/2", off)], period=True).schedule.period == 1


def test_bad_sampling_is_refused():
    plant = L.LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]])
    with pytest.raises(L.InvalidArgument, match="period must be > 0"):
        models.sampled(plant, [[0], [1]], [[-1, 0]], 0)
    with pytest.raises(L.ShapeError):
        models.sampled(plant, [[0], [1]], [[-1, 0, 0]], 1)


def test_figure_of_a_schedule_uses_each_phases_system():
    """The u panel of the buck converter's figure: while the diode blocks (switch off, i = 0), u is
    its reverse voltage v(C) > 0 from the off phase's own data (the on phase's would give v - 2)."""
    import matplotlib
    matplotlib.use("Agg")
    tr = L.simulate(buck(), [0, 0, 1], 2, digits=20)
    fig = tr.plot(points=400)
    ax_u = fig.axes[1]
    t_off = float(tr.events[1].time)  # the diode turns off
    pts = [(x, y) for line in ax_u.get_lines() if len(line.get_xdata()) > 2  # the phases' lines, not markers
           for x, y in zip(*line.get_data()) if t_off + 0.01 < x < 0.99]
    assert pts and all(abs(y - float(tr.u(Fraction(x).limit_denominator(10 ** 12))[0])) < 1e-9 and y > 0.8 for x, y in pts)
    assert {t.get_text() for t in fig.axes[0].texts} >= {"phase 0", "phase 1"}  # the schedule's band
    with pytest.raises(L.Unsupported, match="one system"):
        buck().to_model("unused.json")


def test_sampled_control_of_a_plant_with_sources_reads_the_plants_states():
    """A ball under gravity (q'' = -10 + u + w, state (q, q', 1)) with w = -q(t_k) held for 1/4:
    K and Bh may be given on the plant's states alone.  From q = 1 at rest: w = -1 on [0, 1/4]:
    q = 1 - 11 t^2 / 2, so q(1/4) = 21/32, q'(1/4) = -11/4 and w(1/4) = -21/32."""
    ball = L.examples.bouncing_ball(g=10, e="1/2")
    loop = models.sampled(ball, [[0], [1]], [[-1, 0]], "1/4")
    assert loop.state_names == ("q", "q'", "1", "w_0") and loop.embed([1, 0]).transpose().tolist() == [[1, 0, 1, -1]]
    tr = L.simulate(loop, loop.embed([1, 0]), "1/2")
    e = tr.events[0]
    assert e.time.known_rational() == fmpq(1, 4) and e.triggers == ("schedule",)
    assert e.state_after.rational().transpose().tolist() == [[fmpq(21, 32), fmpq(-11, 4), 1, fmpq(-21, 32)]]


def test_compare_reads_each_events_derivative_jump_from_the_systems_in_force():
    """At the switch 1/4 the buck converter's i' jumps from 20 - 10 v to -10 v (the switch opens): a
    kink computed from the on phase before and the off phase after, found in the exact data;
    inside the off phase the diode's turn-off is a kink too (i' = -10 v -> 0)."""
    tr = L.simulate(buck(), [0, 0, 1], 2, digits=20)
    t = [k / 400 for k in range(801)]
    r = L.compare(tr, t, tr.to_numpy(t))
    assert [e.kind for e in r.events[:3]] == ["kink (x' jumps)"] * 3
    assert abs(r.events[0].solver_time - 0.25) <= 1 / 400 and abs(r.events[1].time_error) <= 1 / 400


def test_a_schedules_well_posedness_covers_every_phase():
    on = L.LCS([[-1, 2], [0, 0]], [[1], [0]], [[1, 0]], [[0]], state_names=["i", "1"])
    bad = L.LCS([[-1, 2], [0, 0]], [[1], [0]], [[-1, 1]], [[-1]], state_names=["i", "1"])  # M = N = [-1]
    assert on.well_posedness() and not bad.well_posedness()
    report = models.scheduled([("1/2", on), ("1/2", bad)], period=1).well_posedness()
    assert not report and all(r.startswith("phase 1 of the schedule") for r in report.reasons)
    assert models.scheduled([("1/2", on), ("1/2", on)], period=1).well_posedness()
    with pytest.raises(L.InvalidArgument, match="same state_names"):
        models.scheduled([("1/2", on), ("1/2", L.LCS(on.A, on.B, on.C, on.D, state_names=["v", "c"]))])
    with pytest.raises(L.Unsupported, match="one phase's"):
        models.scheduled([("1/2", on), ("1/2", on)]).to_statespace()


def test_a_reset_reads_as_a_jump():
    loop = models.sampled(L.LCS([[1]], [[1]], [[1]], [[0]]), [[1]], [[-3]], "1/2")
    e = L.simulate(loop, [1, 5], 1).events[0]   # w(0) = -3 x(0) = -3, not the 5 given
    assert e.time.known_rational() == 0 and "reset (schedule)" in repr(e)
    assert e.state_after.rational().transpose().tolist() == [[1, -3]]
