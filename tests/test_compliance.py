"""Compliant contacts (models.mechanical(..., compliance=...)): y = E q + gap + C_c u, the LCS's
D = C_c.  Every expected value is derived here by hand (closed forms evaluated with mpmath at 40
digits), never copied from a run.

The compliant ball (m = 1, g = 10, c = 1/100, dropped from rest at h = 1 onto y = q + c u):

* flight: q = h - g t^2 / 2, q = 0 at t0 = sqrt(2 h / g) = sqrt(1/5), with q' = v0 = -g t0;
* contact (u > 0, so y = 0: u = -q/c): m q'' = -m g - q/c, a harmonic oscillator about
  q_e = -m g c = -1/10 of frequency w = sqrt(1/(m c)) = 10.  With q - q_e = R cos(w tau + phi),
  R cos(phi) = -q_e, R sin(phi) = -v0/w: q = 0 again when cos(w tau + phi) = cos(phi), first for
  w tau + phi = 2 pi - phi, i.e. tau1 = 2 (pi - phi) / w, where q' = R w sin(phi) = -v0 > 0
  (lift-off: u = -q/c reaches 0 from above);
* the energy m v^2/2 + m g q (+ q^2/(2c) in contact, the spring of the contact) is m g h
  throughout: the contact is elastic, and the next flight is the first one reflected, landing
  again at t0 + tau1 + 2 t0.
"""
from __future__ import annotations

import mpmath as mp
import pytest
from flint import fmpq, fmpq_mat

import lcs_exact as L
from helpers import mpmath_digits, num
from lcs_exact.errors import InvalidArgument, NotRational, ShapeError
from lcs_exact.models import mechanical

_mp = mpmath_digits(40)
DIGITS25 = mp.mpf(10) ** -25


def near(a, b) -> bool:
    return abs(a - b) <= DIGITS25 * max(1, abs(b))


def compliant_ball():
    return mechanical([[1]], [[0]], [[1]], force=[-10], compliance="1/100", q_names=["q"],
                      constraint_names=["floor"])


def hand_ball():
    """The closed forms of the module docstring (mpmath)."""
    m, g, c, h = mp.mpf(1), mp.mpf(10), mp.mpf(1) / 100, mp.mpf(1)
    t0 = mp.sqrt(2 * h / g)
    v0 = -g * t0
    w, qe = 1 / mp.sqrt(m * c), -m * g * c
    phi = mp.atan2(-v0 / w, -qe)
    R = mp.hypot(-qe, -v0 / w)
    tau1 = 2 * (mp.pi - phi) / w

    def contact(tau):  # (q, q') in contact, tau after landing
        return qe + R * mp.cos(w * tau + phi), -R * w * mp.sin(w * tau + phi)

    return dict(t0=t0, v0=v0, tau1=tau1, contact=contact, m=m, g=g, c=c, h=h)


def test_compliance_is_the_d_of_the_lcs_and_makes_it_well_posed():
    """D = c; H_0 = D is the leading matrix of the (single) row: relative degree 0, M = N = [c]
    (Theorem 6.3)."""
    ball = compliant_ball()
    assert ball.D == fmpq_mat([[fmpq(1, 100)]])
    assert ball.A == fmpq_mat([[0, 1, 0], [0, 0, -10], [0, 0, 0]])
    assert ball.B == fmpq_mat([[0], [1], [0]]) and ball.C == fmpq_mat([[1, 0, 0]])
    wp = ball.well_posedness()
    assert wp.well_posed and wp.rho == (0,) and wp.M == fmpq_mat([[fmpq(1, 100)]])


