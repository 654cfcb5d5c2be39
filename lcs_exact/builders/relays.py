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

Sources.  x' = A x + B w + E s(t), w in Sgn(C x + F s(t)) (``relay(A, B, C, E, F, sources=...)``:
a belt's speed inside Coulomb friction's sign, a sine bias): the sources' exosystem z' = S z
(:func:`~lcs_exact.sources.exosystem`, s = W z) is appended instead of c, with the constant atom
1 added to it, whose state is the level c (shared with the constant sources).  With e_c that
state, A' = [[A, E W - B 1 e_c^T], [0, S]], C'_{2j} = (-C_j, -F_j W), C'_{2j+1} = 2 e_c^T; B' and
D' are as above, so the Markov parameters, the modes and the argument on the non-autonomous
modes (c = 1) are unchanged.  ``lcs.embed(x)`` = (x, z(0)).

Outputs.  The relays' outputs w_j = u_{2j} - c are what a user of the relay system asks for, not
the pairs: the builder declares them as :class:`RelayOutputs` (a linear map w = W_x x + W_u u)
carried by the LCS's embedding (:class:`LevelEmbedding`), so that ``traj.outputs(t)``,
``traj.to_pandas(t)`` and ``traj.plot()`` give w(t) under the relays' names.
"""
from __future__ import annotations

from typing import Any

from flint import fmpq_mat

from ..errors import InvalidArgument, ShapeError
from ..algebra import submatrix, to_matrix
from ..system import AppendedStates, as_source, constant, exosystem
from ..system import LCS

__all__ = ["relay", "LevelEmbedding", "LinearOutputs", "RelayOutputs"]


class LinearOutputs:
    """Outputs a builder derives from the state and the inputs: w = W_x x + W_u u (exact).

    Parameters
    ----------
    names : sequence of m str
        The outputs' names (columns of ``traj.to_pandas``, lines of ``traj.plot``).
    Wx : m x n matrix
        Coefficients of the LCS's state x (all n states, appended ones included).
    Wu : m x k matrix
        Coefficients of the inputs u.
    symbol : str
        The outputs' symbol (the label of their panel in a figure), ``"w"`` by default.

    An LCS carries them on its embedding (``lcs.embedding.outputs``, set by the builder): a
    trajectory evaluates them exactly (``traj.outputs(t)``: w = W_x x(t) + W_u u(t) on the phase
    holding t).

    Examples
    --------
    >>> out = LinearOutputs(["w"], [[0, -1]], [[1, 0]])
    >>> out.names, out.Wx, out.Wu
    (('w',), [0, -1], [1, 0])
    """

    def __init__(self, names: Any, Wx: Any, Wu: Any, symbol: str = "w"):
        if isinstance(names, str) or not hasattr(names, "__iter__"):
            raise InvalidArgument(f"names must be a sequence of str, got {type(names).__name__}")
        self.names = tuple(str(nm) for nm in names)
        m = len(self.names)
        if m == 0 or len(set(self.names)) != m or not all(self.names):
            raise InvalidArgument(f"output names must be distinct nonempty strings, got {self.names!r}")
        self.Wx = to_matrix(Wx, "Wx", (m, None))
        self.Wu = to_matrix(Wu, "Wu", (m, None))
        self.symbol = str(symbol)

    def describe_mode(self, I: Any) -> str | None:
        """The outputs in a mode, in words (None: the outputs do not say)."""
        return None

    def __repr__(self):
        return f"{type(self).__name__}({self.names!r})"


class RelayOutputs(LinearOutputs):
    """The outputs w_j = u_{2j} - c of the relays of :func:`relay` (the module docstring), whose
    mode description says each relay's level: ``+1`` (z_j > 0), ``-1`` (z_j < 0) or sliding.

    >>> out = relay([[0, 0], [0, 0]], [[-1, 2], [-2, -1]], [[1, 0], [0, 1]]).embedding.outputs
    >>> out.names, out.describe_mode({0, 1}), out.describe_mode({0, 2})
    (('w_0', 'w_1'), 'w_0 = +1, w_1 = -1', 'w_0 sliding, w_1 sliding')
    """

    def describe_mode(self, I: Any) -> str:
        """Each relay's level in mode I: ``"w_0 = +1, w_1 sliding"``."""
        I = frozenset(I)
        words = []
        for j, nm in enumerate(self.names):
            lo, hi = 2 * j in I, 2 * j + 1 in I
            words.append(f"{nm} " + ("= +1" if lo and hi else "sliding" if lo else "= -1" if not hi else "not admissible"))
        return ", ".join(words)


