"""One meaning of an event step (issue 29 item 4): steps one to three of Algorithm 7.1 (Newton's
law, mode selection, z in V_I?, z := P_I z) are one function, :func:`event_step`, run here in
both of its arithmetics on the same scenes:

* exact states (:class:`ExactStates`, what ``simulate`` runs), at sample points of a family;
* the family itself (:class:`FamilyStates`, what the cascade proof runs): Taylor models in eps on
  eps in (0, 1/8], every sign certified on the whole box, exact zeros only structural.

Each scene is a family of rational states z(eps) = z0 + eps z1 at an event; the test derives its
mode, chain of jumps and state after by hand (the paper's section 7 for the two carts, Newton's
law for the ball, momentum and the acceleration LCP for the three carts), and both arithmetics
must give exactly that: the same modes, and the family's state polynomials equal to the exact
states at every sample point.  Where the exact steps differ across a family, the family's step
must refuse (an undecided sign), never pick one.
"""
from __future__ import annotations

from fractions import Fraction
from itertools import combinations

import pytest
from flint import fmpq, fmpq_mat

from lcs_exact.algebra import hstack, image, rank
from lcs_exact.phases.eventstep import (SELECTION_CASES, ExactStates, FamilyState, FamilyStates, event_step,
                                          in_consistent_subspace, selection_verdict)
from lcs_exact.examples import bouncing_ball
from lcs_exact.models import mechanical, two_carts
from lcs_exact.numbers import Box, NoProof, Space, as_exact_vector

S = fmpq(1, 8)  # the family's box: eps in [0, S] (its signs hold for eps in (0, S])
POINTS = [fmpq(1, 8), fmpq(1, 16), fmpq(1, 1000)]

STOPS = [[1, 0, 0], [-1, 1, 0], [0, -1, 1]]
CARTS = ([[2, 0, 0], [0, 3, 0], [0, 0, 2]], [[6, -2, 0], [-2, 4, -2], [0, -2, 6]])


def _q(x):
    if isinstance(x, fmpq):
        return x
    return fmpq(Fraction(x).numerator, Fraction(x).denominator)


def _col(v):
    return fmpq_mat(len(v), 1, [_q(c) for c in v])


def family(z0, z1, order=6):
    """The family z0 + eps z1 as Taylor models on eps in [0, S], in the exact subspace span(z0, z1)."""
    sp = Space(S)
    box = Box(sp)
    e = sp.gens[0]
    x = [box.model(sp.const(_q(a)) + e * _q(b), order) for a, b in zip(z0, z1)]
    return FamilyState(box, x, image(hstack(_col(z0), _col(z1), nrows=len(z0))))


def at(z0, z1, eps):
    return [_q(a) + eps * _q(b) for a, b in zip(z0, z1)]


def exact_step(lcs, z):
    arith = ExactStates(lcs)
    return event_step(arith, as_exact_vector(z, lcs.n)), arith


def family_step(lcs, z0, z1, chain, after):
    arith = FamilyStates(lcs, (*chain, after))
    step = event_step(arith, family(z0, z1))
    arith.follows(step, chain, after)
    return step


def check_scene(lcs, z0, z1, chain, after, w0, w1, impulse=None):
    """Both arithmetics at the family z0 + eps z1 give the chain, the mode ``after`` and the state
    w0 + eps w1 (exactly: at the sample points, and as the family's polynomials)."""
    chain, after = tuple(frozenset(c) for c in chain), frozenset(after)
    for eps in POINTS:
        step, arith = exact_step(lcs, at(z0, z1, eps))
        assert step.chain == chain and step.mode.index_set == after
        assert step.state.known_rational() == _col(at(w0, w1, eps))
        if impulse is not None:
            assert {i: v.known_rational() for i, v in arith.impulse.items()} == {0: _col(impulse(eps))}
    fam = family_step(lcs, z0, z1, chain, after)
    assert fam.chain == chain and fam.mode.index_set == after
    sp = fam.state.box.sp
    e = sp.gens[0]
    for xi, a, b in zip(fam.state.x, w0, w1):
        assert xi.r == 0 and xi.p == sp.const(_q(a)) + e * _q(b)  # exact: P_I and Newton's jump are rational
    for w in (w0, w1):  # the state after, for every eps, lies in the family's exact subspace
        assert rank(hstack(fam.state.U, _col(w), nrows=len(w))) == fam.state.U.ncols()
    return fam


