"""The scenes of ``benchmarks/battery.py``: systems built to break the engine, each a function
returning (lcs, x0, t_end, simulate's keyword arguments).

Groups (the number after ``s``): 1 symmetric copies and exact grazes in copies, 2 grazes next to
other blocks' events, 3 random chains of carts (n = 32 to 48), 4 stiff chains, 5 long runs of
blocks, 6 diode ladders (RLC, RC; relative degree 0 and 1), 7 hard inputs (quiet coupled runs,
events 10^-30 apart, 60 digits, huge rationals, unstable modes, restitution, starts on the
constraints, friction, copies with closed forms), 8 dips near zero (10^-8, 10^-20) and horizons
at events, 9 long runs and Newton's cradles and a bouncing ball's accumulation beside a chain,
10 wrapping (cyclic, skew), 11 coincidences and dips of 10^-60, 10^-200, 12 slow, fast and
300-digit chains, 64 carts, huge dynamic ranges and growth, 13 stiff RC ladders, near grazes
over long horizons, events at exact times, quiet copies.
"""
import random
from fractions import Fraction as F
from flint import fmpq, fmpq_mat
import lcs_exact as L
from lcs_exact.builders.mechanics import mechanical

def blockdiag(*systems):
    """block-diagonal LCS of several LCS"""
    n = sum(s.n for s in systems); m = sum(s.B.ncols() for s in systems)
    A = fmpq_mat(n, n); B = fmpq_mat(n, m); C = fmpq_mat(m, n); D = fmpq_mat(m, m)
    r = c = 0
    for s in systems:
        k = s.B.ncols()
        for i in range(s.n):
            for j in range(s.n): A[r + i, r + j] = s.A[i, j]
            for j in range(k): B[r + i, c + j] = s.B[i, j]
        for i in range(k):
            for j in range(s.n): C[c + i, r + j] = s.C[i, j]
            for j in range(k): D[c + i, c + j] = s.D[i, j]
        r += s.n; c += k
    res = []
    for s_ in systems:
        r_ = s_.restitution
        res += list(r_) if r_ is not None else [0] * s_.B.ncols()
    if any(e != 0 for e in res):
        return L.LCS(A, B, C, D, restitution=res)
    return L.LCS(A, B, C, D)

def outer_stops():
    A3 = [[0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1],
          [-1, 1, 0, 0, 0, 0], [1, -2, 1, 0, 0, 0], [0, 1, -1, 0, 0, 0]]
    return L.LCS(A3, [[0, 0], [0, 0], [0, 0], [1, 0], [0, 0], [0, 1]],
                 [[1, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0]], [[0, 0], [0, 0]]), A3

# ---- 1. symmetry ---------------------------------------------------------------------------
def s1a_carts_rational():
    c = L.models.two_carts()
    return blockdiag(*[c] * 8), [F(1, 2), F(-1, 3), 0, F(1, 5)] * 8, 12, {}

def s1b_outer_exact_graze():
    # 6 copies (n = 36) of the 3-mass chain from e^{-A}(0,1,0,0,1,0): exact grazes at t = 1 in every copy
    s, A3 = outer_stops()
    x = L.expm_action(A3, -1, [0, 1, 0, 0, 1, 0])
    return blockdiag(*[s] * 6), list(x) * 6, 6, {}

def s1c_outer_rational():
    s, A3 = outer_stops()
    return blockdiag(*[s] * 6), [1, 2, 1, -1, 0, -1] * 6, 6, {}

def mirror_chain(N, stops):
    K = [[2 if i == j else -1 if abs(i - j) == 1 else 0 for j in range(N)] for i in range(N)]
    E = [[int(j == i) for j in range(N)] for i in stops]
    return mechanical([[int(i == j) for j in range(N)] for i in range(N)], K, E)

