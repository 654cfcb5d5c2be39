"""The exact data of a cycle of Newton impacts (:mod:`.bounces` proves its accumulation).

The last events of a run repeat one impact: the same contact b (or several hitting together),
the same mode J of resting contacts before and after, Newton's law with restitution 0 < e < 1.
:func:`bounce_cycle` reads that cycle off the events and builds, exactly, what the induction of
:mod:`.bounces` runs on: the flights' closed loop A = A_J, the gap's row c, the impulse's direction
r (c r = 0, c A r = 1), the background V with the coordinates w = L x, the jump R, the rows of the
other contacts, and a bound ||A^j|| <= C nu^j.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

from flint import arb, arb_mat, fmpq, fmpq_mat

from ..algebra import hstack, identity, is_zero, kernel, norm_inf, rank, row_basis, submatrix, vstack, zeros
from ..numbers import dyadic_upper, workprec
from .accumulation import event_signature

__all__ = ["BounceCycle", "bounce_cycle"]


def _row(M: fmpq_mat, i: int) -> fmpq_mat:
    return submatrix(M, [i], None)


@dataclass(frozen=True)
class BounceCycle:
    """The exact data of one flight-and-impact cycle of contact ``b`` (the module docstring)."""

    lcs: Any
    b: int
    e: fmpq
    A: fmpq_mat  # the flight's closed loop (mode {}: A itself)
    c: fmpq_mat  # C_b
    r: fmpq_mat  # B_b / W_bb: c r = 0, c A r = 1
    V: fmpq_mat  # the background {c x = 0, c A x = 0}, n x m
    L: fmpq_mat  # m x n: w = L x on {c x = 0}
    R: fmpq_mat  # the impact's jump
    others: tuple  # rows C_i of the other contacts (their gaps stay positive)
    nu: fmpq  # ||A^j|| <= C nu^j
    C: fmpq
    powers: list  # A^j, j = 0, 1, ... (extended on demand)
    same: fmpq_mat = None  # forms vanishing on the family: the gaps of several contacts agree

    @property
    def m(self) -> int:
        return self.V.ncols()

    def power(self, j: int) -> fmpq_mat:
        while len(self.powers) <= j:
            self.powers.append(self.A * self.powers[-1])
        return self.powers[j]

    def coefficients(self, J: int, prec: int) -> dict:
        """The series' rational coefficients as balls, j < J (cached per (J, prec))."""
        cache = self.__dict__.setdefault("_coeffs", {})
        key = (J, prec)
        if key not in cache:
            LR = self.L * self.R
            with workprec(prec):
                cr = [arb((self.c * self.power(j + 1) * self.r)[0, 0]) for j in range(J + 1)]
                cw = [arb_mat(self.c * self.power(j + 2) * self.V) for j in range(J + 1)]
                Ar = [arb_mat(self.power(j) * self.r) for j in range(J + 1)]
                AV = [arb_mat(self.power(j + 1) * self.V) for j in range(J + 1)]
                LRr = [arb_mat(LR) * a for a in Ar]
                LRV = [arb_mat(LR) * a for a in AV]
                facts = [arb(math.factorial(j)) for j in range(J + 3)]
            cache[key] = dict(cr=cr, cw=cw, Ar=Ar, AV=AV, LRr=LRr, LRV=LRV, f=facts)
        return cache[key]


