"""Sources: Bohl functions with rational data, each the output of a small autonomous exosystem.

An LCS (4.1) has no input besides u: a force, a gap or a voltage source that depends on time
enters through states appended to x, an *exosystem* z' = S z, z(0) = z0, whose output W z is the
signal (docs/extensions.md).  The paper's theory then applies unchanged: the extended system is
an LCS with rational data, and every number stays exact.

A :class:`Source` is a finite sum  w(t) = sum_a c_a a(t)  of *atoms* with rational coefficients:

    t^j (j >= 0; t^0 = 1 is a constant)    exp(r t) (r != 0)    sin(w t), cos(w t) (w > 0)

The atoms of a set of sources share one exosystem (:func:`exosystem`):

* the powers t^0 .. t^d: a chain of integrators z_j = t^j / j!, z_j' = z_{j-1}, z(0) = (1, 0, ...);
* exp(r t): one state, z' = r z, z(0) = 1;
* sin(w t), cos(w t): one pair (s, c), s' = w c, c' = -w s, (s, c)(0) = (0, 1).

so that gravity on every coordinate uses one constant state, and a sine and a cosine of the same
frequency one pair.  ``constant(2) + sine(3, 5) * "1/2"`` is a source; so are sums and rational
multiples of sources.  The sources themselves (:class:`Source`, its constructors, its text read by
:func:`parse_source`) are defined in :mod:`lcs_exact.system.signals` and exported here; this
module builds their exosystems and places them in an LCS (:class:`SourceBlock`).

>>> w = sine(2, amplitude=3) + constant(1)
>>> w
constant(1) + sine(2, amplitude=3)
>>> ex = exosystem([w])
>>> ex.names, ex.S, ex.z0.transpose(), ex.W
(('1', 'sin(2t)', 'cos(2t)'), [0,  0, 0]
[0,  0, 2]
[0, -2, 0], [1, 0, 1], [1, 3, 0])
"""
from __future__ import annotations

from dataclasses import dataclass
from math import factorial
from typing import Any, Sequence

from flint import arb_mat, ctx, fmpq, fmpq_mat

from ..errors import ShapeError
from ..algebra import to_vector, vector_entries
from ..numbers import RationalReal
from ..numbers import ComponentsVector, ExactVector, as_exact_vector
from .signals import (Source, as_source, atom_text, constant, cosine, exponential, parse_source, polynomial,
                      sine)

__all__ = ["Source", "constant", "polynomial", "exponential", "sine", "cosine", "as_source", "parse_source",
           "Exosystem", "exosystem", "SourceBlock", "source_block", "state_signals", "AppendedStates"]


@dataclass(frozen=True)
class Exosystem:
    """z' = S z, z(0) = z0, with the sources as outputs: source i is (W z)_i (module docstring).
    Made by :func:`exosystem`.

    Attributes
    ----------
    S : fmpq_mat
        m x m, the exosystem matrix.
    z0 : fmpq_mat
        m x 1, its state at t = 0.
    W : fmpq_mat
        One row per source, m columns.
    names : tuple of str
        The states' names: ``'1'``, ``'t'``, ``'t^2/2'``, ``'exp(-2t)'``, ``'sin(3t)'``, ``'cos(3t)'``.
    """

    S: fmpq_mat
    z0: fmpq_mat
    W: fmpq_mat
    names: tuple

    @property
    def size(self) -> int:
        return self.S.nrows()


