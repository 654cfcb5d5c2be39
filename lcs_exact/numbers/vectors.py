"""Exact vectors (docs/numerics.md): e^{Mt} v, P v, c q, components, algebraic vectors.

An exact vector (:class:`ExactVector`) is an immutable exact definition (a node,
:mod:`lcs_exact.nodes`) that evaluates to an n x 1 ``arb_mat`` ball of any precision with the
true value inside; its components are exact reals (:mod:`lcs_exact.reals`).

Signs.  ``x.sign_of_form(g)`` decides the sign of g . x, in this order (docs/numerics.md):
exact when x is proven rational; 0 when g lies in the rational span of the forms proven to vanish
on x (``zero_forms``: the annihilator of V_I along a phase, forms vanishing on the orbit of a
rational phase start, the constraint whose root ended the phase, all pulled back through
projections); by homogeneity (x = c q with c > 0 certified and q structured: the sign of g q);
then a ball that excludes 0, an exact zero test of the closed form (``prove_zero``: Calcium) and
refinement up to the policy's ceiling; otherwise an *unresolved zero*
(:meth:`~lcs_exact.balls.Policy.unresolved`).
"""
from __future__ import annotations

from typing import Any, Callable, Iterator

from flint import arb, arb_mat, fmpq, fmpq_mat

from . import calcium
from .balls import Policy, check_digits, decide_sign
from ..errors import ShapeError, UnresolvedSign
from .expm import Spectrum, spectrum_of, symbolic_expm, t_symbol
from ..interfaces import SystemLike
from .nodes import Node, closed_ready, derive_closed, in_dependency_order
from ..algebra import as_list, format_form, is_zero, matrix_to_sympy, to_matrix, to_vector, vector_entries, zeros
from .reals import ComponentReal, Real, ScaledReal, as_real, ca_from_state, ca_state, is_sympy, radical_form, rational_ca
from ..algebra import RowSpan, invariant_forms, kernel, orbit_zero_forms, pulled_back_forms, row_basis

__all__ = ["ExactVector", "RationalVector", "ScaledVector", "ExpVector", "ProjectedVector", "ComponentsVector",
           "AlgebraicVector", "algebraic_vector", "ca_matvec", "as_exact_vector", "as_state", "expm_action", "homogenized",
           "orbit_start"]


