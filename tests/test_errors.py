"""errors.py: the exception tree, and that each error is raised where it should be with a message
that names the object and the reason (DESIGN.md sections 3-5).  Also the CLI's exit codes."""
from __future__ import annotations

import json

import pytest
from flint import fmpq_mat
from helpers import F, carts, modes, vec

import lcs_exact
from lcs_exact import (LCS, Deadlock, IllPosed, LCSError, LimitExceeded, NotAutonomous, NotRational,
                       ShapeError, UnresolvedSign, ZenoDetected)
from lcs_exact.cli import main

A2 = [[0, 1], [0, 0]]


# ---------------------------------------------------------------------------------------------
# the tree
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("cls, bases, not_bases", [
    (ShapeError, (LCSError, ValueError), (TypeError,)),
    (NotRational, (LCSError, TypeError), (ValueError,)),
    (NotAutonomous, (LCSError, ValueError), (TypeError,)),
    (IllPosed, (LCSError, ValueError), (TypeError,)),
    (Deadlock, (LCSError,), (ValueError, TypeError, ArithmeticError)),
    (ZenoDetected, (LCSError,), (ValueError, TypeError, ArithmeticError)),
    (UnresolvedSign, (LCSError, ArithmeticError), (ValueError,)),
    (LimitExceeded, (LCSError,), (ValueError, TypeError, ArithmeticError)),
    (LCSError, (Exception,), (ValueError, TypeError)),
])
def test_error_classes_and_bases(cls, bases, not_bases):
    assert all(issubclass(cls, b) for b in bases)
    assert not any(issubclass(cls, b) for b in not_bases)
    e = cls("what went wrong")
    assert str(e) == "what went wrong" and e.trajectory is None
    marker = object()
    assert cls("partial run", trajectory=marker).trajectory is marker
    assert cls.__name__ in lcs_exact.__all__ and getattr(lcs_exact, cls.__name__) is cls
    with pytest.raises(LCSError, match="^caught through the root$"):
        raise cls("caught through the root")


# ---------------------------------------------------------------------------------------------
# LCS construction
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("args, pattern", [
    (([[0, 1, 2], [0, 0, 0]], [[1], [0]], [[1, 0]], [[0]]), r"A must be a nonempty square matrix, got shape 2x3"),
    (([], [[1]], [[1]], [[0]]), r"A must be a nonempty square matrix, got shape 0x0"),
    ((A2, [[1], [0], [1]], [[1, 0]], [[0]]), r"B has shape 3x1, expected 2x\?"),
    ((A2, [[1], [0]], [[1, 0, 0]], [[0]]), r"C has shape 1x3, expected 1x2"),
    ((A2, [[1, 0], [0, 1]], [[1, 0]], [[0, 0], [0, 0]]), r"C has shape 1x2, expected 2x2"),
    ((A2, [[1], [0]], [[1, 0]], [[0, 0]]), r"D has shape 1x2, expected 1x1"),
    ((A2, [[1, 0], [0, 1]], [[1, 0], [0, 1]], [[0, 0]]), r"D has shape 1x2, expected 2x2"),
    ((A2, [[1], [0]], [[1, 0]], [[0], [0]]), r"D has shape 2x1, expected 1x1"),
    (([[0, 1], [0]], [[1], [0]], [[1, 0]], [[0]]), r"A has rows of different lengths \[1, 2\]"),
    (([[0]], [[]], [[1]], [[0]]), r"B has no columns"),
])
def test_lcs_wrong_shapes(args, pattern):
    with pytest.raises(ShapeError, match=pattern):
        LCS(*args)


@pytest.mark.parametrize("args, where", [
    (([[0, "x"], [0, 0]], [[1], [0]], [[1, 0]], [[0]]), "A[0, 1]"),
    ((A2, [[1], [None]], [[1, 0]], [[0]]), "B[1, 0]"),
    ((A2, [[1], [0]], [[1, float("nan")]], [[0]]), "C[0, 1]"),
    ((A2, [[1], [0]], [[1, 0]], [[1j]]), "D[0, 0]"),
    ((A2, [[1], [0]], [[1, 0]], [[True]]), "D[0, 0]"),
])
def test_lcs_non_rational_entries_name_the_position(args, where):
    with pytest.raises(NotRational) as ei:
        LCS(*args)
    assert where in str(ei.value)


def test_lcs_accepts_the_documented_inputs():
    # floats by shortest repr, strings, and the k = 1 shorthand (flat B, C and a scalar D)
    lcs = LCS([[0, 1], [0, 0]], [0, 1], [1, 0], "1/2")
    assert (lcs.n, lcs.k) == (2, 1)
    assert vec(lcs.B) == [0, 1] and vec(lcs.C) == [1, 0] and F(lcs.D[0, 0]) == F("1/2")
    assert F(LCS([[0.1]], [[1]], [[1]], [[0]]).A[0, 0]) == F("1/10")


# ---------------------------------------------------------------------------------------------
# modes and leading matrices
# ---------------------------------------------------------------------------------------------

