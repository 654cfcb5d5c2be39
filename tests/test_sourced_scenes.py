"""Sources inside relays and gaps (issue 31): Coulomb friction on a moving belt and a relay with a
sine bias (models.relay(..., sources=...)), a ball on a plane moving as a sine
(models.mechanical(gap=[source])).  Every expected value is derived here by hand (closed forms
evaluated with mpmath at 40 digits, roots of transcendental equations by mpmath.findroot),
never copied from a run.
"""
from __future__ import annotations

import mpmath as mp
import pytest
import sympy as sp
from flint import fmpq, fmpq_mat

import lcs_exact as L
from helpers import mpmath_digits, num
from lcs_exact import sources
from lcs_exact.errors import InvalidArgument, NotRational, ShapeError
from lcs_exact.models import mechanical, relay
from lcs_exact.builders.relays import LevelEmbedding

_mp = mpmath_digits(40)
DIGITS25 = mp.mpf(10) ** -25


def near(a, b) -> bool:
    return abs(a - b) <= DIGITS25 * max(1, abs(b))


def first_root(f, a, b, step=mp.mpf(1) / 1000):
    """The first sign change of f on (a, b] on a grid of ``step``, refined by findroot."""
    t = a + step
    while t <= b:
        if f(t - step) * f(t) < 0:
            return mp.findroot(f, (t - step, t), solver="anderson")
        t += step
    raise AssertionError("no root")


def mpt(t):
    """A rational time (int or fmpq) as an mpf."""
    t = fmpq(t)
    return mp.mpf(int(t.p)) / int(t.q)


def rational(r):
    q = r.rational()
    return None if q is None else fmpq(q.p, q.q)


# ---------------------------------------------------------------------------------------------
# Coulomb friction on a moving belt: m q'' = -k q - mu N w, w in Sgn(q' - v_b)
# ---------------------------------------------------------------------------------------------
# m = 2, k = 8 (omega = sqrt(k/m) = 2), mu N = 3, v_b = 1/2: in the relay's form x = (q, v),
# q' = v, v' = -4 q - (3/2) w, w in Sgn(v - 1/2): A = [[0, 1], [-4, 0]], B = [[0], [-3/2]],
# C = [[0, 1]], F = [[-1]], sources = [1/2].
MASS, K, MUN, VB = 2, 8, 3, fmpq(1, 2)
OMEGA = mp.sqrt(mp.mpf(K) / MASS)
QSTAR = mp.mpf(MUN) / K          # 3/8: where the spring balances the friction force


def belt():
    return relay([[0, 1], [-fmpq(K, MASS), 0]], [[0], [-fmpq(MUN, MASS)]], [[0, 1]], F=[[-1]], sources=[VB],
                 state_names=["q", "v"], relay_names=["friction"])


def test_belt_lcs_data_by_hand():
    """State (q, v, 1): the belt's speed is the constant source 1/2 and the state '1' is also the
    relay level c of relays.py: v' = -4 q - (3/2)(u_0 - 1), y_0 = -(v - 1/2) + u_1,
    y_1 = 2 - u_0."""
    lcs = belt()
    assert lcs.state_names == ("q", "v", "1") and lcs.constraint_names == ("friction-", "friction+")
    assert lcs.A == fmpq_mat([[0, 1, 0], [-4, 0, fmpq(3, 2)], [0, 0, 0]])
    assert lcs.B == fmpq_mat([[0, 0], [-fmpq(3, 2), 0], [0, 0]])
    assert lcs.C == fmpq_mat([[0, -1, fmpq(1, 2)], [0, 0, 2]])
    assert lcs.D == fmpq_mat([[0, 1], [-1, 0]])
    assert lcs.embed([0, "1/2"]) == fmpq_mat([[0], [fmpq(1, 2)], [1]])
    assert isinstance(lcs.embedding, LevelEmbedding) and lcs.plant == (0, 1)
    sb = lcs.sources
    assert sb.states == (2,) and sb.expressions == ("1",)
    out = lcs.embedding.outputs
    assert out.names == ("friction",) and out.Wx == fmpq_mat([[0, 0, -1]]) and out.Wu == fmpq_mat([[1, 0]])


