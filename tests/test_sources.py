"""Sources and driven systems (lcs_exact.sources, lcs_exact.builders.exosystems; DESIGN.md section 7).

Exosystem data are checked entry by entry against the definitions; the driven rectifier against a
hand solution derived here (conduction: v' = sin t - 2v from v(0) = 0, so
v = (2 sin t - cos t + e^{-2t}) / 5 and u = sin t - v = (3 sin t + cos t - e^{-2t}) / 5: the diode
turns off at the first t > 0 with 3 sin t + cos t = e^{-2t}, found here by mpmath)."""
from __future__ import annotations

import mpmath
import pytest
from flint import fmpq, fmpq_mat

from lcs_exact import InvalidArgument, LCS, NotRational, ShapeError, simulate, sources
from lcs_exact.builders.circuits import circuit
from lcs_exact.builders.exosystems import driven
from lcs_exact.builders.mechanics import mechanical
from lcs_exact.sources import constant, cosine, exosystem, exponential, polynomial, sine


def rows(m):
    return [[m[i, j] for j in range(m.ncols())] for i in range(m.nrows())]


def test_atoms_and_their_exosystems():
    ex = exosystem([constant(3)])
    assert ex.names == ("1",) and rows(ex.S) == [[0]] and rows(ex.z0) == [[1]] and rows(ex.W) == [[3]]
    ex = exosystem([polynomial([1, -2, 6])])  # 1 - 2t + 6t^2 on the chain (1, t, t^2/2)
    assert ex.names == ("1", "t", "t^2/2")
    assert rows(ex.S) == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and rows(ex.z0) == [[1], [0], [0]]
    assert rows(ex.W) == [[1, -2, 12]]
    ex = exosystem([exponential("-1/2", 4)])
    assert ex.names == ("exp(-t/2)",) and rows(ex.S) == [[fmpq(-1, 2)]] and rows(ex.W) == [[4]]
    ex = exosystem([sine(3, 2), cosine(3, -1)])  # one (sin, cos) pair for both
    assert ex.names == ("sin(3t)", "cos(3t)")
    assert rows(ex.S) == [[0, 3], [-3, 0]] and rows(ex.z0) == [[0], [1]]
    assert rows(ex.W) == [[2, 0], [0, -1]]


def test_sources_share_states_and_combine():
    g = constant(-10)
    ex = exosystem([g, g * 2, polynomial([0, 1]), sine(1) + cosine(1) * "1/2", 0])
    assert ex.names == ("1", "t", "sin(t)", "cos(t)")
    assert rows(ex.W) == [[-10, 0, 0, 0], [-20, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, fmpq(1, 2)], [0, 0, 0, 0]]
    assert (sine(2) - sine(2)).terms == () and repr(sine(-3)) == "sine(3, amplitude=-1)"
    assert polynomial([1, 0, 3]).value("1/2") == fmpq(7, 4) and (constant(1) + cosine(5)).value(0) == 2
    with pytest.raises(InvalidArgument, match="not rational at t"):
        sine(1).value(1)
    with pytest.raises(InvalidArgument, match="product of two sources"):
        sine(1) * cosine(1)
    with pytest.raises(NotRational, match="source"):
        sources.as_source("abc")
    with pytest.raises(InvalidArgument, match="omega = 0"):
        sine(0)


