"""Relay systems x' = A x + B w, w in Sgn(C x), as linear complementarity systems.

Sgn is the set-valued sign: Sgn(z) = {1} for z > 0, {-1} for z < 0 and [-1, 1] at z = 0 (the
paper's (4.12) is a relay system; "because this system consists of two relay characteristics, it
can be modeled as a linear complementarity system" (Remark 4.11, [16])).

Formulation.  The relay levels +-1 are affine in the inputs, so one constant state c is appended
(c' = 0, c = 1 on every trajectory that starts from :meth:`LCS.embed`).  Relay j, with input
z_j = C_j x and output w_j, gets two complementarity pairs, inputs (u_-, u_+) >= 0:

    w_j = u_- - c,
    pair 2j   "wj-":  u_- = 1 + w_j,   y_- = -z_j + u_+   (= z_j^-, the negative part of z_j),
    pair 2j+1 "wj+":  u_+ = z_j^+,     y_+ = 2c - u_-     (= 1 - w_j).

Check (c = 1): z > 0 forces y_- = -z + u_+ >= 0, so u_+ > 0, y_+ = 0, u_- = 2 (w = 1) and then
u_+ = z; z < 0 forces y_- > 0, so u_- = 0 (w = -1), y_+ = 2 and u_+ = 0; at z = 0, u_+ > 0
would need u_- = 2 and y_- = u_+ > 0 together, which complementarity forbids, so u_+ = 0, y_- = 0
and u_- in [0, 2]: w in [-1, 1].  So 0 <= y ⊥ u >= 0 is exactly w_j in Sgn(z_j).

The LCS (state (x, c), n + 1; k = 2m pairs) is

    A' = [[A, -B 1], [0, 0]],  B'_{., 2j} = (B_{.j}, 0),  B'_{., 2j+1} = 0,
    C'_{2j} = (-C_j, 0),  C'_{2j+1} = (0, 2),  D' = diag([[0, 1], [-1, 0]], ...)

D' is skew: its leading matrices are M = N = D' (H_0 = D' has no zero row or column), which are
not P-matrices, so Theorem 6.3 does not apply, and the modes where some relay has "wj+" in I but
not "wj-" are not autonomous (the row of y_+ in G_II(s) vanishes).  They are never admissible
when c != 0 (y_+ = 0 and u_- = 0 give 2c = 0), which mode selection proves
(:mod:`lcs_exact.rcpfamily`).  In mode terms: relay j with z_j > 0 (w = 1) is {2j, 2j+1}; with
z_j < 0 (w = -1) neither index; sliding (z_j = 0 with |w_j| < 1) is {2j} alone.
"""
from __future__ import annotations

from typing import Any

from flint import fmpq_mat

from .errors import InvalidArgument, ShapeError
from .rational import to_matrix, to_vector
from .sources import AppendedStates
from .system import LCS

__all__ = ["relay", "LevelEmbedding"]


class LevelEmbedding(AppendedStates):
    """x -> (x, 1): the full initial state of a relay LCS (the appended relay level c = 1, a
    constant source).

    >>> LevelEmbedding(2)([3, "1/2"]).transpose()
    [3, 1/2, 1]
    """

    def __init__(self, n: int):
        super().__init__(n, [1], ("c",))

    def __repr__(self):
        return f"LevelEmbedding({self.n})"


def relay(A: Any, B: Any, C: Any, *, name: str | None = None, state_names: Any = None) -> LCS:
    """The LCS of the relay system x' = A x + B w, w in Sgn(C x) (componentwise, Sgn(0) = [-1, 1]).

    Parameters
    ----------
    A : n x n matrix
    B : n x m matrix (a flat list is one relay)
    C : m x n matrix (a flat list is one relay)
    name : str, optional
    state_names : sequence of n str, optional
        Names of x; the appended constant state is called ``"c"``.  Default ``x_0, ..., x_{n-1}``.

    Returns
    -------
    LCS
        State (x, c) of dimension n + 1, 2m complementarity pairs named ``"w0-", "w0+", "w1-", ...``
        (see the module docstring for the formulation).  ``lcs.embed(x)`` returns (x, 1), the full
        initial state of the relay system's state x.

    Examples
    --------
    A single relay x' = -sgn(x):

    >>> lcs = relay([[0]], [[-1]], [[1]])
    >>> lcs.A, lcs.B, lcs.C, lcs.D
    ([0, 1]
    [0, 0], [-1, 0]
    [ 0, 0], [-1, 0]
    [ 0, 2], [ 0, 1]
    [-1, 0])
    >>> lcs.constraint_names, lcs.state_names, lcs.embed([1]).transpose()
    (('w0-', 'w0+'), ('x_0', 'c'), [1, 1])
    >>> sorted(sorted(I) for I in lcs.select_modes(lcs.embed([1])))   # x > 0: w = 1
    [[0, 1]]
    >>> sorted(sorted(I) for I in lcs.select_modes(lcs.embed([0])))   # x = 0: sliding, w = 0
    [[0]]
    """
    A = to_matrix(A, "A")
    n = A.nrows()
    if n == 0 or A.ncols() != n:
        raise ShapeError(f"A must be a nonempty square matrix, got shape {n}x{A.ncols()}")
    if isinstance(B, (list, tuple)) and B and not isinstance(B[0], (list, tuple)):
        B = [[e] for e in B] if n > 1 else [list(B)]
    B = to_matrix(B, "B", (n, None))
    m = B.ncols()
    if m == 0:
        raise ShapeError("B has no columns: a relay system needs at least one relay")
    if isinstance(C, (list, tuple)) and C and not isinstance(C[0], (list, tuple)):
        C = [list(C)]
    C = to_matrix(C, "C", (m, n))
    if state_names is not None:
        if isinstance(state_names, str) or not hasattr(state_names, "__iter__"):
            raise InvalidArgument(f"state_names must be a sequence of {n} strings, got {type(state_names).__name__}")
        state_names = tuple(state_names)
        if len(state_names) != n:
            raise ShapeError(f"state_names has {len(state_names)} names, expected {n} (the constant "
                             f"state 'c' is added by relay())")
        names = state_names + ("c",)
    else:
        names = tuple(f"x_{i}" for i in range(n)) + ("c",)
    N, k = n + 1, 2 * m
    Af = fmpq_mat(N, N)
    for i in range(n):
        for j in range(n):
            Af[i, j] = A[i, j]
        Af[i, n] = -sum((B[i, j] for j in range(m)), 0 * B[i, 0])  # -B 1: the level -c of w = u_- - c
    Bf, Cf, Df = fmpq_mat(N, k), fmpq_mat(k, N), fmpq_mat(k, k)
    for j in range(m):
        for i in range(n):
            Bf[i, 2 * j] = B[i, j]
            Cf[2 * j, i] = -C[j, i]
        Cf[2 * j + 1, n] = 2
        Df[2 * j, 2 * j + 1] = 1
        Df[2 * j + 1, 2 * j] = -1
    cnames = tuple(f"w{j}{sign}" for j in range(m) for sign in "-+")
    return LCS(Af, Bf, Cf, Df, name=name, state_names=names, constraint_names=cnames,
               embedding=LevelEmbedding(n))