class LevelEmbedding(AppendedStates):
    """x -> (x, 1): the full initial state of a relay LCS (the appended relay level c = 1, a
    constant source); ``outputs`` are the relays' outputs (:class:`RelayOutputs`).  A relay
    system with sources appends their exosystem instead (``tail`` its z(0), ``names`` its
    states), whose constant state ``'1'`` is the level.

    >>> LevelEmbedding(2)([3, "1/2"]).transpose()
    [3, 1/2, 1]
    >>> LevelEmbedding(1, tail=[1, 0, 1], names=("1", "sin(t)", "cos(t)"))(["1/2"]).transpose()
    [1/2, 1, 0, 1]
    """

    def __init__(self, n: int, outputs: LinearOutputs | None = None, tail: Any = (1,), names: Any = ("c",)):
        super().__init__(n, tail if isinstance(tail, fmpq_mat) else list(tail), tuple(names))
        self.outputs = outputs

    def __repr__(self):
        if self.names == ("c",):
            return f"LevelEmbedding({self.n})"
        return f"LevelEmbedding({self.n}, names={self.names!r})"


def relay(A: Any, B: Any, C: Any, E: Any = None, F: Any = None, *, w: Any = None, sources: Any = None,
          name: str | None = None, state_names: Any = None, relay_names: Any = None) -> LCS:
    """The LCS of the relay system x' = A x + B w + E s(t), w in Sgn(C x + F s(t)) (componentwise,
    Sgn(0) = [-1, 1]); without sources x' = A x + B w, w in Sgn(C x).

    Parameters
    ----------
    A : n x n matrix
    B : n x m matrix (a flat list is one relay)
    C : m x n matrix (a flat list is one relay)
    E : n x p matrix, optional
        How the sources enter the state equation (zero by default).
    F : m x p matrix, optional
        How the sources enter the relays' inputs (zero by default): relay j switches where
        C_j x + F_j s(t) changes sign (a belt speed, a sine bias).
    w, sources : sequence of p sources, optional
        s(t): :mod:`lcs_exact.sources` objects, or rationals for constants, as ``w`` of
        :func:`~lcs_exact.exosystems.driven`.  Needs E or F.  ``sources=`` is the same argument
        under a name that does not clash with the relays' outputs w (give one of the two).
    name : str, optional
    state_names : sequence of n str, optional
        Names of x; the appended constant state is called ``"c"`` (with sources, the appended
        states are the sources' exosystem, named after its atoms: ``'1'``, ``'sin(t)'``, ...;
        its constant state ``'1'`` is the relay level).  Default ``x_0, ..., x_{n-1}``.
    relay_names : sequence of m str, optional
        Names of the relays' outputs w_j.  Default ``w_0, ..., w_{m-1}``.

    Returns
    -------
    LCS
        State (x, c) of dimension n + 1 (with sources (x, z), z the sources' exosystem), 2m
        complementarity pairs named ``"w0-", "w0+", "w1-", ...`` (``"s-", "s+"`` for a relay
        named ``"s"``; see the module docstring for the formulation).  ``lcs.embed(x)``
        returns (x, 1) (with sources (x, z(0))), the full initial state of the relay system's
        state x.  The relays' outputs w are declared on the embedding (:class:`RelayOutputs`):
        a trajectory gives them by ``traj.outputs(t)``, as columns of ``traj.to_pandas(t)`` and
        in the panel ``"w"`` of ``traj.plot()``, which it draws instead of the pairs' u and y.

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
    >>> out = lcs.embedding.outputs      # w_0 = u_0 - c
    >>> out.names, out.Wx, out.Wu
    (('w_0',), [0, -1], [1, 0])

    Coulomb friction on a belt moving at 1/2 (unit mass and spring, friction force 1):
    q'' = -q - w, w in Sgn(q' - 1/2); the belt's speed is a constant source inside the sign,
    carried by the state ``'1'``, which is also the relay level:

    >>> belt = relay([[0, 1], [-1, 0]], [[0], [-1]], [[0, 1]], F=[[-1]], sources=["1/2"],
    ...              state_names=["q", "v"], relay_names=["friction"])
    >>> belt.state_names, belt.A, belt.C
    (('q', 'v', '1'), [ 0, 1, 0]
    [-1, 0, 1]
    [ 0, 0, 0], [0, -1, 1/2]
    [0,  0,   2])
    >>> belt.embed([0, "1/2"]).transpose()     # at rest on the belt
    [0, 1/2, 1]
    """
    sources = _one_of_w_and_sources(w, sources)
    A, B, C = _relay_data(A, B, C)
    n, m = B.nrows(), B.ncols()
    names = _state_names(state_names, n)
    S, z0, exo, level, EW, FW = _appended(sources, E, F, n, m, names)
    Af = _relay_state_matrix(A, B, S, EW, level)
    Bf, Cf, Df = _relay_complementarity(B, C, FW, level, S.nrows())
    relay_names, cnames = _relay_and_pair_names(relay_names, m)
    outputs = _relay_outputs(relay_names, n, Af.nrows(), level)
    return LCS(Af, Bf, Cf, Df, name=name, state_names=names + exo, constraint_names=cnames,
               embedding=LevelEmbedding(n, outputs, z0, exo))


