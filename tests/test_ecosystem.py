"""The results in the users' ecosystem (issue 16; DESIGN.md section 7): NumPy arrays, pandas data
frames, CSV/NPZ files, python-control systems, a progress bar, and the testing helper.  The values
are checked against the exact states (certified balls), not against themselves."""
from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from flint import fmpq

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
    from lcs_exact.compare import read_solution_csv
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
    control = pytest.importorskip("control")
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
    t = [0.25, 0.5, 0.75, 1.3]
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
