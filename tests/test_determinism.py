"""The same input gives the same run on any machine and under any load (issue 28, item 3): the
budgets that end a proof count work (coefficient products for the cascade proofs, Python calls
for SymPy's steps), so no event, closed form or stopping point depends on the wall clock; the
clock only cuts a run short (``time_limit``) or, as SymPy's safety net, is named where it acts.

A loaded machine is emulated by a clock that jumps an hour at every reading and SymPy steps that
sleep before they start; the runs must be identical to those on a quiet machine."""
import itertools
import time

import mpmath as mp
import pytest
import sympy

import lcs_exact as L
from lcs_exact import forms
from lcs_exact.mechanics import mechanical


@pytest.fixture
def loaded(monkeypatch):
    """Every clock reading is an hour after the previous one; simplify and solve sleep 20 ms first."""
    jumps = itertools.count()
    for name in ("monotonic", "perf_counter", "time"):
        real = getattr(time, name)
        monkeypatch.setattr(time, name, lambda real=real: real() + 3600.0 * next(jumps))
    sleep = time.sleep
    for name in ("simplify", "solve"):
        f = getattr(sympy, name)

        def slow(*args, f=f, **kw):
            sleep(0.02)
            return f(*args, **kw)
        monkeypatch.setattr(sympy, name, slow)


def _scenes():
    """(system, x0, t_end): closed forms from SymPy's steps - an atan form (solve), the next
    impact a half period later (t1 + pi), a log of an algebraic number (exp_candidates), an acos
    of a root of a quadratic in cos t (harmonic_candidates)."""
    osc = mechanical([[1]], [[1]], [[1]], restitution="1/2")
    three = L.LCS([[-1, 0, 0], [0, -2, 0], [0, 0, -3]], [[1], [1], [1]], [[1, -5, 5]], [[0]])
    two = mechanical([[1, 0], [0, 1]], [[1, 0], [0, 4]], [[1, 1]], gap=[8])
    return [(osc, [1, "1/3"], 8), (three, [1, 1, 1], 1), (two, two.embed([-2, 16, 0, 0]), 2)]


def _record(lcs, x0, t_end):
    tr = L.simulate(lcs, x0, t_end, closed_forms=True)
    events = [(str(e.time.closed_form), e.time.closed_form_status, e.time.decimal(30), sorted(e.mode_after),
               [str(c.closed_form) for c in e.state_after]) for e in tr.events]
    return tr.status, events, list(tr.policy.deadline.safety_cuts)


def test_the_same_scenes_give_the_same_events_and_closed_forms_on_a_loaded_machine(loaded):
    # first on a quiet clock (the fixture's patches are undone for it), then loaded
    quiet = [_quiet_record(lcs, x0, t_end) for lcs, x0, t_end in _scenes()]
    busy = [_record(lcs, x0, t_end) for lcs, x0, t_end in _scenes()]
    assert busy == quiet
    status, events, cuts = busy[0]
    assert cuts == [] and status is L.Status.COMPLETE
    t1 = sympy.pi - sympy.atan(3)
    assert [sympy.simplify(sympy.sympify(e[0]) - want) for e, want in zip(events, [t1, t1 + sympy.pi])] == [0, 0]
    with mp.workdps(40):
        assert abs(mp.mpf(events[0][2].split()[0]) - (mp.pi - mp.atan(3))) < mp.mpf(10) ** -29


def _quiet_record(lcs, x0, t_end):
    with pytest.MonkeyPatch.context() as mpatch:
        for name in ("monotonic", "perf_counter", "time", "sleep"):
            mpatch.setattr(time, name, _REAL[name])
        for name in ("simplify", "solve"):
            mpatch.setattr(sympy, name, _REAL[name])
        return _record(lcs, x0, t_end)


_REAL = {**{n: getattr(time, n) for n in ("monotonic", "perf_counter", "time", "sleep")},
         **{n: getattr(sympy, n) for n in ("simplify", "solve")}}


def test_a_sympy_step_ends_after_the_same_count_of_calls_however_slow(monkeypatch):
    """The budget counts Python calls: a step of 10,000 calls under a budget of 500 stops at the
    same call whether each call sleeps or not (a budget in seconds would stop the slow one sooner)."""
    monkeypatch.setattr(forms, "SYMPY_WORK", 500)

    def run(pause):
        done = []

        def step(i):
            if pause:
                time.sleep(pause)
            done.append(i)
        with pytest.raises(forms.SympyOutOfTime) as err:
            with forms.sympy_budget():
                for i in range(10_000):
                    step(i)
        assert err.value.cut is False  # the work ran out: searched to the end of its budget
        return len(done)
    assert run(0) == run(0.001) == 500  # the 501st call is the one refused


def test_a_time_limit_reached_inside_sympy_cuts_the_run_short_never_changes_it():
    """time_limit inside a SymPy step raises TimeLimitExceeded (the run partial, marked), never a
    closed form reported as absent: with a deadline already past, a step is refused at once."""
    from lcs_exact.balls import Deadline
    d = Deadline(0.0)
    with pytest.raises(L.TimeLimitExceeded):
        with forms.sympy_budget(d, "a test step"):
            for _ in range(10 ** 6):
                sympy.Integer(3)._eval_is_positive()
    assert d.safety_cuts == []
