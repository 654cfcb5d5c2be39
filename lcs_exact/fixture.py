"""The fixture format ``lcs-exact/trajectory/1``: ground truth for numerical solvers (docs/fixtures.md).

A fixture is a JSON object: the system (rational strings), ``x0``, ``t_end``, ``digits``, the
events (Def. 4.3: time, modes before / re-initialization chain (4.9) / after, states before and
after, multiplicity), the accumulation points crossed, the final state and, when asked, a grid
of ``samples``.  ``docs/fixtures.md`` describes every field; the JSON Schema ships in the package
(``lcs_exact/schemas/trajectory-1.schema.json``, :func:`schema`, :func:`validate_fixture`).

This module is the whole format: writing (:func:`fixture_dict`, the sample grid, the digests),
validating (the schema and what a schema cannot say) and reading back (:func:`read_fixture`,
:class:`FixtureTrajectory`: events, states and samples as certified ``flint.arb`` balls).  Its
numbers ``{"value": decimal, "error": bound, "exact": closed form | null}`` (|value - true| <=
error) are written and read by :mod:`lcs_exact.fixnumbers`; the names are importable from here
too (:func:`number_ball` turns a number back into a certified ball).

Layering.  The writer reads a trajectory through its public interface only (duck typing), and
:meth:`lcs_exact.Trajectory.to_fixture` writes through this module, so the format sits below
the engine and never imports it.  A fixture read back repeats its run exactly when x0 and t_end
are rational (:attr:`FixtureTrajectory.exact`, Algorithm 7.1): the engine that does it is handed
down by the module above both (:mod:`lcs_exact.compare` calls :func:`set_engine` with
:func:`lcs_exact.simulate` when the package is imported).
"""
from __future__ import annotations

import contextvars
import hashlib
import json
import re
from dataclasses import dataclass
from fractions import Fraction
from importlib.resources import files
from pathlib import Path
from typing import Any, Callable, Sequence

from flint import arb, fmpq

from .balls import MAX_DIGITS
from .errors import FixtureMismatch, FormatError, IllPosed, InvalidArgument, LCSError
from .fixnumbers import (MAX_SAMPLES, ball_number, ball_text, number_ball, number_exact, number_rational,
                         rational_number, sample_grid, short_text, to_fraction)
from .modes import format_mode
from .rational import to_fmpq
from .system import LCS

__all__ = ["content_digest", "check_digest", "SCHEMA", "MAX_SAMPLES", "fixture_dict", "build_fixture", "sample_grid",
           "schema", "validate_fixture", "read_fixture", "FixtureTrajectory", "FixtureEvent", "Sample", "set_engine",
           "number_ball", "number_exact", "number_rational", "ball_number", "rational_number"]

SCHEMA = "lcs-exact/trajectory/1"
_SCHEMA_FILE = "trajectory-1.schema.json"


# ---------------------------------------------------------------------------------------------
# writing: the values of a trajectory as fixture numbers (lcs_exact.fixnumbers)
# ---------------------------------------------------------------------------------------------

#: whether the writer derives closed forms (``fixture_dict(..., closed_forms=False)``: only
#: those already known, for a quick write, e.g. of the partial run of an interrupted command)
_DERIVE: contextvars.ContextVar = contextvars.ContextVar("lcs_exact_fixture_derive", default=True)


def _real_number(r: Any, digits: int, cf: Any = None) -> dict:
    """A fixture number for an exact real: exact rationals as such, others from a certified
    ball (``r.ball``) rounded to ``digits`` digits with the bound; ``exact`` is the closed form."""
    if cf is None:
        cf = r.closed_form if _DERIVE.get() else getattr(r, "known_closed_form", None)
    if cf is not None and getattr(cf, "is_Rational", False):
        return rational_number(fmpq(int(cf.p), int(cf.q)), digits)
    out = ball_number(r.ball(min(digits + 3, MAX_DIGITS)), digits)  # the error bound covers the rest
    out["exact"] = None if cf is None else str(cf)
    return out


def _vector(v: Any, digits: int) -> list:
    # the vector's own closed form may be derived once for all components (fixtures are written once)
    closed = getattr(v, "closed_form", None)
    cf = closed(_DERIVE.get()) if callable(closed) else None
    return [_real_number(c, digits, None if cf is None else cf[i]) for i, c in enumerate(v)]


