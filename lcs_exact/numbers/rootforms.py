"""Candidate roots of a phase function in its symbolic form (SymPy, lazily imported): an
exponential polynomial in one e^{gamma t} (logarithms of its algebraic roots), a one-frequency
sum a cos(wt) + b sin(wt) + c (SymPy's solve on it), and a harmonic sum that is a polynomial in
cos t (arccosines of its roots).  Candidates only: :mod:`lcs_exact.numbers.closedforms` proves
each one (inside the root's bracket, f exactly zero there) before it is accepted.
"""
from __future__ import annotations

import functools

from flint import arb

from .laplace import t_symbol

__all__ = ["exp_candidates", "solve_candidates", "harmonic_candidates"]


def exp_candidates(sym, b: arb | None = None) -> list:
    """Roots of an exponential sum f = sum c_k e^{mu_k t} whose exponents are integer multiples of
    one gamma (rational ratios): f is a polynomial in u = e^{gamma t}; each positive real root r of
    a factor of degree <= 2 gives t = log(r) / gamma. (Candidates only: they are proven by the
    caller.)"""
    import sympy
    t = t_symbol()
    if sym.has(sympy.sin, sympy.cos):
        return []
    f = sympy.powsimp(sympy.expand(sym.rewrite(sympy.exp)))
    terms: dict = {}
    for term in sympy.Add.make_args(f):
        coeff, mu = term, sympy.Integer(0)
        for e in term.atoms(sympy.exp):
            mu += sympy.diff(e.args[0], t)
            coeff = coeff.subs(e, 1)
        if coeff.has(t) or mu.has(t):
            return []  # t^m e^{mu t} terms or non-linear exponents: no polynomial in e^{gamma t}
        terms[mu] = terms.get(mu, 0) + coeff
    mus = [m for m in terms if m != 0]
    if not mus:
        return []
    ratios = [sympy.nsimplify(sympy.simplify(m / mus[0])) for m in mus]
    if not all(r.is_Rational for r in ratios):
        return []
    num = sympy.gcd([r.p for r in ratios])
    den = sympy.lcm([r.q for r in ratios])
    gam = sympy.simplify(mus[0] * num / den)
    u = sympy.Symbol("u", positive=True)
    powers = {m: int(sympy.nsimplify(sympy.simplify(m / gam))) for m in terms}
    low = min(powers.values())
    if max(powers.values()) - low > 12:
        return []  # (rates 1 and 10^-400: a polynomial of degree 10^400 in u is not built)
    poly = sympy.Poly(sum(terms[m] * u ** (powers[m] - low) for m in terms), u)
    if poly.degree() < 1 or poly.degree() > 12:
        return []
    out = []
    for factor, _ in poly.factor_list()[1]:
        if factor.degree() > 2:
            continue  # cubic/quartic radicals: unreadable and slow to prove
        for r in sympy.roots(factor, filter=None):
            if r.is_real and r.is_positive and r != 1:
                out.append(sympy.log(r) / gam)
    return out


