"""Impact cascades at a corner (issue 15): three contacts closing one after the other with gaps that
shrink super-geometrically (1e-20, 1e-59, 1e-176, ...) are accumulations of events (Remark 4.11)
with no scaling law.  The run must stop with ZenoDetected carrying a certified enclosure
lower <= T* <= upper of the accumulation time, never with an unresolved sign.

The accumulation times are computed here independently: an event-driven run of the mechanical
system written from its physics (M q'' + K q = E^T u, 0 <= E q ⊥ u >= 0, impacts plastic: the
velocity is projected in the metric of M onto the contacts that take an impulse, chosen by the
velocity LCP; a contact stays closed while its force is positive, chosen by the acceleration LCP),
in mpmath at 250 digits, until the next phase is shorter than the digits can resolve.
"""
from __future__ import annotations

import itertools
import re
from fractions import Fraction

import mpmath as mp
import pytest
from flint import fmpq

import lcs_exact as L
from lcs_exact.accumulations.cascade import cascade_bound
from lcs_exact.models import mechanical
from lcs_exact.phases.trajectory import Status

STOPS = [[1, 0, 0], [-1, 1, 0], [0, -1, 1]]  # q0 >= 0 (a wall), q1 - q0 >= 0, q2 - q1 >= 0


# --------------------------------------------------------------------------------------------
# the independent run (mpmath)
# --------------------------------------------------------------------------------------------

def _mp(q):
    q = Fraction(q)
    return mp.mpf(q.numerator) / q.denominator


def _rows(E, idx):
    return mp.matrix([[E[i, j] for j in range(E.cols)] for i in idx])