def bounce_cycle(lcs, events: Sequence) -> BounceCycle | None:
    """The cycle the last events repeat when they are Newton impacts of one contact b between
    flights in one mode J of resting contacts (each event: J before and after, the chain
    (J + {b},), trigger y_b; J = {} for a lone ball), with 0 < e_b < 1, D = 0 on those rows,
    Theorem 6.3, and every resting contact pushed by the impact (W_CC^-1 e_b > 0, C = J + {b}:
    the jump is then r = B_C W_CC^-1 e_b times -(1 + e_b) c A x for every state); else None.

    Several contacts B hitting together at every event (two masses on a spring dropped
    symmetrically on two stops) are one contact b = min B on the subspace where their gaps are one
    function of time: the family is restricted to (c_i - c_b) A^j x = 0 (every i in B, j < n: the
    gaps agree on the whole flight, Cayley-Hamilton), the jump direction is r = B_C W_CC^-1 1_B
    (c_i A r = 1 for every i in B, so each gets its own Newton law), with one restitution for all."""
    rest = getattr(lcs, "restitution", None)
    if rest is None or len(events) < 3:
        return None
    sig = event_signature(events[-1])
    if any(event_signature(ev) != sig for ev in events[-3:]):
        return None
    J, chain, after, triggers = sig
    J = frozenset(J or ())
    if after != J or len(chain) != 1 or not J <= chain[0] or not chain[0] - J:
        return None
    Bset = sorted(chain[0] - J)
    b = Bset[0]
    closed = sorted(chain[0])
    if sorted(triggers) != sorted(f"y_{i}" for i in Bset) or not 0 < rest[b] < 1 or \
            any(rest[i] != rest[b] for i in Bset) or any(lcs.D[i, j] != 0 for i in closed for j in range(lcs.k)):
        return None
    if not lcs.well_posedness():
        return None
    n, mode = lcs.n, lcs.mode(J)
    A = mode.closed_loop() if J else lcs.A
    c = _row(lcs.C, b)
    W = submatrix(lcs.C * lcs.A * lcs.B, closed, closed)
    if W.det() == 0:
        return None
    z = W.inv() * fmpq_mat([[int(i in Bset)] for i in closed])
    if any(z[i, 0] <= 0 for i in range(len(closed))):
        return None
    r = submatrix(lcs.B, None, closed) * z  # c_i A r = 1 (i in B), the resting contacts' speeds unmoved
    G = vstack(c, c * A, *[_row(lcs.C, i) for i in J], *[_row(lcs.C * lcs.A, i) for i in J])
    if (c * r)[0, 0] != 0 or rank(G) != G.nrows() or (G * r)[1, 0] != 1:
        return None
    same = _same_gaps(lcs, A, Bset)  # the gaps of B agree on the flight: on the family, exactly
    if same.nrows() and not is_zero(same * r):
        return None
    V = kernel(vstack(G, same)) if same.nrows() else kernel(G)
    basis = hstack(V, r, nrows=n)
    if rank(basis) != V.ncols() + 1:
        return None
    # w = L x on {c x = 0} inside V_J: the coordinates of x in the basis [V, r] (exact left inverse)
    L = submatrix((basis.transpose() * basis).inv() * basis.transpose(), range(V.ncols()), None)
    R = identity(n) - (1 + rest[b]) * r * (c * lcs.A)
    # monitored on the flights: the resting contacts' forces u_J = F_J x, the other gaps y_i
    F, I = (mode.feedback(), list(mode.I)) if J else (None, [])
    others = tuple(_row(F, k) for k in range(len(I))) + tuple(
        _row(lcs.C, i) + submatrix(lcs.D, [i], I) * F if I else _row(lcs.C, i)
        for i in range(lcs.k) if i not in Bset and i not in J)
    nu, C = _growth(A)
    return BounceCycle(lcs, b, rest[b], A, c, r, V, L, R, others, nu, C, [identity(n)], same)


def _same_gaps(lcs, A: fmpq_mat, B: list[int]) -> fmpq_mat:
    """Rows (c_i - c_b) A^j, i in B beyond b = B[0], j < n (a row basis; none for one contact): the
    gaps of B are one function of time on a flight of A exactly where they all vanish."""
    rows = [(_row(lcs.C, i) - _row(lcs.C, B[0])) * A ** j for i in B[1:] for j in range(lcs.n)]
    return row_basis(vstack(*rows)) if rows else zeros(0, lcs.n)


def _growth(A: fmpq_mat) -> tuple[fmpq, fmpq]:
    """(nu, C) with ||A^j||_inf <= C nu^j for every j (nu from the best of ||A^p||^(1/p),
    p = 1, 2, 4, 8, rounded up; C = max_{i<p} ||A^i|| / nu^i)."""
    powers = [identity(A.nrows()), A]
    best = None
    p = 1
    while p <= 8:
        while len(powers) <= p:
            powers.append(A * powers[-1])
        norm = norm_inf(powers[p])
        if norm == 0:  # nilpotent: A^j = 0 for j >= p, any nu > 0 serves
            nu = fmpq(1, 2 ** 30)
        else:
            with workprec(64):
                nu = max(dyadic_upper(arb(norm).root(p) * arb(1 + 2 ** -40)) if p > 1 else norm, fmpq(1, 2 ** 30))
        C = max(norm_inf(powers[i]) / nu ** i for i in range(p))
        if best is None or nu < best[0]:
            best = (nu, C)
        p *= 2
    return best