def exosystem(sources: Sequence[Any]) -> Exosystem:
    """The shared exosystem of ``sources`` (Sources or rationals), one output row per source.

    Parameters
    ----------
    sources : sequence of Source or rational-like
        The signals (a rational is a constant).

    Examples
    --------
    >>> ex = exosystem([polynomial([1, 2, 3]), exponential(-1)])
    >>> ex.names, ex.W
    (('1', 't', 't^2/2', 'exp(-t)'), [1, 2, 6, 0]
    [0, 0, 0, 1])
    >>> exosystem([0, 0]).size      # no nonzero source: no state
    0
    """
    srcs = [as_source(s, f"source {i}") for i, s in enumerate(sources)]
    atoms = {a for s in srcs for a, _ in s.terms}
    powers = max((p for k, p in atoms if k == "pow"), default=-1)
    index: dict = {}
    names: list[str] = []
    blocks: list = []  # (first state, S block, z0 block)
    if powers >= 0:
        first = len(names)
        for j in range(powers + 1):
            index["pow", j] = first + j
            names.append("1" if j == 0 else "t" if j == 1 else f"t^{j}/{factorial(j)}")
        S = fmpq_mat(powers + 1, powers + 1)
        for j in range(1, powers + 1):
            S[j, j - 1] = 1
        blocks.append((first, S, [1] + [0] * powers))
    for r in sorted({p for k, p in atoms if k == "exp"}):
        index["exp", r] = len(names)
        blocks.append((len(names), fmpq_mat([[r]]), [1]))
        names.append(atom_text(("exp", r)))
    for w in sorted({p for k, p in atoms if k in ("sin", "cos")}):
        first = len(names)
        index["sin", w], index["cos", w] = first, first + 1
        names += [atom_text(("sin", w)), atom_text(("cos", w))]
        blocks.append((first, fmpq_mat([[0, w], [-w, 0]]), [0, 1]))
    m = len(names)
    S, z0, W = fmpq_mat(m, m), fmpq_mat(m, 1), fmpq_mat(len(srcs), m)
    for first, Sb, zb in blocks:
        for i in range(Sb.nrows()):
            z0[first + i, 0] = zb[i]
            for j in range(Sb.ncols()):
                S[first + i, first + j] = Sb[i, j]
    for i, s in enumerate(srcs):
        for (kind, p), c in s.terms:
            # t^j = j! z_j on the chain of integrators; every other atom is its state
            W[i, index[kind, p]] += c * factorial(p) if kind == "pow" else c
    return Exosystem(S, z0, W, tuple(names))


# ---------------------------------------------------------------------------------------------
# the exosystem inside an LCS: which states are sources, and their functions of time
# ---------------------------------------------------------------------------------------------

class AppendedStates:
    """x -> (x, tail): the full state of an LCS whose last states are appended by a builder
    (an exosystem's initial state z0, a relay level 1).  ``n`` is the number of states of the
    modelled system (the *plant*), ``names`` those of the appended states.

    An exact vector x (e.g. ``traj.state(t)`` restricted to the model) is accepted too.

    Parameters
    ----------
    n : int
        The number of the plant's states.
    tail : fmpq_mat or sequence of rational-like
        The appended states' values, appended to every x.
    names : sequence of str, optional
        The appended states' names.

    Examples
    --------
    >>> AppendedStates(2, [1, 0], ("sin(t)", "cos(t)"))([3, "1/2"]).transpose()
    [3, 1/2, 1, 0]
    """

    def __init__(self, n: int, tail: Any, names: Sequence[str] = ()):
        self.n = n
        self.tail = tail if isinstance(tail, fmpq_mat) else to_vector(tail, len(vector_entries(tail, None, "tail")), "tail")
        self.names = tuple(names)

    def __call__(self, x: Any):
        if isinstance(x, ExactVector) or (isinstance(x, (list, tuple)) and any(hasattr(e, "arb") for e in x)):
            v = as_exact_vector(list(x) if not isinstance(x, ExactVector) else x, self.n, "x")
            q = v.known_rational()
            if q is None:
                tail = [RationalReal(self.tail[i, 0]) for i in range(self.tail.nrows())]
                return ComponentsVector(list(v) + tail)
            x = q
        v = to_vector(x, self.n, "x")
        return fmpq_mat(self.n + self.tail.nrows(), 1,
                        [v[i, 0] for i in range(self.n)] + [self.tail[i, 0] for i in range(self.tail.nrows())])

    def __repr__(self):
        tail = ", ".join(str(self.tail[i, 0]) for i in range(self.tail.nrows()))
        return f"AppendedStates({self.n}, [{tail}], {self.names!r})"


def _blocks(S: fmpq_mat) -> list[tuple[str, list[int]]] | None:
    """The diagonal blocks of S that the exosystem builder makes (module docstring): a chain of
    integrators (``"chain"``: z_j' = z_{j-1}; one state with S = 0 is a constant), a scalar
    (``"exp"``: z' = r z, r != 0), a rotation (``"rotation"``: s' = w c, c' = -w s, w > 0); each
    with its indices, or None when S is of another shape."""
    m, out, i = S.nrows(), [], 0
    while i < m:
        j = i + 1
        while j < m and S[j, j - 1] == 1 and all(S[j, c] == 0 for c in range(m) if c != j - 1):
            j += 1  # a chain of integrators continues
        if j > i + 1 and all(S[i, c] == 0 for c in range(m)):
            out.append(("chain", list(range(i, j))))
            i = j
            continue
        if i + 1 < m and S[i, i] == 0 and S[i + 1, i + 1] == 0 and S[i, i + 1] != 0 and S[i, i + 1] == -S[i + 1, i] \
                and S[i, i + 1] > 0 and all(S[a, c] == 0 for a in (i, i + 1) for c in range(m) if c not in (i, i + 1)):
            out.append(("rotation", [i, i + 1]))
            i += 2
            continue
        if all(S[i, c] == 0 for c in range(m) if c != i):
            out.append(("exp" if S[i, i] != 0 else "chain", [i]))
            i += 1
            continue
        return None
    return out


