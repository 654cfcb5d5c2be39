"""Relay systems x' = Ax + Bw, w in Sgn(Cx), as LCSs (lcs_exact.builders.relays): the data of (4.12) derived
by hand, embed, mode selection against hand-derived sign patterns, the exact switching law of the
spiral (4.12) from (1, 2), and sliding/rest of a single relay and of a Coulomb-friction oscillator.

Hand derivation of the LCS (relays.py): state (x, c), pairs 2j "wj-" (u = 1 + w_j, y = -z_j + u_{2j+1})
and 2j+1 "wj+" (u = z_j^+, y = 2c - u_{2j}); w_j = u_{2j} - c.  For (4.12): A = 0, B = [[-1, 2],
[-2, -1]], C = I, so x' = B (u_- - c 1) = B u_- - (B 1) c with B 1 = (1, -3).
"""
from __future__ import annotations

import inspect
from fractions import Fraction as Fr
from itertools import combinations

import pytest
import sympy as sp
from flint import arb, fmpq, fmpq_mat

import lcs_exact as L
import mpmath as mp
from helpers import close, modes, num
from lcs_exact import RationalFunction
from lcs_exact.errors import InvalidArgument, LimitExceeded, NotAutonomous, ShapeError, ZenoDetected
from lcs_exact.examples import filippov_spiral
from lcs_exact.models import relay
from lcs_exact.modes.selection import admissibility_conditions

s = RationalFunction.s()
ALL_MODES = [frozenset(c) for r in range(5) for c in combinations(range(4), r)]


def col(*xs) -> fmpq_mat:
    return fmpq_mat([[fmpq(x.numerator, x.denominator) if isinstance(x, Fr) else x] for x in xs])


def rat(v):
    """An exact vector or an fmpq_mat as a tuple of Fractions (None when not proven rational)."""
    q = v if isinstance(v, fmpq_mat) else v.rational()
    if q is None:
        return None
    return tuple(Fr(int(q[i, 0].p), int(q[i, 0].q)) for i in range(q.nrows()))


def qtime(r):
    q = r.rational() if hasattr(r, "rational") else r
    return None if q is None else Fr(int(q.p), int(q.q))


# ---------------------------------------------------------------------------------------------
# the LCS data of (4.12), by hand
# ---------------------------------------------------------------------------------------------

def test_filippov_spiral_lcs_data_by_hand():
    lcs = filippov_spiral()
    # x0' = -w0 + 2 w1 = -u0 + 2 u2 - c ;  x1' = -2 w0 - w1 = -2 u0 - u2 + 3c ;  c' = 0
    assert lcs.A == fmpq_mat([[0, 0, -1], [0, 0, 3], [0, 0, 0]])
    assert lcs.B == fmpq_mat([[-1, 0, 2, 0], [-2, 0, -1, 0], [0, 0, 0, 0]])
    # y0 = -x0 + u1, y1 = 2c - u0, y2 = -x1 + u3, y3 = 2c - u2
    assert lcs.C == fmpq_mat([[-1, 0, 0], [0, 0, 2], [0, -1, 0], [0, 0, 2]])
    assert lcs.D == fmpq_mat([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]])
    assert lcs.state_names == ("x_0", "x_1", "c") and lcs.constraint_names == ("w0-", "w0+", "w1-", "w1+")
    # A nilpotent (A^2 = 0): (sI - A)^{-1} = I/s + A/s^2.  G = C B/s + C A B/s^2 + D with A B = 0:
    G = [[1 / s, 1, -2 / s, 0], [-1, 0, 0, 0], [2 / s, 0, 1 / s, 1], [0, 0, -1, 0]]
    assert lcs.G() == L.RationalMatrix(G)
    R = [[-1 / s, 0, 1 / s**2], [0, 0, 2 / s], [0, -1 / s, -3 / s**2], [0, 0, 2 / s]]
    assert lcs.R() == L.RationalMatrix(R)
    # D is skew: H_0 = D has no zero row/column, so M = N = D: not P-matrices, Theorem 6.3 silent
    wp = lcs.well_posedness()
    assert not wp and wp.M == lcs.D and wp.N == lcs.D and not wp.M_is_P and not wp.N_is_P


