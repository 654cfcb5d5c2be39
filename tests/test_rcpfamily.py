"""RCP(x0) in modes that are not autonomous (lcs_exact.modes.rcpfamily): consistency and Fourier-Motzkin
over Q(s), checked on systems solved by hand, against the autonomous path, and on exact-real states."""
from __future__ import annotations

from itertools import combinations

import mpmath as mp
import pytest
from flint import fmpq_mat
from hypothesis import given, settings
from hypothesis import strategies as st

import lcs_exact as L
from helpers import close, modes, num
from lcs_exact import RationalFunction, RationalMatrix
from lcs_exact.modes import rcpfamily
from lcs_exact.errors import LCSError, NotAutonomous, UnresolvedSign, Unsupported
from lcs_exact.modes.rcpfamily import family
from lcs_exact.modes.selection import admissibility_conditions, mode_admissible, state_groups, undetermined_inputs

s = RationalFunction.s()


def v1(x) -> fmpq_mat:
    return fmpq_mat([[x]])


def lazy():
    """x' = u, y = 0: G(s) = 0, R(s) = 0.  Mode {0}: any u(s) >= 0 solves RCP(x0)."""
    return L.LCS([[0]], [[1]], [[0]], [[0]])


def twins():
    """x' = u0 + u1, y0 = y1 = x: G = [[1/s, 1/s], [1/s, 1/s]], R = [1/s, 1/s].

    Mode {0, 1}: y = 0 gives (u0 + u1)/s = -x/s, i.e. u0 + u1 = -x (an impulse of weight -x, split
    freely): with u1 = v >= 0 and u0 = -x - v >= 0, a solution exists iff -x >= 0 (rank 1, one
    free input, always consistent).  Mode {0}: u0 = -x, y1 = x/s - x/s = 0: admissible iff
    x <= 0; likewise {1}; mode ∅: y = x/s, admissible iff x >= 0."""
    return L.LCS([[0]], [[1, 1]], [[1], [1]], [[0, 0], [0, 0]])


def tilted():
    """x' = u0 + u1, y0 = x, y1 = x + u0 + u1: G = [[1/s, 1/s], [1/s + 1, 1/s + 1]] (rank 1).

    Mode {0, 1}: pivot row 0 gives u0 + u1 = -x; row 1 then reads x/s + (1/s + 1)(-x) = -x = 0:
    consistent only at x = 0.  Mode {0}: u0 = -x, y1 = -x/s... = x/s + (1/s + 1)(-x) = -x: at
    x = -1, u0 = 1 (an impulse) and y1 = 1 (nonnegative).  Mode {1}: u1 = -x/(s + 1),
    y0 = x/s + u1/s = x/(s + 1): opposite signs, admissible only at 0.  Mode ∅: y = (x/s, x/s).
    So S(1) = {∅}, S(-1) = {{0}}, and at 0 every mode (the zero solution)."""
    return L.LCS([[0]], [[1, 1]], [[1], [1]], [[0, 0], [1, 1]])


def test_lazy_system_family():
    lcs = lazy()
    fam = family(lcs.mode({0}))
    assert (fam.rank, fam.pivot_rows, fam.pivot_cols, fam.free) == (0, (), (), (0,))
    assert fam.conditions() == ((), ())
    for x in (1, -1, 0):
        assert fam.admissible(v1(x))
        assert fam.solution(v1(x)) == ([RationalFunction(0)], [])  # v = 0 is feasible
    assert lcs.select_modes([5], nonautonomous="include") == modes([], [0])
    with pytest.raises(NotAutonomous, match=r"mode \{0\} is not autonomous"):
        lcs.initial_solution([5])


