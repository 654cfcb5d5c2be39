"""Fixtures read back (``lcs-exact/trajectory/1``, docs/fixtures.md): :func:`read_fixture` and
:class:`FixtureTrajectory`, whose events, accumulations, samples and exosystem are certified
``flint.arb`` balls, validated by :mod:`lcs_exact.fixture` (the schema, the digests).

A fixture read back repeats its run exactly when x0 and t_end are rational
(:attr:`FixtureTrajectory.exact`, Algorithm 7.1 by :func:`lcs_exact.simulate`, checked against the
fixture's events and samples), so this module sits above the engine and imports it; a run
recomputed elsewhere (from the recipe of a zoo problem when x0 is irrational) is attached by
:meth:`FixtureTrajectory.with_run`.
"""
from __future__ import annotations

import ast
import json
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any, Sequence

from flint import arb, fmpq

from ..numbers import check_digits, workprec
from ..errors import FixtureMismatch, FormatError, IllPosed, InvalidArgument, LCSError
from ..dynamics import ball_text, number_ball, number_exact, number_rational, short_text, to_fraction
from ..dynamics import SCHEMA, check_digest, validate_fixture
from ..modes import format_mode
from ..algebra import to_fmpq, to_matrix
from ..dynamics import scheduled
from ..dynamics import simulate, simulate_branches
from ..system import AppendedStates, SourceBlock
from ..system import LCS
from ..numbers import expm_action

__all__ = ["read_fixture", "FixtureTrajectory", "FixtureEvent", "FixtureAccumulation", "Sample"]


def _frozen_mode(m: Any, where: str) -> frozenset | None:
    if m is None:
        return None
    if not isinstance(m, list) or not all(isinstance(i, int) and not isinstance(i, bool) for i in m):
        raise FormatError(f"fixture: {where} must be a list of indices")
    return frozenset(m)


def _key(d: dict, key: str, where: str = "fixture") -> Any:
    if not isinstance(d, dict) or key not in d:
        raise FormatError(f"{where} lacks '{key}'")
    return d[key]


def _balls(v: Any, where: str) -> tuple:
    if not isinstance(v, list):
        raise FormatError(f"fixture: {where} must be a list of numbers")
    return tuple(number_ball(c, where=f"{where}[{i}]") for i, c in enumerate(v))


@dataclass(frozen=True)
class FixtureEvent:
    """An event read from a fixture: the certified time ball (and closed form when given), the
    modes (Def. 4.3, (4.9)) and the states before and after as certified balls."""

    time: arb
    time_exact: str | None
    mode_before: frozenset | None
    modes: tuple
    mode_after: frozenset
    state_before: tuple
    state_after: tuple
    multiplicity: int
    triggers: tuple = ()

    def __repr__(self):
        mb = "start" if self.mode_before is None else _fmt_modes(self.mode_before)
        chain = " -> ".join(_fmt_modes(m) for m in self.modes) or "no jump"
        t = ball_text(self.time) + (f" = {self.time_exact}" if self.time_exact and not self.time.is_exact() else "")
        return (f"FixtureEvent(t={t}, {mb} => {_fmt_modes(self.mode_after)}, jumps: {chain}, "
                f"x- = {_show_vec(self.state_before)}, x+ = {_show_vec(self.state_after)})")


@dataclass(frozen=True)
class Sample:
    """One grid point of a fixture: the exact time ``t`` (rational) and the certified state."""

    t: Fraction
    x: tuple

    def __repr__(self):
        return f"Sample(t={self.t}, x={_show_vec(self.x)})"


def _show_vec(v: tuple) -> str:
    return "(" + ", ".join(ball_text(c) for c in v) + ")"


