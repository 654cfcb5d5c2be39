"""Exact vectors on an orbit of e^{Mt} (docs/numerics.md): :class:`ExpVector`, e^{M t} v for a
rational M, an exact real t and an exact vector v; :func:`expm_action`, its constructor for any
input, which composes e^{Ma} e^{Mb} v = e^{M(a+b)} v; :func:`orbit_start`, the start w of the orbit
a vector lies on.  A phase's states are such vectors (x(t) = e^{A_I t} z, :mod:`lcs_exact.phase`).
The other exact vectors are in :mod:`lcs_exact.numbers.vectors`.
"""
from __future__ import annotations

from typing import Any, Callable

from flint import fmpq, fmpq_mat

from . import calcium
from .balls import Policy
from ..errors import ShapeError, UnresolvedSign
from .expm import Spectrum, spectrum_of
from .laplace import symbolic_expm, t_symbol
from .nodes import closed_ready, derive_closed, in_dependency_order
from ..algebra import invariant_forms, is_zero, orbit_zero_forms, to_matrix, zeros
from .reals import Real, as_real
from .vectors import ExactVector, RationalVector, as_exact_vector, tidy

__all__ = ["ExpVector", "expm_action", "orbit_start"]


class ExpVector(ExactVector):
    """e^{M t} v: M rational (through its :class:`~lcs_exact.expm.Spectrum`), t an exact real, v
    an exact vector (built by :func:`expm_action`, and by a phase for its states).

    Parameters
    ----------
    spectrum : Spectrum or callable
        The spectral data of the n x n rational matrix M (:func:`~lcs_exact.expm.spectrum_of`),
        or a function giving it, called on first use (then ``M`` is required).
    t : Real
        The time.
    v : ExactVector
        The vector at t = 0, of length n.
    zero_forms : fmpq_mat, optional
        Forms proven to vanish on e^{M t} v (:func:`expm_action` passes those that vanish on the
        whole orbit of v).  Default: none.
    policy : Policy, optional
        Default: v's.
    modal : callable, optional
        prec -> the per-eigenvalue vectors of v at ``prec`` bits (:meth:`Spectrum.modal
        <lcs_exact.expm.Spectrum.modal>`): a phase computes them once for all its functions.
    M : fmpq_mat, optional
        The matrix, when ``spectrum`` is a function (default: ``spectrum.M``).
    propagate : callable, optional
        (t ball, prec) -> a ball of e^{M t} v: the balls of a phase evaluated by Taylor steps
        (:mod:`lcs_exact.numbers.taylorsteps`) instead of the spectral data.
    """

    def __init__(self, spectrum: Spectrum | Callable[[], Spectrum], t: Real, v: ExactVector,
                 zero_forms: fmpq_mat | None = None, policy: Policy | None = None,
                 modal: Callable[[int], list] | None = None, *, M: fmpq_mat | None = None,
                 propagate: Callable[[Any, int], Any] | None = None):
        super().__init__(v.n, zero_forms, policy or v.policy)
        self._spectrum, self.t, self.v = spectrum, t, v
        self._M = M if M is not None else spectrum.M
        self._modal, self._propagate = modal, propagate

    @property
    def spectrum(self) -> Spectrum:
        """The spectral data of M (computed on first use when a function was given)."""
        if not isinstance(self._spectrum, Spectrum):
            self._spectrum = self._spectrum()
        return self._spectrum

    @property
    def M(self) -> fmpq_mat:
        return self._M

    def _deps(self):
        return (self.t, self.v)

    def _compute(self, prec):
        t = self.t.arb(prec)
        if self._propagate is not None:
            return self._propagate(t, prec)
        modal = self._modal(prec) if self._modal is not None else None
        return self.spectrum.apply(t, self.v.arb(prec), prec, modal)

    def known_rational(self):
        if self._twin is not None:
            return self._twin.known_rational()
        tq = self.t.known_rational()
        if tq == 0:
            return self.v.known_rational()
        if tq is not None and self.spectrum.nilpotent_only:
            q = self.v.known_rational()
            if q is not None:  # a nilpotent M: every q is in its generalized kernel
                out = _exp_rational_time(self.M, q, tq)
                self._twin = RationalVector(out, policy=self.policy)
                return out
        return None

    def _exact_rational(self, depth):
        inner, s = orbit_start(self.v, self.M)  # e^{Mt} e^{Ms} w = e^{M(t+s)} w
        q = inner.exact_rational(depth)
        if q is None:
            return None
        tc = self.t.closed
        if tc is not None and s is not None:
            sc = s.closed
            tc = None if sc is None else tc + sc
        if tc is None:
            return None
        if tc.is_zero:
            return q
        if all(q[i, 0] == 0 for i in range(self.n)):
            return q
        tq = tc.to_fmpq()
        if tq is not None:
            return _exp_rational_time(self.M, q, tq)
        if not calcium.available():
            return None
        try:  # e^{M t*} q exactly (Calcium), rational when every component is
            tca = tc.to_ca()
            if tca is None:
                return None
            xs = self.spectrum.ca_apply(tca, [calcium.Ca(q[i, 0]) for i in range(self.n)], calcium)
            qs = None if xs is None else [x.to_fmpq() for x in xs]
        except (ValueError, ZeroDivisionError, UnresolvedSign):
            return None
        return None if qs is None or any(x is None for x in qs) else fmpq_mat(self.n, 1, qs)

    def _closed_ready(self) -> bool:
        return "_sym" in self.__dict__ or self._twin is not None

    def _derive_closed(self) -> None:
        self.closed_form(True)

    def closed_form(self, derive: bool = True):
        if self._twin is not None:
            return self._twin.closed_form(derive)
        if not derive:
            return None
        q = self.exact_rational()
        if q is not None:
            return self._twin.closed_form()
        if "_sym" not in self.__dict__:
            # the closed forms of the times and states before it first, in a loop (no deep recursion)
            in_dependency_order(self, derive_closed, closed_ready)
            self._sym = None
            tc = self.t.closed_form
            vc = self.v.closed_form(derive) if tc is not None else None
            if vc is not None:
                E = symbolic_expm(self.spectrum)
                if E is not None:
                    self._sym = (E.subs(t_symbol(), tc) * vc).applyfunc(tidy)
        return self._sym

    def _to_ca(self):
        tc = self.t.to_ca()
        if tc is None:
            return None
        xs = self.v.to_ca()
        if xs is None:
            return None
        return self.spectrum.ca_apply(tc, xs, calcium)


