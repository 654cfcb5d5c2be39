"""Test helpers for other solvers' test suites: compare a numerical solution with a certified
fixture in one line (docs/fixtures.md, docs/zoo.md).  In a pytest test of a solver::

    from lcs_exact.testing import assert_matches_fixture
    assert_matches_fixture("ball.json", t, X, atol=1e-3)

The fixture's states at the times t are its certified samples where t is on the sample grid, and
recomputed exactly from the fixture's system and x0 elsewhere (``read_fixture``); a fixture
whose content does not match its digest is refused (``FixtureMismatch``).  The check is
``|X - x| <= atol + rtol |x|`` componentwise; a failure is an ``AssertionError`` whose message names
the worst point: its time, component (by name), the solver's value, the exact value with its
certified digits, and the error.
"""
from __future__ import annotations

from typing import Any, Sequence

from flint import arb

from .balls import workprec
from .errors import InvalidArgument
from .fixture import read_fixture
from .rational import to_fmpq

__all__ = ["assert_matches_fixture"]


def _rows(X: Any) -> list[list[float]]:
    if hasattr(X, "tolist"):
        X = X.tolist()
    rows = [list(r) if isinstance(r, (list, tuple)) else [r] for r in X]
    return [[float(v) for v in r] for r in rows]


def assert_matches_fixture(fixture: Any, t: Sequence[Any], X: Any, atol: float = 1e-6, rtol: float = 0.0,
                           digits: int = 20) -> None:
    """Assert that a solver's states X at the times t match the certified fixture.

    Parameters
    ----------
    fixture : dict, str or FixtureTrajectory
        A fixture dict, the path of its JSON file, or a fixture read back (``read_fixture``).
    t : sequence of numbers
        The solver's times (floats are read as their shortest decimals).  Off the fixture's
        sample grid the exact values are recomputed, which needs a rational x0.
    X : array-like, len(t) x n
        The solver's states at those times.
    atol, rtol : float
        Tolerances: ``|X - x| <= atol + rtol |x|``, componentwise.
    digits : int
        Digits of the exact values computed for the comparison (and printed).

    Raises
    ------
    AssertionError
        At least one component is outside the tolerance; the message names the worst point.

    Examples
    --------
    >>> import lcs_exact as L
    >>> osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    >>> fx = L.simulate(osc, [1, 0], 3).to_fixture(20)
    >>> assert_matches_fixture(fx, [0.5, 1.0], [[0.8775826, -0.4794255], [0.5403023, -0.8414710]], atol=1e-6)
    >>> assert_matches_fixture(fx, [0.5], [[0.88, -0.48]], atol=1e-6)
    Traceback (most recent call last):
    ...
    AssertionError: the solution differs from the fixture by 0.00242 > tolerance 1e-06 at t = 0.5, component x_0: solver 0.88, exact 0.87758256189037271612 (+/- ...)
    """
    fx = read_fixture(fixture)
    ts = [to_fmpq(v, "t") for v in (t.tolist() if hasattr(t, "tolist") else t)]
    rows = _rows(X)
    if len(rows) != len(ts):
        raise InvalidArgument(f"X has {len(rows)} rows but t has {len(ts)} times")
    names = list(getattr(fx.lcs, "state_names", ())) or [f"x_{i}" for i in range(len(rows[0]) if rows else 0)]
    worst = None  # (excess, t, i, solver value, exact ball, error)
    with workprec(128):
        # the fixture's certified samples when every t is on its grid (any x0: the section 7 run
        # starts from an irrational state), else the exact recomputation (x0 rational)
        exact = fx.sample(ts, digits) if ts else []
        for tq, row, comps in zip(ts, rows, exact):
            if len(row) != len(comps):
                raise InvalidArgument(f"X has {len(row)} columns but the fixture's state has {len(comps)}")
            for i, (v, b) in enumerate(zip(row, comps)):
                err = abs(arb(v) - b)
                tol = atol + rtol * abs(float(b.mid()))
                if err.upper() > tol:
                    excess = float(err.upper()) - tol
                    if worst is None or excess > worst[0]:
                        worst = (excess, tq, i, v, b, float(err.mid()), tol)
    if worst is not None:
        _, tq, i, v, b, e, tol = worst
        exact = _ball_text(b, digits)
        raise AssertionError(f"the solution differs from the fixture by {e:.3g} > tolerance {tol:.3g} at t = "
                             f"{float(tq):.17g}, component {names[i]}: solver {v!r}, exact {exact}")


def _ball_text(b: arb, digits: int) -> str:
    """A certified ball as 'value (+/- radius)' for a message."""
    return f"{b.mid().str(digits, radius=False)} (+/- {float(b.rad()):.3g})"