# --------------------------------------------------------------------------------------------
# the two carts of the paper (section 7): y = x1, the left cart against its stop
# --------------------------------------------------------------------------------------------

def test_two_carts_hit_the_stop():
    """Section 7 at t = 1: z = (0, -1, -1, 0), S(z) = {{1}} (0-based {0}): u(s) = 1 + s/(s^2 + 1),
    not strictly proper, so z := P_{1} z = (0, -1, 0, 0) (x3 := 0: the left cart stops), then
    u(s) = s/(s^2 + 1) and smooth continuation in {1}.  With the right cart moving at eps:
    u(s) = 1 + (s - eps)/(s^2 + 1) and z := (0, -1, 0, eps); the impulse is 1 (x3 from -1 to 0)."""
    check_scene(two_carts(), (0, -1, -1, 0), (0, 0, 0, 1), [{0}], {0}, (0, -1, 0, 0), (0, 0, 0, 1),
                impulse=lambda eps: [1])


def test_two_carts_let_go_after_the_jump():
    """Section 2's mode transition (z0 = (0, 1, -1, 0) in section 7): the jump in mode {1}
    (u(s) = 1 - (s + eps)/(s^2 + 1)), then at (0, 1, 0, eps) y(s) = (s + eps)/(s^4 + 3 s^2 + 1) > 0 and
    u(s) < 0 in {1}: the unconstrained mode, the right cart pulls the left one away."""
    check_scene(two_carts(), (0, 1, -1, 0), (0, 0, 0, 1), [{0}], set(), (0, 1, 0, 0), (0, 0, 0, 1))


def test_two_carts_pulled_from_the_stop():
    """Section 7 at t = 1 + pi/2: z = (0, 0, 0, 1), S(z) = {emptyset} (LDCP_4), no jump; with the right
    cart at eps: y = x1 = 0, y' = x3 = 0, y'' = x2 = eps > 0: still the unconstrained mode."""
    check_scene(two_carts(), (0, 0, 0, 1), (0, 1, 0, 0), [], set(), (0, 0, 0, 1), (0, 1, 0, 0))
    step, _ = exact_step(two_carts(), [0, 0, 0, 1])  # the paper's own state (eps = 0)
    assert step.chain == () and step.mode.index_set == frozenset()


# --------------------------------------------------------------------------------------------
# a ball's Newton impact (restitution 9/10): x = (q, v, 1)
# --------------------------------------------------------------------------------------------

def test_a_ball_bounces_by_newtons_law():
    """At the floor falling at 1 - eps: Newton's law v+ = -e v- = (9/10)(1 - eps) with the impulse
    (1 + e)(1 - eps); then y = 0, y' > 0: the flight (mode {})."""
    ball = bouncing_ball()
    e = Fraction(9, 10)
    fam = check_scene(ball, (0, -1, 1), (0, 1, 0), [{0}], set(), (0, e, 1), (0, -e, 0),
                      impulse=lambda eps: [_q(1 + e) * (1 - eps)])
    assert fam.impact is not None and fam.impact.active == frozenset({0})


# --------------------------------------------------------------------------------------------
# three carts at the wall (tests/test_cascades.py): the cycle's event y_1
# --------------------------------------------------------------------------------------------

