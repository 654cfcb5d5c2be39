"""Non-uniqueness answered honestly: S(z) holding different initial solutions raises IllPosed with
the alternatives (default) or yields every branch (branches="all"); derived by hand."""
from __future__ import annotations

import typing
from fractions import Fraction

import mpmath as mp
import pytest

import lcs_exact as L
from lcs_exact.modes.selection import initial_solution_groups

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
    """From x0 = 1 both modes are solutions: x = e^-t (mode ∅) and x = 1 (mode {0}, u = x).  Each
    branch is one solution with every digit right: certified; the problem is not unique."""
    b = L.simulate(SCALAR, [1], 2, branches="all")
    assert len(b) == 2 and all(tr.certified and not tr.partial for tr in b)
    assert not b.unique and b.certified and all(not tr.unique for tr in b)
    decay, rest = b.trajectories
    assert [m for _, m in decay.choices] == [frozenset()] and [m for _, m in rest.choices] == [frozenset({0})]
    assert [t.rational() for t, _ in decay.choices + rest.choices] == [0, 0]
    with mp.workdps(40):
        for t in ("1/3", 1, 2):
            want = mp.exp(-mp.mpf(Fraction(t).numerator) / Fraction(t).denominator)
            got = mp.mpf(decay.state(t)[0].ball(30).mid().str(35, radius=False))
            assert abs(got - want) < mp.mpf(10) ** -29 * want
    assert all(rest.state(t)[0].rational() == 1 for t in ("1/3", 1, 2))
    assert rest.u(2)[0].rational() == 1 and decay.u(2)[0].rational() == 0  # u = x in mode {0}, 0 in ∅
    text = repr(b)
    assert "2 solutions" in text and "NOT unique" in text and "each certified" in text
    assert "one of several solutions" in repr(decay) and "certified" in repr(decay)


def test_four_branches_of_two_independent_scalars_each_certified():
    """Two uncoupled copies of the scalar system from (1, 1): four solutions, (e^-t or 1) x (e^-t
    or 1), found by hand; each branch certified with its own exact states."""
    two = L.LCS([[-1, 0], [0, -1]], [[1, 0], [0, 1]], [[1, 0], [0, 1]], [[-1, 0], [0, -1]])
    b = L.simulate(two, [1, 1], 3, branches="all")
    assert len(b) == 4 and not b.unique and b.certified
    found = set()
    with mp.workdps(40):
        for tr in b:
            assert tr.certified and not tr.unique and tr.status is L.trajectory.Status.COMPLETE
            x = tr.state(3)
            kinds = []
            for c in x:
                if c.rational() == 1:
                    kinds.append("rest")
                else:
                    got = mp.mpf(c.ball(30).mid().str(35, radius=False))
                    assert abs(got - mp.exp(-3)) < mp.mpf(10) ** -29
                    kinds.append("decay")
            found.add(tuple(kinds))
            (t0, mode), = tr.choices  # one choice at t = 0 among the four initial solutions
            assert t0.rational() == 0 and kinds == ["rest" if i in mode else "decay" for i in range(2)]
    assert found == {("rest", "rest"), ("rest", "decay"), ("decay", "rest"), ("decay", "decay")}


def test_a_unique_problem_through_branches_all_is_one_certified_branch():
    """branches='all' on a problem that does not branch: one trajectory, unique, certified."""
    b = L.simulate(SCALAR, [0], 1, branches="all")
    assert len(b) == 1 and b.unique and b.certified and b[0].unique and b[0].choices == ()
    assert "unique" in repr(b) and "NOT unique" not in repr(b)


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


def test_a_branch_fixture_without_its_digests_is_checked_against_its_branch():
    """A fixture of one branch of a non-unique problem, its digests removed, is recomputed: the
    run from x0 is not unique, so the branch whose events and samples match is found (x = e^-t or
    x = 1 from x0 = 1); an edited sample matches no branch and is refused."""
    b = L.simulate(SCALAR, [1], 2, branches="all")
    for tr in b:
        d = tr.to_fixture(10, sample="1/2")
        del d["digest"], d["samples_digest"]
        assert not L.read_fixture(dict(d)).digested
        d["samples"][2]["x"][0].update(value="0.7", exact=None)  # x(1) is e^-1 or 1, never 0.7
        with pytest.raises(L.FixtureMismatch, match="none of its 2 solutions matches"):
            L.read_fixture(d)


def _summary(b):
    """What a Branches says, exactly: per branch its status, choices (time, mode), events (time,
    jump modes) and states at t = 1/3 and at t_end (rationals where exact, balls to 30 digits)."""
    def value(c):
        q = c.rational()
        return ("q", q) if q is not None else ("ball", c.ball(30).mid().str(30, radius=False))

    out = []
    for tr in b:
        out.append((tr.status, tr.certified, tr.partial,
                    tuple((t.rational(), m) for t, m in tr.choices),
                    tuple((e.time.ball(30).mid().str(30, radius=False), tuple(e.jumps)) for e in tr.events),
                    tuple(value(c) for c in tr.state("1/3")), tuple(value(c) for c in tr.state(tr.t_end))))
    return b.unique, b.certified, out


@pytest.mark.parametrize("system, x0, t_end, count", [
    (SCALAR, [1], 2, 2),                                          # x = e^-t or x = 1
    (L.LCS([[-1, 0], [0, -1]], [[1, 0], [0, 1]], [[1, 0], [0, 1]], [[-1, 0], [0, -1]]), [1, 1], 3, 4),
    (SCALAR, [0], 1, 1),                                          # unique, through the same door
])
def test_simulate_branches_is_simulate_with_branches_all(system, x0, t_end, count):
    """The typed entry point returns the same branches, in the same order, as simulate(...,
    branches="all"), which keeps working as before."""
    mine = L.simulate_branches(system, x0, t_end, digits=25)
    theirs = L.simulate(system, x0, t_end, digits=25, branches="all")
    assert type(mine) is type(theirs) is L.Branches
    assert _summary(mine) == _summary(theirs)
    assert len(mine) == count and mine.unique == (count == 1)


def test_simulate_branches_takes_simulates_options_but_not_branches():
    b = L.simulate_branches(SCALAR, [1], 2, max_events=5, closed_forms="off", zeno="stop", digits=12)
    assert len(b) == 2 and all(tr.digits == 12 and tr.policy.closed_forms == "off" for tr in b)
    with pytest.raises(TypeError, match="branches"):
        L.simulate_branches(SCALAR, [1], 2, branches="unique")
    with pytest.raises(L.InvalidArgument, match="zeno"):
        L.simulate_branches(SCALAR, [1], 2, zeno="go")
    with pytest.raises(L.ShapeError, match="x0"):
        L.simulate_branches(SCALAR, [1, 2], 2)


def test_simulate_is_typed_by_its_branches_argument():
    """typing.overload with Literal: branches="unique" (the default) gives a Trajectory,
    branches="all" a Branches; simulate_branches is annotated Branches."""
    hints = [typing.get_type_hints(f) for f in typing.get_overloads(L.simulate)]
    assert [(h["branches"], h["return"]) for h in hints] == [
        (typing.Literal["unique"], L.Trajectory), (typing.Literal["all"], L.Branches), (str, L.Trajectory | L.Branches)]
    assert typing.get_type_hints(L.simulate)["return"] == L.Trajectory | L.Branches
    assert typing.get_type_hints(L.simulate_branches)["return"] is L.Branches
    assert "simulate_branches" in L.__all__ and "simulate_branches" in L.dynamics.__all__