def test_twins_every_solution_violates_a_sign_for_positive_x():
    lcs = twins()
    m = lcs.mode({0, 1})
    assert not m.is_autonomous
    fam = family(m)
    assert fam.rank == 1 and fam.free == (1,)
    eqs, ineqs = fam.conditions()
    assert eqs == ()  # always consistent
    assert ineqs == ((fmpq_mat([[-1]]),),)  # Fourier-Motzkin: (-x - v) + v >= 0, i.e. -x >= 0
    assert not fam.admissible(v1(1)) and fam.admissible(v1(-2)) and fam.admissible(v1(0))
    assert lcs.select_modes([1]) == modes([])  # no raise: the non-autonomous mode is not admissible
    assert lcs.select_modes([-2], nonautonomous="include") == modes([0], [1], [0, 1])
    # every admissible mode jumps x to 0 (u0 + u1 = 2 delta, split freely): the state is unique,
    # the split is not (DESIGN.md section 7), so selection goes on and reports u0, u1 undetermined
    S = lcs.select_modes([-2])
    assert S == modes([0], [1], [0, 1])
    assert len(state_groups(lcs, v1(-2), S)) == 1 and undetermined_inputs(lcs, v1(-2), S) == {0, 1}
    tr = L.simulate(lcs, [-2], 1)
    assert tr.events[0].state_after.known_rational() == v1(0) and tr.state(1).known_rational() == v1(0)
    assert tr.undetermined("1/2") == {0, 1} and repr(tr.u("1/2")) == "(undetermined, undetermined)"
    u, y = fam.solution(v1(-2))  # one member: u0 + u1 = 2, both >= 0
    assert u[0] + u[1] == 2 and all(f.sign_at_infinity() >= 0 for f in u) and y == []
    sols = {sol.mode: sol for sol in lcs.rcp([-2])}
    assert sols[frozenset({0, 1})].unique is False and sols[frozenset({0})].unique is True
    assert "unique=False" in repr(sols[frozenset({0, 1})])
    with pytest.raises(LCSError, match="not admissible"):
        fam.solution(v1(1))


def test_tilted_inconsistent_except_at_zero():
    lcs = tilted()
    fam = family(lcs.mode({0, 1}))
    assert fam.rank == 1 and fam.pivot_rows == (0,)
    (row,), _ = fam.conditions()
    assert row == (fmpq_mat([[-1]]),)  # -x = 0
    assert not fam.consistent(v1(1)) and not fam.consistent(v1(-1)) and fam.consistent(v1(0))
    assert lcs.select_modes([1]) == modes([])
    assert lcs.select_modes([-1]) == modes([0])
    assert lcs.select_modes([0], nonautonomous="include") == modes([], [0], [1], [0, 1])
    with pytest.raises(NotAutonomous):
        lcs.select_modes([0])
    (sol,) = lcs.rcp([-1])
    assert sol.mode == {0} and sol.u == (1, 0) and sol.y == (0, 1)


def test_exact_real_states():
    lcs = twins()
    minus_e = L.expm_action([[1]], 1, [-1])  # -e
    plus_e = L.expm_action([[1]], 1, [1])
    assert lcs.select_modes(minus_e, nonautonomous="include") == modes([0], [1], [0, 1])
    assert lcs.select_modes(plus_e) == modes([])
    assert mode_admissible(lcs.mode({0, 1}), plus_e) is False


class _Oracle:
    """A stand-in state whose signs are given per form (None: cannot be certified)."""

    def __init__(self, signs):
        self.signs = signs

    def sign_of_form(self, form):
        v = self.signs.get(tuple(int(form[0, j]) for j in range(form.ncols())))
        if v is None:
            raise UnresolvedSign("cannot certify")
        return v


def test_a_certified_violation_wins_over_an_unresolved_sign():
    fam = family(tilted().mode({0, 1}))
    with pytest.raises(UnresolvedSign):
        fam.admissible(_Oracle({}))
    assert fam.admissible(_Oracle({(-1,): 1})) is False  # -x != 0: inconsistent
    fam2 = family(twins().mode({0, 1}))
    assert fam2.admissible(_Oracle({(-1,): -1})) is False


def test_elimination_is_bounded(monkeypatch):
    monkeypatch.setattr(rcpfamily, "MAX_ELIMINATION_ROWS", 0)
    lcs = twins()
    with pytest.raises(Unsupported, match="MAX_ELIMINATION_ROWS"):
        family(lcs.mode({0, 1})).admissible(v1(-1))


small = st.integers(-2, 2)


