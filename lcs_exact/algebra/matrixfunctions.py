"""Functions of a rational matrix: p(A) for p in Q[s], the coefficients of adj(sI - A), the moduli of
the eigenvalues, the infinity norm - exactly, or as certified balls where a number is irrational.
"""
from __future__ import annotations

import math

import flint
from flint import fmpq, fmpq_mat, fmpq_poly, fmpz, fmpz_mat

from .rational import identity, zeros

__all__ = ["adjugate_coefficients", "eigenvalue_moduli", "norm_inf", "row_norms", "poly_at_matrix", "polys_at_matrix"]


def eigenvalue_moduli(A: fmpq_mat, chi: fmpq_poly | None = None):
    """(smallest nonzero |lambda|, largest |lambda|) over the eigenvalues of A, as certified ``arb`` balls,
    or None when A is nilpotent (every eigenvalue 0).  The zero eigenvalues are split off exactly (the
    power of s dividing det(sI - A)), the others isolated by flint.

    Parameters
    ----------
    A : fmpq_mat
    chi : fmpq_poly, optional
        det(sI - A), when known.

    >>> lo, hi = eigenvalue_moduli(fmpq_mat([[0, 1], [-4, 0]]))
    >>> lo.contains(2) and hi.contains(2)
    True
    """
    p = flint.fmpz_poly((chi if chi is not None else A.charpoly()).numer())
    while p.degree() > 0 and p[0] == 0:
        p = flint.fmpz_poly(p.coeffs()[1:])
    if p.degree() <= 0:
        return None
    p = p / p.gcd(p.derivative())  # squarefree part: the roots once each
    mods = [abs(r) for r, _ in flint.fmpz_poly(p).complex_roots()]
    lows, ups = [m.lower() for m in mods], [m.upper() for m in mods]  # exact endpoints
    # min |lambda| lies in [min lower, min upper], max |lambda| in [max lower, max upper]
    return min(lows).union(min(ups)), max(lows).union(max(ups))


def row_norms(m: fmpq_mat) -> list[fmpq]:
    """[sum_j |m_ij| for each row i], exactly.

    Parameters
    ----------
    m : fmpq_mat

    >>> row_norms(fmpq_mat([[1, -2], [0, 0]]))
    [3, 0]
    """
    c = m.ncols()
    e = m.entries()  # row-major, one call (an entry read at a time costs twice as much)
    return [sum((abs(x) for x in e[i * c:(i + 1) * c] if x), fmpq(0)) for i in range(m.nrows())]


def norm_inf(m: fmpq_mat) -> fmpq:
    """The infinity norm max_i sum_j |m_ij|, exactly (0 for an empty matrix).

    Parameters
    ----------
    m : fmpq_mat
    """
    return max(row_norms(m), default=fmpq(0))


def adjugate_coefficients(A: fmpq_mat, chi: fmpq_poly | None = None) -> list[fmpq_mat]:
    """adj(sI - A) = sum_j s^{n-1-j} B_j (Faddeev-LeVerrier: B_0 = I, B_j = A B_{j-1} + c_j I, with
    det(sI - A) = s^n + c_1 s^{n-1} + ... + c_n).

    For any monic ``chi`` of degree d (not only the characteristic polynomial) the same recursion
    gives sum_j s^{d-1-j} B_j = (chi(s) I - chi(A)) (sI - A)^{-1}, a polynomial in s and A.

    Parameters
    ----------
    A : fmpq_mat
    chi : fmpq_poly, optional
        Monic (above); default det(sI - A).

    >>> [b.entries() for b in adjugate_coefficients(fmpq_mat([[0, 1], [-1, 0]]))]
    [[1, 0, 0, 1], [0, 1, -1, 0]]
    """
    n = A.nrows()
    c = (chi if chi is not None else A.charpoly()).coeffs()[::-1]  # c[j]: coefficient of s^{d-j}
    bs = [identity(n)]
    for j in range(1, len(c) - 1):
        bs.append(A * bs[-1] + identity(n) * c[j])
    return bs


def poly_at_matrix(p: fmpq_poly, S: fmpq_mat) -> fmpq_mat:
    """p(S) for p in Q[s], exactly, by Paterson-Stockmeyer: with the powers S^0..S^b (b ~ sqrt(deg p)),
    p(S) = sum_i p_i(S) (S^b)^i is Horner's rule in S^b on blocks of b coefficients, about 2 sqrt(deg p)
    matrix products instead of deg p (the spectral data of a 64 x 64 mode: 16 products, not 64).

    Parameters
    ----------
    p : fmpq_poly
    S : fmpq_mat, square

    >>> poly_at_matrix(fmpq_poly([1, 0, 1]), fmpq_mat([[0, 1], [-1, 0]])).entries()  # I + S^2 = 0
    [0, 0, 0, 0]
    """
    return polys_at_matrix([p], S)[0]


def polys_at_matrix(ps: list[fmpq_poly], S: fmpq_mat) -> list[fmpq_mat]:
    """[p(S) for p in ps] exactly, as :func:`poly_at_matrix`, sharing the powers of S.

    In integers: S = S_z / D and p(S) = P(S_z) / (e D^deg) with P = sum_k e p_k D^(deg-k) s^k (e the
    common denominator of the p_k): fmpz_mat products and scalings, no gcd per entry and step.

    Parameters
    ----------
    ps : list of fmpq_poly
    S : fmpq_mat, square

    >>> [m.entries() for m in polys_at_matrix([fmpq_poly([0, 1]), fmpq_poly([1, 0, 1])], fmpq_mat([[0, 1], [-1, 0]]))]
    [[0, 1, -1, 0], [0, 0, 0, 0]]
    """
    n = S.nrows()
    Sz, D = S.numer_denom()
    b = max(1, math.isqrt(max([len(p.coeffs()) - 1 for p in ps] + [1])))
    powers = [fmpz_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])]
    for _ in range(b):
        powers.append(powers[-1] * Sz)
    outs = []
    for p in ps:
        cs = p.coeffs()
        if not cs:
            outs.append(zeros(n, n))
            continue
        deg = len(cs) - 1
        e = fmpz(1)
        for c in cs:
            e = e * c.q // e.gcd(c.q)
        ints = [c.p * (e // c.q) * D ** (deg - k) for k, c in enumerate(cs)]
        out = fmpz_mat(n, n)
        for start in range((deg // b) * b, -1, -b):
            block = fmpz_mat(n, n)
            for j, c in enumerate(ints[start:start + b]):
                if c:
                    block += powers[j] * c
            out = out * powers[b] + block
        outs.append(fmpq_mat(out) / (e * D ** deg))
    return outs
