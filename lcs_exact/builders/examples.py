"""The paper's systems and a few standard circuits, ready to simulate, with names.

* :func:`two_carts` - section 2, (2.1); :func:`two_carts_with_hook` - Example 8.3, (8.12);
* :func:`half_wave_rectifier`, :func:`diode_bridge` - LC tanks rectified by ideal diodes;
* :func:`filippov_spiral` - (4.12), a relay system (:func:`lcs_exact.relays.relay`);
* :func:`cart_chain` - N unit carts on springs with stops, the (8.3) system of the benchmarks;
* the standard scenes beyond the paper (docs/extensions.md; Siconos' tutorials): :func:`bouncing_ball`,
  :func:`ball_on_spring`, :func:`ball_column`, :func:`newtons_cradle` (restitution, gravity, gaps),
  :func:`sine_rectifier` (half- and full-wave, a sine source), :func:`diode_bridge_cap_filter`
  (Siconos' DiodeBridgeCapFilter: a floating tank).

Indices are 0-based (the paper's x_1 and mode {1} are ``x_0`` and ``{0}`` here).  Mechanical
examples name their states q_0, q_1, q_0', q_1' (positions, velocities): the paper's x1..x4.
"""
from __future__ import annotations

from typing import Any

from .circuits import circuit
from ..errors import InvalidArgument
from .mechanics import mechanical
from ..algebra import to_fmpq
from ..system import sine
from .exosystems import driven
from .relays import relay
from ..dynamics import scheduled
from ..system import constant
from ..system import LCS

__all__ = ["two_carts", "two_carts_with_hook", "half_wave_rectifier", "diode_bridge", "filippov_spiral",
           "cart_chain", "bouncing_ball", "ball_on_spring", "ball_column", "newtons_cradle", "sine_rectifier",
           "diode_bridge_cap_filter", "buck_converter"]


def two_carts() -> LCS:
    """Two carts, springs and an inelastic stop (section 2, (2.1)).

    Unit masses at positions q_0 (left cart) and q_1; a spring of stiffness 1 from the wall to the
    left cart and one between the carts (K = [[2, -1], [-1, 1]]); a completely inelastic stop
    keeps q_0 >= 0 with contact force u >= 0 (the constraint "stop", y = q_0).  State
    x = (q_0, q_1, q_0', q_1') = the paper's (x1, x2, x3, x4).

    >>> carts = two_carts()
    >>> carts.markov(2)[0, 0], carts.constraint_names
    (1, ('stop',))
    """
    return mechanical([[1, 0], [0, 1]], [[2, -1], [-1, 1]], [[1, 0]], name="two carts (section 2)",
                      constraint_names=("stop",))


def two_carts_with_hook() -> LCS:
    """The two carts with the stop (y_0 = q_0 >= 0) and a hook (y_1 = q_0 - q_1 >= 0) (Example 8.3).

    (8.12): M = I, D = 0, K = [[2, -1], [-1, 1]], E = [[1, 0], [1, -1]]; u_0, u_1 are the forces
    of the stop and the hook.  Figure 8.2 is the mode map on the slice q = 0:
    ``two_carts_with_hook().mode_map(slice=([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]]))``.

    >>> two_carts_with_hook().select_modes([0, 0, -1, 2])   # hook-constrained (see section 8)
    {frozenset({1})}
    """
    return mechanical([[1, 0], [0, 1]], [[2, -1], [-1, 1]], [[1, 0], [1, -1]],
                      name="two carts with hook (Example 8.3)", constraint_names=("stop", "hook"))


