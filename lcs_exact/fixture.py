"""The fixture format ``lcs-exact/trajectory/1``: ground truth for numerical solvers (docs/fixtures.md).

A fixture is a JSON object: the system (rational strings), ``x0``, ``t_end``, ``digits``, the
events (Def. 4.3: time, modes before / re-initialization chain (4.9) / after, states before and
after, multiplicity), the accumulation points crossed, the final state and, when asked, a grid
of ``samples``.  ``docs/fixtures.md`` describes every field; the JSON Schema ships in the package
(``lcs_exact/schemas/trajectory-1.schema.json``, :func:`schema`, :func:`validate_fixture`).

Every real number is an object ``{"value": decimal, "error": bound, "exact": closed form | null}``
with the invariant |value - true| <= error; ``"error": "0"`` means the decimal is the exact value.
Decimals are exact rationals (read with ``fractions.Fraction``), so a reader loses nothing:
:func:`number_ball` turns a number back into a certified ``flint.arb`` ball.

This module sits just above :mod:`lcs_exact.errors` and :mod:`lcs_exact.rational`: it reads a
trajectory only through its public interface (duck typing), so it never imports the engine.
"""
from __future__ import annotations

import contextvars
import hashlib
import json
import re
from fractions import Fraction
from typing import Any

from flint import arb, ctx, fmpq, fmpz

from .balls import MAX_DIGITS
from .errors import FixtureMismatch, FormatError, InvalidArgument, LCSError
from .rational import to_fmpq

__all__ = ["content_digest", "check_digest", "SCHEMA", "MAX_SAMPLES", "fixture_dict", "sample_grid", "schema", "validate_fixture",
           "number_ball", "number_exact", "number_rational", "ball_number", "rational_number"]

SCHEMA = "lcs-exact/trajectory/1"
MAX_SAMPLES = 1_000_000  # a grid beyond this is a typo in the step, not a fixture anyone reads
_SCHEMA_FILE = "trajectory-1.schema.json"


# ---------------------------------------------------------------------------------------------
# numbers: writing
# ---------------------------------------------------------------------------------------------

def _text(m: int) -> str:
    """str(m) without Python's 4300-digit limit on int <-> str conversion (fixtures may hold more)."""
    return str(m) if m.bit_length() < 14000 else str(fmpz(m))  # 14000 bits < 4300 digits


def _ndigits(m: int) -> int:
    return len(_text(abs(m)))


def _format_decimal(m: int, e: int) -> str:
    """The decimal m * 10^e: positional for moderate exponents, else ``d.ddde±k``."""
    if m == 0:
        return "0"
    sign, digits = ("-" if m < 0 else ""), _text(abs(m))
    stripped = digits.rstrip("0")  # 1.50 -> 1.5, 10e20 -> 1e21 (same value; zeros come back below)
    digits, e = stripped, e + len(digits) - len(stripped)
    point = len(digits) + e  # position of the decimal point from the left of ``digits``
    if -5 < point <= 0:
        return f"{sign}0.{'0' * -point}{digits}"
    if 0 < point <= max(len(digits), 21):
        if e >= 0:
            return sign + digits + "0" * e
        return f"{sign}{digits[:point]}.{digits[point:]}"
    mant = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    return f"{sign}{mant}e{point - 1}"


