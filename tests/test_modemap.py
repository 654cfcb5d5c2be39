"""The exact mode map: Figure 8.2 derived by hand (Moreau's rule, Theorem 8.2, and the RCP's
Laurent coefficients), and locate() against select_modes() on random rational points."""
from __future__ import annotations

import functools
from fractions import Fraction as Fr

import pytest
from flint import fmpq_mat
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from lcs_exact import LCS, is_p_matrix
from lcs_exact.errors import NotAutonomous, ShapeError, Unsupported
from lcs_exact.examples import two_carts, two_carts_with_hook
from lcs_exact.system.modemap import Inequality
from lcs_exact.algebra.rational import to_vector

SLICE = ([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]])
E, S0, S1, S01 = frozenset(), frozenset({0}), frozenset({1}), frozenset({0, 1})


# --- Figure 8.2 by hand ---------------------------------------------------------------------
# Coordinates (a, b) = the paper's (x3, x4) = velocities (q_0', q_1'), with q = 0, so both
# constraints are active (J = {0, 1}) and Minimization problem 8.1 (M = I) projects w0 = (a, b)
# onto the cone K = {w : w1 >= 0, w1 - w2 >= 0}.  Its KKT conditions (8.4)-(8.5),
# w = w0 + E^T lambda, 0 <= lambda ⊥ E w >= 0, give four closed cones:
#   stop-constrained  {0}:    lambda = (-a, 0),            w = (0, b):   a <= 0, b <= 0
#                             (Example 8.3's text: x30 <= 0 and x40 <= 0)
#   hook-constrained  {1}:    lambda = (0, (b - a)/2),     w = ((a+b)/2, (a+b)/2):  b >= a, a + b >= 0
#   hook/stop         {0, 1}: lambda = (-a - b, b),        w = (0, 0):   b >= 0, a + b <= 0
#   unconstrained     ∅:      lambda = 0,                  w = (a, b):   a >= 0, a >= b
# Theorem 8.2: the RCP's modes carry these jumps.  The RCP is finer than Moreau's rule on the
# boundary of the unconstrained cone, where the jump is zero: ∅ is in S(x0) iff y(s) = R(s) x0
# is lexicographically >= 0, and R(s) x0 has Laurent coefficients C x0, C A x0, C A^2 x0, C A^3 x0.
# With A of (8.12) and x0 = (0, 0, a, b): C x0 = (0, 0), C A x0 = (a, a - b),
# C A^2 x0 = (0, 0), C A^3 x0 = (-2a + b, -3a + 2b).  So ∅ in S iff
#   (a > 0 or (a = 0 and b >= 0)) and (a > b or (a = b and -3a + 2b >= 0, i.e. a = b <= 0)),
# i.e. (a > 0 and b < a) or a = b = 0: the rays a = 0 > b and a = b > 0 are not free.

def hand_admissible(I, a, b) -> bool:
    if I == S0:
        return a <= 0 and b <= 0
    if I == S1:
        return b >= a and a + b >= 0
    if I == S01:
        return b >= 0 and a + b <= 0
    return (a > 0 and b < a) or (a == 0 and b == 0)


def hand_S(a, b) -> frozenset:
    return frozenset(I for I in (E, S0, S1, S01) if hand_admissible(I, a, b))


def hand_jump(a, b):
    """x(0+) by Moreau's rule (the projection above)."""
    if a >= 0 and b <= a:
        return (0, 0, a, b)
    if a <= 0 and b <= 0:
        return (0, 0, 0, b)
    if b >= a and a + b >= 0:
        return (0, 0, (a + b) / 2, (a + b) / 2)
    return (0, 0, 0, 0)


def witnesses(lines):
    """One rational point in every face of a central arrangement of lines in the plane: the
    origin, a point on each ray, and a point between each two consecutive rays (exact angular
    order).  Two unions of faces are equal iff they agree on these points."""
    rays = set()
    for a, b in lines:
        rays |= {(-b, a), (b, -a)}
    rays = sorted({(Fr(str(x)), Fr(str(y))) for x, y in rays}, key=functools.cmp_to_key(_angle_cmp))
    # normalize: drop rays on the same half-line
    uniq = []
    for r in rays:
        if not uniq or _angle_cmp(uniq[-1], r) != 0:
            uniq.append(r)
    pts = [(Fr(0), Fr(0))] + uniq
    for i, r in enumerate(uniq):
        q = uniq[(i + 1) % len(uniq)]
        pts.append((r[0] + q[0], r[1] + q[1]) if (r[0] * q[1] - r[1] * q[0]) != 0 else (-r[1], r[0]))
    return pts


def _half(p):
    return 0 if (p[1] > 0 or (p[1] == 0 and p[0] > 0)) else 1


def _angle_cmp(p, q):
    hp, hq = _half(p), _half(q)
    if hp != hq:
        return hp - hq
    cross = p[0] * q[1] - p[1] * q[0]
    return -1 if cross > 0 else (1 if cross < 0 else 0)


