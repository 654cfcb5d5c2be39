"""Closed forms of event times: candidates and their proofs (docs/numerics.md).

A root theta of f(t) = g e^{A_I t} v (a phase function) may have a closed form: a small-height
rational, a rational multiple of pi/omega (omega a frequency of A_I) plus nothing else, a
logarithm of a rational over a rational eigenvalue, a logarithm of an algebraic root of f written
as a polynomial in e^{gamma t}, or an exact solution of a one-frequency f.  A candidate is
accepted only when proven:

1. it lies inside the certified bracket of the root (a ball comparison well above the bracket's
   width), and
2. f vanishes there exactly: with Calcium (:mod:`lcs_exact.calcium`: f(t*) = g sum_lambda
   e^{lambda t*} K_lambda ... v evaluated exactly, then its zero test, which never answers wrongly),
   or, when Calcium is unavailable or undecided, SymPy's simplification of the symbolic f(t*) to
   a literal 0 under the run's deadline (last resort, off the hot path).

Nothing here runs unless a closed form is asked for (``closed_form`` on first access, fixtures,
``closed_forms=True``) or an exact zero is needed by a sign decision, an order of roots or a
grazing test.  SymPy is imported lazily.
"""
from __future__ import annotations

from fractions import Fraction
from typing import Any

from flint import arb, arb_mat, fmpq, fmpq_mat

from . import calcium
from .balls import ball_sign, closed_form_arb, workprec
from ..errors import InvalidArgument, LCSError, UnresolvedSign
from .expm import Spectrum, spectrum_of
from .laplace import laplace_closed_form, symbolic_expm, t_symbol
from .rootforms import exp_candidates, harmonic_candidates, solve_candidates
from .forms import Closed, SympyOutOfTime, sympy_budget, sympy_proves_zero
from ..algebra import matrix_to_sympy
from .algebraics import radical_form
from .vectors import ProjectedVector, RationalVector
from .expvectors import orbit_start
from ..algebra import in_row_span, rank, row_basis, solve_any, vstack

__all__ = ["candidates", "observed", "prove_root", "prove_root_is", "prove_zero_at", "function_closed_form", "prove_touch", "prove_flat_touch",
           "exp_candidates", "solve_candidates", "harmonic_candidates", "symbolic_candidates"]

_MAX_SIMPLIFY_OPS = 400


def _frequencies(M: fmpq_mat, factors: list | None = None) -> tuple[list[fmpq], list[fmpq]]:
    """(omega^2 of the complex-pair quadratic factors, real rational eigenvalues) of chi(M),
    exactly (no SymPy); ``factors``: chi's irreducible factors when already known."""
    squares, lambdas = [], []
    for p, _ in (factors if factors is not None else M.charpoly().factor()[1]):
        c = p.coeffs()
        if p.degree() == 1:
            lambdas.append(-c[0] / c[1])
        elif p.degree() == 2:
            q, pp, a2 = c
            disc = q / a2 - (pp / a2) ** 2 / 4
            if disc > 0:  # a complex pair; a real irrational pair gives no candidate here
                squares.append(disc)
    return squares, lambdas


def candidates(theta: arb, M: fmpq_mat, factors: list | None = None) -> list[Closed]:
    """Small-height candidates near the ball ``theta``: rationals, (p/q) pi/omega, log(p/q)/lambda
    (light :class:`~lcs_exact.forms.Closed` forms, nonnegative, without repetition).

    Parameters
    ----------
    theta : arb
        The ball of the root.
    M : fmpq_mat
        The phase's matrix: its frequencies omega (complex pairs of quadratic factors of det(sI - M),
        and omega = 1) and rational eigenvalues lambda give the pi/omega and log/lambda candidates.
    factors : list, optional
        [(p, multiplicity)]: the irreducible factors of det(sI - M) over Q, when known
        (:meth:`~lcs_exact.numbers.expm.Spectrum.irreducible_factors`); else they are computed.
    """
    from mpmath import mp, mpf
    out = []
    with mp.workdps(40):
        x = mpf(theta.mid().str(40, radius=False))

        def approx(v):
            f = Fraction(str(v))
            return {f.limit_denominator(d) for d in (1, 2, 3, 4, 6, 8, 12, 16, 24, 100, 1000)}

        for f in approx(x):
            out.append(Closed.rational(fmpq(f.numerator, f.denominator)))
        squares, lambdas = _frequencies(M, factors)
        for w2 in [fmpq(1)] + squares:
            wv = mp.sqrt(mpf(int(w2.p)) / int(w2.q))
            for f in approx(x * wv / mp.pi):
                if f > 0:
                    out.append(Closed.pi_over_sqrt(w2) * fmpq(f.numerator, f.denominator))
        for lam in lambdas:
            rate = mpf(int(lam.p)) / int(lam.q) * x
            if lam != 0 and abs(rate) <= 700:  # e^{lam t} a small-height rational: |lam t| < 700
                v = mp.exp(rate)
                for f in approx(v):
                    # log(f) / lam >= 0: f > 1 with lam > 0, or f < 1 with lam < 0
                    if f > 0 and f != 1 and (f > 1) == (lam > 0):
                        out.append(Closed.log(fmpq(f.numerator, f.denominator)) * (1 / lam))
    seen, uniq = set(), []
    for c in out:
        if c not in seen and (c.terms or c.const >= 0):
            seen.add(c)
            uniq.append(c)
    return uniq


