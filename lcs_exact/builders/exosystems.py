"""Driven LCSs: sources carried by appended exosystem states (docs/extensions.md).

    x' = A x + B u + E w(t),   y = C x + D u + F w(t),   0 <= y ⊥ u >= 0

with w a vector of :mod:`~lcs_exact.sources` (Bohl functions with rational data).  Each source is
the output W z of the exosystem z' = S z, z(0) = z0 (:func:`~lcs_exact.sources.exosystem`), so the
system is the autonomous LCS (4.1) in the state (x, z):

    A' = [[A, E W], [0, S]],  B' = [[B], [0]],  C' = [C, F W],  D' = D.

Its Markov parameters C' A'^i B' = C A^i B are those of (A, B, C, D): the leading matrices and
the well-posedness of Theorem 6.3 do not depend on the sources, and every mode, projection and
event of the paper applies to (x, z) as it stands (z is never re-initialized: B' has no rows
there).  ``lcs.embed(x)`` returns the full initial state (x, z0) (:class:`AppendedStates`).
"""
from __future__ import annotations

from typing import Any, Sequence

from flint import fmpq_mat

from ..errors import InvalidArgument, ShapeError
from ..algebra import hstack, to_matrix, vstack, zeros
from ..system import AppendedStates, Exosystem, as_source, exosystem
from ..system import LCS

__all__ = ["AppendedStates", "driven", "extend"]


def extend(A: fmpq_mat, B: fmpq_mat, C: fmpq_mat, D: fmpq_mat, EW: fmpq_mat | None, FW: fmpq_mat | None,
           ex: Exosystem, **lcs_options: Any) -> LCS:
    """The LCS of (A, B, C, D) driven by the exosystem ``ex`` through E W (n x m) and F W (k x m),
    with ``lcs.embed(x) = (x, z0)``; ``lcs_options`` go to :class:`~lcs_exact.system.LCS`
    (``state_names`` are those of x: the exosystem's names are appended)."""
    n, k, m = A.nrows(), B.ncols(), ex.size
    EW = zeros(n, m) if EW is None else EW
    FW = zeros(k, m) if FW is None else FW
    Ab = vstack(hstack(A, EW), hstack(zeros(m, n), ex.S))
    Bb = vstack(B, zeros(m, k))
    Cb = hstack(C, FW)
    names = lcs_options.pop("state_names", None)
    names = tuple(f"x_{i}" for i in range(n)) if names is None else tuple(names)
    if len(names) != n:
        raise ShapeError(f"state_names has {len(names)} names, expected {n} (the exosystem's states "
                         "are named by the builder)")
    taken = set(names)
    exo = tuple(nm if nm not in taken else f"{nm} (source)" for nm in ex.names)
    return LCS(Ab, Bb, Cb, D, state_names=names + exo, embedding=AppendedStates(n, ex.z0, exo), **lcs_options)


def driven(A: Any, B: Any, C: Any, D: Any, E: Any = None, F: Any = None, *, w: Any, name: str | None = None,
           state_names: Any = None, constraint_names: Any = None, restitution: Any = None, roles: Any = None) -> LCS:
    """x' = A x + B u + E w(t), y = C x + D u + F w(t), 0 <= y ⊥ u >= 0, as an LCS in (x, z).

    Parameters
    ----------
    A, B, C, D : matrices as for :class:`~lcs_exact.system.LCS` (n x n, n x k, k x n, k x k)
    E : n x m matrix, optional (zero: the sources enter y only)
    F : k x m matrix, optional (zero: the sources enter x' only)
    w : sequence of m sources (:mod:`lcs_exact.sources`, or rationals for constants)
    name, state_names, constraint_names, restitution, roles : as for LCS (``state_names`` name x only;
        the exosystem's states are named after their atoms: ``'1'``, ``'sin(2t)'``, ...)

    Returns
    -------
    LCS
        State (x, z); ``lcs.embed(x)`` is (x, z0), the full initial state.

    Examples
    --------
    A diode rectifying sin t into a capacitor with a resistor (v' = u - v, the diode current u,
    its reverse voltage y = v - sin t + u):

    >>> from lcs_exact import sources
    >>> rect = driven([[-1]], [[1]], [[1]], [[1]], F=[[-1]], w=[sources.sine(1)])
    >>> rect.A, rect.C, rect.state_names
    ([-1,  0, 0]
    [ 0,  0, 1]
    [ 0, -1, 0], [1, -1, 0], ('x_0', 'sin(t)', 'cos(t)'))
    >>> rect.embed([0]).transpose()
    [0, 0, 1]
    """
    if isinstance(w, (str, bytes)) or not hasattr(w, "__iter__"):
        w = [w]
    srcs = [as_source(s, f"source w[{i}]") for i, s in enumerate(w)]
    if not srcs:
        raise ShapeError("w has no sources: use LCS(A, B, C, D) for a system without sources")
    probe = LCS(A, B, C, D)  # validates A, B, C, D (and reads flat B, C for k = 1) once
    n, k, m = probe.n, probe.k, len(srcs)
    Em = None if E is None else to_matrix(_column(E, n, m), "E", (n, m))
    Fm = None if F is None else to_matrix(_column(F, k, m), "F", (k, m))
    if Em is None and Fm is None:
        raise InvalidArgument("driven() needs E or F: the sources enter x' through E or y through F")
    ex = exosystem(srcs)
    return extend(probe.A, probe.B, probe.C, probe.D, None if Em is None else Em * ex.W,
                  None if Fm is None else Fm * ex.W, ex, name=name, state_names=state_names,
                  constraint_names=constraint_names, restitution=restitution, roles=roles)


def _column(M: Any, rows: int, m: int) -> Any:
    """A flat list is a column when m = 1 (one source), a row when rows = 1."""
    if isinstance(M, (list, tuple)) and M and not isinstance(M[0], (list, tuple)) and not hasattr(M[0], "tolist"):
        return [[e] for e in M] if m == 1 and rows > 1 else [list(M)]
    return M