def test_compliant_ball_events_and_states_against_the_closed_forms():
    ball = compliant_ball()
    hb = hand_ball()
    tr = L.simulate(ball, ball.embed([1, 0]), 2)
    assert tr.certified
    land, lift, land2 = tr.events
    t_lift = hb["t0"] + hb["tau1"]
    assert near(num(land.time), hb["t0"]) and near(num(lift.time), t_lift)
    assert near(num(land2.time), t_lift + 2 * hb["t0"])
    assert (land.mode_before, land.mode_after, lift.mode_after) == (frozenset(), frozenset({0}), frozenset())
    assert land.modes == () and lift.modes == () and land2.modes == ()   # no impulse, no jump
    # states: q = 0 at both ends of the contact, q' = v0 then -v0; nothing jumps
    for e, v in ((land, hb["v0"]), (lift, -hb["v0"]), (land2, hb["v0"])):
        assert near(num(e.state_before[0]), 0) and near(num(e.state_after[0]), 0)
        assert near(num(e.state_before[1]), v) and near(num(e.state_after[1]), v)
    # inside the contact (t = 1/2 is in (t0, t_lift) = (0.447, 0.805)): the oscillator, and
    # the force u = -q/c of the spring
    q, v = hb["contact"](mp.mpf(1) / 2 - hb["t0"])
    x = tr.state(fmpq(1, 2))
    assert near(num(x[0]), q) and near(num(x[1]), v)
    assert near(num(tr.u(fmpq(1, 2))[0]), -q / hb["c"]) and q < 0
    # free flight: u = 0 exactly, y = q
    assert tr.u(fmpq(1, 4))[0].rational() == 0 and tr.u(1)[0].rational() == 0


def test_compliant_contact_is_elastic():
    """The energy m v^2/2 + m g q (+ q^2/(2c) in contact) is m g h = 10 before the landing,
    in contact and after the lift-off."""
    ball = compliant_ball()
    hb = hand_ball()
    tr = L.simulate(ball, ball.embed([1, 0]), 2)
    E0 = hb["m"] * hb["g"] * hb["h"]
    for t in (fmpq(1, 5), fmpq(1, 2), fmpq(3, 5), 1, fmpq(3, 2)):
        x = tr.state(t)
        q, v = num(x[0]), num(x[1])
        spring = q ** 2 / (2 * hb["c"]) if q < 0 else 0
        assert near(hb["m"] * v ** 2 / 2 + hb["m"] * hb["g"] * q + spring, E0), t
    # and the lift-off state has exactly the landing's speed: the energy of the first flight
    lift = tr.events[1]
    v = num(lift.state_after[1])
    assert near(v ** 2 / 2 + hb["g"] * num(lift.state_after[0]), E0)


def test_mixed_rigid_floor_and_compliant_ceiling():
    """A ball (m = 1, g = 10) between a rigid floor (q >= 0) and a compliant ceiling at 2
    (y = 2 - q + u/100), from (q, q') = (1, 7), by hand:

    * flight to the ceiling: 1 + 7t - 5t^2 = 2, t_a = (7 - sqrt 29)/10, q' = 7 - 10 t_a = sqrt 29;
    * ceiling contact: u = 100 (q - 2), q'' = -10 - 100 (q - 2): about 19/10 at frequency 10,
      q - 19/10 = (1/10) cos 10 tau + (sqrt 29 / 10) sin 10 tau, back at q = 2 at
      tau = 2 atan(sqrt 29) / 10 with q' = -sqrt 29;
    * fall: 2 - sqrt 29 s - 5 s^2 = 0, s = (sqrt 69 - sqrt 29)/10, then the floor's inelastic
      impact (the paper's rule: q' -> 0) and rest on the floor with u_floor = m g = 10.

    The leading matrices (rows: floor of relative degree 2, ceiling of degree 0) are
    M = [[1, -1], [0, 1/100]] (E M^-1 E^T's floor row, the compliance's ceiling row) and N its
    column analogue [[1, 0], [-1, 1/100]]: P-matrices."""
    lcs = mechanical([[1]], [[0]], [[1], [-1]], force=[-10], gap=[0, 2], compliance=[0, "1/100"],
                     q_names=["q"], constraint_names=["floor", "ceiling"])
    assert lcs.D == fmpq_mat([[0, 0], [0, fmpq(1, 100)]])
    wp = lcs.well_posedness()
    assert wp.well_posed and wp.M == fmpq_mat([[1, -1], [0, fmpq(1, 100)]])
    assert wp.N == fmpq_mat([[1, 0], [-1, fmpq(1, 100)]])
    tr = L.simulate(lcs, lcs.embed([1, 7]), 2)
    assert tr.certified
    hit, leave, impact = tr.events
    s29, s69 = mp.sqrt(29), mp.sqrt(69)
    t_a = (7 - s29) / 10
    t_b = t_a + 2 * mp.atan(s29) / 10
    t_c = t_b + (s69 - s29) / 10
    assert near(num(hit.time), t_a) and near(num(leave.time), t_b) and near(num(impact.time), t_c)
    assert (hit.mode_after, leave.mode_after, impact.mode_after) == (frozenset({1}), frozenset(), frozenset({0}))
    assert hit.modes == () and leave.modes == () and impact.modes == (frozenset({0}),)
    assert near(num(leave.state_after[1]), -s29) and near(num(impact.state_before[1]), -s69)
    assert impact.state_after[1].rational() == 0
    x, u = tr.state(2), tr.u(2)
    assert near(num(x[0]), 0) and near(num(x[1]), 0)
    assert near(num(u[0]), 10) and near(num(u[1]), 0)