@pytest.fixture(scope="module")
def fig82():
    return two_carts_with_hook().mode_map(slice=SLICE)


def test_figure_8_2_lines_and_names(fig82):
    assert fig82.variables == ("q_0'", "q_1'")
    assert all(b == 0 for _, b in fig82.hyperplanes)  # a central arrangement (the slice is linear)


def test_figure_8_2_regions_equal_the_hand_derivation(fig82):
    lines = [(1, 0), (0, 1), (1, -1), (1, 1)] + [(a[0], a[1]) for a, _ in fig82.hyperplanes]
    pts = witnesses(lines)
    assert len(pts) >= 17
    for a, b in pts:
        want = hand_S(a, b)
        reg = fig82.locate([a, b])
        assert reg.modes == want, (a, b)
        assert sum(r.contains([a, b]) for r in fig82.regions) == 1  # a partition, by the inequalities
        assert reg.contains([a, b])
        # the union of the regions whose S holds I is the hand cone of I
        for I in (E, S0, S1, S01):
            assert any(r.contains([a, b]) for r in fig82.admissible(I)) == hand_admissible(I, a, b)
        # re-initialization = Moreau's projection (Theorem 8.2)
        x0 = to_vector([0, 0, a, b], 4)
        got = reg.jump * x0
        assert tuple(Fr(str(got[i, 0])) for i in range(4)) == hand_jump(a, b)


def test_figure_8_2_seven_regions_with_their_inequalities(fig82):
    got = {r.modes: r for r in fig82.regions}
    assert set(got) == {frozenset({E}), frozenset({S0}), frozenset({S1}), frozenset({S01}),
                        frozenset({S0, S01}), frozenset({S1, S01}), frozenset({E, S0, S1, S01})}
    dims = {frozenset({E}): 2, frozenset({S0}): 2, frozenset({S1}): 2, frozenset({S01}): 2,
            frozenset({S0, S01}): 1, frozenset({S1, S01}): 1, frozenset({E, S0, S1, S01}): 0}
    assert {m: r.dimension for m, r in got.items()} == dims
    # each region is convex: one conjunction, irredundant, as derived above
    v = ("q_0'", "q_1'")

    def ineqs(*rows):
        return {Inequality(tuple(Fr(c) for c in a), Fr(0), rel, v) for a, rel in rows}

    def as_set(r):
        assert len(r.inequalities) == 1
        return {Inequality(tuple(Fr(str(c)) for c in q.coefficients), Fr(str(q.constant)), q.relation, v)
                for q in r.inequalities[0]}

    assert as_set(got[frozenset({E})]) == ineqs(((1, 0), ">"), ((1, -1), ">"))
    assert as_set(got[frozenset({S0})]) == ineqs(((-1, 0), ">="), ((0, -1), ">"))
    assert as_set(got[frozenset({S1})]) == ineqs(((-1, 1), ">="), ((1, 1), ">"))
    assert as_set(got[frozenset({S01})]) == ineqs(((0, 1), ">"), ((-1, -1), ">"))
    assert as_set(got[frozenset({S0, S01})]) == ineqs(((-1, 0), ">"), ((0, 1), "="))
    assert as_set(got[frozenset({S1, S01})]) == ineqs(((0, 1), ">"), ((1, 1), "="))
    assert as_set(got[frozenset({E, S0, S1, S01})]) == ineqs(((1, 0), "="), ((0, 1), "="))
    assert str(got[frozenset({S0})].inequalities[0][0]) in ("-q_0' >= 0", "-q_1' > 0")
    # the selected mode (smallest) and its projection
    assert got[frozenset({S0, S01})].mode == S0 and got[frozenset({E, S0, S1, S01})].mode == E
    assert all(r.unique_jump for r in fig82.regions)


def test_figure_8_2_jump_directions(fig82):
    """The arrows of Figure 8.2: P_I x0 - x0 in slice coordinates, exact and inside the slice."""
    reg = fig82.locate([-1, -2])  # stop-constrained: jump (0, 0, -x30, 0) (Example 8.3)
    c0, C1, exact = fig82.slice_jump(reg)
    assert exact and c0 == fmpq_mat(2, 1) and C1 == fmpq_mat([[-1, 0], [0, 0]])
    reg = fig82.locate([-1, 3])  # hook: to ((a+b)/2, (a+b)/2)
    _, C1, exact = fig82.slice_jump(reg)
    assert exact and C1 == fmpq_mat([[-1, 1], [1, -1]]) / 2


def rationals(lo=-3, hi=3):
    return st.one_of(st.integers(lo, hi).map(Fr), st.fractions(min_value=lo, max_value=hi, max_denominator=6))


@pytest.mark.slow
@settings(max_examples=150, deadline=None)
@given(rationals(), rationals())
def test_figure_8_2_locate_matches_select_modes(fig82, a, b):
    x0 = [0, 0, a, b]
    lcs = fig82.lcs
    want = lcs.select_modes(x0, method="rcp")
    reg = fig82.locate([a, b])
    assert reg.modes == want == hand_S(a, b)
    assert lcs.initial_solution(x0).mode == reg.mode


