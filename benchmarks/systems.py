"""The benchmark systems, each with its exact data (for lcs_exact), its float data (for Siconos
and the scipy baseline) and the run it is benchmarked on.

A :class:`Case` holds the LCS matrices as rational strings, x0 (rational, or the exact vector
e^{-A} v of the paper's section 7), t_end, the relative degree r of the constraints (0: D > 0,
1: CB > 0 as in circuits, 2: CB = 0, CAB > 0 as in mechanics) and, for mechanical systems,
M, K, E so that Siconos can run its Lagrangian (Moreau-Jean, event-driven) schemes.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction


@dataclass
class Case:
    name: str
    label: str
    A: list
    B: list
    C: list
    D: list
    x0: list                      # rational entries, or None with x0_expm set
    t_end: Fraction
    r: int                        # uniform relative degree of y (0, 1 or 2)
    mech: dict | None = None      # {"M", "K", "E"} for the Lagrangian Siconos schemes
    x0_expm: tuple | None = None  # (A, t, v): x0 = e^{A t} v, exact
    stiff: bool = False
    note: str = ""
    fallback_t_end: Fraction | None = None   # used when the exact run at t_end hits the limit
    max_events: int = 1000
    extra: dict = field(default_factory=dict)

    def lcs(self):
        import lcs_exact as L
        return L.LCS(self.A, self.B, self.C, self.D, name=self.label)

    def exact_x0(self):
        import lcs_exact as L
        if self.x0_expm is not None:
            A, t, v = self.x0_expm
            return L.expm_action(A, t, v)
        return [Fraction(c) for c in self.x0]

    def float_x0(self) -> list[float]:
        if self.x0_expm is not None:
            import mpmath as mp
            A, t, v = self.x0_expm
            with mp.workdps(40):
                x = mp.expm(mp.matrix([[mp.mpf(Fraction(c).numerator) / Fraction(c).denominator
                                        for c in row] for row in A]) * t) * mp.matrix(v)
                return [float(c) for c in x]
        return [float(Fraction(c)) for c in self.x0]


def fr(v):
    return str(Fraction(v))


def text_matrix(m) -> list:
    """A flint matrix as rows of rational strings (what a Case holds)."""
    return [[str(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())]


def mechanical_data(M, K, E):
    """A, B, C, D of (8.3) for M q'' + K q = E^T u, y = E q (:func:`lcs_exact.models.mechanical`)."""
    import lcs_exact as L
    lcs = L.mechanics.mechanical(M, K, E)
    return tuple(text_matrix(m) for m in (lcs.A, lcs.B, lcs.C, lcs.D))


def two_carts() -> Case:
    M, K, E = [[1, 0], [0, 1]], [[2, -1], [-1, 1]], [[1, 0]]
    A, B, C, D = mechanical_data(M, K, E)
    return Case("two_carts", "two carts (sec. 7)", A, B, C, D, None, Fraction(3), 2,
                mech={"M": M, "K": K, "E": E}, x0_expm=(A, -1, [0, -1, -1, 0]),
                note="x0 = e^{-A}(0,-1,-1,0), T = 3: impact at 1, release at 1 + pi/2")


def rlc_diode() -> Case:
    # series R, L, C and an ideal diode: x = (v_C, i_L), y = i_L, u = reverse diode voltage;
    # L = C = 1, R = 1/2: v_C' = -i, i' = v_C - i/2 + u
    return Case("rlc_diode", "RLC + ideal diode", [[0, -1], [1, "-1/2"]], [[0], [1]],
                [[0, 1]], [[0]], [1, 0], Fraction(5), 1,
                note="series RLC (L = C = 1, R = 1/2) with an ideal diode, v_C(0) = 1; "
                     "the diode blocks at 4 pi / sqrt 15")


def d_positive() -> Case:
    # relative degree 0: y = x1 + u, so u = max(0, -x1): a damped piecewise-linear oscillator
    return Case("d_positive", "D > 0 (rel. degree 0)", [[0, 1], [-1, "-1/10"]], [[0], [1]],
                [[1, 0]], [[1]], [1, 0], Fraction(10), 0,
                note="x'' + x'/10 + x = u, y = x + u (D = 1): stiffness 1 for x > 0, 2 for x < 0")


def stiff_rc_diode() -> Case:
    # node 1: C1 = 1, R1 = 1 to ground; node 2: C2 = 1e-3, R2 = 1e-3 to ground; R12 = 1 between;
    # an ideal diode from ground to node 2 (y = v2 >= 0, u = its current into node 2)
    return Case("stiff_rc", "stiff RC + diode", [[-2, 1], [1000, -1001000]], [[0], [1000]],
                [[0, 1]], [[0]], [-1, 1], Fraction(5), 1, stiff=True,
                note="time constants 1e-6 and 0.5 (eigenvalues -1.001e6 and -1.999); the diode "
                     "clamps v2 at t ~ 7e-6")


def chain(N: int) -> Case:
    import lcs_exact as L
    lcs = L.examples.cart_chain(N)
    A, B, C, D = (text_matrix(m) for m in (lcs.A, lcs.B, lcs.C, lcs.D))
    # the Lagrangian data Siconos needs: M = I, K = -A[N:, :N], E = C[:, :N]
    M = [[1 if i == j else 0 for j in range(N)] for i in range(N)]
    K = [[int(-lcs.A[N + i, j]) for j in range(N)] for i in range(N)]
    E = [[int(lcs.C[r, j]) for j in range(N)] for r in range(lcs.k)]
    x0 = [fr(Fraction((-1) ** i, 2)) for i in range(N)] + [0] * N
    return Case(f"chain{N}", f"chain N = {N}", A, B, C, D, x0, Fraction(10), 2,
                mech={"M": M, "K": K, "E": E}, fallback_t_end=Fraction(3, 4),
                note=f"{N} unit carts, K = tridiag(-1, 2, -1) with K[N-1][N-1] = 1, stops on "
                     f"carts 0, 2, ..., q0 = (1, -1, ...)/2, v0 = 0, T = 10")


def long_run() -> Case:
    M, K, E = [[1, 0], [0, 2]], [[5, -2], [-2, 3]], [[1, 0]]
    A = [[0, 0, 1, 0], [0, 0, 0, 1], [-5, 2, 0, 0], [1, "-3/2", 0, 0]]
    return Case("long_run", "long run (1000 events)", A, [[0], [0], [1], [0]], [[1, 0, 0, 0]],
                [[0]], [1, "1/3", 0, "1/2"], Fraction(2000), 2, mech={"M": M, "K": K, "E": E},
                fallback_t_end=Fraction(200), max_events=1000,
                note="m = (1, 2), wall springs 3 and 1, coupling 2, a stop on q1, "
                     "x0 = (1, 1/3, 0, 1/2); T = 2000 with max_events = 1000")


def all_cases(quick: bool = False) -> list[Case]:
    chains = [chain(N) for N in (2, 4, 8, 16, 24, 32)]
    return [two_carts(), rlc_diode(), d_positive(), stiff_rc_diode(), *chains, long_run()]


def chain_k(N: int, k: int) -> Case:
    """The N-cart chain with stops on the first k even carts (all start at q = +1/2)."""
    c = chain(N)
    E = [[1 if j == i else 0 for j in range(N)] for i in range(0, 2 * k, 2)]
    A, B, C, D = mechanical_data(c.mech["M"], c.mech["K"], E)
    return Case(f"chain{N}_k{k}", f"chain N = {N}, k = {k}", A, B, C, D, c.x0, c.t_end, 2,
                mech={"M": c.mech["M"], "K": c.mech["K"], "E": E}, note=c.note)


def scaling_cases() -> list[Case]:
    return [chain_k(8, k) for k in (1, 2, 3, 4)]
