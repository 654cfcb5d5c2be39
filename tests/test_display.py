"""Reprs that paste back, names, and LaTeX (issue 9, item 6)."""
from __future__ import annotations

from fractions import Fraction as Fr

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lcs_exact import LCS, RationalFunction, RationalMatrix
from lcs_exact.errors import InvalidArgument, NotRational, ShapeError
from lcs_exact.examples import two_carts, two_carts_with_hook
from lcs_exact.modes.mode import latex_mode


def roundtrip(lcs):
    back = eval(repr(lcs), {"LCS": LCS})
    assert (back.A, back.B, back.C, back.D) == (lcs.A, lcs.B, lcs.C, lcs.D)
    assert (back.name, back.state_names, back.constraint_names) == (lcs.name, lcs.state_names, lcs.constraint_names)
    return back


def test_repr_pastes_back_rationals_exactly():
    lcs = LCS([["1/3", 0], [1, "-7/2"]], [[1], ["2/3"]], [[1, "1/10"]], [["1/3"]])
    assert "'1/3'" in repr(lcs) and "3333" not in repr(lcs)
    back = roundtrip(lcs)
    assert str(back.A[0, 0]) == "1/3" and str(back.D[0, 0]) == "1/3"


def test_repr_with_names_pastes_back():
    lcs = LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]], name="mass on a stop",
              state_names=["q", "q'"], constraint_names=["wall"])
    r = repr(lcs)
    assert "state_names=('q', \"q'\")" in r and "constraint_names=('wall',)" in r and "name='mass on a stop'" in r
    roundtrip(lcs)
    roundtrip(two_carts_with_hook())
    # default names are not printed (short reprs), and are 0-based
    plain = LCS([[1]], [[1]], [[1]], [[0]])
    assert repr(plain) == "LCS(A=[[1]], B=[[1]], C=[[1]], D=[[0]])"
    assert plain.state_names == ("x_0",) and plain.constraint_names == ("0",)


def test_names_in_str_and_latex():
    h = two_carts_with_hook()
    assert str(h) == ("two carts with hook (Example 8.3): n = 4 states (q_0, q_1, q_0', q_1'), "
                      "k = 2 complementarity pairs (stop, hook)")
    tex = h._repr_latex_()
    assert r"x = (q_{0},\ q_{1},\ q_{0}',\ q_{1}')" in tex and r"\text{stop}" in tex
    odd = LCS([[1]], [[1]], [[1]], [[0]], state_names=["v_C & 50%"])
    assert r"\text{v\_C \& 50\%}" in odd._repr_latex_()


def test_name_validation():
    args = ([[1, 0], [0, 1]], [[1], [0]], [[1, 0]], [[0]])
    with pytest.raises(ShapeError, match="state_names has 3 names, expected 2"):
        LCS(*args, state_names=["a", "b", "c"])
    with pytest.raises(InvalidArgument, match="distinct"):
        LCS(*args, state_names=["a", "a"])
    with pytest.raises(InvalidArgument, match="nonempty strings"):
        LCS(*args, state_names=["a", 2])
    with pytest.raises(InvalidArgument, match="nonempty strings"):
        LCS(*args, constraint_names=[""])
    with pytest.raises(InvalidArgument, match="sequence"):
        LCS(*args, constraint_names="stop")  # a bare string is not a sequence of names
    with pytest.raises(InvalidArgument, match="name must be a str"):
        LCS(*args, name=3)
    lcs = LCS(*args, state_names=iter(["a", "b"]))
    assert lcs.state_names == ("a", "b") and isinstance(lcs.constraint_names, tuple)


def test_latex_of_modes_escapes_braces():
    assert latex_mode({0}) == r"\{0\}" and latex_mode(()) == r"\emptyset" and latex_mode({2, 0}) == r"\{0, 2\}"
    carts = two_carts()
    assert r"I = \{0\}" in carts.mode({0})._repr_latex_()
    assert r"I = \emptyset" in carts.mode(())._repr_latex_()
    sol = carts.rcp([0, -1, -1, 0])[0]
    assert r"I = \{0\}" in sol._repr_latex_()


def test_latex_size_caps():
    n = 13
    big = LCS([[int(i == j) for j in range(n)] for i in range(n)], [[1]] + [[0]] * (n - 1),
              [[1] + [0] * (n - 1)], [[1]])
    assert big.mode(())._repr_latex_() is None  # n > 12
    assert big.rcp([0] * n)[0]._repr_latex_() is not None  # k = 1: small
    huge = LCS([[int(i == j) for j in range(21)] for i in range(21)], [[1]] + [[0]] * 20, [[1] + [0] * 20], [[1]])
    assert huge._repr_latex_() is None
    s = RationalFunction.s()
    assert RationalMatrix([[s] * 9] * 9)._repr_latex_() is None


def test_latex_size_caps_count_digits_not_only_shapes():
    """A 1 x 1 system or a degree-800 rational function is small by shape but pages of digits
    as LaTeX: _repr_latex_ gives None (Jupyter shows the repr, which still pastes back)."""
    wide = LCS([[10**4000]], [[1]], [[1]], [[0]])
    assert wide._repr_latex_() is None and eval(repr(wide), {"LCS": LCS}).A == wide.A
    assert LCS([[10**20]], [[1]], [[1]], [[0]])._repr_latex_() == (
        r"$\dot x = \left[\begin{matrix}100000000000000000000\end{matrix}\right] x + "
        r"\left[\begin{matrix}1\end{matrix}\right] u,\quad y = \left[\begin{matrix}1\end{matrix}\right] x + "
        r"\left[\begin{matrix}0\end{matrix}\right] u,\quad 0 \le y \perp u \ge 0$")
    s = RationalFunction.s()
    long = RationalFunction(1)
    for _ in range(800):
        long = long * s + 1
    assert long._repr_latex_() is None and RationalMatrix([[long]])._repr_latex_() is None
    assert eval(repr(long), {"RationalFunction": RationalFunction}) == long
    assert (s + 1)._repr_latex_() == "$s + 1$"


# --- RationalFunction: the repr evaluates --------------------------------------------------

def test_rational_function_repr_evaluates():
    f = RationalFunction("(s^2 + s + 1)/(s^2 + 1)")
    s = RationalFunction.s()
    assert f == 1 + s / (s**2 + 1)
    assert eval(repr(f)) == f
    assert RationalFunction("-1/3*s^2 - 2/7") == RationalFunction([Fr(-2, 7), 0, Fr(-1, 3)])
    assert RationalFunction("s**-2") == 1 / s**2
    assert RationalFunction("2*(s + 1)^2/(4*s)") == (s + 1) ** 2 / (2 * s)
    assert RationalFunction("0.25*s") == s / 4
    assert RationalFunction("s", 3) == s / 3
    m = RationalMatrix([[1 / (s + 1), s], [0, "1/3"]])
    assert eval(repr(m)) == m


@pytest.mark.parametrize("text", ["s+", "(s", "x", "1/0", "s^1.5", "", "s/(s - s)", "0^-1", "2 s", "s)"])
def test_rational_function_parse_errors(text):
    with pytest.raises(NotRational, match="rational function of s|empty"):
        RationalFunction(text)


small = st.fractions(min_value=-5, max_value=5, max_denominator=7)


@pytest.mark.slow
@settings(max_examples=150, deadline=None)
@given(st.lists(small, min_size=1, max_size=4), st.lists(small, min_size=1, max_size=4))
def test_repr_roundtrip_property(num, den):
    if all(c == 0 for c in den):
        den = [1]
    f = RationalFunction(num, den)
    assert eval(repr(f)) == f
    assert RationalFunction(str(f)) == f
