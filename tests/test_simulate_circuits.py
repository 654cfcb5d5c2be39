"""Held-out systems with answers derived by hand in each test: an LC network with an ideal diode
(D = 0, C B != 0) and a piecewise-linear oscillator with D > 0 (relative degree 0)."""
from __future__ import annotations

import mpmath as mp
import sympy as sp

import lcs_exact as L
from helpers import close, num

mp.mp.dps = 60


# v' = -i + u (capacitor 1 fed by the diode current u), i' = v - w (inductor), w' = i (capacitor 2);
# the diode voltage is y = v >= 0, u >= 0, y u = 0.  C B = 1, D = 0: relative degree 1.
DIODE = L.LCS([[0, -1, 0], [1, 0, -1], [0, 1, 0]], [[1], [0], [0]], [[1, 0, 0]], [[0]])


def test_diode_conducts_then_blocks():
    # free: v + w = 1/2 is conserved, i'' = -2 i, i(0) = 0, i'(0) = v0 - w0 = 3/2, so
    # i = (3/2) sin(sqrt2 t)/sqrt2 and v = 1/4 + (3/4) cos(sqrt2 t): v = 0 at t1 = acos(-1/3)/sqrt2,
    # where i = 1, w = 1/2, v' = -1 < 0.  Conducting: v = 0, u = i, i' = -w, w' = i from (1, 1/2):
    # i = cos s - sin(s)/2 vanishes at s = atan 2 (w = sqrt5/2 there): the diode blocks at t1 + atan 2.
    tr = L.simulate(DIODE, [1, 0, sp.Rational(-1, 2)], 4, digits=30)
    assert tr.certified
    e1, e2 = tr.events[0], tr.events[1]
    t1 = mp.acos(mp.mpf(-1) / 3) / mp.sqrt(2)
    assert close(num(e1.time), t1)
    assert e1.mode_before == frozenset() and e1.mode_after == {0} and e1.multiplicity == 0
    assert all(close(num(c), w) for c, w in zip(e1.state_after, [0, 1, mp.mpf(1) / 2]))
    assert close(num(e2.time), t1 + mp.atan(2))
    assert e2.mode_before == {0} and e2.mode_after == frozenset()
    want = [0, 0, mp.sqrt(5) / 2]
    assert all(close(num(c), w) for c, w in zip(e2.state_after, want))
    # closed forms, when claimed, must be right
    for e, t in ((e1, t1), (e2, t1 + mp.atan(2))):
        if e.time.closed_form is not None:
            assert close(mp.mpf(str(sp.N(e.time.closed_form, 50))), t)


def test_diode_grazing_is_not_an_event():
    # from (1, 0, 0): v = (1 + cos(sqrt2 t))/2 >= 0 touches 0 at pi/sqrt2 with v' = 0, v'' > 0
    tr = L.simulate(DIODE, [1, 0, 0], 4, digits=30)
    assert tr.events == () and tr.certified


# x1' = x2, x2' = -x1 + u, y = x1 + u (D = 1 > 0): u = max(0, -x1), so x1'' = -x1 for x1 > 0 and
# x1'' = -2 x1 for x1 < 0 (a piecewise-linear oscillator)
PWL = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[1]])


def test_relative_degree_zero_oscillator():
    tr = L.simulate(PWL, [1, 0], 7, digits=30)
    assert tr.certified
    times = [e.time for e in tr.events]
    # x1 = cos t until pi/2 (x2 = -1); then x1 = -sin(sqrt2 s)/sqrt2 until s = pi/sqrt2 (x2 = 1);
    # then x1 = sin s until s = pi (x2 = -1)
    want = [mp.pi / 2, mp.pi / 2 + mp.pi / mp.sqrt(2), 3 * mp.pi / 2 + mp.pi / mp.sqrt(2)]
    assert len(times) == 3
    assert all(close(num(t), w) for t, w in zip(times, want))
    assert [e.mode_after for e in tr.events] == [frozenset({0}), frozenset(), frozenset({0})]
    assert all(e.multiplicity == 0 for e in tr.events)  # relative degree 0: no jumps
    xs = [[num(c) for c in e.state_after] for e in tr.events]
    assert all(close(a, b) for a, b in zip(xs[0], [0, -1]))
    assert all(close(a, b) for a, b in zip(xs[1], [0, 1]))
    assert all(close(a, b) for a, b in zip(xs[2], [0, -1]))
    assert sp.simplify(times[0].closed_form - sp.pi / 2) == 0
    # x(7) in the last phase: x1 = -sin(sqrt2 s)/sqrt2 with s = 7 - t3
    s = 7 - want[2]
    x7 = [num(c) for c in tr.state(7)]
    assert close(x7[0], -mp.sin(mp.sqrt(2) * s) / mp.sqrt(2)) and close(x7[1], -mp.cos(mp.sqrt(2) * s))
