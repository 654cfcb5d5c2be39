"""Rational functions in Q(s) and matrices of them: G(s), R(s), G_II(s)^{-1} (5.3), their Laurent
coefficients at s = oo (5.6), the resolvent C (sI - A)^{-1} B.

Representation
--------------
* A rational function is :class:`RationalFunction`: a pair of ``fmpq_poly`` with the
  denominator monic and coprime to the numerator (the zero function is 0/1).
* :class:`RationalMatrix` is a small dense matrix of :class:`RationalFunction`.
* Laurent coefficients at s = oo come from the exact division of the numerator by the
  denominator, term by term (:func:`laurent_coefficients`); signs of rational functions for
  large s are decided on them by :func:`lcs_exact.rational.lex_sign` (5.7, Lemma 5.1).
"""
from __future__ import annotations

import re
from typing import Any, Sequence

from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import NotRational, ShapeError
from .matrixfunctions import adjugate_coefficients
from .rational import fmpq_to_sympy, to_fmpq

__all__ = ["RationalFunction", "RationalMatrix", "laurent_coefficients", "resolvent"]

# ---------------------------------------------------------------------------------------------
# Q(s)
# ---------------------------------------------------------------------------------------------

_S = fmpq_poly([0, 1])


def _poly(p: Any) -> fmpq_poly:
    if isinstance(p, fmpq_poly):
        return p
    if isinstance(p, (list, tuple)):
        return fmpq_poly([to_fmpq(c) for c in p])
    return fmpq_poly([to_fmpq(p)])


