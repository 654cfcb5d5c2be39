"""Signals: the Bohl functions with rational data that drive a system (docs/extensions.md).

A :class:`Source` is a finite sum  w(t) = sum_a c_a a(t)  of *atoms* with rational coefficients:

    t^j (j >= 0; t^0 = 1 is a constant)    exp(r t) (r != 0)    sin(w t), cos(w t) (w > 0)

made by :func:`constant`, :func:`polynomial`, :func:`exponential`, :func:`sine`, :func:`cosine`
(and :func:`as_source` from a rational); sums and rational multiples of sources are sources.  Its
text is its repr, read back without ``eval`` by :func:`parse_source` (model files).  Each source
is the output of an exosystem appended to the system's states: :mod:`lcs_exact.sources` (the
module :mod:`lcs_exact.system.sources`), which exports these names too.

>>> constant(2) + sine(3, 5) * "1/2"
constant(2) + sine(3, amplitude='5/2')
"""
from __future__ import annotations

import ast
from dataclasses import dataclass
from typing import Any, Sequence

from flint import fmpq

from ..errors import InvalidArgument, NotRational
from ..algebra import to_fmpq

__all__ = ["Source", "constant", "polynomial", "exponential", "sine", "cosine", "as_source", "parse_source"]

# an atom: ("pow", j) = t^j, ("exp", r) = e^{r t}, ("sin", w) = sin(w t), ("cos", w) = cos(w t)
_ORDER = {"pow": 0, "exp": 1, "sin": 2, "cos": 2}


def _atom_key(atom: tuple) -> tuple:
    kind, p = atom
    return (_ORDER[kind], p, kind)


@dataclass(frozen=True)
class Source:
    """w(t) = sum of rational multiples of t^j, exp(r t), sin(w t), cos(w t) (module docstring).

    Sources add, subtract and multiply by rationals; :meth:`value` evaluates a source exactly at a
    rational time when every atom is rational there (powers; exp and trigonometric atoms at t = 0).
    Made by the functions below, not by hand.

    Attributes
    ----------
    terms : tuple
        ((atom, coefficient), ...): each atom with its nonzero ``fmpq`` coefficient, sorted; an
        atom is ``("pow", j)`` (t^j), ``("exp", r)``, ``("sin", w)`` or ``("cos", w)``.
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

        Parameters
        ----------
        t : rational-like
            The time (int, ``"p/q"``, Fraction, a float read as its shortest decimal, ...).

        Examples
        --------
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
                raise InvalidArgument(f"{atom_text((kind, p))} is not rational at t = {tq}: evaluate the "
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

    Parameters
    ----------
    x : Source or rational-like
    what : str, optional
        The name of x in the error message when it is neither
        (:class:`~lcs_exact.errors.NotRational`).

    Examples
    --------
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

    Parameters
    ----------
    c : rational-like, optional
        The value (default 1).

    Examples
    --------
    >>> constant(-10)
    constant(-10)
    """
    return Source._of({("pow", 0): to_fmpq(c, "the constant")})


def polynomial(coeffs: Sequence[Any]) -> Source:
    """c_0 + c_1 t + c_2 t^2 + ... (low degree first).

    Parameters
    ----------
    coeffs : sequence of rational-like
        c_0, c_1, ...: at most 64 (degree 63; each power is an exosystem state).

    Examples
    --------
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

    Parameters
    ----------
    rate : rational-like
        r, per unit of time.
    amplitude : rational-like, optional
        The value at t = 0 (default 1).

    Examples
    --------
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

    Parameters
    ----------
    omega : rational-like
        The angular frequency (radians per unit of time), nonzero; a negative one flips the sign.
    amplitude : rational-like, optional
        Default 1.

    Examples
    --------
    >>> sine(-3)                   # sin(-3t) = -sin(3t)
    sine(3, amplitude=-1)
    """
    w, a = _frequency(omega), to_fmpq(amplitude, "amplitude")
    return Source._of({("sin", abs(w)): a if w > 0 else -a})


def cosine(omega: Any, amplitude: Any = 1) -> Source:
    """amplitude * cos(omega t).

    Parameters
    ----------
    omega : rational-like
        The angular frequency (radians per unit of time), nonzero; cos(-w t) = cos(w t).
    amplitude : rational-like, optional
        Default 1.

    Examples
    --------
    >>> cosine("1/2", 4)
    cosine('1/2', amplitude=4)
    """
    w, a = _frequency(omega), to_fmpq(amplitude, "amplitude")
    return Source._of({("cos", abs(w)): a})


def atom_text(atom: tuple) -> str:
    kind, p = atom
    if kind != "pow":
        num, den = int(p.p), int(p.q)
        arg = ("t" if num == 1 else "-t" if num == -1 else f"{num}t") + ("" if den == 1 else f"/{den}")
    if kind == "pow":
        return "1" if p == 0 else "t" if p == 1 else f"t^{p}"
    return f"{kind}({arg})"


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

    Parameters
    ----------
    text : str, Source or rational-like
        The text, at most ``MAX_SOURCE_TEXT`` (4,000,000) characters.

    Examples
    --------
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