def plastic_run(Mm, K, E, x0, t_end, dps=250):
    """(event times, [(trigger, impulse set, contacts held after)], the time the run reached,
    a bound of what is left of the cascade) for M q'' + K q = E^T u with plastic impacts."""
    with mp.workdps(dps):
        M, Kq, Ec = mp.matrix(Mm), mp.matrix(K), mp.matrix(E)
        m, k = M.rows, Ec.rows
        Mi = M ** -1
        tol = mp.mpf(10) ** (-(dps - 12))

        def W(I):
            EI = _rows(Ec, I)
            return EI * Mi * EI.T

        def force_rows(J):  # u_J = W_JJ^-1 E_J M^-1 K q keeps E_J q'' = 0
            return W(J) ** -1 * _rows(Ec, J) * Mi * Kq if J else None

        def mode_matrix(J):
            acc = -Mi * Kq
            if J:
                acc = acc + Mi * _rows(Ec, J).T * force_rows(J)
            A = mp.zeros(2 * m, 2 * m)
            for i in range(m):
                A[i, m + i] = 1
                for j in range(m):
                    A[m + i, j] = acc[i, j]
            return A

        def monitored(J):  # (name, row on x = (q, v)) of the gaps y_i (i not in J) and forces u_i (i in J)
            out = []
            F = force_rows(J)
            for i in range(k):
                row = mp.zeros(1, 2 * m)
                if i in J:
                    r = J.index(i)
                    for j in range(m):
                        row[0, j] = F[r, j]
                    out.append((f"u_{i}", row))
                else:
                    for j in range(m):
                        row[0, j] = Ec[i, j]
                    out.append((f"y_{i}", row))
            return out

        def acc_lcp(q, Z):  # the contacts of Z (closed, at rest) that stay closed: forces >= 0, others separate
            found = []
            for r in range(len(Z) + 1):
                for J in itertools.combinations(Z, r):
                    J = list(J)
                    a = -Mi * Kq * q
                    lam = []
                    if J:
                        lam_m = force_rows(J) * q
                        lam = [lam_m[i] for i in range(len(J))]
                        a = a + Mi * _rows(Ec, J).T * lam_m
                    if all(x > tol for x in lam) and \
                            all((_rows(Ec, [i]) * a)[0] > tol for i in Z if i not in J):
                        found.append(J)
            assert len(found) == 1, (Z, found, [mp.nstr(c, 5) for c in q])
            return found[0]

        def impact(v, Z):  # the velocity LCP on the closed contacts Z: impulses >= 0, no contact approaching
            found = []  # (W positive definite: every solution gives the same velocity after)
            for r in range(1, len(Z) + 1):
                for I in itertools.combinations(Z, r):
                    I = list(I)
                    lam = -(W(I) ** -1) * (_rows(Ec, I) * v)
                    vp = v + Mi * _rows(Ec, I).T * lam
                    if all(lam[i] > -tol for i in range(len(I))) and \
                            all((_rows(Ec, [i]) * vp)[0] > -tol for i in Z if i not in I):
                        found.append((I, vp))
            assert found and all(mp.norm(f[1] - found[0][1]) < tol for f in found), (Z, [f[0] for f in found])
            return max(found, key=lambda f: len(f[0]))

        def split(x):
            return mp.matrix([x[i] for i in range(m)]), mp.matrix([x[m + i] for i in range(m)])

        x = mp.matrix([_mp(c) for c in x0])
        t, times, kinds = mp.mpf(0), [], []
        q0, v0 = split(x)
        Z = [i for i in range(k) if abs((_rows(Ec, [i]) * q0)[0]) < tol]
        if any((_rows(Ec, [i]) * v0)[0] < -tol for i in Z):  # an impact at t = 0
            I, v0 = impact(v0, Z)
            x = mp.matrix(list(q0) + list(v0))
            times.append(t)
            kinds.append(("t = 0", tuple(I), None))
        Z0 = [i for i in Z if abs((_rows(Ec, [i]) * v0)[0]) < tol]
        J = acc_lcp(q0, Z0)
        if kinds:
            kinds[-1] = ("t = 0", kinds[-1][1], tuple(J))
        floor = mp.mpf(10) ** (-(dps - 40))
        # a phase of length h decides the order of events h^3 apart (the next gaps): stop at h < floor^(1/3)
        shortest = mp.mpf(10) ** (-(dps - 40) // 3)
        while True:
            A, cons = mode_matrix(J), monitored(J)
            scales = []
            for _, row in cons:
                f0, f1 = (row * x)[0], (row * A * x)[0]
                if f0 > -tol and f1 < -tol:
                    scales.append(max(f0, 0) / -f1)
            scale = min(scales) if scales else t_end - t
            if scale < shortest:  # what is left: the next phase (~ scale) and deeper ones (~ scale^3)
                return times, kinds, t, 4 * max(scale, floor)
            hi, hit, steps = min(3 * scale, t_end - t), None, 600
            while hit is None:
                step = mp.expm(A * (hi / steps))
                prev, y = mp.mpf(0), x
                for _ in range(steps):
                    y = step * y
                    bad = [(name, row) for name, row in cons if (row * y)[0] < -tol]
                    if bad:
                        hit = (prev, prev + hi / steps, bad)
                        break
                    prev = prev + hi / steps
                if hit is None:
                    if hi == t_end - t:
                        return times, kinds, t_end, mp.mpf(0)
                    hi = min(3 * hi, t_end - t)
            a, b, bad = hit  # the first root of the functions that turned negative in [a, b]
            h, name = min((mp.findroot(lambda s, r=row: (r * mp.expm(A * s) * x)[0], (a, b), solver="anderson"), name)
                          for name, row in bad)
            x = mp.expm(A * h) * x
            t += h
            i = int(name[2:])
            q, v = split(x)
            if name.startswith("y"):
                I, v = impact(v, sorted(J + [i]))
                Z0 = [c for c in sorted(J + [i]) if abs((_rows(Ec, [c]) * v)[0]) < tol]
            else:  # a contact lets go: its force reached 0
                I, Z0 = [], [c for c in J if c != i]
            times.append(t)
            if max(abs(c) for c in q) < floor:  # at the corner deeper than the digits: stop here
                kinds.append((name, tuple(I), None))
                return times, kinds, t, 4 * floor
            J = acc_lcp(q, Z0)
            x = mp.matrix(list(q) + list(v))
            kinds.append((name, tuple(I), tuple(J)))


def enclosure(err):
    """(lower, upper) of a ZenoDetected as mpf (at the caller's working precision)."""
    assert isinstance(err.lower, type(fmpq(0))) and isinstance(err.upper, type(fmpq(0)))
    return _mp(Fraction(int(err.lower.p), int(err.lower.q))), _mp(Fraction(int(err.upper.p), int(err.upper.q)))


def num(r, digits=40):
    """The midpoint of a certified ball of an exact real (at the caller's working precision)."""
    return mp.mpf(r.ball(digits).mid().str(digits + 5, radius=False))


def contains(err, t_last, left, width):
    """The enclosure of err holds the independent T* in [t_last, t_last + left] and is < width wide."""
    lo, hi = enclosure(err)
    slack = mp.mpf(10) ** -70
    assert lo - slack <= t_last and t_last + left <= hi + slack, (lo, t_last, hi)
    assert lo < hi and hi - lo < width


# --------------------------------------------------------------------------------------------
# three carts between walls, started at the wall: every phase ends at the corner
# --------------------------------------------------------------------------------------------

CARTS = ([[2, 0, 0], [0, 3, 0], [0, 0, 2]], [[6, -2, 0], [-2, 4, -2], [0, -2, 6]])


@pytest.mark.slow
def test_cascade_from_the_wall_ends_as_a_certified_accumulation():
    """Masses 2, 3, 2, springs 4 | 2 | 2 | 4 between two walls; cart 0 at rest against the left wall,
    carts 1 and 2 touching, 1/100 away, moving at -1.  Cart 1 hits cart 0 (all three at one speed,
    2 v0 + 5 V = 7 w), cart 0 hits the wall (v0 = 0), and so on: at the corner q = 0 the springs
    push with forces proportional to the gaps, so each gap is about the cube of the one before
    (1e-2, 5e-7, 4e-20, 3e-59, ...) and the impacts accumulate at T* ~ 0.0099997 while every
    velocity tends to 0 (a factor 5/7 a cycle).  The run stops with ZenoDetected after a few
    events; its enclosure contains the independent T* and is 1e-40 wide."""
    lcs = mechanical(*CARTS, STOPS)
    x0 = [0, Fraction(1, 100), Fraction(1, 100), 0, -1, -1]
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, x0, 1)
    err = info.value
    times, kinds, t_last, left = plastic_run(CARTS[0], CARTS[1], STOPS, x0, 1)
    with mp.workdps(100):
        # the independent run: the alternation, each gap about the cube of the one before
        assert kinds == [("y_1", (1, 2), (2,)), ("y_0", (0, 2), (2,))] * 2
        d = [b - a for a, b in zip(times, times[1:])] + [left / 4]
        assert mp.mpf("1e-7") < d[0] < mp.mpf("1e-6") and mp.mpf("1e-20") < d[1] < mp.mpf("1e-19")
        assert mp.mpf("1e-59") < d[2] < mp.mpf("1e-58") and mp.mpf("1e-177") < d[3] < mp.mpf("1e-175")
        assert mp.mpf("0.00999973") < t_last < mp.mpf("0.00999974")
        contains(err, t_last, left, mp.mpf(10) ** -35)
        assert abs(mp.mpf(err.estimate) - t_last) < mp.mpf(10) ** -15
        # the message's decimals are bounds too: rounded outward
        lo_text, hi_text = re.search(r"T\* in \[([0-9.eE+-]+), ([0-9.eE+-]+)\]", str(err)).groups()
        assert Fraction(lo_text) <= Fraction(int(err.lower.p), int(err.lower.q))
        assert Fraction(hi_text) >= Fraction(int(err.upper.p), int(err.upper.q))
        tr = err.trajectory
        assert tr.partial and tr.status is Status.ZENO and tr.certified and err.time is None
        assert 3 <= len(tr.events) <= 5 and [e.triggers for e in tr.events[:2]] == [("y_1",), ("y_0",)]
        for e, t in zip(tr.events, times):  # the events computed are the independent ones
            assert abs(num(e.time) - t) < mp.mpf(10) ** -35


