"""Adversarial cases: systems that are NOT in the paper, each checked against an answer derived
independently of the library.

Every expected value comes from a hand analysis written out in the test (mode sequences, jump
rules, closed forms) and from mpmath at 50 digits applied to matrices and formulas written here
or in the references ``reference.mechanics`` and ``reference.flows`` (mp.expm of closed-loop
matrices derived by hand, mp.findroot on a bracket found by a float64 scan of the same
hand-written functions, event-driven simulators).  Nothing expected is taken from the library.  Event times
and states are compared to 25 digits after a run at digits=30.

Conventions of the hand analysis (semantics of the library's interface, DESIGN.md section 4):
* mechanical systems M q'' + D q' + K q = E^T u, y = E q: an impact on the contact set J gives the
  inelastic (Moreau) jump  v+ = v- - M^-1 E_J^T (E_J M^-1 E_J^T)^-1 E_J v-, with J chosen so that
  the impulses are >= 0 and E v+ >= 0 on the closed contacts;
* in the constrained mode I (E_I q == 0) the contact forces are
  u_I = (E_I M^-1 E_I^T)^-1 E_I M^-1 (K q + D v); a phase ends when some u_i (i in I) or some
  y_j (j not in I) turns negative.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath as mp
import pytest
import sympy as sp

import lcs_exact as L
from lcs_exact.models import mechanical

from helpers import mpmath_digits, num as _num
from reference.flows import Q, first_crossing, mpm, mpv, pl_reference, row
from reference.mechanics import impact, mech_matrices, mech_reference

mp.mp.dps = 50
TOL = mp.mpf(10) ** -25
DIGITS = 30


_mp50 = mpmath_digits(50)


# -------------------------------------------------------------------------------------------------
# comparison with the library
# -------------------------------------------------------------------------------------------------
def num(r) -> mp.mpf:
    return _num(r, 40)


def check(r, want, what=""):
    """The library's exact real r equals want to 25 digits (absolute for values near 0)."""
    got = num(r)
    want = mp.mpf(want)
    assert abs(got - want) <= TOL * max(1, abs(want)), f"{what}: got {got}, want {want}"
    b = r.ball(DIGITS)  # the promised 30-digit ball must contain the true value
    mid = mp.mpf(b.mid().str(60, radius=False))
    rad = mp.mpf(b.rad().str(10, radius=False)) if not b.is_exact() else mp.mpf(0)
    assert abs(mid - want) <= rad + mp.mpf(10) ** -45 * max(1, abs(want)), f"{what}: not in ball"


def check_vec(v, want, what=""):
    v = list(v)
    assert len(v) == len(want)
    for i, (r, w) in enumerate(zip(v, want)):
        check(r, w, f"{what}[{i}]")


def sim(lcs, x0, t_end, **kw):
    tr = L.simulate(lcs, x0, t_end, digits=DIGITS, **kw)
    assert tr.certified and not tr.assumptions
    return tr


# -------------------------------------------------------------------------------------------------
# 1. three masses, two relative contacts (q1 >= q2 >= q3), unequal masses, 4 events
# -------------------------------------------------------------------------------------------------
# M = diag(1, 2, 3), K = I (each mass on its own spring), E = [[1, -1, 0], [0, 1, -1]].
# x0: q = (1, 0, 0), v = (-1, 0, 0).
# * Free flight: masses 2, 3 stay at rest (K diagonal), so y1 = q2 - q3 == 0 while u == 0;
#   q1 = cos t - sin t hits 0 at t1 = pi/4 with v1 = -sqrt 2.  Both gaps are closed: the impact
#   LCP gives a common velocity -sqrt2/6 (momentum / total mass 6) with impulses
#   (5 sqrt2/6, sqrt2/2) > 0: one event, jump with mode {0, 1}.  Afterwards q = 0 and the forces
#   u = K q-terms vanish; y0''' = -v1/1 + v2/2 > 0 and y1''' > 0: separation, mode_after = {}.
# * Free flight: q_i(s) = V sqrt(m_i) sin(s / sqrt(m_i)), V = -sqrt2/6.  y0 = q1 - q2 vanishes
#   first (s ~ 5.32, y1 later): impact on {0}, masses 1, 2 stick; in mode {0} the pair (mass 3,
#   stiffness 2) has q12'' = -2/3 q12 and u0 = q12/3 > 0 (q12 > 0): mode_after = {0}.
# * Mode {0}: y1 = q12 - q3 vanishes before u0 does: impact with mode {0, 1}: all stick, then
#   q'' = -q/2 and u0 = u1 = q/2 > 0.  Both forces vanish together at q = 0: one event, no jump,
#   triggers u_0 and u_1, mode_after = {} (the masses move apart again, as after t1).
@pytest.mark.slow
def test_three_masses_relative_contacts():
    Mm, Dm, Km, E = [[1, 0, 0], [0, 2, 0], [0, 0, 3]], [[0] * 3] * 3, [[1, 0, 0], [0, 1, 0], [0, 0, 1]], \
        [[1, -1, 0], [0, 1, -1]]
    tr = sim(mechanical(Mm, Dm, Km, E), [1, 0, 0, -1, 0, 0], 12)
    ev = tr.events
    assert len(ev) == 4
    s2 = mp.sqrt(2)
    # event 1: closed form pi/4
    assert ev[0].time.closed_form == sp.pi / 4
    x1m = mpv([0, 0, 0, -s2, 0, 0])
    x1p, lam = impact(Mm, E, x1m, [0, 1])
    assert all(l > 0 for l in lam)
    assert x1p[3] == x1p[4] == x1p[5]
    check(ev[0].time, mp.pi / 4)
    check_vec(ev[0].state_before, x1m, "x(t1-)")
    check_vec(ev[0].state_after, [0, 0, 0] + [-s2 / 6] * 3, "x(t1+)")
    assert ev[0].modes == (frozenset({0, 1}),) and ev[0].mode_after == frozenset()
    assert ev[0].multiplicity == 1
    # event 2: modal solution of the free flight
    V = -s2 / 6
    ms = [1, 2, 3]
    q = lambda s: [V * mp.sqrt(m) * mp.sin(s / mp.sqrt(m)) for m in ms]
    v = lambda s: [V * mp.cos(s / mp.sqrt(m)) for m in ms]
    A0, _ = mech_matrices(Mm, Dm, Km, E)
    g0, g1 = [1, -1, 0, 0, 0, 0], [0, 1, -1, 0, 0, 0]
    t2 = first_crossing(g0, A0, x1p, mp.pi / 4, 12, 0.01, start_eps=0.01)
    assert first_crossing(g1, A0, x1p, mp.pi / 4, t2, 0.01, start_eps=0.01) is None
    s = mp.findroot(lambda s: q(s)[0] - q(s)[1], t2 - mp.pi / 4)  # the same root from the modal form
    assert abs(s + mp.pi / 4 - t2) < mp.mpf(10) ** -40
    x2m = mpv(q(s) + v(s))
    x2p, lam = impact(Mm, E, x2m, [0])
    assert lam[0] > 0 and x2p[0] > 0  # u0 = q12/3 > 0 in mode {0}
    check(ev[1].time, t2)
    check_vec(ev[1].state_before, x2m, "x(t2-)")
    check_vec(ev[1].state_after, x2p, "x(t2+)")
    assert ev[1].mode_before == frozenset() and ev[1].modes == (frozenset({0}),)
    assert ev[1].mode_after == frozenset({0}) and ev[1].triggers == ("y_0",)
    # event 3: mode {0}
    A1, F1 = mech_matrices(Mm, Dm, Km, E, [0])
    t3 = first_crossing(g1, A1, x2p, t2, 12, 0.01)
    assert first_crossing(row(F1, 0), A1, x2p, t2, t3, 0.01) is None
    x3m = mp.expm(A1 * (t3 - t2)) * x2p
    x3p, lam = impact(Mm, E, x3m, [0, 1])
    assert all(l > 0 for l in lam)
    check(ev[2].time, t3)
    check_vec(ev[2].state_before, x3m, "x(t3-)")
    check_vec(ev[2].state_after, x3p, "x(t3+)")
    assert ev[2].mode_before == frozenset({0}) and ev[2].modes == (frozenset({0, 1}),)
    assert ev[2].mode_after == frozenset({0, 1})
    # event 4: mode {0, 1}, q'' = -q/2: both forces q/2 vanish at q = 0
    A2, F2 = mech_matrices(Mm, Dm, Km, E, [0, 1])
    u3 = F2 * x3p
    assert abs(u3[0] - u3[1]) < mp.mpf(10) ** -45 and u3[0] > 0
    t4 = first_crossing(row(F2, 0), A2, x3p, t3, 12, 0.01)
    Q3, W = x3p[0], x3p[3]
    w = 1 / s2
    assert abs(t4 - t3 - (mp.pi + mp.atan(-Q3 * w / W)) / w) < mp.mpf(10) ** -40  # q = 0 in closed form
    x4 = mp.expm(A2 * (t4 - t3)) * x3p
    check(ev[3].time, t4)
    check_vec(ev[3].state_before, x4, "x(t4)")
    check_vec(ev[3].state_after, x4, "x(t4)")
    assert ev[3].modes == () and ev[3].multiplicity == 0
    assert set(ev[3].triggers) == {"u_0", "u_1"} and ev[3].mode_after == frozenset()
    # final state: free flight after t4 (no further event before 12)
    assert first_crossing(g0, A0, x4, t4, 12, 0.01, start_eps=0.01) is None
    assert first_crossing(g1, A0, x4, t4, 12, 0.01, start_eps=0.01) is None
    check_vec(tr.state(12), mp.expm(A0 * (12 - t4)) * x4, "x(12)")