def test_mode_index_out_of_range():
    c = carts()
    with pytest.raises(ShapeError, match=r"mode \{1\} has indices \[1\] outside 0\.\.0"):
        c.mode({1})
    with pytest.raises(ShapeError, match=r"\[-1\]"):
        c.mode([-1])
    with pytest.raises(ShapeError, match="set of constraint indices"):
        c.mode(5)


def zero_G():
    # x' = u, y = 0 x + 0 u: G(s) = 0 * 1/s * 1 + 0 = 0 identically, R(s) = 0
    return LCS([[0]], [[1]], [[0]], [[0]])


def test_leading_matrices_undefined_when_G_has_a_zero_row():
    lcs = zero_G()
    with pytest.raises(IllPosed, match=r"row 0 of G\(s\) is identically zero") as ei:
        lcs.leading_row_matrix()
    assert isinstance(ei.value, ValueError)
    with pytest.raises(IllPosed, match=r"column 0 of G\(s\) is identically zero"):
        lcs.leading_column_matrix()
    wp = lcs.well_posedness()
    assert not wp and wp.M is None and wp.N is None
    assert any("row 0 of G(s)" in r for r in wp.reasons)
    # a 2 x 2 example where only the second row vanishes: y2 = 0 * x + 0 * u
    two = LCS([[0, 0], [0, 0]], [[1, 0], [0, 1]], [[1, 0], [0, 0]], [[0, 0], [0, 0]])
    with pytest.raises(IllPosed, match=r"row 1 of G\(s\)"):
        two.leading_row_matrix()


def test_non_autonomous_mode_V_and_T_intersect():
    # mode {0}: y = 0 always holds, so V_{0} = Q^1; an impulse in u jumps x freely, so T_{0} = Q^1:
    # V ∩ T != {0}, and det G_II(s) = 0 (Lemma 3.3)
    lcs = zero_G()
    m = lcs.mode({0})
    assert m.is_autonomous is False
    assert m.consistent_subspace().ncols() == 1 and m.jump_space().ncols() == 1
    assert "V_I ∩ T_I" in m.autonomy_reason and "G_II(s) is singular" in m.autonomy_reason
    with pytest.raises(NotAutonomous) as ei:
        m.projection()
    msg = str(ei.value)
    assert "mode {0}" in msg and "not autonomous" in msg and "G_II(s) is singular" in msg
    with pytest.raises(NotAutonomous, match="not autonomous"):
        m.feedback()
    assert lcs.mode(set()).is_autonomous is True
    # mode {0} is admissible at x0 = 1 (any u >= 0 keeps y = 0): RCP(x0) has a family of solutions
    # there, the initial solution is not unique, and selection refuses (Assumption 4.1) ...
    with pytest.raises(NotAutonomous, match=r"mode \{0\} is not autonomous") as ei:
        lcs.select_modes([1])
    assert "not unique" in str(ei.value) and "nonautonomous='include'" in str(ei.value)
    # ... unless asked for S_RCP(x0) itself (5.5): y(s) = 0 in mode ∅, u(s) = any v >= 0 in {0}
    assert lcs.select_modes([1], nonautonomous="include") == modes([], [0])


def test_non_autonomous_mode_input_not_determined():
    # B = 0, D = 0: u does not act at all, Ker[B_I; D_II] = Q^1
    lcs = LCS([[0]], [[0]], [[1]], [[0]])
    m = lcs.mode({0})
    assert not m.is_autonomous
    with pytest.raises(NotAutonomous, match=r"not autonomous \(Ker\[B_I; D_II\] != \{0\}.*state is not determined"):
        m.projection()


# ---------------------------------------------------------------------------------------------
# mode selection
# ---------------------------------------------------------------------------------------------

def deadlock_system():
    """x' = u, y = x - u.

    (sI - A)^{-1} = 1/s, so G(s) = 1/s - 1 = (1 - s)/s and R(s) = 1/s.
      mode ∅:   u = 0, y(s) = R x0 = x0/s                      admissible iff x0 >= 0;
      mode {0}: y = 0, u(s) = -G^{-1} R x0 = -(s/(1 - s)) x0/s = x0/(s - 1)
                = x0 (s^-1 + s^-2 + ...)                      admissible iff x0 >= 0.
    Hence S(x0) = ∅ for x0 < 0: a deadlock.  (H_0 = D = -1, so N = M = [-1] is not a P-matrix.)
    """
    return LCS([[0]], [[1]], [[1]], [[-1]])


def test_deadlock_example_by_hand():
    lcs = deadlock_system()
    assert lcs.select_modes([-1]) == set()
    assert lcs.select_modes(["-1/3"], method="rcp") == set()
    assert lcs.select_modes([1]) == modes([], [0])
    assert lcs.select_modes([0]) == modes([], [0])
    sols = {tuple(sorted(sol.mode)): sol for sol in lcs.rcp([1])}
    assert set(sols) == {(), (0,)}
    assert str(sols[()].y[0]) == "1/s" and sols[()].u[0] == 0
    assert str(sols[(0,)].u[0]) == "1/(s - 1)" and sols[(0,)].y[0] == 0