@pytest.mark.slow
def test_cascade_after_a_flight_stops_at_the_certified_enclosure():
    """The same carts from q = (1/4, 3/4, 7/8), v = (-3/4, -1/4, 0): cart 0 hits the wall, carts 1
    and 2 collide, cart 1 hits cart 0, and the cascade at the corner follows (near t = 1.3654).
    The run used to end at the precision cap after 9 events with only a lower bound; now it
    stops with the enclosure, which contains the independent accumulation time."""
    lcs = mechanical(*CARTS, STOPS)
    x0 = [Fraction(1, 4), Fraction(3, 4), Fraction(7, 8), Fraction(-3, 4), Fraction(-1, 4), 0]
    for zeno in ("cross", "stop"):
        with pytest.raises(L.ZenoDetected) as info:
            L.simulate(lcs, x0, 12, zeno=zeno)
        err = info.value
        times, kinds, t_last, left = plastic_run(CARTS[0], CARTS[1], STOPS, x0, 12)
        with mp.workdps(100):
            assert [k[:2] for k in kinds[:3]] == [("y_0", (0,)), ("y_2", (2,)), ("y_1", (1, 2))]
            assert [k[0] for k in kinds[3:]] == ["y_0", "y_1", "y_0", "y_1", "y_0"]
            assert mp.mpf("1.3654") < t_last < mp.mpf("1.3655")
            contains(err, t_last, left, mp.mpf(10) ** -35)
            tr = err.trajectory
            assert tr.status is Status.ZENO and len(tr.events) >= 5
            assert all(abs(num(e.time) - t) < mp.mpf(10) ** -35 for e, t in zip(tr.events, times))


