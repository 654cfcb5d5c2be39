"""Two numerical solvers written as a user of lcs_exact would write them, from a zoo case's float
data only (A, B, C, D, x0, restitution, and the sources' values): they share no code with the
library.  The tests use them to check that a right solver passes ``ZooCase.assert_matches`` and a
wrong one fails it.

* :func:`backward_euler`: x_{k+1} = x_k + h (A x_{k+1} + B u_{k+1}), 0 <= C x_{k+1} + D u_{k+1} ⊥
  u_{k+1} >= 0, one LCP per step (impacts come out inelastic);
* :func:`moreau_jean`: the theta-method on x with velocity-level impacts for mechanical systems
  (D = 0, C B = 0): the constraints predicted closed (y + h/2 y' <= 0) get Newton's law
  y'_{k+1} + e y'_k >= 0 ⊥ impulse >= 0.

States that are sources (``case.sources``) are not integrated: they are set to their exact values
at every step, so a sine source keeps its amplitude.
"""
from __future__ import annotations

import itertools

import numpy as np


def solve_lcp(M: np.ndarray, q: np.ndarray, tol: float = 1e-12) -> np.ndarray:
    """u >= 0 with w = M u + q >= 0, u . w = 0, by enumeration of the complementary bases (k <= 8);
    among several solutions the one with the smallest support."""
    k = len(q)
    if np.all(q >= -tol):
        return np.zeros(k)
    for size in range(1, k + 1):
        for S in itertools.combinations(range(k), size):
            S = list(S)
            try:
                uS = np.linalg.solve(M[np.ix_(S, S)], -q[S])
            except np.linalg.LinAlgError:
                continue
            u = np.zeros(k)
            u[S] = uS
            w = M @ u + q
            if np.all(u >= -tol) and np.all(w >= -tol * (1 + np.abs(q).max())):
                return np.maximum(u, 0)
    raise RuntimeError("no solution of the LCP found")


def _pin_sources(x: np.ndarray, case, t: float) -> None:
    if case.sources is not None:
        x[list(case.sources.states)] = case.sources(t)


def _data_at(case, t: float):
    """(A, B, C, D) in force at t: a scheduled case's phase holding t, else the case's own."""
    phases = getattr(case, "schedule", None)
    if not phases:
        return case.A, case.B, case.C, case.D
    start = 0.0
    while True:
        for duration, A, B, C, D, _ in phases:
            if duration is None or t < start + duration - 1e-12:
                return A, B, C, D
            start += duration


def backward_euler(case, h: float, t_end: float | None = None, A=None, B=None, C=None, D=None, x0=None):
    """The implicit Euler time-stepper with one LCP per step; returns (t, X).  A scheduled case
    (``case.schedule``) steps with the data of the phase in force at each step's start (h must
    divide its durations)."""
    x = (case.x0 if x0 is None else x0).copy()
    T = case.t_end if t_end is None else t_end
    N = int(round(T / h))
    n = len(x)
    ts, X = [0.0], [x.copy()]
    for k in range(N):
        t1 = (k + 1) * h
        if A is None or k == 0 or getattr(case, "schedule", None):
            Ak, Bk, Ck, Dk = _data_at(case, k * h)
            Ak, Bk, Ck, Dk = (Ak if A is None else A), (Bk if B is None else B), (Ck if C is None else C), (Dk if D is None else D)
            Winv = np.linalg.inv(np.eye(n) - h * Ak)
            M = h * Ck @ Winv @ Bk + Dk
        free = Winv @ x
        u = solve_lcp(M, Ck @ free)
        x = free + h * Winv @ Bk @ u
        _pin_sources(x, case, t1)
        ts.append(t1)
        X.append(x.copy())
    return np.array(ts), np.array(X)


def moreau_jean(case, h: float, t_end: float | None = None, theta: float = 0.5, restitution=None, x0=None):
    """Moreau-Jean's time-stepping for a mechanical LCS (y = C x of relative degree 2); returns (t, X)."""
    A, B, C = case.A, case.B, case.C
    e = case.restitution if restitution is None else np.asarray(restitution, dtype=float)
    if e is None:
        e = np.zeros(C.shape[0])
    x = (case.x0 if x0 is None else x0).copy()
    T = case.t_end if t_end is None else t_end
    N = int(round(T / h))
    n = len(x)
    W = np.linalg.inv(np.eye(n) - h * theta * A)
    P = np.eye(n) + h * (1 - theta) * A
    CA = C @ A
    ts, X = [0.0], [x.copy()]
    for k in range(N):
        t1 = (k + 1) * h
        free = W @ (P @ x)
        y, ydot = C @ x, CA @ x
        active = np.flatnonzero(y + 0.5 * h * ydot <= 0)
        if active.size:
            Wp = CA @ W @ B  # y'_{k+1} = CA x_{k+1} = CA free + CA W B p
            M = Wp[np.ix_(active, active)]
            q = (CA @ free)[active] + e[active] * ydot[active]
            p = np.zeros(C.shape[0])
            p[active] = solve_lcp(M, q)
            x = free + W @ B @ p
        else:
            x = free
        _pin_sources(x, case, t1)
        ts.append(t1)
        X.append(x.copy())
    return np.array(ts), np.array(X)