# -------------------------------------------------------------------------------------------------
# 2. a contact pushed by an external oscillator: impact, sticking, release (closed forms)
# -------------------------------------------------------------------------------------------------
# x = (q, v, w, z): q'' = -w + u, w'' = -w (w = cos t from w(0) = 1, z(0) = 0), y = q.
# From q(0) = 1/2, v(0) = 0: q = cos t - 1/2 hits 0 at t = pi/3 with v = -sin(pi/3) = -sqrt3/2.
# Impact: v -> 0 (B = e_2, CB = 0, CAB = 1: the jump is along e_2).  In contact u = w = cos t > 0
# until t = pi/2: release (no jump); then q = cos t + t - pi/2 (q(pi/2) = q'(pi/2) = 0) and
# q' = 1 - sin t >= 0: no further event.  Started in contact (q = v = 0, w = 1): no event at 0,
# release at pi/2, then the same q.
FORCED_A = [[0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1], [0, 0, -1, 0]]


def forced():
    return L.LCS(FORCED_A, [[0], [1], [0], [0]], [[1, 0, 0, 0]], [[0]])


def test_forced_contact_impact_stick_release():
    tr = sim(forced(), ["1/2", 0, 1, 0], 3)
    assert len(tr.events) == 2
    e1, e2 = tr.events
    assert e1.time.closed_form == sp.pi / 3 and e2.time.closed_form == sp.pi / 2
    r3 = mp.sqrt(3) / 2
    check(e1.time, mp.pi / 3)
    check_vec(e1.state_before, [0, -r3, mp.mpf(1) / 2, -r3], "x(pi/3-)")
    check_vec(e1.state_after, [0, 0, mp.mpf(1) / 2, -r3], "x(pi/3+)")
    assert e1.mode_before == frozenset() and e1.modes == (frozenset({0}),)
    assert e1.mode_after == frozenset({0}) and e1.multiplicity == 1 and e1.triggers == ("y_0",)
    check(e1.impulse[0][0], r3, "impulse")  # the velocity jump sqrt3/2 is the delta coefficient
    check(e2.time, mp.pi / 2)
    check_vec(e2.state_after, [0, 0, 0, -1], "x(pi/2)")
    assert e2.modes == () and e2.mode_before == frozenset({0}) and e2.mode_after == frozenset()
    assert e2.triggers == ("u_0",)
    # before pi/3: free flight, u = 0, y = q = cos t - 1/2; in contact (pi/3 < 5/4 < pi/2): u = cos t
    check(tr.u(1)[0], 0, "u(1)")
    check(tr.y(1)[0], mp.cos(1) - mp.mpf(1) / 2, "y(1)")
    check(tr.u(Fraction(5, 4))[0], mp.cos(mp.mpf(5) / 4), "u(5/4)")
    check(tr.y(Fraction(5, 4))[0], 0, "y(5/4)")
    check_vec(tr.state(3), [mp.cos(3) + 3 - mp.pi / 2, 1 - mp.sin(3), mp.cos(3), -mp.sin(3)], "x(3)")


def test_forced_contact_starts_closed_no_event_at_zero():
    tr = sim(forced(), [0, 0, 1, 0], 3)
    assert len(tr.events) == 1  # t = 0 needs no jump: not an event
    e = tr.events[0]
    assert e.time.closed_form == sp.pi / 2 and e.mode_before == frozenset({0}) and e.modes == ()
    check(tr.u(1)[0], mp.cos(1), "u(1)")
    check_vec(tr.state(1), [0, 0, mp.cos(1), -mp.sin(1)], "x(1)")
    check_vec(tr.state(3), [mp.cos(3) + 3 - mp.pi / 2, 1 - mp.sin(3), mp.cos(3), -mp.sin(3)], "x(3)")


# -------------------------------------------------------------------------------------------------
# 3. two unequal masses, each with a wall stop; second mass 1e-6 further away
# -------------------------------------------------------------------------------------------------
# M = diag(1, 2), K = [[2, -1], [-1, 1]], E = I, q = (1, 1 + 1e-6), v = (-1, -1).
# Mass 1 hits first (its spring pushes it to the wall): impact on {0}, v1 -> 0; then q1 = v1 = 0
# and q1'' = q2 > 0: lift-off, mode {}.  Then mass 2 hits; v2 -> 0, q2'' = (q1 - q2)/2 > 0
# (q1 > 0): lift-off.  Found by scanning y on the free flights (hand-written A below).
@pytest.mark.slow
def test_unequal_masses_two_wall_stops():
    Mm, Dm, Km, E = [[1, 0], [0, 2]], [[0, 0], [0, 0]], [[2, -1], [-1, 1]], [[1, 0], [0, 1]]
    x0 = [1, Fraction(1000001, 1000000), -1, -1]
    tr = sim(mechanical(Mm, Dm, Km, E), x0, 3)
    A = mpm([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], ["1/2", "-1/2", 0, 0]])  # -M^-1 K by hand
    x = mpv(x0)
    t1 = first_crossing([1, 0, 0, 0], A, x, 0, 3, 0.01)
    assert first_crossing([0, 1, 0, 0], A, x, 0, t1, 0.01) is None
    xm1 = mp.expm(A * t1) * x
    xp1 = mpv([0, xm1[1], 0, xm1[3]])
    assert xp1[1] > 0  # q1'' = q2 > 0 after the impact: lift-off
    t2 = first_crossing([0, 1, 0, 0], A, xp1, t1, 3, 0.01)
    assert first_crossing([1, 0, 0, 0], A, xp1, t1, t2, 0.01, start_eps=0.01) is None
    xm2 = mp.expm(A * (t2 - t1)) * xp1
    xp2 = mpv([xm2[0], 0, xm2[2], 0])
    assert xp2[0] > 0
    assert first_crossing([1, 0, 0, 0], A, xp2, t2, 3, 0.01) is None
    assert first_crossing([0, 1, 0, 0], A, xp2, t2, 3, 0.01, start_eps=0.01) is None
    ev = tr.events
    assert len(ev) == 2
    for e, t, xm, xp, j in [(ev[0], t1, xm1, xp1, 0), (ev[1], t2, xm2, xp2, 1)]:
        check(e.time, t)
        check_vec(e.state_before, xm, "x-")
        check_vec(e.state_after, xp, "x+")
        assert e.modes == (frozenset({j}),) and e.mode_after == frozenset() and e.multiplicity == 1
    check_vec(tr.state(3), mp.expm(A * (3 - t2)) * xp2, "x(3)")