def _shifted_candidates(b: arb, spectrum: Spectrum, v: Any):
    """Candidates near the ball b; when the start is v = e^{Ms} w with a closed-form s (e.g.
    x0 = e^{-sqrt2 M} w), also c - s for the candidates c of the time measured on w's orbit
    (a touch at sqrt 2 is pi-free on the orbit of w: its candidate is c - s)."""
    yield from candidates(b, spectrum.M, spectrum.irreducible_factors())
    inner, shift = orbit_start(v, spectrum.M)
    sc = shift.closed if shift is not None else None
    if sc is not None and not sc.is_zero:
        with workprec(200):
            bs = b + sc.arb()
        for c in candidates(bs, spectrum.M, spectrum.irreducible_factors()):
            yield c - sc


def _inside(cand, lo: fmpq, hi: fmpq) -> bool:
    """The candidate lies in [lo, hi] (certified at a precision well above the bracket's width)."""
    bits = 64
    w = hi - lo
    if w > 0:
        bits = max(64, int(w.q.bit_length() - w.p.bit_length()) + 64)
    with workprec(bits):
        cb = cand.arb()
        return bool(cb >= arb(lo) and cb <= arb(hi))


def observed(spectrum: Spectrum, g: fmpq_mat, v: Any) -> tuple[Spectrum, fmpq_mat, Any]:
    """f(t) = g e^{Mt} v on the left Krylov space of g: (spectrum of M', c, O v) with
    f(t) = c e^{M't} (O v) and f^{(d)} = c M'^d e^{M't} (O v).

    The rows of O are the canonical basis of span{g, gM, gM^2, ...} (dimension d <= n), O M = M' O
    and g = c O.  A proof about f then works in d dimensions: a stop on one block of a 33-state
    scene evaluates e^{M t*} of that block in Calcium, not of all 33 states (minutes).
    (spectrum, g, v) itself unless d <= n/2 (the reduction would save little).

    Parameters
    ----------
    spectrum : Spectrum
        The spectral data of M.
    g : fmpq_mat
        1 x n row.
    v : ExactVector
        The start state.
    """
    cache = spectrum.__dict__.setdefault("_observed", {})
    key = tuple(g.entries())
    if key not in cache:
        cache[key] = _krylov_basis(spectrum.M, g)
    O, Mr, c = cache[key]
    if O is None:
        return spectrum, g, v
    q = v.known_rational()
    w = RationalVector(O * q, v.policy) if q is not None else ProjectedVector(O, v)
    return spectrum_of(Mr), c, w