def test_belt_stick_then_slip_from_rest_on_the_belt():
    """From q = 0 at the belt's speed (at rest relative to the belt): sticking, q = v_b t, with
    the friction balancing the spring: w = -k q / (mu N) = -4t/3 in (-1, 1) until the spring
    force k q reaches mu N at q = mu N / k = 3/8, t1 = mu N / (k v_b) = 3/4 exactly.  Then
    slipping backwards relative to the belt (w = -1: the friction +mu N drags the mass along),
    m q'' = -k q + mu N, harmonic about q* = mu N / k = 3/8 (not -mu N / k): from (q*, v_b),
    q = q* + (v_b/omega) sin(omega (t - t1)), v = v_b cos(omega (t - t1)) <= v_b.  The velocity
    touches v_b again at t1 + pi (period 2 pi / omega = pi) at q = q*, where sticking would need
    |w| = k q / (mu N) to decrease from 1, but q keeps increasing: no stick, no event - the
    closed orbit of the slip goes on."""
    lcs = belt()
    tr = L.simulate(lcs, lcs.embed([0, VB]), 5)
    assert tr.certified
    (e,) = tr.events
    assert rational(e.time) == fmpq(MUN, 1) / (K * VB) == fmpq(3, 4)
    assert (e.mode_before, e.mode_after, e.modes) == (frozenset({0}), frozenset(), ())
    assert e.state_after.rational() == fmpq_mat([[fmpq(3, 8)], [VB], [1]])
    # sticking: exact rational states and friction
    for t in (fmpq(1, 4), fmpq(1, 2)):
        assert tr.state(t).rational() == fmpq_mat([[VB * t], [VB], [1]])
        assert rational(tr.outputs(t)[0]) == -fmpq(K, MUN) * VB * t
    # slipping, before and after the touch at 3/4 + pi = 3.89...
    for t in (1, 2, fmpq(7, 2), 4, 5):
        tau = mpt(t) - mp.mpf(3) / 4
        x = tr.state(t)
        assert near(num(x[0]), QSTAR + mp.mpf(1) / 2 / OMEGA * mp.sin(OMEGA * tau))
        assert near(num(x[1]), mp.mpf(1) / 2 * mp.cos(OMEGA * tau))
        assert rational(tr.outputs(t)[0]) == -1


def test_belt_slip_stick_slip_from_rest():
    """From rest in the lab frame (q = 0, v = 0 < v_b): slipping (w = -1) about q*:
    q = q* (1 - cos 2t), v = 2 q* sin 2t = (3/4) sin 2t, until v = v_b: sin 2t = 2/3, first at
    t_s = asin(2/3)/2, where q_s = q* (1 - cos 2t_s) = (3 - sqrt 5)/8 lies in (-q*, q*), so the
    mass sticks (|w| = k q / (mu N) < 1).  Sticking, q = q_s + v_b (t - t_s) until q = q*:
    t_u = t_s + (q* - q_s)/v_b = t_s + sqrt(5)/4; then the slip of the test above."""
    lcs = belt()
    tr = L.simulate(lcs, lcs.embed([0, 0]), 3)
    assert tr.certified
    stick, slip = tr.events
    t_s = mp.asin(mp.mpf(2) / 3) / 2
    q_s = (3 - mp.sqrt(5)) / 8
    t_u = t_s + mp.sqrt(5) / 4
    assert near(num(stick.time), t_s) and near(num(slip.time), t_u)
    assert sp.simplify(stick.time.closed_form - sp.asin(sp.Rational(2, 3)) / 2) == 0
    assert (stick.mode_before, stick.mode_after, slip.mode_after) == (frozenset(), frozenset({0}), frozenset())
    assert near(num(stick.state_after[0]), q_s) and near(num(stick.state_after[1]), mp.mpf(1) / 2)
    assert near(num(slip.state_after[0]), QSTAR) and near(num(slip.state_after[1]), mp.mpf(1) / 2)
    # while sticking (t_s, t_u) = (0.36.., 0.92..): q = q_s + v_b (t - t_s), w = -k q / (mu N)
    tq = fmpq(2, 3)
    assert t_s < mpt(tq) < t_u
    q = q_s + mp.mpf(1) / 2 * (mpt(tq) - t_s)
    assert near(num(tr.state(tq)[0]), q) and near(num(tr.outputs(tq)[0]), -K * q / MUN)