@pytest.mark.slow
def test_cascade_with_releases_used_to_end_in_an_unresolved_sign():
    """Masses 2, 3, 3, springs 4 | 4 | 1 | 3: the cascade at the corner runs a cycle of five events
    (carts 1-2 collide, cart 1 hits cart 0 with 1-2 held, the 1-2 contact lets go (u_2 = 0), cart
    0 hits the wall, cart 1 hits cart 0 again) whose durations go 1e-6, 1e-17, 1e-6, 1e-19,
    1e-19, then 1e-56, ...  It ended in UnresolvedSign after 15 events; now in ZenoDetected whose
    enclosure contains the independent accumulation time."""
    Mm, K = [[2, 0, 0], [0, 3, 0], [0, 0, 3]], [[8, -4, 0], [-4, 5, -1], [0, -1, 4]]
    lcs = mechanical(Mm, K, STOPS)
    x0 = [Fraction(3, 8), Fraction(9, 8), Fraction(15, 8), Fraction(1, 4), Fraction(-3, 4), Fraction(-3, 8)]
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, x0, 6)
    err = info.value
    times, kinds, t_last, left = plastic_run(Mm, K, STOPS, x0, 6)
    with mp.workdps(100):
        assert [k[0] for k in kinds[1:5]] == ["y_2", "u_2", "y_0", "y_1"]
        assert [k[0] for k in kinds[5:]] == ["y_2", "y_1", "u_2", "y_0", "y_1", "y_2"]
        assert kinds[6][1:] == ((1, 2), (2,)) and kinds[7][1:] == ((), ())  # all three at one speed; 1-2 let go
        assert mp.mpf("1.39045") < t_last < mp.mpf("1.39046")
        contains(err, t_last, left, mp.mpf(10) ** -35)
        tr = err.trajectory
        assert tr.status is Status.ZENO and tr.certified and len(tr.events) >= 8
        assert all(abs(num(e.time) - t) < mp.mpf(10) ** -35 for e, t in zip(tr.events, times))


