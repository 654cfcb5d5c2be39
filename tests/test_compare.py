"""compare.py: fixtures read back (exact recomputation checked against the file), and other
solvers' solutions measured against certified trajectories (state error away from events, event
times from the solver's data, order of convergence).  Expected values are derived in the tests
(mpmath at 50 digits, the solver's own arithmetic), never copied from a run."""
from __future__ import annotations

import copy
import json
import math
from fractions import Fraction

import mpmath as mp
import numpy as np
import pytest
from flint import arb, ctx, fmpq
from helpers import A_CARTS, carts, mpmath_digits

import lcs_exact as L
from lcs_exact.verify.compare import read_solution_csv

_mp = mpmath_digits(50)
OSC = ([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])  # x'' = -x + u, 0 <= x ⊥ u >= 0 (a stop at 0)


def osc_state(t):
    """From (1, 0): (cos t, -sin t) until the stop at π/2, then at rest at 0 (inelastic impact).
    At 120 digits: the library's balls may be far tighter than the 30 digits asked."""
    with mp.workdps(120):
        t = mp.mpf(t.numerator) / t.denominator if isinstance(t, Fraction) else mp.mpf(t)
        return [+mp.cos(t), -mp.sin(t)] if t < mp.pi / 2 else [mp.mpf(0), mp.mpf(0)]


def mpf_of(text) -> mp.mpf:
    q = Fraction(text)
    return mp.mpf(q.numerator) / q.denominator


def contains(ball: arb, value) -> bool:
    with ctx.workprec(500):
        return ball.contains(arb(mp.nstr(value, 110)))


@pytest.fixture(scope="module")
def osc_run():
    return L.simulate(L.LCS(*OSC), [1, 0], 4, digits=30)


@pytest.fixture(scope="module")
def osc_fixture(osc_run):
    return osc_run.to_fixture(30, sample="1/20")


# ---------------------------------------------------------------------------------------------
# read_fixture
# ---------------------------------------------------------------------------------------------

def test_read_fixture_round_trip(osc_run, tmp_path):
    path = tmp_path / "osc.json"
    path.write_text(json.dumps(osc_run.to_fixture(25, sample="1/4")))
    fx = L.read_fixture(str(path))
    assert fx.digits == 25 and fx.certified and not fx.partial and fx.can_recompute
    (e,) = fx.events
    assert contains(e.time, mp.pi / 2) and e.time_exact == "pi/2" and e.time.rad() < 1e-24
    assert (e.mode_before, e.modes, e.mode_after, e.multiplicity) == (frozenset(), (frozenset({0}),), frozenset(), 1)
    assert contains(e.state_before[1], -1) and contains(e.state_after[1], 0)
    assert [s.t for s in fx.samples] == [Fraction(k, 4) for k in range(17)]
    for s in fx.samples:
        assert all(contains(b, v) for b, v in zip(s.x, osc_state(s.t)))
    assert fx.x0_rational == (1, 0) and fx.t_end_rational == 4
    # between samples: the run recomputed exactly from the fixture's system and x0
    x = fx.state("3/5")
    assert all(contains(c.ball(30), v) for c, v in zip(x, osc_state(Fraction(3, 5))))
    rows = fx.sample(["1/4", "3/5"], 20)
    assert all(contains(b, v) for row, t in zip(rows, ("1/4", "3/5")) for b, v in zip(row, osc_state(Fraction(t))))
    assert "exact evaluation available" in repr(fx) and "1 events" in repr(fx)
    assert L.read_fixture(fx) is fx and L.read_fixture(json.loads(path.read_text())).events[0].time_exact == "pi/2"


@pytest.mark.slow
def test_read_fixture_without_rational_x0():
    """Section 7 starts from e^{-A}(0,-1,-1,0): no exact recomputation, the samples are the data."""
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    fx = L.read_fixture(L.simulate(carts(), x0, 3, digits=20).to_fixture(20, sample="1/2"))
    assert not fx.can_recompute and fx.exact is None and fx.x0_rational is None
    assert [e.time_exact for e in fx.events] == ["1", "1 + pi/2"]
    (row,) = fx.sample(["3/2"])
    assert contains(row[1], -mp.cos(mp.mpf(1) / 2)) and contains(row[0], 0)
    with pytest.raises(L.FormatError, match="not a sample time"):
        fx.sample(["1/3"])
    with pytest.raises(L.FormatError, match="cannot be recomputed"):
        fx.state(2)
    assert "balls only" in repr(fx)


