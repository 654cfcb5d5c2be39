"""Vectors of exact real algebraic numbers (Calcium): the states of polynomial phases.

A free fall, a relay's constant field or any phase whose closed-loop matrix is nilpotent has
polynomial states; from an exact start their event times are algebraic (roots of polynomials,
:mod:`lcs_exact.phases.polyroots`), and so are the states there.  :class:`AlgebraicVector` holds
such a state as Calcium numbers (:mod:`.calcium`): every sign of a rational form is decided
exactly, and balls come from Calcium's enclosures at any precision.
"""
from __future__ import annotations

from flint import arb_mat, fmpq_mat

from . import calcium
from .algebraics import ca_from_state, ca_state, radical_form, rational_ca
from .balls import Policy
from .vectors import ExactVector, RationalVector

__all__ = ["AlgebraicVector", "algebraic_vector"]


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

    exact_signs = True

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
    """A RationalVector when every Calcium number of xs is rational, else an AlgebraicVector.

    Parameters
    ----------
    xs : list of Ca
        The components: real algebraic numbers (:class:`~lcs_exact.numbers.calcium.Ca`).
    zero_forms : fmpq_mat, optional
        Forms proven to vanish on the vector (kept by an AlgebraicVector, see :class:`ExactVector`).
    policy : Policy, optional
        The precision policy (default ``DEFAULT_POLICY``).
    """
    cs = [c.compact() for c in xs]
    qs = [c.to_fmpq() for c in cs]
    if all(q is not None for q in qs):
        return RationalVector(fmpq_mat(len(xs), 1, qs), policy)
    return AlgebraicVector(cs, zero_forms, policy, rationals=qs)
