"""Closed forms of the kinds issue 28 (item 6) found missing, each scene derived by hand here: a
phase that lasts a whole period 2 pi / omega of its mode, the first zero of a damped harmonic
(an atan form), and sums of such times after starts at irrational times.  Each closed form is
accepted by the library only when proven (inside the certified bracket of the first root, and an
exact zero); the tests compare it with the hand-derived form (SymPy) and its digits (mpmath)."""
import mpmath as mp
import sympy as sp

import lcs_exact as L
from lcs_exact.mechanics import mechanical

mp.mp.dps = 50


def digits_match(real, value, digits=40):
    got = mp.mpf(real.decimal(digits).split()[0])
    return abs(got - value) < mp.mpf(10) ** (-digits + 2) * max(1, abs(value))


def test_a_phase_lasting_a_whole_period_of_a_resonant_mode():
    """q'' = -2 q + (2/5) cos(sqrt2 t) below a stop q <= 1 (y = 1 - q, the force u pushes down),
    the cosine from the states c' = -s, s' = 2 c: from q = 1 at rest, q = cos(w t) + (t / (5 w))
    sin(w t) with w = sqrt 2 (resonance), so y = 1 - cos(wt) - (t / (5w)) sin(wt) > 0 on
    (0, 2 pi / w) (y'' (0) = w^2 - 2/5 > 0) and y crosses 0 at the whole period 2 pi / w =
    sqrt(2) pi with q' = 2 pi / (5 w) > 0; the inelastic impact leaves the state as it was at 0,
    so the next phase is the same: events at k sqrt(2) pi."""
    A = [[0, 1, 0, 0, 0], [-2, 0, "2/5", 0, 0], [0, 0, 0, -1, 0], [0, 0, 2, 0, 0], [0, 0, 0, 0, 0]]
    lcs = L.LCS(A, [[0], [-1], [0], [0], [0]], [[-1, 0, 0, 0, 1]], [[0]])
    tr = L.simulate(lcs, [1, 0, 1, 0, 1], 10)
    assert len(tr.events) == 2 and tr.certified
    for k, e in enumerate(tr.events, 1):
        assert sp.simplify(e.time.closed_form - k * sp.sqrt(2) * sp.pi) == 0
        assert digits_match(e.time, k * mp.sqrt(2) * mp.pi)
    w = mp.sqrt(2)
    assert digits_match(tr.events[0].state_before[1], 2 * mp.pi / (5 * w))


def test_the_first_zero_of_a_damped_harmonic_and_the_later_impacts():
    """q'' + q'/5 + q = u, a stop q >= 0, e = 1/2, from q = 1 at rest: q = e^{-t/10} (cos wt +
    sin(wt) / (10 w)), w = sqrt(99)/10 = 3 sqrt(11)/10, is first zero where tan(wt) = -10 w:
    t1 = (pi - atan(3 sqrt 11)) / w.  Each later flight starts at q = 0 with q' > 0, so
    q = (v/w) e^{-s/10} sin(ws) returns after pi / w: t_k = t1 + (k - 1) pi / w, sums proven after
    starts at irrational times."""
    lcs = mechanical([[1]], [[1]], [[1]], damping=[["1/5"]], restitution="1/2")
    tr = L.simulate(lcs, [1, 0], 12)
    w = 3 * sp.sqrt(11) / 10
    t1 = (sp.pi - sp.atan(3 * sp.sqrt(11))) / w
    assert len(tr.events) == 4
    wm = 3 * mp.sqrt(11) / 10
    for k, e in enumerate(tr.events):
        assert sp.simplify(e.time.closed_form - (t1 + k * sp.pi / w)) == 0
        assert digits_match(e.time, (mp.pi - mp.atan(3 * mp.sqrt(11))) / wm + k * mp.pi / wm)
    assert tr.events[0].time.closed_form_status == "proven"


def test_sums_of_atan_times_after_starts_at_irrational_times():
    """q'' = 1 - q (rest at 1), a stop q >= 0, e = 1/2, from q = 5/2 at rest: q = 1 + (3/2) cos t
    reaches 0 at t1 = acos(-2/3), at speed -sqrt(5)/2; from q = 0 with speed k, q = 1 - cos s +
    k sin s = 2 sin(s/2) (sin(s/2) + k cos(s/2)) returns at s = 2 pi - 2 atan(k), at speed -k:
    with k = sqrt(5)/4 then sqrt(5)/8, t2 = t1 + 2 pi - 2 atan(sqrt(5)/4) and
    t3 = t2 + 2 pi - 2 atan(sqrt(5)/8)."""
    lcs = mechanical([[1]], [[1]], [[1]], force=[1], restitution="1/2")
    tr = L.simulate(lcs, lcs.embed(["5/2", 0]), 14)
    t1 = sp.acos(sp.Rational(-2, 3))
    t2 = t1 + 2 * sp.pi - 2 * sp.atan(sp.sqrt(5) / 4)
    t3 = t2 + 2 * sp.pi - 2 * sp.atan(sp.sqrt(5) / 8)
    m1 = mp.acos(mp.mpf(-2) / 3)
    m2 = m1 + 2 * mp.pi - 2 * mp.atan(mp.sqrt(5) / 4)
    m3 = m2 + 2 * mp.pi - 2 * mp.atan(mp.sqrt(5) / 8)
    assert len(tr.events) == 3
    for e, want, value in zip(tr.events, (t1, t2, t3), (m1, m2, m3)):
        assert sp.simplify(e.time.closed_form - want) == 0
        assert digits_match(e.time, value)
    assert digits_match(tr.events[2].state_before[1], -mp.sqrt(5) / 8)
