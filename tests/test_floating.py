"""Floating networks: modes that are not autonomous but leave the state unique (DESIGN.md
section 7; lcs_exact.modes.mode, lcs_exact.modes.selection).

Siconos' DiodeBridgeCapFilter (LC tank L = 10 mH, C = 1 uF, a four-diode bridge, a 300 nF filter
with a 1 kOhm load, x0 = (10 V, 0, 0), t_end = 5 ms) has a floating tank: while all four diodes
block, its potential against ground is not determined, though the state is.  The oracle is the
same circuit with the tank tied to ground by 10^12 Ohm (every mode autonomous there): its states
must agree to the effect of that leak, ~ t / (R_g C) = 5e-9 relative."""
from __future__ import annotations

import pytest
from flint import arb, fmpq

from lcs_exact import LCS, NotAutonomous, Undetermined, simulate
from lcs_exact.numbers.balls import workprec
from lcs_exact.builders.circuits import circuit

NET = """C1 a b 1/1000000
L1 a b 1/100
D1 a p
D2 b p
D3 0 a
D4 0 b
Cf p 0 3/10000000
R1 p 0 1000"""


@pytest.fixture(scope="module")
def runs():
    floating = circuit(NET)
    grounded = circuit(NET + "\nRg a 0 1000000000000")
    return (simulate(floating, [10, 0, 0], fmpq(1, 200), max_events=200),
            simulate(grounded, [10, 0, 0], fmpq(1, 200), max_events=200))


def test_the_floating_bridge_runs_certified(runs):
    floating, _ = runs
    assert floating.certified and not floating.partial and len(floating.events) >= 30
    singular = [m for m in {p.mode for p in floating.phases} if not floating.lcs.mode(m).is_autonomous]
    assert singular and all(floating.lcs.mode(m).is_state_determined for m in singular)


def test_against_the_grounded_bridge(runs):
    floating, grounded = runs
    for k in range(1, 11):
        t = fmpq(k, 2000)
        a, b = floating.state(t).ball(30), grounded.state(t).ball(30)
        with workprec(128):
            for x, y in zip(a, b):
                assert abs(x - y) <= arb("1e-7") * (1 + abs(y))
    # the first events (before the tank's common mode matters) agree to the leak's effect
    for ea, eb in zip(floating.events[:5], grounded.events[:5]):
        with workprec(128):
            assert abs(ea.time.ball(30) - eb.time.ball(30)) < arb("1e-14")


def test_the_undetermined_inputs_are_reported(runs):
    floating, _ = runs
    phases = [p for p in floating.phases if p.undetermined]
    assert phases  # all diodes blocking: the tank's potential is free
    p = phases[0]
    from lcs_exact.numbers.balls import dyadic
    with workprec(64):
        t = dyadic((p.t0.ball(30) + p.t1.ball(30)) / 2)  # a rational time inside the phase
    free = floating.undetermined(t)
    assert free == p.undetermined
    u = floating.u(t)
    j = min(free)
    assert u[j].label() == "undetermined" and "undetermined" in repr(u)
    with pytest.raises(Undetermined, match="not determined by the state"):
        u[j].decimal(10)
    # the determined inputs are numbers, and the state is certified there
    others = [i for i in range(4) if i not in free]
    assert all(u[i].ball(20) is not None for i in others)
    assert all(c.ball(30).rad() < arb("1e-29") * (1 + abs(c.ball(30))) for c in floating.state(t))


def test_a_state_that_is_not_determined_is_refused():
    lazy = LCS([[0]], [[1]], [[0]], [[0]])  # x' = u, y = 0: u pushes x anywhere
    with pytest.raises(NotAutonomous, match="state after x0 is not unique"):
        lazy.select_modes([1])