@st.composite
def systems(draw, twin: bool):
    n = draw(st.integers(1, 2))
    k = 2
    A = [[draw(small) for _ in range(n)] for _ in range(n)]
    B = [[draw(small) for _ in range(k)] for _ in range(n)]
    C = [[draw(small) for _ in range(n)] for _ in range(k)]
    D = [[draw(small) for _ in range(k)] for _ in range(k)]
    if twin:  # input 1 acts like input 0: G(s) has equal columns, modes {0, 1} are singular
        for r in B:
            r[1] = r[0]
        for r in D:
            r[1] = r[0]
    x0 = [draw(small) for _ in range(n)]
    return L.LCS(A, B, C, D), x0


@settings(max_examples=60, deadline=None)
@given(systems(twin=False))
def test_family_agrees_with_the_autonomous_path(case):
    lcs, x0 = case
    x = fmpq_mat([[v] for v in x0])
    for I in (set(), {0}, {1}, {0, 1}):
        m = lcs.mode(I)
        if m.is_autonomous:
            fam = family(m)
            assert fam.rank == len(I) and fam.free == () and fam.conditions()[0] == ()
            assert fam.admissible(x) == mode_admissible(m, x)
            assert admissibility_conditions(m)[0] == ()


@settings(max_examples=60, deadline=None)
@given(systems(twin=True))
def test_solutions_of_singular_modes_solve_rcp(case):
    """Whenever a mode that is not autonomous is declared admissible, the member shown solves
    RCP(x0) exactly: y = R x0 + G u, u_Ic = 0, y_I = 0, u, y >= 0 at s = oo."""
    lcs, x0 = case
    x = fmpq_mat([[v] for v in x0])
    G, R = lcs.G(), lcs.R()
    Rx = R.apply(x)
    for sol in lcs.rcp(x):
        u = RationalMatrix([[f] for f in sol.u])
        y = [Rx[i] + (G * u)[i, 0] for i in range(lcs.k)]
        assert list(sol.y) == y
        assert all(sol.u[i] == 0 for i in range(lcs.k) if i not in sol.mode)
        assert all(sol.y[i] == 0 for i in sol.mode)
        assert all(f.sign_at_infinity() >= 0 for f in sol.u + sol.y)
        assert sol.unique == lcs.mode(sol.mode).is_autonomous
    S = lcs.select_modes(x, "rcp", nonautonomous="include")
    assert S == {sol.mode for sol in lcs.rcp(x)}


def test_ideal_diode_bridge_runs_past_its_singular_modes():
    """The full-wave bridge without series resistances and ground resistors (notebook 04) has two
    modes that are not autonomous; away from rest they are proven inadmissible and the run goes on.
    By hand: in either half-wave the tank (C = L = 1) sees the load R = 1, so C v' = -i_L - v,
    L i_L' = v, v'' + v' + v = 0.  From v = 0, i_L = -1: v'(0) = 1, v = (2/sqrt 3) e^{-t/2}
    sin(sqrt(3) t / 2), zero again at T = 2 pi/sqrt(3), where i_L = -v'(T) = e^{-T/2}: the k-th
    event is at k T with i_L = (-1)^(k+1) e^{-k pi/sqrt(3)}."""
    ideal = L.models.circuit("C1 a b 1\nL1 a b 1\nD1 a p\nD2 b p\nD3 0 a\nD4 0 b\nR1 p 0 1")
    singular = {frozenset(c) for r in range(5) for c in combinations(range(4), r)
                if not ideal.mode(c).is_autonomous}
    assert singular == modes([0], [1, 2, 3])
    tr = L.simulate(ideal, [0, -1], 8)
    assert tr.certified and len(tr.events) == 2
    root3 = mp.sqrt(3)
    for k, e in enumerate(tr.events, 1):
        assert close(num(e.time), k * 2 * mp.pi / root3)
        assert close(num(e.state_after[1]), (-1) ** (k + 1) * mp.exp(-k * mp.pi / root3))
    # at rest, RCP has a family in mode {0} (a current circulating in the loop of diodes, a
    # floating tank potential): the state stays at rest whatever it is, so the run goes on
    rest = L.simulate(ideal, [0, 0], 1)
    assert rest.certified and rest.events == () and rest.state(1).known_rational() == fmpq_mat(2, 1)
    assert rest.undetermined(1)
