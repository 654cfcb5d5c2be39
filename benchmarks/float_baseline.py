"""The float baseline: what a user might write with scipy instead of lcs_exact.

An event-driven loop around ``scipy.integrate.solve_ivp``: in mode I the constraints y_I = 0 are
held by u_I = -H_II^{-1} (C A^r x)_I (H = D for relative degree r = 0, C A^{r-1} B otherwise);
terminal events stop the integration when some u_i (i in I) or y_j (j not in I) crosses zero
downwards; the next mode is chosen by an LCP (Lemke's pivoting method, :func:`lcp`) at the level
of the first non-vanishing derivative (acceleration level for mechanics; for r = 0 the triggering
constraint is toggled, as the sign of y at the switch is a rounding error), and an impact (r = 2,
y_j = 0 with y_j' < 0) is resolved by the velocity-level LCP (Newton's law with e = 0, Moreau's
rule). Tolerances are plain floats (``tol_y``): exactly the kind of decision lcs_exact refuses to
take on a guess.
"""
from __future__ import annotations

import itertools
import time

import numpy as np
from scipy.integrate import solve_ivp


def lcp(W, q, eps=1e-12, max_pivots=None):
    """Solve 0 <= w = q + W u  ⊥  u >= 0 by Lemke's complementary pivoting (covering vector
    e = 1, lexicographic ratio test against cycling on degenerate LCPs), in floats with
    tolerances: O(k^2) per pivot, a handful of pivots on the LCPs here.  Finds the solution of
    every P-matrix LCP (W here is C A^{r-1} B or D of a well-posed system); raises RuntimeError
    on ray termination (no solution found)."""
    W = np.asarray(W, dtype=float)
    q = np.asarray(q, dtype=float)
    k = len(q)
    if k == 0:
        return np.zeros(0)
    if np.all(q >= -eps):
        return np.zeros(k)
    # tableau [B^-1 | B^-1 (-W) | B^-1 (-e) | B^-1 q] over the columns w (0..k-1), u (k..2k-1),
    # z0 (2k); the basis starts at w = q
    T = np.hstack([np.eye(k), -W, -np.ones((k, 1)), q.reshape(-1, 1)])
    basis = list(range(k))
    Z0 = 2 * k
    scale = 1.0 + np.abs(T).max()
    ptol = 1e-12 * scale

    def pivot(r, c):
        T[r] /= T[r, c]
        col = T[:, c].copy()
        col[r] = 0.0
        T[:] -= np.outer(col, T[r])

    # z0 enters where q is most negative; among ties the largest index keeps the rows
    # lexicographically positive
    qmin = q.min()
    r = max(i for i in range(k) if q[i] <= qmin + 1e-12 * (1.0 + abs(qmin)))
    pivot(r, Z0)
    leaving, basis[r] = basis[r], Z0
    for _ in range(max_pivots or 50 * (k + 1)):
        entering = leaving + k if leaving < k else leaving - k     # the complement
        d = T[:, entering]
        rows = np.nonzero(d > ptol)[0]
        if len(rows) == 0:
            raise RuntimeError("LCP: Lemke's ray termination (no solution found)")
        ratio = T[rows, -1] / d[rows]
        m = ratio.min()
        tied = rows[ratio <= m + 1e-12 * (1.0 + abs(m))]
        if any(basis[i] == Z0 for i in tied):
            r = next(i for i in tied if basis[i] == Z0)
        else:  # lexicographic rule on the rows of B^-1 / d
            for j in range(k):
                if len(tied) == 1:
                    break
                v = T[tied, j] / d[tied]
                tied = tied[v <= v.min() + 1e-12 * (1.0 + abs(v.min()))]
            r = int(tied[0])
        pivot(r, entering)
        leaving, basis[r] = basis[r], entering
        if leaving == Z0:
            u = np.zeros(k)
            for i, b in enumerate(basis):
                if k <= b < 2 * k:
                    u[b - k] = T[i, -1]
            return np.maximum(u, 0.0)
    raise RuntimeError("LCP: Lemke's algorithm did not end within its pivot limit")


def _lcp_enumerate(W, q, eps=1e-12):
    """The former float LCP, 2^k active sets: kept only as the reference of :func:`self_test`
    (no benchmark uses it)."""
    k = len(q)
    if k == 0:
        return np.zeros(0)
    if np.all(q >= -eps):
        return np.zeros(k)
    for size in range(1, k + 1):
        for S in itertools.combinations(range(k), size):
            S = list(S)
            try:
                uS = np.linalg.solve(W[np.ix_(S, S)], -q[S])
            except np.linalg.LinAlgError:
                continue
            u = np.zeros(k)
            u[S] = uS
            if np.all(uS >= -eps) and np.all(q + W @ u >= -eps * (1 + np.abs(q).max())):
                return np.maximum(u, 0.0)
    raise RuntimeError("LCP without solution (float enumeration)")


