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
multiples of sources.

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

import ast
from dataclasses import dataclass
from math import factorial
from typing import Any, Sequence

from flint import arb_mat, ctx, fmpq, fmpq_mat

from ..errors import InvalidArgument, NotRational, ShapeError
from ..algebra import to_fmpq, to_vector, vector_entries
from ..numbers import RationalReal
from ..numbers import ComponentsVector, ExactVector, as_exact_vector

__all__ = ["Source", "constant", "polynomial", "exponential", "sine", "cosine", "as_source", "parse_source",
           "Exosystem", "exosystem", "SourceBlock", "source_block", "state_signals", "AppendedStates"]

# an atom: ("pow", j) = t^j, ("exp", r) = e^{r t}, ("sin", w) = sin(w t), ("cos", w) = cos(w t)
_ORDER = {"pow": 0, "exp": 1, "sin": 2, "cos": 2}


def _atom_key(atom: tuple) -> tuple:
    kind, p = atom
    return (_ORDER[kind], p, kind)


@dataclass(frozen=True)
class Source:
    """w(t) = sum of rational multiples of t^j, exp(r t), sin(w t), cos(w t) (module docstring).

    ``terms`` maps each atom to its (nonzero) rational coefficient.  Sources add, subtract and
    multiply by rationals; ``w(t)`` (``value``) evaluates a source exactly at a rational time
    when every atom is rational there (powers; exp and trigonometric atoms at t = 0).
    """

    terms: tuple  # ((atom, coefficient), ...) sorted, coefficients nonzero

    @staticmethod
    def _of(d: dict) -> "Source":
        return Source(tuple(sorted(((a, c) for a, c in d.items() if c != 0), key=lambda ac: _atom_key(ac[0]))))

    def _dict(self) -> dict:
        return dict(self.terms)

    def __add__(self, other: Any) -> "Source":
        o = as_source(other, "a source term")
        d = self._dict()
        for a, c in o.terms:
            d[a] = d.get(a, fmpq(0)) + c
        return Source._of(d)

    __radd__ = __add__

    def __neg__(self) -> "Source":
        return Source._of({a: -c for a, c in self.terms})

    def __sub__(self, other: Any) -> "Source":
        return self + (-as_source(other, "a source term"))

    def __rsub__(self, other: Any) -> "Source":
        return as_source(other, "a source term") - self

    def __mul__(self, q: Any) -> "Source":
        if isinstance(q, Source):
            raise InvalidArgument("a product of two sources is not supported (sums and rational multiples are)")
        q = to_fmpq(q, "the factor of a source")
        return Source._of({a: c * q for a, c in self.terms})

    __rmul__ = __mul__

    def __truediv__(self, q: Any) -> "Source":
        q = to_fmpq(q, "the divisor of a source")
        if q == 0:
            raise InvalidArgument("a source divided by 0")
        return self * (1 / q)

    @property
    def is_constant(self) -> bool:
        """True when the source is a constant (possibly 0)."""
        return all(a == ("pow", 0) for a, _ in self.terms)

    def value(self, t: Any) -> fmpq:
        """w(t) exactly, for a rational t at which every atom is rational (powers anywhere;
        exp, sin, cos at t = 0 only); otherwise InvalidArgument.

        >>> (polynomial([1, 0, 3]) + cosine(5)).value(0), polynomial([1, 0, 3]).value("1/2")
        (2, 7/4)
        """
        tq = to_fmpq(t, "t")
        out = fmpq(0)
        for (kind, p), c in self.terms:
            if kind == "pow":
                out += c * tq ** int(p)
            elif tq == 0:
                out += c * (0 if kind == "sin" else 1)
            else:
                raise InvalidArgument(f"{_atom_text((kind, p))} is not rational at t = {tq}: evaluate the "
                                      "source with sympy (to_sympy) or through a simulated state")
        return out

    def to_sympy(self):
        """The source as a SymPy expression in t (for display)."""
        import sympy
        t = sympy.Symbol("t", real=True)
        out = sympy.Integer(0)
        for (kind, p), c in self.terms:
            cc = sympy.Rational(int(c.p), int(c.q))
            pp = sympy.Rational(int(p.p), int(p.q)) if isinstance(p, fmpq) else sympy.Integer(p)
            atom = {"pow": lambda: t ** pp, "exp": lambda: sympy.exp(pp * t), "sin": lambda: sympy.sin(pp * t),
                    "cos": lambda: sympy.cos(pp * t)}[kind]()
            out += cc * atom
        return out

    def _repr_latex_(self):
        import sympy
        return f"${sympy.latex(self.to_sympy())}$"

    def __repr__(self):
        if not self.terms:
            return "constant(0)"
        parts = []
        polys = [(p, c) for (k, p), c in self.terms if k == "pow"]
        if polys and any(p > 0 for p, _ in polys):
            coeffs = [fmpq(0)] * (max(p for p, _ in polys) + 1)
            for p, c in polys:
                coeffs[p] = c
            parts.append("polynomial([" + ", ".join(_q(c) for c in coeffs) + "])")
        elif polys:
            parts.append(f"constant({_q(polys[0][1])})")
        for (kind, p), c in self.terms:
            if kind == "pow":
                continue
            name = {"exp": "exponential", "sin": "sine", "cos": "cosine"}[kind]
            amp = "" if c == 1 else f", amplitude={_q(c)}"
            parts.append(f"{name}({_q(p)}{amp})")
        return " + ".join(parts)


