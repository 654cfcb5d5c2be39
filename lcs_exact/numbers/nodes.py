"""Exact definitions with a cached ball (an *anchor*) and their evaluation in a loop.

A node (:class:`Node`) is an immutable exact definition - an exact real (:mod:`lcs_exact.reals`)
or vector (:mod:`lcs_exact.vectors`) - that evaluates to an ``arb`` ball (or an n x 1
``arb_mat``) of any requested precision with the true value inside.  Every node caches its best
ball and the precision it was computed at.  ``node.arb(prec)`` evaluates the definitions it depends
on in a loop over an explicit stack (:func:`evaluate`), walking forward from the nearest anchors at
>= prec bits (or exact leaves), never by recursion: a state after 10,000 events is evaluated in
O(10,000) steps and cannot exhaust the Python stack, and a state whose anchor is good enough costs
nothing.  The simulation anchors each event at its working precision
(:meth:`lcs_exact.balls.Policy.working_prec`).
"""
from __future__ import annotations

import abc

from flint import arb

from .balls import DEFAULT_POLICY, Policy, workprec

__all__ = ["Node", "evaluate", "in_dependency_order", "derive_closed", "closed_ready", "ANCHOR_SLACK"]


#: an anchor computed at >= prec - ANCHOR_SLACK bits serves a request for prec bits
ANCHOR_SLACK = 64


class Node:
    """A definition with a cached ball (the anchor) and the definitions it depends on."""

    def __init__(self, policy: Policy | None = None):
        self._ball = None
        self._prec = 0
        self.policy = policy or DEFAULT_POLICY

    def _deps(self) -> tuple:
        """The nodes whose balls at the same precision :meth:`_compute` reads."""
        return ()

    def _closed_ready(self) -> bool:
        """True when the node's closed form is derived and cached (exact reals and vectors say)."""
        return False

    def _derive_closed(self) -> None:
        """Derive and cache the node's closed form, if it keeps one (see :func:`in_dependency_order`)."""

    def __getstate__(self):
        # Calcium numbers do not pickle: drop the caches that hold them (rebuilt on demand)
        state = dict(self.__dict__)
        if "_ca" in state:
            state["_ca"], state["_ca_done"] = None, False
        if isinstance(state.get("_kca"), list):  # a vector's Calcium components (rebuilt by known_ca)
            del state["_kca"]
        return state

    @abc.abstractmethod
    def _compute(self, prec: int):
        """The ball at ``prec`` bits, assuming every dependency has a ball at >= prec bits."""

    def _store(self, ball, prec: int) -> None:
        if self._ball is None or radius_le(ball, self._ball):
            self._ball = ball
        self._prec = max(self._prec, prec)

    @property
    def anchor_prec(self) -> int:
        """The working precision of the cached ball (0 when none is cached)."""
        return self._prec

    def arb(self, prec: int):
        """A ball computed at working precision >= ``prec - ANCHOR_SLACK`` bits (cached; the true
        value inside).  The slack lets a run whose working precision grows by a bit or two per
        event reuse the anchors of earlier events instead of re-evaluating the whole history;
        callers that need more accuracy double ``prec``, which forces a real refinement."""
        if self._prec < prec - ANCHOR_SLACK or self._ball is None:
            evaluate(self, prec)
        return self._ball


def radius_le(a, b) -> bool:
    if isinstance(a, arb):
        return a.rad() <= b.rad()
    ra = max((a[i, j].rad() for i in range(a.nrows()) for j in range(a.ncols())), default=arb(0))
    rb = max((b[i, j].rad() for i in range(b.nrows()) for j in range(b.ncols())), default=arb(0))
    return ra <= rb


def evaluate(node: Node, prec: int) -> None:
    """Give ``node`` a ball at ``prec`` bits, and every definition it needs one at >= prec -
    ANCHOR_SLACK bits, in a loop: post-order over an explicit stack, stopping at the anchors
    that are good enough (walking forward from the nearest anchor, never by recursion).  The
    policy's deadline is checked every 64 nodes (a walk over a long history stops in time)."""
    stack: list = [(node, False)]
    steps = 0
    while stack:
        steps += 1
        if steps % 64 == 0:
            node.policy.check_deadline(" while evaluating a long definition")
        cur, ready = stack.pop()
        if cur is not node and cur._prec >= prec - ANCHOR_SLACK and cur._ball is not None:
            continue
        if ready:
            with workprec(prec):
                cur._store(cur._compute(prec), prec)
            continue
        stack.append((cur, True))
        for d in cur._deps():
            if d._prec < prec - ANCHOR_SLACK or d._ball is None:
                stack.append((d, False))


def in_dependency_order(node: Node, visit, done) -> None:
    """Call ``visit(d)`` on every definition ``d`` that ``node`` depends on, deepest first, in a
    loop over an explicit stack; the walk does not go past a definition that is ``done(d)``.

    What a definition derives from its dependencies (a closed form from the closed forms of the
    event times and states before it, a Calcium number from theirs) is computed by recursion in
    its own code; derived first for everything it needs, in this order, that recursion stops
    one level down, so that the last event of a run of 10,000 gets its closed form without
    exhausting the Python stack.  The policy's deadline is checked every 64 nodes."""
    stack: list = [(node, False)]
    seen: set = set()
    steps = 0
    while stack:
        steps += 1
        if steps % 64 == 0:
            node.policy.check_deadline(" while deriving a long definition")
        cur, ready = stack.pop()
        if ready:
            if cur is not node:
                visit(cur)
            continue
        if id(cur) in seen:
            continue
        seen.add(id(cur))
        stack.append((cur, True))
        for d in cur._deps():
            if id(d) not in seen and not done(d):
                stack.append((d, False))


def derive_closed(node: Node) -> None:
    """``node._derive_closed()``: for :func:`in_dependency_order` over closed forms."""
    node._derive_closed()


def closed_ready(node: Node) -> bool:
    """``node._closed_ready()``: for :func:`in_dependency_order` over closed forms."""
    return node._closed_ready()

