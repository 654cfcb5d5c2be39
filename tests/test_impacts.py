"""Newton's impact law with Moreau's generalisation (lcs_exact.system.impacts; DESIGN.md section 7).

Oracles derived here: with e = 0 the law is (8.7)-(8.8), so every run must equal the paper's run
(P_I) event by event; with e = 1 a single impact reverses the normal velocity, which keeps the
energy 1/2 q'^T M q' + 1/2 q^T K q (computed here from M and K); the bouncing ball's impact times
and velocities follow from free fall: launched upwards at v0 from the floor under gravity g, it
lands at 2 v0 / g with velocity -v0 and leaves at e v0, so t_k = (2 v0 / g)(1 + e + ... + e^(k-1)).
"""
from __future__ import annotations

import pytest
from flint import arb, fmpq, fmpq_mat

from lcs_exact.numbers.balls import workprec
from lcs_exact import InvalidArgument, LCS, ShapeError, expm_action, simulate
from lcs_exact.examples import cart_chain, two_carts, two_carts_with_hook
from lcs_exact.system.impacts import newton_impact
from lcs_exact.builders.mechanics import mechanical


def agree(a, b, digits=40):
    """Two exact reals agree to ``digits`` digits (balls overlap at that accuracy)."""
    return a.ball(digits).overlaps(b.ball(digits))


def same_run(ta, tb):
    assert len(ta.events) == len(tb.events) and ta.status == tb.status
    for ea, eb in zip(ta.events, tb.events):
        assert agree(ea.time, eb.time)
        assert (ea.mode_before, ea.mode_after) == (eb.mode_before, eb.mode_after)
        qa, qb = ea.state_after.known_rational(), eb.state_after.known_rational()
        if qa is not None or qb is not None:
            assert qa == qb
        assert all(agree(x, y) for x, y in zip(ea.state_after, eb.state_after))
        assert all(agree(x, y) for x, y in zip(ea.state_before, eb.state_before))


def with_restitution(lcs, e):
    return LCS(lcs.A, lcs.B, lcs.C, lcs.D, restitution=e)


def test_validation():
    with pytest.raises(InvalidArgument, match=r"in \[0, 1\]"):
        LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]], restitution="3/2")
    with pytest.raises(ShapeError, match="one per constraint"):
        LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]], restitution=[0, 1])
    with pytest.raises(InvalidArgument, match="relative degree 2"):
        LCS([[-1]], [[1]], [[1]], [[1]], restitution=0)  # a diode: D != 0
    with pytest.raises(InvalidArgument, match="relative degree 2"):
        LCS([[0]], [[1]], [[1]], [[0]], restitution=0)  # C B != 0: relative degree 1
    with pytest.raises(InvalidArgument, match="positive diagonal"):
        LCS([[0, 1, 0], [0, 0, 1], [0, 0, 0]], [[0], [0], [1]], [[1, 0, 0]], [[0]], restitution=0)  # degree 3
    assert "restitution='1/2'" in repr(LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]], restitution="1/2"))


def test_the_impact_lcp():
    # two unit carts, stop on q0 and hook q0 - q1 >= 0 (Example 8.3) at q = 0, both closed
    hook = with_restitution(two_carts_with_hook(), "1/2")
    z = fmpq_mat([[0], [0], [-2], [1]])
    imp = newton_impact(hook, z)
    # y' = (v0, v0 - v1) = (-2, -3); W = E E^T = [[1, 1], [1, 2]]; the LCP on (1 + e) y' = (-3, -9/2):
    # both impulses positive: y'(+) = -e y'(-) = (1, 3/2), so v0 = 1, v1 = v0 - 3/2 = -1/2
    after = imp.jump * z
    assert imp.closed == frozenset({0, 1}) and imp.active == frozenset({0, 1})
    assert [after[i, 0] for i in range(4)] == [0, 0, 1, fmpq(-1, 2)]
    assert newton_impact(hook, fmpq_mat([[1], [0], [-2], [1]])) is None  # stop open, hook y = 1 > 0
    assert newton_impact(hook, fmpq_mat([[0], [-1], [1], [0]])) is None  # closed but separating
    assert newton_impact(hook, fmpq_mat([[-1], [0], [-2], [1]])) is None  # infeasible: the paper's rule


