"""Taylor steps of e^{Mt} x (lcs_exact.numbers.taylorsteps) and the constraint functions on them
(lcs_exact.phases.taylorsum): enclosures checked against closed forms written here, and runs of
large systems (Taylor steps) checked event by event against the spectral path."""
from fractions import Fraction

import pytest
from flint import arb, arb_mat, fmpq, fmpq_mat

import lcs_exact.phases.phase as phase_module
from lcs_exact import simulate
from lcs_exact.examples import cart_chain
from lcs_exact.numbers import TaylorSteps, first_step, workprec
from lcs_exact.phases.taylorsum import TaylorRows


def _contains(ball, exact):
    """ball holds the exact value, given as a ball at least as accurate (overlapping a wider
    reference would prove nothing; the references here are far tighter: computed at 400 bits)."""
    assert exact.rad() <= ball.rad() or exact.rad() < arb(2) ** -300
    return ball.contains(exact)


def test_rotation_over_several_steps_holds_cos_and_sin():
    """M = [[0, 1], [-1, 0]], x0 = (1, 0): x(t) = (cos t, -sin t); ||M|| = 1, so h = 4 and t = 10
    is in the third step."""
    with workprec(200):
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 200)
        assert st.h == 4
        for t in (fmpq(1, 3), fmpq(4), fmpq(10), fmpq(57, 7)):
            x = st.state(arb(t))
            with workprec(400):
                assert _contains(x[0, 0], arb(t).cos()) and _contains(x[1, 0], -arb(t).sin())
            assert x[0, 0].rad() < arb(2) ** -150  # accurate, not merely enclosing
        assert st.locate(fmpq(10)) == 2 and st.start(2) == 8


def test_high_precision_steps_stay_accurate():
    """At 600 bits (J ~ 120 terms a step of ||M h|| = 4, unscaled columns M^j x up to 4^120) the
    rotation's state at t = 10 (third step) still holds (cos 10, -sin 10) to ~2^-590."""
    with workprec(600):
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 600)
        x = st.state(arb(10))
        assert x[0, 0].contains(arb(10).cos()) and x[1, 0].contains(-arb(10).sin())
        assert x[0, 0].rad() < arb(2) ** -580 and x[1, 0].rad() < arb(2) ** -580


def test_zero_coordinates_stay_exactly_zero():
    """zero = [2]: the caller's proof that x_3(t) = 0 (here x_3' = x_3, x_3(0) = 0).  A start
    ball with a radius in x_3 still gives exact zeros in every column and state, and (x_1, x_2)
    is the rotation (cos t, -sin t) of a start (1, 0), the start's radius 10^-30 grown at most as
    e^{||M|| t}."""
    M = fmpq_mat([[0, 1, 0], [-1, 0, 0], [0, 0, 1]])
    with workprec(200):
        x0 = arb_mat([[arb(1, fmpq(1, 10 ** 30))], [arb(0, fmpq(1, 10 ** 30))], [arb(0, fmpq(1, 10 ** 30))]])
        st = TaylorSteps(M, fmpq(1), x0, 200, zero=[2])
        assert x0[2, 0].rad() > 0  # the caller's ball is not changed
        for k in range(3):
            assert all(w[2, 0].is_exact() and w[2, 0] == 0 for w in st.columns(k))
        for t in (fmpq(1, 3), fmpq(10)):
            x = st.state(arb(t))
            assert x[2, 0].is_exact() and x[2, 0] == 0
            assert x[0, 0].contains(arb(t).cos()) and x[1, 0].contains(-arb(t).sin())
            assert x[0, 0].rad() < 2e-30 * arb(t).exp()  # the start's radius, grown at most as e^{||M|| t}


