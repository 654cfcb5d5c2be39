"""e^{Mt} for a rational matrix M: spectral balls, modal coefficients, exact values at closed forms.

Representation (:class:`Spectrum`, one per matrix, cached by its owner - the mode of section 4.1
holds the spectrum of its closed-loop matrix A_I): the exact Jordan-Chevalley split M = S + N
(S semisimple, N nilpotent, SN = NS, both polynomials in M with rational coefficients), the
squarefree part r of the characteristic polynomial (the minimal polynomial of S), and

    e^{Mt} = sum_lambda e^{lambda t} K_lambda sum_{j < m} t^j N^j / j!,
    K_lambda = q_lambda(S) / r'(lambda),  q_lambda(s) = r(s) / (s - lambda),

the spectral projectors of S (``adj(lambda I - M) / chi'(lambda)`` when chi is squarefree).  The
eigenvalues are certified complex balls of the roots of r; real ones are exact-real balls; of a
conjugate pair only the one with positive imaginary part is kept, with weight 2 (the sum is real:
K of the conjugate is the conjugate of K).  Unlike ``arb_mat.exp`` (whose error bounds grow like
e^{||M|| t}) the sum has no norm blow-up for stiff or oscillatory M: each term carries its own
e^{Re(lambda) t}.

:meth:`Spectrum.modal` gives the per-eigenvalue vectors w_{lambda,j} = K_lambda N^j z / j! of a
state z (computed once per phase), from which every constraint function g e^{Mt} z of the phase
is an exponential sum (:mod:`lcs_exact.roots`).
"""
from __future__ import annotations

import math
from typing import Any, Callable

from flint import acb, acb_mat, acb_poly, arb, arb_mat, fmpq, fmpq_mat, fmpq_poly, fmpz_mat

from .balls import workprec
from .krylov import evaluate_columns, exact_poly, factor_accuracy, horner_vectors, primary_basis, vandermonde
from ..errors import UnresolvedSign
from ..algebra import adjugate_coefficients, identity, is_zero, polys_at_matrix, zeros

__all__ = ["Spectrum", "jordan_chevalley", "spectrum_of"]


def jordan_chevalley(M: fmpq_mat, r: fmpq_poly | None = None) -> tuple[fmpq_mat, fmpq_mat, int]:
    """(S, N, m): M = S + N with S semisimple, N nilpotent (N^m = 0), SN = NS, both exact.

    S is a polynomial in M found by Newton's iteration S <- S - r(S) r'(S)^{-1} on the squarefree
    part r of chi (exact in Q[M]; quadratic convergence, so about log2(max multiplicity) steps).

    >>> S, N, m = jordan_chevalley(fmpq_mat([[0, 1], [0, 0]]))
    >>> S.entries(), N.entries(), m
    ([0, 0, 0, 0], [0, 1, 0, 0], 2)
    """
    chi = M.charpoly()
    if r is None:
        r = fmpq_poly(chi / chi.gcd(chi.derivative()))
    r = r / r.coeffs()[-1]
    dr = r.derivative()
    S = M
    for _ in range(M.nrows() + 1):
        rS, drS = polys_at_matrix([r, dr], S)
        if is_zero(rS):
            break
        X = drS.solve(rS)  # r'(S)^{-1} r(S) (they commute)
        S = S - X
        # X = E U with E = S - (semisimple part), U invertible, all commuting: X^2 = 0 means E^2 = 0,
        # and then one Newton step is exact (no r(S) = 0 check, a whole polynomial evaluation)
        if is_zero(X * X):
            break
    N = M - S
    m, P = 1, N
    while not is_zero(P):
        P, m = P * N, m + 1
    return S, N, m


#: matrices up to this size estimate the Krylov guard from a norm, not from float eigenvalues
SMALL_GUARD_N = 8

#: bits the spectral factors are computed beyond a doubled precision (covers the guard bits
#: a root or an eigenvalue asks on top of a working precision)
FACTOR_HEADROOM = 64