def test_partial_fixture_recomputes_its_computed_part():
    """From (0, -1, -1, 0) the carts hit the stop at t = 0 and lift off at π/2; a run stopped after
    the first event is read back, recomputed with the same limit and checked."""
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(carts(), [0, -1, -1, 0], 3, max_events=1)
    fx = L.read_fixture(err.value.trajectory.to_fixture(20))
    assert fx.partial and fx.can_recompute and len(fx.events) == 1
    assert fx.exact.partial and len(fx.exact.events) == 1
    x = fx.state("1/2")  # on the constrained phase after the impact: (0, -cos t, 0, sin t)
    assert contains(x[1].ball(25), -mp.cos(mp.mpf(1) / 2)) and contains(x[3].ball(25), mp.sin(mp.mpf(1) / 2))


@pytest.mark.parametrize("live", [False, True])
def test_compare_with_a_partial_reference_leaves_out_the_later_times(live):
    """The carts from (0, -1, -1, 0) stopped after their first event: the run covers [0, pi/2]
    (the lift-off at pi/2 is the next event, not computed); a solution on [0, 3] is compared on
    [0, pi/2] and the later times are counted in n_beyond (they raised an error before)."""
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(carts(), [0, -1, -1, 0], 3, max_events=1)
    part = err.value.trajectory
    ref = part if live else L.read_fixture(part.to_fixture(20, sample="1/10"))
    ts = [Fraction(k, 10) for k in range(31)]
    X = [[0.0, -math.cos(float(t)), 0.0, math.sin(float(t))] for t in ts]  # (0, -cos t, 0, sin t)
    r = L.compare(ref, ts, X)
    # 0.0, 0.1, 0.2 are in the window |t - 0| <= w = 2 x 0.1 of the jump at t = 0; 0.3 ... 1.5
    # compared; 1.6 ... 3.0 after pi/2 = 1.5707...
    assert (r.n_in_windows, r.n_compared, r.n_beyond) == (3, 13, 15)
    assert float(r.max_error.mid()) < 1e-15
    with mp.workdps(120):
        assert contains(r.last_time, mp.pi / 2)
    assert "15 after the reference's last time 1.5707963267949" in str(r)
    assert r.to_dict()["beyond_last_time"] == 15


def test_fixture_events_and_samples_show_their_digits(osc_fixture):
    """Reprs show the digits the balls hold (a 30-digit fixture is not printed as +/- 1e-15)."""
    fx = L.read_fixture(osc_fixture)
    text = repr(fx.events[0])
    assert text.startswith("FixtureEvent(t=1.5707963267948966192 +/- ") and "= pi/2, ∅ => ∅, jumps: {0}" in text
    assert "x- = (0, -1), x+ = (0, 0)" in text
    assert repr(fx.samples[1]) .startswith("Sample(t=1/20, x=(0.99875026039496624656 +/- ")
    assert mp.cos(mp.mpf(1) / 20) == pytest.approx(mpf_of("0.99875026039496624656"), abs=1e-20)


@pytest.mark.parametrize("edit, fragment", [
    (lambda d: d["events"][0]["time"].update(value="1.6", error="0.001"), "event 0: recomputed time"),
    (lambda d: d["events"][0].update(mode_after=[0]), "mode_after"),
    (lambda d: d["x0"][0].update(value="2", exact="2"), "state_before"),
    (lambda d: d["events"].append(copy.deepcopy(d["events"][0])), "2"),
])
def test_recomputation_disagreeing_with_the_fixture(osc_fixture, edit, fragment):
    d = copy.deepcopy(osc_fixture)
    edit(d)
    d.pop("digest")  # as a fixture without a digest would be: well-formed, so the disagreement
    with pytest.raises(L.FixtureMismatch, match="recomputed") as err:  # shows on recomputation,
        L.read_fixture(d)  # which read_fixture runs for a fixture without a digest
    assert fragment in str(err.value)


