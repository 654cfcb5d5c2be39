"""The linear part of an LCS as a state-space system, x' = A x + B u, y = C x + D u, and its
faces in python-control.

* :func:`signal_names`: the names of the states, the inputs u and the outputs y, one rule for
  tables (``Trajectory.to_pandas``), python-control systems and responses: the builder's words
  when it gave roles (``"force (stop)"``, ``"i(D1)"``), ``u_j`` / ``y_j`` for unnamed pairs, else
  ``u (name)`` / ``y (name)``;
* :func:`to_statespace` (``LCS.to_statespace``): a ``control.StateSpace`` with those names, its
  matrices rounded to float64 (the complementarity conditions are not part of it);
* :func:`read_statespace` (``LCS.from_statespace``): the matrices and names of a state-space
  system, floats read as their shortest decimals, so that a system written by
  :func:`to_statespace` from decimal data reads back to the same exact LCS with the same names;
* :func:`time_response` (``Trajectory.to_control``): a ``control.TimeResponseData`` of the
  certified states, inputs and outputs at given times, rounded to float64.

python-control is an optional extra (``pip install lcs_exact[control]``), imported inside the
functions: ``import lcs_exact`` does not load it.  This module sits below
:mod:`lcs_exact.system` and :mod:`lcs_exact.trajectory` and uses an LCS or a trajectory through
their public attributes only.
"""
from __future__ import annotations

import re
from fractions import Fraction
from typing import Any

from ..errors import InvalidArgument, ShapeError
from ..display import pair_label
from ..algebra import as_list, mat_rows, to_fmpq, to_short

__all__ = ["signal_names", "to_statespace", "read_statespace", "time_response", "to_arrays"]

_SUFFIX = re.compile(r"\(([^()]+)\)\s*\Z")  # the name in "force (stop)", "i(D1)", "u (stop)"


def signal_names(lcs: Any) -> tuple[tuple, tuple, tuple]:
    """(state names, input names, output names) of an LCS: ``lcs.state_names``; for each pair j
    the builder's words ``roles[j][0]`` / ``roles[j][1]`` when it gave roles, ``u_j`` / ``y_j``
    when the pairs have their default names, ``u (name)`` / ``y (name)`` otherwise (the plots'
    labels, as plain text).

    Parameters
    ----------
    lcs : LCS

    >>> from lcs_exact import LCS
    >>> signal_names(LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]))
    (('x_0', 'x_1'), ('u_0',), ('y_0',))
    >>> signal_names(LCS([[0]], [[1]], [[1]], [[0]], state_names=["q"], constraint_names=["stop"]))
    (('q',), ('u (stop)',), ('y (stop)',))
    """
    return (tuple(lcs.state_names), tuple(pair_label(lcs, "u", j, latex=False) for j in range(lcs.k)),
            tuple(pair_label(lcs, "y", j, latex=False) for j in range(lcs.k)))


def _control(what: str):
    try:
        import control
    except ModuleNotFoundError as e:
        raise ModuleNotFoundError(f"{what} needs python-control: pip install control (or lcs_exact[control])",
                                  name="control") from e
    return control


def to_statespace(lcs: Any):
    """The linear part of ``lcs`` (x' = A x + B u, y = C x + D u) as a python-control
    ``StateSpace``: A, B, C, D rounded to float64 (``lcs.to_numpy()``), the states, inputs and
    outputs named by :func:`signal_names`, the system by ``lcs.name`` when it has one.  The
    complementarity 0 <= y ⊥ u >= 0 is not part of it: python-control sees u as a free input.

    >>> from lcs_exact.examples import two_carts
    >>> ss = to_statespace(two_carts())
    >>> ss.input_labels, ss.output_labels, ss.nstates
    (['force (stop)'], ['gap (stop)'], 4)
    """
    control = _control("to_statespace")
    A, B, C, D = lcs.to_numpy()
    states, inputs, outputs = signal_names(lcs)
    named = {"name": lcs.name} if getattr(lcs, "name", None) else {}
    return control.ss(A, B, C, D, states=list(states), inputs=list(inputs), outputs=list(outputs), **named)


def _defaults(labels: list, prefix: str) -> bool:
    """Labels that name nothing: python-control's own (``u[0]``, ...) or this library's (``u_0``)."""
    return labels in ([f"{prefix}[{i}]" for i in range(len(labels))], [f"{prefix}_{i}" for i in range(len(labels))])