def _plastic(Mm, E, I, v):
    """Moreau's plastic impact on the contacts I: v - M^-1 E_I^T (E_I M^-1 E_I^T)^-1 E_I v."""
    M, Ec, V = fmpq_mat([[_q(c) for c in r] for r in Mm]), fmpq_mat([[_q(c) for c in r] for r in E]), _col(v)
    EI = fmpq_mat([[Ec[i, j] for j in range(Ec.ncols())] for i in sorted(I)])
    Mi = M.inv()
    return Mi * EI.transpose() * (EI * Mi * EI.transpose()).inv() * (EI * V) * -1 + V


def _held(Mm, K, E, q, closed):
    """The contacts of ``closed`` (at rest) that stay closed: the acceleration LCP by brute force
    (forces > 0 on them, the others separating); the unique solution."""
    M, Kq, Ec = (fmpq_mat([[_q(c) for c in r] for r in X]) for X in (Mm, K, E))
    found = []
    for r in range(len(closed) + 1):
        for J in combinations(sorted(closed), r):
            rows = fmpq_mat([[Ec[i, j] for j in range(Ec.ncols())] for i in J]) if J else None
            a = M.inv() * Kq * _col(q) * -1
            lam = []
            if J:
                W = rows * M.inv() * rows.transpose()
                lam_m = W.inv() * (rows * a) * -1  # keeps E_J a = 0
                lam = [lam_m[i, 0] for i in range(len(J))]
                a = a + M.inv() * rows.transpose() * lam_m
            if all(x > 0 for x in lam) and all((Ec * a)[i, 0] > 0 for i in closed if i not in J):
                found.append(frozenset(J))
    assert len(found) == 1
    return found[0]


def test_three_carts_collide_at_the_wall():
    """Masses 2, 3, 2: cart 0 at rest eps from the wall, carts 1 and 2 touching it and each other
    at -1.  Contact 1 closes (y_1 = 0, y_1' = -1) with contact 2 closed: the jump in mode {1, 2}
    takes all three to one speed, 2 0 + 3 (-1) + 2 (-1) = 7 w, w = -5/7 (Moreau's projection);
    then the springs' forces at q = eps (1, 1, 1) hold contact 2 only (u_2 = 12 eps / 5 > 0,
    y_1'' = 6 eps / 5 > 0): the cascade's event y_1 -> {2}."""
    Mm, K = CARTS
    lcs = mechanical(Mm, K, STOPS)
    v = _plastic(Mm, STOPS, {1, 2}, [0, -1, -1])
    assert [v[i, 0] for i in range(3)] == [fmpq(-5, 7)] * 3
    assert _held(Mm, K, STOPS, [fmpq(1, 16)] * 3, {1, 2}) == frozenset({2})
    w = Fraction(-5, 7)
    check_scene(lcs, (0, 0, 0, 0, -1, -1), (1, 1, 1, 0, 0, 0), [{1, 2}], {2}, (0, 0, 0, w, w, w),
                (1, 1, 1, 0, 0, 0), impulse=lambda eps: [0, 2 * -w, 2 * (w + 1)])  # cart 0's and cart 2's momenta


# --------------------------------------------------------------------------------------------
# the family's step refuses what it cannot prove
# --------------------------------------------------------------------------------------------

def test_a_family_across_two_selections_is_refused():
    """The left cart at the stop with the speed eps - 1/16: the exact steps differ across the box
    (a jump in {1} below 1/16, the unconstrained mode above), so the family's step decides
    neither: an undecided sign (a higher order might not help either, but it is not a refusal of
    the mode)."""
    lcs = two_carts()
    z0, z1 = (0, -1, Fraction(-1, 16), 0), (0, 0, 1, 0)
    below, _ = exact_step(lcs, at(z0, z1, fmpq(1, 32)))
    above, _ = exact_step(lcs, at(z0, z1, fmpq(3, 32)))
    assert (below.chain, below.mode.index_set) == ((frozenset({0}),), frozenset({0}))
    assert (above.chain, above.mode.index_set) == ((), frozenset())
    for chain, after in (([{0}], {0}), ([], set())):
        with pytest.raises(NoProof) as info:
            family_step(lcs, z0, z1, [frozenset(c) for c in chain], frozenset(after))
        assert info.value.order and "not decided" in str(info.value)