def test_compliance_forms_and_their_checks():
    M, K, E = [[1, 0], [0, 1]], [[0, 0], [0, 0]], [[1, 0], [0, 1]]
    assert mechanical(M, K, E, compliance="1/2").D == fmpq_mat([[fmpq(1, 2), 0], [0, fmpq(1, 2)]])
    assert mechanical(M, K, E, compliance=[1, "1/3"]).D == fmpq_mat([[1, 0], [0, fmpq(1, 3)]])
    assert mechanical(M, K, E, compliance=[[2, 1], [1, 2]]).D == fmpq_mat([[2, 1], [1, 2]])
    assert mechanical(M, K, E, compliance=0).D == fmpq_mat(2, 2)
    # a nonsymmetric P-matrix is accepted (Theorem 6.3 needs P, not symmetry)
    assert mechanical(M, K, E, compliance=[[1, 3], [0, 1]]).D == fmpq_mat([[1, 3], [0, 1]])
    with pytest.raises(InvalidArgument, match="P-matrix"):
        mechanical(M, K, E, compliance=[[1, 2], [2, 1]])       # det = -3
    with pytest.raises(InvalidArgument, match="rigid"):
        mechanical(M, K, E, compliance=[[1, 2], [0, 0]])
    with pytest.raises(InvalidArgument, match=">= 0"):
        mechanical(M, K, E, compliance=-1)
    with pytest.raises(InvalidArgument, match=">= 0"):
        mechanical(M, K, E, compliance=[1, -1])
    with pytest.raises(ShapeError, match="compliance"):
        mechanical(M, K, E, compliance=[1])
    with pytest.raises(ShapeError, match="compliance"):
        mechanical(M, K, E, compliance=[[1, 0, 0], [0, 1, 0]])
    with pytest.raises(NotRational, match=r"compliance\[1\]"):
        mechanical(M, K, E, compliance=[1, "x"])


def test_restitution_with_compliance_acts_on_the_rigid_contacts_only():
    """A compliant contact never takes an impulse, so Newton's law has nothing to act on there:
    restitution with a compliance is one entry per constraint, None for the compliant ones."""
    with pytest.raises(InvalidArgument, match="one coefficient per constraint"):
        mechanical([[1]], [[0]], [[1]], force=[-10], compliance="1/100", restitution=1)
    with pytest.raises(InvalidArgument, match=r"restitution\[0\] must be None"):
        mechanical([[1]], [[0]], [[1]], force=[-10], compliance="1/100", restitution=[1])
    with pytest.raises(InvalidArgument, match="relative degree 2"):   # nothing rigid to act on
        mechanical([[1]], [[0]], [[1]], force=[-10], compliance="1/100", restitution=[None])
    two = dict(force=[-10], gap=[0, 2], constraint_names=["floor", "ceiling"])
    with pytest.raises(InvalidArgument, match="one coefficient per constraint"):
        mechanical([[1]], [[0]], [[1], [-1]], compliance=["1/100", 0], restitution="1/2", **two)
    lcs = mechanical([[1]], [[0]], [[1], [-1]], compliance=["1/100", 0], restitution=[None, "1/2"], **two)
    assert lcs.restitution == (0, fmpq(1, 2))
    # the LCS itself: a nonzero coefficient on a row with D_ii > 0 is refused, 0 (None) is not
    with pytest.raises(InvalidArgument, match="'floor' must be None or 0"):
        L.LCS(lcs.A, lcs.B, lcs.C, lcs.D, constraint_names=["floor", "ceiling"], restitution=[1, 1])
    assert L.LCS(lcs.A, lcs.B, lcs.C, lcs.D, restitution=[0, 1]).restitution == (0, 1)
    # a zero compliance is a rigid contact: restitution applies as without compliance
    ball = mechanical([[1]], [[0]], [[1]], force=[-10], compliance=0, restitution="1/2")
    assert ball.restitution == (fmpq(1, 2),) and ball.D == fmpq_mat(1, 1)