def read_statespace(sys: Any) -> tuple[list, dict]:
    """([A, B, C, D], names) of a state-space system (a python-control ``StateSpace`` or anything
    with ``A``, ``B``, ``C``, ``D`` arrays; floats are read later, by :class:`~lcs_exact.LCS`, as
    their shortest decimals).  ``names`` holds ``state_names`` and ``constraint_names`` when the
    system names its signals: its state labels; for the pairs, the name X that the input and the
    output of each pair share as a suffix ``(X)`` (``u (stop)`` and ``y (stop)``, ``force (stop)``
    and ``gap (stop)``), else its input labels.  Default labels (``x[0]``, ``u[0]``, ``u_0``) name
    nothing.  ShapeError unless inputs and outputs are as many (an LCS pairs them).

    >>> class SS:  # a stand-in with the attributes of control.StateSpace
    ...     A, B, C, D = [[0.0, 1.0], [-2.5, 0.0]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]]
    ...     state_labels, input_labels, output_labels = ["q", "q'"], ["u (stop)"], ["y (stop)"]
    >>> read_statespace(SS())[1]
    {'state_names': ['q', "q'"], 'constraint_names': ['stop']}
    """
    mats = []
    for key in ("A", "B", "C", "D"):
        m = getattr(sys, key, None)
        if m is None:
            raise InvalidArgument(f"from_statespace needs a system with A, B, C, D; {key} is missing")
        mats.append(as_list(m) if hasattr(m, "tolist") else m)
    B, C = mats[1], mats[2]
    k_in = len(B[0]) if B and isinstance(B[0], list) else 1
    if k_in != len(C):
        raise ShapeError(f"an LCS pairs each input u_i with an output y_i: the system has {k_in} inputs "
                         f"and {len(C)} outputs")
    names: dict = {}
    states = list(getattr(sys, "state_labels", None) or [])
    if states and not _defaults(states, "x"):
        names["state_names"] = states
    ins, outs = list(getattr(sys, "input_labels", None) or []), list(getattr(sys, "output_labels", None) or [])
    if ins and not (_defaults(ins, "u") and (not outs or _defaults(outs, "y"))):
        shared = [_shared_name(a, b) for a, b in zip(ins, outs)]
        ok = len(shared) == len(ins) and None not in shared and len(set(shared)) == len(ins)
        names["constraint_names"] = shared if ok else ins
    return mats, names


def _shared_name(a: str, b: str) -> str | None:
    """X when both labels end in ``(X)`` (``u (stop)`` and ``y (stop)``), else None."""
    ma, mb = _SUFFIX.search(str(a)), _SUFFIX.search(str(b))
    return ma[1] if ma and mb and ma[1] == mb[1] else None


def time_response(traj: Any, t: Any):
    """The trajectory at the times ``t`` as a python-control ``TimeResponseData``: ``time``,
    ``states`` x(t) (n x len(t); at an event time the state after it), ``inputs`` u(t) and
    ``outputs`` y(t) (k x len(t); after the event too), certified and rounded to float64 (an
    input the state leaves undetermined is NaN), named by :func:`signal_names`.  ``t``: rationals,
    or floats read as their shortest decimals; times outside the computed trajectory raise
    InvalidArgument.  ``success`` is False and ``message`` the stop reason for a partial run.
    A system with k = 1 is SISO (``outputs`` of shape (len(t),), python-control's convention).

    Parameters
    ----------
    traj : Trajectory
    t : sequence of rationals
        The times (above).

    >>> from lcs_exact import LCS, simulate
    >>> tr = simulate(LCS([[0, -1], [0, 0]], [[1], [0]], [[1, 0]], [[0]]), [1, 1], 3)
    >>> r = time_response(tr, [0, 1, 2])      # x_0 = 1 - t reaches the stop at t = 1, where u = 1
    >>> r.states.tolist(), r.inputs.tolist(), r.outputs.tolist()
    ([[1.0, 0.0, 0.0], [1.0, 1.0, 1.0]], [0.0, 1.0, 1.0], [1.0, 0.0, 0.0])
    """
    control = _control("to_control")
    import numpy as np
    if hasattr(t, "tolist"):
        t = as_list(t)
    if isinstance(t, (str, bytes)) or not hasattr(t, "__iter__"):
        t = [t]
    ts = [to_fmpq(v, "t") for v in t]
    lcs = traj.lcs
    n, k = lcs.n, lcs.k
    X = traj.to_numpy(ts, u=True, y=True).reshape(len(ts), n + 2 * k)
    states, inputs, outputs = signal_names(lcs)
    return control.TimeResponseData(
        np.array([float(q) for q in ts]), X[:, n + k:].T, X[:, :n].T, X[:, n:n + k].T, issiso=k == 1,
        output_labels=list(outputs), state_labels=list(states), input_labels=list(inputs),
        sysname=getattr(lcs, "name", None), success=not traj.partial, message=traj.stop_reason)


def to_arrays(lcs: Any) -> tuple:
    """(A, B, C, D) of an LCS as float64 arrays (``LCS.to_numpy``); an entry beyond float64's range
    is an InvalidArgument naming it (not infinity).

    Parameters
    ----------
    lcs : LCS
    """
    import numpy as np  # lazy: `import lcs_exact` stays without numpy
    out = []
    for key in "ABCD":
        m = getattr(lcs, key)
        try:
            out.append(np.array([[float(Fraction(int(e.p), int(e.q))) for e in row] for row in mat_rows(m)],
                                dtype=np.float64).reshape(m.nrows(), m.ncols()))
        except OverflowError:
            big = next(e for row in mat_rows(m) for e in row if abs(e) > 2**1023)
            raise InvalidArgument(f"{key} has an entry {to_short(big)} beyond the range of float64: it has "
                                  "no float (to_numpy and to_statespace round to float64)") from None
    return tuple(out)