class ExactVector(Node):
    """An exact vector in R^n: evaluates to an n x 1 ``arb_mat`` ball of any precision.

    ``zero_forms`` (an m x n ``fmpq_mat``, a row basis) are linear forms proven to vanish on the
    vector; they are fixed at construction (vectors are immutable).
    """

    n: int

    def __init__(self, n: int, zero_forms: fmpq_mat | None = None, policy: Policy | None = None):
        super().__init__(policy)
        self.n = n
        zf = zero_forms if zero_forms is not None and zero_forms.nrows() else zeros(0, n)
        self.zero_forms = row_basis(zf) if zf.nrows() > 1 else zf
        self._twin: ExactVector | None = None  # an exact equal found by a proof (see prove_zero)
        self._ca = None
        self._ca_done = False

    @property
    def zero_span(self) -> RowSpan:
        """The span of ``zero_forms``, for membership tests (built once; a cache)."""
        span = self.__dict__.get("_zero_span")
        if span is None:
            span = self._zero_span = RowSpan(self.zero_forms)
        return span

    def known_rational(self) -> fmpq_mat | None:
        """The vector as an n x 1 ``fmpq_mat`` when already known to be rational (cheap)."""
        return self._twin.known_rational() if self._twin is not None else None

    def rational(self) -> fmpq_mat | None:
        """The vector as an n x 1 ``fmpq_mat`` when proven rational, deriving the closed forms
        of the times in its definition if needed (lazy); None when not proven."""
        q = self.known_rational()
        if q is None and self.policy.closed_forms != "off":
            q = self.exact_rational()
        return q

    def exact_rational(self, depth: int = 40) -> fmpq_mat | None:
        """The vector as a rational vector when closed forms prove it (may derive the closed forms
        of the times in its definition, e.g. e^{A(theta - 1)} q with theta = 1 proven is q); None when
        not proven.

        Parameters
        ----------
        depth : int, optional
            How far back the definition is followed (default 40)."""
        q = self.known_rational()
        if q is not None or depth <= 0:
            return q
        q = self._exact_rational(depth - 1)
        if q is not None and self._twin is None:
            self._twin = RationalVector(q, policy=self.policy)
        return q

    def _exact_rational(self, depth: int) -> fmpq_mat | None:
        return None

    def proven_zero(self, i: int) -> bool:
        """Component i is 0 by a proven relation (or by an exact twin found by a proof).

        Parameters
        ----------
        i : int"""
        if self._twin is not None:
            return self._twin.q[i, 0] == 0
        if not self.zero_forms.nrows():
            return False
        return self.zero_span.has_unit(i)

    def closed_form(self, derive: bool = True):
        """A SymPy column vector when every component has a proven closed form, else None.

        Parameters
        ----------
        derive : bool, optional
            False: only what is cheaply known; True (default) may derive it with SymPy (the symbolic
            e^{Mt}: up to a second for a new matrix)."""
        if self._twin is not None:
            return self._twin.closed_form(derive)
        return None

    def known_ca(self) -> list | None:
        """The components as Calcium numbers when the vector is already known exactly (rational,
        or algebraic: :class:`AlgebraicVector`); cheap, never derives a closed form."""
        q = self.known_rational()
        if q is None:
            return None
        return [calcium.Ca(q[i, 0]) for i in range(self.n)] if calcium.available() else None

    def to_ca(self) -> list | None:
        """The components as Calcium numbers (exact), or None (cached)."""
        if not self._ca_done:
            self._ca_done = True
            try:
                self._ca = self._to_ca()
            except (ZeroDivisionError, ValueError, UnresolvedSign):
                self._ca = None  # Calcium could not build it (an undecided divisor): no closed form
        return self._ca

    def _to_ca(self):
        return None

    def sign_of_form(self, form: fmpq_mat) -> int:
        """Certified sign of form . x (see the module docstring for the order of the tests).

        Parameters
        ----------
        form : fmpq_mat, 1 x n"""
        q = self.known_rational()
        if q is not None:
            v = (form * q)[0, 0]
            return (v > 0) - (v < 0)
        if is_zero(form):
            return 0
        if self.zero_forms.nrows() and form in self.zero_span:
            return 0
        s = self._structural_sign(form)
        if s is not None:
            return s
        return decide_sign(lambda p: (arb_mat(form) * self.arb(p))[0, 0], policy=self.policy,
                           what=lambda: f"the form {format_form(form)} at {self!r}",
                           start=max(64, self._prec), prove_zero=lambda: self.prove_zero(form))

    def _structural_sign(self, form: fmpq_mat) -> int | None:
        return None

    def prove_zero(self, form: fmpq_mat) -> bool | None:
        """form . x == 0 by an exact proof: True, False (proven nonzero), None (unknown).

        Tries the Calcium closed form of the vector; when every component is rational there,
        the vector gets an exact twin (a rational vector) used from then on.  Never with
        ``closed_forms=False``.

        Parameters
        ----------
        form : fmpq_mat, 1 x n"""
        if self.policy.closed_forms == "off":
            return None
        xs = self.to_ca()
        if xs is None:
            return None
        qs = [c.to_fmpq() for c in xs]
        if all(q is not None for q in qs):
            self._twin = RationalVector(fmpq_mat(self.n, 1, qs), policy=self.policy)
            v = (form * self._twin.q)[0, 0]
            return v == 0
        acc = calcium.Ca(0)
        for j, c in enumerate(xs):
            if form[0, j] != 0:
                acc = acc + c * calcium.Ca(form[0, j])
        return acc.is_zero()

    def __len__(self):
        return self.n

    def __getitem__(self, i: int | slice) -> Real | list[Real]:
        if isinstance(i, slice):  # x[:2]: the components, as a list of exact reals
            return [ComponentReal(self, j) for j in range(*i.indices(self.n))]
        if not -self.n <= i < self.n:
            raise IndexError(f"component {i} of a vector of length {self.n}")
        return ComponentReal(self, i % self.n)

    def __iter__(self) -> Iterator[Real]:
        return (ComponentReal(self, i) for i in range(self.n))

    def tolist(self) -> list[Real]:
        return list(self)

    def ball(self, digits: int = 30) -> list[arb]:
        """Certified balls of the components, each to ``digits`` digits (one query: bounded by the run's
        ``time_limit`` as a whole).

        Parameters
        ----------
        digits : int, optional"""
        digits = check_digits(digits)
        with self.policy.deadline.query():
            return [c.ball(digits) for c in self]

    def __repr__(self):
        q = self.known_rational()
        if q is not None:
            return "(" + ", ".join(str(q[i, 0]) for i in range(self.n)) + ")"
        return "(" + ", ".join(c.label() for c in self) + ")"