def _q(x: fmpq) -> str:
    # an integer of 4000 digits or more is quoted too: Python's parser refuses such literals
    return str(x) if x.q == 1 and abs(x.p) < 10 ** 3999 else f"'{x}'"


def as_source(x: Any, what: str = "a source") -> Source:
    """A :class:`Source` from a Source or a rational (a constant).

    >>> as_source("3/2")
    constant('3/2')
    """
    if isinstance(x, Source):
        return x
    try:
        q = to_fmpq(x, what)
    except NotRational:
        raise NotRational(f"{what} must be a rational number or a source (lcs_exact.sources), got {x!r}") from None
    return Source._of({("pow", 0): q})


def constant(c: Any = 1) -> Source:
    """The constant c (gravity, a DC voltage, a fixed gap).

    >>> constant(-10)
    constant(-10)
    """
    return Source._of({("pow", 0): to_fmpq(c, "the constant")})


def polynomial(coeffs: Sequence[Any]) -> Source:
    """c_0 + c_1 t + c_2 t^2 + ... (low degree first).

    >>> polynomial([0, 2])        # a ramp 2t
    polynomial([0, 2])
    """
    if isinstance(coeffs, (str, bytes)) or not hasattr(coeffs, "__iter__"):
        raise InvalidArgument(f"polynomial() takes a list of coefficients (low degree first), got {coeffs!r}")
    cs = [to_fmpq(c, f"coefficient {j} of the polynomial") for j, c in enumerate(coeffs)]
    if len(cs) > 64:
        raise InvalidArgument(f"a polynomial source of degree {len(cs) - 1} > 63: too many exosystem states")
    return Source._of({("pow", j): c for j, c in enumerate(cs)})


def exponential(rate: Any, amplitude: Any = 1) -> Source:
    """amplitude * exp(rate t) (rate 0 is a constant).

    >>> exponential(-2, 3)
    exponential(-2, amplitude=3)
    """
    r, a = to_fmpq(rate, "rate"), to_fmpq(amplitude, "amplitude")
    if r == 0:
        return constant(a)
    return Source._of({("exp", r): a})


def _frequency(omega: Any) -> fmpq:
    w = to_fmpq(omega, "omega")
    if w == 0:
        raise InvalidArgument("omega = 0: sin(0 t) = 0 and cos(0 t) = 1 are constants; use constant()")
    return w


def sine(omega: Any, amplitude: Any = 1) -> Source:
    """amplitude * sin(omega t).

    >>> sine(-3)                   # sin(-3t) = -sin(3t)
    sine(3, amplitude=-1)
    """
    w, a = _frequency(omega), to_fmpq(amplitude, "amplitude")
    return Source._of({("sin", abs(w)): a if w > 0 else -a})


def cosine(omega: Any, amplitude: Any = 1) -> Source:
    """amplitude * cos(omega t).

    >>> cosine("1/2", 4)
    cosine('1/2', amplitude=4)
    """
    w, a = _frequency(omega), to_fmpq(amplitude, "amplitude")
    return Source._of({("cos", abs(w)): a})