def s1d_mirror_chain():
    N = 16
    lcs = mirror_chain(N, [0, 3, 12, 15])
    rnd = random.Random(7)
    half = [F(rnd.randint(-9, 9), rnd.randint(1, 9)) for _ in range(N // 2)]
    q = half + half[::-1]
    vh = [F(rnd.randint(-9, 9), rnd.randint(1, 9)) for _ in range(N // 2)]
    v = vh + vh[::-1]
    q[0] = q[-1] = F(1, 3); q[3] = q[12] = F(2, 7)
    return lcs, q + v, 8, {}

def s1e_scaled_copies():
    # copy k = (k+1) * base start: homogeneity -> simultaneous events in 8 copies, exact-real start
    c = L.models.two_carts()
    x = L.expm_action(c.A, -1, [0, -1, -1, 0])
    x0 = []
    for k in range(8):
        x0 += [xi * (k + 1) for xi in x]
    return blockdiag(*[c] * 8), x0, 8, {}

def s1f_mirror_exact():
    # mirror chain from an exact start e^{-A} (symmetric rational vector)
    N = 16
    lcs = mirror_chain(N, [0, 15])
    q = [F(1, 2)] + [F((-1) ** i, 3) for i in range(1, N - 1)] + [F(1, 2)]
    q = q[:N // 2] + q[:N // 2][::-1]
    v = [F(-1)] + [0] * (N - 2) + [F(-1)]
    x = L.expm_action(lcs.A, -F(1, 2), q + v)
    return lcs, list(x), 5, {}

# ---- 2. grazes -------------------------------------------------------------------------------
def s2a_graze_plus_chain():
    g = mechanical([[1]], [[1]], [[1]], gap=[1])        # y = 1 - sin t from (0, -1): graze at pi/2
    ch = L.examples.cart_chain(15)                        # n = 30 -> total 33
    x0 = [0, -1, 1] + [F((-1) ** i, 2) for i in range(15)] + [0] * 15
    return blockdiag(g, ch), x0, 4, {}

def s2b_graze_rational_double_root():
    osc = mechanical([[1]], [[4]], [[1]], gap=[5])        # y = 5 + 5 cos(2t - phi): touches 0
    ch = L.examples.cart_chain(15)
    x0 = [3, 8, 1] + [F(i % 3 + 1, 4) for i in range(15)] + [0] * 15
    return blockdiag(osc, ch), x0, 4, {}

def s2c_graze_coupled():
    # outer-stop graze (exact start) + 13 uncoupled carts chain (n = 6 + 26 = 32)
    s, A3 = outer_stops()
    ch = L.examples.cart_chain(13)
    x = L.expm_action(A3, -1, [0, 1, 0, 0, 1, 0])
    return blockdiag(s, ch), list(x) + [F(3, 4)] * 13 + [0] * 13, 3, {}

# ---- 3. clusters -----------------------------------------------------------------------------
def _chain_random(N, seed, T):
    rnd = random.Random(seed)
    lcs = L.examples.cart_chain(N)
    q = [F(rnd.randint(-20, 20), rnd.randint(1, 20)) for _ in range(N)]
    for i in range(0, N, 2):
        q[i] = abs(q[i]) + F(1, 100)
    v = [F(rnd.randint(-10, 10), rnd.randint(1, 10)) for _ in range(N)]
    return lcs, q + v, T, {}

def s3a_chain16(): return _chain_random(16, 1, 6)
def s3b_chain20(): return _chain_random(20, 2, 5)
def s3c_chain24(): return _chain_random(24, 3, 4)
def s3d_chain16_alt():
    lcs = L.examples.cart_chain(16)
    x0 = [F((-1) ** i, 2) + F(i, 10 ** 6) for i in range(16)] + [0] * 16   # nearly simultaneous
    return lcs, x0, 6, {}

# ---- 4. stiff --------------------------------------------------------------------------------
def _stiff_chain(N, k, kpos):
    K = [[0] * N for _ in range(N)]
    springs = [(-1, 0, 1)] + [(i, i + 1, k if i == kpos else 1) for i in range(N - 1)]
    for a, b, s in springs:
        if a >= 0:
            K[a][a] += s; K[b][b] += s; K[a][b] -= s; K[b][a] -= s
        else:
            K[b][b] += s
    E = [[int(j == i) for j in range(N)] for i in range(0, N, 2)]
    return mechanical([[int(i == j) for j in range(N)] for i in range(N)], K, E)

def s4a_stiff1500():
    N = 16
    lcs = _stiff_chain(N, 1500, 7)
    x0 = [F((-1) ** i, 2) for i in range(N)] + [0] * N
    return lcs, x0, 4, {}

def s4b_stiff1e4():
    N = 16
    lcs = _stiff_chain(N, 10 ** 4, 7)
    x0 = [F((-1) ** i, 2) for i in range(N)] + [0] * N
    return lcs, x0, 4, {}

def s4c_stiff_block():
    # stiff free pair (k = 2000, stop on mass 1) + cart chain 14 (n = 4 + 28 = 32)
    k = 2000
    fp = L.LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-k, k, 0, 0], [k, -k, 0, 0]], [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])
    ch = L.examples.cart_chain(14)
    return blockdiag(fp, ch), [1, 1, -1, 0] + [F((-1) ** i, 2) for i in range(14)] + [0] * 14, F(21, 10), {}

# ---- 5. long runs ----------------------------------------------------------------------------
def s5a_long_blocks():
    c = L.models.two_carts()
    rnd = random.Random(11)
    x0 = []
    for k in range(8):
        x0 += [F(rnd.randint(1, 9), 10), F(rnd.randint(-9, 9), 10), F(rnd.randint(-9, 9), 10), F(rnd.randint(-9, 9), 10)]
    return blockdiag(*[c] * 8), x0, 200, {'max_events': 200}

def s5b_chain_long():
    lcs = L.examples.cart_chain(16)
    x0 = [F((-1) ** i, 2) for i in range(16)] + [0] * 16
    return lcs, x0, 300, {'max_events': 150}

# ---- 6. circuits -----------------------------------------------------------------------------
def rlc_diode_ladder(N, r):
    """N sections: node capacitor C_i=1 to ground, inductor L=1 (with series R=1/10) from node i-1
    (node -1 = ground) to node i; a diode clamp (series r) at each node: y_i = v_i + r u_i >= 0.
    state: v_0..v_{N-1}, i_0..i_{N-1} (i_k flows into node k from node k-1)."""
    n = 2 * N
    A = [[F(0)] * n for _ in range(n)]
    Rs = F(1, 10)
    for k in range(N):
        # C dv_k = i_k - i_{k+1} + u_k
        A[k][N + k] += 1
        if k + 1 < N: A[k][N + k + 1] -= 1
        # L di_k = v_{k-1} - v_k - Rs i_k
        if k >= 1: A[N + k][k - 1] += 1
        A[N + k][k] -= 1
        A[N + k][N + k] -= Rs
    B = [[F(int(i == j)) if i < N else F(0) for j in range(N)] for i in range(n)]
    C = [[F(int(i == j)) for j in range(n)] for i in range(N)]
    D = [[F(r) if i == j else F(0) for j in range(N)] for i in range(N)]
    return L.LCS(A, B, C, D)

def s6a_diode_rlc_reldeg0():
    N = 16
    lcs = rlc_diode_ladder(N, F(1, 2))
    rnd = random.Random(5)
    x0 = [F(rnd.randint(0, 9), 4) for _ in range(N)] + [F(rnd.randint(-9, 9), 4) for _ in range(N)]
    return lcs, x0, 8, {}

def s6b_diode_rlc_reldeg1():
    N = 16
    lcs = rlc_diode_ladder(N, 0)
    rnd = random.Random(6)
    x0 = [F(rnd.randint(0, 9), 4) for _ in range(N)] + [F(rnd.randint(-9, 9), 4) for _ in range(N)]
    return lcs, x0, 8, {}

def rc_diode_ladder(N, r):
    """first order RC ladder (n = N): resistors 1 between nodes and to ground at node 0, a
    capacitor 1 at each node, a constant source state '1' driving node 0 through R=1 with -1 V,
    diode clamps with series r."""
    n = N + 1
    A = [[F(0)] * n for _ in range(n)]
    for k in range(N):
        # dv_k = sum (v_j - v_k) over neighbours; node 0 connected to source -1 via R=1
        if k > 0:
            A[k][k - 1] += 1; A[k][k] -= 1
        else:
            A[0][N] += -1; A[0][0] -= 1   # current (-1 - v0)
        if k + 1 < N:
            A[k][k + 1] += 1; A[k][k] -= 1
    B = [[F(int(i == j)) if i < N else F(0) for j in range(N)] for i in range(n)]
    C = [[F(int(i == j)) for j in range(n)] for i in range(N)]
    D = [[F(r) if i == j else F(0) for j in range(N)] for i in range(N)]
    return L.LCS(A, B, C, D)

def s6c_rc_ladder_reldeg0():
    N = 33
    lcs = rc_diode_ladder(N, F(1, 3))
    x0 = [F(N - k, N) for k in range(N)] + [1]
    return lcs, x0, 30, {}

def s6d_rc_ladder_reldeg1():
    N = 33
    lcs = rc_diode_ladder(N, 0)
    x0 = [F(N - k, N) for k in range(N)] + [1]
    return lcs, x0, 30, {}

# ================= round 2 =====================================================================
def _chain_K(N, wall=1):
    K = [[2 if i == j else -1 if abs(i - j) == 1 else 0 for j in range(N)] for i in range(N)]
    K[N - 1][N - 1] = 1
    K[0][0] = 1 + wall
    return K

def _slow_oscillator_and_chain(off, N):
    """A of q'' = -q/6400 (states 0, 1) and a free chain of N carts (positions from ``off``,
    velocities after them); states between 2 and ``off`` are constant."""
    n = off + 2 * N
    A = [[F(0)] * n for _ in range(n)]
    A[0][1] = 1; A[1][0] = F(-1, 6400)
    K = _chain_K(N)
    for i in range(N):
        A[off + i][off + N + i] = 1
        for j in range(N):
            A[off + N + i][off + j] = -K[i][j]
    return A


def _quiet_coupled(eps, amplitude):
    """slow oscillator q'' = -q/6400 (stop on y = q + eps*c0) + a chain of 15 carts (no stops),
    the carts started at +-amplitude."""
    N = 15
    A = _slow_oscillator_and_chain(2, N)
    n = len(A)
    B = [[F(0)] for _ in range(n)]; B[1][0] = F(1)
    C = [[F(0)] * n]; C[0][0] = F(1); C[0][2] = eps
    lcs = L.LCS(A, B, C, [[0]])
    x0 = [1, 0] + [amplitude * (-1) ** i for i in range(N)] + [0] * N
    return lcs, x0


def s7a_quiet_long_coupled():
    """slow oscillator q'' = -q/6400 (stop on y = q + eps*c0) + a chain of 15 carts (no stops):
    one long quiet phase of ~126 time units (~503 units of ||A|| t) on Taylor steps."""
    lcs, x0 = _quiet_coupled(F(1, 1000), F(1, 2))
    return lcs, x0, 127, {}

def s7b_stiff_short():
    N = 16
    lcs = _stiff_chain(N, 1500, 7)
    q = [F(i + 1, 1000) for i in range(N)]
    v = [F(-1)] * N
    return lcs, q + v, F(1, 6), {}

def s7c_1e30_apart():
    two = mechanical([[1, 0], [0, 1]], [[1, 0], [0, 1]], [[1, 0], [0, 1]])
    ch = L.examples.cart_chain(14)
    x0 = [1, 1, 0, fmpq(-1, 10 ** 30)] + [F((-1) ** i, 2) for i in range(14)] + [0] * 14
    return blockdiag(two, ch), x0, 3, {}

def s7d_high_digits():
    lcs = L.examples.cart_chain(16)
    x0 = [F((-1) ** i, 2) for i in range(16)] + [0] * 16
    return lcs, x0, 6, {'digits': 200}

def s7e_huge_rationals():
    lcs = L.examples.cart_chain(16)
    big = 10 ** 40
    x0 = [F((-1) ** i * (big + i), 2 * big + 1) for i in range(16)] + [F(1, big)] * 16
    return lcs, x0, 6, {}

def s7f_unstable():
    N = 16
    K = [[k - 3 * (i == j) for j, k in enumerate(row)] for i, row in enumerate(_chain_K(N))]
    E = [[int(j == i) for j in range(N)] for i in range(0, N, 2)]
    lcs = mechanical([[int(i == j) for j in range(N)] for i in range(N)], K, E)
    x0 = [F(1, 2) if i % 2 == 0 else F(-1, 3) for i in range(N)] + [0] * N
    return lcs, x0, 8, {}

def s7g_damped_restitution():
    N = 16
    E = [[int(j == i) for j in range(N)] for i in range(0, N, 2)]
    Dm = [[F(1, 10) if i == j else 0 for j in range(N)] for i in range(N)]
    lcs = mechanical([[int(i == j) for j in range(N)] for i in range(N)], _chain_K(N), E, damping=Dm,
                     restitution=F(1, 2))
    x0 = [F((-1) ** i, 2) for i in range(N)] + [0] * N
    return lcs, x0, 8, {}

def s7h_start_on_constraints():
    lcs = L.examples.cart_chain(16)
    q = [0 if i % 2 == 0 else F(-1, 2) for i in range(16)]
    v = [0 if i % 2 == 0 else F(1, 3) for i in range(16)]
    return lcs, q + v, 6, {}

def s7i_friction_chain():
    N = 16
    K = _chain_K(N)
    n = 2 * N
    A = [[F(0)] * n for _ in range(n)]
    for i in range(N):
        A[i][N + i] = 1
        for j in range(N):
            A[N + i][j] = -K[i][j]
    fr = [0, 5, 10, 15]
    B = [[F(-1, 2) if (i - N) == c else F(0) for c in fr] for i in range(n)]
    C = [[F(int(j == N + c)) for j in range(n)] for c in fr]
    from lcs_exact.builders.relays import relay
    lcs = relay(A, B, C)
    x = [F((-1) ** i, 2) for i in range(N)] + [0] * N
    return lcs, lcs.embed(x), 10, {}

def s7j_copies_closed_forms():
    c = L.models.two_carts()
    x = L.expm_action(c.A, -1, [0, -1, -1, 0])
    return blockdiag(*[c] * 8), list(x) * 8, 5, {'closed_forms': 'eager'}

# ================= round 3 =====================================================================
def _neargraze(gap):
    g = mechanical([[1]], [[1]], [[1]], gap=[gap])        # y = gap - sin t from (0, -1)
    ch = L.examples.cart_chain(15)                        # n = 30 -> total 33
    x0 = [0, -1, 1] + [F(1 + i, 5) for i in range(15)] + [0] * 15
    # chain carts well inside: even carts start at positive q; may still hit
    return blockdiag(g, ch), x0

def s8a_dip_1e8():
    lcs, x0 = _neargraze(1 - fmpq(1, 10 ** 8)); return lcs, x0, 2, {}
def s8b_dip_1e20():
    lcs, x0 = _neargraze(1 - fmpq(1, 10 ** 20)); return lcs, x0, 2, {}
def s8c_above_1e20():
    lcs, x0 = _neargraze(1 + fmpq(1, 10 ** 20)); return lcs, x0, 2, {}

def s8d_horizon_at_event():
    import sympy as sp
    c = L.models.two_carts()
    x = L.expm_action(c.A, -1, [0, -1, -1, 0])
    return blockdiag(*[c] * 8), list(x) * 8, 1 + sp.pi / 2, {}

def s8e_horizon_at_rational_event():
    c = L.models.two_carts()
    x = L.expm_action(c.A, -1, [0, -1, -1, 0])
    return blockdiag(*[c] * 8), list(x) * 8, 1, {}

def s8f_ball_zeno_plus_chain():
    b = L.examples.bouncing_ball(g=10, e=F(1, 2))
    ch = L.examples.cart_chain(15, stops=[])  if False else None
    ch = mechanical([[int(i == j) for j in range(15)] for i in range(15)], _chain_K(15), [[1] + [0] * 14], gap=[10])
    return blockdiag(b, ch), [5, 0, 1] + [F((-1) ** i, 2) for i in range(15)] + [0] * 15 + [1], 4, {}

def s8g_rectifier_copies():
    r = L.examples.sine_rectifier()
    x = list(r.embed([0]))
    rs = [L.examples.sine_rectifier(omega=F(k + 1, 2), R=F(k + 2, 3)) for k in range(11)]
    return blockdiag(*rs), sum((list(s.embed([F(k, 7)])) for k, s in enumerate(rs)), []), 10, {}

def s8h_halfwave_copies_exact():
    r = L.examples.half_wave_rectifier()
    rs = [r] * 16
    x = L.expm_action(r.A, -F(1, 3), [0, -1])
    return blockdiag(*rs), list(x) * 16, 12, {}

# ================= round 4 =====================================================================
def s9a_rect_long():
    lcs, x0, T, kw = s8g_rectifier_copies(); return lcs, x0, 60, {'max_events': 600}
def s9b_rlc_long():
    lcs, x0, T, kw = s6a_diode_rlc_reldeg0(); return lcs, x0, 100, {'max_events': 600}
def s9c_chain_long_taylor():
    lcs, x0, T, kw = _chain_random(16, 9, 120); kw['max_events'] = 600; return lcs, x0, T, kw

def cradle_springs(N, e):
    K = [[int(i == j) for j in range(N)] for i in range(N)]
    E = [[(1 if j == i + 1 else -1 if j == i else 0) for j in range(N)] for i in range(N - 1)]
    return mechanical([[int(i == j) for j in range(N)] for i in range(N)], K, E, restitution=e)

def s9d_cradle_e1():
    N = 16
    return cradle_springs(N, 1), [0] * N + [1] + [0] * (N - 1), 4, {}
def s9e_cradle_e_half():
    N = 16
    return cradle_springs(N, F(1, 2)), [0] * N + [1] + [0] * (N - 1), 4, {}
def s9f_ball_zeno_plus_chain():
    return s8f_ball_zeno_plus_chain()
def s9g_chain32():
    return _chain_random(32, 4, 3)
def s9h_chain48():
    return _chain_random(48, 5, 2)

def s9i_rect_1000():
    lcs, x0, T, kw = s8g_rectifier_copies(); return lcs, x0, 100, {'max_events': 1000, 'time_limit': 400}

# ================= round 5: wrapping =========================================================
def s10a_cyclic_wrapping(c=8, T=F(319, 10)):
    """cyclic consensus block x_i' = c (x_{i+1} - x_i) (n = 30, ||A|| = 2c, |A| has spectral radius
    2c: plain balls grow e^{2ct}) + slow oscillator q'' = -q/400, stop y = q + x_cyc0/10 >= 0."""
    m = 30
    n = m + 2
    A = [[F(0)] * n for _ in range(n)]
    A[0][1] = 1; A[1][0] = F(-1, 400)
    for i in range(m):
        A[2 + i][2 + i] = -c
        A[2 + i][2 + (i + 1) % m] = c
    B = [[F(0)] for _ in range(n)]; B[1][0] = F(1)
    C = [[F(0)] * n]; C[0][0] = F(1); C[0][2] = F(1, 10)
    lcs = L.LCS(A, B, C, [[0]])
    rnd = random.Random(3)
    x0 = [1, 0] + [F(rnd.randint(-9, 9), 10) for _ in range(m)]
    return lcs, x0, T, {}

def s10b_chain_wrapping():
    """s7a with eps = 1 instead of 1/1000 (chain amplitude 1/100)."""
    lcs, x0 = _quiet_coupled(F(1), F(1, 100))
    return lcs, x0, 127, {}

def s10c_skew_wrapping():
    """dense-ish skew rotation block: A = c (P - P^T) on 30 coords (eigenvalues imaginary, |A| spectral
    radius 2c), + slow oscillator; stop y = q + x_0/10."""
    m = 30; c = 8
    n = m + 2
    A = [[F(0)] * n for _ in range(n)]
    A[0][1] = 1; A[1][0] = F(-1, 400)
    for i in range(m):
        A[2 + i][2 + (i + 1) % m] += c
        A[2 + (i + 1) % m][2 + i] -= c
    B = [[F(0)] for _ in range(n)]; B[1][0] = F(1)
    C = [[F(0)] * n]; C[0][0] = F(1); C[0][2] = F(1, 10)
    lcs = L.LCS(A, B, C, [[0]])
    rnd = random.Random(4)
    x0 = [1, 0] + [F(rnd.randint(-9, 9), 10) for _ in range(m)]
    return lcs, x0, F(319, 10), {}

# ================= round 6 ===================================================================
def s11a_triple_root():
    fp = L.LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-1, 1, 0, 0], [1, -1, 0, 0]], [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])
    x = L.expm_action(fp.A, -1, [0, 0, 0, -1])
    ch = L.examples.cart_chain(14)
    return blockdiag(fp, ch), list(x) + [F(3, 4) + F(i, 100) for i in range(14)] + [0] * 14, 2, {}

