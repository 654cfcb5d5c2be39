"""Polynomials over Q as coefficient lists (lowest degree first, no trailing zeros; [] is 0), in
``fractions.Fraction``: arithmetic, division with remainder, determinants of polynomial matrices,
the sign at s = +oo and Horner evaluation."""
from __future__ import annotations

from fractions import Fraction
from itertools import permutations


def ptrim(p):
    p = list(p)
    while p and p[-1] == 0:
        p.pop()
    return p


def padd(p, q):
    n = max(len(p), len(q))
    return ptrim([(p[i] if i < len(p) else 0) + (q[i] if i < len(q) else 0) for i in range(n)])


def pneg(p):
    return [-c for c in p]


def pmul(p, q):
    if not p or not q:
        return []
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return ptrim(out)


def pscale(c, p):
    return ptrim([c * x for x in p])


def pdivmod(p, q):
    """Quotient and remainder of p / q (q != 0)."""
    p, quo = list(p), [Fraction(0)] * max(len(p) - len(q) + 1, 0)
    while len(p) >= len(q) and p:
        c = p[-1] / q[-1]
        d = len(p) - len(q)
        quo[d] = c
        for i, b in enumerate(q):
            p[i + d] -= c * b
        p = ptrim(p)
    return ptrim(quo), p


def pdet(m):
    """Determinant of a square matrix of polynomials (Leibniz; meant for sizes <= 3)."""
    n = len(m)
    if n == 0:
        return [Fraction(1)]
    total = []
    for perm in permutations(range(n)):
        sign = 1
        for i in range(n):
            for j in range(i + 1, n):
                if perm[i] > perm[j]:
                    sign = -sign
        term = [Fraction(sign)]
        for i in range(n):
            term = pmul(term, m[i][perm[i]])
        total = padd(total, term)
    return total


def sign_at_infinity(num, den) -> int:
    """Sign of num(s)/den(s) for all large real s: the sign of the ratio of leading coefficients."""
    if not num:
        return 0
    return 1 if (num[-1] > 0) == (den[-1] > 0) else -1


def peval(coeffs, t: Fraction) -> Fraction:
    """Horner on a low-degree-first coefficient list, in Fractions."""
    acc = Fraction(0)
    for c in reversed(coeffs):
        acc = acc * t + Fraction(c)
    return acc