def _atom_text(atom: tuple) -> str:
    kind, p = atom
    if kind != "pow":
        num, den = int(p.p), int(p.q)
        arg = ("t" if num == 1 else "-t" if num == -1 else f"{num}t") + ("" if den == 1 else f"/{den}")
    if kind == "pow":
        return "1" if p == 0 else "t" if p == 1 else f"t^{p}"
    return f"{kind}({arg})"


@dataclass(frozen=True)
class Exosystem:
    """z' = S z, z(0) = z0, with the sources as outputs: source i is (W z)_i (module docstring).

    ``names`` names the states (``'1'``, ``'t'``, ``'t^2/2'``, ``'exp(-2t)'``, ``'sin(3t)'``,
    ``'cos(3t)'``); ``W`` has one row per source.
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
        names.append(_atom_text(("exp", r)))
    for w in sorted({p for k, p in atoms if k in ("sin", "cos")}):
        first = len(names)
        index["sin", w], index["cos", w] = first, first + 1
        names += [_atom_text(("sin", w)), _atom_text(("cos", w))]
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


# ---------------------------------------------------------------------------------------------
# source text: the repr of a Source read back (model files), without eval
# ---------------------------------------------------------------------------------------------

#: the calls a source text may contain, with their parameters (in order)
SOURCE_CALLS = {"constant": ("c",), "polynomial": ("coeffs",), "exponential": ("rate", "amplitude"),
                "sine": ("omega", "amplitude"), "cosine": ("omega", "amplitude")}
MAX_SOURCE_TEXT = 4_000_000  # characters of one source's text (64 coefficients of MAX_RATIONAL_BITS bits fit)
_ALLOWED = ("the calls constant(c), polynomial([c0, c1, ...]), exponential(rate, amplitude), sine(omega, "
            "amplitude), cosine(omega, amplitude) with rational arguments (3, -1/2, '1/2', 0.25), "
            "+, -, and * or / by a rational")


def parse_source(text: Any) -> Source:
    """The :class:`Source` a text describes: the repr of a Source (``"constant(1) + sine(2,
    amplitude=3)"``), a sum or difference of the calls ``constant``, ``polynomial``,
    ``exponential``, ``sine``, ``cosine`` with rational arguments (integers, decimals, ``'p/q'``
    strings, ``p/q``), rational multiples (``3 * sine(2)``, ``sine(2) / 4``) and rationals alone
    (constants).  The text is parsed (``ast``), never evaluated; a Source or a number is taken as
    it is (:func:`as_source`).  Anything else is :class:`~lcs_exact.errors.InvalidArgument`.

    >>> parse_source("constant(1) + sine(2, amplitude=3)") == constant(1) + sine(2, 3)
    True
    >>> parse_source("cosine('1/2', amplitude=4)"), parse_source("-981/100")
    (cosine('1/2', amplitude=4), constant('-981/100'))
    >>> parse_source("2 * exponential(-1) - polynomial([0, 0.5])")
    polynomial([0, '-1/2']) + exponential(-1, amplitude=2)
    >>> parse_source("__import__('os')")
    Traceback (most recent call last):
    ...
    lcs_exact.errors.InvalidArgument: source text "__import__('os')": '__import__' is not a source (allowed: the calls constant(c), polynomial([c0, c1, ...]), exponential(rate, amplitude), sine(omega, amplitude), cosine(omega, amplitude) with rational arguments (3, -1/2, '1/2', 0.25), +, -, and * or / by a rational)
    """
    if not isinstance(text, str):
        return as_source(text)
    short = text if len(text) <= 60 else text[:57] + "..."
    if len(text) > MAX_SOURCE_TEXT:
        raise InvalidArgument(f"source text {short!r} has {len(text)} characters (at most {MAX_SOURCE_TEXT})")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as e:
        if "digits" in str(e.msg) and "integer" in str(e.msg):  # Python's limit on integer literals
            raise InvalidArgument(f"source text {short!r}: an integer has more than 4300 digits; write it "
                                  f"as a string ('123...')") from None
        raise InvalidArgument(f"source text {short!r} is not an expression ({e.msg})") from None
    except (ValueError, RecursionError, MemoryError) as e:  # an integer beyond Python's digit limit, nesting
        raise InvalidArgument(f"source text {short!r} cannot be read: {' '.join(str(e).split())[:80]}") from None
    try:
        return as_source(_SourceText(text.strip(), short).value(tree.body))
    except RecursionError:
        raise InvalidArgument(f"source text {short!r} is nested too deeply") from None
    except (InvalidArgument, NotRational) as e:  # a bad argument (sine(0), '1/x'): in the text's words
        if str(e).startswith("source text"):
            raise
        raise type(e)(f"source text {short!r}: {e}") from None


class _SourceText:
    """The walk of :func:`parse_source` over one expression: each node is a rational or a Source."""

    def __init__(self, text: str, short: str):
        self.text, self.short = text, short

    def fail(self, why: str):
        raise InvalidArgument(f"source text {self.short!r}: {why}")

    def value(self, node: ast.AST):
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
            a, b = self.value(node.left), self.value(node.right)
            if isinstance(node.op, ast.Add):
                return a + b if not (isinstance(a, Source) or isinstance(b, Source)) else as_source(a) + as_source(b)
            if isinstance(node.op, ast.Sub):
                return a - b if not (isinstance(a, Source) or isinstance(b, Source)) else as_source(a) - as_source(b)
            if isinstance(b, Source) and (isinstance(node.op, ast.Div) or isinstance(a, Source)):
                self.fail("a source is multiplied or divided by a rational only, not by a source")
            if isinstance(node.op, ast.Div):
                if b == 0:
                    self.fail("division by 0")
                return a / b
            return b * a if isinstance(b, Source) else a * b
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            v = self.value(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        return self.rational(node)

    def rational(self, node: ast.AST) -> fmpq:
        """A literal number: an int, a decimal read from its text (exactly), a 'p/q' string."""
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float, str)) \
                and not isinstance(node.value, bool):
            if isinstance(node.value, float):  # 0.1 is 1/10: the literal's digits, not the binary double
                return to_fmpq(ast.get_source_segment(self.text, node) or repr(node.value), "a number")
            return to_fmpq(node.value, "a number")
        if (isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div))) or \
                (isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd))):
            v = self.value(node)
            if isinstance(v, Source):
                self.fail("a source where a rational number is expected")
            return v
        if isinstance(node, ast.Name):
            self.fail(f"{node.id!r} is not a source (allowed: {_ALLOWED})")
        segment = ast.get_source_segment(self.text, node) or ""
        self.fail(f"{segment[:40]!r} is not allowed (allowed: {_ALLOWED})")

    def call(self, node: ast.Call) -> Source:
        name = node.func.id if isinstance(node.func, ast.Name) else None
        if name not in SOURCE_CALLS:
            what = name if name is not None else ast.get_source_segment(self.text, node.func)
            self.fail(f"{what!r} is not a source (allowed: {_ALLOWED})")
        params = SOURCE_CALLS[name]
        if any(isinstance(a, ast.Starred) for a in node.args) or any(k.arg is None for k in node.keywords):
            self.fail(f"{name}() takes its arguments as they are, not unpacked with * or **")
        if len(node.args) > len(params):
            self.fail(f"{name}() takes at most {len(params)} arguments ({', '.join(params)}), got {len(node.args)}")
        args = dict(zip(params, node.args))
        for k in node.keywords:
            if k.arg not in params:
                self.fail(f"{name}() has no argument {k.arg!r} (its arguments: {', '.join(params)})")
            if k.arg in args:
                self.fail(f"{name}() got the argument {k.arg!r} twice")
            args[k.arg] = k.value
        if params[0] not in args:
            self.fail(f"{name}() needs its argument {params[0]!r}")
        if name == "polynomial":
            seq = args["coeffs"]
            if not isinstance(seq, (ast.List, ast.Tuple)):
                self.fail("polynomial() takes a list of coefficients, low degree first: polynomial([1, 0, 2])")
            if len(seq.elts) > 64:
                self.fail(f"a polynomial source of degree {len(seq.elts) - 1} > 63: too many exosystem states")
            return polynomial([self.rational(e) for e in seq.elts])
        values = {k: self.rational(v) for k, v in args.items()}
        return {"constant": constant, "exponential": exponential, "sine": sine, "cosine": cosine}[name](**values)