def _ceil_3(c: int, k: int) -> tuple[int, int]:
    """The smallest c' * 10^k' >= c * 10^k whose mantissa c' has at most 3 digits (c > 0): a
    bound rounded up, never down."""
    drop = _ndigits(c) - 3
    if drop > 0:
        c, k = -(-c // 10 ** drop), k + drop
        if c == 1000:
            c, k = 100, k + 1
    return c, k


def _bound_text(err: Fraction) -> str:
    """A decimal with 3 significant digits that is >= err (rounded up: it is a bound)."""
    if err <= 0:
        return "0"
    num, den = err.numerator, err.denominator
    k = _ndigits(num) - _ndigits(den) - 3  # err / 10^k is within a factor 10 of [100, 1000)
    c = -(-num * 10 ** -k // den) if k <= 0 else -(-num // (den * 10 ** k))  # ceil(err / 10^k)
    return _format_decimal(*_ceil_3(c, k))


def _bound_text_int(r: int, e: int) -> str:
    """_bound_text of the error r * 10^e (r >= 0 an integer): integer arithmetic only."""
    return "0" if r <= 0 else _format_decimal(*_ceil_3(r, e))


def rational_number(q: Any, digits: int) -> dict:
    """A fixture number for an exact rational: the decimal when it terminates within ``digits``
    significant digits (error 0), else rounded (half to even) to ``digits`` digits with a bound
    on the rounding; ``exact`` is ``"p/q"``.

    >>> rational_number("1/4", 5)
    {'value': '0.25', 'error': '0', 'exact': '1/4'}
    >>> rational_number("1/3", 5)
    {'value': '0.33333', 'error': '3.34e-6', 'exact': '1/3'}
    """
    f = to_fmpq(q, "number")
    p, d = int(f.p), int(f.q)
    exact = str(f)
    if p == 0:
        return {"value": "0", "error": "0", "exact": "0"}
    a = abs(p)
    # the exponent e with 10^(digits-1) <= |q| / 10^e < 10^digits, in integers: N / M = |q| / 10^e
    e = _ndigits(a) - _ndigits(d) - digits
    while True:
        N, M = (a * 10 ** -e, d) if e <= 0 else (a, d * 10 ** e)
        m, rem = divmod(N, M)
        if m >= 10 ** digits:
            e += 1
        elif m < 10 ** (digits - 1):
            e -= 1
        else:
            break
    if 2 * rem > M or (2 * rem == M and m % 2 == 1):  # half to even
        m, rem = m + 1, rem - M
    err = Fraction(abs(rem), M) * (Fraction(10) ** e)  # |q| - m 10^e, exactly
    return {"value": _format_decimal(m if p > 0 else -m, e), "error": _bound_text(err), "exact": exact}


def ball_number(b: arb, digits: int) -> dict:
    """A fixture number for a certified ball: the midpoint to ``digits`` significant digits and a
    bound on |value - true| that covers both the ball's radius and the rounding of the midpoint.
    An exact ball (radius 0) is an exact dyadic rational and says so in ``exact``.

    >>> ball_number(arb(fmpq(3, 8)), 10)
    {'value': '0.375', 'error': '0', 'exact': '3/8'}
    >>> ball_number(arb(2).sqrt(), 5)["value"]
    '1.4142'
    """
    if not b.is_finite():
        raise LCSError(f"cannot write the ball {b} as a fixture number: it is not finite")
    if b.is_exact():
        return rational_number(b.fmpq(), digits)
    m, r, e = (int(v) for v in b.mid_rad_10exp(digits + 5))  # b is inside [m +/- r] 10^e
    drop = max(0, _ndigits(m) - digits)
    value = m
    if drop:  # round the midpoint to ``digits`` significant digits; the rounding joins the bound
        scale = 10 ** drop
        value = (abs(m) + scale // 2) // scale * (1 if m >= 0 else -1)
        r += abs(m - value * scale)
    return {"value": _format_decimal(value, e + drop), "error": _bound_text_int(r, e), "exact": None}


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
# the sample grid
# ---------------------------------------------------------------------------------------------

def _as_fraction(r: Any) -> Fraction | None:
    """An exact real as a Fraction when its closed form is rational, else None."""
    cf = r.closed_form
    if cf is not None and getattr(cf, "is_Rational", False):
        return Fraction(int(cf.p), int(cf.q))
    return None


def sample_grid(t_end: Any, h: Any) -> list[Fraction]:
    """The grid 0, h, 2h, ... <= t_end (h rational > 0; t_end rational or an exact real).

    ``h`` accepts what :func:`lcs_exact.rational.to_fmpq` accepts (a float by its shortest
    repr: 0.1 is 1/10).  The count is decided exactly (certified balls when t_end is irrational).

    >>> [str(t) for t in sample_grid(1, "1/4")]
    ['0', '1/4', '1/2', '3/4', '1']
    """
    hq = to_fmpq(h, "the sample step")
    step = Fraction(int(hq.p), int(hq.q))
    if step <= 0:
        raise FormatError(f"the sample step must be > 0, got {step}")
    if hasattr(t_end, "ball"):
        T = _as_fraction(t_end)
    else:
        tq = to_fmpq(t_end, "t_end")
        T = Fraction(int(tq.p), int(tq.q))
    if T is not None:
        count = int(T // step)
    else:  # irrational t_end: floor(t_end / h) from a ball that excludes every integer
        count = None
        for digits in (30, 60, 120, 240):
            with ctx.workprec(4 * digits + 64):
                ratio = t_end.ball(digits) / arb(fmpq(step.numerator, step.denominator))
                lo, hi = ratio.lower().floor(), ratio.upper().floor()
            if lo == hi:
                count = int(lo.unique_fmpz())
                break
        if count is None:
            raise FormatError(f"cannot decide how many grid points of step {step} fit before t_end")
    if count < 0:
        return []
    if count + 1 > MAX_SAMPLES:
        raise FormatError(f"the sample step {step} gives {count + 1} grid points on [0, t_end]; "
                          f"at most {MAX_SAMPLES} are written (choose a larger step)")
    return [k * step for k in range(count + 1)]


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
    from importlib.resources import files
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
# numbers: reading
# ---------------------------------------------------------------------------------------------

_MAX_EXPONENT = 100_000  # |exponent| of a decimal read exactly (10^(10^9) would not fit in memory)


_DECIMAL = re.compile(r"([+-]?)([0-9]*)(?:\.([0-9]*))?(?:[eE]([+-]?[0-9]{1,7}))?")


def _decimal(text: Any, where: str) -> Fraction:
    """A decimal string read exactly (any number of digits; exponents up to 10^5)."""
    if not isinstance(text, str):
        raise FormatError(f"fixture: {where} must be a decimal string, got {type(text).__name__}")
    m = _DECIMAL.fullmatch(text.strip())
    if m is None or not (m.group(2) or m.group(3)) or abs(int(m.group(4) or 0)) > _MAX_EXPONENT:
        raise FormatError(f"fixture: {where} = {text[:40]!r} is not a decimal number "
                          f"(with |exponent| <= {_MAX_EXPONENT})")
    sign, whole, frac, exp = m.group(1), m.group(2), m.group(3) or "", int(m.group(4) or 0)
    mant = int(fmpz(whole + frac or "0"))
    e = exp - len(frac)
    q = Fraction(mant * 10 ** e) if e >= 0 else Fraction(mant, 10 ** -e)
    return -q if sign == "-" else q


def number_ball(num: dict, prec: int | None = None, *, where: str = "number") -> arb:
    """The certified ball [value - error, value + error] of a fixture number.

    The decimal ``value`` is read exactly (as a rational), so the ball's only widening is
    flint's outward rounding of that rational to ``prec`` bits (default: enough for every digit
    of ``value`` and for a rounding far below ``error``; at least 128 bits).

    >>> b = number_ball({"value": "0.333", "error": "0.001", "exact": "1/3"})
    >>> b.contains(fmpq(1, 3)), b.contains(fmpq(3331, 10000)), b.contains(fmpq(3341, 10000))
    (True, True, False)
    """
    if not isinstance(num, dict) or "value" not in num or "error" not in num:
        raise FormatError(f"fixture: {where} must be an object with 'value' and 'error'")
    v, e = _decimal(num["value"], f"{where}.value"), _decimal(num["error"], f"{where}.error")
    if e < 0:
        raise FormatError(f"fixture: {where}.error is negative")
    if prec is None:  # every digit of value, and rounding well below the error (a 30-digit
        # sample "0.32" +/- 3e-30 must not come back as 0.32 +/- 1e-17)
        prec = max(128, 48 + int(3.33 * max(_ndigits(v.numerator), _ndigits(v.denominator))))
        if e > 0 and v != 0:
            rel = _ndigits(abs(v.numerator) * e.denominator) - _ndigits(v.denominator * e.numerator)
            prec = max(prec, 48 + int(3.33 * rel))
    with ctx.workprec(prec):
        b = arb(fmpq(v.numerator, v.denominator))  # rounded outward: the ball contains v
        return b if e == 0 else arb(b, arb(fmpq(e.numerator, e.denominator)))


def number_exact(num: dict) -> str | None:
    """The closed form string of a fixture number, or None.

    >>> number_exact({"value": "1.5707963", "error": "2.7e-8", "exact": "pi/2"})
    'pi/2'
    """
    ex = num.get("exact") if isinstance(num, dict) else None
    return ex if isinstance(ex, str) else None


def number_rational(num: dict) -> Fraction | None:
    """The exact rational value of a fixture number, or None when it is not known to be rational.

    Rational when ``exact`` is an integer or ``p/q``, or when ``error`` is 0 (the decimal is then
    the exact value).

    >>> number_rational({"value": "0.333", "error": "0.0004", "exact": "1/3"})
    Fraction(1, 3)
    >>> number_rational({"value": "1.5707963", "error": "2.7e-8", "exact": "pi/2"}) is None
    True
    """
    ex = number_exact(num)
    if ex is not None:
        m = re.fullmatch(r"(-?[0-9]+)(?:/([0-9]+))?", ex.strip())
        if m is not None and (m.group(2) is None or int(fmpz(m.group(2))) != 0):
            return Fraction(int(fmpz(m.group(1))), int(fmpz(m.group(2) or "1")))
    if isinstance(num, dict) and num.get("error") == "0":
        return _decimal(num.get("value"), "value")
    return None