class FixtureTrajectory:
    """A trajectory read back from a fixture (see :func:`read_fixture`).

    Attributes: ``lcs`` (the exact system), ``x0``, ``t_end``, ``digits``, ``events``
    (:class:`FixtureEvent`), ``samples`` (:class:`Sample`), ``sample_step``, ``final_time``,
    ``final_state``, ``certified``, ``assumptions``, ``partial``, ``stop_reason``,
    ``accumulations``, ``provenance`` (the dict written with the fixture, or None), ``data``
    (the dict).  Numbers are certified ``flint.arb`` balls.
    ``x0_rational`` holds x0 as Fractions when the fixture says it is rational; then, or when
    its provenance says how x0 is made exactly (``"x0": "expm_action(A, -1, [0, -1, -1, 0])"``,
    as the zoo writes: e^{A t} v with the fixture's own A, checked against its x0 balls),
    ``exact`` is the trajectory recomputed exactly (on first use, checked against the fixture's
    events and samples).  ``digested``: the fixture carries its content digest (checked on
    reading).

    Parameters
    ----------
    data : dict
        The fixture (schema ``lcs-exact/trajectory/1``), checked: schema, content and digest.
    source : str, optional
        Its name in error messages (a path).
    """

    def __init__(self, data: dict, source: str = "fixture"):
        if not isinstance(data, dict):
            raise FormatError(f"{source}: a fixture is a JSON object, got {type(data).__name__}")
        if data.get("schema") != SCHEMA:
            raise FormatError(f"{source}: schema is {data.get('schema')!r}, expected {SCHEMA!r}")
        try:
            validate_fixture(data)
        except ModuleNotFoundError:  # without jsonschema the reader's own checks below still run
            pass
        check_digest(data, source)  # an edited fixture is not ground truth
        self.data, self.source = data, source
        #: True when the fixture carries its digest (checked above); a fixture without one
        #: (written before digests existed, or with them removed) is verified against its
        #: recomputed run before :func:`lcs_exact.compare` takes its samples as ground truth
        self.digested = "digest" in data
        sysd = _key(data, "system")
        A = to_matrix(_key(sysd, "A", "system"), "system.A")
        self.sources = _source_block(data.get("sources"), A, source)
        embedding = None
        if self.sources is not None and self.sources.states == tuple(range(A.nrows() - len(self.sources.states), A.nrows())):
            names = sysd.get("state_names") or [f"x_{i}" for i in range(A.nrows())]
            embedding = AppendedStates(self.sources.states[0], self.sources.z0, [names[i] for i in self.sources.states])
        self.lcs = LCS(A, _key(sysd, "B", "system"), _key(sysd, "C", "system"),
                       _key(sysd, "D", "system"), name=sysd.get("name"), restitution=sysd.get("restitution"),
                       state_names=sysd.get("state_names") or None,
                       constraint_names=sysd.get("constraint_names") or None, embedding=embedding)
        if data.get("schedule") is not None:  # the data switch at scheduled times: the same run needs them
            self.lcs = _scheduled(data["schedule"], self.lcs, source)
        #: Newton's restitution coefficients (one rational per constraint) or None (the paper's P_I)
        self.restitution = self.lcs.restitution
        self.name = self.lcs.name
        self.digits = _key(data, "digits")
        self.x0 = _balls(_key(data, "x0"), "x0")
        rat = [number_rational(c) for c in data["x0"]]
        self.x0_rational = tuple(rat) if all(q is not None for q in rat) else None
        self.t_end = number_ball(_key(data, "t_end"), where="t_end")
        self.t_end_rational = number_rational(data["t_end"])
        self.events = tuple(self._event(e, j) for j, e in enumerate(_key(data, "events")))
        self.final_time = number_ball(_key(data, "final_time"), where="final_time")
        self.final_state = _balls(_key(data, "final_state"), "final_state")
        self.certified = bool(_key(data, "certified"))
        self.assumptions = tuple(_key(data, "assumptions"))
        self.partial = bool(data.get("partial", False))
        self.stop_reason = data.get("stop_reason")
        self.provenance = data.get("provenance")
        self.accumulations = tuple(_fixture_accumulation(a, i, self.digits)
                                   for i, a in enumerate(data.get("accumulations", ())))
        step = data.get("sample_step")
        self.sample_step = None if step is None else to_fraction(step, "sample_step")
        samples = []
        for j, s in enumerate(data.get("samples", ())):
            t = number_rational(_key(s, "t", f"samples[{j}]"))
            if t is None:
                raise FormatError(f"{source}: samples[{j}].t is not an exact rational")
            samples.append(Sample(t, _balls(_key(s, "x", f"samples[{j}]"), f"samples[{j}].x")))
        self.samples = tuple(samples)
        self._by_time = {s.t: s for s in self.samples}
        self._exact = None
        if any(len(v) != self.lcs.n for v in [self.x0, self.final_state] + [s.x for s in self.samples]):
            raise FormatError(f"{source}: a state does not have n = {self.lcs.n} components")

    def _event(self, e: dict, j: int) -> FixtureEvent:
        w = f"events[{j}]"
        return FixtureEvent(
            time=number_ball(_key(e, "time", w), where=f"{w}.time"), time_exact=number_exact(e["time"]),
            mode_before=_frozen_mode(_key(e, "mode_before", w), f"{w}.mode_before"),
            modes=tuple(_frozen_mode(m, f"{w}.modes") for m in _key(e, "modes", w)),
            mode_after=_frozen_mode(_key(e, "mode_after", w), f"{w}.mode_after"),
            state_before=_balls(_key(e, "state_before", w), f"{w}.state_before"),
            state_after=_balls(_key(e, "state_after", w), f"{w}.state_after"),
            multiplicity=int(_key(e, "multiplicity", w)), triggers=tuple(e.get("triggers", ())))

    # --- exact evaluation -----------------------------------------------------------------------
    def with_run(self, traj: Any) -> "FixtureTrajectory":
        """Use ``traj`` (a :class:`~lcs_exact.Trajectory` of the same problem, e.g. recomputed from
        the recipe of the fixture's provenance when x0 is not rational) as the exact recomputation
        between the samples, after checking it against every event and sample of the fixture
        (:class:`~lcs_exact.errors.FixtureMismatch` otherwise).  Returns the fixture.

        Parameters
        ----------
        traj : Trajectory
            The exact run of the fixture's problem.
        """
        self._verify(traj)
        self._exact = traj
        return self

    @property
    def schedule(self):
        """The schedule of a run whose data switch at scheduled times (a
        :class:`~lcs_exact.schedule.Schedule`: each phase's duration, exact system and reset), or None."""
        return getattr(self.lcs, "schedule", None)

    @property
    def has_exact(self) -> bool:
        """True when states between the samples can be computed exactly (x0 and t_end rational,
        or a run attached by :meth:`with_run`)."""
        return self._exact is not None or self.can_recompute

    @property
    def can_recompute(self) -> bool:
        """True when x0 (rational, or made as the provenance says) and t_end are exact: the run
        can be repeated exactly."""
        return self.t_end_rational is not None and self._x0_exact() is not None

    def _x0_exact(self):
        """x0 exactly: the rational x0, or e^{A t} v from the provenance's recipe (the zoo's
        ``expm_action(A, t, v)``), checked against the fixture's x0 balls; else None."""
        if self.x0_rational is not None:
            return [fmpq(q.numerator, q.denominator) for q in self.x0_rational]
        if "_x0_recipe" not in self.__dict__:
            self._x0_recipe = _x0_recipe(self.provenance, self.lcs, self.x0)
        return self._x0_recipe

    @property
    def exact(self):
        """The trajectory recomputed exactly from the fixture's system and x0 (None when x0 or
        t_end is not rational).  Computed on first access and checked against the fixture."""
        if self._exact is None and self.can_recompute:
            self._exact = self._recompute()
        return self._exact

    def verify(self) -> "FixtureTrajectory":
        """Recompute the run exactly and check every event and sample of the fixture against it
        (:class:`~lcs_exact.errors.FixtureMismatch` on a disagreement; :class:`FormatError` when
        x0 or t_end is not rational).  Returns the fixture."""
        if not self.can_recompute:
            raise FormatError(f"{self.source}: x0 or t_end is not rational: the run cannot be recomputed exactly")
        self.exact  # noqa: B018 -- computed and checked on first access
        return self

    def _recompute(self):
        x0 = self._x0_exact()
        T = fmpq(self.t_end_rational.numerator, self.t_end_rational.denominator)
        opts = {"allow_unresolved": not self.certified, "max_events": max(1000, len(self.events))}
        if self.partial:
            opts["max_events"] = len(self.events)
        try:
            traj = simulate(self.lcs, x0, T, digits=self.digits, **opts)
        except IllPosed:  # a non-unique problem (Theorem 6.3 fails): the fixture is one of its branches
            return self._matching_branch(simulate_branches(self.lcs, x0, T, digits=self.digits, **opts))
        except LCSError as e:
            if not self.partial or getattr(e, "trajectory", None) is None:
                raise FixtureMismatch(f"{self.source}: recomputing the run failed where the fixture "
                                      f"has none: {type(e).__name__}: {e}") from e
            traj = e.trajectory
        self._verify(traj)
        return traj

    def _matching_branch(self, branches):
        """The branch of a non-unique problem whose events and samples are the fixture's."""
        for traj in branches:
            try:
                self._verify(traj)
            except FixtureMismatch:
                continue
            return traj
        raise FixtureMismatch(f"{self.source}: the problem is not unique and none of its {len(branches)} "
                              "solutions matches the fixture")

    def _verify(self, traj) -> None:
        """Every event and every sample of the recomputed run agrees with the fixture (modes
        exactly, times and states as overlapping certified balls: disjoint balls prove a
        disagreement)."""
        src, d = self.source, self.digits
        if len(traj.events) != len(self.events):
            raise FixtureMismatch(f"{src}: the recomputed run has {len(traj.events)} events, the fixture "
                                  f"{len(self.events)}")
        for j, (e, f) in enumerate(zip(traj.events, self.events)):
            for key in ("mode_before", "mode_after", "modes"):
                if getattr(e, key) != getattr(f, key):
                    raise FixtureMismatch(f"{src}: event {j}: recomputed {key} {_fmt_modes(getattr(e, key))} "
                                          f"differs from the fixture's {_fmt_modes(getattr(f, key))}")
            if not e.time.ball(d).overlaps(f.time):
                raise FixtureMismatch(f"{src}: event {j}: recomputed time {e.time.decimal(20)} is outside the "
                                      f"fixture's {f.time}")
            for key in ("state_before", "state_after"):
                for i, (c, b) in enumerate(zip(getattr(e, key), getattr(f, key))):
                    if not c.ball(d).overlaps(b):
                        raise FixtureMismatch(f"{src}: event {j}: {key}[{i}] recomputed as "
                                              f"{c.decimal(20)} is outside the fixture's {b}")
        if self.samples:
            rows = traj.sample([s.t for s in self.samples], d)
            for s, row in zip(self.samples, rows):
                for i, (c, b) in enumerate(zip(row, s.x)):
                    if not c.overlaps(b):
                        raise FixtureMismatch(f"{src}: the sample at t = {s.t}: x[{i}] recomputed as {c} is "
                                              f"outside the fixture's {b}")

    def state(self, t: Any):
        """x(t) as an exact vector (from the recomputed run); see :meth:`sample` for balls.

        Parameters
        ----------
        t : rational
            The time.
        """
        if self.exact is None:
            raise FormatError(f"{self.source}: x0 is not rational, so the run cannot be recomputed "
                              f"exactly; the fixture's samples are certified at their grid times "
                              f"(use .sample(ts) at grid times)")
        return self.exact.state(t)

    def sample(self, ts: Sequence[Any], digits: int = 17) -> list[list]:
        """Certified balls of x(t) for t in ts: from the fixture's samples at grid times, else from
        the exact recomputation (FormatError when neither is available).

        Parameters
        ----------
        ts : sequence of rationals
            The times.
        digits : int, optional
            Correct digits of each component (1..MAX_DIGITS; InvalidArgument otherwise, also
            when every time is a sample time).
        """
        digits = check_digits(digits)
        times = [to_fraction(t, "t") for t in ts]
        rows: list = [self._by_time.get(t) for t in times]
        missing = [i for i, r in enumerate(rows) if r is None]
        if len(missing) < len(times) and not self.digested and self.can_recompute:
            self.verify()  # no digest vouches for the samples: the recomputed run checks them
        if missing:
            if self.exact is None:
                raise FormatError(f"{self.source}: t = {times[missing[0]]} is not a sample time and x0 is not "
                                  f"known exactly (no exact recomputation)")
            for i, x in zip(missing, self.exact.sample([times[i] for i in missing], digits)):
                rows[i] = x
        return [list(r.x) if isinstance(r, Sample) else r for r in rows]

    def to_numpy(self, t: Any):
        """A float64 array of shape (len(t), n): the certified states at the times t (right limits),
        rounded to float; as :meth:`lcs_exact.Trajectory.to_numpy` (from the samples at grid times,
        else from the exact recomputation).

        Parameters
        ----------
        t : sequence of rationals or floats
            The times.

        >>> import lcs_exact as L
        >>> osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
        >>> fx = read_fixture(L.simulate(osc, [1, 0], 2).to_fixture(20, sample="1/2"))
        >>> fx.to_numpy([0, 0.5, 2]).round(9).tolist()   # cos t, -sin t; at rest on the stop after pi/2
        [[1.0, 0.0], [0.877582562, -0.479425539], [0.0, 0.0]]
        """
        import numpy as np  # numpy is not loaded by ``import lcs_exact``
        ts = t.tolist() if hasattr(t, "tolist") else t
        if isinstance(ts, (str, bytes)) or not hasattr(ts, "__iter__"):
            ts = [ts]
        rows = self.sample(list(ts), 17)
        return np.array([[float(b.mid()) for b in row] for row in rows], dtype=np.float64).reshape(len(rows), self.lcs.n)

    def __repr__(self):
        status = "certified" if self.certified else f"NOT certified ({len(self.assumptions)} assumptions)"
        exact = "exact evaluation available (x0 known exactly)" if self.can_recompute else "balls only (x0 not known exactly)"
        part = ", PARTIAL" if self.partial else ""
        name = f" {self.name!r}" if self.name else ""
        return (f"<FixtureTrajectory{name} on [0, {short_text(self.t_end)}]: {len(self.events)} events, "
                f"{len(self.samples)} samples, {status}{part}; {exact}>")


