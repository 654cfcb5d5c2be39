"""A trajectory's certified samples as floats, for other tools: an array (NumPy), a data frame
(pandas), a CSV file (the format ``lcs-exact compare`` reads) and a NumPy ``.npz`` file; the
methods :meth:`Trajectory.to_numpy <lcs_exact.Trajectory.to_numpy>`, ``to_pandas``, ``to_csv``
and ``to_npz`` are these.  The fixture format is written by :mod:`lcs_exact.phases.fixture`,
python-control's ``TimeResponseData`` by :func:`lcs_exact.statespace.time_response`.

Each reads the trajectory through its public interface only (``lcs``, ``sample``, ``u``, ``y``,
``outputs``, ``output_names``); numpy and pandas are imported when asked for.
"""
from __future__ import annotations

from typing import Any

from ..errors import InvalidArgument
from ..algebra import as_list, to_fmpq
from ..system import signal_names

__all__ = ["columns", "array", "data_frame", "write_csv", "write_npz"]


def columns(traj: Any, t: Any, u: bool, y: bool, w: bool = False) -> tuple[list, list[str], list[list[float]]]:
    """(times as fmpq, column names, rows of floats): the states at t (right limits), then u and y
    when asked (an undetermined input is NaN), then the declared outputs (``w``).

    Parameters
    ----------
    traj : Trajectory
    t : rational-like or sequence of rational-like
        The times (floats read as their shortest decimal).
    u, y, w : bool
        Add the columns of u(t), y(t), the declared outputs w(t).
    """
    if hasattr(t, "tolist"):
        t = as_list(t)
    if isinstance(t, (str, bytes)) or not hasattr(t, "__iter__"):
        t = [t]
    ts = [to_fmpq(v, "t") for v in t]
    names = list(traj.lcs.state_names)
    rows = [[float(b.mid()) for b in row] for row in traj.sample(ts, 17)]
    for kind, wanted in (("u", u), ("y", y)):
        if not wanted:
            continue
        names += signal_names(traj.lcs)[1 if kind == "u" else 2]
        for row, tq in zip(rows, ts):
            vec = getattr(traj, kind)(tq)
            row += [float(c) for c in vec]
    if w:
        names += list(traj.output_names)
        for row, tq in zip(rows, ts):
            row += [float(c) for c in traj.outputs(tq)]
    return ts, names, rows


def array(traj: Any, t: Any, u: bool = False, y: bool = False):
    """:meth:`Trajectory.to_numpy <lcs_exact.Trajectory.to_numpy>` (its parameters, after ``traj``)."""
    import numpy as np
    _, _, rows = columns(traj, t, u, y)
    return np.array(rows, dtype=np.float64)


def data_frame(traj: Any, t: Any, u: bool = False, y: bool = False, outputs: bool | None = None):
    """:meth:`Trajectory.to_pandas <lcs_exact.Trajectory.to_pandas>` (its parameters, after ``traj``)."""
    try:
        import pandas as pd
    except ImportError:
        raise InvalidArgument("to_pandas needs pandas: pip install pandas (or lcs_exact[data])") from None
    if outputs is None:
        outputs = bool(traj.output_names)
    ts, names, rows = columns(traj, t, u, y, outputs)
    return pd.DataFrame(rows, index=pd.Index([float(v) for v in ts], name="t"), columns=names)


def write_csv(traj: Any, path: Any, t: Any, u: bool = False, y: bool = False) -> None:
    """:meth:`Trajectory.to_csv <lcs_exact.Trajectory.to_csv>` (its parameters, after ``traj``)."""
    import csv
    ts, names, rows = columns(traj, t, u, y)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow(["t"] + names)
        for tq, row in zip(ts, rows):
            w.writerow([repr(float(tq))] + [repr(v) for v in row])


def write_npz(traj: Any, path: Any, t: Any, u: bool = False, y: bool = False) -> None:
    """:meth:`Trajectory.to_npz <lcs_exact.Trajectory.to_npz>` (its parameters, after ``traj``)."""
    import numpy as np
    ts, names, rows = columns(traj, t, u, y)
    np.savez(path, t=np.array([float(v) for v in ts]), x=np.array(rows, dtype=np.float64),
             names=np.array(names))