def test_filippov_spiral_non_autonomous_modes_by_hand():
    """G_II(s) is singular exactly when some relay has "wj+" (2j+1) in I without "wj-" (2j): the
    row of y_{2j+1} = 2c - u_{2j} has no entry in the columns of I.  Otherwise det G_II =
    ± det(C_S B_S)/s^|S| with S the sliding relays (2j in I, 2j+1 not): B_SS is a principal
    submatrix of B (-1, -1, det 5), never singular."""
    lcs = filippov_spiral()
    want = {I for I in ALL_MODES if any(2 * j + 1 in I and 2 * j not in I for j in range(2))}
    assert want == modes({1}, {3}, {0, 3}, {1, 2}, {1, 3}, {0, 1, 3}, {1, 2, 3})
    assert {I for I in ALL_MODES if not lcs.mode(I).is_autonomous} == want
    # each is proven inadmissible by consistency alone: y_{2j+1} = 0 with u_{2j} = 0 needs 2c = 0
    for I in want:
        eqs, _ = admissibility_conditions(lcs.mode(I))
        forms = {tuple(int(f[0, i]) for i in range(3)) for row in eqs for f in row}
        assert (0, 0, 2) in forms, I
        assert forms <= {(0, 0, 2), (0, 0, -2)} | {(0, 0, 0)}, (I, forms)


def test_embed():
    lcs = filippov_spiral()
    assert lcs.embed([1, 2]) == col(1, 2, 1)
    assert lcs.embed(["1/3", Fr(-2, 7)]) == col(Fr(1, 3), Fr(-2, 7), 1)
    assert lcs.embed(fmpq_mat([[5, 6]])) == col(5, 6, 1)
    with pytest.raises(ShapeError, match="x has length 3, expected 2"):
        lcs.embed([1, 2, 1])
    # an LCS without a builder's embedding reads x as it is
    plain = L.LCS([[0]], [[1]], [[1]], [[0]])
    assert plain.embedding is None and plain.embed([Fr(1, 2)]) == col(Fr(1, 2))
    with pytest.raises(InvalidArgument, match="embedding must be callable"):
        L.LCS([[0]], [[1]], [[1]], [[0]], embedding=3)


def test_relay_builder_validates_its_input():
    with pytest.raises(ShapeError, match="C has shape 1x2, expected 2x2"):
        relay([[0, 0], [0, 0]], [[1, 0], [0, 1]], [[1, 0]])
    with pytest.raises(ShapeError, match="A must be a nonempty square"):
        relay([[0, 1]], [[1]], [[1]])
    with pytest.raises(ShapeError, match="state_names has 1 names, expected 2"):
        relay([[0, 0], [0, 0]], [[1], [0]], [[1, 0]], state_names=["p"])
    with pytest.raises(InvalidArgument, match="distinct"):
        relay([[0, 0], [0, 0]], [[1], [0]], [[1, 0]], state_names=["c", "v"])  # "c" is the level
    one = relay([[0, 1], [0, 0]], [0, 1], [1, 0], name="double integrator", state_names=["p", "v"])
    assert one.B == fmpq_mat([[0, 0], [1, 0], [0, 0]]) and one.A == fmpq_mat([[0, 1, 0], [0, 0, -1], [0, 0, 0]])
    assert one.state_names == ("p", "v", "c") and one.name == "double integrator"


# ---------------------------------------------------------------------------------------------
# mode selection against the hand-derived sign patterns of (4.12)
# ---------------------------------------------------------------------------------------------

def hand_mode(x1: Fr, x2: Fr) -> frozenset:
    """The mode of (4.12) at (x1, x2), by hand.  Relay j with z_j > 0: {2j, 2j+1} (w = 1); z_j < 0:
    neither (w = -1).  On the axis x1 = 0 (x2 != 0), x1' = -w0 + 2 sgn(x2) has the sign of x2 for
    every w0 in [-1, 1]: x1 leaves with that sign, so w0 = sgn(x2); on x2 = 0 (x1 != 0),
    x2' = -2 sgn(x1) - w1 has the sign of -x1: w1 = -sgn(x1).  At the origin B w = 0 forces
    w = 0: both relays slide, {0, 2}."""
    if x1 == 0 and x2 == 0:
        return frozenset({0, 2})
    s1 = (x1 > 0) - (x1 < 0) if x1 != 0 else (x2 > 0) - (x2 < 0)
    s2 = (x2 > 0) - (x2 < 0) if x2 != 0 else -s1
    return frozenset(({0, 1} if s1 > 0 else set()) | ({2, 3} if s2 > 0 else set()))


GRID = [Fr(-3), Fr(-1, 3), Fr(0), Fr(1, 5), Fr(2)]


