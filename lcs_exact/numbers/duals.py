"""Balls with derivatives: forward differentiation over python-flint's ``arb`` (dual numbers whose
parts are balls), and bounds of 2-norms of ball vectors and matrices.

A :class:`Dual` carries a value v and its partial derivatives d = (dv/dz_1, ..., dv/dz_m) as balls.
Evaluated on balls z (an interval box), its parts enclose the values and the Jacobian of the
function over the whole box: the mean value theorem then bounds |F(p) - F(c)| by the Jacobian's
norm over the box times |p - c| (Moore, Kearfott and Cloud, *Introduction to Interval Analysis*,
2009, section 6.1).  Used by the proofs of :mod:`lcs_exact.accumulations.collapses`.

>>> from flint import arb
>>> x = Dual(arb(2), [arb(1)])
>>> y = (x * x + 1) / x          # x + 1/x, derivative 1 - 1/x^2
>>> y.v, y.d[0]
(2.50000000000000, 0.750000000000000)
"""
from __future__ import annotations

from flint import arb, arb_mat

__all__ = ["Dual", "norm2_bound", "vector_norm2_bound"]


class Dual:
    """A ball ``v`` with its partial derivatives ``d`` (a list of balls): +, -, *, / with balls,
    integers or other duals, and ``sqrt``.

    Parameters
    ----------
    v : arb
        The value.
    d : list of arb
        The partial derivatives, one per variable.
    """

    __slots__ = ("v", "d")

    def __init__(self, v: arb, d: list):
        self.v, self.d = v, d

    @staticmethod
    def _of(o, n: int) -> "Dual":
        return o if isinstance(o, Dual) else Dual(o, [arb(0)] * n)

    def __add__(self, o):
        o = Dual._of(o, len(self.d))
        return Dual(self.v + o.v, [a + b for a, b in zip(self.d, o.d)])

    __radd__ = __add__

    def __neg__(self):
        return Dual(-self.v, [-a for a in self.d])

    def __sub__(self, o):
        return self + (-Dual._of(o, len(self.d)))

    def __rsub__(self, o):
        return Dual._of(o, len(self.d)) - self

    def __mul__(self, o):
        o = Dual._of(o, len(self.d))
        return Dual(self.v * o.v, [self.v * b + o.v * a for a, b in zip(self.d, o.d)])

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = Dual._of(o, len(self.d))
        q = self.v / o.v
        return Dual(q, [(a - q * b) / o.v for a, b in zip(self.d, o.d)])

    def __rtruediv__(self, o):
        return Dual._of(o, len(self.d)) / self

    def sqrt(self):
        r = self.v.sqrt()
        return Dual(r, [a / (2 * r) for a in self.d])


def norm2_bound(M: arb_mat) -> arb:
    """An upper bound of the spectral norm of every matrix in a ball matrix: ||mid||_2 (Gershgorin on
    mid^T mid, exact for a normal midpoint up to its off-diagonal part) plus the Frobenius norm of
    the radii.

    Parameters
    ----------
    M : arb_mat
        A square ball matrix.
    """
    d = M.nrows()
    mid = arb_mat(d, d, [arb(M[i, j].mid()) for i in range(d) for j in range(d)])
    G = mid.transpose() * mid
    gersh = max((sum((abs(G[i, j]) for j in range(d)), arb(0)) for i in range(d)), key=lambda b: b.upper())
    rad = sum((arb(M[i, j].rad()) ** 2 for i in range(d) for j in range(d)), arb(0))
    return arb(gersh.upper()).sqrt() + arb(rad.upper()).sqrt()


def vector_norm2_bound(v: list) -> arb:
    """An upper bound (an exact ball) of the 2-norm of a vector of balls.

    Parameters
    ----------
    v : list of arb
    """
    return arb(sum((x * x for x in v), arb(0)).upper()).sqrt()