@pytest.mark.slow
def test_two_contacts_taking_turns_over_a_moving_background():
    """Masses 3, 1, 4 (springs 2 | 4 to the right wall, 2 between carts 0-1 and 4 between 1-2),
    from q = (7/8, 3/2, 5/2), v = (-5/8, 0, -1/4): the light cart 1 is caught between carts 0 and
    2, hitting them in turn (y_2, y_1, y_2, ...; plastic: the two that meet take one speed, then
    the springs part them again with accelerations of order 1).  The phases shrink like
    0.04, 4e-4, 8e-11, 2e-21, 5e-63 while the three carts move on together: no corner, a moving
    background.  It ends in ZenoDetected whose enclosure contains the independent
    accumulation time."""
    Mm, K = [[3, 0, 0], [0, 1, 0], [0, 0, 4]], [[4, -2, 0], [-2, 6, -4], [0, -4, 4]]
    lcs = mechanical(Mm, K, STOPS)
    x0 = [Fraction(7, 8), Fraction(3, 2), Fraction(5, 2), Fraction(-5, 8), 0, Fraction(-1, 4)]
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, x0, 6)
    err = info.value
    times, kinds, t_last, left = plastic_run(Mm, K, STOPS, x0, 6)
    with mp.workdps(100):
        names = [k[0] for k in kinds]
        assert names[:2] == ["y_2", "y_1"] and all(a != b for a, b in zip(names, names[1:]))
        assert all(k[1] == (int(k[0][2:]),) and k[2] == () for k in kinds[:-1])  # single impacts, all apart after
        d = [b - a for a, b in zip(times, times[1:])]
        assert all(b < a ** mp.mpf("1.5") for a, b in zip(d[3:], d[4:]))  # squaring, roughly
        assert mp.mpf("2.930") < t_last < mp.mpf("2.931")
        contains(err, t_last, left, mp.mpf(10) ** -35)
        tr = err.trajectory
        assert tr.status is Status.ZENO and tr.certified and "background" in str(err)
        assert all(abs(num(e.time) - t) < mp.mpf(10) ** -35 for e, t in zip(tr.events, times))


@pytest.mark.slow
def test_four_coupled_masses_taking_turns_proven_without_a_budget():
    """Four masses with a coupled (non-diagonal) mass matrix, contacts q1 >= 0 and q0 - q3 >= 0,
    from x0 = (10/3, 1/3, 1/2, 2, -1, -2, -1, 3): the two contacts take turns (y_0, y_1, ...) with
    phases 5.5e-6, 5.6e-12, 4.8e-23, ... over a background of dimension 4 (found by a fuzz of
    random systems).  Inside simulate the proof has a time budget; called directly, without one,
    on the first seven events it proves the cascade, and its enclosure contains the accumulation
    time of the independent mpmath run."""
    Mm = [[2, 1, 0, 0], [1, 2, 1, 0], [0, 1, 2, 1], [0, 0, 1, 2]]
    K = [[3, -1, 0, 0], [-1, 6, -2, 0], [0, -2, 5, -3], [0, 0, -3, 3]]
    E = [[0, 1, 0, 0], [1, 0, 0, -1]]
    x0 = [Fraction(10, 3), Fraction(1, 3), Fraction(1, 2), 2, -1, -2, -1, 3]
    lcs = mechanical(Mm, K, E)
    with pytest.raises(L.LimitExceeded) as info:
        L.simulate(lcs, x0, 4, max_events=7)
    events = info.value.trajectory.events
    bound = cascade_bound(lcs, events, background_order=12)
    assert bound is not None and bound.background and bound.period == 2
    times, kinds, t_last, left = plastic_run(Mm, K, E, x0, 4)
    with mp.workdps(100):
        assert [k[0] for k in kinds[:7]] == ["y_0", "y_1"] * 3 + ["y_0"]
        lo = _mp(Fraction(int(bound.lower.p), int(bound.lower.q)))
        hi = _mp(Fraction(int(bound.upper.p), int(bound.upper.q)))
        assert lo <= t_last and t_last + left <= hi and hi - lo < mp.mpf(10) ** -35
        assert all(abs(num(e.time) - t) < mp.mpf(10) ** -35 for e, t in zip(events, times))