def _exp_rational_time(M: fmpq_mat, q: fmpq_mat, t: fmpq) -> fmpq_mat | None:
    """e^{M t} q for a rational t != 0 when it is rational, else None, decided without Calcium.
    e^{Mt} q = sum_lambda e^{lambda t} K_lambda e^{Nt} q; by Lindemann-Weierstrass the e^{lambda t}
    (distinct algebraic exponents) are linearly independent over the algebraic numbers, so every
    component is rational only if K_lambda q = 0 for every lambda != 0: q lies in the generalized
    kernel of M (M^n q = 0), and then e^{Mt} q = sum_j t^j M^j q / j!, a finite rational sum.
    (Calcium took minutes on e^{3 M} q for a 10 x 10 chain of carts to find out the same.)"""
    out, v, j = zeros(M.nrows(), 1), q, 0
    while not is_zero(v):
        if j >= M.nrows():
            return None  # not in the generalized kernel: irrational
        out, v, j = out + v, M * v * t / (j + 1), j + 1
    return out


def orbit_start(v: ExactVector, M: fmpq_mat) -> tuple[ExactVector, Real | None]:
    """(w, s) with v = e^{M s} w and w not itself of that form (s None when v is not e^{M s} w):
    a phase from v follows the orbit of w, so forms vanishing on the orbit of w vanish on it.

    Parameters
    ----------
    v : ExactVector
    M : fmpq_mat
        The matrix of the orbit (an :class:`ExpVector` of another matrix is not unwound).
    """
    s = None
    while isinstance(v, ExpVector) and (v.M is M or v.M == M):
        s = v.t if s is None else s + v.t
        v = v.v
    return v, s


def expm_action(M: Any, t: Any, v: Any, *, policy: Policy | None = None) -> ExactVector:
    """e^{M t} v as an exact vector (M, v: any matrix/vector input LCS accepts; t exact).

    Composes structurally: expm_action(M, a, expm_action(M, b, v)) = e^{M(a+b)} v, and is v
    itself (rational again) when a + b is proven 0.

    Parameters
    ----------
    M : matrix-like or Spectrum
        n x n, rational (any matrix input :class:`~lcs_exact.LCS` accepts), or its
        :class:`~lcs_exact.expm.Spectrum`.
    t : Real, rational-like or SymPy expression
        The time (any input :func:`~lcs_exact.reals.as_real` accepts).
    v : ExactVector or vector input
        Of length n (any input :func:`~lcs_exact.vectors.as_exact_vector` accepts).
    policy : Policy, optional
        The precision policy of the numbers made here (default ``DEFAULT_POLICY``).

    Examples
    --------
    >>> x0 = expm_action([[0, 1], [-1, 0]], -1, [1, 0])
    >>> expm_action([[0, 1], [-1, 0]], 1, x0).known_rational().transpose()
    [1, 0]
    """
    if isinstance(M, Spectrum):
        sp = M
    else:
        Mq = to_matrix(M, "M")
        if Mq.nrows() != Mq.ncols():
            raise ShapeError(f"M must be square, got {Mq.nrows()}x{Mq.ncols()}")
        sp = spectrum_of(Mq)
    t = as_real(t, policy)
    v = as_exact_vector(v, sp.n, "v", policy)
    if isinstance(v, ExpVector) and v.M == sp.M:
        t, v = t + v.t, v.v
    if t.known_rational() == 0:
        return v
    q = v.known_rational()
    if q is not None and is_zero(sp.M * q):  # an equilibrium: e^{Mt} v = v
        return v
    if q is not None:  # forms vanishing on the whole orbit e^{Ms} q (e.g. coordinates M leaves at 0)
        zf = orbit_zero_forms(sp.M, q)
    else:
        zf = invariant_forms(v.zero_forms, sp.M) if v.zero_forms.nrows() else None
    return ExpVector(sp, t, v, zf, policy)