@pytest.mark.parametrize("chain, after, why", [
    ([], {0}, "does not end where"),             # {1} is selected, but z is not in V_{1}: a jump follows
    ([{0}], set(), "not admissible"),            # after the jump the unconstrained mode is not admissible
    ([set()], {0}, "not admissible"),            # the unconstrained mode is not selected at the impact
    ([{0}, {0}], {0}, "does not follow"),        # the chain ends after one jump
])
def test_a_wrong_event_is_refused(chain, after, why):
    """The two carts hitting the stop, with the run's chain or mode after altered: refused, and not
    for want of order (a decided sign, or a chain that does not match)."""
    with pytest.raises(NoProof) as info:
        family_step(two_carts(), (0, -1, -1, 0), (0, 0, 0, 1), [frozenset(c) for c in chain], frozenset(after))
    assert why in str(info.value) and not info.value.order


# --------------------------------------------------------------------------------------------
# the two selections agree: S(z)'s smallest mode is the one Theorem 6.3's certificate names
# --------------------------------------------------------------------------------------------

SCENES = [(two_carts(), (0, -1, -1, 0), (0, 0, 0, 1)), (two_carts(), (0, 1, -1, 0), (0, 0, 0, 1)),
          (two_carts(), (0, 0, 0, 1), (0, 1, 0, 0)), (bouncing_ball(), (0, -1, 1), (0, 1, 0)),
          (mechanical(*CARTS, STOPS), (0, 0, 0, 0, -1, -1), (1, 1, 1, 0, 0, 0)),
          (two_carts(), (0, 0, 0, 0), (0, 0, 0, 0))]  # at rest at the stop: S(0) = {{}, {1}}, u = 0 in {1}


@pytest.mark.parametrize("scene", range(len(SCENES)))
def test_the_selected_mode_is_the_one_the_certificate_names(scene):
    """At every state of the exact chain (before each selection), the mode Algorithm 7.1 selects
    (S(z) by the LCPs of section 5, its smallest mode) is the only mode of all 2^k that
    :func:`selection_verdict` certifies (u_I strictly positive, y_Ic nonnegative: Theorem 6.3),
    in either arithmetic; every other mode gets a decided reason (never "undecided"): at rest at
    the stop, mode {1} is admissible too, but its input vanishes (a smaller mode is selected)."""
    lcs, z0, z1 = SCENES[scene]
    modes = [frozenset(c) for r in range(lcs.k + 1) for c in combinations(range(lcs.k), r)]
    exact = ExactStates(lcs)
    for eps in POINTS:
        chosen = []
        z = as_exact_vector(at(z0, z1, eps), lcs.n)
        hit = exact.impact(z)
        z = exact.jump(hit, z) if hit is not None else z
        while True:
            I = exact.select(z)
            chosen.append(I)
            verdicts = {J: selection_verdict(exact, lcs.mode(J), z) for J in modes}
            assert [J for J, v in verdicts.items() if v is None] == [I]
            assert all(v in SELECTION_CASES and v != "undecided" for J, v in verdicts.items() if J != I)
            if not any(z0) and not any(z1):
                assert verdicts == {frozenset(): None, frozenset({0}): "input vanishes"}
            if in_consistent_subspace(exact, lcs.mode(I), z):
                break
            z = exact.project(lcs.mode(I), z, False)
    fam = FamilyStates(lcs, ())
    x = family(z0, z1)
    hit = fam.impact(x)
    x = x.mapped(hit.jump) if hit is not None else x
    for I in chosen:  # the same modes, certified on the whole family
        assert selection_verdict(fam, lcs.mode(I), x) is None
        if not in_consistent_subspace(fam, lcs.mode(I), x):
            x = fam.project(lcs.mode(I), x, False)