def test_jordan_block_at_a_point_and_over_an_interval():
    """M = -I + N (N the 3 x 3 shift): e^{Mt} x = e^{-t} (x1 + t x2 + t^2/2 x3, x2 + t x3, x3)."""
    M = fmpq_mat([[-1, 1, 0], [0, -1, 1], [0, 0, -1]])
    x0 = fmpq_mat([[1], [-2], [fmpq(1, 3)]])
    with workprec(128):
        st = TaylorSteps(M, fmpq(2), arb_mat(x0), 128)

        def exact(t):
            e = (-t).exp()
            return [e * (1 - 2 * t + t * t / 6), e * (-2 + t / 3), e / 3]

        for t in (fmpq(7, 3), fmpq(5)):
            x = st.state(arb(t))
            with workprec(400):
                for i, v in enumerate(exact(arb(t))):
                    assert _contains(x[i, 0], v)
        X = st.state(arb(1).union(arb(2)))  # an enclosure over [1, 2], across a step boundary
        with workprec(400):
            for k in range(11):
                t = arb(1) + arb(fmpq(k, 10))
                for i, v in enumerate(exact(t)):
                    assert _contains(X[i, 0], v)


def test_rows_and_their_derivatives():
    """f = g e^{Mt} x0 with the rotation, g = (1, 0): f = cos t, f^(d) = cos(t + d pi / 2); a
    second row g = (1, 1) on the same steps: cos t - sin t."""
    with workprec(128):
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 128)
        rows = TaylorRows(st, [fmpq_mat([[1, 0]]), fmpq_mat([[1, 1]])])
        f, g = rows.function(0), rows.function(1)
        for t in (fmpq(1, 2), fmpq(6)):
            vals = f.values(t, range(0, 6))
            gv = g.value(t)
            with workprec(400):
                for d, v in enumerate(vals):
                    assert _contains(v, (arb(t) + d * arb.pi() / 2).cos()), (t, d)
                assert _contains(gv, arb(t).cos() - arb(t).sin())
        # enclosures over an interval hold the values inside it and are tight on a short one
        E = f.enclose(fmpq(3), fmpq(31, 10), 0)
        with workprec(400):
            assert _contains(E, arb(3).cos()) and _contains(E, arb(fmpq(31, 10)).cos())
        assert E.rad() < 0.01
        assert f.sign_enclose(fmpq(0), fmpq(1), 0) > 0  # cos > 0 on [0, 1]
        assert f.sign_enclose(fmpq(2), fmpq(3), 0) < 0
        # float guesses on a grid of h / 64 = 1/16 (offset by 0.618 / 16): cos first turns negative
        # after pi/2, cos - sin after pi/4 (both in the first step, where the scan stops); ``only``
        # leaves rows out
        ga = rows.guess_crossings(0.0, 10.0)
        assert 0 <= ga[0] - 1.5707963268 < 1 / 16 and 0 <= ga[1] - 0.7853981634 < 1 / 16
        assert rows.guess_crossings(0.0, 10.0, only=[1])[0] is None
        g5 = rows.guess_crossings(5.0, 10.0)[0]  # cos t < 0 again after 5 pi / 2 (in step 1)
        assert 0 <= g5 - 7.853981634 < 1 / 16 and g5 * 16 != int(g5 * 16)
        assert abs(f.guess_root(1.0, 2.0) - 1.5707963267948966) < 1e-12


def _chain_runs(N, T=10):
    lcs = cart_chain(N)
    x0 = [Fraction((-1) ** i, 2) for i in range(N)] + [0] * N
    return lcs, x0


def test_a_chain_on_taylor_steps_matches_the_spectral_path(monkeypatch):
    """Eight carts (n = 16, on Taylor steps from n = 16 here): every event time to 40 digits, the
    modes, and x(10) agree with the spectral path (the same run with Taylor steps switched off);
    the Taylor run never computes a mode's spectral data."""
    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 16)
    lcs, x0 = _chain_runs(8)
    taylor = simulate(lcs, x0, 10, digits=30)
    visited = [lcs.mode(e.mode_after) for e in taylor.events]
    assert not any("_spectrum" in m.__dict__ for m in visited)
    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 10 ** 9)
    lcs2, _ = _chain_runs(8)
    spectral = simulate(lcs2, x0, 10, digits=30)
    assert len(taylor.events) == len(spectral.events) == 6
    for a, b in zip(taylor.events, spectral.events):
        assert (a.mode_before, a.modes, a.mode_after) == (b.mode_before, b.modes, b.mode_after)
        assert a.time.decimal(40).split(" ")[0] == b.time.decimal(40).split(" ")[0]
    xa, xb = taylor.state(10), spectral.state(10)
    for a, b in zip(xa.ball(30), xb.ball(30)):  # two certified balls of 30 digits that overlap
        assert a.overlaps(b) and a.rad() < 1e-30 and b.rad() < 1e-30
    assert taylor.certified and spectral.certified