@functools.lru_cache(maxsize=256)
def _one_frequency_solutions(sym):
    """(times, angles, step, w) of :func:`solve_candidates`: the solutions t of f = 0 are
    times[i] + k step / w and angles[j] / w + k step / w; None when f is not of that form.
    Cached: a source's function recurs event after event."""
    import sympy
    t = t_symbol()
    trig = sym.atoms(sympy.sin, sympy.cos)
    if sym.has(sympy.exp) and trig:
        sym = _without_common_exp(sym)  # e^{-at} (c1 cos wt + c2 sin wt): the zeros of the sum
    if sym is None or sym.has(sympy.exp, sympy.cosh, sympy.sinh) or not trig:
        return None
    freqs = {sympy.simplify(sympy.diff(f.args[0], t)) for f in trig}
    if len(freqs) != 1:
        return None
    (w,) = freqs
    if w.has(t) or not all(sympy.diff(f.args[0], t, 2) == 0 or f.args[0] == w * t for f in trig):
        return None
    if any(sympy.simplify(f.args[0] - w * t) != 0 for f in trig):
        return None  # a phase shift inside the argument: not of the form handled here
    expanded = sympy.expand(sym)
    A = expanded.coeff(sympy.cos(w * t))
    B = expanded.coeff(sympy.sin(w * t))
    c = sympy.simplify(expanded - A * sympy.cos(w * t) - B * sympy.sin(w * t))
    if c.has(t) or A.has(t) or B.has(t) or (A == 0 and B == 0):
        return None
    times: list = []  # candidate times t, each repeating with period ``step`` / w
    if c == 0 and B != 0:  # tan(wt) = -A/B: wt = atan(-A/B) + pi k
        angles, step = [sympy.atan(-A / B)], sympy.pi
    else:
        R = sympy.sqrt(sympy.nsimplify(A ** 2 + B ** 2))
        if A == 0:
            phi = sympy.pi / 2 if B > 0 else -sympy.pi / 2
        else:
            phi = sympy.atan(B / A) + (sympy.pi if A < 0 else 0)
        ratio = sympy.radsimp(-c / R)
        try:
            if abs(float(ratio)) > 1:
                return None  # R cos(.) = -c has no real solution
        except TypeError:
            return None
        psi = sympy.pi / 2 if ratio == 0 else sympy.acos(ratio)
        angles, step = [phi - psi, phi + psi], 2 * sympy.pi
        try:  # SymPy's own forms first (half-angle atan): often simpler, and proven the same way
            times = [sol for sol in sympy.solve(sym, t) if sol.is_number]
        except Exception:  # noqa: BLE001 - SymPy could not solve: the explicit branches remain
            times = []
    return tuple(times), tuple(angles), step, w


def _without_common_exp(sym):
    """f e^{-sigma t} when every term of f carries the same e^{sigma t} (a damped harmonic
    e^{sigma t} (c1 cos wt + c2 sin wt)): the same zeros, without the exponential; None otherwise."""
    import sympy
    t = t_symbol()
    f = sympy.powsimp(sympy.expand(sym))
    rates = set()
    for term in sympy.Add.make_args(f):
        rate = sympy.Integer(0)
        for e in term.atoms(sympy.exp):
            rate += sympy.diff(e.args[0], t)
        if rate.has(t):
            return None
        rates.add(sympy.nsimplify(rate) if rate.is_number else rate)
    if len(rates) != 1:
        return None
    (rate,) = rates
    out = sympy.powsimp(sympy.expand(f * sympy.exp(-rate * t)))
    return None if out.has(sympy.exp) else out


def solve_candidates(sym, b: arb) -> list:
    """Exact solutions of a one-frequency f = a cos(wt) + b sin(wt) + c near the root ball b:
    with R = sqrt(a^2 + b^2) and phi the angle of (a, b), f = R cos(wt - phi) + c vanishes at
    wt = phi +- acos(-c / R) + 2 pi k (both branches: SymPy's solve may return one of them only),
    at wt = atan(-a/b) + pi k when c = 0; SymPy's own solutions come first (candidates only: the
    caller proves them).

    >>> from lcs_exact.numbers.laplace import t_symbol
    >>> import sympy
    >>> t = t_symbol()
    >>> solve_candidates(sympy.cos(t) + sympy.sin(t) / 3, arb("1.8925"))   # tan t = -3
    [pi - atan(3)]
    >>> solve_candidates(4 * sympy.cos(2 * t) - 1, arb("0.659"))[0]        # cos 2t = 1/4
    acos(1/4)/2
    """
    import sympy
    from mpmath import mp, mpf
    family = _one_frequency_solutions(sym)
    if family is None:
        return []
    times, angles, step, w = family
    out = []
    with mp.workdps(30):
        target = mpf(b.mid().str(30, radius=False))
        period = mpf(str(sympy.N(step / w, 30)))
        for tb in list(times) + [a / w for a in angles]:
            k = int(mp.nint((target - mpf(str(sympy.N(tb, 30)))) / period))
            cand = sympy.expand(tb + step * k / w)
            if cand not in out:
                out.append(cand)
    return sorted(out, key=lambda e: abs(float(e) - float(target)))


