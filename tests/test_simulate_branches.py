"""Non-uniqueness answered honestly: S(z) holding different initial solutions raises IllPosed with
the alternatives (default) or yields every branch (branches="all"); derived by hand."""
from __future__ import annotations

import mpmath as mp
import pytest

import lcs_exact as L
from lcs_exact.selection import initial_solution_groups

# x' = -x + u, y = x - u, 0 <= y ⊥ u >= 0.  Mode ∅: u = 0, y = x (needs x >= 0), x = x0 e^-t.
# Mode {0}: y = 0 so u = x, x' = 0 (needs u = x >= 0): x = x0 for ever.  From x0 > 0 both are
# solutions (different trajectories); from 0 both are the zero solution; from x0 < 0 neither.
SCALAR = L.LCS([[-1]], [[1]], [[1]], [[-1]])


def test_groups_of_initial_solutions():
    assert initial_solution_groups(SCALAR, [1], SCALAR.select_modes([1])) == [[frozenset()], [frozenset({0})]]
    assert initial_solution_groups(SCALAR, [0], SCALAR.select_modes([0])) == [[frozenset(), frozenset({0})]]


def test_default_refuses_a_silent_choice():
    with pytest.raises(L.IllPosed, match="non-unique") as err:
        L.simulate(SCALAR, [1], 2)
    e = err.value
    assert [m for m, _ in e.alternatives] == [frozenset(), frozenset({0})]
    assert [s.smooth for _, s in e.alternatives] == [True, True]
    assert e.trajectory.partial and not e.trajectory.certified


def test_all_branches_with_their_choices():
    b = L.simulate(SCALAR, [1], 2, branches="all")
    assert len(b) == 2 and all(not tr.certified and not tr.partial for tr in b)
    decay, rest = b.trajectories
    assert [m for _, m in decay.choices] == [frozenset()] and [m for _, m in rest.choices] == [frozenset({0})]
    with mp.workdps(40):
        assert abs(mp.mpf(decay.state(2)[0].ball(30).mid().str(35, radius=False)) - mp.exp(-2)) < mp.mpf(10) ** -29
    assert rest.state(2)[0].rational() == 1


def test_zero_is_unique_and_negative_is_a_deadlock():
    tr = L.simulate(SCALAR, [0], 2)
    assert tr.certified and tr.state(2)[0].rational() == 0
    with pytest.raises(L.Deadlock):
        L.simulate(SCALAR, [-1], 2)


def test_well_posed_systems_never_branch():
    """Theorem 6.3 (the hook system): at the origin S(0) holds all four modes of one solution."""
    h = L.models.two_carts_with_hook()
    tr = L.simulate(h, [0, 0, 0, 0], 1)
    assert tr.certified and tr.choices == ()