@pytest.mark.slow
def test_restitution_zero_is_the_paper_run():
    carts = two_carts()
    x0 = expm_action(carts.A, -1, [0, -1, -1, 0])
    same_run(simulate(carts, x0, 3), simulate(with_restitution(carts, 0), x0, 3))
    hook = two_carts_with_hook()
    for x in ([1, 1, -1, 2], [0, 0, -1, 2], ["1/2", 0, -1, "-1/3"]):
        same_run(simulate(hook, x, 4), simulate(with_restitution(hook, 0), x, 4))
    chain = cart_chain(4)
    q0 = ["1/2", "-1/2", "1/2", "-1/2", 0, 0, 0, 0]
    same_run(simulate(chain, q0, 4), simulate(with_restitution(chain, [0, 0]), q0, 4))


def energy(x, M, K):
    """1/2 q'^T M q' + 1/2 q^T K q of a state x = (q, q') as a ball (from certified components)."""
    m = len(M)
    b = [c.ball(40) for c in x][:2 * m]
    q, v = b[:m], b[m:]
    with workprec(200):
        out = arb(0)
        for i in range(m):
            for j in range(m):
                out += (v[i] * M[i][j] * v[j] + q[i] * K[i][j] * q[j]) / 2
    return out


def test_elastic_impacts_keep_the_energy():
    M, K = [[1, 0], [0, 1]], [[2, -1], [-1, 1]]
    carts = mechanical(M, K, [[1, 0]], restitution=1)
    x0 = expm_action(carts.A, -1, [0, -1, -1, 0])
    tr = simulate(carts, x0, 12)
    impacts = [e for e in tr.events if e.modes]
    assert len(impacts) >= 3
    first = impacts[0]
    assert first.state_before.rational() == fmpq_mat([[0], [-1], [-1], [0]])
    assert first.state_after.rational() == fmpq_mat([[0], [-1], [1], [0]])  # v0 reversed, exactly
    for e in impacts:
        before, after = energy(e.state_before, M, K), energy(e.state_after, M, K)
        with workprec(200):
            assert before.overlaps(after) and abs(before - after) < arb(10) ** -35
    # and the energy of x0 is that of every impact state (no loss anywhere)
    assert energy(x0, M, K).overlaps(energy(impacts[-1].state_after, M, K))


def test_partially_elastic_impacts_lose_energy():
    M, K = [[1, 0], [0, 1]], [[2, -1], [-1, 1]]
    carts = mechanical(M, K, [[1, 0]], restitution="1/2")
    tr = simulate(carts, [0, -1, -1, 0], 1)
    e0 = tr.events[0]  # at t = 0: v0 = -1 -> +1/2, energy 1 -> 5/8 (q^T K q / 2 = 1/2)
    assert e0.state_after.known_rational() == fmpq_mat([[0], [-1], [fmpq(1, 2)], [0]])
    assert e0.modes == (frozenset({0}),) and e0.mode_after == frozenset()


def test_bouncing_ball_times_and_velocities():
    g, v0, e = fmpq(10), fmpq(10), fmpq(1, 2)
    ball = mechanical([[1]], [[0]], [[1]], force=[-g], restitution=e, q_names=["h"])
    tr = simulate(ball, ball.embed([0, v0]), fmpq(39, 10))
    t, v = fmpq(0), v0
    assert len(tr.events) == 5
    for ev in tr.events:
        t += 2 * v / g  # free flight from the floor at speed v
        assert ev.time.ball(40).overlaps(arb(t))
        assert all(a.ball(40).overlaps(arb(b)) for a, b in zip(ev.state_before, (0, -v, 1)))
        v = e * v
        assert all(a.ball(40).overlaps(arb(b)) for a, b in zip(ev.state_after, (0, v, 1)))
        assert ev.mode_before == ev.mode_after == frozenset() and ev.modes == (frozenset({0}),)