def test_two_stops_hit_1e6_apart():
    """M = diag(1, 2), K = [[1, -1], [-1, 1]] (one spring between the masses only), E = I,
    q = (1, 1 + 1e-6), v = (-1, -1): the pair moves almost rigidly; mass 1 hits near t = 1, lifts
    off (q1'' = q2 - q1 > 0), mass 2 hits about 3.4e-7 later and lifts off as well."""
    Mm, Dm, Km, E = [[1, 0], [0, 2]], [[0, 0], [0, 0]], [[1, -1], [-1, 1]], [[1, 0], [0, 1]]
    x0 = [1, Fraction(1000001, 1000000), -1, -1]
    tr = sim(mechanical(Mm, Dm, Km, E), x0, 8)
    A = mpm([[0, 0, 1, 0], [0, 0, 0, 1], [-1, 1, 0, 0], ["1/2", "-1/2", 0, 0]])
    x = mpv(x0)
    t1 = first_crossing([1, 0, 0, 0], A, x, 0, 2, 0.01)
    xm1 = mp.expm(A * t1) * x
    xp1 = mpv([0, xm1[1], 0, xm1[3]])
    # mass 2 is only ~3e-7 away: scan finely
    t2 = first_crossing([0, 1, 0, 0], A, xp1, t1, t1 + mp.mpf(10) ** -5, 1e-8)
    assert 3e-7 < t2 - t1 < 4e-7
    xm2 = mp.expm(A * (t2 - t1)) * xp1
    xp2 = mpv([xm2[0], 0, xm2[2], 0])
    assert xp2[0] > 0 and xp2[2] > 0  # both move away from the wall: no more events
    ev = tr.events
    assert len(ev) == 2
    check(ev[0].time, t1)
    check(ev[1].time, t2)
    check(ev[1].time - ev[0].time, t2 - t1, "t2 - t1")
    check_vec(ev[0].state_after, xp1, "x(t1+)")
    check_vec(ev[1].state_before, xm2, "x(t2-)")
    check_vec(ev[1].state_after, xp2, "x(t2+)")
    # the tiny state after t2 must be right in relative terms too
    got = num(ev[1].state_after[0])
    assert abs(got - xp2[0]) <= TOL * abs(xp2[0])
    check_vec(tr.state(8), mp.expm(A * (8 - t2)) * xp2, "x(8)")