def test_a_taylor_run_travels_to_a_sweep_parent_and_refines_there():
    """A trajectory of Taylor phases travels as a sweep's worker sends it (its ball caches left
    behind) and refines its event times further after the trip: the same 60 digits as the
    original refined in place."""
    from lcs_exact.dynamics.sweep import _dumps, _loads

    lcs, x0 = _chain_runs(16)  # n = 32: Taylor steps
    tr = simulate(lcs, x0, 3, digits=20)
    assert tr.phases[-1].phase.taylor
    back = _loads(_dumps(tr, lcs), lcs)
    assert back.events[-1].time.decimal(60) == tr.events[-1].time.decimal(60)
    assert len(back.events) == len(tr.events) >= 3


def test_a_long_quiet_horizon_goes_to_the_spectral_path(monkeypatch):
    """A phase whose search would span more than TAYLOR_MAX_SPAN units of ||A_I|| t uses the
    spectral data: the same events as with Taylor steps."""
    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 16)
    lcs, x0 = _chain_runs(8)
    ref = simulate(lcs, x0, 2, digits=30)
    monkeypatch.setattr(phase_module, "TAYLOR_MAX_SPAN", 1)
    lcs2, _ = _chain_runs(8)
    other = simulate(lcs2, x0, 2, digits=30)
    assert [e.time.decimal(35) for e in ref.events] == [e.time.decimal(35) for e in other.events]
    assert all(m.__dict__.get("_spectrum") is not None for m in [lcs2.mode(ref.events[0].mode_after)])


def test_a_theta_past_the_step_widens_the_tail_and_far_past_it_is_refused():
    """The tail bound holds for |theta| <= 1; a ball just past it (a rounding at a step's end)
    gets the factor m^J e^{s (m - 1)}, a time before -h is an internal error, not a guess."""
    from lcs_exact.errors import LCSError

    with workprec(128):
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 128)
        inside, past = st.tail_at(0, 0, arb(1)), st.tail_at(0, 0, arb(fmpq(9, 8)))
        m = arb(fmpq(9, 8))
        assert past >= inside * m ** st.J * (4 * (m - 1)).exp() * arb(fmpq(99, 100))
        assert inside.mid() == st.tail(0, 0).mid() and inside.rad() == st.tail(0, 0).rad()
        with pytest.raises(LCSError):
            st.pieces(fmpq(-5), fmpq(1))


def test_the_paper_two_carts_on_taylor_steps(monkeypatch):
    """Section 7 with every phase on Taylor steps (TAYLOR_MIN_N = 1): the events at t = 1 exactly
    (a rational root, where a float guess on a dyadic grid would have landed with no sign to show)
    and at 1 + pi/2 (closed form proven), and x(3) = e^{A(2 - pi/2)} (0, 0, 0, 1) to 30 digits
    (mpmath's expm)."""
    import mpmath as mp
    import sympy as sp

    from lcs_exact import expm_action
    from lcs_exact.examples import two_carts

    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 1)
    lcs = two_carts()
    tr = simulate(lcs, expm_action(lcs.A, -1, [0, -1, -1, 0]), 3, digits=30)
    assert [e.time.closed_form for e in tr.events] == [1, 1 + sp.pi / 2]
    A = [[int(lcs.A[i, j]) for j in range(4)] for i in range(4)]
    with mp.workdps(50):
        want = mp.expm(mp.matrix(A) * (2 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1])
        for b, w in zip(tr.state(3).ball(30), want):
            assert abs(mp.mpf(b.mid().str(45, radius=False)) - w) < mp.mpf(10) ** -30 and b.rad() < 1e-30


