"""Exact Krylov (Horner) vectors of a rational matrix and their evaluation at eigenvalue balls.

The spectral projectors of :class:`lcs_exact.numbers.expm.Spectrum` are built from the columns
K_lambda(T) C = q_lambda(T) C / r'(lambda), q_lambda(s) = r(s) / (s - lambda) = sum_i
lambda^{d-1-i} b_i(s), with the Horner polynomials b_0 = 1, b_i(s) = s b_{i-1}(s) + r_{d-i} of the
squarefree part r (degree d) of the characteristic polynomial.  T, C and r are exact rationals, so
the Horner vectors v_i = b_i(T) C are exact: they are computed here with FLINT's integer matrices
(denominators cleared once, u_i = cd D^i v_i for T = T_z / D and cd the common denominator of r's
coefficients; fmpz_mat products are multi-modular, a fraction of the cost of n x n ball products at
hundreds of bits), and the only rounding left is the one product (Horner vectors) x (Vandermonde
matrix of the eigenvalues).  The cancellation of that product (tens to hundreds of bits at n = 64 -
128) is what the caller's guard bits cover; its accuracy check decides.
"""
from __future__ import annotations

from typing import Callable

from flint import acb, acb_mat, arb, arb_mat, fmpq, fmpq_mat, fmpq_poly, fmpz, fmpz_mat

from .balls import workprec
from ..algebra import kernel, poly_at_matrix

__all__ = ["horner_vectors", "vandermonde", "evaluate_columns", "exact_poly", "primary_basis", "factor_accuracy"]


