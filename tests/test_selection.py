"""Mode selection (section 5): RCP, LDCP_kappa, S(x0), the initial solution, regular states."""
from __future__ import annotations

from fractions import Fraction

import pytest
import sympy as sp
from helpers import carts, hook, mat, modes, vec

from lcs_exact import LCS, RationalFunction

s = RationalFunction.s()


def test_rcp_solutions_printed_in_section_7():
    c = carts()
    (sol,) = c.rcp([0, -1, -1, 0])
    assert sol.mode == {0} and sol.u[0] == 1 + s / (s**2 + 1) and sol.y[0] == 0
    (sol,) = c.rcp([0, -1, 0, 0])
    assert sol.mode == {0} and sol.u[0] == s / (s**2 + 1) and sol.is_strictly_proper
    # Example 4.5 / section 7: u(s) = 1 - s/(s^2+1) at (0,1,-1,0); y(s) = s/(s^4+3s^2+1) at (0,1,0,0)
    (sol,) = c.rcp([0, 1, -1, 0])
    assert sol.u[0] == 1 - s / (s**2 + 1)
    (sol,) = c.rcp([0, 1, 0, 0])
    assert sol.mode == frozenset() and sol.y[0] == s / (s**4 + 3 * s**2 + 1)


def test_selection_at_the_states_of_section_7():
    c = carts()
    for method in ("rcp", "ldcp", "auto"):
        assert c.select_modes([0, -1, -1, 0], method) == modes({0})
        assert c.select_modes([0, -1, 0, 0], method) == modes({0})  # Example 4.4
        assert c.select_modes([0, 0, 0, 1], method) == modes(set())  # release
        assert c.select_modes([0, 1, -1, 0], method) == modes({0})  # Example 4.5 ...
        assert c.select_modes([0, 1, 0, 0], method) == modes(set())  # ... then free (Remark 4.9)
        assert c.select_modes([0, 0, 0, 0], method) == modes(set(), {0})  # Remark 4.8


def _carts_ldcp_equations(kappa=4, n=4):
    """(5.10) for the two carts derived independently: H_i from the series of G(s) at oo."""
    S, t = sp.symbols("s t")
    G = (S**2 + 1) / (S**4 + 3 * S**2 + 1)
    ser = sp.series(G.subs(S, 1 / t), t, 0, 2 * n + kappa + 2).removeO()
    H = {i: sp.Rational(ser.coeff(t, i)) for i in range(0, 2 * n + kappa + 1)}
    eqs = {}
    for i in range(-n + 1, kappa + 1):
        eqs[i] = {j: H[i - j] for j in range(-n + 1, i + 1) if H[i - j] != 0}
    return eqs


def test_ldcp4_at_release_state():
    c = carts()
    sol = c.ldcp([0, 0, 0, 1], 4)
    want = _carts_ldcp_equations()
    got = {i: {j: Fraction(int(h[0, 0].p), int(h[0, 0].q)) for j, h in coeffs.items()}
           for i, _, coeffs in sol.equations()}
    assert got == {i: {j: Fraction(int(v.p), int(v.q)) for j, v in d.items()} for i, d in want.items()}
    # constants C A^{i-1} x0: zero except y^4 = 1 + ... (section 7)
    consts = {i: vec(cst)[0] for i, cst, _ in sol.equations()}
    assert consts == {-3: 0, -2: 0, -1: 0, 0: 0, 1: 0, 2: 0, 3: 0, 4: 1}
    assert "y^4 = 1 + u^2 - 2*u^0 + 5*u^-2" in sol.equations_text()
    # u = 0 and y = (0, ..., 0, 1) >= 0 lexicographically: S^4 = {∅}
    assert all(vec(sol.u[j]) == [0] for j in range(-3, 5))
    assert [vec(sol.y[i])[0] for i in range(-3, 5)] == [0, 0, 0, 0, 0, 0, 0, 1]
    assert sol.modes == modes(set()) and sol.active == frozenset()
    assert sol.undetermined == {(0, 3), (0, 4)}  # u^{kappa-eta+1..kappa} free (Theorem 6.9)


def test_ldcp_impulse_at_impact():
    # at (0,-1,-1,0): u(s) = 1 + s/(s^2+1) = 1 + s^-1 - s^-3 + ...: u^0 = 1 (a delta), u^1 = 1
    sol = carts().ldcp([0, -1, -1, 0], 4)
    assert sol.active == {0}
    assert [vec(sol.u[j])[0] for j in range(-3, 3)] == [0, 0, 0, 1, 1, 0]
    assert all(vec(sol.y[i]) == [0] for i in range(-3, 5))
    assert vec(sol.impulse[0]) == [1] and vec(sol.impulse[1]) == [0]


def test_initial_solution_and_jump_3_8():
    c = carts()
    init = c.initial_solution([0, -1, -1, 0])
    assert init.mode == {0} and not init.smooth
    assert vec(init.impulse[0]) == [1]  # u_imp = delta
    assert vec(init.state_after) == [0, -1, 0, 0]  # x0 + B * 1 = P_{1} x0
    init = c.initial_solution([0, 1, -1, 0])
    assert vec(init.state_after) == [0, 1, 0, 0]
    assert c.select_modes(vec(init.state_after)) == modes(set())
    init = c.initial_solution([0, 0, 0, 0])
    assert init.mode == frozenset() and init.modes == modes(set(), {0}) and init.smooth