class Spectrum:
    """Spectral data of e^{Mt} for a rational M (see the module docstring); balls on demand.

    Cost: O(n^3) per matrix and precision, O(n^2) per state; nothing builds an n x n matrix per
    eigenvalue.  The projector of an eigenvalue lambda of multiplicity m is stored in factored
    form K_lambda = R_lambda G_lambda^{-1} L_lambda, with R = K_lambda C, L = C'^T K_lambda for
    fixed integer n x m matrices C, C' and G = C'^T K_lambda C (invertible for almost every C, C';
    certified, else other C, C' are drawn): if K = X Y^T with Y^T X = I, then
    R G^{-1} L = X (Y^T C) (Y^T C)^{-1} (C'^T X)^{-1} (C'^T X) Y^T = K.  The columns
    K_lambda c = q_lambda(S) c / r'(lambda) of all eigenvalues at once come from the d Krylov
    (Horner) vectors b_i(S) c, b_0 = 1, b_i(s) = s b_{i-1}(s) + r_{d-i} (exact, in integers:
    :mod:`.krylov`), times the matrix of lambda^{d-1-i} / r'(lambda); multiple eigenvalues from
    the exact primary projector of their factor f of r and the Horner vectors of f.  That product
    is ill-conditioned (about 300 bits at n = 128), but it sees only the exact integer vectors C,
    never a state: a state's ball is carried through the factors, of the projector's size.

    Parameters
    ----------
    M : fmpq_mat

    >>> sp = Spectrum(fmpq_mat([[0, 1], [-1, 0]]))       # rotation: e^{Mt} = [[cos, sin], [-sin, cos]]
    >>> x = sp.apply(arb.pi() / 2, arb_mat([[1], [0]]), 64)
    >>> abs(x[0, 0]) < 1e-15, abs(x[1, 0] + 1) < 1e-15
    (True, True)
    """

    def __init__(self, M: fmpq_mat):
        self.M = M
        self.n = M.nrows()
        self._irreducible: list | None = None  # [(p, multiplicity in chi)], on first use
        self._roots: tuple = (0, [])  # (prec, [(lambda, weight, multiplicity)])
        self._factors: tuple = (0, [])  # (prec, [(lambda, weight, R_lambda, G^-1 L_lambda)])
        self._guard = 24  # bits the Krylov basis loses, learnt per matrix

    def __getattr__(self, name: str):
        # the decomposition on first use: a closed-form search mostly needs M alone (its candidates
        # come from chi's factors), and Jordan-Chevalley costs 90 ms at n = 128
        if name in ("chi", "r", "S", "N", "nilpotent") and "M" in self.__dict__:
            self._decompose()
            return self.__dict__[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _decompose(self) -> None:
        """chi, r (its squarefree part), M = S + N (Jordan-Chevalley) and N^j / j!."""
        M, n = self.M, self.n
        chi = M.charpoly()
        g = chi.gcd(chi.derivative())
        if g.degree() <= 0:
            r = chi
            S, N, m = M, zeros(n, n), 1
        else:
            r = fmpq_poly(chi / g)
            r = r / r.coeffs()[-1]
            S, N, m = jordan_chevalley(M, r)
        self.chi, self.r = chi, r
        self.S, self.N = S, N
        nil, P, fact = [], identity(n), 1
        for j in range(m):
            if j:
                P, fact = P * N, fact * j
            nil.append(P * fmpq(1, fact))
        self.nilpotent = nil  # N^j / j!, j < m (exact)

    def irreducible_factors(self) -> list:
        """[(p, multiplicity in chi)]: chi's irreducible factors over Q (cached; no decomposition)."""
        if self._irreducible is None:
            chi = self.__dict__.get("chi") or self.M.charpoly()
            self._irreducible = [(fmpq_poly(p), k) for p, k in chi.factor()[1]] if self.n else []
        return self._irreducible

    @property
    def nilpotent_only(self) -> bool:
        """True when M is nilpotent (every eigenvalue 0): e^{Mt} is a polynomial in t."""
        return self.r.degree() == 1 and self.r.coeffs()[0] == 0

    @property
    def semisimple(self) -> bool:
        """True when M is diagonalizable over C (N = 0)."""
        return len(self.nilpotent) == 1

    @property
    def horner_basis(self) -> list[fmpq_mat]:
        """The exact B_i = b_i(S), i < d, with q_lambda(S) = sum_i lambda^{d-1-i} B_i (on first
        use: only exact Calcium values need them)."""
        if "_B" not in self.__dict__:
            self._B = adjugate_coefficients(self.S, self.r)
        return self._B

    def modulus_bounds(self) -> tuple[fmpq, fmpq] | None:
        """Rational upper bounds of max |lambda| and of min{|lambda| : lambda != 0} from the
        coefficients of chi alone, no roots (None when every eigenvalue is 0): Cauchy's bound
        1 + max |a_i| of the monic chi, and max(1, |c|) >= |c|^(1/m) >= the smallest of the m
        nonzero roots, c their product (the lowest nonzero coefficient, up to sign)."""
        if self.n == 0 or self.nilpotent_only:
            return None
        cs = self.chi.coeffs()
        low = next(c for c in cs if c != 0)
        return 1 + max(abs(c) for c in cs[:-1]), max(fmpq(1), abs(low))

    def eigenvalues(self, prec: int) -> list[tuple[acb, int]]:
        """[(lambda, weight)] at ``prec`` bits: the roots of r, one of each conjugate pair
        (weight 2).

        Parameters
        ----------
        prec : int
        """
        return [(lam, w) for lam, w, _ in self._eigen(prec)]

    def _eigen(self, prec: int) -> list[tuple[acb, int, int]]:
        """[(lambda, weight, multiplicity)], cached at the highest precision asked."""
        if self._roots[0] < prec:
            # the roots grouped by their multiplicity in chi (= the rank of K_lambda), from the
            # irreducible factors over Q: isolating the roots of each factor costs a fraction of
            # isolating them all at once (a 64 x 64 mode of a chain of carts: factors of degree
            # 2, 2, 30, 30; 9 ms instead of 25 ms at 640 bits), and factoring costs a few percent
            with workprec(prec + 16):
                out, self._root_factor = [], []
                for idx, (p, mult) in enumerate(self.irreducible_factors()):
                    for lam, _ in p.complex_roots():
                        if lam.imag.is_zero():
                            out.append((acb(lam.real), 1, mult))
                        elif lam.imag > 0:
                            out.append((lam, 2, mult))
                        else:
                            continue
                        self._root_factor.append(idx)
            self._roots = (prec, out)
        return self._roots[1]

    def _krylov_columns(self, T: fmpq_mat, c: fmpq_mat, eig: list, work: int,
                        check: Callable[[], None] | None = None, row: fmpz_mat | None = None) -> acb_mat:
        """The columns K_lambda(T) c of every eigenvalue at once (n x e balls; T = S or S^T, c an
        integer n x 1 probe): one product of the exact integer Horner vectors (:mod:`.krylov`) by a
        Vandermonde matrix.  With ``row`` (1 x n integers), a simple eigenvalue's column is divided
        by row K_lambda(T) c instead of r'(lambda) (a polynomial of exact coefficients at lambda);
        a divisor not certified nonzero raises ZeroDivisionError."""
        key = (tuple(c.entries()), None if row is None else tuple(row.entries()))  # kept: exact
        cache = self.__dict__.setdefault("_horner", {})
        if key not in cache:
            us, D, cd = horner_vectors(T, c, self.r, check)
            cache[key] = (us, D, cd, None if row is None else exact_poly(us, row, D, cd))
        us, D, cd, wpoly = cache[key]
        lams = [lam for lam, _, _ in eig]
        with workprec(work):
            drp = acb_poly(self.r.derivative())  # r' evaluated in C (rectangular splitting)
            tops = [drp(lam) for lam in lams]
            if row is not None:
                wp = acb_poly(wpoly)
                tops = [wp(lam) if m == 1 else top for (lam, _, m), top in zip(eig, tops)]
            if any(top.contains(0) for top in tops):
                raise ZeroDivisionError("a projector's divisor is not certified nonzero")
        return evaluate_columns(us, 1, vandermonde(lams, tops, len(us), D, cd, work), work)

    def _multiple_columns(self, eig: list, C: fmpq_mat, Cl: fmpq_mat, work: int) -> dict:
        """{k: (K_lambda C_m, K_lambda^T Cl_m)} (n x m balls) for the eigenvalues of multiplicity
        m > 1, C_m the first m columns: K_lambda = f_lambda(S) P_f / f'(lambda) with the exact
        primary projector P_f of the irreducible factor f of lambda (:func:`.krylov.primary_basis`),
        so that P_f C_m is exact and the Horner vectors are those of f (degree 1 or 2 for the
        many-fold eigenvalues of mechanics), not of r with m columns."""
        groups: dict = {}
        for k, (_, _, m) in enumerate(eig):
            if m > 1:
                groups.setdefault(self._root_factor[k], []).append(k)
        primary = self.__dict__.setdefault("_primary", {})
        out: dict = {}
        for idx, ks in groups.items():
            f, m = self._irreducible[idx]
            f = f / f.coeffs()[-1]
            if idx not in primary:
                primary[idx] = primary_basis(self.S, f)
            Z, W, WZ = primary[idx]
            lams = [eig[k][0] for k in ks]
            with workprec(work):
                dfp = acb_poly(f.derivative())
                tops = [dfp(lam) for lam in lams]
            for side, (T, X) in enumerate(((self.S, Z * WZ.solve(W.transpose() * _columns(C, m))),
                                           (self.S.transpose(), W * WZ.transpose().solve(Z.transpose() * _columns(Cl, m))))):
                us, D, cd = horner_vectors(T, X, f)
                block = evaluate_columns(us, m, vandermonde(lams, tops, len(us), D, cd, work), work)
                for col, k in enumerate(ks):
                    out.setdefault(k, [None, None])[side] = acb_mat([[block[i * m + j, col] for j in range(m)]
                                                                     for i in range(self.n)])
        return out

    def factors(self, prec: int, check: Callable[[], None] | None = None) -> list[tuple[acb, int, acb_mat, acb_mat]]:
        """[(lambda, weight, R_lambda, H_lambda)] with K_lambda = R_lambda H_lambda (n x m and
        m x n balls, H = G^{-1} L; see the class docstring), at least ``prec`` bits accurate;
        cached at the highest precision asked, with headroom.  ``check`` (a run's deadline check)
        is called between the steps of a long computation.

        Parameters
        ----------
        prec : int
        check : callable, optional
            Called between long steps (a deadline check).
        """
        if self._factors[0] >= prec:
            return self._factors[1]
        # the precision asked of a phase grows by doubling (sign decisions, root isolation), plus
        # a root's guard bits: first 4 p + FACTOR_HEADROOM (a request at 4 p + 32, a root refined
        # at a state's 4 p bits, recomputed every mode of the 64 x 64 chain at 2x); a later request
        # at its own precision plus the headroom, the exact parts kept (the 64 x 64 chain asks each
        # mode once more, at 1288 bits: doubling ahead computed 2640 for nothing)
        prec = (4 * prec if not self._factors[0] else prec) + FACTOR_HEADROOM
        n = self.n
        if not self._factors[0]:
            self._guard = self._initial_guard()
        for attempt in range(64):
            work = prec + self._guard
            eig = self._eigen(work)
            mmax = max(m for _, _, m in eig)
            C, Cl = _probe(n, mmax, 2 * attempt), _probe(n, mmax, 2 * attempt + 1)
            try:
                # simple eigenvalues: R = K c, H = (c'^T K) / (c'^T K c) (G is 1 x 1, its inverse
                # folded into the left columns); multiple ones: G = L C_m solved
                right = self._krylov_columns(self.S, _columns(C, 1), eig, work, check)
                c0 = fmpz_mat(1, n, [int(C[i, 0]) for i in range(n)])
                left = self._krylov_columns(self.S.transpose(), _columns(Cl, 1), eig, work, check, c0)
                more = self._multiple_columns(eig, C, Cl, work) if mmax > 1 else {}
                with workprec(work):
                    out = []
                    for k, (lam, w, m) in enumerate(eig):
                        if m == 1:
                            out.append((lam, w, acb_mat([[right[i, k]] for i in range(n)]),
                                        acb_mat([[left[i, k] for i in range(n)]])))
                            continue
                        R, L = more[k][0], more[k][1].transpose()
                        G = L * acb_mat(_columns(C, m))
                        out.append((lam, w, R, G.solve(L)))
            except ZeroDivisionError:  # G not certified invertible: other probes
                continue
            acc = min(min(factor_accuracy(R, work, prec + 8), factor_accuracy(H, work, prec + 8))
                      for _, _, R, H in out)
            if acc >= prec + 8:
                self._factors = (prec, out)
                self.__dict__.pop("_stacked_low", None)
                if mmax == 1:  # [R_lambda ...] and [H_lambda; ...] for the propagator
                    self._stacked = (right, left.transpose())
                    return out
                with workprec(work):
                    self._stacked = (acb_mat([[R[i, j] for _, _, R, _ in out for j in range(R.ncols())]
                                              for i in range(n)]),
                                     acb_mat([[H[i, j] for j in range(n)] for _, _, _, H in out
                                              for i in range(H.nrows())]))
                return out
            self._guard += prec + 8 - acc + 16
        raise UnresolvedSign(f"the spectral factors of a {n} x {n} matrix could not be certified at {prec} "
                             f"bits (64 attempts, up to {self._guard} guard bits)")

    def _initial_guard(self) -> int:
        """Bits the Krylov basis is expected to lose, about n (1.5 + log2 max(2, rho)) for
        eigenvalues of modulus up to rho (measured: 140-176 bits on the modes of the 64 x 64
        chain, rho = 2); the accuracy check corrects the estimate.  rho is a float estimate
        (a row-sum norm up to SMALL_GUARD_N, else numpy's eigenvalues of S: an estimate is all a
        guard needs, and isolating the roots of r at 64 bits only for it cost as much as at the
        working precision); certified balls when the floats overflow."""
        if self.n <= SMALL_GUARD_N:
            # rho <= the largest absolute row sum: on a small matrix an overestimate adds a few
            # bits, and numpy's eigenvalues cost ~0.1 ms a mode (3 % of a two-cart run)
            try:
                rho = max((sum(abs(float(v)) for v in row) for row in self.S.table()), default=0.0)
            except OverflowError:  # entries beyond floats: the general path below
                rho = math.inf
            if math.isfinite(rho):
                return 24 + int(self.n * (math.log2(max(2.0, rho)) + 1.5))
        import numpy as np  # a heuristic only (as the float estimates of the root search)
        rho = math.nan
        try:
            S = np.array([float(v) for v in self.S.entries()], dtype=float).reshape(self.n, self.n)
            with np.errstate(all="ignore"):
                if self.n and np.all(np.isfinite(S)):
                    rho = float(np.max(np.abs(np.linalg.eigvals(S))))
        except (OverflowError, np.linalg.LinAlgError):  # entries beyond floats; no convergence
            pass
        if not math.isfinite(rho):
            with workprec(64):
                b = max((abs(lam).upper() for lam, _, _ in self._eigen(64)), default=arb(1))
                rho = float(b.mid()) if b < 2 ** 1000 else 2.0 ** 1000
        bits = math.log2(max(2.0, rho))
        return 24 + int(self.n * (bits + 1.5))

    def modal(self, z: arb_mat | Callable[[int], arb_mat], prec: int,
              check: Callable[[], None] | None = None) -> list[tuple[acb, int, list[acb_mat]]]:
        """[(lambda, weight, [w_0, w_1, ...])] with w_j = K_lambda N^j z / j! (z: n x 1 balls, or a
        function giving z at a precision), so that e^{Mt} z = sum weight * Re(e^{lambda t}
        sum_j t^j w_j).  O(n^2) per call once the factors are known.  The list of an eigenvalue
        of multiplicity m stops at w_{m-1}: N = M - lambda on its generalized eigenspace, so
        K_lambda N^j = 0 exactly for j >= m (a simple eigenvalue has no polynomial part, and no
        tiny balls standing for its zeros).

        Parameters
        ----------
        z : arb_mat or callable
        prec : int
        check : callable, optional
        """
        if self.n == 0:
            return []
        fac = self.factors(prec, check)
        zb = z(prec) if callable(z) else z
        with workprec(prec):
            levels = [acb_mat(arb_mat(P) * zb) for P in self.nilpotent] if not self.semisimple else [acb_mat(zb)]
            return [(lam, w, [R * (H * y) for y in levels[:R.ncols()]]) for lam, w, R, H in fac]

    def matrix(self, t: arb, prec: int) -> arb_mat:
        """A ball of the propagator e^{Mt} (t a ball, possibly wide: an enclosure over it):
        sum_lambda w Re(e^{lambda t} R_lambda H_lambda) times sum_j t^j N^j / j!, one product
        [R_lambda ...] diag(w e^{lambda t}) [H_lambda; ...]: O(n^3).  Only the real part is
        wanted, so the complex product is taken as real ones: Re(R X) = Re R Re X - Im R Im X
        with X = D H (a 64 x 64 complex product costs six times two real ones).

        Parameters
        ----------
        t : arb
        prec : int
        """
        n = self.n
        if n == 0:
            return arb_mat(0, 0)
        fac = self.factors(prec)
        R, H = self._stacked_at(prec)
        with workprec(prec):
            tc = acb(t)
            m = R.ncols()
            Dr, Di = arb_mat(m, m), arb_mat(m, m)
            pos = 0
            for lam, w, Rl, _ in fac:
                e = (lam * tc).exp() * w
                for _ in range(Rl.ncols()):
                    Dr[pos, pos], Di[pos, pos] = e.real, e.imag
                    pos += 1
            Hr, Hi = H.real, H.imag
            E = R.real * (Dr * Hr - Di * Hi) - R.imag * (Dr * Hi + Di * Hr)
            if not self.semisimple:
                P, tp = arb_mat(self.nilpotent[0]), arb(1)
                for Q in self.nilpotent[1:]:
                    tp = tp * t
                    P += arb_mat(Q) * tp
                E = E * P
        return E

    def _stacked_at(self, prec: int) -> tuple[acb_mat, acb_mat]:
        """The stacked factors rounded to ``prec`` bits (a propagator wanted for a bound, such as
        the Jacobian of an event state's centered form, costs 64-bit products, not 600-bit)."""
        R, H = self._stacked
        if prec >= self._factors[0]:
            return R, H
        low = self.__dict__.setdefault("_stacked_low", {})
        if prec not in low:
            if len(low) > 4:
                low.clear()
            with workprec(prec):
                low[prec] = (R * acb(1), H * acb(1))  # rounded (radius grows by the rounding)
        return low[prec]

    def apply(self, t: arb, z: arb_mat, prec: int, modal: list | None = None) -> arb_mat:
        """A ball of e^{Mt} z (t a ball, possibly wide: then an enclosure over an interval).

        Parameters
        ----------
        t : arb
        z : arb_mat
        prec : int
        modal : list, optional
            :meth:`modal` of z, when computed.
        """
        if self.n == 0:
            return z
        with workprec(prec):
            terms = modal if modal is not None else self.modal(z, prec)
            tc = acb(t)
            acc = acb_mat(z.nrows(), z.ncols())
            for lam, weight, ws in terms:
                e = (lam * tc).exp()
                s = ws[0]
                tp = acb(1)
                for w in ws[1:]:
                    tp = tp * tc
                    s = s + w * tp
                acc += s * (e * weight)
            return arb_mat([[acc[i, j].real for j in range(z.ncols())] for i in range(z.nrows())])

    def ca_apply(self, t_ca: Any, v_ca: list, calcium: Any) -> list | None:
        """e^{M t*} v exactly, as Calcium numbers (``t_ca`` the Calcium number of a closed-form
        time t*, ``v_ca`` the components of v, ``calcium`` the :mod:`lcs_exact.calcium` module):
        sum over all eigenvalues lambda (algebraic numbers) of e^{lambda t*} K_lambda sum_j
        t*^j N^j v / j!, with K_lambda = q_lambda(S) / r'(lambda).  None when Calcium is
        unavailable.  e^{A pi} for the eigenvalues +-i, +-2i comes out rational.

        Parameters
        ----------
        t_ca : Ca
        v_ca : list of Ca
        calcium : module
        """
        if not calcium.available():
            return None
        n = self.n
        coeffs = self.r.coeffs()
        den = 1
        for c in coeffs:
            den = den * int(c.q) // math.gcd(den, int(c.q))
        ints = [int(c * den) for c in coeffs]
        # w = sum_j t^j N^j v / j!  (exact rational matrices, Calcium vector)
        w = [calcium.Ca(0)] * n
        tp = calcium.Ca(1)
        for j, P in enumerate(self.nilpotent):
            if j:
                tp = tp * t_ca
            Pv = [_ca_dot(P, i, v_ca, calcium) for i in range(n)]
            w = [a + b * tp for a, b in zip(w, Pv)]
        # B_j w (rational matrices times a Calcium vector), reused for every eigenvalue
        Bw = [[_ca_dot(B, i, w, calcium) for i in range(n)] for B in self.horner_basis]
        dr = self.r.derivative().coeffs()
        acc = [calcium.Ca(0)] * n
        for lam_ball, weight in self.eigenvalues(128):
            for lb in ([lam_ball] if weight == 1 else [lam_ball, lam_ball.conjugate()]):
                lam = calcium.Ca.algebraic(ints, lb)
                d = calcium.Ca(0)
                for c in reversed(dr):
                    d = d * lam + calcium.Ca(c)
                q = None
                for vec in Bw:  # Horner in lambda: q_lambda(S) w
                    q = list(vec) if q is None else [x * lam + y for x, y in zip(q, vec)]
                e = (lam * t_ca).exp() / d
                acc = [a + x * e for a, x in zip(acc, q)]
        return acc

    def exact_at(self, t_ca: Any, calcium: Any) -> fmpq_mat | None:
        """e^{M t*} as a rational matrix when it is one (proven with Calcium), else None.

        Parameters
        ----------
        t_ca : Ca
        calcium : module
        """
        cols = []
        for j in range(self.n):
            e = [calcium.Ca(int(i == j)) for i in range(self.n)]
            col = self.ca_apply(t_ca, e, calcium)
            if col is None:
                return None
            qs = [x.to_fmpq() for x in col]
            if any(q is None for q in qs):
                return None
            cols.append(qs)
        return fmpq_mat(self.n, self.n, [cols[j][i] for i in range(self.n) for j in range(self.n)])


def _probe(n: int, m: int, seed: int) -> fmpq_mat:
    """A fixed n x m matrix of small nonzero integers (a linear congruential sequence): the
    probes C, C' of the factored projectors, reproducible from ``seed``."""
    x = 2463534242 + 7919 * seed
    entries = []
    for _ in range(n * m):
        x = (1103515245 * x + 12345) % 2147483648
        v = (x >> 16) % 7 - 3
        entries.append(v if v else 4)
    return fmpq_mat(n, m, entries)


def _columns(C: fmpq_mat, m: int) -> fmpq_mat:
    """The first m columns of C."""
    return fmpq_mat(C.nrows(), m, [C[i, j] for i in range(C.nrows()) for j in range(m)])


def _ca_dot(P: fmpq_mat, i: int, v: list, calcium: Any):
    """Row i of a rational matrix times a Calcium vector."""
    acc = calcium.Ca(0)
    for j in range(P.ncols()):
        if P[i, j] != 0:
            acc = acc + v[j] * calcium.Ca(P[i, j])
    return acc


_CACHE: dict = {}


def spectrum_of(M: fmpq_mat) -> Spectrum:
    """The :class:`Spectrum` of M, shared between callers with equal matrices (a bounded cache:
    modes hold their own; this serves user calls such as ``expm_action``).

    Parameters
    ----------
    M : fmpq_mat
    """
    key = (M.nrows(), tuple(M.entries()))
    sp = _CACHE.get(key)
    if sp is None:
        if len(_CACHE) > 256:
            _CACHE.clear()
        sp = _CACHE[key] = Spectrum(M)
    return sp