def test_a_guess_on_an_event_at_a_rational_time_does_not_end_a_window(monkeypatch):
    """With the guess grid put back on the dyadics (offset 1: points (p + 1) h / 64), section 7's
    guess for y_0 lands exactly on its root t = 1, where f's ball holds 0 at every precision: the
    search ignores that window and searches the horizon (it raised UnresolvedSign before)."""
    import sympy as sp

    import lcs_exact.phases.taylorsum as taylorsum
    from lcs_exact import expm_action
    from lcs_exact.examples import two_carts

    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 1)
    monkeypatch.setattr(taylorsum, "GUESS_OFFSET", 1.0)
    lcs = two_carts()
    tr = simulate(lcs, expm_action(lcs.A, -1, [0, -1, -1, 0]), 3, digits=30)
    assert [e.time.closed_form for e in tr.events] == [1, 1 + sp.pi / 2]


def test_event_states_on_taylor_steps_take_the_centered_form_in_a_run_that_lost_accuracy(monkeypatch):
    """Once a run has lost CENTERED_AFTER_LOST bits, its event states on Taylor steps are computed
    in the centered form (set to -1 here: from the first event): eight carts on Taylor steps to
    t = 60 give the spectral path's events (times to 35 digits, modes) and x(60), as plain balls do."""
    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 16)
    runs = {}
    for centered in (-1, 10 ** 9):
        monkeypatch.setattr(phase_module, "CENTERED_AFTER_LOST", centered)
        lcs, x0 = _chain_runs(8)
        runs[centered] = simulate(lcs, x0, 60, digits=30)
    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 10 ** 9)
    lcs, x0 = _chain_runs(8)
    spectral = simulate(lcs, x0, 60, digits=30)
    first = runs[-1].events[0].state_before
    assert runs[-1].phases[0].phase.taylor and first.centered and not runs[10 ** 9].events[0].state_before.centered
    for tr in runs.values():
        assert tr.certified and len(tr.events) == len(spectral.events) >= 20
        for a, b in zip(tr.events, spectral.events):
            assert (a.mode_before, a.modes, a.mode_after) == (b.mode_before, b.modes, b.mode_after)
            assert a.time.decimal(35).split(" ")[0] == b.time.decimal(35).split(" ")[0]
        for a, b in zip(tr.state(60).ball(30), spectral.state(60).ball(30)):
            assert a.overlaps(b)


def test_a_geometric_start_of_the_grid_keeps_every_value():
    """A first step of 1/1000 (rounded down to h / 2^m = 1/1024, h = 4): the grid runs 0, 1/1024,
    1/512, ..., 2, 4, 8, ...; every point is located in its step, and x(t) = (cos t, -sin t) holds
    on the short steps, across the switch to the regular length and beyond it."""
    with workprec(200):
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 200, first=fmpq(1, 1000))
        assert st.length(0) == fmpq(1, 1024) and st.m == 12
        assert [st.start(k) for k in (0, 1, 2, 3, 12, 13, 14)] == [0, fmpq(1, 1024), fmpq(1, 512), fmpq(1, 256),
                                                                   2, 4, 8]
        for k in range(20):
            assert st.locate(st.start(k)) == k and st.start(k + 1) - st.start(k) == st.length(k)
            assert st.locate(st.start(k + 1) - fmpq(1, 10 ** 6)) == k
        assert st.order(0) < st.order(6) < st.J  # short steps need fewer terms
        for t in (fmpq(1, 3000), fmpq(1, 700), fmpq(3, 10), fmpq(39, 10), fmpq(10)):
            x = st.state(arb(t))
            with workprec(400):
                assert _contains(x[0, 0], arb(t).cos()) and _contains(x[1, 0], -arb(t).sin())
            assert x[0, 0].rad() < arb(2) ** -150
        rows = TaylorRows(st, [fmpq_mat([[1, 0]])])
        f = rows.function(0)
        with workprec(400):  # derivatives on a short step: f^(d) = cos(t + d pi / 2)
            for d, v in enumerate(f.values(fmpq(1, 2000), range(4))):
                assert _contains(v, (arb(fmpq(1, 2000)) + d * arb.pi() / 2).cos())
        assert 0 <= rows.guess_crossings(0.0, 10.0)[0] - 1.5707963268 < 1 / 16