def test_regular_states_theorem_6_8():
    c = carts()
    assert c.is_regular([0, -1, 0, 0]) and c.is_regular([1, -5, -7, 0]) and c.is_regular([0, 0, 3, 0])
    assert not c.is_regular([0, -1, -1, 0]) and not c.is_regular([-1, 0, 0, 0])


def test_hook_section_8():
    h = hook()
    # unconstrained arrival at (0,0,-1,2): the hook mode, not {1,2} as in [28]
    assert h.select_modes([0, 0, -1, 2]) == modes({1})
    assert vec(h.initial_solution([0, 0, -1, 2]).state_after) == [0, 0, Fraction(1, 2), Fraction(1, 2)]
    # (0,0,-2,1): both constraints, jump to the origin
    assert h.select_modes([0, 0, -2, 1]) == modes({0, 1})
    assert vec(h.initial_solution([0, 0, -2, 1]).state_after) == [0, 0, 0, 0]
    # discontinuity: (eps, eps, -2, 1) hook first, (0, -eps, -2, 1) stop first
    eps = Fraction(1, 100)
    assert h.select_modes([eps, eps, -2, 1]) == modes({1})
    assert vec(h.initial_solution([eps, eps, -2, 1]).state_after) == [eps, eps, Fraction(-1, 2), Fraction(-1, 2)]
    assert h.select_modes([0, -eps, -2, 1]) == modes({0})
    assert vec(h.initial_solution([0, -eps, -2, 1]).state_after) == [0, -eps, 0, 1]


def test_hook_stop_mode_rcp_formula():
    # section 8: in the stop mode u1(s) = -x30 - x40/(s^2+1); the mode needs x30 <= 0, x40 <= 0
    h = hook()
    x3, x4 = Fraction(-3), Fraction(-2, 5)
    sols = {sol.mode: sol for sol in h.rcp([0, 0, x3, x4])}
    assert set(sols) == {frozenset({0})}
    assert sols[frozenset({0})].u[0] == -x3 - x4 / (s**2 + 1)
    assert frozenset({0}) not in h.select_modes([0, 0, -3, Fraction(1, 5)])


def test_select_modes_methods_validate():
    with pytest.raises(ValueError, match="method"):
        carts().select_modes([0, 0, 0, 0], "simplex")


def test_mode_sets_are_exact_for_the_origin_k2():
    assert hook().select_modes([0, 0, 0, 0]) == modes(set(), {0}, {1}, {0, 1})
    assert mat(hook().mode({0, 1}).projection()) == [[0] * 4 for _ in range(4)]


def test_exact_real_states_are_decided_like_rational_ones():
    """x' = u, y = x - u: from x0 > 0 both modes are admissible (y(s) = x0/s in mode ∅, u(s) =
    x0/(s - 1) in mode {0}), from x0 < 0 neither.  x0 = ±(sqrt(2) - 1) (a SymPy closed form)
    is decided through its exact sign, as 1 and -1 are."""
    lcs = LCS([[0]], [[1]], [[1]], [[-1]])
    both = {frozenset(), frozenset({0})}
    assert lcs.select_modes([1]) == both and lcs.select_modes([-1]) == set()
    assert lcs.select_modes([sp.sqrt(2) - 1]) == both and lcs.select_modes([1 - sp.sqrt(2)]) == set()


def test_ldcp_with_two_relative_degrees_is_the_laurent_series_of_the_rcp():
    """Constraints of relative degree 1 (y_0 = p, p' = q + u_0) and 2 (y_1 = q, q'' = p + u_1):
    eta = (1, 2), N = I.  From x0 = (-1, -1, -1) both are violated: mode {0, 1}, whose inputs
    u_I(s) = -G_II(s)^{-1} C (sI - A)^{-1} x0 are computed here with SymPy; every determined
    coefficient u_l^j (of s^-j, j <= kappa - eta_l) of LDCP_kappa equals that series'."""
    A = [[0, 1, 0], [0, 0, 1], [1, 0, 0]]
    B = [[0, 0], [0, 1], [1, 0]]
    C = [[0, 0, 1], [1, 0, 0]]
    lcs = LCS(A, B, C, [[0, 0], [0, 0]])
    assert tuple(lcs.leading_column_indices()) == (1, 2)
    x0 = [-1, -1, -1]
    kappa = 5
    sol = lcs.ldcp(x0, kappa)
    S, t = sp.symbols("s t")
    R = (S * sp.eye(3) - sp.Matrix(A)).inv()
    G = sp.Matrix(C) * R * sp.Matrix(B)
    u = -(G.inv() * sp.Matrix(C) * R * sp.Matrix(x0))
    want = {}
    for l in range(2):
        ser = sp.series(sp.simplify(u[l].subs(S, 1 / t)), t, 0, kappa + 1).removeO()
        for j in range(-2, kappa + 1):
            want[l, j] = sp.Rational(sp.expand(ser).coeff(t, j))  # u^j: the coefficient of s^-j = t^j
    assert sol.active == {0, 1}
    for l, eta in ((0, 1), (1, 2)):
        for j in range(-2, kappa - eta + 1):
            got = sol.u[j][l, 0]
            assert Fraction(int(got.p), int(got.q)) == Fraction(int(want[l, j].p), int(want[l, j].q)), (l, j)
    assert any(want[1, j] != 0 for j in range(-2, 1))  # an impulse in u_1: the test sees the earlier stages