def test_an_edited_fixture_is_refused(osc_fixture, tmp_path):
    """Issue 15: a fixture carries the digest of its content; one edited sample makes
    read_fixture (and so compare) refuse it with FixtureMismatch."""
    d = copy.deepcopy(osc_fixture)
    assert d["digest"].startswith("sha256:")
    L.read_fixture(copy.deepcopy(d))  # untouched: accepted
    d["samples"][3]["x"][0]["value"] = "0.5"
    with pytest.raises(L.FixtureMismatch, match="samples do not match the digest"):
        L.read_fixture(d)
    e = copy.deepcopy(osc_fixture)
    e["events"][0]["state_after"][1]["value"] = "0.25"
    with pytest.raises(L.FixtureMismatch, match="events, states or system"):
        L.read_fixture(e)
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(d))
    csv = tmp_path / "sol.csv"
    csv.write_text("t,x1,x2\n0,1,0\n1,0.5,-0.8\n")
    from lcs_exact.cli import main
    assert main(["compare", str(path), str(csv)]) == 2


def test_an_edited_fixture_without_its_digests_is_checked_against_the_system(osc_fixture):
    """Deleting the digests does not make an edited sample ground truth: a fixture without a
    digest (older fixtures have none) is recomputed from the system and x0 it carries, and
    read_fixture and compare refuse a sample the run contradicts; an honest one is read."""
    d = copy.deepcopy(osc_fixture)
    del d["digest"], d["samples_digest"]
    honest = L.read_fixture(copy.deepcopy(d))
    assert not honest.digested and honest.verify() is honest
    s = d["samples"][3]
    s["x"][0].update(value="0.5", exact=None)
    with pytest.raises(L.FixtureMismatch, match="sample at t ="):
        L.read_fixture(copy.deepcopy(d))
    ts = [float(honest.samples[k].t) for k in (2, 3)]
    with pytest.raises(L.FixtureMismatch, match="sample at t ="):
        L.compare(d, ts, [[0.5, 0.0], [0.5, 0.0]])
    assert L.read_fixture(copy.deepcopy(osc_fixture)).digested


@pytest.mark.parametrize("bad, fragment", [
    ({"schema": "something/else"}, "schema"),
    ([1, 2], "path or a dict, got list"),
    (42, "path or a dict"),
])
def test_read_fixture_rejects(bad, fragment):
    with pytest.raises(L.FormatError, match=fragment):
        L.read_fixture(bad)


def test_read_fixture_bad_file(tmp_path):
    p = tmp_path / "f.json"
    p.write_text("{not json")
    with pytest.raises(L.FormatError, match="not JSON"):
        L.read_fixture(p)


# ---------------------------------------------------------------------------------------------
# compare: synthetic solutions with known errors
# ---------------------------------------------------------------------------------------------

TIMES = [Fraction(k, 20) for k in range(81)]  # step 1/20 on [0, 4]


def perturbed_solution():
    """X = x(t) + p(t) with p = 1e-7 (1 + t/4) on x1, as 30-digit decimal strings; returns the
    strings and the exact max |X - x| over the points outside the event window (|t - π/2| <= 2h)."""
    X, worst = [], mp.mpf(0)
    for t in TIMES:
        x = osc_state(t)
        row = [mp.nstr(x[0] + mp.mpf("1e-7") * (1 + mp.mpf(t.numerator) / t.denominator / 4), 30, strip_zeros=False),
               mp.nstr(x[1], 30, strip_zeros=False)]
        X.append(row)
        if abs(mp.mpf(t.numerator) / t.denominator - mp.pi / 2) > mp.mpf(2) / 20:
            worst = max(worst, max(abs(mpf_of(r) - v) for r, v in zip(row, x)))
    return X, worst