@pytest.mark.parametrize("x1", GRID)
@pytest.mark.parametrize("x2", GRID)
def test_selection_in_every_quadrant_and_on_the_axes(x1, x2):
    lcs = filippov_spiral()
    want = hand_mode(x1, x2)
    x0 = lcs.embed([x1, x2])
    for method in ("auto", "rcp"):
        assert lcs.select_modes(x0, method) == {want}, (x1, x2, method)
    assert lcs.mode(want).is_autonomous  # the continuous phase has F_I and P_I
    assert lcs.mode(want).contains(x0)   # and needs no jump
    init = lcs.initial_solution(x0)
    assert init.mode == want and init.smooth


def test_rcp_solutions_of_4_12_by_hand():
    lcs = filippov_spiral()
    # (1, 2): quadrant (+, +), x' = (1, -3): u0 = u2 = 2c = 2 (w = 1), u1 = x0(t) = 1 + t,
    # u3 = x1(t) = 2 - 3t; every y vanishes
    (sol,) = lcs.rcp(lcs.embed([1, 2]))
    assert sol.mode == {0, 1, 2, 3} and sol.unique
    assert sol.u == (2 / s, 1 / s + 1 / s**2, 2 / s, 2 / s - 3 / s**2) and all(y == 0 for y in sol.y)
    # the origin: both relays slide, u_- = 1 + w = 1, y_+ = 1 - w = 1, u_+ = y_- = 0
    (sol,) = lcs.rcp(lcs.embed([0, 0]))
    assert sol.mode == {0, 2} and sol.u == (1 / s, 0, 1 / s, 0) and sol.y == (0, 1 / s, 0, 1 / s)
    # (0, 1): on the axis x0 = 0 the field is (1, -3) (w0 = sgn(x1) = 1): u1 = x0(t) = t
    (sol,) = lcs.rcp(lcs.embed([0, 1]))
    assert sol.u == (2 / s, 1 / s**2, 2 / s, 1 / s - 3 / s**2)


def test_the_level_c_decides_the_non_autonomous_modes():
    """With c = 0 (not a state the relay system reaches, but a state of the LCS) the modes with
    "wj+" alone are consistent, and selection proves them admissible: the decision is made, not
    assumed."""
    lcs = filippov_spiral()
    with pytest.raises(NotAutonomous, match="not autonomous") as ei:
        lcs.select_modes([1, 2, 0])
    assert "not unique" in str(ei.value)
    S = lcs.select_modes([1, 2, 0], nonautonomous="include")
    assert any(not lcs.mode(I).is_autonomous for I in S) and frozenset({1, 3}) in S
    for sol in lcs.rcp([1, 2, 0]):  # every solution shown satisfies RCP exactly
        assert sol.unique == lcs.mode(sol.mode).is_autonomous
        assert all(f.sign_at_infinity() >= 0 for f in sol.u + sol.y)


# ---------------------------------------------------------------------------------------------
# the spiral from (1, 2): the exact switching law
# ---------------------------------------------------------------------------------------------

def hand_spiral(x, count):
    """Switching times and states of (4.12) from x (both coordinates nonzero), with Fractions:
    straight lines across quadrants, field f(s1, s2) = (-s1 + 2 s2, -2 s1 - s2)."""
    f = lambda a, b: (-a + 2 * b, -2 * a - b)  # noqa: E731
    t, out = Fr(0), []
    sg = [1 if x[0] > 0 else -1, 1 if x[1] > 0 else -1]
    for _ in range(count):
        v = f(*sg)
        dt, i = min((-x[i] / v[i], i) for i in range(2) if x[i] != 0 and x[i] * v[i] < 0)
        t += dt
        x = [x[0] + dt * v[0], x[1] + dt * v[1]]
        x[i] = Fr(0)
        sg[i] = -sg[i]
        out.append((t, tuple(x)))
    return out


def test_hand_law_of_the_spiral():
    # |x1| + |x2| decreases at rate 2 in every quadrant: from |1| + |2| = 3 the origin at t = 3/2;
    # each quarter turn scales the state (and the time to the next switch) by 1/3
    ev = hand_spiral([Fr(1), Fr(2)], 12)
    assert [t for t, _ in ev] == [Fr(3, 2) - Fr(5, 2) / 3**k for k in range(1, 13)]
    assert [t for t, _ in ev[:4]] == [Fr(2, 3), Fr(11, 9), Fr(38, 27), Fr(119, 81)]
    assert all(abs(x[0]) + abs(x[1]) == 3 - 2 * t for t, x in ev)