def test_bouncing_ball_dropped_from_rest_crosses_its_accumulation_exactly():
    """h = 1, g = 981/100, e = 9/10 (Siconos' BouncingBallTS): t1 = sqrt(2 h / g) is irrational;
    the impacts are at t1 (1 + 2 e + ... + 2 e^(k-1)), the velocity after impact k is
    e^k g t1, and the impacts accumulate at t* = t1 (1 + e) / (1 - e), after which the ball
    rests on the floor (the contact force equals the weight)."""
    import sympy
    h, g, e = sympy.Integer(1), sympy.Rational(981, 100), sympy.Rational(9, 10)
    ball = mechanical([[1]], [[0]], [[1]], force=["-981/100"], restitution="9/10", q_names=["h"])
    tr = simulate(ball, ball.embed([1, 0]), 10)
    assert tr.certified and not tr.partial
    t1 = sympy.sqrt(2 * h / g)
    t = t1
    for k, ev in enumerate(tr.events, start=1):
        assert sympy.simplify(ev.time.closed_form - t) == 0  # exact, proven closed form
        v_after = ev.state_after.closed_form()[1]
        assert sympy.simplify(v_after - e ** k * g * t1) == 0
        t += 2 * e ** k * t1
    (acc,) = tr.accumulations
    assert sympy.simplify(acc.time.closed_form - t1 * (1 + e) / (1 - e)) == 0
    assert acc.state.known_rational() == fmpq_mat([[0], [0], [1]]) and acc.ratio == fmpq(9, 10)
    assert tr.state(10).known_rational() == fmpq_mat([[0], [0], [1]])
    assert tr.u(10).known_rational() == fmpq_mat([[fmpq(981, 100)]])  # resting: u = m g
    # inside the window: just before t*, the ball is airborne and below its last apex
    x = tr.state(acc.time * fmpq(99, 100))
    assert x[0].sign() > 0 and x[0].ball(30) < arb(1) / 100


def test_a_ball_with_a_radius_rests_on_the_floor_after_its_accumulation():
    """y = q - 1/10 (a ball of radius 1/10, a gap): the symmetry holds in the coordinates
    q - 1/10 (lcs_exact.accumulations.accumulation moves the constant offset onto the state).  Dropped from
    q = 3/10 under g = 10: 3/10 - 1/10 = 5 t1^2, t1 = 1/5, impacts at t1 (1 + 2e + ...), with
    e = 1/2 the accumulation is at t1 (1 + e)/(1 - e) = 3/5, where the ball rests at q = 1/10."""
    ball = mechanical([[1]], [[0]], [[1]], force=[-10], gap=["-1/10"], restitution="1/2")
    tr = simulate(ball, ball.embed(["3/10", 0]), 10)
    assert [e.time.known_rational() for e in tr.events] == [fmpq(1, 5), fmpq(2, 5), fmpq(1, 2)]
    (acc,) = tr.accumulations
    assert acc.time.known_rational() == fmpq(3, 5)
    assert acc.state.known_rational() == fmpq_mat([[fmpq(1, 10)], [0], [1]])
    assert tr.state(10).known_rational() == fmpq_mat([[fmpq(1, 10)], [0], [1]])
    # inside the window, the state at t = 1/2 + 1/8 (the apex of the 4th flight, the reference
    # flight scaled by 1/2): q = 1/10 + 5 (1/20)^2 ... from v = 1/4 after the 3rd impact
    x = tr.state(fmpq(1, 2) + fmpq(1, 40))
    assert x.known_rational() == fmpq_mat([[fmpq(1, 10) + fmpq(1, 4) * fmpq(1, 40) - 5 * fmpq(1, 40) ** 2],
                                           [0], [1]])


def test_fixtures_carry_the_impact_law():
    """The restitution is part of the system: a fixture keeps it (schema-valid), and reading the
    fixture back rebuilds the same LCS, so an exact re-run reproduces the bounces."""
    from lcs_exact import read_fixture, validate_fixture
    ball = mechanical([[1]], [[0]], [[1]], force=[-10], restitution="1/2")
    tr = simulate(ball, ball.embed([0, 10]), 4)
    fx = tr.to_fixture(20, sample="1/2")
    validate_fixture(fx)
    assert fx["system"]["restitution"] == ["1/2"] and fx["accumulations"][0]["time"]["exact"] == "4"
    back = read_fixture(fx)
    assert back.lcs.restitution == (fmpq(1, 2),)
    again = simulate(back.lcs, ball.embed([0, 10]), 4)
    assert [e.time.known_rational() for e in again.events] == [2, 3, fmpq(7, 2)]
    plain = mechanical([[1]], [[0]], [[1]], force=[-10])
    assert "restitution" not in simulate(plain, plain.embed([0, 10]), 1).to_fixture(10)["system"]