@dataclass(frozen=True)
class FixtureAccumulation:
    """An accumulation point read from a fixture (Remark 4.11): ``time`` and the limit ``state``
    as certified balls (``time_exact``: the closed form or None), ``events`` the cycle length of
    its law; :meth:`event_time` gives the k-th event it implies (not in ``events``), certified,
    when the fixture carries the law (``law``: start, cycle_length, ratio, offsets)."""

    time: arb
    time_exact: str | None
    state: tuple
    events: int | None
    law: dict | None = None
    implied: dict | None = None  # no law: {"times": balls, "first_event": i} (an impact map's contraction)

    def event_time(self, k: int) -> arb:
        """The k-th implied event time (k = 0, 1, ...): event j = k mod p of cycle m = k div p at
        start + T rho (1 - rho^m) / (1 - rho) + offsets[j] rho^(m+1), a certified ball.

        >>> import lcs_exact as L
        >>> ball = L.examples.bouncing_ball(g=10, e="1/2")   # impacts at 1, 2, 2.5, 2.75, ...
        >>> fx = read_fixture(L.simulate(ball, ball.embed([5, 0]), 4).to_fixture(20))
        >>> acc = fx.accumulations[0]
        >>> acc.event_time(0), acc.event_time(1), acc.time
        (2.75000000000000, 2.87500000000000, 3.00000000000000)
        """
        if isinstance(k, bool) or not isinstance(k, int) or k < 0:
            raise InvalidArgument(f"k must be an int >= 0, got {k!r}")
        if self.law is None and self.implied is not None:
            times = self.implied["times"]
            if k >= len(times):
                raise InvalidArgument(f"the fixture lists {len(times)} implied events (the last within float "
                                      f"resolution of the accumulation time); k = {k} is beyond them")
            return times[k]
        if self.law is None:
            raise InvalidArgument("this fixture's accumulation carries no law of its implied events")
        law = self.law
        m, j = divmod(k, len(law["offsets"]))
        rho = law["ratio"]
        bits = max(64, int(3.33 * law["digits"]) + 20)
        with workprec(bits):
            r = arb(rho)
            return law["start"] + law["cycle_length"] * (r * (1 - r ** m) / (1 - r)) + law["offsets"][j] * r ** (m + 1)

    def __repr__(self):
        t = ball_text(self.time) + (f" = {self.time_exact}" if self.time_exact and not self.time.is_exact() else "")
        return f"FixtureAccumulation(t={t}, state={_show_vec(self.state)}, cycle of {self.events} events)"