def _matrix(m: Any) -> list:
    return [[str(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())]


def _mode(m: Any) -> list | None:
    return None if m is None else sorted(int(i) for i in m)


# ---------------------------------------------------------------------------------------------
# the writer
# ---------------------------------------------------------------------------------------------

def _computed_until(traj: Any):
    """The last time the trajectory is known at: t_end, or (partial) the last event's time."""
    if not traj.partial:
        return traj.t_end
    t_last = getattr(traj, "t_last", None)
    if t_last is not None:
        return t_last
    return traj.events[-1].time if traj.events else None


def fixture_dict(traj: Any, digits: int | None = None, sample: Any = None, closed_forms: bool = True,
                 provenance: dict | None = None) -> dict:
    """See :func:`build_fixture`; ``closed_forms=False`` writes only the closed forms already
    known (no derivation: a quick write of a long run)."""
    token = _DERIVE.set(bool(closed_forms))
    try:
        return build_fixture(traj, digits, sample, provenance)
    finally:
        _DERIVE.reset(token)


def build_fixture(traj: Any, digits: int | None = None, sample: Any = None, provenance: dict | None = None) -> dict:
    """The fixture (format ``lcs-exact/trajectory/1``) of a trajectory, as a JSON-ready dict.

    Parameters
    ----------
    traj : Trajectory
        Read through its public interface only (``lcs``, ``x0``, ``t_end``, ``digits``,
        ``events``, ``certified``, ``assumptions``, ``partial``, ``stop_reason``,
        ``accumulations``, ``state``, ``sample``).
    digits : int, optional
        Significant digits of every number (default: the run's ``traj.digits``).
    sample : rational, optional
        A step h: adds ``samples``, the states at t = 0, h, 2h, ... <= t_end (of the computed
        part for a partial run), each component certified to ``digits`` digits.
    provenance : dict, optional
        Where the run comes from (free-form JSON: a builder and its parameters, a version, a
        reference), written as ``provenance`` and covered by the ``digest``; the zoo
        (:mod:`lcs_exact.zoo`) writes ``suite``, ``problem``, ``builder``, ``parameters``,
        ``x0``, ``t_end`` and ``lcs_exact_version``.

    Examples
    --------
    >>> import lcs_exact as L
    >>> tr = L.simulate(L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]), [1, 0], 2)
    >>> fx = fixture_dict(tr, 10, sample="1/2")
    >>> fx["events"][0]["time"]["exact"], len(fx["samples"]), fx["samples"][1]["x"][0]["value"]
    ('pi/2', 5, '0.8775825619')
    """
    d = traj.digits if digits is None else digits
    if isinstance(d, bool) or not isinstance(d, int) or not 1 <= d <= MAX_DIGITS:
        raise FormatError(f"digits must be a positive integer <= {MAX_DIGITS} (balls.MAX_DIGITS), got {d!r}")
    lcs = traj.lcs
    until = _computed_until(traj)
    final = traj.state(until) if until is not None else traj.x0
    out = {
        "schema": SCHEMA,
        "system": {"A": _matrix(lcs.A), "B": _matrix(lcs.B), "C": _matrix(lcs.C),
                   "D": _matrix(lcs.D), "name": lcs.name,
                   # Newton's impact law is part of the system (docs/extensions.md): the same run needs it
                   **({"restitution": [str(e) for e in lcs.restitution]} if getattr(lcs, "restitution", None) else {}),
                   "state_names": list(getattr(lcs, "state_names", ())),
                   "constraint_names": list(getattr(lcs, "constraint_names", ()))},
        "x0": _vector(traj.x0, d),
        "t_end": _real_number(traj.t_end, d),
        "digits": d,
        "events": [{"time": _real_number(e.time, d), "mode_before": _mode(e.mode_before),
                    "modes": [_mode(m) for m in e.modes], "mode_after": _mode(e.mode_after),
                    "state_before": _vector(e.state_before, d), "state_after": _vector(e.state_after, d),
                    "multiplicity": int(e.multiplicity), "triggers": [str(s) for s in e.triggers]}
                   for e in traj.events],
        "accumulations": [_accumulation(a, d) for a in getattr(traj, "accumulations", ())],
        "final_time": _real_number(until, d) if until is not None else rational_number(0, d),
        "final_state": _vector(final, d),
        "certified": bool(traj.certified),
        "assumptions": [str(a) for a in traj.assumptions],
        "partial": bool(traj.partial),
        "stop_reason": traj.stop_reason,
    }
    if provenance is not None:
        out["provenance"] = _provenance(provenance)
    if sample is not None:
        grid = sample_grid(until if until is not None else 0, sample)
        step = to_fmpq(sample, "the sample step")
        out["sample_step"] = str(step)
        rows = traj.sample(grid, d) if grid else []
        out["samples"] = [{"t": rational_number(t, d), "x": [ball_number(b, d) for b in row]}
                          for t, row in zip(grid, rows)]
    out["digest"] = content_digest(out)
    if sample is not None:
        out["samples_digest"] = content_digest(out, samples=True)
    return out


def _provenance(p: Any) -> dict:
    """A copy of the provenance as plain JSON (an object with string keys), or InvalidArgument."""
    if not isinstance(p, dict) or not all(isinstance(k, str) for k in p):
        raise InvalidArgument(f"provenance must be a dict with string keys, got {type(p).__name__}")
    try:
        return json.loads(json.dumps(p, allow_nan=False))
    except (TypeError, ValueError) as e:  # not JSON: a set, an object, a NaN
        raise InvalidArgument(f"provenance must be plain JSON (strings, numbers, lists, dicts): {e}") from None


_SAMPLE_KEYS = ("samples", "sample_step")
_DIGEST_KEYS = ("digest", "samples_digest")


def content_digest(d: dict, samples: bool = False) -> str:
    """``sha256:...`` of a fixture's content in canonical JSON: everything but the samples
    (``samples=False``, the ``digest``) or the samples and their step (the ``samples_digest``).
    A fixture edited after it was written (an event, a state, a sample changed by hand) no longer
    matches; the samples may be left out as a whole (with their digest), the rest then still
    recomputes exactly.

    >>> content_digest({"schema": "lcs-exact/trajectory/1", "digits": 5})[:14]
    'sha256:b865713'
    """
    if samples:
        body = {k: d.get(k) for k in _SAMPLE_KEYS}
    else:
        body = {k: v for k, v in d.items() if k not in _DIGEST_KEYS + _SAMPLE_KEYS}
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=True)
    return "sha256:" + hashlib.sha256(text.encode("ascii")).hexdigest()