def test_spiral_first_six_events_exact():
    lcs = filippov_spiral()
    with pytest.raises((ZenoDetected, LimitExceeded)) as ei:
        L.simulate(lcs, lcs.embed([1, 2]), 2, max_events=6)
    tr = ei.value.trajectory
    assert len(tr.events) >= 6
    hand = hand_spiral([Fr(1), Fr(2)], 6)
    prev = hand_mode(Fr(1), Fr(2))
    for k, (e, (t, x)) in enumerate(zip(tr.events, hand), 1):
        assert t == Fr(3, 2) - Fr(5, 2) / 3**k
        assert qtime(e.time) == t, k                    # proven rational, exactly the law
        assert rat(e.state_before) == x + (1,) and rat(e.state_after) == x + (1,), k
        assert e.modes == () and e.multiplicity == 0    # a switch, no jump
        assert e.mode_before == prev
        # after the switch: the mode of the next open quadrant (the axis patterns of hand_mode)
        assert e.mode_after == hand_mode(*x), k
        prev = e.mode_after
    assert [e.mode_after for e in tr.events[:4]] == [frozenset({0, 1}), frozenset(), frozenset({2, 3}),
                                                     frozenset({0, 1, 2, 3})]


def test_spiral_stops_before_the_accumulation():
    """Today: the run cannot cross the accumulation point at 3/2 and stops with ZenoDetected (the
    accumulation heuristic, or ``zeno="stop"`` once simulate has it), keeping its events."""
    lcs = filippov_spiral()
    opts = {"zeno": "stop"} if "zeno" in inspect.signature(L.simulate).parameters else {}
    with pytest.raises(ZenoDetected) as ei:
        L.simulate(lcs, lcs.embed([1, 2]), 2, **opts)
    tr = ei.value.trajectory
    assert tr is not None and len(tr.events) >= 6
    assert all(e.time.ball(20) < arb(3) / 2 for e in tr.events)
    # the events it kept follow the law: t_k = 3/2 - (5/2) 3^-k (certified balls)
    for k, e in enumerate(tr.events, 1):
        b = e.time.ball(25)
        assert b.overlaps(arb(3) / 2 - arb(5) / 2 / arb(3) ** k), k


def test_spiral_crosses_the_accumulation_at_three_halves_and_rests():
    """Definition 4.10 / Remark 4.11: the event times accumulate at exactly 3/2 where x = 0, and the
    solution stays at the origin (both relays sliding, mode {0, 2}) afterwards; inside the window
    the state follows the law (|x1| + |x2| decreases at rate 2: 2 (3/2 - t) at t = 1499/1000);
    with zeno="stop" the run stops at exactly 3/2."""
    lcs = filippov_spiral()
    tr = L.simulate(lcs, lcs.embed([1, 2]), 2)
    assert tr.certified
    (acc,) = tr.accumulations
    assert qtime(acc.time) == Fr(3, 2)
    assert rat(acc.state) == (0, 0, 1)
    assert rat(tr.state(Fr(7, 4))) == (0, 0, 1) and rat(tr.state(2)) == (0, 0, 1)
    assert all(qtime(e.time) is None or qtime(e.time) <= Fr(3, 2) for e in tr.events)
    assert lcs.select_modes(lcs.embed([0, 0])) == {frozenset({0, 2})}
    x = rat(tr.state(Fr(1499, 1000)))
    assert abs(x[0]) + abs(x[1]) == 2 * (Fr(3, 2) - Fr(1499, 1000)) and x[2] == 1
    with pytest.raises(L.ZenoDetected) as err:
        L.simulate(lcs, lcs.embed([1, 2]), 2, zeno="stop")
    assert qtime(err.value.lower) == qtime(err.value.upper) == Fr(3, 2) == qtime(err.value.time)


