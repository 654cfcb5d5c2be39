"""The options of a run and of the queries after it, checked at the door (issue 29, items 2 and 5).

``digits`` has one rule wherever it is taken (``numbers.check_digits``): a Python int in
1..MAX_DIGITS, else an InvalidArgument (exactly that class) whose message names it; the defaults
are the documented ones.  ``closed_forms`` takes its documented spellings and nothing else.
"""
from __future__ import annotations

import inspect

import numpy as np
import pytest
from flint import arb

import lcs_exact as L
from lcs_exact import InvalidArgument
from lcs_exact.dynamics.options import CLOSED_FORMS
from lcs_exact.numbers import MAX_DIGITS, check_digits
from lcs_exact.verify.compare import Violation
from lcs_exact.verify.zoo import Problem, write_zoo
from lcs_exact.testing import assert_matches_fixture

from helpers import carts

X0 = [0, 1, -1, 0]
OSC = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])

BAD_DIGITS = [0, -3, MAX_DIGITS + 1, 10 ** 7, True, False, 30.0, "30", None, np.int64(30), [30]]


@pytest.fixture(scope="module")
def run():
    """The two carts on [0, 1]: one event at t = 0 (a jump), phases after it."""
    return L.simulate(carts(), X0, 1, digits=20)


@pytest.fixture(scope="module")
def osc_fixture():
    return L.read_fixture(L.simulate(OSC, [1, 0], 1, digits=20).to_fixture(20, sample="1/2"))


def _entry_points(run, osc_fixture, tmp_path):
    """Every public call that takes ``digits``: name -> a function of the digits."""
    t = run.events[-1].time
    violation = Violation(time=0.5, component=0, name="x_0", solver=0.9, exact=arb("0.8775825618903727"),
                          error=0.03, tolerance=1e-6)
    return {
        "simulate": lambda d: L.simulate(carts(), X0, 1, digits=d),
        "simulate_branches": lambda d: L.simulate_branches(carts(), X0, 1, digits=d),
        "Trajectory.sample": lambda d: run.sample([0, "1/2"], d),
        "Trajectory.to_fixture": lambda d: run.to_fixture(digits=d),
        "ExactVector.ball": lambda d: run.state("1/2").ball(d),
        "Real.ball": lambda d: t.ball(d),
        "Real.decimal": lambda d: t.decimal(d),
        "FixtureTrajectory.sample": lambda d: osc_fixture.sample(["1/2"], d),   # a grid time: no recomputation
        "write_zoo": lambda d: write_zoo(tmp_path, digits=d, only="relay"),
        "Problem.run": lambda d: Problem.__dict__["run"](_FakeProblem(), d),
        "assert_matches_fixture": lambda d: assert_matches_fixture(osc_fixture, [0.5, 1.0], [[0.8775826, -0.4794255], [0.5403023, -0.8414710]],
            event_tol=0.1, digits=d),
        "Violation.message": lambda d: violation.message(d),
    }


class _FakeProblem:
    """The least a zoo problem needs for ``Problem.run``: its system, x0 and t_end."""
    t_end = 1

    def system(self):
        return OSC

    def initial_state(self, lcs):
        return [1, 0]


ENTRY_NAMES = ["simulate", "simulate_branches", "Trajectory.sample", "Trajectory.to_fixture", "ExactVector.ball", "Real.ball",
               "Real.decimal", "FixtureTrajectory.sample", "write_zoo", "Problem.run", "assert_matches_fixture",
               "Violation.message"]


@pytest.mark.parametrize("entry", ENTRY_NAMES)
def test_bad_digits_are_an_invalid_argument_naming_digits_at_every_entry_point(entry, run, osc_fixture, tmp_path):
    call = _entry_points(run, osc_fixture, tmp_path)[entry]
    for d in BAD_DIGITS:
        if d is None and entry == "Trajectory.to_fixture":
            continue  # None is its default: the run's digits
        with pytest.raises(InvalidArgument) as ei:
            call(d)
        assert type(ei.value) is InvalidArgument, (entry, d)
        msg = str(ei.value)
        assert msg.startswith("digits must be"), (entry, d, msg)
        assert f"1..{MAX_DIGITS}" in msg or "must be an integer, got" in msg, (entry, d, msg)
    assert not any(tmp_path.iterdir())  # write_zoo refused before writing anything