def _rational_text(q: fmpq) -> str:
    return str(int(q.p)) if q.q == 1 else f"{int(q.p)}/{int(q.q)}"


def _argument(r: fmpq) -> str:
    """r t as text: 't', '-t', '2*t', '-t/2', '3*t/2'."""
    p, q = int(r.p), int(r.q)
    out = ("-" if p < 0 else "") + ("t" if abs(p) == 1 else f"{abs(p)}*t")
    return out + ("" if q == 1 else f"/{q}")


def _sum_text(terms: list) -> str:
    """sum c * atom as SymPy-parsable text (``atom`` '1' for a constant), zero terms left out."""
    parts = []
    for c, atom in terms:
        if c == 0:
            continue
        p, q = abs(int(c.p)), int(c.q)
        if atom == "1":
            body = _rational_text(abs(c))
        else:
            body = (atom if p == 1 else f"{p}*{atom}") + ("" if q == 1 else f"/{q}")
        parts.append(("-" if c < 0 else "+", body))
    if not parts:
        return "0"
    text = ("-" if parts[0][0] == "-" else "") + parts[0][1]
    return text + "".join(f" {s} {b}" for s, b in parts[1:])


def _power(j: int) -> str:
    return "1" if j == 0 else "t" if j == 1 else f"t**{j}"


def _expressions(S: fmpq_mat, z0: fmpq_mat, blocks: list) -> tuple:
    """Each state's z_i(t) = (e^{S t} z0)_i as text, block by block (exact coefficients)."""
    out = [""] * S.nrows()
    for kind, b in blocks:
        if kind == "rotation":
            w = S[b[0], b[1]]
            s0, c0 = z0[b[0], 0], z0[b[1], 0]
            sin, cos = f"sin({_argument(w)})", f"cos({_argument(w)})"
            out[b[0]] = _sum_text([(c0, sin), (s0, cos)])    # s = s0 cos + c0 sin
            out[b[1]] = _sum_text([(c0, cos), (-s0, sin)])   # c = c0 cos - s0 sin
        elif kind == "exp":
            out[b[0]] = _sum_text([(z0[b[0], 0], f"exp({_argument(S[b[0], b[0]])})")])
        else:  # a chain of integrators (a single state with S = 0 is a constant)
            for j in range(len(b)):
                out[b[j]] = _sum_text([(z0[b[i], 0] / factorial(j - i), _power(j - i)) for i in range(j, -1, -1)])
    return tuple(out)


@dataclass(frozen=True)
class SourceBlock:
    """The exosystem inside an LCS or a run: the states that are sources, z' = S z (docs/extensions.md).

    Attributes
    ----------
    states : tuple of int
        Indices of the exosystem's states in x (0-based); the others are the plant's.
    S : fmpq_mat
        The exosystem matrix (exact): A restricted to ``states`` (no other state and no u enters them).
    z0 : fmpq_mat
        The exosystem's state at t = 0.
    expressions : tuple of str
        Each state's function of t, SymPy-parsable (``'1'``, ``'t'``, ``'t**2/2'``, ``'exp(-t/2)'``,
        ``'sin(2*t)'``, ``'cos(2*t)'``).
    names : tuple of str
        The states' names in the LCS.

    Calling the block with times gives the float64 values of those states: a numerical solver
    that treats the sources as known inputs (instead of integrating, and damping, a sine) uses it.

    Examples
    --------
    >>> from flint import fmpq_mat
    >>> sb = source_block((1, 2), fmpq_mat([[0, 1], [-1, 0]]), fmpq_mat([[0], [1]]))
    >>> sb.expressions
    ('sin(t)', 'cos(t)')
    >>> sb(1.0).round(12).tolist()
    [0.841470984808, 0.540302305868]
    """

    states: tuple
    S: fmpq_mat
    z0: fmpq_mat
    expressions: tuple
    names: tuple = ()

    def __call__(self, t: Any):
        """float64 values of the sources' states at t: shape (m,) for a number, (len(t), m) for a
        sequence (closed forms per block: polynomials, exponentials, rotations)."""
        import numpy as np  # numpy is not loaded by ``import lcs_exact``
        scalar = np.ndim(t) == 0
        ts = np.atleast_1d(np.asarray(t, dtype=np.float64))
        S, z0, m = self.S, self.z0, self.S.nrows()
        out = np.zeros((ts.size, m))
        blocks = _blocks(S)
        if blocks is None:  # another shape: the exponential of S t as a ball, point by point
            with ctx.workprec(80):
                for r, tv in enumerate(ts.tolist()):
                    z = (arb_mat(S) * fmpq(*tv.as_integer_ratio())).exp() * arb_mat(z0)
                    out[r] = [float(z[i, 0].mid()) for i in range(m)]
            return out[0] if scalar else out
        f = [float(z0[i, 0]) for i in range(m)]
        for kind, b in blocks:
            if kind == "rotation":
                w = float(S[b[0], b[1]])
                sn, cs = np.sin(w * ts), np.cos(w * ts)
                out[:, b[0]] = f[b[0]] * cs + f[b[1]] * sn
                out[:, b[1]] = f[b[1]] * cs - f[b[0]] * sn
            elif kind == "exp":
                out[:, b[0]] = f[b[0]] * np.exp(float(S[b[0], b[0]]) * ts)
            else:
                for j in range(len(b)):
                    out[:, b[j]] = sum(f[b[i]] * ts ** (j - i) / factorial(j - i) for i in range(j + 1))
        return out[0] if scalar else out

    def __repr__(self):
        return f"SourceBlock(states={self.states!r}, expressions={self.expressions!r})"