class RationalVector(ExactVector):
    """A rational vector (n x 1 ``fmpq_mat``)."""

    def __init__(self, q: fmpq_mat, policy: Policy | None = None):
        super().__init__(q.nrows(), None, policy)
        self.q = q
        if all(q[i, 0].q == 1 for i in range(q.nrows())):  # integer entries: exact balls ...
            ball = arb_mat(q)
            if all(ball[i, 0].is_exact() for i in range(q.nrows())):  # ... when they fit the precision
                self._ball, self._prec = ball, 1 << 30

    def _compute(self, prec):
        return arb_mat(self.q)

    def known_rational(self):
        return self.q

    def closed_form(self, derive: bool = True):
        import sympy
        return sympy.Matrix([sympy.Rational(int(self.q[i, 0].p), int(self.q[i, 0].q)) for i in range(self.n)])

    def _to_ca(self):
        return [calcium.Ca(self.q[i, 0]) for i in range(self.n)] if calcium.available() else None


class ScaledVector(ExactVector):
    """c v with c an exact real proven positive and v an exact vector (homogeneity: the LCS is
    linear, so phases from c v have the event times of v and c times its states)."""

    def __init__(self, c: Real, v: ExactVector, policy: Policy | None = None):
        super().__init__(v.n, v.zero_forms, policy or v.policy)
        self.c, self.v = c, v

    def _deps(self):
        return (self.c, self.v)

    def _compute(self, prec):
        return self.v.arb(prec) * self.c.arb(prec)

    def known_rational(self):
        qc = self.c.known_rational()
        qv = self.v.known_rational()
        if qc is not None and qv is not None:
            return qv * qc
        return super().known_rational()

    def _structural_sign(self, form):
        return self.v.sign_of_form(form)  # c > 0

    def known_ca(self):
        if "_kca" not in self.__dict__:
            cc, cv = self.c.known_ca(), self.v.known_ca()
            self._kca = None if cc is None or cv is None else [x * cc for x in cv]
        return self._kca

    def proven_zero(self, i: int) -> bool:
        return self.v.proven_zero(i)

    def _exact_rational(self, depth):
        qv = self.v.exact_rational(depth)
        cf = self.c.closed if qv is not None else None
        if cf is not None and cf.is_rational:
            return qv * cf.to_fmpq()
        return None

    def closed_form(self, derive: bool = True):
        cv = self.v.closed_form(derive)
        cc = (self.c.closed_form if derive else self.c.known_closed_form) if cv is not None else None
        return None if cc is None or cv is None else cv * cc

    def _to_ca(self):
        cc, cv = self.c.to_ca(), self.v.to_ca()
        return None if cc is None or cv is None else [x * cc for x in cv]