@pytest.mark.parametrize("entry", [e for e in ENTRY_NAMES if e != "write_zoo"])
def test_good_digits_still_work_at_every_entry_point(entry, run, osc_fixture, tmp_path):
    call = _entry_points(run, osc_fixture, tmp_path)[entry]
    call(12)
    call(1)


def test_the_values_a_good_digits_gives():
    """The digits asked for are the digits given: the event time pi/2 of the oscillator."""
    tr = L.simulate(OSC, [1, 0], 2, digits=25)
    t = tr.events[0].time
    assert t.decimal(12) == "1.57079632679 +/- 5e-12" or t.decimal(12).startswith("1.57079632679")
    assert t.ball(40).rel_accuracy_bits() >= 130
    x = tr.sample(["1/2"], 17)[0]
    assert abs(float(x[0].mid()) - 0.8775825618903728) < 1e-16


def test_check_digits_messages_name_the_argument_and_the_fix():
    assert check_digits(30) == 30 and check_digits(MAX_DIGITS) == MAX_DIGITS and check_digits(1) == 1
    with pytest.raises(InvalidArgument, match=r"^digits must be an integer in 1\.\.10000, got 0$"):
        check_digits(0)
    with pytest.raises(InvalidArgument, match=r"^digits must be a Python int in 1\.\.10000, .*use int\(\.\.\.\)"):
        check_digits(np.int64(30))
    with pytest.raises(InvalidArgument, match=r"^n_digits must be an integer, got '30' \(str\)$"):
        check_digits("30", "n_digits")
    with pytest.raises(InvalidArgument) as ei:
        check_digits(True)
    assert "bool" in str(ei.value) and "int(" not in str(ei.value)


def test_digits_defaults_are_the_documented_ones():
    """30 for a run and its exact numbers, 17 for float-sized samples, 20 for the zoo and the
    values an assertion prints, the run's own for a fixture (check_digits' docstring)."""
    def default(f):
        return inspect.signature(f).parameters["digits"].default

    assert [default(f) for f in (L.simulate, L.simulate_branches, L.Real.ball, L.Real.decimal,
                                 L.ExactVector.ball)] == [30] * 5
    assert [default(f) for f in (L.Trajectory.sample, L.FixtureTrajectory.sample)] == [17, 17]
    assert [default(f) for f in (write_zoo, Problem.run, assert_matches_fixture, Violation.message)] == [20] * 4
    assert default(L.Trajectory.to_fixture) is None


def test_a_fixture_is_written_at_its_runs_digits_by_default(run):
    assert run.to_fixture()["digits"] == 20 and run.to_fixture(digits=7)["digits"] == 7
@pytest.mark.parametrize("value, meaning", [("lazy", "lazy"), (True, "eager"), ("eager", "eager"),
                                            (False, "off"), ("off", "off")])
def test_closed_forms_spellings_and_their_meanings(value, meaning):
    """lazy: nothing proven until asked, then pi/2; eager (True): the phase's duration pi/2 proven
    by the run itself (the event time is 0 + theta); off (False): never looked for."""
    assert CLOSED_FORMS[value] == meaning
    tr = L.simulate(OSC, [1, 0], 2, closed_forms=value)
    assert tr.policy.closed_forms == meaning
    t = tr.events[0].time
    known = t.b.known_closed_form        # theta, the phase's duration (known_closed_form never derives one)
    if meaning == "eager":
        assert str(known) == "pi/2"
    else:
        assert known is None
    if meaning == "off":
        assert t.closed_form is None and t.closed_form_status == "off"
    else:
        assert str(t.closed_form) == "pi/2" and t.closed_form_status == "proven"


def test_the_default_is_lazy():
    assert inspect.signature(L.simulate).parameters["closed_forms"].default == "lazy"


@pytest.mark.parametrize("value", ["maybe", "Lazy", 1, 0, None, [], "true", np.bool_(True)])
def test_closed_forms_other_values_name_the_accepted_ones(value):
    with pytest.raises(InvalidArgument) as ei:
        L.simulate(OSC, [1, 0], 2, closed_forms=value)
    msg = str(ei.value)
    assert msg.startswith("closed_forms must be")
    for accepted in ("'lazy'", "'eager'", "'off'", "True", "False"):
        assert accepted in msg, msg