def test_driven_blocks_and_embedding():
    A, B, C, D = [[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]
    lcs = driven(A, B, C, D, E=[[0], [1]], F=[["1/2"]], w=[sine(2, 3)])
    # state (x0, x1, sin 2t, cos 2t): x' = A x + B u + E (3 sin 2t), y = x0 + (1/2)(3 sin 2t)
    assert rows(lcs.A) == [[0, 1, 0, 0], [-1, 0, 3, 0], [0, 0, 0, 2], [0, 0, -2, 0]]
    assert rows(lcs.B) == [[0], [1], [0], [0]] and rows(lcs.C) == [[1, 0, fmpq(3, 2), 0]]
    assert rows(lcs.embed([5, "1/3"])) == [[5], [fmpq(1, 3)], [0], [1]]
    plain = LCS(A, B, C, D)
    assert [lcs.markov(i) for i in range(5)] == [plain.markov(i) for i in range(5)]
    assert lcs.well_posedness().M == plain.well_posedness().M
    with pytest.raises(InvalidArgument, match="needs E or F"):
        driven(A, B, C, D, w=[sine(1)])
    with pytest.raises(ShapeError):
        driven(A, B, C, D, E=[[1, 0], [0, 1]], w=[sine(1)])


def test_sine_driven_rectifier_against_the_hand_solution():
    rect = driven([[-1]], [[1]], [[1]], [[1]], F=[[-1]], w=[sine(1)])
    tr = simulate(rect, rect.embed([0]), 4, digits=30)
    assert tr.certified and tr.events[0].mode_before == frozenset({0}) and tr.events[0].mode_after == frozenset()
    with mpmath.workdps(50):
        t_off = mpmath.findroot(lambda t: 3 * mpmath.sin(t) + mpmath.cos(t) - mpmath.exp(-2 * t), 2.8)
        v_off = (2 * mpmath.sin(t_off) - mpmath.cos(t_off) + mpmath.exp(-2 * t_off)) / 5
        got = tr.events[0].time.ball(30)
        assert abs(mpmath.mpf(got.mid().str(40, radius=False)) - t_off) < mpmath.mpf(10) ** -29
        x = tr.events[0].state_after
        assert abs(mpmath.mpf(x[0].ball(30).mid().str(40, radius=False)) - v_off) < mpmath.mpf(10) ** -29
        # the exosystem carries sin t exactly: the state 'sin(t)' at t = 1 is sin 1
        s1 = tr.state(1)[1].ball(30)
        assert abs(mpmath.mpf(s1.mid().str(40, radius=False)) - mpmath.sin(1)) < mpmath.mpf(10) ** -29


def test_mechanical_force_gap_and_names():
    ball = mechanical([[1]], [[0]], [[1]], force=[-10], gap=["1/10"], q_names=["h"])
    assert ball.state_names == ("h", "h'", "1")
    assert rows(ball.A) == [[0, 1, 0], [0, 0, -10], [0, 0, 0]]
    assert rows(ball.C) == [[1, 0, fmpq(1, 10)]] and rows(ball.embed([1, 0])) == [[1], [0], [1]]
    # a sinusoidal push on the second of two masses shares nothing with gravity
    two = mechanical([[2, 0], [0, 1]], [[1, -1], [-1, 1]], [[1, 0]], force=[-20, sine(3, 6)])
    assert two.state_names[4:] == ("1", "sin(3t)", "cos(3t)")
    assert rows(two.A)[2] == [fmpq(-1, 2), fmpq(1, 2), 0, 0, -10, 0, 0]  # q0'' = (-q0 + q1 - 20)/2
    assert rows(two.A)[3] == [1, -1, 0, 0, 0, 6, 0]
    with pytest.raises(ShapeError, match="one entry per coordinate"):
        mechanical([[1, 0], [0, 1]], [[1, 0], [0, 1]], [[1, 0]], force=-10)


def test_circuit_sources():
    # a sine source through a diode into C || R: conducting, v(C) = sin t and the diode current
    # C v' + v / R = cos t + sin t vanishes at 3 pi / 4 (the turn-off)
    rc = circuit("V1 1 0 sine(1)\nD1 1 2\nR1 2 0 1\nC1 2 0 1")
    assert rc.state_names == ("v(C1)", "sin(t)", "cos(t)")
    tr = simulate(rc, rc.embed([0]), 3)
    assert [e.time.closed_form for e in tr.events] == [3 * __import__("sympy").pi / 4]
    dc = circuit([("V1", "1", "0", sources.constant(5)), ("R1", "1", "2", 1), ("D1", "2", "3"), ("C1", "3", "0", 1)])
    assert dc.state_names == ("v(C1)", "1")
    with pytest.raises(ShapeError, match="unknown source"):
        circuit("V1 1 0 square(1)\nD1 1 2\nC1 2 0 1")
    from lcs_exact import Unsupported
    with pytest.raises(Unsupported, match="loop of voltage sources"):
        circuit("V1 1 0 1\nV2 1 0 2\nD1 1 2\nC1 2 0 1")
