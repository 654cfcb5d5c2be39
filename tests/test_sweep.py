"""sweep / param_sweep: the same answers as sequential simulate runs, in input order, failures
kept, on a process pool and on a Dask LocalCluster."""
from __future__ import annotations

import os
from concurrent.futures import ProcessPoolExecutor
from fractions import Fraction
from pathlib import Path

import mpmath
import pytest

import lcs_exact as L
from lcs_exact import LCS, LimitExceeded, SweepResult, param_sweep, simulate, sweep
from lcs_exact.models import two_carts, two_carts_with_hook

ROOT = str(Path(__file__).resolve().parents[1])
EPS = [Fraction(1, 10), Fraction(1, 2), Fraction(1, 100), Fraction(3, 10), Fraction(2)]


def hook_x0(e):
    return [e, e, -2, 1]


def release_time(e) -> mpmath.mpf:
    """Example 8.3 from (e, e, -2, 1), derived by hand: the hook engages at t = 0 (equal masses:
    both velocities become -1/2), the coupled pair 2 q'' = -q moves as
    q = e cos(t/sqrt2) - (sqrt2/2) sin(t/sqrt2) and reaches the stop when tan(t/sqrt2) = sqrt2 e."""
    with mpmath.workdps(50):
        return mpmath.sqrt(2) * mpmath.atan(mpmath.sqrt(2) * mpmath.mpf(e.numerator) / e.denominator)


def same_run(a, b):
    """Two trajectories agree: modes, multiplicities, event times to 30 digits, exact states."""
    assert len(a.events) == len(b.events)
    for ea, eb in zip(a.events, b.events):
        assert (ea.mode_before, ea.modes, ea.mode_after, ea.multiplicity) == \
            (eb.mode_before, eb.modes, eb.mode_after, eb.multiplicity)
        assert ea.time.decimal(30) == eb.time.decimal(30)
        for va, vb in ((ea.state_before, eb.state_before), (ea.state_after, eb.state_after)):
            qa, qb = va.rational(), vb.rational()
            assert (qa is None) == (qb is None)
            if qa is not None:
                assert qa == qb
            else:
                assert [c.decimal(30) for c in va] == [c.decimal(30) for c in vb]
    assert a.certified == b.certified


@pytest.fixture(scope="module")
def pool():
    with ProcessPoolExecutor(max_workers=2) as ex:
        yield ex


@pytest.mark.slow
def test_sweep_equals_sequential_runs_in_input_order(pool):
    lcs = two_carts_with_hook()
    rs = sweep(lcs, [hook_x0(e) for e in EPS], 3, pool, progress=False)
    assert [r.x0 for r in rs] == [hook_x0(e) for e in EPS]
    for e, r in zip(EPS, rs):
        assert isinstance(r, SweepResult) and r.ok and r.error is None
        same_run(r.trajectory, simulate(lcs, hook_x0(e), 3))
        # the stop engages at the hand-derived time, to 30 digits
        t = r.trajectory.events[1].time
        with mpmath.workdps(50):
            assert abs(mpmath.mpf(t.decimal(40).split(" ")[0]) - release_time(e)) < mpmath.mpf(10) ** -30
        # the hook's impact at t = 0: both velocities -1/2, exactly
        assert str(r.trajectory.events[0].state_after) == f"({e}, {e}, -1/2, -1/2)"


def test_results_refer_to_the_callers_system_and_refine_past_the_workers_digits(pool):
    # the worker ships neither the system, its modes, spectra nor ball caches: the parent's
    # own objects stand in, and digits the worker never computed come from the exact data
    lcs = LCS(two_carts_with_hook().A, two_carts_with_hook().B, two_carts_with_hook().C,
              two_carts_with_hook().D, state_names=["q1", "q2", "v1", "v2"],
              constraint_names=["stop", "hook"])
    e = Fraction(3, 10)
    r, = sweep(lcs, [hook_x0(e)], 3, pool, progress=False)
    tr = r.trajectory
    assert tr.lcs is lcs
    assert tr.lcs.constraint_names == ("stop", "hook")
    assert [ev.triggers for ev in tr.events] == [(), ("u_1", "y_0")]  # the hook lets go at the stop
    t = tr.events[1].time  # the worker computed 30 digits; 200 are asked here
    with mpmath.workdps(220):
        got = mpmath.mpf(t.decimal(200).split(" ")[0])
        assert abs(got - release_time_at(e, 220)) < mpmath.mpf(10) ** -199
    # the state after the release, recomputed in the parent from the exact phase data
    x = tr.state(Fraction(5, 2))
    assert [c.decimal(40) for c in x] == [c.decimal(40) for c in simulate(lcs, hook_x0(e), 3).state(Fraction(5, 2))]