def _fixture_accumulation(a: dict, i: int, digits: int) -> FixtureAccumulation:
    w = f"accumulations[{i}]"
    law = a.get("law")
    if law is not None:
        law = {"start": number_ball(law["start"], where=f"{w}.law.start"),
               "cycle_length": number_ball(law["cycle_length"], where=f"{w}.law.cycle_length"),
               "ratio": to_fmpq(law["ratio"], f"{w}.law.ratio"),
               "offsets": tuple(number_ball(o, where=f"{w}.law.offsets") for o in law["offsets"]),
               "digits": digits, "first_event": law.get("first_event")}
    implied = a.get("implied")
    if implied is not None:
        implied = {"times": tuple(number_ball(x, where=f"{w}.implied.times") for x in implied["times"]),
                   "first_event": implied.get("first_event")}
    return FixtureAccumulation(number_ball(_key(a, "time", w), where=f"{w}.time"), number_exact(a["time"]),
                               _balls(_key(a, "state", w), f"{w}.state"), a.get("events"), law, implied)


def _source_block(d: Any, A: Any, source: str):
    """The fixture's exosystem as a :class:`~lcs_exact.sources.SourceBlock`, checked against A
    (the states' rows of A are S and nothing else enters them), or None."""
    if d is None:
        return None
    states = d["states"]
    n, m = A.nrows(), len(states)
    if len(set(states)) != m or any(not 0 <= i < n for i in states):
        raise FormatError(f"{source}: sources.states must be distinct indices below n = {n}")
    S = to_matrix(d["S"], "sources.S", (m, m))
    z0 = to_matrix([[v] for v in d["z0"]], "sources.z0", (m, 1))
    if any(A[i, j] != S[r, c] for r, i in enumerate(states) for c, j in enumerate(states)) or \
            any(A[i, j] != 0 for i in states for j in range(n) if j not in states):  # B is checked by LCS.sources
        raise FormatError(f"{source}: sources.S is not the block of system.A on the sources' states "
                          "(or another state enters them)")
    if len(d["expressions"]) != m:
        raise FormatError(f"{source}: sources.expressions has {len(d['expressions'])} entries, expected {m}")
    return SourceBlock(tuple(states), S, z0, tuple(d["expressions"]))