def check_digest(d: dict, source: str = "fixture") -> None:
    """Raise :class:`~lcs_exact.errors.FixtureMismatch` when the fixture carries a digest that its
    content does not match, or samples without the digest written with them (fixtures written
    before digests existed carry none and are read as they are)."""
    if "digest" not in d:
        return
    bad = None
    if content_digest(d) != d["digest"]:
        bad = "its events, states or system"
    elif "samples" in d and d.get("samples_digest") != content_digest(d, samples=True):
        bad = "its samples"
    if bad is not None:
        raise FixtureMismatch(f"{source}: {bad} do not match the digest written with them: the fixture was changed "
                              "after it was written (an edited sample or event is not ground truth)")


def _accumulation(a: Any, d: int) -> dict:
    events = getattr(a, "events", None)
    count = events if isinstance(events, int) else (len(events) if events is not None else None)
    return {"time": _real_number(a.time, d), "state": _vector(a.state, d), "events": count}


# ---------------------------------------------------------------------------------------------
# the schema and validation
# ---------------------------------------------------------------------------------------------

def schema() -> dict:
    """The JSON Schema of ``lcs-exact/trajectory/1`` shipped in the package.

    >>> schema()["properties"]["schema"]["const"]
    'lcs-exact/trajectory/1'
    """
    return json.loads(files("lcs_exact").joinpath("schemas", _SCHEMA_FILE).read_text(encoding="utf-8"))