def half_wave_rectifier(L: Any = 1, C: Any = 1, R: Any = "13/10") -> LCS:
    """An LC tank (the AC source) feeding a resistive load R through one ideal diode.

    Netlist: ``C1 1 0 C``, ``L1 1 0 L``, ``D1 1 2``, ``R1 2 0 R``.  State x = (v(C1), i(L1)):
    the tank voltage and the inductor current (node 1 -> ground).  The diode is a current port:
    u = i_D (load current), y = R u - v (its reverse voltage), so D = R > 0 (well-posed).
    While v > 0 the diode conducts and the tank is a damped parallel RLC,
    v'' + v'/(RC) + v/(LC) = 0; while v < 0 it blocks and the tank oscillates freely at
    1/sqrt(LC).  Every event is a zero of v: conduction lasts pi/omega_d with
    omega_d^2 = 1/(LC) - 1/(2RC)^2, blocking lasts pi sqrt(LC).  With the defaults (L = C = 1,
    R = 13/10): decay 1/(2RC) = 5/13, omega_d = 12/13, so from v = 0, v' > 0 the events are at
    13pi/12, 25pi/12, 19pi/6, ... and each conduction shrinks the tank's energy by e^(-5pi/6).

    Parameters
    ----------
    L, C : rational, optional
        The tank's inductance and capacitance.
    R : rational, optional
        The load.

    >>> rect = half_wave_rectifier()
    >>> rect.A, rect.D, rect.state_names
    ([0, -1]
    [1,  0], [13/10], ('v(C1)', 'i(L1)'))
    """
    L, C, R = (to_fmpq(v, name) for v, name in ((L, "L"), (C, "C"), (R, "R")))
    return circuit([("C1", "1", "0", C), ("L1", "1", "0", L), ("D1", "1", "2"), ("R1", "2", "0", R)],
                   name="half-wave rectifier (LC tank, diode, load R)")


def diode_bridge(L: Any = 1, C: Any = 1, R: Any = "7/6", r: Any = "1/3", R_ground: Any = 3) -> LCS:
    """A full-wave diode bridge rectifying a floating LC tank into a load R.

    The tank (C1 and L1 in parallel) sits between nodes a and b; diodes D1: a -> p, D2: b -> p,
    D3: 0 -> a, D4: 0 -> b, each with a series on-resistance r (nodes n1..n4); the load R1 is
    between p and ground 0, and two resistors R_ground tie a and b to ground.  The series r
    breaks the loop made of diodes alone (in which a circulating current would be undetermined)
    and R_ground the cutset made of diodes alone (the tank's potential would be undetermined
    when all four block): without them some modes are not autonomous (Lemma 3.3) and the
    network is not an LCS with unique solutions.

    State x = (v(C1), i(L1)) with v = e(a) - e(b); the diodes are current ports
    (u_i = current of D(i+1), y_i = its reverse voltage).  For v > 0, D1 and D4 conduct; for
    v < 0, D2 and D3: either way the tank sees R_eq = (r + R) || R_ground + r || R_ground and
    v'' + v'/(R_eq C) + v/(LC) = 0, and every zero of v is an event that swaps the pairs.  The
    load current flows from p to 0 in both half-waves.  Defaults (L = C = 1, r = 1/3, R = 7/6,
    R_ground = 3): R_eq = 1 + 3/10 = 13/10, the rectifier's conduction: omega_d = 12/13, decay
    5/13, events every 13pi/12.

    Parameters
    ----------
    L, C : rational, optional
        The tank's inductance and capacitance.
    R : rational, optional
        The load.
    r : rational, optional
        Each diode's series on-resistance.
    R_ground : rational, optional
        The two resistors tying the tank's nodes to ground.

    >>> bridge = diode_bridge()
    >>> bridge.constraint_names, bool(bridge.well_posedness())
    (('D1', 'D2', 'D3', 'D4'), True)
    """
    L, C, R, r, Rg = (to_fmpq(v, name) for v, name in ((L, "L"), (C, "C"), (R, "R"), (r, "r"), (R_ground, "R_ground")))
    net = [("C1", "a", "b", C), ("L1", "a", "b", L),
           ("D1", "a", "n1"), ("Rd1", "n1", "p", r),
           ("D2", "b", "n2"), ("Rd2", "n2", "p", r),
           ("D3", "0", "n3"), ("Rd3", "n3", "a", r),
           ("D4", "0", "n4"), ("Rd4", "n4", "b", r),
           ("R1", "p", "0", R), ("Rga", "a", "0", Rg), ("Rgb", "b", "0", Rg)]
    return circuit(net, name="full-wave diode bridge (LC tank, load R)")