def _x0_recipe(provenance: Any, lcs: LCS, balls: tuple):
    """e^{A t} v for a provenance ``"x0": "expm_action(A, t, [v...])"`` (t and v rational literals,
    read by ``ast``, never evaluated), when it agrees with the fixture's x0 balls; else None."""
    text = provenance.get("x0") if isinstance(provenance, dict) else None
    if not isinstance(text, str) or not text.startswith("expm_action(A,") or len(text) > 10_000:
        return None
    try:
        call = ast.parse(text, mode="eval").body
        t, v = (ast.literal_eval(a) for a in call.args[1:3])
        x0 = expm_action(lcs.A, to_fmpq(t, "t"), [to_fmpq(c, "v") for c in v])
        if len(call.args) != 3 or len(x0) != lcs.n:
            return None
    except (SyntaxError, ValueError, TypeError, AttributeError, LCSError):
        return None
    with workprec(128):
        ok = all(c.ball(30).overlaps(b) for c, b in zip(x0, balls))
    return x0 if ok else None


def _scheduled(d: dict, first: LCS, source: str):
    """The fixture's schedule as a :class:`~lcs_exact.schedule.ScheduledLCS` (names and embedding
    of the system read before)."""
    phases = []
    for i, p in enumerate(d["phases"]):
        try:
            lcs = LCS(p["A"], p["B"], p["C"], p["D"], name=first.name, state_names=first.state_names,
                      constraint_names=first.constraint_names, embedding=first.embedding,
                      restitution=p.get("restitution"), roles=first.roles)
        except LCSError as e:
            raise FormatError(f"{source}: schedule.phases[{i}]: {e}") from None
        phases.append((p["duration"], lcs) if p["reset"] is None else (p["duration"], lcs, p["reset"]))
    try:
        return scheduled(phases, d["period"], name=first.name)
    except LCSError as e:
        raise FormatError(f"{source}: schedule: {e}") from None


