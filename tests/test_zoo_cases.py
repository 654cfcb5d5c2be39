"""The zoo as another solver's test suite uses it: lcs_exact.zoo.cases(), ZooCase's float data and
sources, assert_matches, the pytest plugin's ``lcs_zoo_case``, and the shipped fixtures (rebuilt
and compared by digest).  Two solvers written from the cases' float data only (tests/solvers.py:
backward Euler, Moreau-Jean) pass on the cases they can solve and fail when they are wrong.
Expected values are derived here (the bouncing ball's impacts t1 (1 + 2 e + ... + 2 e^j) with
t1 = sqrt(2 h / g); sin and cos of the source), never copied from a run."""
from __future__ import annotations

import json
import math

import mpmath as mp
import numpy as np
import pytest
from solvers import backward_euler, moreau_jean

import lcs_exact as L
from lcs_exact.verify import zoo

def ball_law():
    """The zoo's bouncing ball: g = 981/100, e = 9/10, dropped from H = 1 (at the test's 60 digits)."""
    return mp.mpf(981) / 100, mp.mpf(9) / 10, mp.mpf(1)


def ball_impact(j: int) -> mp.mpf:
    """The j-th impact (j = 0, 1, ...) of the ball dropped from H: t1 (1 + 2 (e + ... + e^j))."""
    G, E, H = ball_law()
    t1 = mp.sqrt(2 * H / G)
    return t1 * (1 + 2 * sum(E ** i for i in range(1, j + 1)))


def holds(ball, value: mp.mpf) -> bool:
    """The certified ball contains the value (computed at 60 digits here)."""
    mid, rad = mp.mpf(ball.mid().str(40, radius=False)), mp.mpf(ball.rad().str(5, radius=False))
    return abs(mid - value) <= rad + mp.mpf(10) ** -35


@pytest.fixture(scope="module")
def ball():
    return zoo.cases(["bouncing_ball"])[0]


def test_cases_are_the_problems_in_order():
    names = [c.name for c in zoo.cases()]
    assert names == [p.name for p in zoo.PROBLEMS] and len(names) == 15
    assert [c.name for c in zoo.cases("relay, bouncing_ball")] == ["bouncing_ball", "relay"]
    with pytest.raises(L.InvalidArgument, match="no problem 'nope'"):
        zoo.cases(["nope"])


def test_a_case_holds_the_float_data_a_solver_starts_from(ball):
    # the ball: q' = v, v' = -g c + u, c' = 0 (c = 1, gravity's constant source), y = q
    assert ball.A.tolist() == [[0, 1, 0], [0, 0, -9.81], [0, 0, 0]] and ball.B.tolist() == [[0], [1], [0]]
    assert ball.C.tolist() == [[1, 0, 0]] and ball.D.tolist() == [[0]] and ball.x0.tolist() == [1, 0, 1]
    assert ball.A.dtype == np.float64 and ball.restitution.tolist() == [0.9] and ball.t_end == 10
    assert ball.plant == (0, 1) and ball.sources.states == (2,) and ball.sources.expressions == ("1",)
    assert ball.sources([0.0, 7.5]).tolist() == [[1.0], [1.0]] and ball.step == pytest.approx(0.1)
    assert ball.state_names == ("q", "q'", "1") and "bouncing ball" in repr(ball)
    ball.A[0, 0] = 5  # a copy: the case stays as shipped
    assert ball.A[0, 0] == 0
    carts = zoo.cases("two_carts")[0]
    assert carts.restitution is None and carts.sources is None and carts.plant == (0, 1, 2, 3)


def test_a_sine_source_is_known_not_integrated():
    case = zoo.cases("sine_rectifier_half")[0]
    sb = case.sources
    assert sb.states == (1, 2) and sb.expressions == ("sin(t)", "cos(t)") and case.plant == (0,)
    ts = np.array([0.0, 1.0, math.pi / 2, 13.0])
    assert np.allclose(sb(ts), np.column_stack([np.sin(ts), np.cos(ts)]), rtol=0, atol=1e-15)
    # the fixture carries the same exosystem: S is the rotation z1' = z2, z2' = -z1
    assert case.fixture.sources.S.tolist() == [[0, 1], [-1, 0]] and case.fixture.data["sources"]["z0"] == ["0", "1"]


