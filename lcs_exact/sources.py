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

from dataclasses import dataclass
from math import factorial
from typing import Any, Sequence

from flint import fmpq, fmpq_mat

from .errors import InvalidArgument, NotRational
from .rational import to_fmpq

__all__ = ["Source", "constant", "polynomial", "exponential", "sine", "cosine", "as_source",
           "Exosystem", "exosystem"]

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
    return str(x) if x.q == 1 else f"'{x}'"


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