@pytest.fixture(scope="module")
def hook_full():
    return two_carts_with_hook().mode_map()


@pytest.mark.slow
@settings(max_examples=80, deadline=None)
@given(st.lists(rationals(-2, 2), min_size=4, max_size=4))
def test_full_state_space_hook(hook_full, x):
    reg = hook_full.locate(x)
    lcs = hook_full.lcs
    assert reg.modes == lcs.select_modes(x, method="rcp") == lcs.select_modes(x, method="ldcp")
    assert reg.contains(x)
    sol = lcs.initial_solution(x)
    assert reg.jump * to_vector(x, 4) == sol.state_after


def test_full_state_space_two_carts():
    mm = two_carts().mode_map()
    assert {r.modes for r in mm.regions} == {frozenset({E}), frozenset({S0}), frozenset({E, S0})}
    # S(x0) = {∅, {0}} only at the origin (every Laurent coefficient of y vanishes)
    both = [r for r in mm.regions if len(r.modes) == 2][0]
    assert both.dimension == 0 and both.contains([0, 0, 0, 0])
    for x in ([1, 0, 0, 0], [0, 5, 1, 0], [0, 0, 0, 1], [0, -1, 0, 0], [-1, 9, 9, 9], [0, 0, 0, -1]):
        assert mm.locate(x).modes == mm.lcs.select_modes(x)


@st.composite
def small_lcs(draw):
    """n = 2, k = 2, D a P-matrix: every mode autonomous (G_II(oo) = D_II is nonsingular)."""
    ints = st.integers(-2, 2)
    A = [[draw(ints) for _ in range(2)] for _ in range(2)]
    B = [[draw(ints) for _ in range(2)] for _ in range(2)]
    C = [[draw(ints) for _ in range(2)] for _ in range(2)]
    D = [[draw(st.integers(1, 3)), draw(ints)], [draw(ints), draw(st.integers(1, 3))]]
    assume(is_p_matrix(fmpq_mat(D)))
    return LCS(A, B, C, D)


@pytest.mark.slow
@settings(max_examples=25, deadline=None)
@given(small_lcs(), st.lists(st.lists(rationals(-2, 2), min_size=2, max_size=2), min_size=8, max_size=8))
def test_random_systems_locate_matches_select_modes(lcs, points):
    mm = lcs.mode_map()
    for r in mm.regions:  # regions are disjoint and every face is inside its region's inequalities
        for f in r.faces:
            assert r.contains(list(f.point))
            assert [q.contains(list(f.point)) for q in mm.regions].count(True) == 1
    for x in points:
        assert mm.locate(x).modes == lcs.select_modes(x, method="rcp")


def test_one_dimensional_slice_and_affine_base():
    lcs = two_carts()
    # the line x0 = (-1, 0, 0, 0) + s (1, 0, 0, 0): the stop is violated for s < 1
    mm = lcs.mode_map(slice=([-1, 0, 0, 0], [[1, 0, 0, 0]]))
    assert mm.variables == ("s_0",)
    assert mm.locate([0]).modes == {S0} and mm.locate([2]).modes == {E}
    assert mm.locate([1]).modes == lcs.select_modes([0, 0, 0, 0])
    assert [str(q) for q in mm.locate([2]).inequalities[0]] == ["s_0 > 1"]
    # names given explicitly
    mm = lcs.mode_map(slice=([0, 0, 0, 0], [[1, 0, 0, 0], [0, 0, 1, 0]], ["position", "velocity"]))
    assert mm.variables == ("position", "velocity")
    assert mm.state([2, 3]) == fmpq_mat([[2], [0], [3], [0]])


def test_errors():
    lcs = two_carts()
    with pytest.raises(ShapeError, match="linearly dependent"):
        lcs.mode_map(slice=([0, 0, 0, 0], [[1, 0, 0, 0], [2, 0, 0, 0]]))
    with pytest.raises(ShapeError, match="slice base"):
        lcs.mode_map(slice=([0, 0, 0], [[1, 0, 0, 0]]))
    with pytest.raises(ShapeError, match="at least one direction"):
        lcs.mode_map(slice=([0, 0, 0, 0], []))
    with pytest.raises(ShapeError):
        lcs.mode_map(slice=[0, 0, 0, 0])
    mm = lcs.mode_map(slice=SLICE)
    with pytest.raises(ShapeError, match="expected 2"):
        mm.locate([1, 2, 3])
    # a system with a non-autonomous mode: the map needs Assumption 4.1
    bad = LCS([[0, 1], [0, 0]], [[0, 0], [1, 1]], [[1, 0], [1, 0]], [[0, 0], [0, 0]])
    with pytest.raises(NotAutonomous, match="Assumption 4.1"):
        bad.mode_map()
    many = LCS([[0]], [[1] * 9], [[1]] * 9, [[int(i == j) for j in range(9)] for i in range(9)])
    with pytest.raises(Unsupported, match="k = 9"):
        many.mode_map()