# ---------------------------------------------------------------------------------------------
# sliding and rest
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("x0, mode0", [(1, frozenset({0, 1})), (-1, frozenset())])
def test_single_relay_reaches_zero_at_one_and_stays(x0, mode0):
    """x' = -sgn(x) from x0 = ±1: x = x0 (1 - t) until t = 1.  At x = 0, with c = 1 (by hand):
    mode ∅ (w = -1) gives x = t, y_0 = -x: y_0(s) = -1/s^2 < 0; {0, 1} (w = 1) gives x = -t,
    u_1 = x: -1/s^2 < 0; {1} needs 2c = 0 (inconsistent); {0}: y_0 = -x = 0 keeps x = 0, so
    x' = -u_0 + c = 0, u_0 = 1 (w = 0, Filippov's equivalent control), y_1 = 2 - u_0 = 1 > 0:
    S = {{0}}, and the phase in {0} is rest (A_I = 0): no further event."""
    lcs = relay([[0]], [[-1]], [[1]])
    z = lcs.embed([0])
    assert lcs.select_modes(z) == {frozenset({0})}
    (sol,) = lcs.rcp(z)
    assert sol.u == (1 / s, 0) and sol.y == (0, 1 / s)
    sliding = lcs.mode({0})
    assert sliding.feedback() == fmpq_mat([[0, 1]]) and sliding.closed_loop() == fmpq_mat(2, 2)
    assert lcs.select_modes(lcs.embed([x0])) == {mode0}
    tr = L.simulate(lcs, lcs.embed([x0]), 3)
    assert tr.certified
    (e,) = tr.events
    assert qtime(e.time) == 1 and e.mode_before == mode0 and e.mode_after == {0} and e.modes == ()
    assert rat(e.state_after) == (0, 1)
    assert rat(tr.state(Fr(1, 2))) == (Fr(x0, 2), 1)
    assert rat(tr.state(3)) == (0, 1) and rat(tr.state(Fr(7, 3))) == (0, 1)


def test_coulomb_friction_oscillator_sticks_after_two_half_turns():
    """x1' = x2, x2' = -x1 - sgn(x2) (unit mass, spring and Coulomb friction) from (4, 0).  By hand:
    at x2 = 0, x2' = -4 - w < 0, so w = -1: circles about (1, 0), x1 = 1 + 3 cos t, x2 = -3 sin t,
    back to x2 = 0 at t = pi in (-2, 0); then w = 1 about (-1, 0) with radius 1: (0, 0) at
    t = 2 pi, where w = -x1 = 0 in (-1, 1) keeps it stuck (mode {0}).  States after the first
    phase are exact reals (e^{A pi}), so selection there decides the non-autonomous modes
    through certified signs."""
    lcs = relay([[0, 1], [-1, 0]], [[0], [-1]], [[0, 1]])
    tr = L.simulate(lcs, lcs.embed([4, 0]), 10)
    assert tr.certified
    e1, e2 = tr.events
    assert e1.time.closed_form == sp.pi and e2.time.closed_form == 2 * sp.pi
    assert (e1.mode_before, e1.mode_after, e2.mode_after) == (frozenset(), frozenset({0, 1}), frozenset({0}))
    # e^{A pi} is rational: the event states are proven rational (closed forms, Calcium)
    assert rat(e1.state_after) == (-2, 0, 1) and rat(e2.state_after) == (0, 0, 1)
    assert rat(tr.state(10)) == (0, 0, 1)
    x = tr.state(Fr(1, 2))  # the first phase: (1 + 3 cos(1/2), -3 sin(1/2)), mpmath at 60 digits
    half = mp.mpf(1) / 2
    assert close(num(x[0]), 1 + 3 * mp.cos(half)) and close(num(x[1]), -3 * mp.sin(half))


# ---------------------------------------------------------------------------------------------
# the relays' outputs w (declared by the builder: traj.outputs, to_pandas, the figure)
# ---------------------------------------------------------------------------------------------

def w_values(v) -> tuple:
    """An exact vector of outputs as Fractions (each proven rational)."""
    return tuple(qtime(c) for c in v)


def test_single_relay_outputs_by_hand():
    """x' = -w, w in Sgn(x), from x0 = 1: x = 1 - t > 0 gives w = 1 on [0, 1); from t = 1 on
    x = 0 slides with x' = 0, so w = 0 (Filippov's equivalent control); at t = 1 itself the
    right limit 0.  From x0 = -1 the mirror image: w = -1, then 0."""
    for x0 in (1, -1):
        lcs = relay([[0]], [[-1]], [[1]])
        tr = L.simulate(lcs, lcs.embed([x0]), 3)
        assert tr.output_names == ("w_0",)
        for t, w in ((0, x0), (Fr(1, 3), x0), (Fr(99, 100), x0), (1, 0), (Fr(3, 2), 0), (3, 0)):
            assert w_values(tr.outputs(t)) == (w,), (x0, t)
        df = tr.to_pandas([0, Fr(1, 2), 2])
        assert list(df.columns) == ["x_0", "c", "w_0"]
        assert df["w_0"].tolist() == [x0, x0, 0] and df["x_0"].tolist() == [x0, x0 / 2, 0]
        assert list(tr.to_pandas([0], outputs=False).columns) == ["x_0", "c"]
        assert tr.to_numpy([0]).shape == (1, 2)   # the numeric formats read by compare keep the states only