# ---------------------------------------------------------------------------------------------
# a relay with a sine bias: x' = -w, w in Sgn(x - 2 sin t), x(0) = 0
# ---------------------------------------------------------------------------------------------

def test_relay_with_a_sine_bias_slides_and_leaves():
    """z = x - 2 sin t.  At t = 0, z = 0 and z' = -w - 2 cos t <= -1 for every w in [-1, 1], so
    z < 0: w = -1, x = t, until t = 2 sin t at t1 in (pi/2, 2 pi/3) (findroot).  There sliding
    on x = 2 sin t needs w = -2 cos t in [-1, 1], i.e. |cos t| <= 1/2: true at t1, so the relay
    slides (x = 2 sin t, w = -2 cos t) until w reaches 1 at t2 = 2 pi / 3 exactly, where
    x = 2 sin(2 pi/3) = sqrt 3.  Then w = 1 (z' = -1 - 2 cos t > 0 just after): x = sqrt 3 -
    (t - t2) until z = 0 again at t3 (the first root of sqrt 3 - (t - t2) - 2 sin t after t2),
    where |cos t3| > 1/2: no sliding, the relay crosses to w = -1, x = x(t3) + (t - t3)."""
    lcs = relay([[0]], [[-1]], [[1]], F=[[-1]], sources=[sources.sine(1, 2)])
    assert lcs.state_names == ("x_0", "1", "sin(t)", "cos(t)")
    # y_0 = -(x - 2 sin t) + u_1: C's row 0 = (-1, 0, 2, 0); the level is the state '1'
    assert lcs.C == fmpq_mat([[-1, 0, 2, 0], [0, 2, 0, 0]]) and lcs.A[0, 1] == 1   # x' = -(u_0 - c)
    tr = L.simulate(lcs, lcs.embed([0]), 6)
    assert tr.certified
    e1, e2, e3 = tr.events
    t1 = mp.findroot(lambda t: t - 2 * mp.sin(t), (mp.pi / 2, 2 * mp.pi / 3), solver="anderson")
    t2 = 2 * mp.pi / 3
    t3 = first_root(lambda t: mp.sqrt(3) - (t - t2) - 2 * mp.sin(t), t2, 6)
    assert mp.pi / 2 < t1 < t2 and abs(mp.cos(t3)) > mp.mpf(1) / 2
    assert near(num(e1.time), t1) and near(num(e2.time), t2) and near(num(e3.time), t3)
    assert e2.time.closed_form == 2 * sp.pi / 3
    assert [(e.mode_before, e.mode_after) for e in tr.events] == [
        (frozenset(), frozenset({0})), (frozenset({0}), frozenset({0, 1})), (frozenset({0, 1}), frozenset())]
    assert near(num(e2.state_after[0]), mp.sqrt(3))
    # x and w on each phase
    assert rational(tr.state(1)[0]) == 1 and rational(tr.outputs(1)[0]) == -1
    for t in (fmpq(19, 10), 2):   # sliding
        tm = mpt(t)
        assert near(num(tr.state(t)[0]), 2 * mp.sin(tm)) and near(num(tr.outputs(t)[0]), -2 * mp.cos(tm))
    # (after the transcendental t1 the level is an exact real, 1 to every digit asked)
    assert near(num(tr.state(4)[0]), mp.sqrt(3) - (4 - t2)) and near(num(tr.outputs(4)[0]), 1)
    assert near(num(tr.state(6)[0]), mp.sqrt(3) - (t3 - t2) + (6 - t3)) and near(num(tr.outputs(6)[0]), -1)