@pytest.mark.parametrize("source", ["trajectory", "fixture with samples", "fixture recomputed"])
def test_compare_reports_a_known_perturbation(osc_run, osc_fixture, source):
    ref = {"trajectory": osc_run, "fixture with samples": osc_fixture,
           "fixture recomputed": {k: v for k, v in osc_fixture.items()
                                  if k not in ("samples", "sample_step", "samples_digest")}}[source]
    X, worst = perturbed_solution()
    r = L.compare(ref, TIMES, X)
    assert r.reference == ("samples" if source == "fixture with samples" else "exact")
    assert r.window == pytest.approx(0.1) and r.window_rule == "2 x the largest step"
    excluded = sum(1 for t in TIMES if abs(float(t) - math.pi / 2) <= 0.1)
    assert (r.n_points, r.n_in_windows, r.n_compared, r.n_unmatched) == (81, excluded, 81 - excluded, 0)
    assert contains(r.max_error, worst) and r.max_error.rad() < 1e-18  # certified to ~20 digits
    assert r.max_error_component == 0 and r.max_error_time == 4.0  # p grows with t
    assert contains(r.component_errors[1], 0) or r.component_errors[1].upper() < 1e-29
    (ev,) = r.events
    assert ev.kind == "jump" and ev.order == 0 and ev.time_exact == "pi/2"
    # the data jump lies in the step containing π/2: the switch is that step's middle
    k = math.ceil(math.pi / 2 * 20)
    assert ev.solver_time == pytest.approx((k - 0.5) / 20, abs=1e-15)
    assert ev.time_error == pytest.approx((k - 0.5) / 20 - math.pi / 2, abs=1e-15)


def test_compare_shifted_event(osc_run):
    """A solver that switches δ late: X(t) = x(t - δ).  The reported switch is the middle of the
    step where the data jumps, t_{k-1} < π/2 + δ <= t_k."""
    delta = mp.mpf(1) / 75
    X = []
    for t in TIMES:
        s = mp.mpf(t.numerator) / t.denominator - delta
        X.append([float(v) for v in ([mp.cos(s), -mp.sin(s)] if s < mp.pi / 2 else [0, 0])])
    r = L.compare(osc_run, [float(t) for t in TIMES], X)
    k = math.ceil((math.pi / 2 + float(delta)) * 20)
    (ev,) = r.events
    assert ev.solver_time == pytest.approx((k - 0.5) / 20, abs=1e-12)
    assert ev.time_error == pytest.approx((k - 0.5) / 20 - math.pi / 2, abs=1e-12)
    # away from the window, the error is max |x(t) - x(t - δ)| over the compared points
    errs = {t: max(abs(mpf_of(x) - e) for x, e in zip(row, osc_state(t)))
            for t, row in zip(TIMES, X) if abs(float(t) - math.pi / 2) > 0.1}
    t_worst = max(errs, key=errs.get)
    assert r.max_error_time == float(t_worst) and abs(float(r.max_error.mid()) - float(errs[t_worst])) < 1e-15


def test_compare_kink_event():
    """q' = -g + u, g' = 0, y = q >= 0 from (1, 1): q = 1 - t reaches the stop at t = 1 and stays;
    x is continuous, x' jumps (order 1).  On the grid of step 3/20 the data's slope changes most at
    the grid point nearest the event, 1.05."""
    lcs = L.LCS([[0, -1], [0, 0]], [[1], [0]], [[1, 0]], [[0]])
    tr = L.simulate(lcs, [1, 1], 2)
    ts = [Fraction(3 * k, 20) for k in range(14)]
    X = [[max(1 - t, 0), 1] for t in ts]
    r = L.compare(tr, ts, X)
    (ev,) = r.events
    assert ev.order == 1 and ev.kind.startswith("kink") and ev.time_exact == "1"
    nearest = min(ts, key=lambda t: abs(t - 1))
    assert ev.solver_time == pytest.approx(float(nearest)) and ev.time_error == pytest.approx(float(nearest) - 1)
    assert contains(r.max_error, 0) and r.max_error.upper() < 1e-19  # exact data: zero error (20 digits)