# -------------------------------------------------------------------------------------------------
# 4. two stops hit at exactly the same instant (one event), with a constant "gravity" state
# -------------------------------------------------------------------------------------------------
# x = (q1, q2, v1, v2, g): q'' = -K q - c q' - g (1, 1)^T + u, g' = 0, y = q, K = [[2, -1], [-1, 2]].
# From q = (1, 1), v = 0, g = 1 the motion stays symmetric, q1 = q2 = p with p'' + c p' + p = -1.
# * c = 0: p = 2 cos t - 1, zero at t = pi/3, v = -sqrt3.  Impact on both stops (one event, jump
#   with mode {0, 1}), then at rest on both stops with u = K q + g = (1, 1) > 0 forever.
# * c = 1/5: p = -1 + 2 e^{-t/10} (cos wt + sin(wt)/(10 w)), w = sqrt(99)/10: no closed form;
#   the simultaneity is structural (q1 - q2 == 0).
def gravity_pair(c):
    A = [[0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [-2, 1, -c, 0, -1], [1, -2, 0, -c, -1], [0, 0, 0, 0, 0]]
    B = [[0, 0], [0, 0], [1, 0], [0, 1], [0, 0]]
    return L.LCS(A, B, [[1, 0, 0, 0, 0], [0, 1, 0, 0, 0]], [[0, 0], [0, 0]])


def test_simultaneous_stops_closed_form():
    tr = sim(gravity_pair(0), [1, 1, 0, 0, 1], 3)
    assert len(tr.events) == 1
    e = tr.events[0]
    assert e.time.closed_form == sp.pi / 3
    assert e.modes == (frozenset({0, 1}),) and e.mode_after == frozenset({0, 1}) and e.multiplicity == 1
    assert set(e.triggers) == {"y_0", "y_1"}
    r3 = mp.sqrt(3)
    check_vec(e.state_before, [0, 0, -r3, -r3, 1], "x-")
    check_vec(e.state_after, [0, 0, 0, 0, 1], "x+")
    check_vec(tr.state(3), [0, 0, 0, 0, 1], "x(3)")
    check_vec(tr.u(3), [1, 1], "u(3)")


def test_simultaneous_stops_damped_no_closed_form():
    tr = sim(gravity_pair(Fraction(1, 5)), [1, 1, 0, 0, 1], 3)
    w = mp.sqrt(99) / 10
    p = lambda t: -1 + 2 * mp.exp(-t / 10) * (mp.cos(w * t) + mp.sin(w * t) / (10 * w))
    dp = lambda t: mp.diff(p, t)
    t1 = mp.findroot(p, 1.09)
    assert abs(t1 - 1.0884) < 1e-3 and p(mp.mpf(1)) > 0  # the first zero (p decreases from 1)
    assert len(tr.events) == 1
    e = tr.events[0]
    check(e.time, t1)
    check_vec(e.state_before, [0, 0, dp(t1), dp(t1), 1], "x-")
    check_vec(e.state_after, [0, 0, 0, 0, 1], "x+")
    assert e.modes == (frozenset({0, 1}),) and e.mode_after == frozenset({0, 1})


def test_simultaneous_stops_unequal_masses_not_structural_in_the_matrices():
    """M = diag(1, 2), D = diag(1/5, 2/5), K = diag(1, 2), E = I, q = (1, 2), v = 0: q2 = 2 q1
    with q1'' + q1'/5 + q1 = 0, q1 = e^{-t/10}(cos wt + sin(wt)/(10w)): both stops at
    w t = pi - atan(10 w), one event, both velocities -> 0, then at rest with u = 0: mode {}."""
    Mm, Dm, Km, E = [[1, 0], [0, 2]], [["1/5", 0], [0, "2/5"]], [[1, 0], [0, 2]], [[1, 0], [0, 1]]
    tr = sim(mechanical(Mm, Dm, Km, E), [1, 2, 0, 0], 3)
    w = mp.sqrt(99) / 10
    t1 = (mp.pi - mp.atan(10 * w)) / w
    q1 = lambda t: mp.exp(-t / 10) * (mp.cos(w * t) + mp.sin(w * t) / (10 * w))
    v1 = mp.diff(q1, t1)
    assert len(tr.events) == 1
    e = tr.events[0]
    check(e.time, t1)
    check_vec(e.state_before, [0, 0, v1, 2 * v1], "x-")
    check_vec(e.state_after, [0, 0, 0, 0], "x+")
    assert e.modes == (frozenset({0, 1}),) and e.mode_after == frozenset()
    check_vec(tr.state(3), [0, 0, 0, 0], "x(3)")


# -------------------------------------------------------------------------------------------------
# 5. damped oscillator with an offset stop; x0 = e^{-A} v so that the impact is at exactly t = 1
# -------------------------------------------------------------------------------------------------
# x = (q, v, g): q'' = -q - q'/5 + u, g' = 0, y = q + g (C B = 0, C A B = 1).
DAMPED_A = [[0, 1, 0], [-1, "-1/5", 0], [0, 0, 0]]


def damped():
    return L.LCS(DAMPED_A, [[0], [1], [0]], [[1, 0, 1]], [[0]])


@pytest.mark.slow
def test_x0_from_expm_action_impact_at_exactly_one():
    """x0 = e^{-A}(-1/2, -1, 1/2): the free flight reaches y = 0 with y' = -1 exactly at t = 1
    (y > 0 before: checked by a scan).  Impact v -> 0, then q'' = -q = 1/2 > 0: lift-off, and the
    damped oscillation never gets back to -1/2: one event."""
    A = mpm(DAMPED_A)
    x0 = L.expm_action(DAMPED_A, -1, ["-1/2", -1, "1/2"])
    check_vec(x0, mp.expm(-A) * mpv(["-1/2", -1, "1/2"]), "x0")
    tr = sim(damped(), x0, 10)
    x0m = mp.expm(-A) * mpv(["-1/2", -1, "1/2"])
    assert first_crossing([1, 0, 1], A, x0m, 0, mp.mpf(1) - mp.mpf(10) ** -6, 0.001) is None
    xp = mpv(["-1/2", 0, "1/2"])
    assert first_crossing([1, 0, 1], A, xp, 1, 10, 0.01, start_eps=0.01) is None
    assert len(tr.events) == 1
    e = tr.events[0]
    assert e.time.closed_form == 1
    check_vec(e.state_before, [-mp.mpf(1) / 2, -1, mp.mpf(1) / 2], "x-")
    check_vec(e.state_after, xp, "x+")
    assert e.modes == (frozenset({0}),) and e.mode_after == frozenset()
    check_vec(tr.state(10), mp.expm(A * 9) * xp, "x(10)")


def test_x0_from_expm_action_exact_graze_at_one():
    """x0 = e^{-A}(-1/2, 0, 1/2): y = q + 1/2 has a local minimum 0 at t = 1 (y' = 0, y'' = 1/2):
    a tangential touch, not an event."""
    A = mpm(DAMPED_A)
    tr = sim(damped(), L.expm_action(DAMPED_A, -1, ["-1/2", 0, "1/2"]), 3)
    assert tr.events == ()
    check_vec(tr.state(1), [-mp.mpf(1) / 2, 0, mp.mpf(1) / 2], "x(1)")
    check_vec(tr.state(3), mp.expm(A * 2) * mpv(["-1/2", 0, "1/2"]), "x(3)")


# -------------------------------------------------------------------------------------------------
# 6. a relative-degree-one circuit with exponentials: closed forms log 2 and log(12/5)
# -------------------------------------------------------------------------------------------------
# x0' = -x0, x1' = -2 x1, x2' = u, y = -5 x0 + 6 x1 + x2 (C B = 1 > 0, D = 0).  From (1, 1, 1):
# y = 6 z^2 - 5 z + 1 = (2z - 1)(3z - 1), z = e^{-t}: first zero z = 1/2, t = log 2 (y' < 0).
# Mode {0}: y == 0, u = -C A x = -5 x0 + 12 x1 = -5 z + 12 z^2 > 0 until z = 5/12: release at
# t = log(12/5) with x = (5/12, 25/144, x2), x2 = 5 x0 - 6 x1 = 25/12 - 25/24 = 25/24.
# Then y = (zr - z)(5 - 6 (zr + z)) > 0 for z < zr = 5/12: no further event.
def test_exponential_circuit_log_closed_forms():
    lcs = L.LCS([[-1, 0, 0], [0, -2, 0], [0, 0, 0]], [[0], [0], [1]], [[-5, 6, 1]], [[0]])
    tr = sim(lcs, [1, 1, 1], 5)
    assert len(tr.events) == 2
    e1, e2 = tr.events
    assert sp.simplify(e1.time.closed_form - sp.log(2)) == 0
    assert sp.simplify(e2.time.closed_form - sp.log(sp.Rational(12, 5))) == 0
    check(e1.time, mp.log(2))
    check(e2.time, mp.log(mp.mpf(12) / 5))
    assert e1.modes == () and e1.mode_after == frozenset({0}) and e1.triggers == ("y_0",)
    assert e2.modes == () and e2.mode_after == frozenset() and e2.triggers == ("u_0",)
    check_vec(e1.state_after, [mp.mpf(1) / 2, mp.mpf(1) / 4, 1], "x(log 2)")
    check_vec(e2.state_after, [mp.mpf(5) / 12, mp.mpf(25) / 144, mp.mpf(25) / 24], "x(log 12/5)")
    t = mp.mpf(4) / 5  # log 2 < 4/5 < log(12/5): in contact
    check(tr.u(Fraction(4, 5))[0], -5 * mp.exp(-t) + 12 * mp.exp(-2 * t), "u(4/5)")
    check(tr.u(1)[0], 0, "u(1)")
    check_vec(tr.state(5), [mp.exp(-5), mp.exp(-10), mp.mpf(25) / 24], "x(5)")


# -------------------------------------------------------------------------------------------------
# 7. polynomial flows (nilpotent A): an algebraic event time, a rational release, an exact graze
# -------------------------------------------------------------------------------------------------
# x0' = x1 + u, x1' = x2, x2' = x3, x3' = 0, y = x0 (C B = 1): y = a + b t + c t^2/2 + d t^3/6.
CHAIN_INT = [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]


def integrators():
    return L.LCS(CHAIN_INT, [[1], [0], [0], [0]], [[1, 0, 0, 0]], [[0]])


def test_polynomial_algebraic_root_then_rational_release():
    """(1, -2, 1, 0): y = 1 - 2t + t^2/2, first zero t1 = 2 - sqrt2 (y' = -sqrt2 < 0).  Mode {0}:
    u = -x1 = sqrt2 - s > 0 until s = sqrt2, i.e. release at t = 2 exactly; then
    x0 = (t - 2)^2 / 2 >= 0 (no event).  x(3) = (1/2, 1, 1, 0)."""
    tr = sim(integrators(), [1, -2, 1, 0], 3)
    assert len(tr.events) == 2
    e1, e2 = tr.events
    s2 = mp.sqrt(2)
    check(e1.time, 2 - s2)
    if e1.time.closed_form is not None:
        assert sp.simplify(e1.time.closed_form - (2 - sp.sqrt(2))) == 0
    check_vec(e1.state_before, [0, -s2, 1, 0], "x(t1)")
    assert e1.modes == () and e1.mode_after == frozenset({0})
    check(e2.time, 2)
    check_vec(e2.state_after, [0, 0, 1, 0], "x(2)")
    assert e2.mode_after == frozenset() and e2.triggers == ("u_0",)
    check(tr.u(Fraction(3, 2))[0], 2 - mp.mpf(3) / 2, "u(3/2)")  # u = -x1 = 2 - t
    check_vec(tr.state(3), [mp.mpf(1) / 2, 1, 1, 0], "x(3)")


def test_polynomial_double_root_is_a_graze():
    """(1, -2, 2, 0): y = (1 - t)^2 touches 0 at t = 1: not an event; x(3) = (4, 4, 2, 0)."""
    tr = sim(integrators(), [1, -2, 2, 0], 3)
    assert tr.events == ()
    check_vec(tr.state(3), [4, 4, 2, 0], "x(3)")
    check_vec(tr.state(1), [0, 0, 2, 0], "x(1)")


# -------------------------------------------------------------------------------------------------
# 8. index-one systems (D a P-matrix, or D = 0 with C B > 0): u continuous, events = mode changes
# -------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_p_matrix_feedthrough_twelve_events():
    """A = [[1/10, 1], [-1, 1/10]] (unstable focus), B = [[1, -1], [0, 1]], C = [[1, 0], [1, 1]],
    D = [[1, -1/2], [1/2, 1]] (a P-matrix: minors 1, 1, 5/4).  From (1, 0), y = C x > 0: mode {}.
    First event: y1 = x0 + x1 = e^{t/10}(cos t - sin t) = 0 at t = pi/4 exactly; then the cycle
    {1} -> {0, 1} -> {0} -> {} repeats (12 events up to t = 15)."""
    Am, Bm, Cm, Dm = [["1/10", 1], [-1, "1/10"]], [[1, -1], [0, 1]], [[1, 0], [1, 1]], [[1, "-1/2"], ["1/2", 1]]
    tr = sim(L.LCS(Am, Bm, Cm, Dm), [1, 0], 15)
    ref, xT = pl_reference(mpm(Am), mpm(Bm), mpm(Cm), mpm(Dm), mpv([1, 0]), 15, frozenset())
    assert len(ref) == 12 and len(tr.events) == 12
    assert abs(ref[0][0] - mp.pi / 4) < mp.mpf(10) ** -40
    assert tr.events[0].time.closed_form == sp.pi / 4
    for e, (t, I, J, x) in zip(tr.events, ref):
        check(e.time, t, "t")
        check_vec(e.state_before, x, "x-")
        check_vec(e.state_after, x, "x+")
        assert e.mode_before == I and e.mode_after == J and e.modes == () and e.multiplicity == 0
    assert [e.mode_after for e in tr.events[:4]] == [frozenset({1}), frozenset({0, 1}), frozenset({0}), frozenset()]
    check_vec(tr.state(15), xT, "x(15)")


@pytest.mark.slow
def test_diode_circuit_initial_jump_release_reentry():
    """x' = A x + e0 u, y = x0 (C B = 1), A = [[-1, 1, 0], [1, 0, 1], [0, -1, 0]], x0 = (-1, -1, 0).
    y(0) < 0: jump at t = 0 onto ker C along B, x+ = (0, -1, 0).  Mode {0}: x0 == 0,
    u = -(A x)_0 = -x1, (x1, x2)' = (x2, -x1): x1 = -cos t, x2 = sin t, release at t = pi/2.
    Then free until x0 returns to 0 (y' = x1 < 0 there): mode {0} again without a jump, etc."""
    Am, Bm, Cm, Dm = [[-1, 1, 0], [1, 0, 1], [0, -1, 0]], [[1], [0], [0]], [[1, 0, 0]], [[0]]
    tr = sim(L.LCS(Am, Bm, Cm, Dm), [-1, -1, 0], 12)
    e0 = tr.events[0]
    check(e0.time, 0)
    assert e0.mode_before is None and e0.modes == (frozenset({0}),) and e0.mode_after == frozenset({0})
    check_vec(e0.state_before, [-1, -1, 0], "x(0-)")
    check_vec(e0.state_after, [0, -1, 0], "x(0+)")
    ref, xT = pl_reference(mpm(Am), mpm(Bm), mpm(Cm), mpm(Dm), mpv([0, -1, 0]), 12, frozenset({0}))
    assert abs(ref[0][0] - mp.pi / 2) < mp.mpf(10) ** -40
    assert len(tr.events) == 1 + len(ref) == 4
    assert tr.events[1].time.closed_form == sp.pi / 2
    for e, (t, I, J, x) in zip(tr.events[1:], ref):
        check(e.time, t, "t")
        check_vec(e.state_after, x, "x")
        assert e.mode_before == I and e.mode_after == J and e.modes == ()
    check_vec(tr.state(12), xT, "x(12)")


# -------------------------------------------------------------------------------------------------
# 9. mechanical systems with several contacts: a small independent event-driven reference
# -------------------------------------------------------------------------------------------------
def compare_mech(tr, ref, xT, T):
    evs, (out, xf) = tr.events, (ref, xT)
    assert len(evs) == len(out), (len(evs), len(out))
    for e, (t, I, J, I2, xm, xp) in zip(evs, out):
        check(e.time, t, "t")
        check_vec(e.state_before, xm, "x-")
        check_vec(e.state_after, xp, "x+")
        assert e.mode_before == I and e.mode_after == I2
        assert e.modes == ((J,) if J else ())
    check_vec(tr.state(T), xf, "x(T)")


@pytest.mark.slow
def test_reference_reproduces_three_mass_case():
    """Sanity check of mech_reference on test 1's system (derived there by hand)."""
    Mm, Dm, Km, E = [[1, 0, 0], [0, 2, 0], [0, 0, 3]], [[0] * 3] * 3, [[1, 0, 0], [0, 1, 0], [0, 0, 1]], \
        [[1, -1, 0], [0, 1, -1]]
    out, xT = mech_reference(Mm, Dm, Km, E, mpv([1, 0, 0, -1, 0, 0]), 12)
    assert [o[2] for o in out] == [frozenset({0, 1}), frozenset({0}), frozenset({0, 1}), frozenset()]
    assert abs(out[0][0] - mp.pi / 4) < mp.mpf(10) ** -40
    compare_mech(sim(mechanical(Mm, Dm, Km, E), [1, 0, 0, -1, 0, 0], 12), out, xT, 12)


@pytest.mark.slow
def test_damped_two_masses_stick_then_release():
    """M = diag(1, 3), D = diag(1/5, 1/10), K = [[3, -2], [-2, 2]] (complex eigenvalues with
    negative real parts, also in the constrained mode), stop q1 >= 0; q = (1, 0), v = (0, -2).
    Impact of mass 1 (v1 -> 0), it stays (u0 = 3 q1 - 2 q2 + q1'/5 = -2 q2 > 0 while q2 < 0)
    and is released when q2 crosses 0 (the force turns negative): 2 events."""
    Mm, Dm, Km, E = [[1, 0], [0, 3]], [["1/5", 0], [0, "1/10"]], [[3, -2], [-2, 2]], [[1, 0]]
    tr = sim(mechanical(Mm, Dm, Km, E), [1, 0, 0, -2], 10)
    out, xT = mech_reference(Mm, Dm, Km, E, mpv([1, 0, 0, -2]), 10)
    assert [(o[2], o[3]) for o in out] == [(frozenset({0}), frozenset({0})), (frozenset(), frozenset())]
    xs = out[1][4]
    assert abs(xs[1]) < mp.mpf(10) ** -40  # the release is at q2 = 0 (u0 = -2 q2)
    compare_mech(tr, out, xT, 10)


@pytest.mark.slow
def test_impact_at_time_zero_then_relative_contact():
    """M = diag(2, 1), K = I, E = [[1, 0], [1, -1]] (q1 >= 0, q1 >= q2), q = (0, -1), v = (-1, 1):
    contact 0 is closed and approaching at t = 0: a jump at t = 0 (mode_before None), v1 -> 0;
    then q1 == 0 (free, K diagonal), q2 = -cos t + sin t reaches q1 at t = pi/4 (both gaps are 0
    there; only contact 1 takes an impulse), later mass 1 comes back to the wall."""
    Mm, Dm, Km, E = [[2, 0], [0, 1]], [[0, 0], [0, 0]], [[1, 0], [0, 1]], [[1, 0], [1, -1]]
    tr = sim(mechanical(Mm, Dm, Km, E), [0, -1, -1, 1], 6)
    out, xT = mech_reference(Mm, Dm, Km, E, mpv([0, -1, -1, 1]), 6)
    assert len(out) == 3 and out[0][0] == 0 and abs(out[1][0] - mp.pi / 4) < mp.mpf(10) ** -40
    assert tr.events[0].mode_before is None
    assert tr.events[1].time.closed_form == sp.pi / 4
    e0 = tr.events[0]
    check(e0.time, 0)
    check_vec(e0.state_after, [0, -1, 0, 1], "x(0+)")
    assert e0.modes == (frozenset({0}),) and e0.mode_after == frozenset()
    compare_mech(tr, out, xT, 6)


@pytest.mark.slow
def test_two_closed_stops_one_approaching_one_leaving():
    """M = I, K = [[2, -1], [-1, 2]], E = I, q = (0, 0), v = (-1, 1): at t = 0 both gaps are 0,
    contact 0 approaches (impact, v1 -> 0), contact 1 leaves (no impulse); then 3 more impacts."""
    Mm, Dm, Km, E = [[1, 0], [0, 1]], [[0, 0], [0, 0]], [[2, -1], [-1, 2]], [[1, 0], [0, 1]]
    tr = sim(mechanical(Mm, Dm, Km, E), [0, 0, -1, 1], 6)
    out, xT = mech_reference(Mm, Dm, Km, E, mpv([0, 0, -1, 1]), 6)
    assert [o[2] for o in out] == [frozenset({0}), frozenset({1}), frozenset({0}), frozenset({1})]
    e0 = tr.events[0]
    assert e0.mode_before is None and e0.modes == (frozenset({0}),)
    check_vec(e0.state_after, [0, 0, 0, 1], "x(0+)")
    compare_mech(tr, out, xT, 6)


@pytest.mark.slow
def test_three_masses_wall_and_relative_contact_sticking():
    """M = diag(1, 1/2, 2), K = a fixed-free spring chain [[2, -1, 0], [-1, 2, -1], [0, -1, 1]],
    contacts q1 >= 0 (wall) and q2 >= q3 (between masses 2 and 3); q = (1/2, 1, 1/2),
    v = (-1, 0, 1): 5 events with sticking, an impact while contact 1 is closed (jump mode {0, 1}),
    and releases."""
    Mm, Dm, Km, E = [[1, 0, 0], [0, "1/2", 0], [0, 0, 2]], [[0] * 3] * 3, \
        [[2, -1, 0], [-1, 2, -1], [0, -1, 1]], [[1, 0, 0], [0, 1, -1]]
    x0 = ["1/2", 1, "1/2", -1, 0, 1]
    tr = sim(mechanical(Mm, Dm, Km, E), x0, 8)
    out, xT = mech_reference(Mm, Dm, Km, E, mpv(x0), 8)
    assert len(out) == 5
    assert out[1][2] == frozenset({0, 1}) and out[1][3] == frozenset({1})
    compare_mech(tr, out, xT, 8)


@pytest.mark.slow
def test_four_masses_three_contacts():
    """M = diag(1, 2, 3, 4), K = fixed-free chain, contacts q1 >= 0, q1 >= q2, q3 >= q4;
    q = (1, 1/2, 3, 2), v = (-1, -2, 1, -1).  In mode {0} the force u0 equals y1 = q1 - q2 (both
    are -q2 when q1 == 0), so event 2 has two triggers at once."""
    K = [[2, -1, 0, 0], [-1, 2, -1, 0], [0, -1, 2, -1], [0, 0, -1, 1]]
    Mm, Dm, E = [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 3, 0], [0, 0, 0, 4]], [[0] * 4] * 4, \
        [[1, 0, 0, 0], [1, -1, 0, 0], [0, 0, 1, -1]]
    x0 = [1, "1/2", 3, 2, -1, -2, 1, -1]
    tr = sim(mechanical(Mm, Dm, K, E), x0, 10)
    out, xT = mech_reference(Mm, Dm, K, E, mpv(x0), 10)
    assert len(out) == 7
    assert set(tr.events[1].triggers) == {"u_0", "y_1"}
    compare_mech(tr, out, xT, 10)


