"""lcs_exact.examples: the paper's systems as printed, and the two rectifiers with their event times
and states derived by hand (closed forms) and checked against simulate to 28 digits."""
from __future__ import annotations

import mpmath as mp
import sympy as sp
from flint import fmpq_mat

import lcs_exact as L
from helpers import A_CARTS, close, mpmath_digits, num
from lcs_exact import examples, models

_mp = mpmath_digits(60)


def test_two_carts_is_2_1():
    c = examples.two_carts()
    assert c.A == fmpq_mat(A_CARTS)  # x4' = x1 - x2 (DESIGN.md: the table's typo is not copied)
    assert c.B == fmpq_mat([[0], [0], [1], [0]]) and c.C == fmpq_mat([[1, 0, 0, 0]]) and c.D == fmpq_mat([[0]])
    assert c.state_names == ("q_0", "q_1", "q_0'", "q_1'") and c.constraint_names == ("stop",)


def test_hook_is_8_12():
    h = examples.two_carts_with_hook()
    assert h.A == fmpq_mat(A_CARTS)
    assert h.B == fmpq_mat([[0, 0], [0, 0], [1, 1], [0, -1]])
    assert h.C == fmpq_mat([[1, 0, 0, 0], [1, -1, 0, 0]]) and h.D == fmpq_mat(2, 2)
    assert h.constraint_names == ("stop", "hook")


def test_models_keeps_the_old_names():
    assert models.two_carts is examples.two_carts and models.two_carts_with_hook is examples.two_carts_with_hook
    assert L.models is models and L.examples is examples


def test_filippov_spiral_is_the_relay_system_4_12():
    # (4.12) as x' = B w, w in Sgn(x): B = [[-1, 2], [-2, -1]] read off the right-hand sides;
    # the LCS data themselves are derived by hand in tests/test_relays.py
    sp_ = examples.filippov_spiral()
    assert models.filippov_spiral is examples.filippov_spiral
    assert (sp_.n, sp_.k) == (3, 4) and sp_.state_names == ("x_0", "x_1", "c")
    assert sp_.constraint_names == ("w0-", "w0+", "w1-", "w1+")
    assert sp_.B == fmpq_mat([[-1, 0, 2, 0], [-2, 0, -1, 0], [0, 0, 0, 0]])
    assert sp_.embed([1, 2]) == fmpq_mat([[1], [2], [1]])


# --- half-wave rectifier ----------------------------------------------------------------------
# C v' = -i_L - i_D, L i_L' = v, i_D = v/R while conducting (v > 0), 0 while blocking.
# Conducting: v'' + v'/(RC) + v/(LC) = 0; from v(0) = 0, v'(0) = -i_L(0)/C:
#   v = (v'(0)/w) e^{-a t} sin(w t),  a = 1/(2RC),  w^2 = 1/(LC) - a^2,
# so v returns to 0 at t = pi/w; there i_D = 0 and C v' = -i_L, v'(pi/w) = -v'(0) e^{-a pi/w},
# hence i_L(pi/w) = -i_L(0) e^{-a pi/w}.  Blocking: the free tank, v = -(i_L/(C w0)) sin(w0 s)
# with w0 = 1/sqrt(LC): back to 0 after pi/w0 with i_L -> -i_L.
# Defaults L = C = 1, R = 13/10: a = 5/13, w = 12/13, pi/w = 13 pi/12, a pi/w = 5 pi/12.


def test_half_wave_rectifier_events_by_hand():
    lcs = examples.half_wave_rectifier()
    assert lcs.A == fmpq_mat([[0, -1], [1, 0]]) and lcs.B == fmpq_mat([[-1], [0]])
    assert lcs.C == fmpq_mat([[-1, 0]]) and lcs.D == fmpq_mat([[13]]) / 10
    tr = L.simulate(lcs, [0, -1], 12, digits=30)
    assert tr.certified
    pi, e = mp.pi, mp.e
    times = [13 * pi / 12, 25 * pi / 12, 19 * pi / 6]
    currents = [e ** (-5 * pi / 12), -e ** (-5 * pi / 12), e ** (-5 * pi / 6)]
    modes = [({0}, set()), (set(), {0}), ({0}, set())]
    assert len(tr.events) == 3
    for ev, t, i, (before, after) in zip(tr.events, times, currents, modes):
        assert close(num(ev.time), t)
        assert ev.mode_before == frozenset(before) and ev.mode_after == frozenset(after)
        assert ev.multiplicity == 0  # no jump: a diode switch in an RLC tank is smooth
        v, iL = ev.state_after
        assert abs(num(v)) < mp.mpf(10) ** -28 and close(num(iL), i)
    # the event times are proven rational multiples of pi
    assert [ev.time.closed_form for ev in tr.events] == [sp.Rational(13, 12) * sp.pi, sp.Rational(25, 12) * sp.pi,
                                                         sp.Rational(19, 6) * sp.pi]