def test_compare_initial_jump_and_float_times_on_the_grid(osc_fixture):
    tr = L.simulate(L.LCS(*OSC), [-1, 2], 1)
    r = L.compare(tr, [0, 0.5, 1], [[0, 0]] * 3)
    assert r.events[0].kind == "initial jump" and r.events[0].solver_time is None
    ts = [k * 0.05 for k in range(81)]  # floats: k * 0.05 is not k/20, but within 1e-9 of the step
    X = [[float(v) for v in osc_state(Fraction(k, 20))] for k in range(81)]
    r = L.compare(osc_fixture, ts, X)
    assert r.reference == "samples" and r.n_unmatched == 0 and 0 < r.time_mismatch < 1e-14
    assert r.max_error.upper() < 1e-15


def test_compare_output_formats(osc_run):
    X, _ = perturbed_solution()
    r = L.compare(osc_run, TIMES, X, label="my solver", names=["q", "v"])
    text = str(r)
    assert text.startswith("my solver: against the exact trajectory")
    assert "max state error 2.0000e-07 at t = 4 in q" in text and "pi/2" in text and "jump" in text
    assert repr(r).startswith("<ComparisonReport 'my solver': max error 2.0000e-07")
    d = json.loads(json.dumps(r.to_dict()))
    assert d["events"][0]["time"]["exact"] == "pi/2" and d["compared"] == r.n_compared
    v, e = Fraction(d["max_error"]["value"]), Fraction(d["max_error"]["error"])
    assert abs(v - Fraction(2, 10 ** 7)) <= e


def test_compare_event_tol(osc_run):
    X, _ = perturbed_solution()
    r = L.compare(osc_run, TIMES, X, event_tol="1/100")
    assert r.window == 0.01 and r.window_rule == "event_tol"
    assert r.n_in_windows == sum(1 for t in TIMES if abs(float(t) - math.pi / 2) <= 0.01)


@pytest.mark.parametrize("t, X, err, fragment", [
    ([0, 1], [[1, 0]], L.ShapeError, "2 times but 1 rows"),
    ([0, 1], [[1, 0], [1]], L.ShapeError, "row 1 has 1 values, expected 2"),
    ([0, 1], [[1, 0, 0], [1, 0, 0]], L.ShapeError, "row 0 has 3 values, expected 2"),
    ([0, 1, "1/2"], [[1, 0]] * 3, L.FormatError, "times decrease at row 2"),
    ([], [], L.FormatError, "at least 1 point"),
    ([0, "x"], [[1, 0]] * 2, L.NotRational, "t[1]"),
    ([0, 1], [[1, 0], [1, float("nan")]], L.NotRational, "X[1][1]"),
])
def test_compare_rejects(osc_run, t, X, err, fragment):
    with pytest.raises(err, match=re_escape(fragment)):
        L.compare(osc_run, t, X)


def re_escape(s: str) -> str:
    import re
    return re.escape(s)


@pytest.mark.slow
def test_compare_needs_a_reference_at_the_solver_times():
    x0 = L.expm_action(A_CARTS, -1, [0, -1, -1, 0])
    fx = L.simulate(carts(), x0, 3, digits=20).to_fixture(20)  # no samples, x0 irrational
    with pytest.raises(L.FormatError, match="none of the solution's times"):
        L.compare(fx, [0, 0.1, 0.2], [[0, 0, 0, 0]] * 3)


# ---------------------------------------------------------------------------------------------
# order of convergence
# ---------------------------------------------------------------------------------------------

def euler(h: Fraction, T: int = 1):
    """Explicit Euler on x'' = -x from (1, 0) (no contact on [0, 1]: x1 = cos t > 0)."""
    N = int(T / h)
    q, v, rows = 1.0, 0.0, [[1.0, 0.0]]
    for _ in range(N):
        q, v = q + float(h) * v, v - float(h) * q
        rows.append([q, v])
    return [k * h for k in range(N + 1)], rows