def _one_of_w_and_sources(w: Any, sources: Any) -> Any:
    """The sources s(t), given as ``w=`` or ``sources=`` (not both)."""
    if w is not None and sources is not None:
        raise InvalidArgument("relay() got both w and sources: they are the same argument (the sources s(t))")
    return w if w is not None else sources


def _relay_data(A: Any, B: Any, C: Any) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat]:
    """A (n x n), B (n x m) and C (m x n) of x' = A x + B w, w in Sgn(C x) as rational matrices,
    checked (a flat B or C is one relay)."""
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
    return A, B, C


def _relay_state_matrix(A: fmpq_mat, B: fmpq_mat, S: fmpq_mat, EW: fmpq_mat, level: int) -> fmpq_mat:
    """The LCS's A on (x, z): [[A, E W - B 1 e_level^T], [0, S]] (w = u_- - c: the level c enters
    x' through -B 1; the appended states z follow z' = S z)."""
    n, m, a = A.nrows(), B.ncols(), S.nrows()
    N = n + a
    Af = fmpq_mat(N, N)
    for i in range(n):
        for j in range(n):
            Af[i, j] = A[i, j]
        for j in range(a):
            Af[i, n + j] = EW[i, j]
        Af[i, n + level] -= sum((B[i, j] for j in range(m)), 0 * B[i, 0])  # -B 1: the level -c of w = u_- - c
    for i in range(a):
        for j in range(a):
            Af[n + i, n + j] = S[i, j]
    return Af


def _relay_complementarity(B: fmpq_mat, C: fmpq_mat, FW: fmpq_mat, level: int, a: int) -> tuple:
    """(B, C, D) of the LCS's 2m complementarity pairs (the module docstring): relay j's pair
    (u_{2j}, u_{2j+1}) enters x' through B_j on u_{2j}, with y_{2j} = -(C_j x + F_j s) + u_{2j+1}
    and y_{2j+1} = 2 c - u_{2j}."""
    n, m = B.nrows(), B.ncols()
    N, k = n + a, 2 * m
    Bf, Cf, Df = fmpq_mat(N, k), fmpq_mat(k, N), fmpq_mat(k, k)
    for j in range(m):
        for i in range(n):
            Bf[i, 2 * j] = B[i, j]
            Cf[2 * j, i] = -C[j, i]
        for i in range(a):
            Cf[2 * j, n + i] = -FW[j, i]
        Cf[2 * j + 1, n + level] = 2
        Df[2 * j, 2 * j + 1] = 1
        Df[2 * j + 1, 2 * j] = -1
    return Bf, Cf, Df