def filippov_spiral() -> LCS:
    """The paper's right-Zeno example (4.12): x1' = -sgn(x1) + 2 sgn(x2), x2' = -2 sgn(x1) - sgn(x2).

    Built with :func:`lcs_exact.relays.relay`: A = 0, B = [[-1, 2], [-2, -1]], C = I.  State
    (x_0, x_1, c) (the paper's x1, x2 and the constant relay level c = 1: start from
    ``lcs.embed([x1, x2])``); pairs ``w0-, w0+, w1-, w1+``.  In the open quadrant with signs
    (sgn x1, sgn x2) the mode is {0, 1} for x1 > 0 (none of them for x1 < 0) united with {2, 3}
    for x2 > 0; at the origin both relays slide (w = 0, mode {0, 2}).  From (1, 2) the switching
    times are 3/2 - (5/2) 3^-k (2/3, 11/9, 38/27, ...), accumulating at 3/2 where the state
    reaches 0 (Remark 4.11).

    >>> spiral = filippov_spiral()
    >>> spiral.select_modes(spiral.embed([1, 2])) == {frozenset({0, 1, 2, 3})}
    True
    >>> spiral.select_modes(spiral.embed([0, 0])) == {frozenset({0, 2})}
    True
    """
    return relay([[0, 0], [0, 0]], [[-1, 2], [-2, -1]], [[1, 0], [0, 1]],
                 name="Filippov's spiral (4.12)", state_names=("x_0", "x_1"))


def cart_chain(N: int, stops: Any = None) -> LCS:
    """N unit carts in a row (8.3): a spring from the wall to cart 0, unit springs between
    neighbours (K = tridiag(-1, 2, -1) with K[N-1][N-1] = 1), a stop q_i >= 0 on each cart in
    ``stops`` (default: carts 0, 2, 4, ...).

    From q0 = (1, -1, 1, ...)/2, v0 = 0 the carts with stops reach them at nearly the same time
    (near-coincident impacts: the benchmarks' and tests' chain).  The two carts of section 2 are
    ``cart_chain(2)``.

    Parameters
    ----------
    N : int
        The number of carts.
    stops : iterable of int, optional
        The carts with a stop q_i >= 0 (default: 0, 2, 4, ...).

    >>> cart_chain(2).A == two_carts().A
    True
    >>> cart_chain(5).k, cart_chain(5, stops=[4]).constraint_names
    (3, ('stop_4',))
    """
    if isinstance(N, bool) or not isinstance(N, int) or N < 1:
        raise InvalidArgument(f"N must be a positive int, got {N!r}")
    stops = list(range(0, N, 2)) if stops is None else list(stops)
    if any(isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < N for i in stops):
        raise InvalidArgument(f"stops must be cart indices in 0..{N - 1}, got {stops!r}")
    K = [[2 if i == j else -1 if abs(i - j) == 1 else 0 for j in range(N)] for i in range(N)]
    K[N - 1][N - 1] = 1
    E = [[int(j == i) for j in range(N)] for i in stops]
    return mechanical([[int(i == j) for j in range(N)] for i in range(N)], K, E,
                      name=f"chain of {N} carts", constraint_names=[f"stop_{i}" for i in stops])


# ---------------------------------------------------------------------------------------------
# scenes beyond the paper: restitution, gravity, gaps, sources, floating networks
# ---------------------------------------------------------------------------------------------