def test_first_step_of_a_gap_closing_early():
    """A free particle (x' = v) at 10^-40 from its stop, moving toward it at unit speed: the
    position crosses zero at t = 10^-40, and the first step is a power of two within a factor 4
    of it; from an O(1) gap, or moving away, there is no short step."""
    M = fmpq_mat([[0, 1], [0, 0]])
    G = fmpq_mat([[1, 0]])
    with workprec(200):
        h0 = first_step(M, G, arb_mat([[fmpq(1, 10 ** 40)], [-1]]), 200, fmpq(1))
        assert fmpq(1, 10 ** 40) < h0 <= fmpq(5, 10 ** 40)
        st = TaylorSteps(M, fmpq(1), arb_mat([[fmpq(1, 10 ** 40)], [-1]]), 200, first=h0)
        assert st.length(0) <= h0 and st.order(0) == 2  # x(t) = 10^-40 - t exactly: two terms
        assert first_step(M, G, arb_mat([[1], [-1]]), 200, fmpq(1)) is None
        assert first_step(M, G, arb_mat([[fmpq(1, 10 ** 40)], [1]]), 200, fmpq(1)) is None


def test_positive_until_proves_rows_positive_without_a_search():
    """cos t > 0 on (0, 1] but not on (0, 2] (it crosses at pi/2); sin t (order 1 at 0) > 0 on
    (0, 3]; on the shift x1' = x2, x2' = x3, x3' = x4: 10^-30 + t^3 > 0 on (0, 1/2] (every
    coefficient positive: Horner on a ball of theta would lose the sign) and t^2 - t^3 (order 2)
    > 0 on (0, 1/2], not on (0, 2] (it crosses at 1)."""
    with workprec(128):
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 128)
        rows = TaylorRows(st, [fmpq_mat([[1, 0]]), fmpq_mat([[0, -1]])])
        assert rows.positive_until(0, 0, fmpq(1)) and not rows.positive_until(0, 0, fmpq(2))
        assert rows.positive_until(1, 1, fmpq(3))
        M = fmpq_mat([[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]])
        st = TaylorSteps(M, fmpq(1), arb_mat([[fmpq(1, 10 ** 30)], [0], [0], [6]]), 128, first=fmpq(1, 2))
        rows = TaylorRows(st, [fmpq_mat([[1, 0, 0, 0]])])
        assert rows.positive_until(0, 0, fmpq(1, 2))
        st = TaylorSteps(M, fmpq(1), arb_mat([[0], [0], [2], [-6]]), 128)
        rows = TaylorRows(st, [fmpq_mat([[1, 0, 0, 0]])])
        assert rows.positive_until(0, 2, fmpq(1, 2)) and not rows.positive_until(0, 2, fmpq(2))


def test_a_quiet_phase_is_proven_on_the_screen_and_the_others_are_searched(monkeypatch):
    """The screen (Taylor steps of SCREEN_PREC bits) decides a phase without events alone, and
    hands every other phase to the search at its own precision.  x = (cos t, -sin t, 1) and
    y = x_0 + c x_2 = cos t + c: c = 2 stays >= 1 (no event in (0, 10], no step at the search's
    precision computed); c = 1/2 crosses at 2 pi / 3 (acos(-1/2), a guess on the screen: the
    search finds it to 30 digits); c = 1 only touches 0 at t = pi (no guess crosses, but no
    enclosure shows y > 0 there: the search proves the touch, which is no event)."""
    import mpmath as mp

    import lcs_exact.phases.flow as flow
    from lcs_exact import LCS
    from lcs_exact.phases.flow import theta

    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 1)
    seen = []
    quiet = flow._quiet

    def spy(phase, end):
        ok, guess = quiet(phase, end)
        seen.append((ok, phase))
        return ok, guess

    monkeypatch.setattr(flow, "_quiet", spy)
    A, B, D = [[0, 1, 0], [-1, 0, 0], [0, 0, 0]], [[0], [0], [0]], [[1]]
    results = {}
    for c in ("2", "1/2", "1"):
        results[c] = theta(LCS(A, B, [[1, 0, c]], D), [1, 0, 1], set(), 10)
    assert [ok for ok, _ in seen] == [True, False, False]
    searched = [ph._rows.steps.computed for _, ph in seen]  # steps at the search's precision
    assert searched[0] == 0 and searched[1] > 0 and searched[2] > 0
    assert results["2"] is None and results["1"] is None
    with mp.workdps(40):
        want = mp.acos(mp.mpf(-1) / 2)
    got = results["1/2"].decimal(30).split(" ")[0]
    assert abs(mp.mpf(got) - want) < mp.mpf(10) ** -29


