"""The event step: steps one to three of Algorithm 7.1 (mode selection, z in V_I?, z := P_I z),
one function over two arithmetics.

    Newton      with restitution, Newton's impact law first: one jump of the velocities
    Step one    select I in S(z)
    Step two    z in V_I ?  yes: the phase starts in I;  no: step three
    Step three  z := P_I z, go to step one          (the re-initialization chain (4.9))

:func:`event_step` runs these steps once and for all; what a state is, and how a sign at it is
decided, is the arithmetic's (an object with the methods of :class:`StepArithmetic`):

* :class:`ExactStates`, Algorithm 7.1 itself (:mod:`~lcs_exact.dynamics.simulate`): a state is
  an exact vector; every sign is exact or certified (else UnresolvedSign); step one is S(z)
  computed by the LCPs of section 5 and its smallest mode taken (Remark 4.8, the run's choice
  outside Theorem 6.3); the impulse of the first jump is kept for the event.
* :class:`FamilyStates`, an impact cascade's cycle (:mod:`~lcs_exact.accumulations.cascade`): a state
  is a family of states (Taylor models on a box of parameters, :class:`FamilyState`); a sign is
  certified on the whole box or undecided (None), an exact zero only a structural one (a form
  vanishing on an exact subspace that holds every member); step one certifies that the mode the
  run selected is selected on the whole family (:func:`selection_verdict`: by Theorem 6.3 the
  smallest admissible mode is the one whose inputs are strictly positive), and an undecided
  sign anywhere ends the proof (:class:`~lcs_exact.taylormodels.NoProof`), never a guess.

Both decide step two by :func:`in_consistent_subspace` (the annihilator of V_I, form by form),
Newton's law by :func:`~lcs_exact.system.newton_impact` on their states (its signs are asked of
the state: ``sign_of_form``), and apply P_I and Newton's jump as the rational matrices they are.
``tests/test_eventstep.py`` runs both on the same scenes.
"""
from __future__ import annotations

from dataclasses import dataclass
from collections.abc import Mapping
from typing import Any, Callable, Iterator, Protocol

from flint import fmpq_mat

from ..algebra import image, is_zero, submatrix, vstack
from ..errors import Deadlock, UnresolvedSign, ZenoDetected
from ..modes import admissibility_forms, impulse_forms, mode_order, rcp_data, select_modes
from ..numbers import NoProof, ProjectedVector, RationalVector
from ..system import newton_impact

__all__ = ["Step", "StepArithmetic", "event_step", "in_consistent_subspace", "lex_sign_at", "selection_verdict",
           "SELECTION_CASES", "ExactStates", "FamilyState", "FamilyStates", "apply_forms", "vanishes"]


@dataclass(frozen=True)
class Step:
    """What an event step gives: the mode the next phase runs in, the chain of jumps (Newton's
    active set first when the law applied, then each mode I whose projection P_I was applied:
    (4.9)), the state after them (in the arithmetic's kind), and Newton's impact or None."""

    mode: Any
    chain: tuple
    state: Any
    impact: Any = None


class StepArithmetic(Protocol):
    """What :func:`event_step` asks of an arithmetic (module docstring)."""

    lcs: Any

    def signs(self, M: fmpq_mat, z) -> Iterator[int | None]:
        """The signs of the rows of M at z, each decided when it is asked for: exact or certified
        (-1, 0, 1), or None when undecided."""

    def undecided(self, what: str):
        """Raise the arithmetic's error for a decision ``what`` it could not make."""

    def impact(self, z):
        """Newton's impact at z (:func:`~lcs_exact.system.newton_impact`), or None."""

    def jump(self, impact, z):
        """The state after Newton's jump: impact.jump z."""

    def select(self, z) -> frozenset:
        """Step one: the mode of S(z) the run continues in."""

    def project(self, mode, z, first: bool):
        """Step three: P_I z (``first``: the event's first jump)."""

    def endless(self, cap: int):
        """Raise: the chain did not end after ``cap`` jumps (Remark 7.2 (2))."""


def event_step(arith: StepArithmetic, z) -> Step:
    """Steps one to three of Algorithm 7.1 at the state z (Newton's law first when the system
    has restitution), in the arithmetic ``arith``: the mode of the next phase, the chain of
    jumps, the state after them (:class:`Step`).  A chain of more than 2^k + n + 1 jumps does
    not end (infinite multiplicity, Remark 7.2 (2)): ``arith.endless``."""
    lcs = arith.lcs
    chain = []
    hit = arith.impact(z)
    if hit is not None:  # Newton's law (restitution) instead of P_I: one jump of the velocities
        chain.append(hit.active)
        z = arith.jump(hit, z)
    cap = 2 ** lcs.k + lcs.n + 1
    for _ in range(cap):
        I = arith.select(z)  # step one
        mode = lcs.mode(I)
        if in_consistent_subspace(arith, mode, z):  # step two
            return Step(mode, tuple(chain), z, hit)
        z = arith.project(mode, z, not chain)  # step three: z := P_I z
        chain.append(I)
    arith.endless(cap)


