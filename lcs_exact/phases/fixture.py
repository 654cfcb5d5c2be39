"""The fixture format ``lcs-exact/trajectory/1``: ground truth for numerical solvers (docs/fixtures.md).

A fixture is a JSON object: the system (rational strings), ``x0``, ``t_end``, ``digits``, the
events (Def. 4.3: time, modes before / re-initialization chain (4.9) / after, states before and
after, multiplicity), the accumulation points crossed (with the law of the events they imply),
the exosystem inside the state (``sources``), the final state and, when asked, a grid of
``samples``.  ``docs/fixtures.md`` describes every field; the JSON Schema ships in the package
(``lcs_exact/schemas/trajectory-1.schema.json``, :func:`schema`, :func:`validate_fixture`).

This module writes the format (:func:`fixture_dict`, the sample grid, the digests) and validates
it (the schema and what a schema cannot say); :mod:`lcs_exact.fixturereader` reads it back.  Its
numbers ``{"value": decimal, "error": bound, "exact": closed form | null}`` (|value - true| <=
error) are written and read by :mod:`lcs_exact.fixnumbers`; the names are importable from here
too (:func:`number_ball` turns a number back into a certified ball).

Layering.  The writer reads a trajectory through its public interface only (duck typing), and
:meth:`lcs_exact.Trajectory.to_fixture` writes through this module, so the format sits below
the engine and never imports it; the reader, which repeats a run exactly, sits above the engine.
"""
from __future__ import annotations

import contextvars
import hashlib
import json
import re
from importlib.resources import files
from typing import Any

from flint import arb, fmpq

from ..numbers import MAX_DIGITS, check_digits, digits_to_bits, workprec
from ..errors import FixtureMismatch, FormatError, InvalidArgument
from .fixnumbers import (MAX_SAMPLES, ball_number, number_ball, number_exact, number_rational,
                         rational_number, sample_grid)
from ..algebra import to_fmpq

__all__ = ["content_digest", "check_digest", "SCHEMA", "MAX_SAMPLES", "fixture_dict", "build_fixture", "sample_grid",
           "schema", "validate_fixture", "number_ball", "number_exact", "number_rational", "ball_number",
           "rational_number"]

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
    d = traj.digits if digits is None else check_digits(digits)
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
    sched = getattr(lcs, "schedule", None)
    if sched is not None:  # data that switch at scheduled times (lcs_exact.schedule): each phase's system
        out["schedule"] = {
            "period": None if sched.period is None else str(sched.period),
            "phases": [{"duration": None if p.duration is None else str(p.duration),
                        "A": _matrix(p.lcs.A), "B": _matrix(p.lcs.B), "C": _matrix(p.lcs.C), "D": _matrix(p.lcs.D),
                        "reset": None if p.reset is None else _matrix(p.reset),
                        **({"restitution": [str(e) for e in p.lcs.restitution]} if p.lcs.restitution else {})}
                       for p in sched.phases]}
    sb = getattr(traj, "sources", None)
    if sb is not None:  # the exosystem: a solver treats these states as known inputs
        out["sources"] = {"states": list(sb.states), "S": _matrix(sb.S), "z0": [str(sb.z0[i, 0]) for i in range(sb.z0.nrows())],
                          "expressions": list(sb.expressions)}
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
    before digests existed carry none and are read as they are).

    Parameters
    ----------
    d : dict
        The fixture.
    source : str, optional
        Its name in the message (a path).
    """
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
    out = {"time": _real_number(a.time, d), "state": _vector(a.state, d), "events": count}
    if getattr(a, "cycle", None) is not None and a.ratio is None:  # no law: the implied events themselves
        out["implied"] = {"times": _implied_times(a, d), "first_event": int(a.first_event)}
    elif getattr(a, "cycle", None) is not None:  # the law of the implied events (Accumulation.event_time)
        out["law"] = {"start": _real_number(a.start, d), "cycle_length": _real_number(a.cycle_length, d),
                      "ratio": str(a.ratio), "offsets": [_real_number(o, d) for o in a.offsets],
                      "first_event": int(a.first_event)}
    return out


def _implied_times(a: Any, d: int) -> list:
    """The implied events of a law-less accumulation, up to the first within 2^-52 (relative) of
    T*: a float time grid cannot tell the later ones apart (at most MAX_IMPLIED)."""
    out = []
    bits = digits_to_bits(d) + 32
    with workprec(bits):
        t_star = a.time.ball(d + 2)
        for k in range(MAX_IMPLIED):
            t = a.event_time_ball(k, bits)  # balls of the window's iteration: no closed form exists
            out.append({**ball_number(t, d), "exact": None})
            if t_star - t <= abs(t_star) * arb(2) ** -52:
                break
    return out


#: the most implied events a fixture lists for a law-less accumulation
MAX_IMPLIED = 20_000


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

    Parameters
    ----------
    d : dict
        The fixture (the JSON document, parsed).

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