class ProjectedVector(ExactVector):
    """P v for a rational matrix P (a projection P_I, an impulse map, a feedback); the forms r
    with r P in the span of v's zero forms vanish on it."""

    def __init__(self, P: fmpq_mat, v: ExactVector, policy: Policy | None = None,
                 zero_forms: fmpq_mat | None = None):
        zf = pulled_back_forms(P, v.zero_forms)
        if zero_forms is not None and zero_forms.nrows():
            zf = row_basis(zf, zero_forms) if zf.nrows() else zero_forms
        super().__init__(P.nrows(), zf, policy or v.policy)
        self.P, self.v = P, v

    def _deps(self):
        return (self.v,)

    def _compute(self, prec):
        return arb_mat(self.P) * self.v.arb(prec)

    def known_rational(self):
        q = self.v.known_rational()
        if q is not None:
            return self.P * q
        return super().known_rational()

    def _structural_sign(self, form):
        return self.v.sign_of_form(form * self.P)

    def known_ca(self):
        if "_kca" not in self.__dict__:
            if self.known_rational() is not None:
                return super().known_ca()
            self._kca = ca_matvec(self.P, self.v.known_ca())
        return self._kca

    def _exact_rational(self, depth):
        q = self.v.exact_rational(depth)
        return None if q is None else self.P * q

    def closed_form(self, derive: bool = True):
        if self._twin is not None:
            return self._twin.closed_form(derive)
        cf = self.v.closed_form(derive)
        if cf is None:
            return None
        return (matrix_to_sympy(self.P) * cf).applyfunc(_tidy)

    def _to_ca(self):
        xs = self.v.to_ca()
        if xs is None:
            return None
        out = []
        for i in range(self.n):
            acc = calcium.Ca(0)
            for j in range(self.v.n):
                if self.P[i, j] != 0:
                    acc = acc + xs[j] * calcium.Ca(self.P[i, j])
            out.append(acc)
        return out


class ExpVector(ExactVector):
    """e^{M t} v: M rational (through its :class:`~lcs_exact.expm.Spectrum`), t an exact real, v
    an exact vector.  ``modal(prec)``, when given, supplies the per-eigenvalue vectors of v at
    ``prec`` (a phase computes them once for all its functions)."""

    def __init__(self, spectrum: Spectrum, t: Real, v: ExactVector, zero_forms: fmpq_mat | None = None,
                 policy: Policy | None = None, modal: Callable[[int], list] | None = None):
        super().__init__(spectrum.n, zero_forms, policy or v.policy)
        self.spectrum, self.t, self.v = spectrum, t, v
        self._modal = modal

    @property
    def M(self) -> fmpq_mat:
        return self.spectrum.M

    def _deps(self):
        return (self.t, self.v)

    def _compute(self, prec):
        t = self.t.arb(prec)
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
                out = _exp_rational_time(self.spectrum.M, q, tq)
                self._twin = RationalVector(out, policy=self.policy)
                return out
        return None

    def _exact_rational(self, depth):
        inner, s = orbit_start(self.v, self.spectrum.M)  # e^{Mt} e^{Ms} w = e^{M(t+s)} w
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
            return _exp_rational_time(self.spectrum.M, q, tq)
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
                    self._sym = (E.subs(t_symbol(), tc) * vc).applyfunc(_tidy)
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


class ComponentsVector(ExactVector):
    """A vector of exact reals (e.g. an initial state with closed-form entries)."""

    def __init__(self, comps: list[Real], policy: Policy | None = None):
        zf = [j for j, c in enumerate(comps) if c.known_rational() == 0]
        Z = fmpq_mat(len(zf), len(comps), [int(j == z) for z in zf for j in range(len(comps))])
        super().__init__(len(comps), Z, policy)
        self.comps = comps

    def _deps(self):
        return tuple(self.comps)

    def _compute(self, prec):
        return arb_mat([[c.arb(prec)] for c in self.comps])

    def known_rational(self):
        qs = [c.known_rational() for c in self.comps]
        if all(q is not None for q in qs):
            return fmpq_mat(self.n, 1, qs)
        return super().known_rational()

    def closed_form(self, derive: bool = True):
        cs = [c.closed_form for c in self.comps]
        if any(c is None for c in cs):
            return None
        import sympy
        return sympy.Matrix(cs)

    def _to_ca(self):
        cs = [c.to_ca() for c in self.comps]
        return None if any(c is None for c in cs) else cs

    def known_ca(self):
        cs = [c.known_ca() for c in self.comps]
        return None if any(c is None for c in cs) else cs