def test_a_phase_bounded_by_its_event_rebuilds_short_steps_with_the_same_values():
    """The first phase of 16 carts (n = 32, Taylor steps; q0 = (1, -1, 1, ...)/2 but cart 14 at
    1/100 from its stop, v0 = 0): once next_event has bracketed the event (cart 14 reaches the
    stop near t = 0.14, pushed at about unit acceleration: sqrt(2 / 100)), steps built at
    a higher precision take a first step longer than the event (the search's grid is uniform,
    h = 1) and fewer terms; the state at the event at 600 bits holds x(theta) = e^{A theta} x0
    computed here with mpmath at 700 bits (A the free chain's matrix, theta the root's midpoint,
    its radius far below the state's)."""
    import mpmath
    from lcs_exact.numbers import Policy, as_exact_vector
    from lcs_exact.phases.flow import next_event
    from lcs_exact.phases.phase import Phase
    from lcs_exact.numbers import as_real
    N = 16
    lcs = cart_chain(N)
    x0 = [Fraction((-1) ** i, 2) for i in range(N)] + [0] * N
    x0[14] = Fraction(1, 100)
    phase = Phase(lcs.mode(set()), as_exact_vector(x0, lcs.n), Policy())
    assert phase.taylor
    hit = next_event(phase, as_real(10), 128)
    theta = hit.theta
    assert [c.name for c in hit.constraints] == ["y_7"] and 0.1 < float(theta.hi) < 0.2
    # the screen's guess (its first negative point after the crossing) gave the search a first step
    # past the event, at most twice the guess; once bracketed, the phase ends by 2 theta.hi
    assert theta.hi < phase.first_step < fmpq(1, 2) and theta.hi < phase._end <= 2 * theta.hi
    steps = phase.taylor_rows(600).steps
    assert theta.hi < steps.length(0) < 1 and steps.locate(theta.hi) == 0
    uniform = phase_module.TaylorSteps(phase.M, phase.mode.closed_loop_norm, phase.base.arb(600), 600)
    assert steps.order(0) < uniform.order(0)
    t = theta.arb(600)
    x = phase.propagate(t, 600)
    mpmath.mp.prec = 700
    A = mpmath.matrix([[mpmath.mpf(int(lcs.A[i, j].p)) / int(lcs.A[i, j].q) for j in range(lcs.n)] for i in range(lcs.n)])
    mid = t.mid().man_exp()
    tm = mpmath.mpf(int(mid[0])) * mpmath.mpf(2) ** int(mid[1])
    ref = mpmath.expm(A * tm) * mpmath.matrix([mpmath.mpf(v.numerator) / v.denominator for v in x0])
    for i in range(lcs.n):
        err = abs(mpmath.mpf(x[i, 0].mid().str(220, radius=False)) - ref[i])
        assert err <= mpmath.mpf(x[i, 0].rad().str(5, radius=False)) * 2 + mpmath.mpf(2) ** -550
        assert x[i, 0].rad() < arb(2) ** -500


def test_a_root_ball_rounded_below_zero_is_evaluated_from_zero():
    """A root bracketed in (10^-185, 3 10^-89] as a 149-bit ball reaches below 0 by rounding; on
    a grid whose first step is 10^-185 that is outside step 0's series (LCSError), and a phase's
    time (nonnegative=True) is taken from 0: the rotation's state over [0, 3 10^-89] holds
    (cos t, -sin t) = (1 - t^2/2 + ..., -t + ...), i.e. (1, 0) within 10^-40 and 3.1 10^-89."""
    from lcs_exact.errors import LCSError
    from lcs_exact.numbers.balls import dyadic_lower
    with workprec(149):
        t = arb(fmpq(1, 10 ** 185)).union(arb(fmpq(3, 10 ** 89)))
        assert dyadic_lower(t) < 0
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 149, first=fmpq(1, 10 ** 185))
        with pytest.raises(LCSError, match="internal inconsistency"):
            st.state(t)
        x = st.state(t, nonnegative=True)
        for s in (fmpq(0), fmpq(1, 10 ** 100), fmpq(3, 10 ** 89)):
            assert x[0, 0].contains(arb(s).cos()) and x[1, 0].contains(-arb(s).sin())
        assert x[0, 0].rad() < 1e-40 and x[1, 0].rad() < 3.1e-89


