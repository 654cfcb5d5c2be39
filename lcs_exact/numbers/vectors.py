"""Exact vectors (docs/numerics.md): rational vectors, c q, P v, components, algebraic vectors;
e^{Mt} v is in :mod:`lcs_exact.numbers.expvectors`.

An exact vector (:class:`ExactVector`) is an immutable exact definition (a node,
:mod:`lcs_exact.nodes`) that evaluates to an n x 1 ``arb_mat`` ball of any precision with the
true value inside; its components are exact reals (:mod:`lcs_exact.reals`).

Signs.  ``x.sign_of_form(g)`` decides the sign of g . x, in this order (docs/numerics.md):
exact when x is proven rational; 0 when g lies in the rational span of the forms proven to vanish
on x (``zero_forms``: the annihilator of V_I along a phase, forms vanishing on the orbit of a
rational phase start, the constraint whose root ended the phase, all pulled back through
projections); by homogeneity (x = c q with c > 0 certified and q structured: the sign of g q);
then a ball that excludes 0 (the one computed already is looked at first: it settles most
signs before any exact test), a positive multiple of a row known positive where the vector was
made (``positive_forms``: an event state's constraints its root search proved > 0), an exact zero test of the closed form (``prove_zero``: Calcium) and
refinement up to the policy's ceiling; otherwise an *unresolved zero*
(:meth:`~lcs_exact.balls.Policy.unresolved`).
"""
from __future__ import annotations

from typing import Any, Iterator

from flint import arb, arb_mat, fmpq_mat

from . import calcium
from .balls import Policy, ball_sign, check_digits, decide_sign, workprec
from ..errors import ShapeError, UnresolvedSign
from ..interfaces import SystemLike
from .nodes import Node
from ..algebra import as_list, format_form, is_zero, matrix_to_sympy, submatrix, to_vector, vector_entries, zeros
from .reals import ComponentReal, Real, ScaledReal, as_real, is_sympy
from .relations import component_relations
from ..algebra import RowSpan, kernel, projected_forms, pulled_back_forms, row_basis

__all__ = ["ExactVector", "RationalVector", "ScaledVector", "ProjectedVector", "ComponentsVector",
           "ca_matvec", "as_exact_vector", "as_state", "homogenized"]