# -------------------------------------------------------------------------------------------------
# 10. resonance (a Jordan block at +-i) pushing on a stop
# -------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_resonant_forcing_stick_release_twice():
    """x = (q, v, w, z, g): q'' = -q + w + u, w'' = -w, g' = 0, y = q + g; x0 = (0, 0, 1, 0, 1/2).
    Free: q = t sin(t)/2 (resonance), y = 0 first where t sin t = -1, t1 in (pi, 3pi/2), impact
    v -> 0.  In contact q == -1/2: u = q - w = -1/2 - cos t > 0 until cos t = -1/2 rising:
    release at t = 4pi/3 (state (-1/2, 0, -1/2, sqrt3/2, 1/2)).  Free again (q'' = 1/2 + w > 0 at
    first) until the next zero t3 of y, impact, release at 10pi/3 (the next cos t = -1/2 rising)."""
    An = [[0, 1, 0, 0, 0], [-1, 0, 1, 0, 0], [0, 0, 0, 1, 0], [0, 0, -1, 0, 0], [0, 0, 0, 0, 0]]
    lcs = L.LCS(An, [[0], [1], [0], [0], [0]], [[1, 0, 0, 0, 1]], [[0]])
    tr = sim(lcs, [0, 0, 1, 0, "1/2"], 12)
    A = mpm(An)
    h = mp.mpf(1) / 2
    t1 = mp.findroot(lambda t: t * mp.sin(t) + 1, (mp.pi + mp.mpf(1) / 10, 3 * mp.pi / 2), solver="illinois")
    assert first_crossing([1, 0, 0, 0, 1], A, mpv([0, 0, 1, 0, h]), 0, t1 - mp.mpf(10) ** -3, 0.01) is None
    v1 = (mp.sin(t1) + t1 * mp.cos(t1)) / 2
    x1m = [-h, v1, mp.cos(t1), -mp.sin(t1), h]
    t2 = 4 * mp.pi / 3
    x2 = mpv([-h, 0, mp.cos(t2), -mp.sin(t2), h])
    t3 = first_crossing([1, 0, 0, 0, 1], A, x2, t2, 12, 0.01, start_eps=0.01)
    x3m = mp.expm(A * (t3 - t2)) * x2
    assert -mp.mpf(1) / 2 - mp.cos(t3) > 0  # the contact force is positive after the impact
    t4 = 10 * mp.pi / 3
    x4 = mpv([-h, 0, mp.cos(t4), -mp.sin(t4), h])
    ev = tr.events
    assert len(ev) == 4
    check(ev[0].time, t1)
    check_vec(ev[0].state_before, x1m, "x(t1-)")
    check_vec(ev[0].state_after, [-h, 0] + x1m[2:], "x(t1+)")
    check(ev[1].time, t2)
    check_vec(ev[1].state_after, x2, "x(4pi/3)")
    check(ev[2].time, t3)
    check_vec(ev[2].state_before, x3m, "x(t3-)")
    check(ev[3].time, t4)
    check_vec(ev[3].state_after, x4, "x(10pi/3)")
    assert [e.mode_after for e in ev] == [frozenset({0}), frozenset(), frozenset({0}), frozenset()]
    assert [len(e.modes) for e in ev] == [1, 0, 1, 0]
    assert first_crossing([1, 0, 0, 0, 1], A, x4, t4, 12, 0.01, start_eps=0.01) is None
    check_vec(tr.state(12), mp.expm(A * (12 - t4)) * x4, "x(12)")