def test_a_ball_rounded_past_a_step_end_is_evaluated_on_that_step():
    """[0, 4] as a ball reaches 4 + 2^-28 by the rounding of its radius; the rotation's step is
    h = 4, so the enclosure over it is step 0's series at theta <= 1 + 2^-30 (the tail widened by
    tail_at), and step 1's columns are not computed for that rounding.  A ball reaching 4 + 1/8
    (past 2^-16 of the step) opens step 1.  Both hold (cos t, -sin t) at 0, 2, 4 and at their upper
    ends, and a row's values over the ball (TaylorSum.values) take the same single step."""
    from lcs_exact.numbers.balls import dyadic_upper

    with workprec(128):
        t = arb(0).union(arb(4))
        assert dyadic_upper(t) > 4
        st = TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 128)
        x = st.state(t)
        assert st.computed == 1
        for s in (fmpq(0), fmpq(2), fmpq(4), dyadic_upper(t)):
            assert x[0, 0].contains(arb(s).cos()) and x[1, 0].contains(-arb(s).sin())
        far = arb(0).union(arb(fmpq(33, 8)))
        y = st.state(far)
        assert st.computed == 2
        assert y[1, 0].contains(-arb(fmpq(33, 8)).sin()) and y[0, 0].contains(arb(fmpq(33, 8)).cos())

        rows = TaylorRows(TaylorSteps(fmpq_mat([[0, 1], [-1, 0]]), fmpq(1), arb_mat([[1], [0]]), 128),
                          [fmpq_mat([[1, 0]])], [fmpq(1)], fmpq_mat([[1, 0]]))
        f = rows.function(0)
        v, dv = f.values(t, range(2))
        assert rows.steps.computed == 1
        for s in (fmpq(0), fmpq(4), dyadic_upper(t)):  # f = cos t, f' = -sin t
            assert v.contains(arb(s).cos()) and dv.contains(-arb(s).sin())


def test_a_crossing_the_screen_foresees_early_in_a_step_gets_a_short_first_step(monkeypatch):
    """x = (cos t, -sin t, 1) (||A|| = 1: regular steps of 4), y = x_0 + c x_2 = cos t + c.
    c = -199/200 crosses 0 at acos(199/200) = 0.1000...: the screen's first negative point is
    theta = 1.618/64 of the step (t = 0.101), so the search's steps start with h_0 = 1/8 (the
    power of two at most twice the guess; then 1/8, 1/4, ..., up to 4) and its root, to 30 digits, is acos(199/200) (mpmath).
    c = 1/2 crosses at 2 pi / 3, past half the step: the uniform grid stays."""
    import mpmath as mp

    import lcs_exact.phases.flow as flow
    from lcs_exact import LCS
    from lcs_exact.phases.flow import theta

    monkeypatch.setattr(phase_module, "TAYLOR_MIN_N", 1)
    seen = []
    quiet = flow._quiet

    def spy(phase, end):
        seen.append(phase)
        return quiet(phase, end)

    monkeypatch.setattr(flow, "_quiet", spy)
    A, B, D = [[0, 1, 0], [-1, 0, 0], [0, 0, 0]], [[0], [0], [0]], [[1]]
    early = theta(LCS(A, B, [[1, 0, "-199/200"]], D), [1, 0, 1], set(), 10)
    late = theta(LCS(A, B, [[1, 0, "1/2"]], D), [1, 0, 1], set(), 10)
    short, uniform = seen[0]._rows.steps, seen[1]._rows.steps
    assert short.h == 4 and short.length(0) == fmpq(1, 8) and short.m == 5 and short.start(short.m + 1) == 4
    assert uniform.m == 0 and uniform.length(0) == 4
    with mp.workdps(40):
        want = {"early": mp.acos(mp.mpf(199) / 200), "late": 2 * mp.pi / 3}
    for name, got in (("early", early), ("late", late)):
        assert abs(mp.mpf(got.decimal(30).split(" ")[0]) - want[name]) < mp.mpf(10) ** -29


