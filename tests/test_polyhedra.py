"""Exact LP feasibility (polyhedra.find_point) against an independent Fourier-Motzkin elimination
(reference.polyhedra)."""
from __future__ import annotations

from fractions import Fraction as Fr

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lcs_exact.errors import InvalidArgument
from lcs_exact.algebra.polyhedra import find_point, is_feasible

from reference.polyhedra import fm_feasible


def check(nvars, cons):
    p = find_point(nvars, cons)
    assert (p is not None) == fm_feasible(nvars, cons)
    if p is not None:  # the point really satisfies the system, by exact rational arithmetic
        for a, b, rel in cons:
            v = sum(Fr(x) * Fr(str(z)) for x, z in zip(a, p)) + Fr(b)
            assert {"=": v == 0, ">": v > 0, ">=": v >= 0}[rel]
    return p


def test_known_systems():
    assert check(2, [([1, 0], 0, ">"), ([0, 1], 0, ">"), ([-1, -1], 1, ">")]) is not None
    assert check(2, [([1, 0], 0, ">"), ([0, 1], 0, ">"), ([-1, -1], 0, ">=")]) is None  # only 0 fits, not strict
    assert check(2, [([1, 0], 0, ">="), ([0, 1], 0, ">="), ([-1, -1], 0, ">=")]) == (0, 0)
    assert check(1, [([1], -3, "="), ([1], -2, ">")]) == (3,)
    assert check(1, [([1], -3, "="), ([-1], 2, ">")]) is None
    assert check(0, []) == ()
    assert check(0, [([], 1, ">")]) == ()
    assert check(0, [([], 0, ">")]) is None
    assert is_feasible(3, [([1, 1, 1], -1, "="), ([1, 0, 0], 0, ">"), ([0, 1, 0], 0, ">"), ([0, 0, 1], 0, ">")])


def test_degenerate_cycling_candidate():
    # many redundant constraints through one point (degenerate pivots; Bland's rule must terminate)
    cons = [([i, j], 0, ">=") for i in range(-2, 3) for j in range(-2, 3) if (i, j) != (0, 0) and i + j >= 0]
    check(2, cons)
    check(2, cons + [([1, 1], 0, ">")])


def test_bad_input():
    with pytest.raises(InvalidArgument, match="expected 2"):
        find_point(2, [([1], 0, ">")])
    with pytest.raises(InvalidArgument, match="relation"):
        find_point(1, [([1], 0, "<")])
    with pytest.raises(InvalidArgument, match="constraint is"):
        find_point(1, [([1], 0)])


coef = st.integers(-3, 3)


@st.composite
def systems(draw):
    n = draw(st.integers(1, 3))
    m = draw(st.integers(1, 6))
    cons = []
    for _ in range(m):
        a = [draw(coef) for _ in range(n)]
        b = draw(st.fractions(min_value=-3, max_value=3, max_denominator=4))
        cons.append((a, b, draw(st.sampled_from(["=", ">", ">="]))))
    return n, cons


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(systems())
def test_find_point_agrees_with_fourier_motzkin(case):
    n, cons = case
    check(n, cons)
