"""Real algebraic numbers held as Calcium numbers (:mod:`lcs_exact.calcium`), as the exact reals
and vectors keep them (:class:`~lcs_exact.reals.AlgebraicReal`,
:class:`~lcs_exact.vectors.AlgebraicVector`): an exact description that pickles (its minimal
polynomial and an isolating interval: :func:`ca_state`, :func:`ca_from_state`) and a closed form
in radicals proven equal to it (:func:`radical_form`).
"""
from __future__ import annotations

from flint import arb, fmpq

from . import calcium
from .balls import closed_form_arb, dyadic_lower, dyadic_upper, workprec
from ..errors import LCSError
from .forms import ca_of_sympy

__all__ = ["ca_state", "ca_from_state", "rational_ca", "radical_form"]


def ca_state(c) -> tuple:
    """A picklable exact description of an algebraic Calcium number: (minimal polynomial, an
    isolating rational interval as ((p, q), (p, q))), rebuilt by :func:`ca_from_state`.

    Parameters
    ----------
    c : Ca
        A real algebraic number.
    """
    coeffs = c.minimal_polynomial()
    if coeffs is None:
        raise LCSError("internal inconsistency: an algebraic number without a minimal polynomial")
    with workprec(256):
        r = c.enclosure(256).real
        a, b = dyadic_lower(r), dyadic_upper(r)
    return (tuple(coeffs), ((int(a.p), int(a.q)), (int(b.p), int(b.q))))


def ca_from_state(state: tuple):
    """The Calcium number that :func:`ca_state` described (the root of the polynomial in the interval).

    Parameters
    ----------
    state : tuple
        (coefficients of the minimal polynomial, ((p, q), (p, q)) the interval's ends).
    """
    coeffs, ((ap, aq), (bp, bq)) = state
    with workprec(256):
        ball = arb(fmpq(ap, aq)).union(arb(fmpq(bp, bq)))
    return calcium.Ca.algebraic(list(coeffs), ball)


def radical_form(c):
    """A SymPy closed form of the real algebraic number c (a Calcium number), proven equal to it
    by Calcium: the rational itself, or a root of its minimal polynomial in radicals (degree <= 4)
    selected by c's enclosure; None otherwise."""
    import sympy
    q = c.to_fmpq()
    if q is not None:
        return sympy.Rational(int(q.p), int(q.q))
    coeffs = c.minimal_polynomial()
    if coeffs is None or len(coeffs) - 1 > 4:
        return None
    x = sympy.Symbol("x")
    poly = sympy.Poly(list(reversed(coeffs)), x)
    with workprec(128):
        target = c.enclosure(128).real
        for r in sympy.roots(poly, multiple=True):
            if not r.is_real:
                continue
            try:
                if not closed_form_arb(r).overlaps(target):
                    continue
            except Exception:  # noqa: BLE001 - an expression the ball evaluator cannot read
                continue
            rc = ca_of_sympy(r)
            if rc is not None and (rc - c).is_zero() is True:
                return sympy.radsimp(r) if len(str(r)) > 40 else r
    return None


def rational_ca(q):
    return calcium.Ca(q)