@pytest.mark.slow
def test_two_contact_ball_accumulates_on_the_floor_below_its_ceiling():
    """Siconos' BouncingBallED-TwoContacts: g = 10, e = 4/5, floor q >= 0 and ceiling 3/2 - q >= 0,
    from q = 1 moving up at 10.  By hand (sympy, here): flights between the contacts under
    gravity, Newton's law at each; once the ball no longer reaches the ceiling (v^2 / 2g < 3/2
    after a floor impact at speed v) its impacts accumulate at t + 2v / (g (1 - e)).  The
    ceiling never acts in that cycle, and it is certified positive on all the scaled flights."""
    import sympy as sp
    g, e, top = sp.Integer(10), sp.Rational(4, 5), sp.Rational(3, 2)
    ball = mechanical([[1]], [[0]], [[1], [-1]], force=[-10], gap=[0, "3/2"], restitution="4/5",
                      constraint_names=["floor", "ceiling"])
    tr = simulate(ball, ball.embed([1, 10]), 10)
    assert tr.certified and not tr.partial
    t, q, v = sp.Integer(0), sp.Integer(1), sp.Integer(10)
    hand = []
    while True:
        # next contact: the ceiling if the apex reaches it, else the floor
        s = sp.Symbol("s", positive=True)
        if v > 0 and q + v ** 2 / (2 * g) >= top:
            dt = min(r for r in sp.solve(q + v * s - g * s ** 2 / 2 - top, s) if r.is_positive)
            which = "ceiling"
        else:
            dt = max(sp.solve(q + v * s - g * s ** 2 / 2, s))
            which = "floor"
        t, v = sp.simplify(t + dt), sp.simplify(-e * (v - g * dt))
        q = top if which == "ceiling" else 0
        hand.append((t, which))
        if which == "floor" and v ** 2 / (2 * g) < top and len(hand) >= 4:
            break
    for ev, (th, which) in zip(tr.events, hand):
        assert sp.simplify(ev.time.closed_form - th) == 0
        assert ev.triggers == ((f"y_{0 if which == 'floor' else 1}"),)
    t_star = hand[-1][0] + 2 * v / (g * (1 - e))
    (acc,) = tr.accumulations
    assert sp.simplify(acc.time.closed_form - t_star) == 0
    assert tr.state(10).known_rational() == fmpq_mat([[0], [0], [1]])


def test_zeno_stop_reports_the_exact_accumulation_time():
    """zeno='stop': ZenoDetected carries t* = t1 (1 + e)/(1 - e) exactly (.time) and a certified
    rational enclosure (.lower <= t* <= .upper)."""
    import sympy
    from lcs_exact import ZenoDetected
    ball = mechanical([[1]], [[0]], [[1]], force=[-10], restitution="1/2")
    with pytest.raises(ZenoDetected) as err:
        simulate(ball, ball.embed([5, 0]), 10, zeno="stop")  # t1 = 1, t* = 3
    z = err.value
    assert z.time.known_rational() == 3 and z.lower == z.upper == 3
    ball = mechanical([[1]], [[0]], [[1]], force=[-10], restitution="1/2")
    with pytest.raises(ZenoDetected) as err:
        simulate(ball, ball.embed([1, 0]), 10, zeno="stop")  # t1 = 1/sqrt 5, t* = 3/sqrt 5
    z = err.value
    assert sympy.simplify(z.time.closed_form - 3 / sympy.sqrt(5)) == 0
    with workprec(128):
        assert arb(z.lower) <= z.time.ball(30) <= arb(z.upper) and z.upper - z.lower < fmpq(1, 10 ** 15)