def release_time_at(e, dps):
    with mpmath.workdps(dps):
        return mpmath.sqrt(2) * mpmath.atan(mpmath.sqrt(2) * mpmath.mpf(e.numerator) / e.denominator)


def test_rational_event_times_stay_exact(pool):
    # two carts from (0, 1, -1, 0): the impact is at t = 0 with an exact rational state
    rs = sweep(two_carts(), [[0, 1, -1, 0], [0, 1, -3, 0]], 1, pool, progress=False)
    for r, v in zip(rs, (-1, -3)):
        ev = r.trajectory.events[0]
        assert ev.time.decimal(30) == "0"
        assert str(ev.state_after) == "(0, 1, 0, 0)"
        assert str(ev.state_before) == f"(0, 1, {v}, 0)"


def test_failed_run_keeps_error_and_partial_trajectory(pool):
    lcs = two_carts_with_hook()
    x0s = [hook_x0(Fraction(1, 10)), [1, 1, 1, 1], hook_x0(Fraction(1, 2))]
    rs = sweep(lcs, x0s, 3, pool, progress=False, max_events=1)
    # (1, 1, 1, 1) is free on [0, 3]? its sequential run decides; the hook runs need 2 events
    for x0, r in zip(x0s, rs):
        try:
            want = simulate(lcs, x0, 3, max_events=1)
        except LimitExceeded as e:
            assert not r.ok and isinstance(r.error, LimitExceeded)
            assert str(r.error) == str(e)
            assert r.error.trajectory is r.trajectory
            assert r.trajectory.partial and len(r.trajectory.events) == 1
            same_run(r.trajectory, e.trajectory)
        else:
            assert r.ok
            same_run(r.trajectory, want)
    assert [r.ok for r in rs] == [False, rs[1].ok, False]


def test_unexpected_exception_is_kept(pool):
    rs = sweep(two_carts(), [[0, 1, -1, 0], [0, 1]], 1, pool, progress=False)
    assert rs[0].ok
    assert not rs[1].ok and isinstance(rs[1].error, ValueError) and rs[1].trajectory is None


def test_param_sweep_family(pool):
    def spring(k):  # a cart on a spring of stiffness k, a stop at 0: impact at pi / (2 sqrt k)
        return LCS([[0, 1], [-k, 0]], [[0], [1]], [[1, 0]], [[0]])
    ks = [1, 4, 9, 16]
    rs = param_sweep(spring, ks, [1, 0], 2, pool, progress=False)
    assert [r.param for r in rs] == ks
    for k, r in zip(ks, rs):
        t = r.trajectory.events[0].time
        with mpmath.workdps(40):
            assert abs(mpmath.mpf(t.decimal(35).split(" ")[0]) - mpmath.pi / (2 * mpmath.sqrt(k))) < 1e-30


def test_default_executor_and_progress_bar(capsys):
    rs = sweep(two_carts(), [[0, 1, -1, 0]], 1)
    assert rs[0].ok and str(rs[0].trajectory.events[0].state_after) == "(0, 1, 0, 0)"
    assert "1/1" in capsys.readouterr().err   # tqdm wrote its bar


def test_irrational_x0_is_refused_with_a_reason():
    x0 = L.expm_action([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]], -1, [0, -1, -1, 0])
    with pytest.raises(TypeError, match="x0s\\[0\\]"):
        sweep(two_carts(), [x0], 3, progress=False)