@functools.lru_cache(maxsize=256)
def _harmonic_roots(sym):
    """(w, the real roots r in [-1, 1] of the factors of degree <= 4 in x = cos(wt)) of
    :func:`harmonic_candidates`, or None when f is not a polynomial in cos(wt), sin(wt) of one
    base frequency.  Cached (a source's function recurs event after event)."""
    import sympy
    t = t_symbol()
    trig = sym.atoms(sympy.sin, sympy.cos)
    if sym.has(sympy.exp, sympy.cosh, sympy.sinh) or len(trig) < 2:
        return None
    freqs = set()
    for f in trig:
        k = sympy.simplify(sympy.diff(f.args[0], t))
        if k.has(t) or sympy.simplify(f.args[0] - k * t) != 0:
            return None
        freqs.add(k)
    base = min(freqs, key=lambda v: float(v))
    mult = {}
    for v in freqs:
        r = sympy.nsimplify(sympy.simplify(v / base))
        if not r.is_Integer or r > 8:
            return None
        mult[v] = int(r)
    x = sympy.Symbol("x")
    expanded = sympy.expand(sym)
    P, Q = sympy.Integer(0), sympy.Integer(0)
    rest = expanded
    for v, k in mult.items():
        a = expanded.coeff(sympy.cos(v * t))
        bb = expanded.coeff(sympy.sin(v * t))
        if a.has(t) or bb.has(t):
            return None  # t cos(vt) (a repeated pair): not a polynomial in cos t
        rest = rest - a * sympy.cos(v * t) - bb * sympy.sin(v * t)
        P += a * sympy.chebyshevt(k, x)
        Q += bb * (sympy.chebyshevu(k - 1, x) if k >= 1 else 0)
    rest = sympy.simplify(rest)
    if rest.has(t):
        return None
    P += rest
    poly = sympy.Poly(sympy.expand(P ** 2 - (1 - x ** 2) * Q ** 2) if Q != 0 else sympy.expand(P), x)
    if poly.degree() < 1 or poly.degree() > 16:
        return None
    roots = []
    for factor, _ in sympy.factor_list(poly)[1]:
        fp = sympy.Poly(factor, x)
        if fp.degree() > 4:
            continue
        for r in sympy.roots(fp, multiple=True):
            # numerically: a real root may be written with I (casus irreducibilis), and
            # float() of an expression SymPy cannot decide is real raises
            try:
                rv = complex(sympy.N(r, 30))
            except TypeError:  # not a number SymPy can evaluate
                continue
            if r.is_real is not True or abs(rv.imag) > 1e-20 or abs(rv.real) > 1:  # (a form with I)
                continue
            roots.append(r)
    return base, tuple(roots)


def harmonic_candidates(sym, b: arb) -> list:
    """Roots of f = sum_k (a_k cos(k w t) + b_k sin(k w t)) + c whose frequencies are integer
    multiples of one w (a spring and its harmonics): with x = cos(wt), cos(kwt) = T_k(x) and
    sin(kwt) = sin(wt) U_{k-1}(x), so f = P(x) + sin(wt) Q(x) and every root has
    P(x)^2 = (1 - x^2) Q(x)^2: a polynomial whose roots r in [-1, 1] (in radicals, degree <= 4
    per factor) give the candidates t = (+-acos(r) + 2 pi m) / w near the ball b, e.g.
    acos((1 + sqrt(129))/16) (candidates only: the caller proves them).

    >>> from lcs_exact.numbers.laplace import t_symbol
    >>> import sympy
    >>> t = t_symbol()
    >>> harmonic_candidates(16 * sympy.cos(2 * t) - 2 * sympy.cos(t) + 8, arb("0.67"))[0]  # 32x^2 - 2x - 8
    acos(1/32 + sqrt(257)/32)
    """
    import sympy
    from mpmath import mp, mpf
    family = _harmonic_roots(sym)
    if family is None:
        return []
    base, roots = family
    out = []
    with mp.workdps(30):
        target = mpf(b.mid().str(30, radius=False))
        wv = mpf(str(sympy.N(base, 30)))
        for r in roots:
            for branch in (sympy.acos(r), -sympy.acos(r)):
                val = mpf(str(sympy.N(branch, 30))) / wv
                m = int(mp.nint((target - val) / (2 * mp.pi / wv)))
                cand = (branch + 2 * sympy.pi * m) / base
                if cand not in out:
                    out.append(cand)
    return sorted(out, key=lambda e: abs(float(e) - float(target)))