def test_relay_with_a_unit_sine_bias_slides_through_its_touches():
    """x' = -w, w in Sgn(x - sin t) from x(0) = 0: sliding from the start (x = sin t, w = -cos t
    in [-1, 1]); w touches 1 at pi and -1 at 2 pi without leaving (|w| <= 1 on both sides): no
    event.  From x(0) = 1: x = 1 - t until 1 - t = sin t, then sliding."""
    lcs = relay([[0]], [[-1]], [[1]], F=[[-1]], sources=[sources.sine(1)])
    tr = L.simulate(lcs, lcs.embed([0]), 7)
    assert tr.certified and tr.events == ()
    for t in (1, 3, 4, 7):
        assert near(num(tr.state(t)[0]), mp.sin(t)) and near(num(tr.outputs(t)[0]), -mp.cos(t))
    tr = L.simulate(lcs, lcs.embed([1]), 2)
    (e,) = tr.events
    assert near(num(e.time), mp.findroot(lambda t: 1 - t - mp.sin(t), (0, 1), solver="anderson"))
    assert e.mode_after == frozenset({0}) and near(num(tr.state(2)[0]), mp.sin(2))


def test_relay_sources_in_the_state_equation():
    """x' = -w + 1/2, w in Sgn(x) (E = [[1]], the source 1/2): A's column of the state '1' is
    E s - B 1 = 1/2 + 1.  From x = 1: w = 1, x = 1 - t/2 reaches 0 at t = 2; from x = -1: w = -1,
    x = -1 + 3t/2 reaches 0 at t = 2/3.  Then sliding: x' = 0 needs w = 1/2 in (-1, 1)."""
    lcs = relay([[0]], [[-1]], [[1]], E=[[1]], sources=[fmpq(1, 2)])
    assert lcs.A == fmpq_mat([[0, fmpq(3, 2)], [0, 0]]) and lcs.state_names == ("x_0", "1")
    for x0, t1 in ((1, fmpq(2)), (-1, fmpq(2, 3))):
        tr = L.simulate(lcs, lcs.embed([x0]), 3)
        (e,) = tr.events
        assert rational(e.time) == t1 and e.mode_after == frozenset({0})
        assert rational(tr.state(t1 / 2)[0]) == fmpq(x0, 2)
        assert rational(tr.outputs(t1 / 2)[0]) == x0
        assert rational(tr.state(3)[0]) == 0 and rational(tr.outputs(3)[0]) == fmpq(1, 2)


def test_relay_builder_checks_its_sources():
    with pytest.raises(InvalidArgument, match="sources"):
        relay([[0]], [[-1]], [[1]], F=[[-1]])
    with pytest.raises(InvalidArgument, match="E or F"):
        relay([[0]], [[-1]], [[1]], sources=[1])
    with pytest.raises(ShapeError, match="sources is empty"):
        relay([[0]], [[-1]], [[1]], F=[[-1]], sources=[])
    with pytest.raises(ShapeError, match="F"):
        relay([[0]], [[-1]], [[1]], F=[[-1, 1]], sources=[1])
    with pytest.raises(ShapeError, match="E"):
        relay([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], E=[[1, 2, 3]], sources=[1])
    with pytest.raises(NotRational, match=r"sources\[0\]"):
        relay([[0]], [[-1]], [[1]], F=[[-1]], sources=["x"])
    # one source: flat E and F are columns; a single source need not be in a list
    a = relay([[0, 1], [0, 0]], [[0], [1]], [[0, 1]], E=[0, 1], F=[-1], sources=sources.sine(2))
    b = relay([[0, 1], [0, 0]], [[0], [1]], [[0, 1]], E=[[0], [1]], F=[[-1]], sources=[sources.sine(2)])
    assert (a.A, a.B, a.C, a.D) == (b.A, b.B, b.C, b.D)
    # a state named like a source's state is kept, the source's state is renamed
    c = relay([[0]], [[-1]], [[1]], F=[[-1]], sources=[1], state_names=["1"])
    assert c.state_names == ("1", "1 (source)")
    # without sources the relay is as before: the level state c
    old = relay([[0]], [[-1]], [[1]])
    assert old.state_names == ("x_0", "c") and repr(old.embedding) == "LevelEmbedding(1)"


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_belt_round_trips_through_a_model_file(tmp_path, suffix):
    """The file carries the plant (q, v), E and F the columns of the state '1' (the belt's speed
    and the level) and w = ["constant(1)"]: it reads back to the same matrices and run (the
    relays' declared outputs w are the builder's, not the file's)."""
    lcs = belt()
    back = L.read_model(str(lcs.to_model(tmp_path / f"belt{suffix}", x0=[0, VB], t_end=1)))
    assert (back.A, back.B, back.C, back.D) == (lcs.A, lcs.B, lcs.C, lcs.D)
    assert back.state_names == lcs.state_names and back.embed([0, VB]) == lcs.embed([0, VB])
    tr = L.simulate(back, back.embed([0, VB]), 1)
    (e,) = tr.events
    assert rational(e.time) == fmpq(3, 4)
    assert tr.output_names == ()   # the file carries the LCS, not the builder's declared outputs