class RationalFunction:
    """An element p(s)/q(s) of Q(s), normalized: q monic, gcd(p, q) = 1, zero is 0/1.

    ``RationalFunction(num, den)`` takes polynomials (``fmpq_poly``, coefficient lists lowest
    degree first, or scalars); ``RationalFunction(text)`` reads an expression in ``s`` with
    rational numbers, ``+ - * /``, parentheses and integer powers (``^`` or ``**``), which is
    what the repr prints, so the repr pastes back.

    Parameters
    ----------
    num : fmpq_poly, list, scalar or str
        The numerator (coefficients lowest degree first), or the whole function as text.
    den : fmpq_poly, list or scalar, optional
        The denominator, nonzero (with text: omitted).

    Examples
    --------
    >>> s = RationalFunction.s()
    >>> f = 1 + s / (s**2 + 1)
    >>> f
    RationalFunction('(s^2 + s + 1)/(s^2 + 1)')
    >>> RationalFunction('(s^2 + s + 1)/(s^2 + 1)') == f
    True
    >>> [str(c) for c in f.laurent(4)]
    ['1', '1', '0', '-1']
    """

    __slots__ = ("num", "den")

    def __init__(self, num: Any = 0, den: Any = 1):
        if isinstance(num, str):
            parsed = _parse_rational_function(num)
            if not (isinstance(den, (int, fmpq)) and den == 1):
                parsed = parsed / RationalFunction(den)
            self.num, self.den = parsed.num, parsed.den
            return
        p, q = _poly(num), _poly(den)
        if q.is_zero():
            raise ZeroDivisionError("rational function with zero denominator")
        if p.is_zero():
            self.num, self.den = fmpq_poly([]), fmpq_poly([1])
            return
        g = p.gcd(q)
        if g.degree() > 0:
            p, q = p / g, q / g  # exact division
            p, q = fmpq_poly(p), fmpq_poly(q)
        lc = q.leading_coefficient()
        self.num, self.den = p / lc, q / lc

    @staticmethod
    def s() -> "RationalFunction":
        """The indeterminate s."""
        return RationalFunction(_S)

    @staticmethod
    def _coerce(x: Any) -> "RationalFunction":
        return x if isinstance(x, RationalFunction) else RationalFunction(x)

    # arithmetic ------------------------------------------------------------------------------
    def __add__(self, o):
        o = self._coerce(o)
        if self.den == o.den:
            return RationalFunction(self.num + o.num, self.den)
        return RationalFunction(self.num * o.den + o.num * self.den, self.den * o.den)

    __radd__ = __add__

    def __neg__(self):
        r = RationalFunction.__new__(RationalFunction)
        r.num, r.den = -self.num, self.den
        return r

    def __sub__(self, o):
        return self + (-self._coerce(o))

    def __rsub__(self, o):
        return self._coerce(o) - self

    def __mul__(self, o):
        o = self._coerce(o)
        return RationalFunction(self.num * o.num, self.den * o.den)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = self._coerce(o)
        if o.is_zero():
            raise ZeroDivisionError("division by the zero rational function")
        return RationalFunction(self.num * o.den, self.den * o.num)

    def __rtruediv__(self, o):
        return self._coerce(o) / self

    def __pow__(self, e: int):
        if e < 0:
            return RationalFunction(1) / (self ** (-e))
        return RationalFunction(self.num ** e, self.den ** e)

    def __eq__(self, o):
        if not isinstance(o, RationalFunction):
            try:
                o = RationalFunction(o)
            except Exception:
                return NotImplemented
        return self.num == o.num and self.den == o.den

    def __hash__(self):
        return hash((str(self.num), str(self.den)))

    def __call__(self, s0: Any) -> fmpq:
        """Exact value at a rational point (raises ZeroDivisionError at a pole)."""
        s0 = to_fmpq(s0, "s")
        d = self.den(s0)
        if d == 0:
            raise ZeroDivisionError(f"s = {s0} is a pole of {self}")
        return self.num(s0) / d

    # structure -------------------------------------------------------------------------------
    def is_zero(self) -> bool:
        return self.num.is_zero()

    def is_proper(self) -> bool:
        return self.is_zero() or self.num.degree() <= self.den.degree()

    def is_strictly_proper(self) -> bool:
        return self.is_zero() or self.num.degree() < self.den.degree()

    def relative_degree(self) -> float | int:
        """deg q - deg p (the first Laurent index, 5.6); +oo for the zero function."""
        return float("inf") if self.is_zero() else self.den.degree() - self.num.degree()

    def polynomial_part(self) -> fmpq_poly:
        """The polynomial part (the impulsive part of the time function, section 5.1)."""
        return fmpq_poly(self.num // self.den) if not self.is_zero() else fmpq_poly([])

    def laurent(self, count: int) -> list[fmpq]:
        """The first ``count`` Laurent coefficients at s = oo, starting at s^{-r}, r = relative degree.

        f(s) = sum_{i >= r} f_i s^{-i} (5.6); returns [f_r, f_{r+1}, ...].

        Parameters
        ----------
        count : int
            How many coefficients.
        """
        if self.is_zero():
            return [fmpq(0)] * count
        return laurent_coefficients(self.num.coeffs(), self.den.coeffs(), count)

    def sign_at_infinity(self) -> int:
        """Sign of f(sigma) for all large real sigma (Lemma 5.1): -1, 0 or +1."""
        if self.is_zero():
            return 0
        return 1 if self.num.leading_coefficient() > 0 else -1

    # display ---------------------------------------------------------------------------------
    def to_sympy(self):
        import sympy
        s = sympy.Symbol("s")
        num = sum(fmpq_to_sympy(c) * s**i for i, c in enumerate(self.num.coeffs()))
        den = sum(fmpq_to_sympy(c) * s**i for i, c in enumerate(self.den.coeffs()))
        return num / den

    def __str__(self):
        n, d = _poly_str(self.num), _poly_str(self.den)
        if self.den.degree() == 0:
            return n
        if self.num.degree() > 0 and ("+" in n or " - " in n):
            n = f"({n})"
        return f"{n}/({d})" if ("+" in d or " - " in d) else f"{n}/{d}"

    def __repr__(self):
        return f"RationalFunction('{self}')"

    def _repr_latex_(self):
        import sympy
        if len(str(self)) > _LATEX_MAX_CHARS:  # size cap: Jupyter then shows the repr
            return None
        return f"${sympy.latex(self.to_sympy())}$"


#: _repr_latex_ of rational functions and matrices returns None above this many characters
_LATEX_MAX_CHARS = 3000

_TOKEN = re.compile(r"\s*(?:(\d+(?:\.\d*)?|\.\d+)|(\*\*|[-+*/^()])|([A-Za-z_]\w*))")


def _parse_rational_function(text: str) -> "RationalFunction":
    """Read an expression in s (numbers, + - * /, parentheses, integer powers) exactly."""
    tokens: list[tuple[str, str]] = []
    pos, text_ = 0, text.strip()
    while pos < len(text_):
        m = _TOKEN.match(text_, pos)
        if m is None or m.end() == pos:
            raise NotRational(f"cannot read {text!r} as a rational function of s: unexpected "
                              f"{text_[pos:pos + 10]!r} at position {pos}")
        num, op, ident = m.groups()
        if ident is not None and ident != "s":
            raise NotRational(f"cannot read {text!r} as a rational function of s: unknown name {ident!r}")
        tokens.append(("num", num) if num is not None else ("op", "^" if op == "**" else op)
                      if op is not None else ("s", "s"))
        pos = m.end()
        while pos < len(text_) and text_[pos].isspace():
            pos += 1
    if not tokens:
        raise NotRational("cannot read an empty string as a rational function of s")
    i = 0

    def fail(why: str):
        raise NotRational(f"cannot read {text!r} as a rational function of s: {why}")

    def peek():
        return tokens[i] if i < len(tokens) else ("end", "")

    def take():
        nonlocal i
        i += 1
        return tokens[i - 1]

    def expr():
        v = term()
        while peek() in (("op", "+"), ("op", "-")):
            v = v + term() if take()[1] == "+" else v - term()
        return v

    def term():
        v = unary()
        while peek() in (("op", "*"), ("op", "/")):
            if take()[1] == "*":
                v = v * unary()
            else:
                d = unary()
                if d.is_zero():
                    fail("division by zero")
                v = v / d
        return v

    def unary():
        if peek() in (("op", "+"), ("op", "-")):
            return unary() if take()[1] == "+" else -unary()
        return power()

    def power():
        v = atom()
        if peek() == ("op", "^"):
            take()
            sign = 1
            if peek() in (("op", "+"), ("op", "-")):
                sign = -1 if take()[1] == "-" else 1
            kind, tok = take() if i < len(tokens) else ("end", "")
            if kind != "num" or not tok.isdigit():
                fail("an exponent must be an integer")
            if v.is_zero() and sign < 0:
                fail("division by zero")
            v = v ** (sign * int(tok))
        return v

    def atom():
        if i >= len(tokens):
            fail("unexpected end")
        kind, tok = take()
        if kind == "num":
            return RationalFunction(to_fmpq(tok))
        if kind == "s":
            return RationalFunction(_S)
        if tok == "(":
            v = expr()
            if i >= len(tokens) or take() != ("op", ")"):
                fail("missing ')'")
            return v
        fail(f"unexpected {tok!r}")

    v = expr()
    if i != len(tokens):
        fail(f"unexpected {tokens[i][1]!r}")
    return v


def _poly_str(p: fmpq_poly, var: str = "s") -> str:
    """s^2 - s + 1 style (high degree first)."""
    terms = []
    for d, c in reversed(list(enumerate(p.coeffs()))):
        if c == 0:
            continue
        mono = "" if d == 0 else var if d == 1 else f"{var}^{d}"
        a = abs(c)
        body = str(a) if not mono else (mono if a == 1 else f"{a}*{mono}")
        terms.append((c < 0, body))
    if not terms:
        return "0"
    out = ("-" if terms[0][0] else "") + terms[0][1]
    for neg, body in terms[1:]:
        out += (" - " if neg else " + ") + body
    return out


def laurent_coefficients(num: Sequence[Any], den: Sequence[Any], count: int) -> list[Any]:
    """Laurent coefficients at s = oo of N(s)/d(s) (5.6), starting at index deg d - deg N.

    ``num`` are the coefficients N_0, N_1, ..., N_a (low degree first) and may be scalars or
    row vectors (``fmpq_mat``: the numerator of a linear form in x0); ``den`` are the rational
    coefficients of d, d_b != 0.  From N = f d, comparing the coefficients of s^{a-r}:
    f_{b-a+r} = (N_{a-r} - sum_{q<b} d_q f_{q-a+r}) / d_b.

    Parameters
    ----------
    num : sequence of fmpq or fmpq_mat
        N_0, ..., N_a (above).
    den : sequence of fmpq
        d_0, ..., d_b (above).
    count : int
        How many coefficients.
    """
    a, b = len(num) - 1, len(den) - 1
    db = den[b]
    zero = num[0] * 0
    f: list[Any] = []  # f[r] = f_{b-a+r}
    for r in range(count):
        acc = num[a - r] if a - r >= 0 else zero
        for q in range(b):
            idx = q - b + r  # position of f_{q-a+r} in f
            if idx >= 0:
                acc = acc - f[idx] * den[q]
        f.append(acc / db if db != 1 else acc)
    return f


# ---------------------------------------------------------------------------------------------
# matrices over Q(s)
# ---------------------------------------------------------------------------------------------


class RationalMatrix:
    """A dense matrix over Q(s) (G(s), R(s), G_II(s)^{-1}, ...), rows of RationalFunction.

    Parameters
    ----------
    rows : sequence of sequences
        The entries: RationalFunction, polynomials, scalars or text (as RationalFunction reads them).
    """

    __slots__ = ("rows",)

    def __init__(self, rows: Sequence[Sequence[Any]]):
        self.rows = [[RationalFunction._coerce(e) for e in r] for r in rows]

    @property
    def shape(self) -> tuple[int, int]:
        return (len(self.rows), len(self.rows[0]) if self.rows else 0)

    def __getitem__(self, ij):
        i, j = ij
        return self.rows[i][j]

    def sub(self, rows: Sequence[int], cols: Sequence[int]) -> "RationalMatrix":
        """The submatrix on ``rows`` x ``cols``.

        Parameters
        ----------
        rows, cols : sequence of int
            The rows and columns kept (0-based, in this order).
        """
        return RationalMatrix([[self.rows[i][j] for j in cols] for i in rows])

    def __mul__(self, o: "RationalMatrix") -> "RationalMatrix":
        n, m = self.shape
        m2, p = o.shape
        if m != m2:
            raise ShapeError(f"cannot multiply {n}x{m} by {m2}x{p}")
        return RationalMatrix([[sum((self.rows[i][l] * o.rows[l][j] for l in range(m)), RationalFunction(0))
                                for j in range(p)] for i in range(n)])

    def __add__(self, o: "RationalMatrix") -> "RationalMatrix":
        return RationalMatrix([[a + b for a, b in zip(r1, r2)] for r1, r2 in zip(self.rows, o.rows)])

    def __neg__(self):
        return RationalMatrix([[-a for a in r] for r in self.rows])

    def __sub__(self, o):
        return self + (-o)

    def __eq__(self, o):
        return isinstance(o, RationalMatrix) and self.rows == o.rows

    def _eliminate(self, rhs: "RationalMatrix | None"):
        """Gaussian elimination over Q(s); returns (det, solution of self X = rhs or None)."""
        n, m = self.shape
        if n != m:
            raise ShapeError(f"square matrix over Q(s) expected, got {n}x{m}")
        a = [list(self.rows[i]) + (list(rhs.rows[i]) if rhs is not None else []) for i in range(n)]
        det = RationalFunction(1)
        for c in range(n):
            # pivot: nonzero entry of smallest numerator degree (keeps degrees low)
            cand = [i for i in range(c, n) if not a[i][c].is_zero()]
            if not cand:
                return RationalFunction(0), None
            p = min(cand, key=lambda i: (a[i][c].num.degree() + a[i][c].den.degree()))
            if p != c:
                a[c], a[p] = a[p], a[c]
                det = -det
            piv = a[c][c]
            det = det * piv
            inv = 1 / piv
            a[c] = [e * inv for e in a[c]]
            for i in range(n):
                if i != c and not a[i][c].is_zero():
                    f = a[i][c]
                    a[i] = [e - f * g for e, g in zip(a[i], a[c])]
        sol = RationalMatrix([r[n:] for r in a]) if rhs is not None else None
        return det, sol

    def det(self) -> RationalFunction:
        """Determinant over Q(s) (zero iff the matrix is singular as a rational matrix)."""
        if self.shape[0] == 0:
            return RationalFunction(1)
        return self._eliminate(None)[0]

    def solve(self, rhs: "RationalMatrix") -> "RationalMatrix":
        """X with self X = rhs over Q(s); raises ZeroDivisionError when self is singular.

        Parameters
        ----------
        rhs : RationalMatrix
            The right-hand side (as many rows as self).
        """
        if self.shape[0] == 0:
            return RationalMatrix([])
        det, sol = self._eliminate(rhs)
        if sol is None:
            raise ZeroDivisionError("matrix over Q(s) is singular")
        return sol

    def row_forms(self, i: int) -> tuple[list[fmpq_mat], fmpq_poly]:
        """Row i as one rational function whose numerator has row-vector coefficients.

        Returns (numerator coefficients N_0..N_a as 1 x m ``fmpq_mat``, common denominator d):
        row_i(s) . x = (sum_p (N_p . x) s^p) / d(s).

        Parameters
        ----------
        i : int
            The row (0-based).
        """
        row = self.rows[i]
        d = fmpq_poly([1])
        for e in row:
            d = d * e.den / d.gcd(e.den)
            d = fmpq_poly(d)
        nums = [fmpq_poly(e.num * fmpq_poly(d / e.den)) for e in row]
        deg = max((p.degree() for p in nums), default=-1)
        m = len(row)
        coeffs = []
        for p in range(max(deg, 0) + 1):
            coeffs.append(fmpq_mat(1, m, [q.coeffs()[p] if p <= q.degree() else 0 for q in nums]))
        return coeffs, d

    def apply(self, x: fmpq_mat) -> list[RationalFunction]:
        """self(s) x for a rational vector x: a list of rational functions.

        Parameters
        ----------
        x : fmpq_mat
            m x 1.
        """
        n, m = self.shape
        return [sum((self.rows[i][j] * RationalFunction(x[j, 0]) for j in range(m)), RationalFunction(0))
                for i in range(n)]

    def to_sympy(self):
        import sympy
        return sympy.Matrix([[e.to_sympy() for e in r] for r in self.rows]) if self.rows else sympy.Matrix([])

    def __repr__(self):
        return "RationalMatrix([" + ", ".join("[" + ", ".join(f"'{e}'" for e in r) + "]" for r in self.rows) + "])"

    def __str__(self):
        return "\n".join("[" + ", ".join(str(e) for e in r) + "]" for r in self.rows)

    def _repr_latex_(self):
        import sympy
        n, m = self.shape
        if n * m > 64 or sum(len(str(e)) for r in self.rows for e in r) > _LATEX_MAX_CHARS:
            return None
        return f"${sympy.latex(self.to_sympy())}$"


def resolvent(A: fmpq_mat, left: fmpq_mat, right: fmpq_mat | None = None) -> RationalMatrix:
    """left (sI - A)^{-1} right over Q(s) (right = I when None): R(s), G(s) - D of (5.3).

    Parameters
    ----------
    A : fmpq_mat
        n x n.
    left : fmpq_mat
        r x n (C in G(s)).
    right : fmpq_mat or None, optional
        n x c (B in G(s)); None for the identity.

    Examples
    --------
    >>> resolvent(fmpq_mat([[0, 1], [-1, 0]]), fmpq_mat([[1, 0]]))
    RationalMatrix([['s/(s^2 + 1)', '1/(s^2 + 1)']])
    """
    chi = A.charpoly()
    n = A.nrows()
    if right is not None and left.nrows() * right.ncols() == 1:
        return RationalMatrix([[RationalFunction(_transfer_numerator(A, chi, left, right), chi)]])
    bs = adjugate_coefficients(A, chi)
    mats = [left * b * right if right is not None else left * b for b in bs]
    r, c = mats[0].nrows(), mats[0].ncols()
    return RationalMatrix([[RationalFunction(fmpq_poly([mats[n - 1 - d][i, j] for d in range(n)]), chi)
                            for j in range(c)] for i in range(r)])


def _transfer_numerator(A: fmpq_mat, chi: fmpq_poly, row: fmpq_mat, col: fmpq_mat) -> fmpq_poly:
    """N(s) = chi(s) row (sI - A)^{-1} col from the Markov parameters h_j = row A^j col
    (n products of A with a vector, O(n^3), where the adjugate's n matrices cost O(n^4)):
    row (sI - A)^{-1} col = sum_j h_j s^{-j-1}, so N_k = sum_j c_{k+j+1} h_j (chi = sum c_i s^i).

    >>> _transfer_numerator(fmpq_mat([[0, 1], [-1, 0]]), fmpq_poly([1, 0, 1]), fmpq_mat([[1, 0]]), fmpq_mat([[1], [0]]))
    x
    """
    n = A.nrows()
    h, v = [], col
    for _ in range(n):
        h.append((row * v)[0, 0])
        v = A * v
    c = chi.coeffs() + [0] * (n + 1 - len(chi.coeffs()))
    return fmpq_poly([sum((c[k + j + 1] * h[j] for j in range(n - k)), fmpq(0)) for k in range(n)])