class ExactVector(Node):
    """An exact vector in R^n: evaluates to an n x 1 ``arb_mat`` ball of any precision (the base of
    the classes below, which say what the vector is; vectors are immutable).

    Parameters
    ----------
    n : int
        The length.
    zero_forms : fmpq_mat, optional
        m x n: linear forms (rows) proven to vanish on the vector, kept as a row basis in
        ``zero_forms`` and fixed at construction.  Default: none.
    policy : Policy, optional
        The precision policy of its evaluations and sign decisions (default ``DEFAULT_POLICY``).
    """

    n: int
    #: rows g proven g . x > 0 where x was made (an event state: constraints its phase's search
    #: proved positive up to the event); a form that is a positive multiple of one is positive
    positive_forms: tuple = ()
    #: every sign is decided exactly without balls (algebraic components): nothing to homogenize
    exact_signs: bool = False

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
        or algebraic: :class:`~lcs_exact.numbers.algebraicvectors.AlgebraicVector`); cheap, never derives a closed form."""
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
        if self._ball is not None:
            # the ball already computed excludes 0: the sign is certified, and the exact tests
            # below (they can only prove a zero) are not needed; LDCPs of large systems ask for
            # many such signs, and an exact membership test costs more than this product
            with workprec(max(64, self._prec)):
                s = ball_sign((arb_mat(form) * self._ball)[0, 0])
            if s:
                return s
        if self.zero_forms.nrows() and form in self.zero_span:
            return 0
        if any(_positive_multiple(form, g) for g in self.positive_forms):
            return 1
        s = self._structural_sign(form)
        if s is not None:
            return s
        return decide_sign(lambda p: (arb_mat(form) * self.arb(p))[0, 0], policy=self.policy,
                           what=lambda: f"the form {format_form(form)} at {self!r}",
                           start=max(64, self._prec), prove_zero=lambda: self.prove_zero(form))

    def signs_of_rows(self, F: fmpq_mat, rows: list[int] | None = None) -> Iterator[int]:
        """The signs of the rows of F (of ``rows``, in that order; default all) at the vector, each
        certified as :meth:`sign_of_form` certifies it and computed when it is asked for: one
        product of balls for all of them (:meth:`form_balls`), a row's exact form only where its
        ball holds 0 with a radius (a ball of radius 0 is the exact value: a zero row is 0).

        Parameters
        ----------
        F : fmpq_mat, m x n
        rows : list of int, optional
        """
        rows = range(F.nrows()) if rows is None else rows
        q = self.known_rational()
        if q is not None:
            V = F * q
            yield from ((V[r, 0] > 0) - (V[r, 0] < 0) for r in rows)
            return
        vals = self.form_balls(F)
        for r in rows:
            v = vals[0][r, 0] if vals is not None else None
            s = ball_sign(v) if v is not None else 0
            yield s if s or (v is not None and v.is_zero()) else self.sign_of_form(submatrix(F, [r], None))

    def form_balls(self, forms: fmpq_mat) -> tuple[arb_mat, int] | None:
        """(balls of forms . x, their precision) from the ball of x already computed, or None (no
        ball yet: a state decided by its structure need not be evaluated): the values mode
        selection's pivoting reads; a sign they do not show is asked of :meth:`sign_of_form`.

        Parameters
        ----------
        forms : fmpq_mat, m x n"""
        if self._ball is None or self.known_rational() is not None:
            return None
        prec = max(64, self._prec)
        with workprec(prec):
            return arb_mat(forms) * self._ball, prec

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
    """A rational vector.

    Parameters
    ----------
    q : fmpq_mat
        Its entries, an n x 1 column.
    policy : Policy, optional
        The precision policy (default ``DEFAULT_POLICY``).
    """

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
    linear, so phases from c v have the event times of v and c times its states).

    Parameters
    ----------
    c : Real
        The factor; the caller has proven c > 0 (signs of forms at c v are taken from v).
    v : ExactVector
    policy : Policy, optional
        Default: v's.
    """

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
    with r P in the span of v's zero forms vanish on it.

    Parameters
    ----------
    P : fmpq_mat
        m x n, with n the length of v.
    v : ExactVector
    policy : Policy, optional
        Default: v's.
    zero_forms : fmpq_mat, optional
        Further forms (rows, m columns) known to vanish on P v, added to those pulled back from v.
    split : (W, T), optional
        P is the projection onto Ker W along Im T (P_I: W the annihilator of V_I, T a basis of
        T_I): the pulled-back forms come from the small matrix Z T (:func:`projected_forms`).
    """

    def __init__(self, P: fmpq_mat, v: ExactVector, policy: Policy | None = None,
                 zero_forms: fmpq_mat | None = None, split: tuple | None = None):
        zf = pulled_back_forms(P, v.zero_forms) if split is None else projected_forms(*split, v.zero_forms)
        if zero_forms is not None and zero_forms.nrows():
            zf = row_basis(zf, zero_forms) if zf.nrows() else zero_forms
        super().__init__(P.nrows(), zf, policy or v.policy)
        self.P, self.v = P, v
        self._split = split
        self._low_rank: tuple | None | bool = None  # (T, K) with P = I - T K; False: none

    def times_P(self, forms: fmpq_mat) -> fmpq_mat:
        """forms P, exactly.  For P_I = I - T (W T)^{-1} W (a ``split`` with W T invertible) as
        forms - (forms T) K, K = (W T)^{-1} W: 2 k n d products instead of k n^2 (d = dim T_I:
        the LDCP stages of a chain of 64 carts ask k = 32 forms of its 128 states, d = 2 to 32).

        Parameters
        ----------
        forms : fmpq_mat, k x m"""
        low = self._factors()
        if low is None:
            return forms * self.P
        T, K = low
        return forms - (forms * T) * K

    def _factors(self) -> tuple[fmpq_mat, fmpq_mat] | None:
        """(T, K) with P = I - T K, K = (W T)^{-1} W, for a ``split`` with W T invertible; None
        otherwise (computed once)."""
        if self._low_rank is None:
            self._low_rank = False
            if self._split is not None:
                W, T = self._split
                if W.nrows() == T.ncols() and T.ncols():
                    try:
                        self._low_rank = (T, (W * T).solve(W))
                    except ZeroDivisionError:  # W T singular: not such a split
                        pass
        return self._low_rank or None

    def _deps(self):
        return (self.v,)

    def _compute(self, prec):
        # P v with P as balls: v - T (K v) costs fewer conversions but its balls are wider (the
        # cancellation of two O(1) vectors), and the accuracy an anchor measures steers the
        # precision of the run (the 64-cart chain: 3.6x the steps' terms)
        return arb_mat(self.P) * self.v.arb(prec)

    def known_rational(self):
        q = self.v.known_rational()
        if q is not None:
            return self.P * q
        return super().known_rational()

    def _structural_sign(self, form):
        return self.v.sign_of_form(self.times_P(form))

    def form_balls(self, forms: fmpq_mat) -> tuple[arb_mat, int] | None:
        """Its own ball's values, or before it has one, (F P) v from v's ball (one exact product
        F P: the selection at a re-initialized state reads v's ball instead of evaluating P v;
        no wider, as P is applied exactly).

        Parameters
        ----------
        forms : fmpq_mat, m x n"""
        own = super().form_balls(forms)
        if own is not None or self._ball is not None or self.known_rational() is not None:
            return own
        return self.v.form_balls(self.times_P(forms))

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
        return (matrix_to_sympy(self.P) * cf).applyfunc(tidy)

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


class ComponentsVector(ExactVector):
    """A vector of exact reals (e.g. an initial state with closed-form entries).

    Parameters
    ----------
    comps : list of Real
        The components; the linear relations among them that their definitions prove give its
        zero forms (:func:`component_relations`: a component known to be 0, two copies of one
        exact real, components of one vector with that vector's zero forms).
    policy : Policy, optional
        The precision policy (default ``DEFAULT_POLICY``).
    """

    def __init__(self, comps: list[Real], policy: Policy | None = None):
        super().__init__(len(comps), component_relations(comps), policy)
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


def _positive_multiple(form: fmpq_mat, g: fmpq_mat) -> bool:
    """form = c g with a rational c > 0 (exactly)."""
    j = next((j for j in range(g.ncols()) if g[0, j] != 0), None)
    if j is None:
        return False
    c = form[0, j] / g[0, j]
    return c > 0 and form == g * c


def ca_matvec(P: fmpq_mat, xs: list | None) -> list | None:
    """P x for a rational matrix P and a vector of Calcium numbers (None stays None).

    Parameters
    ----------
    P : fmpq_mat
        m x n.
    xs : list of n Ca, or None
        The components of x (:class:`~lcs_exact.numbers.calcium.Ca`).

    Returns
    -------
    list of m Ca, or None
    """
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


def tidy(e):
    """Light SymPy clean-up of a closed-form entry (no simplify: it costs seconds)."""
    import sympy
    return sympy.nsimplify(e, rational=False) if e.is_number and e.is_Float else sympy.expand(e)


def as_exact_vector(x: Any, n: int | None = None, name: str = "x0", policy: Policy | None = None) -> ExactVector:
    """An ExactVector from an ExactVector, an ``fmpq_mat`` column or any vector input (entries
    rational-like, or SymPy closed forms).

    Parameters
    ----------
    x : ExactVector, fmpq_mat or sequence
        An exact vector (returned as it is), an ``fmpq_mat`` (a column, or a row), or a sequence
        (or array) of entries: rationals in any form :class:`~lcs_exact.LCS` accepts (int,
        ``"p/q"``, Fraction, a float read as its shortest decimal), exact reals
        (:class:`~lcs_exact.Real`) or SymPy closed forms (then a :class:`ComponentsVector`).
    n : int, optional
        The length x must have (:class:`~lcs_exact.errors.ShapeError` otherwise); None: any.
    name : str, optional
        The name of x in error messages (default ``"x0"``).
    policy : Policy, optional
        The precision policy of a vector made here (default ``DEFAULT_POLICY``).
    """
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
    rational fast path (section 5: every test is a sign of a linear form in x0).

    Parameters
    ----------
    lcs : LCS (SystemLike)
        The system; x0 must have its length n.
    x0 : ExactVector or vector input
        The state, in any form :func:`as_exact_vector` accepts.
    """
    return as_exact_vector(x0, lcs.n, "x0")


def homogenized(x: ExactVector) -> ExactVector:
    """x itself, or c q (c > 0 certified, q rational) when the forms proven to vanish on x leave
    a single direction q (rank n - 1): then every sign at x is the sign at q, exactly; the
    rational 0 when they leave none (rank n: a velocity reset to rest, x = P_I x- with P_I = 0).

    Parameters
    ----------
    x : ExactVector
    """
    if x.known_rational() is None and x.zero_forms.nrows() and x.zero_span.dim == x.n:
        return RationalVector(zeros(x.n, 1), x.policy)
    if x.known_rational() is not None or isinstance(x, ScaledVector) or x.exact_signs or \
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