# -------------------------------------------------------------------------------------------------
# 11. second-order system with a non-symmetric input matrix (not a mechanical M^-1 E^T)
# -------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_nonsymmetric_second_order_impacts():
    """p'' = Ka p + N u, y = p, Ka = [[-2, 1], [1, -1]], N = [[1, 1/2], [-1/2, 1]] (C A B = N, a
    P-matrix, not symmetric).  Jump on contact j with y_j = 0: x+ = P x- along T = Im B_j + Im AB_j;
    since p_j = 0 already only the velocity moves, v+ = v- + N e_j a with v_j+ = 0, which also
    changes the other velocity by N_ij a.  At each impact here the other gap is open and
    (Ka p)_j > 0 after the jump: lift-off, mode {}.  Free flight x = e^{At} x with A written by hand."""
    An = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]
    Bn = [[0, 0], [0, 0], [1, "1/2"], ["-1/2", 1]]
    lcs = L.LCS(An, Bn, [[1, 0, 0, 0], [0, 1, 0, 0]], [[0, 0], [0, 0]])
    x0 = [1, "1/2", -1, -2]
    tr = sim(lcs, x0, 8)
    A, N = mpm(An), mpm([[1, "1/2"], ["-1/2", 1]])
    x, t, ref = mpv(x0), mp.mpf(0), []
    while True:
        hits = [(first_crossing([1 if i == j else 0 for i in range(4)], A, x, t, 8, 0.01,
                                start_eps=0.01 if abs(x[j]) < 1e-30 else 0.0), j) for j in (0, 1)]
        hits = [hj for hj in hits if hj[0] is not None]
        if not hits:
            break
        t1, j = min(hits)
        xm = mp.expm(A * (t1 - t)) * x
        a = -xm[2 + j] / N[j, j]
        xp = mp.matrix(xm)
        xp[2], xp[3] = xm[2] + N[0, j] * a, xm[3] + N[1, j] * a
        assert a > 0 and xm[1 - j] > 0 and (A * xp)[2 + j] > 0  # impact, other gap open, lift-off
        ref.append((t1, j, xm, xp))
        x, t = xp, t1
    assert len(ref) == 6 == len(tr.events)
    for e, (t1, j, xm, xp) in zip(tr.events, ref):
        check(e.time, t1)
        check_vec(e.state_before, xm, "x-")
        check_vec(e.state_after, xp, "x+")
        assert e.modes == (frozenset({j}),) and e.mode_after == frozenset() and e.mode_before == frozenset()
    check_vec(tr.state(8), mp.expm(A * (8 - t)) * x, "x(8)")