def validate_fixture(d: Any) -> None:
    """Raise :class:`~lcs_exact.errors.FormatError` unless ``d`` is a valid fixture.

    Checks the shipped JSON Schema (needs ``jsonschema``: ``pip install lcs_exact[fixtures]``)
    and what a schema cannot say: shapes agree with n and k, mode indices are below k, every
    value and error is a decimal that parses, sample times increase.

    >>> validate_fixture({"schema": "lcs-exact/trajectory/1"})
    Traceback (most recent call last):
    ...
    lcs_exact.errors.FormatError: fixture: 'system' is a required property
    """
    try:
        import jsonschema
    except ImportError:  # pragma: no cover - jsonschema is in the test and fixtures extras
        raise ModuleNotFoundError("validating a fixture needs jsonschema: pip install 'lcs_exact[fixtures]'") from None
    sch = schema()
    validator = jsonschema.Draft202012Validator(sch)
    samples = d.get("samples") if isinstance(d, dict) else None
    if isinstance(samples, list) and len(samples) > 2:
        # jsonschema costs ~1 ms per sample: it checks the document with two samples, and every
        # sample is checked against the same sample schema by _sample_ok (patterns read from the
        # schema); on any doubt the full validation below names the problem
        head = dict(d, samples=samples[:2])
        ok = _sample_checker(sch)
        if not any(True for _ in validator.iter_errors(head)) and all(ok(x) for x in samples):
            _check_consistency(d)
            return
    err = jsonschema.exceptions.best_match(validator.iter_errors(d))
    if err is not None:
        where = "/".join(str(p) for p in err.absolute_path)
        raise FormatError(f"fixture{' at ' + where if where else ''}: {err.message}")
    _check_consistency(d)


def _sample_checker(sch: dict):
    """A fast test that a sample satisfies ``$defs/sample`` of the schema, exactly that definition:
    an object with exactly t (a number) and x (a nonempty list of numbers)."""
    defs = sch["$defs"]
    dec, bound = re.compile(defs["decimal"]["pattern"]), re.compile(defs["bound"]["pattern"])

    def num(v):
        return (type(v) is dict and v.keys() == {"value", "error", "exact"}
                and type(v["value"]) is str and dec.search(v["value"]) is not None
                and type(v["error"]) is str and bound.search(v["error"]) is not None
                and (v["exact"] is None or type(v["exact"]) is str))

    def sample(s):
        return (type(s) is dict and s.keys() == {"t", "x"} and num(s["t"]) and type(s["x"]) is list
                and len(s["x"]) >= 1 and all(num(c) for c in s["x"]))

    return sample


def _check_consistency(d: dict) -> None:
    sysd = d["system"]
    n, k = len(sysd["A"]), len(sysd["C"])
    shapes = {"A": (n, n), "B": (n, k), "C": (k, n), "D": (k, k)}
    for key, (r, c) in shapes.items():
        m = sysd[key]
        if len(m) != r or any(len(row) != c for row in m):
            raise FormatError(f"fixture: system.{key} must be {r}x{c} (n = {n}, k = {k})")

    def vec(v, where):
        if len(v) != n:
            raise FormatError(f"fixture: {where} has length {len(v)}, expected n = {n}")
        for i, num in enumerate(v):
            number_ball(num, where=f"{where}[{i}]")

    def mode(m, where):
        if m is not None and any(i >= k for i in m):
            raise FormatError(f"fixture: {where} = {m} has an index >= k = {k}")

    vec(d["x0"], "x0")
    vec(d["final_state"], "final_state")
    number_ball(d["t_end"], where="t_end")
    for j, e in enumerate(d["events"]):
        w = f"events[{j}]"
        number_ball(e["time"], where=f"{w}.time")
        vec(e["state_before"], f"{w}.state_before")
        vec(e["state_after"], f"{w}.state_after")
        for key in ("mode_before", "mode_after"):
            mode(e[key], f"{w}.{key}")
        for i, m in enumerate(e["modes"]):
            mode(m, f"{w}.modes[{i}]")
    last = None
    for j, s in enumerate(d.get("samples", ())):
        t = number_ball(s["t"], where=f"samples[{j}].t")
        vec(s["x"], f"samples[{j}].x")
        if last is not None and not t > last:
            raise FormatError(f"fixture: samples[{j}].t does not exceed samples[{j - 1}].t")
        last = t


# ---------------------------------------------------------------------------------------------
# reading
# ---------------------------------------------------------------------------------------------