def test_implied_impacts_of_the_accumulation(ball):
    """tr.events lists three impacts; the fourth onward come from the accumulation's law."""
    fx = ball.fixture
    assert len(fx.events) == 3
    for j, e in enumerate(fx.events):
        assert holds(e.time, ball_impact(j))
    (acc,) = fx.accumulations
    for k in (0, 1, 7, 60):
        assert holds(acc.event_time(k), ball_impact(k + 3)), k
    G, E, H = ball_law()
    t_star = mp.sqrt(2 * H / G) * (1 + E) / (1 - E)
    assert holds(acc.time, t_star) and acc.time_exact == "190*sqrt(218)/327"


def test_exact_solution_passes_and_a_perturbed_one_names_the_worst_point(ball):
    t = np.arange(101) * ball.step  # the fixture's grid, accumulated in floats
    X = ball.fixture.to_numpy(t)
    report = ball.assert_matches(t, X, atol=1e-12)
    assert report.passed and report.n_compared >= 25 and report.names == ("q", "q'", "1")
    ball.assert_matches(t, X[:, list(ball.plant)], atol=1e-12)  # the plant's columns only
    X[40, 0] += 1e-3  # t = 4.0: between impacts 4 and 5 of the law (3.78 and 4.26)
    with pytest.raises(AssertionError, match=r"by 0\.001 > tolerance 1e-06 at t = 4(\.0+\d*)?, component q: solver"):
        ball.assert_matches(t, X, atol=1e-6)


def test_float_grid_overshooting_t_end_is_compared_at_t_end():
    """np.arange(N + 1) * h with N = 155 ends at 13.000000000000002 > t_end = 13."""
    case = zoo.cases("sine_rectifier_half")[0]
    t = np.arange(156) * (13 / 155)
    assert t[-1] > 13
    X = case.fixture.to_numpy([float(v) for v in t[:-1]] + [13])
    report = case.assert_matches(t, X, atol=1e-12, event_tol=0)
    assert report.n_beyond == 0 and report.n_compared == 156 - report.n_in_windows


@pytest.mark.slow
@pytest.mark.parametrize("name, h, atol", [
    ("two_carts", 3e-3, 1e-2), ("two_carts_hook", 1e-3, 5e-3), ("bouncing_ball", 1e-3, 0.2),
    ("cart_chain_4", 1e-2, 2e-2), ("ball_column_3", 1e-3, 5e-2), ("newtons_cradle_3", 2e-3, 1e-2)])
def test_moreau_jean_passes_on_the_mechanical_cases(name, h, atol):
    case = zoo.cases(name)[0]
    t, X = moreau_jean(case, h)
    case.assert_matches(t, X, atol=atol)
    case.assert_matches(t, X[:, list(case.plant)], atol=atol)  # the plant's states only


@pytest.mark.slow
@pytest.mark.parametrize("name, e", [("bouncing_ball", [0.8]), ("newtons_cradle_3", [0.9, 0.9]),
                                     ("ball_column_3", [0.4, 0.4, 0.4])])
def test_moreau_jean_with_a_wrong_restitution_fails(name, e):
    case = zoo.cases(name)[0]
    t, X = moreau_jean(case, 1e-3 * case.t_end, restitution=e)
    with pytest.raises(AssertionError, match="differs from the fixture"):
        case.assert_matches(t, X, atol=0.05)


@pytest.mark.slow
@pytest.mark.parametrize("name, frac, atol", [
    ("two_carts", 1e-3, 1e-2), ("half_wave_rectifier", 1e-3, 3e-2), ("diode_bridge", 1e-3, 2e-2),
    ("sine_rectifier_half", 1e-3, 5e-3), ("sine_rectifier_full", 1e-3, 5e-3), ("filippov_spiral", 1e-3, 3e-2),
    ("relay", 1e-3, 1e-9), ("stiff_rc_diode", 1e-3, 5e-3), ("buck_converter_dcm", 1 / 1600, 3e-2)])
def test_backward_euler_passes_on_the_cases_it_can_solve(name, frac, atol):
    case = zoo.cases(name)[0]
    t, X = backward_euler(case, frac * case.t_end)
    case.assert_matches(t, X, atol=atol)