def test_log2_floor_brackets_every_rational_between_powers_of_two():
    """floor(log2 q) from bit lengths and one shifted comparison: 2^e <= q < 2^(e+1) in
    Fractions, for powers of two (the steps' lengths), their neighbours and random rationals of
    up to 80 digits over 80 digits."""
    import random
    from lcs_exact.numbers.taylorsteps import _log2_floor
    rng = random.Random(7)
    cases = [(2 ** i, 2 ** j) for i in (0, 1, 5, 300) for j in (0, 1, 7, 300)]
    cases += [(2 ** i + d, 2 ** j) for i in (3, 64, 200) for j in (0, 9) for d in (-1, 1)]
    cases += [(rng.randint(1, 10 ** rng.randint(1, 80)), rng.randint(1, 10 ** rng.randint(1, 80))) for _ in range(2000)]
    for a, b in cases:
        e = _log2_floor(fmpq(a, b))
        assert Fraction(2) ** e <= Fraction(a, b) < Fraction(2) ** (e + 1), (a, b, e)


def test_positive_on_by_horner_then_by_the_composed_bound_and_never_wrongly():
    """_positive_on(p, lo, hi, rho) proves p + rho > 0 on [lo, hi]: 2 + theta - theta^2 (>= 2 on
    [0, 1]) already by Horner on the ball [0, 1] (2 + [0,1] - [0,1] = [1, 3]); 1/100 + theta^3
    on [0, 1/3] is not shown by Horner with the radius (it is on the composed polynomial's
    coefficients, all >= 0); theta - 1/2 on [0, 1] and 1 - theta on [0, 1] with rho = [+-1/2]
    (min 1/2 - 1/2 = 0 at theta = 1) are never proven positive."""
    from flint import arb_poly
    from lcs_exact.phases.taylorsum import _positive_on
    with workprec(128):
        zero = arb(0)
        assert _positive_on(arb_poly([2, 1, -1]), fmpq(0), fmpq(1), zero, 0)
        cubic = arb_poly([fmpq(1, 100), 0, 0, 1])
        assert not cubic(arb(0).union(arb(fmpq(1, 3)))) + arb(0, fmpq(1, 1000)) > 0  # Horner fails
        assert _positive_on(cubic, fmpq(0), fmpq(1, 3), arb(0, fmpq(1, 1000)), 0)
        assert not _positive_on(arb_poly([fmpq(-1, 2), 1]), fmpq(0), fmpq(1), zero, 3)
        assert not _positive_on(arb_poly([1, -1]), fmpq(0), fmpq(1), arb(0, fmpq(1, 2)), 3)


def test_unscaled_columns_factors_and_a_lazy_step_end():
    """Step k keeps u_j = M^j x_k and the factors h^j / j!; their products are the columns
    w_j = (M h)^j x_k / j! (here computed in Fractions: M the rotation, x_0 = (1, 0), h = 4), and
    x_1 (the sum at theta = 1) is formed only when step 1 is asked for: it holds (cos 4, -sin 4)."""
    M = [[0, 1], [-1, 0]]
    with workprec(128):
        st = TaylorSteps(fmpq_mat(M), fmpq(1), arb_mat([[1], [0]]), 128)
        us, fs = st.unscaled(0), st.factors(0)
        assert len(us) == len(fs) == st.order(0) and st.computed == 1 and len(st._x) == 1
        v, fact = [Fraction(1), Fraction(0)], 1
        for j, (u, f, w) in enumerate(zip(us, fs, st.columns(0))):
            if j:
                v, fact = [v[1], -v[0]], fact * j  # M v
            for i in range(2):
                assert u[i, 0].contains(fmpq(v[i].numerator, v[i].denominator))
                want = v[i] * Fraction(4) ** j / fact
                assert w[i, 0].contains(fmpq(want.numerator, want.denominator))
            assert f.contains(fmpq(4 ** j, fact))
        x1 = st.state_at(1)
        assert len(st._x) == 2 and st.computed == 1
        assert x1[0, 0].contains(arb(4).cos()) and x1[1, 0].contains(-arb(4).sin())
        assert x1[0, 0].rad() < arb(2) ** -100
