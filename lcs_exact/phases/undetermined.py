"""Values a solution does not determine (docs/extensions.md): an input u_j left free by the state
in a mode that is not autonomous (the potential of a floating node), and the outputs that
depend on one.  :meth:`Trajectory.u <lcs_exact.Trajectory.u>`, ``y`` and ``outputs`` report them
as such, never as a chosen value.
"""
from __future__ import annotations

from flint import arb

from ..errors import Undetermined
from ..numbers import ExactVector, Policy, Real

__all__ = ["UndeterminedReal", "PartlyUndetermined"]


class UndeterminedReal(Real):
    """A component the solution does not determine (an input left free by the state, or an
    output depending on one): it has no value to give.  Its ball is the whole real line (it
    contains every admissible value); digits, signs and closed forms raise
    :class:`~lcs_exact.errors.Undetermined`."""

    def __init__(self, name: str, policy: Policy | None = None):
        super().__init__(policy)
        self.name = name

    def _compute(self, prec):
        return arb(0, "inf")

    def _refuse(self, *args, **kw):
        raise Undetermined(f"{self.name} is not determined by the state here: any value that keeps the "
                           "complementarity conditions solves the LCS (a free input of a mode that is not "
                           "autonomous, e.g. the potential of a floating node)")

    ball = decimal = sign = _refuse

    def __float__(self):
        return float("nan")

    def label(self) -> str:
        return "undetermined"

    def __repr__(self):
        return "undetermined"

    def _closed_form(self):
        return None


class PartlyUndetermined(ExactVector):
    """u(t) or y(t) with some components undetermined (:class:`UndeterminedReal`); the others
    are those of ``v``.  Its ball has infinite radius in the undetermined components."""

    def __init__(self, v: ExactVector, undetermined: frozenset, kind: str):
        super().__init__(v.n, None, v.policy)
        self.v, self.free, self.kind = v, frozenset(undetermined), kind

    def _deps(self):
        return (self.v,)

    def _compute(self, prec):
        from flint import arb_mat
        b = self.v.arb(prec)
        return arb_mat([[arb(0, "inf") if i in self.free else b[i, 0]] for i in range(self.n)])

    def _structural_sign(self, form):
        if any(form[0, j] != 0 for j in self.free):
            UndeterminedReal(f"a form in {self.kind}").sign()
        return self.v.sign_of_form(form)

    def known_rational(self):
        return None

    def __getitem__(self, i: int) -> Real:
        if not -self.n <= i < self.n:
            raise IndexError(f"component {i} of a vector of length {self.n}")
        i %= self.n
        return UndeterminedReal(f"{self.kind}_{i}", self.policy) if i in self.free else self.v[i]

    def __iter__(self):
        return (self[i] for i in range(self.n))

    def __repr__(self):
        return "(" + ", ".join(c.label() for c in self) + ")"