def self_test(trials=400, seed=1, kmax=8):
    """:func:`lcp` (Lemke) against :func:`_lcp_enumerate` on random P-matrix LCPs: symmetric
    positive definite W, nonsymmetric W = SPD + skew, and Delassus-like W = E M^-1 E^T of a
    cart chain; q Gaussian with some entries set to exactly 0 (degenerate pivots).  P-matrix
    LCPs have one solution, so both must return it.  Returns (trials, largest difference,
    largest complementarity/feasibility residual); raises AssertionError past 1e-8."""
    rng = np.random.default_rng(seed)
    worst = resid = 0.0
    for t in range(trials):
        k = 1 + t % kmax
        G = rng.standard_normal((k, k))
        kind = t % 3
        if kind == 0:
            W = G @ G.T + 0.1 * np.eye(k)
        elif kind == 1:
            S = rng.standard_normal((k, k))
            W = G @ G.T + 0.1 * np.eye(k) + (S - S.T)
        else:
            N = 2 * k + 1
            K = 2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1)
            E = np.zeros((k, N))
            E[np.arange(k), 2 * np.arange(k)] = 1.0
            W = E @ np.linalg.inv(K + np.eye(N)) @ E.T
        q = rng.standard_normal(k)
        q[rng.random(k) < 0.25] = 0.0
        u1, u2 = lcp(W, q), _lcp_enumerate(W, q)
        w = q + W @ u1
        worst = max(worst, float(np.abs(u1 - u2).max()) / (1.0 + float(np.abs(u2).max())))
        resid = max(resid, float(max(-w.min(), -u1.min(), np.abs(u1 * w).max(), 0.0)))
    assert worst < 1e-8 and resid < 1e-8, (worst, resid)
    return trials, worst, resid


def simulate_float(A, B, C, D, x0, T, r, rtol=1e-8, atol=None, method="DOP853", tol_y=1e-9,
                   max_segments=100000):
    """Event-driven float simulation; returns (segments, event_times, wall seconds).

    ``segments`` is a list of (t0, t1, dense_output) to sample the solution afterwards.
    """
    A, B, C, D = (np.array(M, dtype=float) for M in (A, B, C, D))
    atol = rtol if atol is None else atol
    k = C.shape[0]
    G = C @ np.linalg.matrix_power(A, r)                      # (C A^r) x
    H = D if r == 0 else C @ np.linalg.matrix_power(A, r - 1) @ B
    CA = C @ A
    t, x = 0.0, np.array(x0, dtype=float)
    segments, events = [], []
    start = time.perf_counter()
    banned = set()
    toggled = None  # r = 0: the mode after an event is the old one with the trigger toggled
    for _ in range(max_segments):
        if t >= T:
            break
        scale = 1.0 + np.abs(x).max()
        if r == 2:  # impact: velocity-level LCP on the closed constraints that approach
            y, yd = C @ x, CA @ x
            close = [i for i in range(k) if abs(y[i]) <= tol_y * scale]
            if any(yd[i] < -tol_y * scale for i in close):
                lam = lcp(H[np.ix_(close, close)], yd[close])
                x = x + B[:, close] @ lam
                events.append(t)
        # mode selection: LCP at the level of the first non-vanishing derivative
        if r == 0:
            act = list(range(k))
        elif r == 1:
            y = C @ x
            act = [i for i in range(k) if abs(y[i]) <= tol_y * scale]
        else:
            y, yd = C @ x, CA @ x
            act = [i for i in range(k) if abs(y[i]) <= tol_y * scale and abs(yd[i]) <= tol_y * scale]
        if toggled is not None:
            I = toggled
        else:
            u = lcp(H[np.ix_(act, act)], (G @ x)[act])
            I = [i for j, i in enumerate(act) if u[j] > 1e-12 * scale and i not in banned]
        out = [j for j in range(k) if j not in I]
        if I:
            F = -np.linalg.solve(H[np.ix_(I, I)], G[I])       # u_I = F x
            Acl = A + B[:, I] @ F
        else:
            F, Acl = np.zeros((0, A.shape[0])), A
        Yout = C[out] + (D[np.ix_(out, I)] @ F if r == 0 and I else 0)

        def rhs(_, z, Acl=Acl):
            return Acl @ z

        evs = []
        for row in F:
            def ev(_, z, row=row):
                return row @ z
            ev.terminal, ev.direction = True, -1
            evs.append(ev)
        for row in np.atleast_2d(Yout):
            if len(out) == 0:
                break
            def ev(_, z, row=row):
                return row @ z
            ev.terminal, ev.direction = True, -1
            evs.append(ev)
        sol = solve_ivp(rhs, (t, T), x, method=method, rtol=rtol, atol=atol, events=evs or None,
                        dense_output=True)
        t1 = float(sol.t[-1])
        segments.append((t, t1, sol.sol))
        if t1 - t < 1e-12 * max(1.0, T) and sol.status == 1:
            # a multiplier born at ~0 that decreases at once: leave its constraint out once
            fired = [j for j, te in enumerate(sol.t_events) if len(te)]
            banned = {I[j] for j in fired if j < len(I)}
        else:
            banned = set()
        x, t = sol.y[:, -1], t1
        toggled = None
        if sol.status == 1:
            events.append(t)
            if r == 0:  # y ~ 0 at the switch: decide by the trigger, not by the float sign
                fired = [j for j, te in enumerate(sol.t_events) if len(te)]
                I2 = set(I)
                for j in fired:
                    if j < len(I):
                        I2.discard(I[j])
                    else:
                        I2.add(out[j - len(I)])
                toggled = sorted(I2)
        elif sol.status != 0:
            raise RuntimeError(sol.message)
    wall = time.perf_counter() - start
    return segments, sorted(set(events)), wall


def sample(segments, ts):
    """States at the times ts (right limits at segment ends)."""
    out = []
    j = 0
    for t in ts:
        while j + 1 < len(segments) and t >= segments[j][1]:
            j += 1
        out.append(np.asarray(segments[j][2](t)))
    return np.array(out)