def test_compliant_floor_under_an_elastic_ceiling():
    """Siconos' BouncingBallTS-CompliantContact mixes the two: a compliant floor (here c = 1/100)
    and a rigid ceiling with Newton's e = 1 (here at q = 2).  From (q, q') = (1, 7), m = 1,
    g = 10, by hand:

    * the ceiling at t_a = (7 - sqrt 29)/10 (1 + 7t - 5t^2 = 2) with q' = sqrt 29, reflected to
      -sqrt 29 (an impulse on the ceiling alone);
    * the floor at t_a + s, 2 - sqrt 29 s - 5 s^2 = 0: s = (sqrt 69 - sqrt 29)/10, q' = -sqrt 69;
    * the compliant contact (about -1/10, frequency 10, as in the module docstring, with
      phi = atan2(sqrt(69)/10, 1/10)) lifts off after tau = 2 (pi - phi)/10 at q' = +sqrt 69;
    * the ceiling again after s, at q' = sqrt 29: the motion is periodic, of period 2 s + tau,
      and the energy q'^2/2 + 10 q (+ 50 q^2 in contact) is 49/2 + 10 throughout."""
    lcs = mechanical([[1]], [[0]], [[1], [-1]], force=[-10], gap=[0, 2], compliance=["1/100", 0],
                     restitution=[None, 1], q_names=["q"], constraint_names=["floor", "ceiling"])
    tr = L.simulate(lcs, lcs.embed([1, 7]), fmpq(3, 2))
    assert tr.certified
    s29, s69 = mp.sqrt(29), mp.sqrt(69)
    t_a, s = (7 - s29) / 10, (s69 - s29) / 10
    tau = 2 * (mp.pi - mp.atan2(s69 / 10, mp.mpf(1) / 10)) / 10
    times = [t_a, t_a + s, t_a + s + tau, t_a + 2 * s + tau, t_a + 3 * s + tau]
    assert len(tr.events) == 5 and times[-1] < 1.5 < times[-1] + tau
    for e, t in zip(tr.events, times):
        assert near(num(e.time), t)
    ceiling1, land, lift, ceiling2, land2 = tr.events
    for e in (ceiling1, ceiling2):
        assert e.modes == (frozenset({1}),)
        assert near(num(e.state_before[1]), s29) and near(num(e.state_after[1]), -s29)
    assert land.modes == () and lift.modes == () and land.mode_after == frozenset({0})
    assert near(num(land.state_after[1]), -s69) and near(num(lift.state_after[1]), s69)
    for t in (fmpq(1, 10), fmpq(3, 10), fmpq(6, 10), 1, fmpq(3, 2)):
        x = tr.state(t)
        q, v = num(x[0]), num(x[1])
        assert near(v ** 2 / 2 + 10 * q + (50 * q ** 2 if q < 0 else 0), mp.mpf(49) / 2 + 10), t


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_compliant_scene_round_trips_through_a_model_file(tmp_path, suffix):
    """The compliance is the LCS's D: the model file carries it as D and reads back to the same
    system (and the same run)."""
    ball = compliant_ball()
    path = ball.to_model(tmp_path / f"ball{suffix}", x0=[1, 0], t_end=1)
    back = L.read_model(str(path))
    assert (back.A, back.B, back.C, back.D) == (ball.A, ball.B, ball.C, ball.D)
    assert back.D == fmpq_mat([[fmpq(1, 100)]]) and back.embed([1, 0]) == ball.embed([1, 0])
    tr = L.simulate(back, back.embed([1, 0]), 1)
    assert near(num(tr.events[1].time), hand_ball()["t0"] + hand_ball()["tau1"])