# --------------------------------------------------------------------------------------------
# the proof refuses what it cannot prove
# --------------------------------------------------------------------------------------------

def test_no_cascade_proof_without_a_cascade():
    """Periodic motion (the two carts), a bouncing ball with restitution (Newton's law: not the
    paper's projection), and the cascade's own events read from too early (before the cycle
    repeats) give no proof."""
    from lcs_exact.examples import bouncing_ball
    from lcs_exact.models import two_carts
    tr = L.simulate(two_carts(), [0, 1, -1, 0], 20)
    assert len(tr.events) >= 3 and cascade_bound(two_carts(), tr.events) is None
    ball = bouncing_ball()
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(ball, ball.embed([1, 0]), 10, zeno="stop")
    assert cascade_bound(ball, info.value.trajectory.events) is None
    lcs = mechanical(*CARTS, STOPS)
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, [0, Fraction(1, 100), Fraction(1, 100), 0, -1, -1], 1)
    assert cascade_bound(lcs, info.value.trajectory.events[:2]) is None


@pytest.mark.slow
def test_the_proof_does_not_follow_a_wrong_cycle():
    """Events whose signatures are altered (the triggers of the cycle swapped) are not proven:
    the proof checks every phase and every jump of the cycle it is given."""
    from dataclasses import replace
    lcs = mechanical(*CARTS, STOPS)
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, [0, Fraction(1, 100), Fraction(1, 100), 0, -1, -1], 1)
    events = list(info.value.trajectory.events)
    assert cascade_bound(lcs, events) is not None
    swapped = [replace(e, triggers=("y_0",) if e.triggers == ("y_1",) else ("y_1",)) for e in events]
    assert cascade_bound(lcs, swapped) is None
    assert cascade_bound(lcs, events, budget=0) is None  # a spent budget ends the attempt: no proof, no error
    assert isinstance(cascade_bound(lcs, events).lower, type(fmpq(0)))


@pytest.mark.slow
def test_the_proof_budget_counts_work_not_seconds(monkeypatch):
    """The cascade proof of the three carts at the wall, given the run's events: with a budget of
    work it succeeds or gives up at the same point whatever the clock says (a loaded machine),
    and a budget too small for it gives up (None) on every machine."""
    from lcs_exact.numbers.taylormodels import NoProof, WorkBudget
    lcs = mechanical(*CARTS, STOPS)
    with pytest.raises(L.ZenoDetected) as info:
        L.simulate(lcs, [0, Fraction(1, 100), Fraction(1, 100), 0, -1, -1], 1)
    events = info.value.trajectory.events
    proven = cascade_bound(lcs, events, budget=None)
    assert proven is not None and proven.lower < proven.upper
    assert cascade_bound(lcs, events, budget=10) is None  # too little work for any proof
    import time
    ticks = iter(range(0, 10 ** 9, 1000))  # a clock that jumps 1000 s at every look
    monkeypatch.setattr(time, "monotonic", lambda: next(ticks))
    again = cascade_bound(lcs, events, budget=80_000_000)
    assert (again.lower, again.upper, again.period) == (proven.lower, proven.upper, proven.period)
    b = WorkBudget(5)
    b.charge(5)
    with pytest.raises(NoProof, match="work budget"):
        b.charge(1)