def _krylov_basis(M: fmpq_mat, g: fmpq_mat) -> tuple:
    """(O, M', c) of :func:`observed`, or (None, None, None) when d > n/2."""
    n = M.ncols()
    rows = [g]
    for _ in range(n // 2):  # g M^j, j <= n/2: the space has dimension <= n/2 iff they are dependent
        rows.append(rows[-1] * M)
    if rank(vstack(*rows)) == len(rows):
        return None, None, None
    O = row_basis(*rows)
    Mr = solve_any(O.transpose(), (O * M).transpose()).transpose()  # O M = M' O
    c = solve_any(O.transpose(), g.transpose()).transpose()  # g = c O
    return O, Mr, c


def prove_zero_at(spectrum: Spectrum, g: fmpq_mat, v: Any, cand, *, derivative: int = 0,
                  deadline=None) -> bool | None:
    """g M^d e^{M t*} v == 0 at the closed form t* (``derivative`` d): True (proven), False
    (proven nonzero), None (unknown).  Calcium first; SymPy simplification as a last resort.

    Parameters
    ----------
    spectrum : Spectrum
        The spectral data of the phase's matrix M (A_I of its mode).
    g : fmpq_mat
        1 x n row: f(t) = g e^{Mt} v.
    v : ExactVector
        The phase's start state.
    cand : Closed
        The closed form t*.
    derivative : int, optional
        d >= 0 (default 0): the d-th derivative of f at t*.
    deadline : Deadline, optional
        The run's ``time_limit`` (:class:`~lcs_exact.balls.Deadline`), looked at during the SymPy steps.
    """
    gd = g
    for _ in range(derivative):
        gd = gd * spectrum.M
    inner, shift = orbit_start(v, spectrum.M)
    if shift is not None:  # v = e^{M s} w: f(t*) = g e^{M (t* + s)} w
        sc = shift.closed
        if sc is not None:
            v, cand = inner, cand + sc
    q = v.exact_rational()
    if q is not None:
        if cand.is_zero:
            return (gd * q)[0, 0] == 0
        v = RationalVector(q)
    spectrum, gd, v = observed(spectrum, gd, v)  # the proof in the dimension f needs
    if q is None and calcium.available():
        # a (p/q) pi / omega time after an irrational start: when e^{M t*} is a rational matrix E
        # (proven by Calcium), f(t*) = (g E) v, decided by the relations known on v (the trigger
        # that started the phase) - no closed form of v is needed
        proof = _rational_propagator_zero(spectrum, gd, v, cand)
        if proof is not None:
            return proof
    if calcium.available():
        try:
            tc = cand.to_ca()
            vc = v.to_ca()
            if tc is not None and vc is not None:
                x = spectrum.ca_apply(tc, vc, calcium)
                if x is not None:
                    acc = calcium.Ca(0)
                    for j in range(spectrum.n):
                        if gd[0, j] != 0:
                            acc = acc + x[j] * calcium.Ca(gd[0, j])
                    z = acc.is_zero()
                    if z is not None:
                        return z
        except (ValueError, ZeroDivisionError, UnresolvedSign):
            pass  # Calcium could not build f(t*) (an undecided divisor): try SymPy
    return _sympy_vanishes(spectrum, gd, v, cand, deadline)


def _rational_propagator_zero(spectrum: Spectrum, g: fmpq_mat, v: Any, cand) -> bool | None:
    """g e^{M t*} v == 0 through a rational e^{M t*} (e.g. -I at t* = pi for a unit-frequency
    oscillator): True when g E lies in the span of v's proven zero forms, False when its sign at v
    is certified nonzero, None otherwise (also when e^{M t*} is not rational)."""
    if not cand.has_pi:
        return None
    try:
        tc = cand.to_ca()
        E = spectrum.exact_at(tc, calcium) if tc is not None else None
    except (ValueError, ZeroDivisionError, UnresolvedSign):
        return None
    if E is None:
        return None
    form = g * E
    if all(form[0, j] == 0 for j in range(form.ncols())):
        return True
    if v.zero_forms.nrows() and in_row_span(form, v.zero_forms):
        return True
    return None


def _sympy_vanishes(spectrum: Spectrum, g: fmpq_mat, v: Any, cand, deadline) -> bool | None:
    import sympy
    try:
        with sympy_budget(deadline, "the symbolic value of a phase function at a candidate"):
            sym = function_closed_form(spectrum, g, v)
            if sym is None:
                return None
            expr = sympy.expand_trig(sym.subs(t_symbol(), cand.to_sympy()))
            if sympy.count_ops(expr) > _MAX_SIMPLIFY_OPS:
                return None  # SymPy's simplify can take minutes on large expressions
    except SympyOutOfTime:
        return None
    if deadline is not None:
        deadline.check(" while proving a closed form")
    return sympy_proves_zero(expr, deadline)


def function_closed_form(spectrum: Spectrum, g: fmpq_mat, v: Any):
    """f(t) = g e^{Mt} v as a SymPy expression in t, or None; cross-checked against the certified
    ball of f at two rational times (a defect in the symbolic inversion must never become a
    false proof)."""
    spectrum, g, v = observed(spectrum, g, v)
    q = v.exact_rational()
    if q is not None:
        key = (spectrum.M.nrows(), tuple(spectrum.M.entries()), tuple(g.entries()), tuple(q.entries()))
        if key in _SYMBOLIC:
            return _SYMBOLIC[key]
        sym = laplace_closed_form(spectrum.M, g, q)
    else:
        vc = _radical_start(v)
        if vc is None:
            vc = v.closed_form()
        E = symbolic_expm(spectrum) if vc is not None else None
        sym = None if E is None else (matrix_to_sympy(g) * E * vc)[0, 0].expand()
    if sym is not None:
        import sympy
        t = t_symbol()
        if sym.has(sympy.I):
            return None  # SymPy's general inversion (a repeated complex pair) wrote it with I
        for tq in (fmpq(1, 7), fmpq(5, 3)):
            with workprec(128):
                want = (arb_mat(g) * spectrum.apply(arb(tq), v.arb(128), 128))[0, 0]
                got = closed_form_arb(sym.subs(t, sympy.Rational(int(tq.p), int(tq.q))))
            if not want.overlaps(got):
                raise LCSError(f"internal error: the symbolic form {sym} of g e^(Mt) v disagrees "
                               f"with its certified value at t = {tq}")
    if q is not None:  # the same function recurs (a source's, event after event): keep it
        if len(_SYMBOLIC) > 256:
            _SYMBOLIC.clear()
        _SYMBOLIC[key] = sym
    return sym


def _radical_start(v: Any):
    """v as a SymPy column of radicals when every component is a real algebraic number of degree
    <= 4 (each proven equal by Calcium, :func:`~lcs_exact.numbers.algebraics.radical_form`), else None.  The
    state after an impact at t1 = 2 pi - 2 atan(sqrt(3)/2) is algebraic, but its symbolic form is
    a tangle of cos(2 atan(..)) in which the next phase's zero (an atan of a radical) is not
    found; in radicals it is."""
    if not calcium.available():
        return None
    cs = v.to_ca()
    if cs is None:
        return None
    out = []
    for c in cs:
        r = radical_form(c)
        if r is None:
            return None
        out.append(r)
    import sympy
    return sympy.Matrix(out)


#: symbolic forms g e^{Mt} q of rational starts, by (M, g, q) (bounded)
_SYMBOLIC: dict = {}


def prove_root(root: Any, spectrum: Spectrum, g: fmpq_mat, v: Any, deadline=None):
    """(expr, Calcium number or None) for the root's proven closed form, or None.

    Candidates near the root (:func:`candidates`, also shifted along the orbit of the start, then
    :func:`symbolic_candidates`) are tried in turn; the first that lies in the root's bracket with
    f proven zero there (:func:`prove_zero_at`) is the answer.  In a bracket that may hold several
    roots (``root.simple`` false: a multiple root) a candidate must also be its only zero
    (:func:`_only_zero`).

    Parameters
    ----------
    root : RootReal
        A root of f = g e^{Mt} v (:class:`~lcs_exact.roots.RootReal`).
    spectrum : Spectrum
        The spectral data of the phase's matrix M (A_I of its mode).
    g : fmpq_mat
        1 x n row: f(t) = g e^{Mt} v.
    v : ExactVector
        The phase's start state.
    deadline : Deadline, optional
        The run's ``time_limit`` (:class:`~lcs_exact.balls.Deadline`), looked at during the SymPy steps.
    """
    b = root.arb(200)
    lo, hi = root.interval()
    if not root.simple:
        # a bracket that may hold several roots (a multiple root, a cluster): a zero of f inside
        # it is the crossing only when it is the bracket's one zero
        for cand in _shifted_candidates(b, spectrum, v):
            if _inside(cand, lo, hi) and _only_zero(root, spectrum, g, v, cand, deadline):
                return cand, cand.to_ca()
        return None
    for cand in _shifted_candidates(b, spectrum, v):
        if _inside(cand, lo, hi) and prove_zero_at(spectrum, g, v, cand, deadline=deadline) is True:
            return cand, cand.to_ca()
    for cand in symbolic_candidates(spectrum, g, v, b, deadline):
        if _inside(cand, lo, hi) and prove_zero_at(spectrum, g, v, cand, deadline=deadline) is True:
            return cand, cand.to_ca()
    return None


def _only_zero(root: Any, spectrum: Spectrum, g: fmpq_mat, v: Any, cand, deadline) -> bool:
    """cand is the only zero of f in the root's bracket [lo, hi]: f^{(j)}(cand) = 0 proven for
    j < m and the enclosure of f^{(m)} over [lo, hi] excludes 0.  By Rolle f then has at most m
    zeros in [lo, hi] counted with multiplicity, and cand has m: the crossing (a zero, f(lo) > 0 >
    f(hi)) is cand.  A crossing through a triple root at t = 1 from e^{-A} w is proven so."""
    lo, hi = root.interval()
    return _zero_order(spectrum, g, v, cand, root.function.at(max(200, root.anchor_prec)), lo, hi, deadline) is not None


def _zero_order(spectrum: Spectrum, g: fmpq_mat, v: Any, cand, f: Any, lo: fmpq, hi: fmpq, deadline) -> tuple | None:
    """(m, sign of f^{(m)} on [lo, hi]): f^{(j)}(cand) = 0 proven for j < m and the enclosure of
    f^{(m)} over [lo, hi] excludes 0 (m >= 1, at most 16); None when a derivative at cand is not
    proven zero first."""
    for m in range(min(spectrum.n, 16) + 1):
        if m:
            s = ball_sign(f.sign_enclose(lo, hi, m))
            if s:
                return m, s
        if prove_zero_at(spectrum, g, v, cand, derivative=m, deadline=deadline) is not True:
            return None
    return None


def symbolic_candidates(spectrum: Spectrum, g: fmpq_mat, v: Any, b: arb, deadline=None,
                        generators: tuple = ()):
    """Candidates (:class:`Closed`) near the ball b from the symbolic form of f = g e^{Mt} v:
    ``generators`` (default: exp_candidates, solve_candidates, harmonic_candidates, cheap ones
    first).  Each SymPy step runs under :func:`~lcs_exact.forms.sympy_budget` (its work counted:
    a simplification of a harmonic sum once took 25 s past a run's ``time_limit``); a step out of
    work gives none.  A generator (candidates are yielded as found).

    Parameters
    ----------
    spectrum : Spectrum
        The spectral data of the phase's matrix M (A_I of its mode).
    g : fmpq_mat
        1 x n row: f(t) = g e^{Mt} v.
    v : ExactVector
        The phase's start state.
    b : arb
        The ball of the root sought.
    deadline : Deadline, optional
        The run's ``time_limit`` (:class:`~lcs_exact.balls.Deadline`), looked at during the SymPy steps.
    generators : tuple of callables, optional
        Each called as ``gen(sym, b)`` on the SymPy form ``sym`` of f, returning SymPy expressions;
        those not representable as :class:`Closed` are skipped.  Empty (default): the three above.
    """
    try:
        with sympy_budget(deadline, "the symbolic inversion of a phase function"):
            sym = function_closed_form(spectrum, g, v)
    except SympyOutOfTime:
        return
    if sym is None:
        return
    for more in generators or (exp_candidates, solve_candidates, harmonic_candidates):
        try:
            with sympy_budget(deadline, f"the search of {getattr(more, '__name__', 'candidates')}"):
                exprs = list(_representable(more(sym, b)))
        except SympyOutOfTime:
            continue
        yield from exprs


def prove_root_is(root: Any, spectrum: Spectrum, g: fmpq_mat, v: Any, cand: Closed, deadline=None) -> bool:
    """True when the root (a :class:`~lcs_exact.roots.RootReal` of f = g e^{Mt} v) is proven to
    be the closed form ``cand``, a candidate the caller knows of (the horizon of the run): its
    bracket holds one root, ``cand`` lies in it and f(cand) = 0.

    Parameters
    ----------
    root : RootReal
    spectrum : Spectrum
        The spectral data of the phase's matrix M (A_I of its mode).
    g : fmpq_mat
        1 x n row: f(t) = g e^{Mt} v.
    v : ExactVector
        The phase's start state.
    cand : Closed
    deadline : Deadline, optional
        The run's ``time_limit`` (:class:`~lcs_exact.balls.Deadline`), looked at during the SymPy steps.
    """
    if not root.simple:
        return False
    lo, hi = root.interval()
    return _inside(cand, lo, hi) and prove_zero_at(spectrum, g, v, cand, deadline=deadline) is True


def _representable(exprs):
    """The candidates (SymPy expressions) that are closed forms of the supported set, as
    :class:`Closed`; the others (a root written with I, a RootOf) are skipped: a candidate is a
    guess to be proven, and one that cannot be written is simply not tried."""
    for expr in exprs:
        try:
            yield Closed.of_sympy(expr)
        except InvalidArgument:
            continue


def prove_flat_touch(spectrum: Spectrum, g: fmpq_mat, v: Any, f: Any, lo: fmpq, hi: fmpq, deadline=None) -> bool:
    """f >= 0 on [lo, hi], touching 0 only at a closed form t* there: f^{(j)}(t*) = 0 for j < m
    proven and f^{(m)} > 0 on all of [lo, hi] with m even (Taylor: f(t) = f^{(m)}(xi) (t - t*)^m / m!).
    The touch of (1 - t)^4, where f'' = 12 (1 - t)^2 vanishes too and no convexity is ever shown.

    Parameters
    ----------
    spectrum : Spectrum
        The spectral data of the phase's matrix M (A_I of its mode).
    g : fmpq_mat
        1 x n row: f(t) = g e^{Mt} v.
    v : ExactVector
        The phase's start state.
    f : ExpSum or TaylorSum
        The balls of f and its derivatives (``sign_enclose(lo, hi, d)``).
    lo, hi : fmpq
        The interval.
    deadline : Deadline, optional
        The run's ``time_limit``.
    """
    if not (f.sign_enclose(lo, hi, 1).contains(0) and f.sign_enclose(lo, hi, 2).contains(0)):
        return False  # f monotone, or convex/concave there: not a flat touch (the other provers' case)
    # the order _zero_order would stop at is the first derivative with a sign on [lo, hi], the same
    # for every candidate: none, an odd one or a negative one and no candidate can be proven (a
    # function below the balls' resolution: nothing to prove, only bits to add)
    signed = next((s for s in ((m, ball_sign(f.sign_enclose(lo, hi, m))) for m in range(3, min(spectrum.n, 16) + 1))
                   if s[1]), None)
    if signed is None or signed[0] % 2 or signed[1] < 0:
        return False
    with workprec(128):
        mid = arb(lo).union(arb(hi))
    for cand in _shifted_candidates(mid, spectrum, v):
        if _inside(cand, lo, hi):
            order = _zero_order(spectrum, g, v, cand, f, lo, hi, deadline)
            if order is not None and order[0] % 2 == 0 and order[1] > 0:
                return True
    return False


def prove_touch(spectrum: Spectrum, g: fmpq_mat, v: Any, lo: fmpq, hi: fmpq, deadline=None) -> bool | None:
    """A tangential touch at the critical point t* in [lo, hi] (f' = 0 there, f'' > 0 on it):
    True when a closed form t* is proven with f'(t*) = f(t*) = 0; None otherwise.

    Parameters
    ----------
    spectrum : Spectrum
        The spectral data of the phase's matrix M (A_I of its mode).
    g : fmpq_mat
        1 x n row: f(t) = g e^{Mt} v.
    v : ExactVector
        The phase's start state.
    lo, hi : fmpq
        The bracket of t*.
    deadline : Deadline, optional
        The run's ``time_limit`` (:class:`~lcs_exact.balls.Deadline`), looked at during the SymPy steps.
    """
    with workprec(128):
        mid = arb(lo).union(arb(hi))

    def stream():
        yield from _shifted_candidates(mid, spectrum, v)
        # t* is a root of f'
        yield from symbolic_candidates(spectrum, g * spectrum.M, v, mid, deadline, (exp_candidates, solve_candidates))

    for cand in stream():
        if not _inside(cand, lo, hi):
            continue
        if prove_zero_at(spectrum, g, v, cand, derivative=1, deadline=deadline) is True and \
                prove_zero_at(spectrum, g, v, cand, deadline=deadline) is True:
            return True
    return None