def test_relay_names_name_the_outputs_and_the_pairs():
    lcs = relay([[0]], [[-1]], [[1]], relay_names=["friction"])
    assert lcs.constraint_names == ("friction-", "friction+")
    tr = L.simulate(lcs, lcs.embed([1]), 2)
    assert tr.output_names == ("friction",) and list(tr.to_pandas([0]).columns) == ["x_0", "c", "friction"]
    with pytest.raises(ShapeError, match="relay_names"):
        relay([[0]], [[-1]], [[1]], relay_names=["a", "b"])
    with pytest.raises(InvalidArgument, match="relay_names"):
        relay([[0]], [[-1]], [[1]], relay_names="a")
    # a system without declared outputs says so
    no_outputs = L.simulate(L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]), [1, 0], 1)
    assert no_outputs.output_names == ()
    with pytest.raises(InvalidArgument, match="declares no outputs"):
        no_outputs.outputs(0)


def test_spiral_outputs_are_the_signs_of_the_state_by_hand():
    """(4.12) from (1, 2): w_j = sgn(x_j) on every open phase, read from the hand-derived switching
    law (the midpoint of each phase between two switches lies in an open quadrant), through the
    accumulation window up to 3/2 (phases 7..10 are inside it); both relays slide after 3/2,
    w = (0, 0)."""
    lcs = filippov_spiral()
    tr = L.simulate(lcs, lcs.embed([1, 2]), 2)
    assert tr.output_names == ("w_0", "w_1")
    x, t = (Fr(1), Fr(2)), Fr(0)
    for k, (t1, x1) in enumerate(hand_spiral([Fr(1), Fr(2)], 10)):
        mid = (t + t1) / 2
        xm = tuple(a + (b - a) * (mid - t) / (t1 - t) for a, b in zip(x, x1))  # straight lines
        assert all(c != 0 for c in xm)
        assert w_values(tr.outputs(mid)) == tuple(1 if c > 0 else -1 for c in xm), k
        t, x = t1, x1
    assert w_values(tr.outputs(Fr(7, 4))) == (0, 0) and w_values(tr.outputs(2)) == (0, 0)


def test_relay_figure_draws_the_outputs_not_the_pairs():
    """The default figure of a relay system has the panels state and w (no u, no y), the outputs'
    names in the legend, the level c left out; the w line is 1 before t = 1 and 0 after (the
    single relay by hand)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    lcs = relay([[0]], [[-1]], [[1]])
    tr = L.simulate(lcs, lcs.embed([1]), 2)
    fig = tr.plot(points=40)
    try:
        ax_x, ax_w = fig.axes
        assert [a.get_ylabel() for a in fig.axes] == ["state", "w"]
        assert [t.get_text() for t in ax_w.get_legend().get_texts()] == ["w_0"]
        assert [t.get_text() for t in ax_x.get_legend().get_texts()][0] == "x_0"
        assert not any(t.get_text() == "c" for t in ax_x.get_legend().get_texts())
        lines = [ln for ln in ax_w.get_lines() if len(ln.get_xdata()) > 2]  # one per phase
        assert len(lines) == 2
        for ln in lines:
            before = max(ln.get_xdata()) <= 1   # [0, 1] (its end: the left limit) or [1, 2]
            assert before or min(ln.get_xdata()) >= 1
            assert set(ln.get_ydata()) == ({1.0} if before else {0.0})
        # w jumps at t = 1: open circle at w(1-) = 1, filled at w(1+) = 0
        marks = sorted((ln.get_ydata()[0], ln.get_markerfacecolor() == "white") for ln in ax_w.get_lines()
                       if ln.get_marker() == "o")
        assert marks == [(0.0, False), (1.0, True)]
        # the mode in the relays' words
        labels = [t.get_text() for t in ax_x.get_legend().get_texts()]
        assert "{0, 1}: w_0 = +1" in labels and "{0}: w_0 sliding" in labels
        both = tr.plot(points=20, panels=("x", "w", "u", "y"), sources=True)
        assert [a.get_ylabel() for a in both.axes] == ["state", "w", "u", "y"]
        assert [t.get_text() for t in both.axes[0].get_legend().get_texts()][:2] == ["x_0", "c"]
    finally:
        plt.close("all")