@pytest.mark.slow
def test_backward_euler_with_a_wrong_source_amplitude_fails():
    """The half-wave rectifier driven by 2 sin t instead of sin t: the capacitor charges to 2."""
    case = zoo.cases("sine_rectifier_half")[0]
    t, X = backward_euler(case, 0.013)
    case.assert_matches(t, X[:, list(case.plant)], atol=5e-3)  # right: passes on the plant's states

    class Doubled:  # the solver's source, twice too strong
        states = case.sources.states

        def __call__(self, t):
            return 2 * case.sources(t)

    wrong = type("Case", (), {k: getattr(case, k) for k in ("A", "B", "C", "D", "t_end")})()
    wrong.sources, wrong.x0 = Doubled(), np.array([0.0, 0.0, 2.0])
    t, X = backward_euler(wrong, 0.013)
    with pytest.raises(AssertionError, match=r"component v\(C1\)"):
        case.assert_matches(t, X[:, list(case.plant)], atol=5e-3)


def test_the_plugin_gives_one_test_per_case(pytester):
    pytester.makepyfile(test_solver="""
        def test_solver(lcs_zoo_case):
            t = [k * lcs_zoo_case.step for k in range(101)]
            lcs_zoo_case.assert_matches(t, lcs_zoo_case.fixture.to_numpy(t), atol=1e-12, event_tol=0)
    """)
    result = pytester.runpytest("-p", "no:cacheprovider", "-q")
    result.assert_outcomes(passed=15)
    result = pytester.runpytest("-p", "no:cacheprovider", "-v", "--lcs-zoo", "relay,two_carts")
    result.assert_outcomes(passed=2)
    result.stdout.fnmatch_lines(["*test_solver[[]two_carts[]] PASSED*", "*test_solver[[]relay[]] PASSED*"])


def test_the_plugin_reports_a_wrong_solver_per_case(pytester):
    pytester.makepyfile(test_solver="""
        def test_solver(lcs_zoo_case):
            t = [k * lcs_zoo_case.step for k in range(101)]
            lcs_zoo_case.assert_matches(t, lcs_zoo_case.fixture.to_numpy(t) + 1e-3, atol=1e-6, event_tol=0)
    """)
    result = pytester.runpytest("-p", "no:cacheprovider", "-q", "--lcs-zoo", "bouncing_ball")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*differs from the fixture by 0.001 > tolerance 1e-06*",
                                 "*FAILED*test_solver[[]bouncing_ball[]]*"])


@pytest.mark.slow
def test_the_shipped_zoo_is_what_write_zoo_writes(tmp_path):
    """The pre-built fixtures in the package are rebuilt from their problems and compared by digest."""
    index = zoo.write_zoo(tmp_path, digits=zoo.DEFAULT_DIGITS, samples=zoo.DEFAULT_SAMPLES)
    shipped = json.loads((zoo.files("lcs_exact") / zoo.DATA / zoo.INDEX_FILE).read_text(encoding="utf-8"))
    assert [(e["name"], e["digest"], e["samples_digest"]) for e in index["problems"]] == \
        [(e["name"], e["digest"], e["samples_digest"]) for e in shipped["problems"]]


@pytest.mark.slow
def test_a_scheduled_case_carries_its_schedule():
    """The buck converter switches at 1/4 of each period 1: a backward Euler that follows
    case.schedule passes (above), one that keeps the first phase's data (the switch never opens)
    fails, and the case says so: the phases' durations and data are the builder's (E = 2, L = 1/10:
    i' = 20 s(t) - 10 v + 10 u)."""
    case = zoo.cases("buck_converter_dcm")[0]
    (d_on, A_on, *_), (d_off, A_off, *_) = case.schedule
    assert (d_on, d_off, case.period) == (0.25, 0.75, 1.0)
    assert A_on[0].tolist() == [0, -10, 20] and A_off[0].tolist() == [0, -10, 0]
    assert case.sources.expressions == ("1",) and case.plant == (0, 1)
    t, X = backward_euler(case, 1 / 400, A=case.A, B=case.B, C=case.C, D=case.D)
    with pytest.raises(AssertionError, match="differs from the fixture"):
        case.assert_matches(t, X, atol=3e-2)