def s11b_rational_coincidence():
    c = L.models.two_carts()
    x = L.expm_action(c.A, -1, [0, -1, -1, 0])          # event at t = 1 exactly
    fm = mechanical([[1]], [[0]], [[1]], force=[0])      # free mass q'' = u, y = q (+ const state)
    fm = L.LCS([[0, 1], [0, 0]], [[0], [1]], [[1, 0]], [[0]])
    ch = L.examples.cart_chain(13)
    # free mass from q = 1, v = -1 hits at t = 1; chain carts positive and slow
    return blockdiag(c, fm, ch), list(x) + [1, -1] + [F(3, 4)] * 13 + [0] * 13, 3, {}

def s11c_transcendental_coincidence():
    c = L.models.two_carts()
    x = L.expm_action(c.A, -1, [0, -1, -1, 0])          # events at 1 and 1 + pi/2
    osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    xo = L.expm_action(osc.A, -1, [1, 0])                # q = cos(t - 1): hits at 1 + pi/2
    ch = L.examples.cart_chain(13)
    return blockdiag(c, osc, ch), list(x) + list(xo) + [F(3, 4)] * 13 + [0] * 13, 3, {}

def s11d_dip_1e60():
    lcs, x0 = _neargraze(1 - fmpq(1, 10 ** 60)); return lcs, x0, 2, {}