def horner_vectors(T: fmpq_mat, C: fmpq_mat, r: fmpq_poly,
                   check: Callable[[], None] | None = None) -> tuple[list[fmpz_mat], fmpz, fmpz]:
    """(us, D, cd): the Horner vectors v_i = b_i(T) C (i < d = deg r) exactly, as integer n x m
    matrices u_i = cd D^i v_i (T = T_z / D and C = C_z / c with T_z, C_z integer, cd = c times
    the common denominator e of the coefficients of r): u_0 = e C_z,
    u_i = T_z u_{i-1} + D^i (e r_{d-i}) C_z.

    Parameters
    ----------
    T : fmpq_mat, square
    C : fmpq_mat
    r : fmpq_poly
        Monic, degree d >= 1.
    check : callable, optional
        Called every 16 products (a deadline check).

    >>> us, D, cd = horner_vectors(fmpq_mat([[0, 1], [-1, 0]]), fmpq_mat([[1], [0]]), fmpq_poly([1, 0, 1]))
    >>> [u.entries() for u in us], D, cd
    ([[1, 0], [0, -1]], 1, 1)
    """
    Tz, D = T.numer_denom()
    Cz, cden = C.numer_denom()
    cs = r.coeffs()
    d = len(cs) - 1
    cd = fmpz(1)
    for c in cs:
        cd = cd * c.q // cd.gcd(c.q)
    ints = [c.p * (cd // c.q) for c in cs]
    us = [Cz * cd]
    Dp = fmpz(1)
    for i in range(1, d):
        if check is not None and i % 16 == 0:
            check()
        Dp *= D
        u = Tz * us[-1]
        k = ints[d - i]
        if k:
            u += Cz * (Dp * k)
        us.append(u)
    return us, D, cd * cden


def vandermonde(lams: list[acb], tops: list[acb], d: int, D: fmpz, cd: fmpz, work: int) -> acb_mat:
    """The d x e matrix V[i, k] = lambda_k^{d-1-i} / (top_k cd D^i) at ``work`` bits (the
    scaling of the integer Horner vectors folded in: sum_i u_i V[i, k] = sum_i v_i
    lambda_k^{d-1-i} / top_k).

    Parameters
    ----------
    lams : list of acb
        The eigenvalues lambda_k.
    tops : list of acb
        The divisors top_k (r'(lambda_k) for a projector column).
    d : int
    D : fmpz
    cd : fmpz
    work : int
        Bits.
    """
    e = len(lams)
    with workprec(work):
        V = acb_mat(d, e)
        Dd = D ** (d - 1) * cd
        for k, (lam, top) in enumerate(zip(lams, tops)):
            p = acb(1) / (top * Dd)
            step = lam * D
            for i in range(d - 1, -1, -1):
                V[i, k] = p
                p = p * step
    return V


def evaluate_columns(us: list[fmpz_mat], cols: int, V: acb_mat, work: int) -> acb_mat:
    """sum_i u_i[:, :cols] V[i, :] as an (n cols) x e matrix of balls (row cols * r + j: row r of
    column j), the first ``cols`` columns of the integer Horner vectors against V, as two real
    products (the Horner matrix is real and exact).

    Parameters
    ----------
    us : list of fmpz_mat
    cols : int
        How many leading columns of the u_i.
    V : acb_mat
    work : int
        Bits.
    """
    n, m, d = us[0].nrows(), us[0].ncols(), len(us)
    if cols == m:
        lists = [u.entries() for u in us]
    elif cols == 1:
        lists = [u.entries()[::m] for u in us]
    else:
        lists = [[e[r * m + j] for r in range(n) for j in range(cols)] for e in (u.entries() for u in us)]
    U = arb_mat(fmpz_mat(n * cols, d, [x for row in zip(*lists) for x in row]))
    with workprec(work):
        re, im = U * V.real, U * V.imag
        return acb_mat(re) + acb_mat(im) * acb(0, 1)


def exact_poly(us: list[fmpz_mat], row: fmpz_mat, D: fmpz, cd: fmpz) -> fmpq_poly:
    """W(s) = sum_i (row v_i) s^{d-1-i} exactly (row a 1 x n integer matrix, v_i = u_i / (cd D^i),
    first column): W(lambda) / r'(lambda) = row K_lambda(T) C[:, 0].

    Parameters
    ----------
    us : list of fmpz_mat
    row : fmpz_mat
    D : fmpz
    cd : fmpz
    """
    d = len(us)
    coeffs = [fmpq(0)] * d
    Dp = fmpz(1)
    for i, u in enumerate(us):
        coeffs[d - 1 - i] = fmpq((row * u)[0, 0], cd * Dp)
        Dp *= D
    return fmpq_poly(coeffs)



def primary_basis(S: fmpq_mat, f: fmpq_poly) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat]:
    """(Z, W, W^T Z): exact bases (columns) of Ker f(S) and Ker f(S)^T for an irreducible factor
    f of the minimal polynomial of a semisimple S; the projector onto Ker f(S) along the other
    primary components is P_f = Z (W^T Z)^{-1} W^T, and for a root lambda of f the spectral
    projector is K_lambda = f_lambda(S) P_f / f'(lambda), f_lambda(s) = f(s) / (s - lambda).

    Parameters
    ----------
    S : fmpq_mat, square
    f : fmpq_poly
    """
    F = poly_at_matrix(f, S)
    Z, W = kernel(F), kernel(F.transpose())
    return Z, W, W.transpose() * Z


def _accuracy(entries: list, prec: int) -> int:
    """Relative accuracy in bits of a list of (complex) balls taken as a whole: their largest
    radius against their largest midpoint (entries that are genuinely near zero do not count);
    ``prec`` when they are exact."""
    big, rad = arb(0), arb(0)
    for x in entries:
        for part in ((x.real, x.imag) if isinstance(x, acb) else (x,)):
            m, r = abs(part.mid()), part.rad()  # exact: no rounding at the ambient precision
            if m > big:
                big = m
            if r > rad:
                rad = r
    if rad == 0:
        return prec
    if big == 0:
        return 0
    with workprec(64):
        return min(prec, max(0, int(float(((big.log() - rad.log()) / arb(2).log()).mid()))))


def factor_accuracy(W: acb_mat, work: int, want: int) -> int:
    """The accuracy of a factor, from a sample of its rows; below ``want`` it is measured on every
    entry before it counts: a sample can fall on coordinates where an eigenvector vanishes (a
    symmetric chain of carts), whose balls hold only noise around 0.

    Parameters
    ----------
    W : acb_mat
    work : int
        Bits of the working precision (the accuracy of exact entries).
    want : int
        Bits below which every entry is measured.
    """
    acc = _accuracy(_sample(W), work)
    if acc < want:
        acc = _accuracy([W[i, j] for i in range(W.nrows()) for j in range(W.ncols())], work)
    return acc


def _sample(W, rows: int = 4) -> list:
    """Entries of a few rows of W spread over it (an accuracy estimate costs O(rows x cols))."""
    n = W.nrows()
    idx = sorted({(n - 1) * k // max(rows - 1, 1) for k in range(rows)}) if n else []
    return [W[i, j] for i in idx for j in range(W.ncols())]