def ca_matvec(P: fmpq_mat, xs: list | None) -> list | None:
    """P x for a rational matrix P and a vector of Calcium numbers (None stays None)."""
    if xs is None:
        return None
    out = []
    for i in range(P.nrows()):
        acc = calcium.Ca(0)
        for j in range(P.ncols()):
            if P[i, j] != 0:
                acc = (acc + xs[j] * calcium.Ca(P[i, j])).compact()  # (see Ca.compact)
        out.append(acc)
    return out


class AlgebraicVector(ExactVector):
    """A vector of exact real algebraic numbers (Calcium numbers): the state at an event of a
    polynomial phase (a free fall, a relay's constant field) whose time is algebraic.  Every sign
    of a rational form is decided exactly (Calcium decides algebraic numbers); balls come from
    Calcium's enclosures at any precision.  Rational components stay rational
    (``known_rational`` when all are).

    >>> from lcs_exact.calcium import Ca
    >>> x = AlgebraicVector([Ca(2).sqrt(), Ca(1)])
    >>> x.sign_of_form(fmpq_mat([[1, -2]])), x[0].closed_form
    (-1, sqrt(2))
    """

    def __init__(self, comps: list, zero_forms: fmpq_mat | None = None, policy: Policy | None = None,
                 rationals: list | None = None):
        super().__init__(len(comps), zero_forms, policy)
        # (see Ca.compact: expressions outgrow numbers); ``rationals``: [c.to_fmpq()] of the
        # compacted components when the caller has them (a proof of rationality can take ms)
        self.comps = [c.compact() for c in comps] if rationals is None else list(comps)
        qs = [c.to_fmpq() for c in self.comps] if rationals is None else rationals
        self._q = fmpq_mat(self.n, 1, qs) if all(q is not None for q in qs) else None

    def _compute(self, prec):
        if self._q is not None:
            return arb_mat(self._q)
        return arb_mat([[c.enclosure(prec + 8).real] for c in self.comps])

    def known_rational(self):
        return self._q if self._q is not None else super().known_rational()

    def known_ca(self):
        return self.comps

    def _to_ca(self):
        return self.comps

    def _structural_sign(self, form):
        acc = calcium.Ca(0)
        for j in range(self.n):
            if form[0, j] != 0:
                acc = acc + self.comps[j] * calcium.Ca(form[0, j])
        return acc.sign(real=True)

    def proven_zero(self, i: int) -> bool:
        return self.comps[i].is_zero() is True or super().proven_zero(i)

    def closed_form(self, derive: bool = True):
        if self._q is not None:
            return RationalVector(self._q).closed_form()
        if not derive:
            return None
        cs = [radical_form(c) for c in self.comps]
        if any(c is None for c in cs):
            return None
        import sympy
        return sympy.Matrix(cs)

    def __getstate__(self):
        state = super().__getstate__()
        state["comps"] = None if self._q is not None else [ca_state(c) for c in self.comps]
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        if state["comps"] is None:
            self.comps = [rational_ca(self._q[i, 0]) for i in range(self.n)]
        else:
            self.comps = [ca_from_state(c) for c in state["comps"]]


def algebraic_vector(xs: list, zero_forms: fmpq_mat | None = None, policy: Policy | None = None) -> ExactVector:
    """A RationalVector when every Calcium number of xs is rational, else an AlgebraicVector."""
    cs = [c.compact() for c in xs]
    qs = [c.to_fmpq() for c in cs]
    if all(q is not None for q in qs):
        return RationalVector(fmpq_mat(len(xs), 1, qs), policy)
    return AlgebraicVector(cs, zero_forms, policy, rationals=qs)