def s11e_dip_1e200():
    lcs, x0 = _neargraze(1 - fmpq(1, 10 ** 200)); return lcs, x0, 2, {}
def s11f_above_1e200():
    lcs, x0 = _neargraze(1 + fmpq(1, 10 ** 200)); return lcs, x0, 2, {}

def s11g_fullwave_copies():
    rs = [L.examples.sine_rectifier(omega=F(k + 2, 3), full_wave=True) for k in range(11)]
    return blockdiag(*rs), sum((list(s.embed([F(k, 9)])) for k, s in enumerate(rs)), []), 8, {}

def s11h_bridge_copies():
    rs = [L.examples.diode_bridge(R=F(7 + k, 6)) for k in range(16)]
    r0 = rs[0]
    x = []
    for k in range(16):
        v = [0] * r0.n; v[0] = F(k + 1, 4); x += v
    return blockdiag(*rs), x, 8, {}

# ================= round 7 ===================================================================
def _scaled_chain(N, scale, seed, T):
    lcs, x0, _, kw = _chain_random(N, seed, 1)
    A = lcs.A * fmpq(scale)
    return L.LCS(A, lcs.B * fmpq(scale), lcs.C, lcs.D), x0, T, kw

def s12a_slow_chain(): return _scaled_chain(16, fmpq(1, 1000), 1, 6000)
def s12b_fast_chain(): return _scaled_chain(16, 1000, 1, F(6, 1000))
def s12c_digits300():
    lcs, x0, T, kw = _chain_random(16, 1, 3); kw['digits'] = 300; return lcs, x0, T, kw