def in_consistent_subspace(arith: StepArithmetic, mode, z) -> bool:
    """Step two: z in V_I, decided form by form on the annihilator of V_I: False at the first
    form certified nonzero at z, True when every form is zero there (exactly: an exact zero, or a
    structural one for a family); ``arith.undecided`` when neither is certified."""
    undecided = False
    for s in arith.signs(mode.annihilator(), z):
        if s is None:
            undecided = True
        elif s:
            return False
    if undecided:
        arith.undecided(f"the state is not certified inside or outside V_{sorted(mode.I)}")
    return True


def lex_sign_at(arith: StepArithmetic, forms, z) -> int | None:
    """The lexicographic sign (5.7) of the forms (f_1, f_2, ...) at z: the sign of the first one
    not zero there; 0 when all are; None when a sign before the first nonzero one is undecided."""
    for s in arith.signs(vstack(*forms, ncols=arith.lcs.n), z):
        if s is None or s:
            return s
    return 0


#: the cases of :func:`selection_verdict`: why mode I is not certified the selected mode at z
#: (the message, and whether the sign was undecided rather than decided against I)
SELECTION_CASES = {
    "not autonomous": ("mode {} is not autonomous", False),
    "undecided": ("an admissibility sign of mode {} is not decided", True),
    "not admissible": ("mode {} is not admissible along the family", False),
    "input vanishes": ("an input of mode {} vanishes (a smaller mode is selected)", False),
}


def selection_verdict(arith: StepArithmetic, mode, z) -> str | None:
    """None when mode I is certified the mode Algorithm 7.1 selects at z under Theorem 6.3:
    every row of u_I(s) of the RCP admissibility forms lexicographically strictly positive, every
    row of y_Ic(s) nonnegative (I in S(z), (5.4)); the initial solution being unique, every
    admissible mode contains the inputs that do not vanish, i.e. I, so I is the smallest (Remark
    4.8).  Otherwise the key of :data:`SELECTION_CASES` that says why not."""
    if not mode.is_autonomous:
        return "not autonomous"
    for r, row in enumerate(admissibility_forms(mode)):
        s = lex_sign_at(arith, row, z)
        if s is None:
            return "undecided"
        if s < 0:
            return "not admissible"
        if s == 0 and r < len(mode.I):
            return "input vanishes"
    return None


# ---------------------------------------------------------------------------------------------
# exact states: Algorithm 7.1
# ---------------------------------------------------------------------------------------------


def apply_forms(P: fmpq_mat, z, split: tuple | None = None):
    """P z for a rational matrix P and an exact vector z (rational stays rational); ``split`` =
    (W, T) when P projects onto Ker W along Im T (its zero forms from the small matrix Z T)."""
    q = z.known_rational()
    return RationalVector(P * q, z.policy) if q is not None else ProjectedVector(P, z, split=split)


def _point(z):
    """An exact vector as the modes' functions take it: its rational value when known."""
    q = z.known_rational()
    return q if q is not None else z


class ExactStates:
    """The arithmetic of Algorithm 7.1 (module docstring): exact vectors, exact or certified signs.

    ``choose(S, z)`` is step one's choice in S(z) (default: its smallest mode, Remark 4.8; a run
    settles choices outside Theorem 6.3 there); ``t``, the event time, names the event in the
    errors.  ``impulse`` is {i: u^{-i}} of the event's first jump once the step has run (Newton's
    impulse, or the initial solution's in the first mode of the chain; empty without a jump)."""

    def __init__(self, lcs, choose: Callable | None = None, t=None):
        self.lcs, self.t = lcs, t
        self.choose = choose if choose is not None else (lambda S, z: min(S, key=mode_order))
        self.impulse: dict = {}

    def when(self) -> str:
        return f"t = {self.t.label()}" if self.t is not None else "the event"

    def signs(self, M: fmpq_mat, z) -> Iterator[int]:
        return z.signs_of_rows(M)  # one product for all the rows (exact, or balls first)

    def undecided(self, what: str):
        raise UnresolvedSign(f"{what} at {self.when()}")

    def impact(self, z):
        return newton_impact(self.lcs, _point(z))

    def jump(self, impact, z):
        self.impulse = {0: apply_forms(impact.impulse_forms, z)}
        return apply_forms(impact.jump, z)

    def select(self, z) -> frozenset:
        S = select_modes(self.lcs, _point(z))
        if not S:
            raise Deadlock(f"deadlock at {self.when()}: S(z) is empty at z = {z!r} (Remark 7.2)")
        return self.choose(S, z)

    def project(self, mode, z, first: bool):
        if first:
            self.impulse = Impulse(mode, z)
        return apply_forms(mode.projection(), z, (mode.annihilator(), mode.jump_space()))

    def endless(self, cap: int):
        raise ZenoDetected(f"re-initialization at {self.when()} did not end after {cap} jumps "
                           "(infinite multiplicity, Remark 7.2 (2))")