def _fmt_modes(m) -> str:
    if m is None:
        return "none"
    if isinstance(m, tuple):
        return "(" + ", ".join(_fmt_modes(x) for x in m) + ")"
    return format_mode(m)


def read_fixture(path_or_dict: Any) -> FixtureTrajectory:
    """Read a fixture (a path to its JSON file, or the dict) back as a :class:`FixtureTrajectory`.

    Validates it (the shipped JSON Schema when ``jsonschema`` is installed, and the reader's own
    shape checks); raises :class:`~lcs_exact.errors.FormatError` naming what is wrong.  A fixture
    whose content does not match its digest is refused (:class:`~lcs_exact.errors.FixtureMismatch`);
    one without a digest (written before digests existed, or with them removed) is recomputed from
    its system when x0 is rational and refused when an event or sample disagrees.

    Parameters
    ----------
    path_or_dict : str, path or dict
        The fixture's JSON file, or its dict.

    Examples
    --------
    >>> import lcs_exact as L
    >>> osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    >>> fx = read_fixture(L.simulate(osc, [1, 0], 2).to_fixture(20, sample="1/2"))
    >>> fx.events[0].time_exact, fx.can_recompute, fx.samples[1].t
    ('pi/2', True, Fraction(1, 2))
    >>> x = fx.state("3/4")                 # between samples: recomputed exactly (x2 = -sin t)
    >>> x[1].ball(25).overlaps(-arb(fmpq(3, 4)).sin()), x[1].decimal(12).split()[0]
    (True, '-0.681638760023')
    """
    if isinstance(path_or_dict, FixtureTrajectory):
        return path_or_dict
    if isinstance(path_or_dict, dict):
        return _checked(FixtureTrajectory(path_or_dict))
    if isinstance(path_or_dict, (str, Path)):
        p = Path(path_or_dict)
        try:
            data = json.loads(p.read_text(encoding="utf-8"))
        except json.JSONDecodeError as e:
            raise FormatError(f"{p}: not JSON ({e})") from None
        except RecursionError:
            raise FormatError(f"{p}: JSON nested too deeply") from None
        return _checked(FixtureTrajectory(data, str(p)))
    raise FormatError(f"read_fixture takes a path or a dict, got {type(path_or_dict).__name__}")


def _checked(fx: FixtureTrajectory) -> FixtureTrajectory:
    """No digest vouches for the content: check it against the recomputed run (x0 rational)."""
    return fx.verify() if not fx.digested and fx.can_recompute else fx