def s12d_chain64():
    return _chain_random(64, 8, 1)
def s12e_maxprec256_long():
    lcs, x0, T, kw = _chain_random(16, 9, 120); kw['max_events'] = 600; kw['max_prec'] = 256; return lcs, x0, T, kw
def s12f_maxprec256_rect():
    lcs, x0, T, kw = s8g_rectifier_copies(); kw['max_prec'] = 256; return lcs, x0, 30, kw

def s12g_huge_entry():
    lcs = L.examples.cart_chain(16)
    q = [F(1, 2)] * 16
    q[15] = F(10 ** 400)            # far cart (no stop): the chain is pulled by it
    v = [0] * 16
    return lcs, q + v, F(1, 2), {}

def s12h_huge_dynamic_range():
    lcs = L.examples.cart_chain(16)
    q = [F((-1) ** i, 10 ** 300) for i in range(16)]
    q[1] = F(10 ** 300)
    return lcs, q + [0] * 16, 1, {}

def s12i_unstable_growth():
    """symmetric cyclic coupling with growth e^{8t}: A = 4 (P + P^T) on 30 coords + oscillator with stop
    y = q - x_c0 * 10^-60 (a huge growing term hits late)."""
    m = 30
    n = m + 2
    A = [[F(0)] * n for _ in range(n)]
    A[0][1] = 1; A[1][0] = F(-1)
    for i in range(m):
        A[2 + i][2 + (i + 1) % m] += 4
        A[2 + (i + 1) % m][2 + i] += 4
    B = [[F(0)] for _ in range(n)]; B[1][0] = F(1)
    C = [[F(0)] * n]; C[0][0] = F(1); C[0][2] = -fmpq(1, 10 ** 60)
    lcs = L.LCS(A, B, C, [[0]])
    x0 = [F(1, 2), 0] + [F(1, 1)] * m
    return lcs, x0, 40, {}