def test_half_wave_rectifier_other_parameters():
    # L = 1/2, C = 2, R = 1/2: a = 1/2, w^2 = 1 - 1/4, conduction 2 pi/sqrt 3, blocking pi sqrt(LC) = pi
    lcs = examples.half_wave_rectifier(L="1/2", C=2, R="1/2")
    tr = L.simulate(lcs, [0, -1], 7, digits=30)
    w = mp.sqrt(3) / 2
    assert close(num(tr.events[0].time), mp.pi / w)
    assert close(num(tr.events[1].time), mp.pi / w + mp.pi)
    assert close(num(tr.events[0].state_after[1]), mp.e ** (-mp.pi / (2 * w)))


# --- full-wave bridge -------------------------------------------------------------------------
# v > 0: D1, D4 conduct (modes {0, 3}); v < 0: D2, D3 ({1, 2}).  Either way the tank sees
# R_eq = (r + R) || Rg + r || Rg = (3/2 || 3) + (1/3 || 3) = 1 + 3/10 = 13/10 for r = 1/3,
# R = 7/6, Rg = 3: the rectifier's conduction, in both half-waves: events every 13 pi/12 and
# i_L(k 13pi/12) = (-1)^(k+1) e^{-5 pi k/12} from (v, i_L) = (0, -1).


def test_diode_bridge_events_by_hand():
    lcs = examples.diode_bridge()
    assert lcs.well_posedness().well_posed
    tr = L.simulate(lcs, [0, -1], 9, digits=30)
    assert tr.certified and len(tr.events) == 2
    for k, ev in enumerate(tr.events, 1):
        assert close(num(ev.time), k * 13 * mp.pi / 12)
        assert ev.time.closed_form == sp.Rational(13 * k, 12) * sp.pi
        assert close(num(ev.state_after[1]), (-1) ** (k + 1) * mp.e ** (-5 * mp.pi * k / 12))
    assert [(e.mode_before, e.mode_after) for e in tr.events] == [({0, 3}, {1, 2}), ({1, 2}, {0, 3})]
    # the load current flows p -> 0 in both half-waves: D1's current in the first, D2's in the second
    u1, u2 = tr.u(1), tr.u(5)
    assert num(u1[0]) > 0 and num(u1[3]) > 0 and abs(num(u1[1])) == 0 == abs(num(u1[2]))
    assert num(u2[1]) > 0 and num(u2[2]) > 0 and abs(num(u2[0])) == 0
    # while D1 and D4 conduct: the tank current 10v/13 splits at a between r + R = 3/2 and Rg = 3
    # (e(a) = 10v/13, D1 carries e(a)/(3/2) = 20v/39) and returns through r = 1/3 || Rg = 3
    # (e(0) - e(b) = 3v/13, D4 carries 9v/13); D2 and D3 block with positive reverse voltages
    v = num(tr.state(1)[0])
    assert v > 0 and close(num(u1[0]), 20 * v / 39) and close(num(u1[3]), 9 * v / 13)
    y1 = tr.y(1)
    assert num(y1[1]) > 0 and num(y1[2]) > 0 and abs(num(y1[0])) < mp.mpf(10) ** -28


def test_examples_have_names_everywhere():
    for build in (examples.two_carts, examples.two_carts_with_hook, examples.half_wave_rectifier,
                  examples.diode_bridge):
        lcs = build()
        assert lcs.name and len(lcs.state_names) == lcs.n and len(lcs.constraint_names) == lcs.k
        assert lcs.constraint_names != tuple(str(i) for i in range(lcs.k))
        assert lcs.well_posedness().well_posed
