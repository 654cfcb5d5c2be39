"""Symbolic e^{Mt} by inverse Laplace transforms (SymPy, on request only: display, fixtures and
the symbolic candidates of closed forms).

:func:`laplace_closed_form` inverts row (sI - M)^{-1} z term by term when the reduced
denominator's irreducible factors over Q have degree <= 2 (or are biquadratic over one real
quadratic field); :func:`symbolic_expm` assembles e^{Mt} column by column and checks it against
the certified ball of :class:`~lcs_exact.numbers.expm.Spectrum` (a defect of the symbolic
inversion must never become a false closed form).
"""
from __future__ import annotations

import math

from flint import arb, arb_mat, fmpq, fmpq_mat

from .balls import closed_form_arb, workprec
from .expm import Spectrum
from ..errors import LCSError
from ..algebra import identity, resolvent

__all__ = ["symbolic_expm", "laplace_closed_form", "t_symbol"]

_SYMBOLS: dict = {}


def t_symbol():
    """The SymPy symbol t (real) of symbolic phase functions."""
    if "t" not in _SYMBOLS:
        import sympy
        _SYMBOLS["t"] = sympy.Symbol("t", real=True)
        _SYMBOLS["s"] = sympy.Symbol("s")
    return _SYMBOLS["t"]


def laplace_closed_form(M: fmpq_mat, row: fmpq_mat, z: fmpq_mat):
    """A SymPy closed form of row . e^{Mt} z (z rational), or None.

    The Laplace transform row (sI - M)^{-1} z = N(s)/d(s) is reduced; when every irreducible
    factor of d over Q has degree <= 2 (or is a biquadratic quartic over one Q(sqrt d)) the
    partial fractions are inverted term by term (t^l e^{rt}, e^{at} cos/sin, cosh/sinh);
    otherwise None.
    """
    f = resolvent(M, row, z)[0, 0]
    ext = None if f.is_zero() else _quadratic_extension(f.den)
    if ext is False:
        return None  # decided without SymPy (importing it costs more than most runs)
    import sympy
    if f.is_zero():
        return sympy.Integer(0)
    t = t_symbol()
    s = _SYMBOLS["s"]
    expr = f.to_sympy().subs(sympy.Symbol("s"), s)
    total = sympy.Integer(0)
    if ext is not None:
        ext = sympy.sqrt(sympy.Rational(int(ext.p), int(ext.q)))
    parts = sympy.apart(expr, s) if ext is None else sympy.apart(expr, s, extension=ext)
    for term in sympy.Add.make_args(parts):
        inv = _inverse_laplace_term(term, s, t)
        if inv is None:
            return None
        total += inv
    return total


def _quadratic_extension(den):
    """None when every irreducible factor of den over Q has degree <= 2; d (a rational) when the
    others are biquadratic a s^4 + b s^2 + c splitting over one real Q(sqrt(d)), d = b^2 - 4ac > 0 (the two
    carts' free mode: s^4 + 3s^2 + 1 over Q(sqrt 5)); False otherwise.  Decided in Q: two such
    factors share their field when the product of their d is a rational square."""
    ext = None
    for p, _ in den.factor()[1]:
        if p.degree() <= 2:
            continue
        c = p.coeffs()
        if p.degree() != 4 or c[1] != 0 or c[3] != 0:
            return False
        d = c[2] * c[2] - 4 * c[4] * c[0]
        if d < 0:
            return False  # s^2 = (-b +- sqrt d) / 2a complex: no real quadratic factors over Q(sqrt d)
        if ext is not None and not _rational_square(d * ext):
            return False  # two different quadratic fields
        ext = ext if ext is not None else d
    return ext


def _rational_square(q: fmpq) -> bool:
    """q = r^2 for a rational r."""
    p, d = int(q.p), int(q.q)
    return p >= 0 and math.isqrt(p) ** 2 == p and math.isqrt(d) ** 2 == d


def _inverse_laplace_term(term, s, t):
    import sympy
    num, den = sympy.fraction(sympy.factor(term))
    dp = sympy.Poly(den, s)
    np_ = sympy.Poly(num, s)
    if dp.degree() == 0:
        return None  # a polynomial part: impossible for a strictly proper transform
    lc = dp.LC()
    fl = sympy.factor_list(dp.as_expr() / lc, s)
    if len(fl[1]) != 1:
        return sympy.inverse_laplace_transform(term, s, t)
    base, mult = fl[1][0]
    bp = sympy.Poly(base, s)
    c0 = fl[0] * lc
    if bp.degree() == 1:
        a1, a0 = bp.all_coeffs()
        r = -a0 / a1
        if np_.degree() > 0:
            return sympy.inverse_laplace_transform(term, s, t)
        # term = k / (s - r)^mult with k = num / (c0 a1^mult): the base may be non-monic (2s + 1)
        k = np_.as_expr() / (c0 * a1 ** mult)
        return k * t ** (mult - 1) * sympy.exp(r * t) / sympy.factorial(mult - 1)
    if bp.degree() == 2 and mult == 1:
        a2, p, q = bp.all_coeffs()
        p, q = p / a2, q / a2
        c0 = c0 * a2
        coeffs = np_.all_coeffs()
        alpha, beta = (coeffs if len(coeffs) == 2 else [0] + coeffs)
        alpha, beta = alpha / c0, beta / c0
        disc = q - p ** 2 / 4
        a = -p / 2
        if disc > 0:
            w = sympy.sqrtdenest(sympy.sqrt(disc))
            return sympy.exp(a * t) * (alpha * sympy.cos(w * t) + (beta + alpha * a) / w * sympy.sin(w * t))
        w = sympy.sqrtdenest(sympy.sqrt(-disc))
        return sympy.exp(a * t) * (alpha * sympy.cosh(w * t) + (beta + alpha * a) / w * sympy.sinh(w * t))
    return sympy.inverse_laplace_transform(term, s, t)


def symbolic_expm(spectrum: Spectrum):
    """e^{Mt} as a SymPy matrix in t (column j by :func:`laplace_closed_form` of e_j), or None
    when some denominator has an irreducible factor of degree > 2; cached on the spectrum and
    cross-checked against the certified ball of e^{M/7} (a defect of the symbolic inversion must
    never become a false closed form)."""
    if "symbolic" in spectrum.__dict__:
        return spectrum.symbolic
    M, n = spectrum.M, spectrum.n
    t = t_symbol()
    unit = [fmpq_mat(n, 1, [int(i == j) for i in range(n)]) for j in range(n)]
    cols = []
    for j in range(n):
        col = [laplace_closed_form(M, unit[i].transpose(), unit[j]) for i in range(n)]
        if any(c is None for c in col):
            cols = None
            break
        cols.append(col)
    import sympy
    E = None if cols is None else sympy.Matrix(n, n, lambda i, j: cols[j][i])
    if E is not None:
        with workprec(128):
            ball = spectrum.apply(arb(fmpq(1, 7)), arb_mat(identity(n)), 128)
            for i in range(n):
                for j in range(n):
                    if not ball[i, j].overlaps(closed_form_arb(E[i, j].subs(t, sympy.Rational(1, 7)))):
                        raise LCSError(f"internal error: symbolic e^(Mt) disagrees with its certified "
                                       f"value at t = 1/7 (entry {i}, {j})")
    spectrum.symbolic = E
    return E