#: the exact engine that repeats a fixture's run (Algorithm 7.1): ``lcs_exact.simulate``, handed
#: down by the module above the format and the engine (see the module docstring)
_ENGINE: Callable | None = None


def set_engine(simulate: Callable) -> None:
    """Give the reader the exact engine (:func:`lcs_exact.simulate`, or anything with its
    signature) with which :attr:`FixtureTrajectory.exact` repeats a run.  :mod:`lcs_exact.compare`
    does it when the package is imported; the format cannot import the engine, which writes
    fixtures through it."""
    global _ENGINE
    _ENGINE = simulate


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
    ``x0_rational`` holds x0 as Fractions when the fixture says it is rational; then ``exact``
    is the trajectory recomputed exactly (on first use, checked against the fixture's events and
    samples).  ``digested``: the fixture carries its content digest (checked on reading).
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
        self.lcs = LCS(_key(sysd, "A", "system"), _key(sysd, "B", "system"), _key(sysd, "C", "system"),
                       _key(sysd, "D", "system"), name=sysd.get("name"), restitution=sysd.get("restitution"),
                       state_names=sysd.get("state_names") or None,
                       constraint_names=sysd.get("constraint_names") or None)
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
        self.accumulations = tuple(
            (number_ball(a["time"], where=f"accumulations[{i}].time"), _balls(a["state"], f"accumulations[{i}].state"))
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
    @property
    def can_recompute(self) -> bool:
        """True when x0 and t_end are exact rationals: the run can be repeated exactly."""
        return self.x0_rational is not None and self.t_end_rational is not None

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
        simulate = _ENGINE
        if simulate is None:  # pragma: no cover - lcs_exact/__init__ imports compare, which sets it
            raise LCSError(f"{self.source}: no engine to recompute the run: import lcs_exact (its compare "
                           "module hands lcs_exact.simulate to the fixture reader)")
        x0 = [fmpq(q.numerator, q.denominator) for q in self.x0_rational]
        T = fmpq(self.t_end_rational.numerator, self.t_end_rational.denominator)
        opts = {"allow_unresolved": not self.certified, "max_events": max(1000, len(self.events))}
        if self.partial:
            opts["max_events"] = len(self.events)
        try:
            traj = simulate(self.lcs, x0, T, digits=self.digits, **opts)
        except IllPosed:  # a non-unique problem (Theorem 6.3 fails): the fixture is one of its branches
            return self._matching_branch(simulate(self.lcs, x0, T, digits=self.digits, branches="all", **opts))
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
        """x(t) as an exact vector (from the recomputed run); see :meth:`sample` for balls."""
        if self.exact is None:
            raise FormatError(f"{self.source}: x0 is not rational, so the run cannot be recomputed "
                              f"exactly; the fixture's samples are certified at their grid times "
                              f"(use .sample(ts) at grid times)")
        return self.exact.state(t)

    def sample(self, ts: Sequence[Any], digits: int = 17) -> list[list]:
        """Certified balls of x(t) for t in ts: from the fixture's samples at grid times, else from
        the exact recomputation (FormatError when neither is available)."""
        times = [to_fraction(t, "t") for t in ts]
        if all(t in self._by_time for t in times):
            if not self.digested and self.can_recompute:
                self.verify()  # no digest vouches for the samples: the recomputed run checks them
            return [list(self._by_time[t].x) for t in times]
        if self.exact is None:
            missing = next(t for t in times if t not in self._by_time)
            raise FormatError(f"{self.source}: t = {missing} is not a sample time and x0 is not rational "
                              f"(no exact recomputation)")
        return self.exact.sample(times, digits)

    def __repr__(self):
        status = "certified" if self.certified else f"NOT certified ({len(self.assumptions)} assumptions)"
        exact = "exact evaluation available (x0 rational)" if self.can_recompute else "balls only (x0 not rational)"
        part = ", PARTIAL" if self.partial else ""
        name = f" {self.name!r}" if self.name else ""
        return (f"<FixtureTrajectory{name} on [0, {short_text(self.t_end)}]: {len(self.events)} events, "
                f"{len(self.samples)} samples, {status}{part}; {exact}>")


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