def _relay_and_pair_names(relay_names: Any, m: int) -> tuple[tuple, tuple]:
    """The relays' names (default ``w_0, ...``) and their pairs' names (``"s-", "s+"`` for a relay
    named ``"s"``; default ``"w0-", "w0+", ...``)."""
    if relay_names is not None:
        if isinstance(relay_names, str) or not hasattr(relay_names, "__iter__"):
            raise InvalidArgument(f"relay_names must be a sequence of {m} strings, got {type(relay_names).__name__}")
        relay_names = tuple(str(nm) for nm in relay_names)
        if len(relay_names) != m:
            raise ShapeError(f"relay_names has {len(relay_names)} names, expected {m} (one per column of B)")
        return relay_names, tuple(f"{nm}{sign}" for nm in relay_names for sign in "-+")
    return tuple(f"w_{j}" for j in range(m)), tuple(f"w{j}{sign}" for j in range(m) for sign in "-+")


def _relay_outputs(relay_names: tuple, n: int, N: int, level: int) -> RelayOutputs:
    """The relays' outputs w_j = u_{2j} - c (:class:`RelayOutputs`) on the state of dimension N."""
    m = len(relay_names)
    Wx, Wu = fmpq_mat(m, N), fmpq_mat(m, 2 * m)
    for j in range(m):  # w_j = u_{2j} - c
        Wx[j, n + level] = -1
        Wu[j, 2 * j] = 1
    return RelayOutputs(relay_names, Wx, Wu)


def _state_names(state_names: Any, n: int) -> tuple:
    """The names of x (default ``x_0, ..., x_{n-1}``)."""
    if state_names is None:
        return tuple(f"x_{i}" for i in range(n))
    if isinstance(state_names, str) or not hasattr(state_names, "__iter__"):
        raise InvalidArgument(f"state_names must be a sequence of {n} strings, got {type(state_names).__name__}")
    state_names = tuple(state_names)
    if len(state_names) != n:
        raise ShapeError(f"state_names has {len(state_names)} names, expected {n} (the constant "
                         f"state 'c' is added by relay())")
    return state_names


def _appended(sources: Any, E: Any, F: Any, n: int, m: int, names: tuple) -> tuple:
    """The appended states of a relay LCS: (S, z0, names, index of the level, E W, F W).  Without
    sources the level c alone (c' = 0, c(0) = 1); with sources their exosystem with the constant
    atom 1 added (shared when a source has a constant part), which is the level."""
    if sources is None:
        if E is not None or F is not None:
            raise InvalidArgument("relay() got E or F but no sources: pass sources=[...], the s(t) that "
                                  "E and F multiply")
        return fmpq_mat([[0]]), fmpq_mat([[1]]), ("c",), 0, fmpq_mat(n, 1), fmpq_mat(m, 1)
    if isinstance(sources, (str, bytes)) or not hasattr(sources, "__iter__"):
        sources = [sources]
    srcs = [as_source(v, f"sources[{i}]") for i, v in enumerate(sources)]
    p = len(srcs)
    if p == 0:
        raise ShapeError("sources is empty: leave it out for a relay system without sources")
    if E is None and F is None:
        raise InvalidArgument("relay() with sources needs E or F: the sources enter x' through E or the "
                              "relays' inputs through F")
    Em = fmpq_mat(n, p) if E is None else to_matrix(_flat(E, n, p), "E", (n, p))
    Fm = fmpq_mat(m, p) if F is None else to_matrix(_flat(F, m, p), "F", (m, p))
    ex = exosystem(srcs + [constant(1)])
    level = next(j for j in range(ex.size) if ex.W[p, j] != 0)  # the state '1' (the atom t^0)
    W = submatrix(ex.W, range(p), None)
    taken = set(names)
    exo = tuple(nm if nm not in taken else f"{nm} (source)" for nm in ex.names)
    return ex.S, ex.z0, exo, level, Em * W, Fm * W


def _flat(M: Any, rows: int, p: int) -> Any:
    """A flat list is a column when p = 1 (one source), a row when rows = 1."""
    if isinstance(M, (list, tuple)) and M and not isinstance(M[0], (list, tuple)) and not hasattr(M[0], "tolist"):
        return [[e] for e in M] if p == 1 and rows > 1 else [list(M)]
    return M
