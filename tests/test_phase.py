"""The continuous phase and the next event (lcs_exact.phases.phase, lcs_exact.phases.flow): Lemma 5.1 at the
start, the centered form of event states, simultaneous roots."""
from __future__ import annotations

import mpmath as mp
import sympy as sp
from flint import arb, ctx, fmpq_mat

import lcs_exact as L
from lcs_exact.numbers.balls import Policy, workprec
from lcs_exact.phases.phase import EventState, Phase
from lcs_exact.numbers.expvectors import ExpVector, expm_action
from lcs_exact.numbers.vectors import as_exact_vector

A_CARTS = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]
CARTS = L.LCS(A_CARTS, [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])


def test_start_order_lemma_5_1():
    """At (0, -1, 0, 0) in mode {0}: u = -x2 = 1 > 0 (order 0).  In the free mode from (0, 0, 0, 1):
    y = x1 with y = y' = y'' = 0 and y''' = x4 = 1 > 0 (order 3)."""
    p = Phase(CARTS.mode({0}), as_exact_vector([0, -1, 0, 0], 4), Policy())
    assert [p.start_order(c) for c in p.constraints] == [(1, 0)]
    p = Phase(CARTS.mode(set()), as_exact_vector([0, 0, 0, 1], 4), Policy())
    assert [p.start_order(c) for c in p.constraints] == [(1, 3)]


def test_event_state_centered_form():
    """The first impact of section 7 from a state known only as a ball (e^{-A} of a rational
    vector, projected): the centered enclosure contains x(1-) = (0, -1, -1, 0) and is at least as
    tight as the plain one."""
    x0 = expm_action(A_CARTS, -1, [0, -1, -1, 0])
    z = L.vectors.ProjectedVector(fmpq_mat([[int(i == j) for j in range(4)] for i in range(4)]), x0)
    phase = Phase(CARTS.mode(set()), z, Policy())
    root = L.flow.first_root(phase, phase.constraints[0], L.rational.to_fmpq(3), 128)
    x = phase.event_state(root)
    assert isinstance(x, EventState)
    # the plain enclosure: the same e^{A_I theta} z as an ExpVector (no centered form)
    plain_x = ExpVector(x.spectrum, x.t, x.v, policy=x.policy, modal=phase.modal)
    assert type(plain_x) is ExpVector and plain_x.t is root and plain_x.v is phase.base
    with workprec(200):
        centered = x.arb(200)
        plain = plain_x.arb(200)
    for i, want in enumerate([0, -1, -1, 0]):
        assert centered[i, 0].contains(want)
        assert centered[i, 0].rad() <= plain[i, 0].rad()


def test_simultaneous_roots_proven_by_proportionality():
    """Symmetric impact of three masses on two relative contacts (q1 = q3 on the whole phase):
    the two constraints reach zero together; their order is proven equal, not assumed."""
    from lcs_exact.models import mechanical
    lcs = mechanical([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
                     [[1, 0, 0], [0, 0, 1]])
    tr = L.simulate(lcs, [1, 0, 1, 0, 0, 0], 3)
    e = tr.events[0]
    assert set(e.triggers) == {"y_0", "y_1"} and tr.certified
    assert sp.simplify(e.time.closed_form - sp.pi / 2) == 0


def test_event_state_refined_after_a_first_ball_reuses_a_valid_jacobian():
    """The two carts from x0 = e^{-A} (0, -1, -1, 0) (an exact start that is not rational: the
    phase start is a ball): x(1-) = (0, -1, -1, 0) exactly.  Asked at 30 and then at 200 digits,
    the centered form of the second request reuses the Jacobian certified over the first, wider
    ball of the start (valid: the new ball lies inside it) - and the result still holds the exact
    state, 200 digits tight."""
    from lcs_exact.models import two_carts
    lcs = two_carts()
    tr = L.simulate(lcs, L.expm_action(lcs.A, -1, [0, -1, -1, 0]), 3, digits=30)
    x = tr.events[0].state_before
    first = [c.ball(30) for c in x]
    second = [c.ball(200) for c in x]
    for b1, b2, want in zip(first, second, (0, -1, -1, 0)):
        assert b1.contains(want) and b2.contains(want)
        assert b2.rad() < arb(10) ** -200