# ---------------------------------------------------------------------------------------------
# a moving obstacle: a ball on a plane moving as p(t) = 20 sin t (gap = -20 sin t)
# ---------------------------------------------------------------------------------------------

def test_ball_on_a_plane_moving_as_a_sine():
    """m = 1, g = 10, the plane at p(t) = a sin t, a = 20: y = q - p(t) >= 0 (gap = -20 sin t).
    Resting on it from (q, q') = (p(0), p'(0)) = (0, 20), the contact force is
    u = m (p'' + g) = 10 - 20 sin t >= 0 until the plane's acceleration -20 sin t falls below
    -g: sin t = 1/2, lift-off at pi/6 with (q, q') = (10, 10 sqrt 3).  Flight:
    q = 10 + 10 sqrt3 tau - 5 tau^2 until it meets the plane (the first root t_i of
    q - 20 sin t, findroot); the inelastic impact gives q' = p'(t_i) = 20 cos t_i; there
    u = 10 - 20 sin t_i > 0, so the ball rides on the plane again until 13 pi / 6."""
    plane = mechanical([[1]], [[0]], [[1]], force=[-10], gap=[sources.sine(1, -20)], q_names=["q"],
                       constraint_names=["plane"])
    assert plane.state_names == ("q", "q'", "1", "sin(t)", "cos(t)")
    assert plane.C == fmpq_mat([[1, 0, 0, -20, 0]])
    tr = L.simulate(plane, plane.embed([0, 20]), 7)
    assert tr.certified
    lift, impact, lift2 = tr.events
    s3 = mp.sqrt(3)
    assert lift.time.closed_form == sp.pi / 6 and lift2.time.closed_form == 13 * sp.pi / 6
    assert near(num(lift.state_after[0]), 10) and near(num(lift.state_after[1]), 10 * s3)
    t0 = mp.pi / 6
    flight = lambda t: 10 + 10 * s3 * (t - t0) - 5 * (t - t0) ** 2 - 20 * mp.sin(t)  # noqa: E731
    t_i = first_root(flight, t0, 7)
    assert near(num(impact.time), t_i) and impact.modes == (frozenset({0}),)
    assert near(num(impact.state_before[1]), 10 * s3 - 10 * (t_i - t0))
    assert near(num(impact.state_after[1]), 20 * mp.cos(t_i)) and 10 - 20 * mp.sin(t_i) > 0
    assert (lift.mode_after, impact.mode_after, lift2.mode_after) == (frozenset(), frozenset({0}), frozenset())
    # the contact force while riding: u = 10 - 20 sin t
    for t in (fmpq(1, 10), fmpq(1, 2), 6):
        tm = mpt(t)
        assert near(num(tr.u(t)[0]), 10 - 20 * mp.sin(tm))
        assert near(num(tr.state(t)[0]), 20 * mp.sin(tm))


def test_relay_takes_its_sources_as_w_like_driven():
    """relay(A, B, C, E=, F=, w=[...]): the sources by the name driven() gives them (sources= is the
    same argument); the relay x' = -w, w in Sgn(x - 2 sin t) built both ways is the same LCS."""
    from lcs_exact import sources as S
    from lcs_exact import models
    a = models.relay([[0]], [[-1]], [[1]], F=[[-2]], w=[S.sine(1)])
    b = models.relay([[0]], [[-1]], [[1]], F=[[-2]], sources=[S.sine(1)])
    assert (a.A, a.B, a.C, a.D, a.state_names) == (b.A, b.B, b.C, b.D, b.state_names)
    with pytest.raises(L.InvalidArgument, match="same argument"):
        models.relay([[0]], [[-1]], [[1]], F=[[-2]], w=[S.sine(1)], sources=[S.sine(1)])
