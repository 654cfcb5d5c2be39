"""The results in the users' ecosystem (issue 16; DESIGN.md section 7): NumPy arrays, pandas data
frames, CSV/NPZ files, python-control systems, a progress bar, and the testing helper.  The values
are checked against the exact states (certified balls), not against themselves."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pandas as pd
import control  # in the test extra: a missing python-control is a broken environment, not a skip
import pytest
from flint import fmpq
from helpers import mat

import lcs_exact as L
from lcs_exact import LCS, simulate
from lcs_exact.examples import bouncing_ball, diode_bridge_cap_filter, two_carts
from lcs_exact.testing import assert_matches_fixture


@pytest.fixture(scope="module")
def carts_run():
    return simulate(two_carts(), [0, 1, -1, 0], 3)


def test_to_numpy_against_the_exact_states(carts_run):
    t = [0, 0.5, "3/2", fmpq(2)]
    X = carts_run.to_numpy(t)
    assert X.shape == (4, 4) and X.dtype == np.float64
    for row, tq in zip(X, t):
        exact = carts_run.state(L.rational.to_fmpq(tq)).ball(30)
        assert all(abs(v - float(b.mid())) <= 2e-16 * max(1.0, abs(v)) for v, b in zip(row, exact))
    assert X[0].tolist() == [0.0, 1.0, 0.0, 0.0]  # x(0+): the jump of Example 4.5
    XU = carts_run.to_numpy(t, u=True, y=True)
    assert XU.shape == (4, 6) and XU[:, 5].tolist() == X[:, 0].tolist()  # y = x_0
    A, B, C, D = two_carts().to_numpy()
    assert A.tolist() == [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]] and D.shape == (1, 1)


def test_to_pandas_and_files(carts_run, tmp_path):
    df = carts_run.to_pandas([0, 1, 2], u=True)
    assert list(df.columns) == ["q_0", "q_1", "q_0'", "q_1'", "force (stop)"]
    assert df.index.name == "t" and df.index.tolist() == [0.0, 1.0, 2.0]
    assert df.loc[0.0, "q_1"] == 1.0
    csv = tmp_path / "carts.csv"
    carts_run.to_csv(csv, [0, 0.25, 0.5])
    from lcs_exact.verify.compare import read_solution_csv
    t, X = read_solution_csv(csv)  # the format lcs-exact compare reads
    assert t == ["0.0", "0.25", "0.5"] and len(X[0]) == 4
    npz = tmp_path / "carts.npz"
    carts_run.to_npz(npz, [0, 1])
    data = np.load(npz)
    assert data["x"].shape == (2, 4) and data["names"].tolist() == ["q_0", "q_1", "q_0'", "q_1'"]
    assert np.array_equal(data["x"], carts_run.to_numpy([0, 1]))


def test_undetermined_inputs_are_nan():
    bridge = diode_bridge_cap_filter()
    tr = simulate(bridge, [10, 0, 0], fmpq(1, 5000))
    free = [p for p in tr.phases if p.undetermined]
    t = L.balls.dyadic((free[0].t0.ball(20) + free[0].t1.ball(20)) / 2) if free else None
    assert t is not None
    row = tr.to_numpy([t], u=True)[0]
    j = min(free[0].undetermined)
    assert np.isnan(row[3 + j]) and not np.isnan(row[:3]).any()


@pytest.mark.slow
def test_from_statespace_reads_python_control_exactly():
    sys = control.ss([[0, 1], [-2.5, -0.1]], [[0], [1]], [[1, 0]], [[0]])
    lcs = LCS.from_statespace(sys, constraint_names=["stop"])
    assert lcs.A[1, 0] == fmpq(-5, 2) and lcs.A[1, 1] == fmpq(-1, 10)  # shortest decimals, exact
    assert lcs.constraint_names == ("stop",) and lcs.n == 2
    tr = simulate(lcs, [1, 0], 3)
    assert tr.certified and len(tr.events) >= 1
    with pytest.raises(L.ShapeError, match="pairs each input"):
        LCS.from_statespace(control.ss([[0]], [[1, 1]], [[1]], [[0, 0]]))


def test_progress_bar(capsys):
    ball = bouncing_ball()
    tr = simulate(ball, ball.embed([1, 0]), 10, progress=True)
    err = capsys.readouterr().err
    assert "simulate" in err and "of 10" in err and tr.certified
    with pytest.raises(L.InvalidArgument, match="progress"):
        simulate(ball, ball.embed([1, 0]), 1, progress="yes")


def test_assert_matches_fixture_names_the_worst_point(carts_run, tmp_path):
    fx = carts_run.to_fixture(20, sample="1/4")
    t = [0.25, 0.5, 0.75, 1.3, 2, 2.5, 3]  # to t_end = 3: a solution that stops early fails (below)
    X = carts_run.to_numpy(t)
    assert_matches_fixture(fx, t, X, atol=1e-12, event_tol=0.1)  # the exact solution passes
    X[2, 1] += 3e-4
    X[1, 3] += 1e-4
    with pytest.raises(AssertionError) as err:
        assert_matches_fixture(fx, t, X, atol=1e-6, event_tol=0.1)
    msg = str(err.value)
    assert "t = 0.75" in msg and "component q_1" in msg and "exact 0." in msg  # the worst of the two
    path = tmp_path / "fx.json"
    path.write_text(__import__("json").dumps(fx))
    assert_matches_fixture(str(path), t, carts_run.to_numpy(t), atol=1e-12, event_tol=0.1)  # from a file too
    with pytest.raises(L.ShapeError, match="rows"):
        assert_matches_fixture(fx, t, X[:2])
    with pytest.raises(AssertionError, match=r"ends at t = 1\.3, before the reference's last time 3"):
        assert_matches_fixture(fx, t[:4], carts_run.to_numpy(t[:4]), atol=1e-12, event_tol=0.1)


# --- python-control: the linear part and time responses --------------------------------------

OSC = dict(A=[[0, 1], [-1, 0]], B=[[0], [1]], C=[[1, 0]], D=[[0]])  # x'' = -x + u, a stop y = x >= 0


def test_to_statespace_names_and_floats():
    ss = LCS(**OSC).to_statespace()
    assert isinstance(ss, control.StateSpace)
    assert (ss.state_labels, ss.input_labels, ss.output_labels) == (["x_0", "x_1"], ["u_0"], ["y_0"])
    assert ss.A.tolist() == [[0.0, 1.0], [-1.0, 0.0]] and ss.B.tolist() == [[0.0], [1.0]]
    assert ss.C.tolist() == [[1.0, 0.0]] and ss.D.tolist() == [[0.0]]
    named = LCS(**OSC, name="oscillator", state_names=["q", "v"], constraint_names=["stop"]).to_statespace()
    assert (named.name, named.state_labels, named.input_labels, named.output_labels) == \
        ("oscillator", ["q", "v"], ["u (stop)"], ["y (stop)"])
    # the builder's words when it gave roles: the names of to_pandas and of the plots
    carts = two_carts().to_statespace()
    assert (carts.input_labels, carts.output_labels) == (["force (stop)"], ["gap (stop)"])
    assert carts.state_labels == ["q_0", "q_1", "q_0'", "q_1'"]
    # 1/3 is not a float: the nearest float64, as Fraction's correctly rounded division gives it
    third = LCS([["1/3"]], [[1]], [[1]], [[0]]).to_statespace()
    assert third.A[0, 0] == 1 / 3 and np.float64(third.A[0, 0]).hex() == (1 / 3).hex()


def test_statespace_round_trip_is_exact_for_decimal_data():
    """Decimal entries of at most 15 significant digits: the float64 nearest each has that
    decimal as its shortest repr, which from_statespace reads back: the same exact rationals."""
    data = dict(A=[["0.1", "-2.5", "123.456"], ["1e-3", "-0.3", "7"], ["0", "1.5e7", "-0.125"]],
                B=[["0.3", "1"], ["-7", "0"], ["0.05", "2.75"]], C=[["1/4", "0.2", "0"], ["0", "0", "-1.1"]],
                D=[["0.01", "0"], ["0", "3"]])
    for names in (dict(), dict(state_names=["a", "b", "c"], constraint_names=["left", "right"], name="three")):
        lcs = LCS(**data, **names)
        back = LCS.from_statespace(lcs.to_statespace())
        for key, rows in data.items():
            assert mat(getattr(back, key)) == [[Fraction(e) for e in row] for row in rows], key
        assert back.state_names == lcs.state_names and back.constraint_names == lcs.constraint_names
    # roles (the builder's words) give the pairs' names back: "force (stop)" and "gap (stop)" share "stop",
    # the diodes' "-v(D1)" and "i(D1)" share "D1" (the bridge's data are not all decimal: names only)
    for lcs in (two_carts(), diode_bridge_cap_filter()):
        back = LCS.from_statespace(lcs.to_statespace())
        assert (back.state_names, back.constraint_names) == (lcs.state_names, lcs.constraint_names)
        assert back.roles is None
    assert all(getattr(LCS.from_statespace(two_carts().to_statespace()), m) == getattr(two_carts(), m) for m in "ABCD")


def test_an_entry_beyond_float64_is_named_not_infinite():
    """10^400 has no float64 (the largest is (2 - 2^-52) 2^1023 < 10^309): to_numpy and
    to_statespace refuse it by name (it was a bare OverflowError); 2^1023 and 10^-400 round."""
    huge = LCS([[0, 1], [10**400, 0]], [[0], [1]], [[1, 0]], [[0]])
    with pytest.raises(L.InvalidArgument, match=r"A has an entry 1000.* beyond the range of float64"):
        huge.to_numpy()
    with pytest.raises(L.InvalidArgument, match="beyond the range of float64"):
        huge.to_statespace()
    A = LCS([[2**1023]], [[fmpq(1, 10**400)]], [[1]], [[0]]).to_numpy()
    assert A[0].tolist() == [[2.0**1023]] and A[1].tolist() == [[0.0]]


def test_from_statespace_reads_python_controls_default_names_as_no_names():
    lcs = LCS.from_statespace(control.ss(OSC["A"], OSC["B"], OSC["C"], OSC["D"]))  # x[0], u[0], y[0]
    assert lcs.state_names == ("x_0", "x_1") and lcs.constraint_names == ("0",)
    own = LCS.from_statespace(control.ss(OSC["A"], OSC["B"], OSC["C"], OSC["D"], inputs=["push"], outputs=["gap"]))
    assert own.constraint_names == ("push",)  # no shared "(name)": the input's label, as before


def test_without_python_control_the_error_says_what_to_install(monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "control", None)  # import control now fails
    with pytest.raises(ModuleNotFoundError, match=r"to_statespace needs python-control: pip install control"):
        LCS(**OSC).to_statespace()
    with pytest.raises(ModuleNotFoundError, match=r"to_control needs python-control"):
        simulate(LCS(**OSC), [1, 0], 1).to_control([0])


def _close(got, want, what):
    """float64 values of certified numbers: within a few ulps of the exact value (mpmath, 50 digits)."""
    import mpmath as mp
    assert len(got) == len(want), what
    for g, w in zip(got, want):
        assert abs(mp.mpf(float(g)) - w) <= 4e-16 * max(1, abs(w)), (what, g, w)


def test_to_control_oscillator_against_its_closed_form():
    """From (1, 0): x = (cos t, -sin t), u = 0, y = cos t until y reaches 0 at pi/2 (x = (0, -1));
    the stop resets the velocity (an impulse: u is a delta there, no function value), so x = 0
    from pi/2 on, and the smallest mode at 0 is the free one: u = 0, y = x_0 = 0."""
    import mpmath as mp
    mp.mp.dps = 50
    tr = simulate(LCS(**OSC), [1, 0], 4)
    ts = [0, Fraction(1, 2), 1, Fraction(3, 2), 2, 3, 4]
    r = tr.to_control(ts)
    assert isinstance(r, control.TimeResponseData) and r.issiso and r.success
    assert r.time.tolist() == [float(t) for t in ts]
    assert (r.state_labels, r.input_labels, r.output_labels) == (["x_0", "x_1"], ["u_0"], ["y_0"])
    assert r.states.shape == (2, 7) and r.inputs.shape == r.outputs.shape == (7,)
    tm = [mp.mpf(t.numerator) / t.denominator if isinstance(t, Fraction) else mp.mpf(t) for t in ts]
    before = [t < mp.pi / 2 for t in tm]
    _close(r.states[0], [mp.cos(t) if b else 0 for t, b in zip(tm, before)], "x_0")
    _close(r.states[1], [-mp.sin(t) if b else 0 for t, b in zip(tm, before)], "x_1")
    _close(r.inputs, [0] * 7, "u")
    _close(r.outputs, [mp.cos(t) if b else 0 for t, b in zip(tm, before)], "y")


def test_to_control_section7_input_is_cos_of_t_minus_1():
    """Section 7: the carts from x0 = e^{-A} (0, -1, -1, 0) reach the stop at t = 1 with
    x = (0, -1, -1, 0); the impact stops cart 0: x(1+) = (0, -1, 0, 0).  In contact (q0 = v0 = 0)
    q1'' = q0 - q1 = -q1 from (-1, 0): q1 = -cos(t - 1), v1 = sin(t - 1), and v0' = -2 q0 + q1 + u = 0
    gives u = cos(t - 1) > 0, y = q0 = 0, until u reaches 0 at 1 + pi/2.  At t = 1 itself the row
    holds the right limits: x(1+), u(1+) = cos 0 = 1, y = 0 (u(1-) = 0 before the impact)."""
    import mpmath as mp
    from helpers import A_CARTS, carts
    mp.mp.dps = 50
    tr = simulate(carts(), L.expm_action(A_CARTS, -1, [0, -1, -1, 0]), 3)
    ts = [1, Fraction(5, 4), Fraction(3, 2), 2, Fraction(5, 2)]  # 5/2 < 1 + pi/2 = 2.5707...
    r = tr.to_control(ts)
    s = [mp.mpf(Fraction(t).numerator) / Fraction(t).denominator - 1 for t in ts]
    _close(r.inputs, [mp.cos(v) for v in s], "u = cos(t - 1)")
    _close(r.outputs, [0] * len(ts), "y")
    for i, want in enumerate(([0] * len(ts), [-mp.cos(v) for v in s], [0] * len(ts), [mp.sin(v) for v in s])):
        _close(r.states[i], want, f"x_{i}")
    assert float(r.inputs[0]) == 1.0 and tr.u(Fraction(999, 1000))[0].ball(20).contains(0)


def test_to_control_multi_input_multi_output():
    """Two independent stops (k = 2): x1'' = -x1 + u1 and x3'' = -4 x3 + u2, y = (x1, x3), from
    (1, 0, 1, 0): x1 = cos t until pi/2, x3 = cos 2t (v = -2 sin 2t) until pi/4; each stop then
    resets its velocity and holds 0.  Inputs and outputs are 2 x len(t) (python-control refuses
    to guess whether such data are SISO)."""
    import mpmath as mp
    mp.mp.dps = 50
    lcs = LCS([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, -4, 0]], [[0, 0], [1, 0], [0, 0], [0, 1]],
              [[1, 0, 0, 0], [0, 0, 1, 0]], [[0, 0], [0, 0]], constraint_names=["slow", "fast"])
    tr = simulate(lcs, [1, 0, 1, 0], 3)
    ts = [0, Fraction(1, 2), 1, 2, 3]
    r = tr.to_control(np.array([float(t) for t in ts]))  # floats, read as their shortest decimals
    assert not r.issiso and r.inputs.shape == r.outputs.shape == (2, 5) and r.states.shape == (4, 5)
    assert r.input_labels == ["u (slow)", "u (fast)"] and r.output_labels == ["y (slow)", "y (fast)"]
    tm = [mp.mpf(t.numerator) / t.denominator if isinstance(t, Fraction) else mp.mpf(t) for t in ts]
    x1 = [mp.cos(t) if t < mp.pi / 2 else 0 for t in tm]
    x3 = [mp.cos(2 * t) if t < mp.pi / 4 else 0 for t in tm]
    _close(r.states[0], x1, "x1")
    _close(r.states[1], [-mp.sin(t) if t < mp.pi / 2 else 0 for t in tm], "x2")
    _close(r.states[2], x3, "x3")
    _close(r.states[3], [-2 * mp.sin(2 * t) if t < mp.pi / 4 else 0 for t in tm], "x4")
    _close(r.outputs[0], x1, "y1")
    _close(r.outputs[1], x3, "y2")
    _close(r.inputs[0], [0] * 5, "u1")
    _close(r.inputs[1], [0] * 5, "u2")
    df = r.to_pandas()  # python-control's own table, with our names
    assert list(df.columns) == ["time", "u (slow)", "u (fast)", "y (slow)", "y (fast)", "x_0", "x_1", "x_2", "x_3"]


def test_to_control_of_a_partial_run_says_so():
    with pytest.raises(L.LimitExceeded) as err:
        simulate(LCS([[0, -1], [0, 0]], [[1], [0]], [[1, 0]], [[0]]), [1, 1], 3, max_events=0)
    tr = err.value.trajectory  # x_0 = 1 - t up to the stop at t = 1, where the run stopped
    r = tr.to_control([0, Fraction(1, 2)])
    assert not r.success and "max_events = 0" in r.message
    assert r.states.tolist() == [[1.0, 0.5], [1.0, 1.0]]
    with pytest.raises(L.InvalidArgument, match="after the last computed time"):
        tr.to_control([2])


def test_table_names_are_the_plots_names():
    """u and y columns are named as the plots label them: u_0 for unnamed pairs, u (stop) for a
    named one (it was u_0 in tables whatever the name), the builder's words with roles."""
    tr = simulate(LCS(**OSC, constraint_names=["stop"]), [1, 0], 1)
    assert list(tr.to_pandas([0], u=True, y=True).columns) == ["x_0", "x_1", "u (stop)", "y (stop)"]
    from lcs_exact.display.figlabels import pair_label  # the plots' legend names: one rule
    assert pair_label(tr.lcs, "u", 0) == "u (stop)" and pair_label(tr.lcs, "y", 0) == "y (stop)"
    plain = simulate(LCS(**OSC), [1, 0], 1)
    assert list(plain.to_pandas([0], u=True, y=True).columns) == ["x_0", "x_1", "u_0", "y_0"]