def test_initial_solution_deadlock():
    lcs = deadlock_system()
    with pytest.raises(Deadlock) as ei:
        lcs.initial_solution([-1])
    assert "S(x0) is empty" in str(ei.value) and "(-1)" in str(ei.value)
    assert ei.value.trajectory is None
    # x0 = 1 is fine: the smallest mode ∅, smooth (y(s) = 1/s has no impulse)
    init = lcs.initial_solution([1])
    assert init.mode == frozenset() and init.smooth


def test_ldcp_needs_N_to_be_a_P_matrix():
    lcs = deadlock_system()
    with pytest.raises(IllPosed) as ei:
        lcs.ldcp([1], 1)
    assert "P-matrix" in str(ei.value) and "N" in str(ei.value)
    with pytest.raises(IllPosed, match="P-matrix"):
        lcs.select_modes([1], method="ldcp")
    with pytest.raises(IllPosed, match="P-matrix"):
        zero_G().ldcp([1])
    with pytest.raises(ValueError, match="kappa"):
        carts().ldcp([0, 0, 0, 1], -10)


def test_select_modes_bad_arguments():
    c = carts()
    with pytest.raises(ShapeError, match="x0 has length 3, expected 4"):
        c.select_modes([0, 1, 0])
    with pytest.raises(ShapeError):
        c.select_modes(fmpq_mat([[0, 1], [0, 0]]))
    with pytest.raises(ShapeError):
        c.initial_solution([0, 1, 0, 0, 0])
    with pytest.raises(ValueError, match="bogus"):
        c.select_modes([0, -1, -1, 0], method="bogus")
    with pytest.raises(NotRational, match=r"x0\[1\]"):
        c.select_modes([0, "one", 0, 0])


# ---------------------------------------------------------------------------------------------
# CLI
# ---------------------------------------------------------------------------------------------

CARTS_MODEL = {"A": [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]],
               "B": [[0], [0], [1], [0]], "C": [[1, 0, 0, 0]], "D": [[0]], "name": "two carts"}


def test_cli_two_carts(capsys):
    assert main(["two-carts", "--digits", "10"]) == 0
    out = capsys.readouterr().out
    assert "WELL-POSED" in out and "NOT ESTABLISHED" not in out
    assert "H_0, H_1, H_2 = 0, 0, 1" in out                      # section 7
    assert "P_I x0 = (0, -1, 0, 0)" in out                        # P_{1} (0,-1,-1,0), section 7


def test_cli_select_json(tmp_path, capsys):
    path = tmp_path / "carts.json"
    path.write_text(json.dumps(CARTS_MODEL))
    assert main(["select", str(path), "--x0", "0,-1,-1,0"]) == 0
    out = capsys.readouterr().out
    # S(x0) = {{0}}; u(s) = -G^{-1} R x0 with G = (s^2+1)/chi, R x0 = -(s + s^2 + 1)/chi (7.1):
    # u(s) = (s^2 + s + 1)/(s^2 + 1); the jump is x(0+) = P_{1} x0 = (0, -1, 0, 0)
    assert "S(x0) = {{0}}" in out
    assert "u(s) = ((s^2 + s + 1)/(s^2 + 1))" in out
    assert "(0, -1, 0, 0)" in out


def test_cli_select_toml_and_deadlock(tmp_path, capsys):
    path = tmp_path / "deadlock.toml"
    path.write_text('A = [[0]]\nB = [[1]]\nC = [[1]]\nD = [["-1"]]\nx0 = [1]\n')
    assert main(["select", str(path)]) == 0          # x0 from the file
    out = capsys.readouterr().out
    assert "RCP in mode {0}: u(s) = (1/(s - 1))" in out and "y(s) = (1/s)" in out
    assert main(["select", str(path), "--x0", "-1"]) == 2
    cap = capsys.readouterr()
    assert "S(x0) is empty" in cap.err and cap.err.strip().count("\n") == 0


def test_cli_model_missing_D(tmp_path, capsys):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({k: v for k, v in CARTS_MODEL.items() if k != "D"}))
    assert main(["select", str(path), "--x0", "0,-1,-1,0"]) == 2
    cap = capsys.readouterr()
    err = cap.err.strip()
    assert err.count("\n") == 0 and "lacks D" in err and err.startswith("lcs-exact: error:")
    assert cap.out == ""


@pytest.mark.parametrize("model, x0, fragment", [
    ({**CARTS_MODEL, "A": [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, "x"]]}, "0,0,0,0", "A[3, 3]"),
    ({**CARTS_MODEL, "C": [[1, 0, 0]]}, "0,0,0,0", "C has shape 1x3, expected 1x4"),
    (CARTS_MODEL, "0,1", "x0 has length 2, expected 4"),
    (CARTS_MODEL, None, "no initial state"),
])
def test_cli_bad_input_exit_2(tmp_path, capsys, model, x0, fragment):
    path = tmp_path / "m.json"
    path.write_text(json.dumps(model))
    argv = ["select", str(path)] + (["--x0", x0] if x0 else [])
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert fragment in err and err.count("\n") == 0


def test_cli_missing_file(tmp_path, capsys):
    assert main(["select", str(tmp_path / "nope.json"), "--x0", "0"]) == 2
    assert capsys.readouterr().err.strip().count("\n") == 0