@pytest.mark.slow
def test_dask_local_cluster(monkeypatch):
    import distributed  # in the test extra (a missing one is a broken environment, not a skip)
    monkeypatch.setenv("PYTHONPATH", ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    lcs = two_carts_with_hook()
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        rs = sweep(lcs, [hook_x0(e) for e in EPS[:3]], 3, client.get_executor(), progress=False)
        bad = sweep(lcs, [hook_x0(EPS[0])], 3, client.get_executor(), progress=False, max_events=1)
    for e, r in zip(EPS, rs):
        same_run(r.trajectory, simulate(lcs, hook_x0(e), 3))
    assert isinstance(bad[0].error, LimitExceeded) and len(bad[0].trajectory.events) == 1


def _killed_by_sigkill():
    """A job that kills its own worker, as the OOM killer or a user's ``kill -9`` would."""
    import signal
    os.kill(os.getpid(), signal.SIGKILL)


class _PoolWithAKiller(ProcessPoolExecutor):
    """A process pool whose first job kills its worker: queued ahead of the sweep's chunks, so
    the pool breaks while they are pending, on any machine load (no sleeps, no race)."""

    def submit(self, fn, /, *args, **kwargs):
        if not getattr(self, "_killer_sent", False):
            self._killer_sent = True
            super().submit(_killed_by_sigkill)
        return super().submit(fn, *args, **kwargs)


@pytest.mark.slow
def test_a_worker_killed_by_a_signal_loses_nothing():
    """Issue 15: SIGKILL to a worker of the user's pool in the middle of a sweep breaks the pool
    (BrokenProcessPool for every pending chunk); each of those jobs is run again alone on a fresh
    worker, so every result is there and equals the sequential run."""
    carts = two_carts()
    x0s = [[0, 1, -1, 0], [0, -1, -1, 0], [0, 0, 0, 1], [0, 1, 0, -1], [1, 0, 0, 0], [0, 2, -1, 1]]
    pool = _PoolWithAKiller(max_workers=2)
    results = sweep(carts, x0s, 150, executor=pool, max_events=100000, progress=False)
    from concurrent.futures.process import BrokenProcessPool
    with pytest.raises(BrokenProcessPool):  # the kill did break the pool during the sweep
        pool.submit(int).result()
    pool.shutdown(wait=False)
    assert len(results) == len(x0s) and all(r.error is None for r in results)
    for x0, r in zip(x0s, results):  # the same answers as sequential runs
        seq = simulate(carts, x0, 150)
        assert len(r.trajectory.events) == len(seq.events)
        assert all(a.ball(20).overlaps(b.ball(20)) for a, b in zip(r.trajectory.state(150), seq.state(150)))


def test_a_sweep_keeps_restitution_and_schedules():
    """The worker rebuilds the system from text: Newton's restitution and a schedule's phases must
    travel with it (they did not: a damped ball with e = 1/2 stuck to the floor at its first impact
    in a sweep, and a PWM buck converter ran its first phase forever).  Each result equals the
    sequential run: events, times, the damped ball's accumulation, the final state."""
    from concurrent.futures import ThreadPoolExecutor
    from lcs_exact import sources
    from lcs_exact.examples import buck_converter
    ball = L.models.mechanical([[1]], [[0]], [[1]], damping=[["1/10"]], force=[sources.constant(-10)],
                               restitution="1/2")
    buck = buck_converter()
    with ThreadPoolExecutor(1) as ex:
        balls = sweep(ball, [ball.embed([1, 0]), ball.embed([2, 0])], 3, ex, progress=False)
        bucks = sweep(buck, [buck.embed([0, 0]), buck.embed([1, 1])], 3, ex, progress=False)
    for x0, r in zip([[1, 0], [2, 0]], balls):
        seq = simulate(ball, ball.embed(x0), 3)
        same_run(r.trajectory, seq)
        assert len(r.trajectory.accumulations) == 1
        assert r.trajectory.accumulations[0].time.decimal(30) == seq.accumulations[0].time.decimal(30)
    for x0, r in zip([[0, 0], [1, 1]], bucks):
        seq = simulate(buck, buck.embed(x0), 3)
        same_run(r.trajectory, seq)
        assert [e.triggers for e in r.trajectory.events] == [e.triggers for e in seq.events]
        assert r.trajectory.state(3).rational() == seq.state(3).rational()


def test_a_system_with_its_derived_data_travels_exactly():
    """An LCS pickled by value (the sweep's exact pickler: a system a trajectory refers to that is
    not the sweep's own) carries its derived data, kept in typed attributes since issue 29 (no
    string-keyed memo): the copy answers charpoly, G, R, the leading indices, well-posedness,
    sources and its modes' V, T, P, F, A_I without recomputing, and the same as the original."""
    from lcs_exact.dynamics.sweep import _dumps, _loads

    lcs = L.models.driven([[-1, 0], [0, -2]], [[1], [1]], [[1, 1]], [[1]], E=[[1], [0]], F=[[-1]],
                          w=[L.sources.sine(1)])
    m = lcs.mode({0})
    before = (lcs.charpoly(), lcs.G(), lcs.R(), lcs.leading_row_indices(), lcs.leading_column_indices(),
              bool(lcs.well_posedness()), lcs.spectral_scales(), m.consistent_subspace(), m.jump_space(),
              m.projection(), m.feedback(), m.closed_loop(), m.is_autonomous)
    copy = _loads(_dumps(lcs))
    assert copy is not lcs and copy.sources.expressions == lcs.sources.expressions
    cached = {"_charpoly", "_G", "_R", "_rho", "_eta", "_well_posedness", "_scales", "_sources"}
    assert cached <= set(vars(copy)) and "_cache" not in vars(copy)
    cm = copy.mode({0})
    assert {"_V", "_T", "_P", "_F", "_A_I", "_autonomy"} <= set(vars(cm)) and "_cache" not in vars(cm)
    after = (copy.charpoly(), copy.G(), copy.R(), copy.leading_row_indices(), copy.leading_column_indices(),
             bool(copy.well_posedness()), copy.spectral_scales(), cm.consistent_subspace(), cm.jump_space(),
             cm.projection(), cm.feedback(), cm.closed_loop(), cm.is_autonomous)
    for a, b in zip(before, after):
        if isinstance(a, tuple) and a and hasattr(a[0], "mid"):   # spectral scales: balls, radii rounded up
            assert all(x.mid() == y.mid() and y.contains(x) and float(y.rad()) < 1.001 * float(x.rad())
                       for x, y in zip(a, b))
        elif isinstance(a, L.RationalMatrix):
            assert [[str(e) for e in r] for r in a.rows] == [[str(e) for e in r] for r in b.rows]
        else:
            assert a == b
    same_run(simulate(lcs, lcs.embed([1, 0]), 2), simulate(copy, copy.embed([1, 0]), 2))


def test_algebraic_event_times_and_a_collapse_come_back_from_the_workers(pool):
    """Two balls dropped on a floor: their event times are algebraic (Calcium numbers inside the
    trajectory: they travel as minimal polynomials and isolating intervals) and their impacts
    collapse (a proven accumulation window).  Each swept trajectory equals the direct run: the first
    impact at sqrt(2 h / g) exactly, T* to 30 digits, the balls at rest after it."""
    import sympy
    two = L.models.mechanical([[1, 0], [0, 2]], [[0, 0], [0, 0]], [[1, 0], [-1, 1]], force=[-10, -20], gap=[0, -1],
                              restitution="1/2")
    x0s = [two.embed([Fraction(1, 2), Fraction(8, 5), 0, 0]), two.embed([Fraction(4, 5), Fraction(2), 0, 0])]
    results = sweep(two, x0s, 1, executor=pool, progress=False)
    for x0, h, res in zip(x0s, (Fraction(1, 2), Fraction(4, 5)), results):
        assert res.error is None
        tr, direct = res.trajectory, simulate(two, x0, 1)
        assert sympy.simplify(tr.events[0].time.closed_form - sympy.sqrt(sympy.Rational(2 * h.numerator, 10 * h.denominator))) == 0
        assert len(tr.accumulations) == 1 and len(tr.events) == len(direct.events)
        with mpmath.workdps(40):
            a, b = (mpmath.mpf(t.accumulations[0].time.ball(30).mid().str(35, radius=False)) for t in (tr, direct))
            assert abs(a - b) < mpmath.mpf(10) ** -29
        assert tr.state(1).known_rational() == direct.state(1).known_rational()