def bouncing_ball(g: Any = "981/100", e: Any = "9/10", radius: Any = 0, mass: Any = 1) -> LCS:
    """A ball of ``mass`` falling under gravity ``g`` onto a floor, Newton's impact law with
    restitution ``e`` (Siconos' BouncingBall: g = 9.81, e = 0.9).  The constraint is the height
    of the ball's lowest point, y = q - radius >= 0.  State (q, q', 1) (the last state carries
    gravity); ``ball.embed([h, v0])`` is the full initial state.

    Dropped from rest at h: impacts at t1 (1 + 2e + ... + 2e^(k-1)), t1 = sqrt(2 (h - r) / g),
    accumulating at t* = t1 (1 + e) / (1 - e), after which it rests (``traj.accumulations``).

    Parameters
    ----------
    g : rational, optional
        Gravity.
    e : rational, optional
        The restitution coefficient.
    radius : rational, optional
        The ball's radius (the constraint is its lowest point).
    mass : rational, optional
        The ball's mass.

    >>> ball = bouncing_ball(g=10, e="1/2")
    >>> ball.state_names, ball.restitution, ball.embed([5, 0]).transpose()
    (('q', "q'", '1'), (1/2,), [5, 0, 1])
    """
    m, gg = to_fmpq(mass, "mass"), to_fmpq(g, "g")
    return mechanical([[m]], [[0]], [[1]], force=[-m * gg], gap=[-to_fmpq(radius, "radius")], restitution=e,
                      name="bouncing ball", q_names=["q"], constraint_names=["floor"])


def ball_on_spring(k: Any = 1, mass: Any = 1, g: Any = 10, e: Any = "1/2", rest: Any = 12) -> LCS:
    """A ball hanging on a spring (stiffness k, anchored so that without gravity it rests at
    height ``rest``) above a floor q >= 0, with restitution e.  Its free motion oscillates about
    q_eq = rest - m g / k (2 with the defaults); started high enough it hits the floor, and each
    impact takes energy until the oscillation clears the floor: then it oscillates forever.
    State (q, q', 1).

    Parameters
    ----------
    k : rational, optional
        The spring's stiffness.
    mass : rational, optional
        The ball's mass.
    g : rational, optional
        Gravity.
    e : rational, optional
        The restitution coefficient at the floor.
    rest : rational, optional
        The spring's rest height (without gravity).

    >>> spring = ball_on_spring()
    >>> spring.A
    [ 0, 1, 0]
    [-1, 0, 2]
    [ 0, 0, 0]
    """
    kk, m, gg = to_fmpq(k, "k"), to_fmpq(mass, "mass"), to_fmpq(g, "g")
    return mechanical([[m]], [[kk]], [[1]], force=[kk * to_fmpq(rest, "rest") - m * gg], restitution=e,
                      name="ball on a spring above a floor", q_names=["q"], constraint_names=["floor"])


def ball_column(N: int = 3, g: Any = 10, e: Any = "1/2", radius: Any = "1/20", mass: Any = 1) -> LCS:
    """N beads of one radius stacked on a floor under gravity (Siconos' column of beads,
    Newton's law at every contact): q_i is the height of bead i's centre, the contacts are the
    floor y_0 = q_0 - r and neighbours y_i = q_i - q_(i-1) - 2r.  State (q, q', 1).

    Parameters
    ----------
    N : int, optional
        The number of beads.
    g : rational, optional
        Gravity.
    e : rational, optional
        The restitution coefficient of every contact (Newton's law, section 8).
    radius : rational, optional
        The beads' radius.
    mass : rational, optional
        Each bead's mass.

    >>> col = ball_column(3)
    >>> col.constraint_names, col.C
    (('floor', 'beads 0-1', 'beads 1-2'), [ 1,  0, 0, 0, 0, 0, -1/20]
    [-1,  1, 0, 0, 0, 0, -1/10]
    [ 0, -1, 1, 0, 0, 0, -1/10])
    """
    if isinstance(N, bool) or not isinstance(N, int) or N < 1:
        raise InvalidArgument(f"N must be a positive int, got {N!r}")
    r, m, gg = to_fmpq(radius, "radius"), to_fmpq(mass, "mass"), to_fmpq(g, "g")
    E = [[int(j == 0) for j in range(N)]] + [[-1 if j == i - 1 else 1 if j == i else 0 for j in range(N)]
                                              for i in range(1, N)]
    return mechanical([[m if i == j else 0 for j in range(N)] for i in range(N)], [[0] * N for _ in range(N)], E,
                      force=[-m * gg] * N, gap=[-r] + [-2 * r] * (N - 1), restitution=e,
                      name=f"column of {N} beads", q_names=[f"q_{i}" for i in range(N)],
                      constraint_names=["floor"] + [f"beads {i - 1}-{i}" for i in range(1, N)])