def source_block(states: Sequence[int], S: fmpq_mat, z0: fmpq_mat, names: Sequence[str] = ()) -> SourceBlock:
    """The :class:`SourceBlock` of exosystem states ``states`` with matrix S and initial state z0
    (exact); their expressions are derived from the blocks of S (a chain of integrators, scalars,
    rotations: those :func:`exosystem` builds); for an S of another shape they read ``'z_i(t)'``.

    Parameters
    ----------
    states : sequence of int
        The exosystem's m states: their indices in the LCS's x (0-based).
    S : fmpq_mat
        m x m, the exosystem matrix.
    z0 : fmpq_mat
        m x 1, the exosystem's state at t = 0.
    names : sequence of str, optional
        The states' names in the LCS.
    """
    states = tuple(int(i) for i in states)
    m = len(states)
    if S.nrows() != m or S.ncols() != m or z0.nrows() != m or z0.ncols() != 1:
        raise ShapeError(f"an exosystem of {m} states needs S {m}x{m} and z0 of length {m}")
    blocks = _blocks(S)
    exprs = (_expressions(S, z0, blocks) if blocks is not None
             else tuple(f"z_{i}(t)" for i in states))
    return SourceBlock(states, S, z0, exprs, tuple(names))


def state_signals(S: fmpq_mat, z0: fmpq_mat) -> tuple | None:
    """Each state's function of time z_i(t) = (e^{S t} z0)_i as a :class:`Source`, block by block
    (a chain of integrators, scalars, rotations: those :func:`exosystem` builds), or None when S
    is of another shape.  The inverse of :func:`exosystem` on its own states: the states of
    ``exosystem(ws)`` are the atoms (``'t^2/2'`` is ``polynomial([0, 0, '1/2'])``).

    Parameters
    ----------
    S : fmpq_mat
        m x m, the exosystem matrix.
    z0 : fmpq_mat
        m x 1, the state at t = 0.

    Examples
    --------
    >>> ex = exosystem([polynomial([1, 0, 3]), sine(2)])
    >>> state_signals(ex.S, ex.z0)
    (constant(1), polynomial([0, 1]), polynomial([0, 0, '1/2']), sine(2), cosine(2))
    >>> state_signals(fmpq_mat([[0, 1], [-1, 0]]), fmpq_mat([[2], [0]]))   # (2 cos t, -2 sin t)
    (cosine(1, amplitude=2), sine(1, amplitude=-2))
    """
    blocks = _blocks(S)
    if blocks is None:
        return None
    out: list = [None] * S.nrows()
    for kind, b in blocks:
        if kind == "rotation":
            w = S[b[0], b[1]]
            s0, c0 = z0[b[0], 0], z0[b[1], 0]
            out[b[0]] = sine(w, c0) + cosine(w, s0)    # s = s0 cos + c0 sin
            out[b[1]] = cosine(w, c0) - sine(w, s0)    # c = c0 cos - s0 sin
        elif kind == "exp":
            out[b[0]] = exponential(S[b[0], b[0]], z0[b[0], 0])
        else:  # z_j = sum_i z0_i t^(j-i) / (j-i)!
            for j in range(len(b)):
                coeffs = [fmpq(0)] * (j + 1)
                for i in range(j + 1):
                    coeffs[j - i] += z0[b[i], 0] / factorial(j - i)
                out[b[j]] = polynomial(coeffs)
    return tuple(out)