def s12j_fullwave_plus_chain():
    rs = [L.examples.sine_rectifier(omega=F(k + 2, 3), full_wave=True) for k in range(3)]
    ch = L.examples.cart_chain(12, stops=[0])
    x0 = sum((list(s.embed([F(k, 9)])) for k, s in enumerate(rs)), []) + [F((-1) ** i, 2) for i in range(12)] + [0] * 12
    return blockdiag(*rs, ch), x0, 8, {}

def s12k_friction_plus_halfwave():
    lcs, x0, T, kw = s7i_friction_chain()
    return lcs, x0, 20, {}

# ================= round 8 ===================================================================
def s13a_stiff_rc():
    lcs = rc_diode_ladder(33, F(1, 3))
    A = lcs.A * fmpq(500)
    B = lcs.B * fmpq(500)
    x0 = [F(33 - k, 33) for k in range(33)] + [1]
    return L.LCS(A, B, lcs.C, lcs.D), x0, F(1, 5), {}

def s13b_slow_neargraze(depth=25):
    """slow oscillator q = -sin(t/80) with y = q + (1 - 10^-depth) (exo state), dip at t = 40 pi,
    plus chain 15 coupled into y by 1/1000 c0... (n = 33)"""
    N = 15
    A = _slow_oscillator_and_chain(3, N)
    n = len(A)
    B = [[F(0)] for _ in range(n)]; B[1][0] = F(1)
    C = [[fmpq(0)] * n]; C[0][0] = fmpq(1); C[0][2] = 1 - fmpq(1, 10 ** depth)
    lcs = L.LCS(A, B, C, [[0]])
    x0 = [0, F(-1, 80), 1] + [F((-1) ** i, 2) for i in range(N)] + [0] * N
    return lcs, x0, 127, {}