def newtons_cradle(N: int = 3, e: Any = 1, gap: Any = 0) -> LCS:
    """N unit balls in a row on a line, no gravity, contacts between neighbours
    y_i = q_(i+1) - q_i - gap >= 0 with restitution e (a Newton's cradle hit by ball 0).
    State (q, q') (with a constant state '1' when gap != 0).

    Parameters
    ----------
    N : int, optional
        The number of balls.
    e : rational, optional
        The restitution coefficient of every contact.
    gap : rational, optional
        The gap between neighbours at contact.

    >>> cradle = newtons_cradle(3)
    >>> cradle.constraint_names, cradle.n
    (('0-1', '1-2'), 6)
    """
    if isinstance(N, bool) or not isinstance(N, int) or N < 2:
        raise InvalidArgument(f"N must be an int >= 2, got {N!r}")
    E = [[-1 if j == i else 1 if j == i + 1 else 0 for j in range(N)] for i in range(N - 1)]
    gq = to_fmpq(gap, "gap")
    return mechanical([[int(i == j) for j in range(N)] for i in range(N)], [[0] * N for _ in range(N)], E,
                      gap=None if gq == 0 else [-gq] * (N - 1), restitution=e, name=f"Newton's cradle of {N} balls",
                      q_names=[f"q_{i}" for i in range(N)], constraint_names=[f"{i}-{i + 1}" for i in range(N - 1)])


def sine_rectifier(omega: Any = 1, amplitude: Any = 1, R: Any = 1, C: Any = 1, full_wave: bool = False) -> LCS:
    """A sine source amplitude * sin(omega t) rectified into a capacitor C with a load R.

    Half-wave (default): ``V1 in 0``, ``D1 in out``, ``R1 out 0``, ``C1 out 0``: while D1
    conducts v(C1) follows the source; it turns off where the diode current C v' + v / R
    vanishes (t = 3 pi / 4 for omega = R = C = 1, from v = 0).  Full-wave: a floating source
    feeding a four-diode bridge (``D1 a p``, ``D2 b p``, ``D3 0 a``, ``D4 0 b``): while all diodes
    block, the source's potential against ground is undetermined (the state is not).  State
    (v(C1), sin(omega t), cos(omega t)); start from ``rect.embed([v0])``.

    Parameters
    ----------
    omega, amplitude : rational, optional
        The source amplitude * sin(omega t).
    R, C : rational, optional
        The load and the capacitor.
    full_wave : bool, optional
        A four-diode bridge fed by a floating source instead of one diode.

    >>> rect = sine_rectifier()
    >>> rect.state_names, rect.constraint_names
    (('v(C1)', 'sin(t)', 'cos(t)'), ('D1',))
    """
    src = sine(omega, amplitude)
    Rq, Cq = to_fmpq(R, "R"), to_fmpq(C, "C")
    if not full_wave:
        net = [("V1", "in", "0", src), ("D1", "in", "out"), ("R1", "out", "0", Rq), ("C1", "out", "0", Cq)]
        return circuit(net, name="half-wave rectifier, sine source")
    net = [("V1", "a", "b", src), ("D1", "a", "p"), ("D2", "b", "p"), ("D3", "0", "a"), ("D4", "0", "b"),
           ("R1", "p", "0", Rq), ("C1", "p", "0", Cq)]
    return circuit(net, name="full-wave bridge rectifier, sine source")