def _tidy(e):
    """Light SymPy clean-up of a closed-form entry (no simplify: it costs seconds)."""
    import sympy
    return sympy.nsimplify(e, rational=False) if e.is_number and e.is_Float else sympy.expand(e)


def as_exact_vector(x: Any, n: int | None = None, name: str = "x0", policy: Policy | None = None) -> ExactVector:
    """An ExactVector from an ExactVector, an ``fmpq_mat`` column or any vector input (entries
    rational-like, or SymPy closed forms)."""
    if isinstance(x, ExactVector):
        if n is not None and x.n != n:
            raise ShapeError(f"{name} has length {x.n}, expected {n}")
        return x
    if isinstance(x, fmpq_mat):
        return RationalVector(to_vector(x, x.nrows() if n is None and x.ncols() == 1 else
                                        (n if n is not None else x.ncols()), name), policy)
    if hasattr(x, "tolist") and not is_sympy(x):
        x = as_list(x)
    flat = vector_entries(x, n, name)
    if any(isinstance(e, Real) or (is_sympy(e) and not getattr(e, "is_Rational", False)) for e in flat):
        # the library's own exact reals (a component of traj.state(t)) and SymPy closed forms
        return ComponentsVector([as_real(e, policy) for e in flat], policy)
    return RationalVector(to_vector(flat, len(flat), name), policy)


def as_state(lcs: SystemLike, x0: Any) -> ExactVector:
    """The state as every layer from here up holds it: one exact vector of length n (a
    :class:`RationalVector` for rational input; an exact vector as it is, length checked).  Its
    ``sign_of_form`` is the one decision mode selection asks of it, ``known_rational()`` the
    rational fast path (section 5: every test is a sign of a linear form in x0)."""
    return as_exact_vector(x0, lcs.n, "x0")


def orbit_start(v: ExactVector, M: fmpq_mat) -> tuple[ExactVector, Real | None]:
    """(w, s) with v = e^{M s} w and w not itself of that form (s None when v is not e^{M s} w):
    a phase from v follows the orbit of w, so forms vanishing on the orbit of w vanish on it."""
    s = None
    while isinstance(v, ExpVector) and (v.spectrum.M is M or v.spectrum.M == M):
        s = v.t if s is None else s + v.t
        v = v.v
    return v, s


def homogenized(x: ExactVector) -> ExactVector:
    """x itself, or c q (c > 0 certified, q rational) when the forms proven to vanish on x leave
    a single direction q (rank n - 1): then every sign at x is the sign at q, exactly; the
    rational 0 when they leave none (rank n: a velocity reset to rest, x = P_I x- with P_I = 0)."""
    if x.known_rational() is None and x.zero_forms.nrows() and x.zero_span.dim == x.n:
        return RationalVector(zeros(x.n, 1), x.policy)
    if x.known_rational() is not None or isinstance(x, (ScaledVector, AlgebraicVector)) or \
            x.zero_forms.nrows() != x.n - 1:
        return x
    q = kernel(x.zero_forms)
    i = next(i for i in range(x.n) if q[i, 0] != 0)
    c = ScaledReal(ComponentReal(x, i), 1 / q[i, 0])
    s = c.sign()
    if s == 0:
        return RationalVector(zeros(x.n, 1), x.policy)
    if s < 0:
        c, q = -c, -q
    return ScaledVector(c, RationalVector(q, x.policy), x.policy)


def expm_action(M: Any, t: Any, v: Any, *, policy: Policy | None = None) -> ExactVector:
    """e^{M t} v as an exact vector (M, v: any matrix/vector input LCS accepts; t exact).

    Composes structurally: expm_action(M, a, expm_action(M, b, v)) = e^{M(a+b)} v, and is v
    itself (rational again) when a + b is proven 0.

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
    if isinstance(v, ExpVector) and v.spectrum.M == sp.M:
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