def test_convergence_order_of_explicit_euler():
    tr = L.simulate(L.LCS(*OSC), [1, 0], 1)
    steps = [Fraction(1, 10), Fraction(1, 20), Fraction(1, 40), Fraction(1, 80)]
    reports, errors = [], []
    for h in steps:
        ts, X = euler(h)
        reports.append(L.compare(tr, ts, X))
        errors.append(max(abs(mp.mpf(x) - e) for t, row in zip(ts, X) for x, e in zip(row, osc_state(t))))
    for r, e in zip(reports, errors):  # each report's error is the independently computed one
        assert abs(float(r.max_error.mid()) - float(e)) <= 1e-15
    xs, ys = [math.log(h) for h in steps], [math.log(e) for e in errors]
    mx, my = sum(xs) / 4, sum(ys) / 4
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    p = L.convergence_order(reports)
    assert p == pytest.approx(slope, abs=1e-9) and 0.9 < p < 1.1  # Euler is a first-order method
    assert L.convergence_order(reports, steps) == pytest.approx(slope, abs=1e-9)


def test_convergence_order_rejects():
    class R:
        def __init__(self, e, h=0.1):
            self.max_error, self.step = arb(e), h
    with pytest.raises(L.FormatError, match="at least 2"):
        L.convergence_order([R(1)])
    with pytest.raises(L.ShapeError):
        L.convergence_order([R(1), R(2)], [0.1])
    with pytest.raises(L.FormatError, match="positive errors"):
        L.convergence_order([R(0), R(1)], [0.1, 0.2])
    with pytest.raises(L.FormatError, match="different steps"):
        L.convergence_order([R(1), R(2)])


# ---------------------------------------------------------------------------------------------
# CSV solutions
# ---------------------------------------------------------------------------------------------

def test_csv_with_and_without_header(osc_run, tmp_path):
    X, worst = perturbed_solution()
    body = "".join(f"{t.numerator / t.denominator!r},{a},{b}\n" for t, (a, b) in zip(TIMES, X))
    with_header, without = tmp_path / "h.csv", tmp_path / "n.csv"
    with_header.write_text("# my solver\nt, q, v\n" + body)
    without.write_text(body.replace(",", " "))  # whitespace-separated also reads
    for p in (with_header, without):
        t, rows = read_solution_csv(p)
        assert len(t) == 81 and rows[3] == X[3]
        r = L.compare(osc_run, t, rows)
        assert contains(r.max_error, worst)


@pytest.mark.parametrize("text, err, fragment", [
    ("t,x1,x2\n0,1,0\n1,2\n", L.ShapeError, "line 3 has 2 columns, expected 3"),
    ("0,1,0\n1,abc,0\n", L.FormatError, "line 2: 'abc' is not a number"),
    ("t,x1\n0,1\n", L.FormatError, "at least 2 rows"),
    ("0\n1\n", L.ShapeError, "expected t, x_0, ..., x_{n-1}"),
])
def test_bad_csv(tmp_path, text, err, fragment):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(err, match=re_escape(fragment)):
        read_solution_csv(p)


# ---------------------------------------------------------------------------------------------
# windows: the events an accumulation implies, the solver's own switch, float grids, the plant
# ---------------------------------------------------------------------------------------------

def _ball_half():
    """A ball dropped from 5 with g = 10, e = 1/2: impacts at 1, 2, 2.5, 2.75, ..., 3 - 2^-k,
    accumulating at T* = 3 (flight times 2, 1, 1/2, ...); at rest on the floor afterwards."""
    ball = L.examples.bouncing_ball(g=10, e="1/2")
    return L.simulate(ball, ball.embed([5, 0]), 4, digits=20)


def _ball_state(t: float) -> list[float]:
    """(q, q', 1) of that ball at t, derived here as flights between impacts: impact k at t_k
    (t_0 = 1), take-off speed 10 / 2^(k+1), flight time 2 v / g; at rest from T* = 3."""
    if t < 1:
        return [5 - 5 * t * t, -10 * t, 1.0]
    if t >= 3:
        return [0.0, 0.0, 1.0]
    k, tk, v = 0, 1.0, 5.0  # impact k at tk, take-off speed v = 10 e^(k+1)
    while tk + 2 * v / 10 <= t:
        tk, v, k = tk + 2 * v / 10, v / 2, k + 1
    s = t - tk
    return [v * s - 5 * s * s, v - 10 * s, 1.0]