def s13c_cyclic_digits250():
    lcs, x0, T, kw = s10a_cyclic_wrapping(); kw['digits'] = 250; return lcs, x0, T, kw

def s13d_event_at_t2():
    c = L.models.two_carts()
    x = L.expm_action(c.A, -2, [0, -1, -1, 0])
    x2 = L.expm_action(c.A, -F(3, 2), [0, -1, -1, 0])
    return blockdiag(*([c] * 4 + [c] * 4)), list(x) * 4 + list(x2) * 4, 4, {}

def s13e_quiet_copies(digits=30):
    """slow oscillator (q'' = -q/10^4, stop) + 15 unit oscillators coupled into the stop row by 1/10:
    y = q + sum_i x_i / 10 ... (quiet ~157 time units, norm 1, h = 4)."""
    m = 15
    n = 2 + 2 * m
    A = [[F(0)] * n for _ in range(n)]
    A[0][1] = 1; A[1][0] = F(-1, 10 ** 4)
    for i in range(m):
        A[2 + 2 * i][3 + 2 * i] = 1; A[3 + 2 * i][2 + 2 * i] = -1
    B = [[F(0)] for _ in range(n)]; B[1][0] = F(1)
    C = [[F(0)] * n]; C[0][0] = F(1)
    for i in range(m):
        C[0][2 + 2 * i] = F(1, 1000)
    lcs = L.LCS(A, B, C, [[0]])
    x0 = [1, 0] + [F(1, i + 2) for i in range(2 * m)]
    return lcs, x0, 200, {'digits': digits}

def s13f_quiet_copies_d100():
    return s13e_quiet_copies(100)
