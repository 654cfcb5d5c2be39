"""Stiff systems whose A has a repeated eigenvalue (free masses: 0 is a double eigenvalue).

e^{At} is evaluated through the Jordan-Chevalley split A = S + N (reals.jordan_chevalley), so the
error bounds do not grow like e^{||A|| t}; the answers are derived by hand below.
"""
import mpmath as mp
import pytest
from flint import fmpq, fmpq_mat

import lcs_exact as L
from lcs_exact.reals import jordan_chevalley

from helpers import close, num

mp.mp.dps = 50


def free_pair(k):
    """Two unit masses joined by a spring k, no wall spring; stop on mass 1 (q1 >= 0)."""
    A = [[0, 0, 1, 0], [0, 0, 0, 1], [-k, k, 0, 0], [k, -k, 0, 0]]
    return L.LCS(A, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])


def first_crossing(f, a, b, h):
    x, fx = mp.mpf(a), f(mp.mpf(a))
    while x < b:
        y = x + h
        fy = f(y)
        if fy < 0 < fx:
            return mp.findroot(f, (x, y), solver="anderson")
        x, fx = y, fy
    raise AssertionError("no crossing")


@pytest.mark.parametrize("k", [10 ** 4, 10 ** 6])
def test_stiff_free_pair_first_impact(k):
    """From q = (1, 1), v = (-1, 0): centre c = 1 - t/2, difference d = -sin(ωt)/ω with ω = √(2k),
    so q1 = 1 - t/2 - sin(ωt)/(2ω). The impact is at its first root (near t = 2); v1 jumps to 0."""
    tr = L.simulate(free_pair(k), [1, 1, -1, 0], "21/10")
    assert tr.certified and len(tr.events) >= 1
    w = mp.sqrt(2 * k)
    f = lambda t: 1 - t / 2 - mp.sin(w * t) / (2 * w)
    # the oscillation is 1/(2ω) small: start scanning where 1 - t/2 < 1/(2ω), step << period
    start = 2 - 1 / w
    tau = first_crossing(f, start, mp.mpf(2) + 1 / w, 2 * mp.pi / w / 50)
    e = tr.events[0]
    assert close(num(e.time), tau)
    assert e.modes == (frozenset({0}),)
    q2 = 1 - tau / 2 + mp.sin(w * tau) / (2 * w)
    v2 = -mp.mpf(1) / 2 + mp.cos(w * tau) / 2
    after = [num(c) for c in e.state_after]
    assert after[0] == 0 and after[2] == 0
    assert close(after[1], q2) and close(after[3], v2)


def test_jordan_chevalley_split():
    """A = S + N with SN = NS, N nilpotent, S diagonalizable (minimal polynomial squarefree):
    for the free pair with k = 3, S = A - N with N = [[0, 0, 1/2, 1/2]]-type rank-one nilpotent."""
    A = fmpq_mat(4, 4, [0, 0, 1, 0, 0, 0, 0, 1, -3, 3, 0, 0, 3, -3, 0, 0])
    S, N, m = jordan_chevalley(A)
    assert S + N == A and S * N == N * S
    assert m == 2 and N * N == fmpq_mat(4, 4) and N != fmpq_mat(4, 4)
    # S annihilated by the squarefree part s(s^2 + 6) of χ = s^2 (s^2 + 6)
    I = fmpq_mat(4, 4, [int(i == j) for i in range(4) for j in range(4)])
    assert S * (S * S + 6 * I) == fmpq_mat(4, 4)
    # N is the centre-of-mass drift: q_i gains t (v1 + v2)/2, i.e. N = [[0, 0, 1/2, 1/2]] twice
    h = fmpq(1, 2)
    assert N == fmpq_mat(4, 4, [0, 0, h, h, 0, 0, h, h] + [0] * 8)
