"""Exact first crossings of polynomial phases (lcs_exact.phases.polyroots) and the runs they make exact.

Each root is derived here: by hand (1/2, 1, 2, sqrt 2, (sqrt 2 + sqrt 6)/2) or, for the cubic,
by mpmath's polynomial solver at 50 digits."""
from __future__ import annotations

import mpmath
from flint import fmpq, fmpq_mat

from lcs_exact import LCS, simulate
from lcs_exact.numbers.calcium import Ca
from lcs_exact.models import relay
from lcs_exact.phases.polyroots import exact_first_crossing


def q(*cs):
    return [fmpq(c) for c in cs]


def test_rational_polynomials():
    assert exact_first_crossing(q(1, -2), fmpq(10)).root.known_rational() == fmpq(1, 2)
    # (1 - t)^3 = 1 - 3t + 3t^2 - t^3: a triple root is a crossing, exactly 1
    assert exact_first_crossing(q(1, -3, 3, -1), fmpq(10)).root.known_rational() == 1
    # (1 - t)^2 (2 - t) = 2 - 5t + 4t^2 - t^3: the touch at 1 is no event, the crossing is at 2
    assert exact_first_crossing(q(2, -5, 4, -1), fmpq(10)).root.known_rational() == 2
    # (1 - t)^2: a touch only: no crossing at all
    assert exact_first_crossing(q(1, -2, 1), fmpq(10)).root is None
    # t (2 - t^2): the root at the start is not an event; sqrt 2 is, exactly
    r = exact_first_crossing(q(0, 2, 0, -1), fmpq(10)).root
    assert str(r.closed_form) == "sqrt(2)" and r.known_rational() is None
    assert exact_first_crossing(q(5, 0, -1), fmpq(2)).root is None  # sqrt 5 > horizon 2


def test_an_irreducible_cubic():
    # 1 - t - t^3: one real root, irreducible over Q (no rational root +-1)
    r = exact_first_crossing(q(1, -1, 0, -1), fmpq(10)).root
    with mpmath.workdps(60):
        want = [x for x in mpmath.polyroots([-1, 0, -1, 1]) if abs(mpmath.im(x)) < 1e-40][0]
        got = mpmath.mpf(r.ball(50).mid().str(60, radius=False))
        assert abs(got - mpmath.re(want)) < mpmath.mpf(10) ** -48
    assert r.ca.minimal_polynomial() == [-1, 1, 0, 1]


def test_algebraic_coefficients():
    s2 = Ca(2).sqrt()
    r = exact_first_crossing([s2, Ca(-1)], fmpq(10)).root  # sqrt 2 - t
    assert (r.ca - s2).is_zero() is True
    # 1 + sqrt2 t - t^2: roots (sqrt 2 +- sqrt 6) / 2, the positive one is the crossing
    r = exact_first_crossing([Ca(1), s2, Ca(-1)], fmpq(10)).root
    assert (r.ca - (s2 + Ca(6).sqrt()) / 2).is_zero() is True
    # (sqrt 2 - t)^2 = 2 - 2 sqrt2 t + t^2: a double root, a touch: no crossing
    assert exact_first_crossing([Ca(2), -2 * s2, Ca(1)], fmpq(10)).root is None


def test_two_relays_switch_together_exactly():
    """Siconos' SimpleExampleRelay: x' = -2 sgn(x) componentwise from (1, 1): both relays reach 0
    at exactly t = 1/2 (one event, both triggers) and slide there ever after."""
    lcs = relay([[0, 0], [0, 0]], [[-2, 0], [0, -2]], [[1, 0], [0, 1]])
    tr = simulate(lcs, lcs.embed([1, 1]), 2)
    assert tr.certified and len(tr.events) == 1
    (ev,) = tr.events
    assert ev.time.known_rational() == fmpq(1, 2)
    assert ev.state_before.known_rational() == fmpq_mat([[0], [0], [1]])
    assert ev.mode_after == frozenset({0, 2}) and len(ev.triggers) == 2
    assert tr.state(2).known_rational() == fmpq_mat([[0], [0], [1]])


def test_a_chain_of_integrators_through_a_triple_root():
    """x1' = x2, x2' = x3, x3' = x4 + u, y = x1 = (1 - t)^3 from (1, -3, 6, -6): the stop is
    reached at t = 1 exactly with x(1) = (0, 0, 0, -6), and the run goes on (the jump to rest)."""
    A = [[0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]
    lcs = LCS(A, [[0], [0], [0], [1]], [[1, 0, 0, 0]], [[0]])
    tr = simulate(lcs, [1, -3, 6, -6], 3)
    (ev,) = tr.events
    assert ev.time.known_rational() == 1
    assert ev.state_before.known_rational() == fmpq_mat([[0], [0], [0], [-6]])
    assert tr.state(3).known_rational() == fmpq_mat(4, 1) and not tr.partial