# -------------------------------------------------------------------------------------------------
# 12. grazing and near-grazing
# -------------------------------------------------------------------------------------------------
# x = (q, v, g): q'' = -q + u, g' = 0, y = q + g; q0 = 1: y = g + cos t.
def graze_lcs():
    return L.LCS([[0, 1, 0], [-1, 0, 0], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 1]], [[0]])


def test_exact_graze_at_pi_is_not_an_event():
    """g = 1: y = 1 + cos t touches 0 at t = pi (y' = 0, y'' = 1 > 0): no event up to 4."""
    tr = sim(graze_lcs(), [1, 0, 1], 4)
    assert tr.events == ()
    check_vec(tr.state(4), [mp.cos(4), -mp.sin(4), 1], "x(4)")


def test_near_graze_crossing_1e20():
    """g = 1 - 1e-20: y = g + cos t dips to -1e-20: event at t1 = pi - acos(g) (~ pi - 1.4e-10),
    v = -sin t1 -> 0, then q = -g cos(t - t1): y = g (1 - cos(t - t1)) >= 0, a graze at t1 + 2pi
    (> 4): one event.  g = 1 + 1e-20: no event."""
    g = Fraction(10 ** 20 - 1, 10 ** 20)
    tr = sim(graze_lcs(), [1, 0, g], 4)
    with mp.workdps(100):  # acos is ill-conditioned near 1 (factor ~1e10): extra digits
        G = Q(g)
        t1 = +(mp.pi - mp.acos(G))
        st1 = mp.sin(t1)
    assert len(tr.events) == 1
    e = tr.events[0]
    check(e.time, t1)
    check(e.state_before[1], -st1, "v(t1-)")
    assert abs(num(e.state_before[1]) + st1) <= TOL * st1  # relative, v ~ 1.4e-10
    check_vec(e.state_after, [-G, 0, G], "x(t1+)")
    assert e.modes == (frozenset({0}),) and e.mode_after == frozenset()
    check_vec(tr.state(4), [-G * mp.cos(4 - t1), G * mp.sin(4 - t1), G], "x(4)")
    tr = sim(graze_lcs(), [1, 0, Fraction(10 ** 20 + 1, 10 ** 20)], 4)
    assert tr.events == ()


# x = (q, v, c, s, g): q'' = -(g + c) + u, c'' = -c, y = q: in contact, u = g + cos t.
def pushed_lcs():
    A = [[0, 1, 0, 0, 0], [0, 0, -1, 0, -1], [0, 0, 0, 1, 0], [0, 0, -1, 0, 0], [0, 0, 0, 0, 0]]
    return L.LCS(A, [[0], [1], [0], [0], [0]], [[1, 0, 0, 0, 0]], [[0]])


def test_contact_force_grazes_zero():
    """g = 1, start in contact: u = 1 + cos t touches 0 at t = pi (u' = 0, u'' > 0): not an
    event; the mass stays on the stop, x(5) = (0, 0, cos 5, -sin 5, 1), u(5) = 1 + cos 5."""
    tr = sim(pushed_lcs(), [0, 0, 1, 0, 1], 5)
    assert tr.events == ()
    check_vec(tr.state(5), [0, 0, mp.cos(5), -mp.sin(5), 1], "x(5)")
    check(tr.u(5)[0], 1 + mp.cos(5), "u(5)")


def test_contact_force_dips_below_zero_1e6():
    """g = 1 - 1e-6: u = g + cos t < 0 on a short interval around pi: release at
    tr = pi - acos(g) (no jump), flight q(t) = -g (t - tr)^2/2 + cos t - cos tr + sin(tr)(t - tr)
    (q = q' = q'' = 0 at tr), re-contact at its first zero t2 ~ tr + 4 sqrt(2e-6) with q' < 0:
    impact v -> 0, mode {0} again (u = g + cos t2 > 0)."""
    g = Fraction(10 ** 6 - 1, 10 ** 6)
    tr = sim(pushed_lcs(), [0, 0, 1, 0, g], 5)
    G = Q(g)
    trel = mp.pi - mp.acos(G)
    q = lambda t: -G * (t - trel) ** 2 / 2 + mp.cos(t) - mp.cos(trel) + mp.sin(trel) * (t - trel)
    a = mp.sqrt(2 * (1 - G))
    t2 = mp.findroot(q, (trel + a, trel + 10 * a), solver="illinois")
    assert q(trel + a) > 0 and q(trel + 2 * a) > 0 and q(trel + 3 * a) > 0
    v2 = mp.diff(q, t2)
    assert v2 < 0 and G + mp.cos(t2) > 0
    assert len(tr.events) == 2
    e1, e2 = tr.events
    check(e1.time, trel)
    assert e1.modes == () and e1.mode_after == frozenset() and e1.triggers == ("u_0",)
    check(e2.time, t2)
    check_vec(e2.state_before, [0, v2, mp.cos(t2), -mp.sin(t2), G], "x(t2-)")
    check_vec(e2.state_after, [0, 0, mp.cos(t2), -mp.sin(t2), G], "x(t2+)")
    assert e2.modes == (frozenset({0}),) and e2.mode_after == frozenset({0})
    check_vec(tr.state(5), [0, 0, mp.cos(5), -mp.sin(5), G], "x(5)")