class Impulse(Mapping):
    """{i: u^{-i}} of the initial solution in mode I from z (:func:`_impulse`), computed on first
    access: the LDCP stages at z run again for it, and a run that never reads an event's impulse
    (a large system's impacts: 10 % of the run of 64 carts) does not pay for them."""

    def __init__(self, mode, z):
        self.mode, self.z = mode, z
        self._terms: dict | None = None

    def _data(self) -> dict:
        if self._terms is None:
            self._terms = _impulse(self.mode, self.z)
        return self._terms

    def __getitem__(self, i):
        return self._data()[i]

    def __iter__(self):
        return iter(self._data())

    def __len__(self):
        return len(self._data())

    def __repr__(self):
        return repr(self._data())


def _impulse(mode, z) -> dict:
    """{i: u^{-i}} of the initial solution in mode I from z (nonzero terms only); empty for a
    mode that is not autonomous (its impulse is not unique, only the jump P_I z is)."""
    out = {}
    if not mode.is_autonomous:
        return out
    lcs = mode.lcs
    # well-posed (Theorem 6.3): the impulse of the unique initial solution comes from the LDCP
    # stages at z; otherwise from the mode's RCP data W_I(s) = -G_II^{-1} R_I
    q = z.known_rational()
    forms = impulse_forms(lcs, q if q is not None else z) if lcs.well_posedness() else rcp_data(mode).impulse
    for i, U in enumerate(forms):
        if not is_zero(U):
            out[i] = RationalVector(U * q, z.policy) if q is not None else ProjectedVector(U, z)
    return out


# ---------------------------------------------------------------------------------------------
# families of states: an impact cascade's Taylor models
# ---------------------------------------------------------------------------------------------


def vanishes(form: fmpq_mat, U: fmpq_mat) -> bool:
    """form . x = 0 for every x in span(U) (exactly)."""
    return U.ncols() == 0 or all(v == 0 for v in (form * U).entries())


@dataclass(frozen=True)
class FamilyState:
    """A family of states: ``x`` its components (Taylor models on ``box``, a
    :class:`~lcs_exact.taylormodels.Box`), ``U`` an exact subspace (a basis) holding every member.
    Signs are the family's (:meth:`sign`); :meth:`sign_of_form` is the one decision the LCPs of
    Newton's law ask of a state."""

    box: Any
    x: list
    U: fmpq_mat

    def sign(self, form: fmpq_mat) -> int | None:
        """0 when the form vanishes on U (a structural zero), else its sign certified on the whole
        box (1 or -1), or None."""
        if vanishes(form, self.U):
            return 0
        return self.box.sign(self.box.lin([form[0, j] for j in range(form.ncols())], self.x))

    def sign_of_form(self, form: fmpq_mat) -> int:
        s = self.sign(form)
        if s is None:
            raise NoProof("a sign of Newton's impact law is not decided on the family", order=True)
        return s

    def known_rational(self):
        return None

    def mapped(self, P: fmpq_mat) -> "FamilyState":
        """P x, in P U."""
        return FamilyState(self.box, self.box.matvec(P, self.x), image(P * self.U) if self.U.ncols() else self.U)


class FamilyStates:
    """The arithmetic of an impact cascade's cycle (module docstring): families of states, signs
    certified on the whole box.  ``expected`` are the jumps and the mode after of the event as the
    run found them (Newton's active set when the law applies, the chain's modes, the mode after):
    step one certifies, in turn, that each is selected on the whole family (its selection is
    never searched for), and an event step that does not follow them is refused (NoProof)."""

    def __init__(self, lcs, expected: tuple):
        self.lcs = lcs
        self.expected = list(expected)

    def signs(self, M: fmpq_mat, z: FamilyState) -> Iterator[int | None]:
        return (z.sign(submatrix(M, [r], None)) for r in range(M.nrows()))

    def undecided(self, what: str):
        raise NoProof(what)

    def impact(self, z: FamilyState):
        return newton_impact(self.lcs, z)

    def next_expected(self, what: str) -> frozenset:
        if not self.expected:
            raise NoProof(f"the re-initialization does not end where the run's did ({what})")
        return self.expected.pop(0)

    def jump(self, impact, z: FamilyState) -> FamilyState:
        if impact.active != self.next_expected("a Newton impact"):
            raise NoProof("Newton's impact on the family is not the run's")
        return z.mapped(impact.jump)

    def select(self, z: FamilyState) -> frozenset:
        I = self.next_expected("one more jump")
        case = selection_verdict(self, self.lcs.mode(I), z)
        if case is not None:
            message, undecided = SELECTION_CASES[case]
            raise NoProof(message.format(sorted(I)), order=undecided)
        return I

    def project(self, mode, z: FamilyState, first: bool) -> FamilyState:
        return z.mapped(mode.projection())

    def endless(self, cap: int):
        raise NoProof(f"the re-initialization did not end after {cap} jumps")

    def follows(self, step: Step, chain: tuple, after: frozenset) -> None:
        """NoProof unless the step took the run's chain and ended in its mode after."""
        if self.expected or step.chain != tuple(chain) or step.mode.index_set != after:
            raise NoProof("the re-initialization does not follow the run's: the state is not proven in V_"
                          f"{sorted(after)} after the jumps {[sorted(I) for I in chain]}")