def diode_bridge_cap_filter(L: Any = "1/100", C: Any = "1/1000000", Cf: Any = "3/10000000", R: Any = 1000) -> LCS:
    """Siconos' DiodeBridgeCapFilter: an LC tank (L = 10 mH, C = 1 uF) feeding a four-diode bridge
    with a filter capacitor Cf = 300 nF and a load R = 1 kOhm; x0 = (10, 0, 0), t_end = 5 ms in
    the tutorial.  The tank floats: while all four diodes block its potential against ground is
    undetermined, the state (v(C1), i(L1), v(Cf)) is not (docs/extensions.md).

    Parameters
    ----------
    L, C : rational, optional
        The tank's inductance and capacitance.
    Cf : rational, optional
        The filter capacitor.
    R : rational, optional
        The load.

    >>> bridge = diode_bridge_cap_filter()
    >>> bridge.state_names, bridge.constraint_names
    (('v(C1)', 'i(L1)', 'v(Cf)'), ('D1', 'D2', 'D3', 'D4'))
    """
    Lq, Cq, Cfq, Rq = (to_fmpq(v, nm) for v, nm in ((L, "L"), (C, "C"), (Cf, "Cf"), (R, "R")))
    net = [("C1", "a", "b", Cq), ("L1", "a", "b", Lq), ("D1", "a", "p"), ("D2", "b", "p"), ("D3", "0", "a"),
           ("D4", "0", "b"), ("Cf", "p", "0", Cfq), ("R1", "p", "0", Rq)]
    return circuit(net, name="diode bridge with capacitor filter (Siconos)")


def buck_converter(E: Any = 2, L: Any = "1/10", C: Any = 1, R: Any = 1, period: Any = 1, duty: Any = "1/4") -> LCS:
    """A buck (step-down) converter: a switch driven by PWM (on for ``duty * period`` of each
    ``period``), a freewheeling diode, an inductor L and an output capacitor C with a load R,
    fed by a DC source E.  State (i(L), v(C), 1) (the source's constant), one pair for the diode:

        L i' = s(t) E - v + u,   C v' = i - v / R,   0 <= y = i ⊥ u >= 0

    with s(t) = 1 while the switch is on, 0 while it is off (:func:`lcs_exact.models.scheduled`);
    u is the diode's reverse voltage: while the switch is off and i > 0 the diode conducts
    (u = 0); when i reaches 0 it blocks (u = v holds i at 0: discontinuous conduction) until the
    switch closes again (the switch conducts one way, so i >= 0 in both phases).  The defaults
    (E = 2, L = 1/10, C = R = 1, duty 1/4 of a period 1) conduct discontinuously from the first
    period on.  Start from ``buck.embed([i0, v0])``.

    Parameters
    ----------
    E : rational, optional
        The DC source voltage.
    L, C, R : rational, optional
        The inductance, the output capacitance and the load resistance.
    period : rational, optional
        The PWM period.
    duty : rational, optional
        The duty cycle in (0, 1): the switch is on for ``duty * period`` of each period.

    >>> buck = buck_converter()
    >>> buck.state_names, [p.duration for p in buck.schedule.phases], buck.embed([0, 0]).transpose()
    (('i(L)', 'v(C)', '1'), [1/4, 3/4], [0, 0, 1])
    """
    Eq, Lq, Cq, Rq, T, d = (to_fmpq(v, nm) for v, nm in ((E, "E"), (L, "L"), (C, "C"), (R, "R"), (period, "period"),
                                                         (duty, "duty")))
    if Lq <= 0 or Cq <= 0 or Rq <= 0 or T <= 0 or not 0 < d < 1:
        raise InvalidArgument(f"buck_converter needs L, C, R, period > 0 and 0 < duty < 1, got L = {Lq}, C = {Cq}, "
                              f"R = {Rq}, period = {T}, duty = {d}")
    A = [[0, -1 / Lq], [1 / Cq, -1 / (Rq * Cq)]]
    options = dict(state_names=["i(L)", "v(C)"], constraint_names=["D"],
                   roles=[("-v(D)", "i(L)", "blocking", "conducting")])
    on = driven(A, [[1 / Lq], [0]], [[1, 0]], [[0]], E=[[Eq / Lq], [0]], w=[constant(1)], name="switch on", **options)
    off = driven(A, [[1 / Lq], [0]], [[1, 0]], [[0]], E=[[0], [0]], w=[constant(1)], name="switch off", **options)
    return scheduled([(d * T, on), ((1 - d) * T, off)], period=T, name="buck converter (PWM, freewheeling diode)")
