"""Test helpers for other solvers' test suites: compare a numerical solution with a certified
fixture in one line (docs/fixtures.md, docs/zoo.md).  In a pytest test of a solver::

    from lcs_exact.testing import assert_matches_fixture
    assert_matches_fixture("ball.json", t, X, atol=1e-3)

:func:`assert_matches_fixture` is :func:`lcs_exact.compare` with tolerances, plus a raise: the
same windows around every event (those an accumulation implies included; by default twice the
solver's largest step), the same float-grid rounding forgiven, the same component names (the
fixture's state names), X with all n states or the plant's only.  A failure is an
``AssertionError`` whose message names the worst point: its time, component, the solver's value,
the exact value with its certified digits, and the error.
"""
from __future__ import annotations

from typing import Any, Sequence

from .compare import ComparisonReport, compare
from ..errors import FormatError
from ..numbers import check_digits

__all__ = ["assert_matches_fixture"]


def assert_matches_fixture(fixture: Any, t: Sequence[Any], X: Any, atol: float = 1e-6, rtol: float = 0.0,
                           event_tol: Any = None, digits: int = 20) -> ComparisonReport:
    """Assert that a solver's states X at the times t match the certified fixture.

    Parameters
    ----------
    fixture : dict, str, FixtureTrajectory or Trajectory
        A fixture dict, the path of its JSON file, a fixture read back (``read_fixture``), or a
        trajectory from :func:`lcs_exact.simulate`.
    t : sequence of numbers
        The solver's times (floats are read as their shortest decimals; a float grid that
        overshoots t_end or the sample grid by rounding is accepted).  Off the fixture's sample
        grid the exact values are recomputed, which needs a rational x0 (or a run attached with
        ``FixtureTrajectory.with_run``; the zoo's cases do it).
    X : array-like, len(t) x n, or len(t) x len(plant)
        The solver's states at those times: all n states, or the plant's only (without the
        sources a builder appended, ``lcs.plant``).
    atol, rtol : float
        Tolerances: ``|X - x| <= atol + rtol |x|``, componentwise.
    event_tol : float, optional
        Half-width of the window left out around each exact event (states only); None: twice the
        solver's largest step, as :func:`lcs_exact.compare`.  Each window also reaches the
        solver's own switch for its event, so ``event_tol=0`` still leaves out the span between
        the exact event time and the solver's.
    digits : int
        Digits of the exact value printed in the message.

    Returns
    -------
    ComparisonReport
        The comparison (``report.passed`` is True), for a look at the errors.

    Raises
    ------
    AssertionError
        At least one component is outside the tolerance (the message names the worst point), the
        solution ends before the reference does (by more than a step and a half), or no point
        could be compared (all in event windows or after the reference's end).
    FormatError
        Some times have no reference: off the sample grid of a fixture whose run cannot be
        recomputed exactly.

    Examples
    --------
    >>> import lcs_exact as L
    >>> osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    >>> fx = L.simulate(osc, [1, 0], 1).to_fixture(20)
    >>> _ = assert_matches_fixture(fx, [0.5, 1.0], [[0.8775826, -0.4794255], [0.5403023, -0.8414710]], event_tol=0.1)
    >>> _ = assert_matches_fixture(fx, [0.5, 1.0], [[0.88, -0.48], [0.5403023, -0.8414710]], event_tol=0.1)
    Traceback (most recent call last):
    ...
    AssertionError: the solution differs from the fixture by 0.00242 > tolerance 1e-06 at t = 0.5, component x_0: solver 0.88, exact 0.87758256189037271612 (+/- ...)
    """
    digits = check_digits(digits)  # before the comparison: a bad value is not an error of the solver
    report = compare(fixture, t, X, event_tol=event_tol, atol=atol, rtol=rtol)
    if report.n_unmatched:
        raise FormatError(f"{report.n_unmatched} of the solver's times are not on the fixture's sample grid and "
                          "its run cannot be recomputed exactly (x0 is not rational): compare at grid times, or "
                          "attach the run with FixtureTrajectory.with_run")
    if report.violation is not None:
        raise AssertionError(report.violation.message(digits)
                             + (f" ({report.n_violations} points outside the tolerance)" if report.n_violations > 1 else ""))
    end, last = report.solver_end, float(report.last_time.mid())
    if end is not None and end < last - 1.5 * report.step - 1e-12 * abs(last):
        raise AssertionError(f"the solution ends at t = {end:.10g}, before the reference's last time {last:.10g}: "
                             f"[{end:.6g}, {last:.6g}] is not tested (pass the solver's whole run, or compare a "
                             "part of it with lcs_exact.compare)")
    if report.n_compared == 0:
        raise AssertionError(f"none of the solver's {report.n_points} points was compared: {report.n_in_windows} lie in "
                             f"the windows |t - event| <= {report.window:.3g} ({report.window_rule}) and "
                             f"{report.n_beyond} after the reference's last time")
    return report