# -------------------------------------------------------------------------------------------------
# 13. an impact at a rational time; the state at the event time is the right limit
# -------------------------------------------------------------------------------------------------
def test_state_at_an_interior_event_time_is_the_right_limit():
    """x = (q, v, g): q'' = -g + u, y = q, from (1/2, 0, 1): q = 1/2 - t^2/2 hits 0 at t = 1 with
    v = -1; impact v -> 0 and it stays (u = g = 1).  With t_end = 3, x(1) = x(1+) = (0, 0, 1)."""
    lcs = L.LCS([[0, 1, 0], [0, 0, -1], [0, 0, 0]], [[0], [1], [0]], [[1, 0, 0]], [[0]])
    tr = sim(lcs, ["1/2", 0, 1], 3)
    assert len(tr.events) == 1
    e = tr.events[0]
    assert e.time.closed_form == 1 and e.mode_after == frozenset({0})
    check_vec(e.state_before, [0, -1, 1], "x(1-)")
    check_vec(tr.state(1), [0, 0, 1], "x(1)")
    check_vec(tr.state(Fraction(1, 2)), [mp.mpf(3) / 8, -mp.mpf(1) / 2, 1], "x(1/2)")
    check(tr.u(2)[0], 1, "u(2)")
    check_vec(tr.state(3), [0, 0, 1], "x(3)")


# -------------------------------------------------------------------------------------------------
# 14. two diodes with a coupled (non-diagonal) C B: a two-constraint jump at t = 0
# -------------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_two_diodes_coupled_jump_and_closed_forms():
    """x = (x0, x1, x2, x3): (x0, x1)' = (x2, x3) + N u, (x2, x3)' = (x3, -x2), y = (x0, x1),
    N = C B = [[2, -1], [-1, 2]] (P-matrix).  x0 = (-2, 1/2, -1, 0).
    * t = 0: y = (-2, 1/2).  The jump x+ = x- + B a solves LCP(y-, N): a = (1, 0) would give
      y1+ = 1/2 - 1 < 0, so both: N a = (2, -1/2), a = (7/6, 1/3) >= 0, x+ = (0, 0, -1, 0).
    * Mode {0, 1}: u = -N^-1 (x2, x3) = (2 cos t - sin t, cos t - 2 sin t)/3 (x2 = -cos t,
      x3 = sin t): u1 = 0 first, at t = atan(1/2).
    * Mode {0}: u0 = cos(t)/2 > 0 until pi/2; x1' = sin t - cos(t)/2 (x1'(atan 1/2) = 0 and
      x1'' > 0: x1 leaves 0).  At pi/2: x1 = cos ta - (1 - sin ta)/2 = (sqrt5 - 1)/2.
    * Mode {}: x0 = 1 - sin t >= 0 (graze at 5pi/2 > 7), x1 = (sqrt5 - 1)/2 - cos t: zero at
      t3 = 2 pi - acos((sqrt5 - 1)/2); mode {1}: u1 = -x3/2 = -sin(t)/2 > 0 until t = 2 pi.
    Cross-checked with pl_reference (mode-by-mode closed loops, scans)."""
    Am = [[0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 1], [0, 0, -1, 0]]
    Bm, Cm, Dm = [[2, -1], [-1, 2], [0, 0], [0, 0]], [[1, 0, 0, 0], [0, 1, 0, 0]], [[0, 0], [0, 0]]
    tr = sim(L.LCS(Am, Bm, Cm, Dm), [-2, "1/2", -1, 0], 7)
    ev = tr.events
    assert len(ev) == 5
    e0 = ev[0]
    check(e0.time, 0)
    assert e0.mode_before is None and e0.modes == (frozenset({0, 1}),) and e0.mode_after == frozenset({0, 1})
    check_vec(e0.state_after, [0, 0, -1, 0], "x(0+)")
    g = (mp.sqrt(5) - 1) / 2
    times = [mp.atan(mp.mpf(1) / 2), mp.pi / 2, 2 * mp.pi - mp.acos(g), 2 * mp.pi]
    ref, xT = pl_reference(mpm(Am), mpm(Bm), mpm(Cm), mpm(Dm), mpv([0, 0, -1, 0]), 7, frozenset({0, 1}))
    assert len(ref) == 4
    for (t, I, J, x), th in zip(ref, times):
        assert abs(t - th) < mp.mpf(10) ** -40
    modes = [(frozenset({0, 1}), frozenset({0})), (frozenset({0}), frozenset()),
             (frozenset(), frozenset({1})), (frozenset({1}), frozenset())]
    for e, (t, I, J, x), th, mm in zip(ev[1:], ref, times, modes):
        check(e.time, th, "t")
        check_vec(e.state_after, x, "x")
        assert (e.mode_before, e.mode_after) == mm == (I, J) and e.modes == ()
        if e.time.closed_form is not None:  # a claimed closed form must be right
            assert abs(mp.mpf(str(sp.N(e.time.closed_form, 60))) - th) < mp.mpf(10) ** -45
    check_vec(ev[2].state_after, [0, g, 0, 1], "x(pi/2)")
    check_vec(tr.state(7), xT, "x(7)")


# -------------------------------------------------------------------------------------------------
# 15. x0 = e^{-R} v with a matrix R other than A
# -------------------------------------------------------------------------------------------------
def test_x0_expm_action_of_another_matrix():
    """The forced contact system of test 2 from x0 = e^{-R}(1/2, 0, 1, 0), R rotating (w, z) only:
    x0 = (1/2, 0, cos 1, sin 1), so w = cos(t - 1) and q = cos(t - 1) - t sin 1 + 1/2 - cos 1.
    Impact at the first zero t1 of q, sticking (u = w > 0), release at t = 1 + pi/2 (w = 0)."""
    R = [[0, 0, 0, 0], [0, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]]
    x0 = L.expm_action(R, -1, ["1/2", 0, 1, 0])
    tr = sim(forced(), x0, 3)
    s1, c1 = mp.sin(1), mp.cos(1)
    q = lambda t: mp.cos(t - 1) - t * s1 + mp.mpf(1) / 2 - c1
    t1 = mp.findroot(q, (1, mp.mpf(6) / 5), solver="illinois")
    assert q(1) > 0 and all(q(mp.mpf(i) / 100) > 0 for i in range(100))
    v1 = -mp.sin(t1 - 1) - s1
    assert len(tr.events) == 2
    e1, e2 = tr.events
    check(e1.time, t1)
    check_vec(e1.state_before, [0, v1, mp.cos(t1 - 1), -mp.sin(t1 - 1)], "x(t1-)")
    check_vec(e1.state_after, [0, 0, mp.cos(t1 - 1), -mp.sin(t1 - 1)], "x(t1+)")
    check(e2.time, 1 + mp.pi / 2)
    assert e2.modes == () and e2.mode_after == frozenset()
    # after the release: q(t) = cos(t - 1) + (t - 1 - pi/2), q' = 1 - sin(t - 1) >= 0
    check_vec(tr.state(3), [mp.cos(2) + 2 - mp.pi / 2, 1 - mp.sin(2), mp.cos(2), -mp.sin(2)], "x(3)")