def test_windows_cover_the_implied_impacts_and_the_solvers_late_switch():
    tr = _ball_half()
    assert [float(e.time) for e in tr.events] == [1.0, 2.0, 2.5] and len(tr.accumulations) == 1
    acc = tr.accumulations[0]  # impacts 3 - 2^-(k+2) after the listed ones: exactly, and as balls
    assert [acc.event_time(k).known_rational() for k in (0, 5)] == [fmpq(11, 4), fmpq(3) - fmpq(1, 2 ** 7)]
    assert acc.event_time_ball(5).contains(arb(fmpq(383, 128))) and acc.event_time_ball(5).rad() < 1e-30
    h, delay = 1e-3, 3e-3  # a solver three steps late at every impact: X(t) = x(t - delay)
    t = np.arange(4001) * h
    X = np.array([_ball_state(max(0.0, s - delay)) for s in t])
    r = L.compare(tr, t, X, atol=0.05)
    assert r.passed, str(r)
    assert all(abs(e.time_error - delay) <= h for e in r.events)  # the middle of the stencil of the jump
    # the window of the first implied impact, 2.75, reaches the solver's switch 2.753 (+- one step)
    (w,) = [w for w in r.windows if w[0] < 2.75 < w[1]]
    assert w[0] <= 2.75 - 2 * h and w[1] >= 2.753 + h
    # from the implied impact closer than 2w to T* = 3, one window reaches past it
    assert any(a < 3 - 4 * h and b >= 3 + 2 * h for a, b in r.windows)
    # windows of 2h around the listed impacts only (no implied ones, no switch) would leave the
    # velocity's O(1) jump in: between 2.75 and 2.753 the error is 10 / 2^3 + 10 / 2^4 = 1.875 (minus 10 s)
    assert max(abs(a[1] - b[1]) for s, a, b in zip(t, X, (_ball_state(v) for v in t)) if 2.7505 < s < 2.7525) > 1.8


def test_a_wrong_restitution_is_not_hidden_by_the_windows():
    tr = _ball_half()
    t = np.arange(4001) * 1e-3
    X = np.array([_ball_state(s) for s in t])
    X[t > 2.0, 1] *= 0.9  # the take-off after the second impact 10 % too slow
    r = L.compare(tr, t, X, atol=0.05)
    assert not r.passed and r.violation.name == "q'" and 2.0 < r.violation.time < 2.5


def test_float_grid_overshoot_and_the_plants_columns():
    tr = _ball_half()
    t = np.arange(401) * 0.01
    t[-1] = np.nextafter(4.0, 5.0)  # 4.000000000000001: a float grid that overshoots t_end = 4 by rounding
    assert t[-1] > 4
    X = np.array([_ball_state(min(s, 4.0)) for s in t])
    r = L.compare(tr, t, X, atol=1e-9)
    assert r.n_beyond == 0 and r.passed and r.components == (0, 1, 2)
    r = L.compare(tr, t, X[:, :2], atol=1e-9)  # the plant (q, q') without gravity's constant
    assert r.passed and r.components == (0, 1) and r.names == ("q", "q'", "1")
    assert list(r.to_pandas().index) == ["q", "q'"]
    with pytest.raises(L.ShapeError, match="all n states, or the plant's states only"):
        L.compare(tr, t, X[:, :1])


def test_an_older_fixture_without_sources_and_laws_still_reads():
    from lcs_exact.phases.fixture import content_digest
    fx = _ball_half().to_fixture(20)
    assert fx["sources"]["expressions"] == ["1"] and "law" in fx["accumulations"][0]
    old = {k: v for k, v in fx.items() if k not in ("sources", "digest")}
    old["accumulations"] = [{k: v for k, v in a.items() if k != "law"} for a in fx["accumulations"]]
    old["digest"] = content_digest(old)
    back = L.read_fixture(old)
    assert back.sources is None and back.accumulations[0].law is None and back.restitution == (fmpq(1, 2),)
    with pytest.raises(L.InvalidArgument, match="no law"):
        back.accumulations[0].event_time(0)
    new = L.read_fixture(fx)
    assert new.sources.expressions == ("1",) and new.lcs.plant == (0, 1)
    assert [float(new.accumulations[0].event_time(k).mid()) for k in range(3)] == [2.75, 2.875, 2.9375]
