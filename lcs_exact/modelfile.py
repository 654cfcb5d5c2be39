"""The model-file format: a system (and optionally x0, t_end, names) in TOML or JSON (docs/model-files.md).

A model file is an object with ``A``, ``B``, ``C``, ``D`` as lists of rows of numbers or rational
strings ("1/3"), and optionally ``x0``, ``t_end``, ``name``, ``states`` and ``inputs`` (names);
any other key is an error (:data:`MODEL_KEYS`).  Numbers are read exactly: a JSON or TOML decimal
such as 1e-400 is the rational 10^-400 (never a float); exponents beyond +/-10^4 are refused
before anything turns them into rationals.  A fixture (``"schema": "lcs-exact/trajectory/1"``) is
refused with a hint to ``lcs-exact compare``.

:func:`read_model` returns the checked data, :func:`load_model` the :class:`~lcs_exact.LCS` and
the data; every error is a :class:`~lcs_exact.errors.FormatError` (or the LCS's own error) naming
the file.  The command ``lcs-exact`` (:mod:`lcs_exact.cli`) reads its models here.
"""
from __future__ import annotations

import json
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

from flint import fmpz

from .errors import FormatError, LCSError
from .system import LCS

__all__ = ["MODEL_KEYS", "read_model", "load_model", "check_exponents"]

#: the keys of a model file, in the order of docs/model-files.md: the system, then the optional ones
MODEL_KEYS = ("A", "B", "C", "D", "x0", "t_end", "name", "states", "inputs")
_MAX_EXPONENT = 10_000  # 1e999999999 would be a gigabyte-sized rational: refused, not computed
_EXPONENT = re.compile(r"[eE]\s*([+-]?\d+)")


def _exact_number(text: str) -> Fraction:
    """A JSON/TOML float literal read exactly (exponent bounded)."""
    m = _EXPONENT.search(text)
    if m and abs(int(m.group(1))) > _MAX_EXPONENT:
        raise FormatError(f"the number {text[:30]} has an exponent beyond +/-{_MAX_EXPONENT}")
    try:
        return Fraction(text.replace("_", ""))
    except (ValueError, ZeroDivisionError):
        raise FormatError(f"{text[:30]!r} is not a finite number") from None


def _exact_int(text: str) -> int:
    """A JSON integer literal of any length (Python's int(str) stops at 4300 digits)."""
    return int(text) if len(text) < 4000 else int(fmpz(text))


def _reject_constant(name: str):
    raise FormatError(f"{name} is not a finite number")


def check_exponents(v: Any, where: str) -> None:
    """Refuse numeric strings (alone or in nested lists) whose exponent is beyond +/-10^4, before
    anything turns them into rationals (1e999999999 would be a gigabyte-sized rational); the
    command applies it to its own options too (``--x0``, ``--t-end``, ``--sample``).

    >>> check_exponents(["1", ["2e5000"]], "x0")
    >>> check_exponents(["1", ["2e50000"]], "x0")
    Traceback (most recent call last):
    ...
    lcs_exact.errors.FormatError: x0[1][0] = '2e50000' has an exponent beyond +/-10000
    """
    if isinstance(v, str):
        m = _EXPONENT.search(v)
        if m and abs(int(m.group(1))) > _MAX_EXPONENT:
            raise FormatError(f"{where} = {v[:30]!r} has an exponent beyond +/-{_MAX_EXPONENT}")
    elif isinstance(v, list):
        for i, e in enumerate(v):
            check_exponents(e, f"{where}[{i}]")


def _is_scalar(v: Any) -> bool:
    """A number or a string (a rational "p/q"); booleans, null, lists and objects are not."""
    return isinstance(v, (int, float, Fraction, str)) and not isinstance(v, bool)


def _kind(v: Any) -> str:
    return {type(None): "null", bool: "a boolean", dict: "an object", list: "a list", str: "a string"}.get(
        type(v), "a number")


def read_model(path: str) -> dict:
    """The model file's data, checked: an object with A, B, C, D and only the known keys."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError as e:
        raise FormatError(f"model file {path} is not UTF-8 text (JSON or TOML): byte {e.start}") from None
    try:
        if p.suffix.lower() == ".toml":
            try:
                import tomllib
            except ModuleNotFoundError:  # pragma: no cover - Python 3.10 has no TOML reader
                raise FormatError("TOML model files need Python 3.11 or later (tomllib); write it as JSON") from None
            data = tomllib.loads(text, parse_float=_exact_number)
        else:
            data = json.loads(text, parse_float=_exact_number, parse_int=_exact_int,
                              parse_constant=_reject_constant)
    except RecursionError:
        raise FormatError(f"model file {path}: nested too deeply") from None
    except FormatError as e:
        raise FormatError(f"model file {path}: {e}") from None
    except ValueError as e:  # JSONDecodeError, TOMLDecodeError, integers beyond Python's digit limit
        if "integer string conversion" in str(e):  # TOML's integers go through int(str)
            raise FormatError(f"model file {path}: an integer has more than 4300 digits; write it as a "
                              f"string (\"123...\") or use a JSON model file") from None
        raise FormatError(f"model file {path}: {e}") from None
    if not isinstance(data, dict):
        raise FormatError(f"model file {path} must hold an object with keys A, B, C, D, got {_kind(data)}")
    if isinstance(data.get("schema"), str) and data["schema"].startswith("lcs-exact/"):
        raise FormatError(f"{path} is a fixture ({data['schema']}), not a model file: "
                          f"use `lcs-exact compare {path} SOLUTION.csv`")
    unknown = [k for k in data if k not in MODEL_KEYS]
    if unknown:
        raise FormatError(f"model file {path}: unknown key {unknown[0][:40]!r} (allowed: {', '.join(MODEL_KEYS)})")
    missing = [key for key in "ABCD" if key not in data]
    if missing:
        raise FormatError(f"model file {path} lacks {', '.join(missing)}")
    for key in "ABCD":
        v = data[key]
        if not isinstance(v, list) or not all(isinstance(r, list) for r in v):
            raise FormatError(f"model file {path}: {key} must be a list of rows (lists of numbers), got {_kind(v)}")
    if "x0" in data and not isinstance(data["x0"], list):
        raise FormatError(f"model file {path}: x0 must be a list of numbers, got {_kind(data['x0'])}")
    for key in "ABCD":  # entries are scalars: [[1], 0] is not read as 1
        for i, row in enumerate(data[key]):
            j = next((j for j, v in enumerate(row) if not _is_scalar(v)), None)
            if j is not None:
                raise FormatError(f"model file {path}: {key}[{i}, {j}] is {_kind(row[j])}, not a number "
                                  f"or a rational string")
    j = next((j for j, v in enumerate(data.get("x0", ())) if not _is_scalar(v)), None)
    if j is not None:
        raise FormatError(f"model file {path}: x0[{j}] is {_kind(data['x0'][j])}, not a number or a "
                          f"rational string")
    if "t_end" in data and (isinstance(data["t_end"], (bool, list, dict)) or data["t_end"] is None):
        raise FormatError(f"model file {path}: t_end must be a number, got {_kind(data['t_end'])}")
    if "name" in data and not isinstance(data["name"], str):
        raise FormatError(f"model file {path}: name must be a string, got {_kind(data['name'])}")
    for key in ("states", "inputs"):
        if key in data and (not isinstance(data[key], list) or not all(isinstance(s, str) for s in data[key])):
            raise FormatError(f"model file {path}: {key} must be a list of names (strings)")
    for key in ("A", "B", "C", "D", "x0", "t_end"):
        if key in data:
            check_exponents(data[key], f"model file {path}: {key}")
    return data


def load_model(path: str) -> tuple[LCS, dict]:
    """Read a model file (TOML or JSON) into an LCS and its checked data (see :func:`read_model`).

    ``states`` and ``inputs`` become the LCS's ``state_names`` and ``constraint_names`` (shown by
    ``check``, ``select`` and ``simulate``); an error in the data names the file.

    >>> import json, os, tempfile
    >>> with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
    ...     json.dump({"A": [[0, 1], [-1, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]],
    ...                "states": ["x", "v"], "inputs": ["wall"]}, f)
    >>> lcs, data = load_model(f.name); os.unlink(f.name)
    >>> lcs.state_names, lcs.constraint_names
    (('x', 'v'), ('wall',))
    """
    data = read_model(path)
    try:
        lcs = LCS(data["A"], data["B"], data["C"], data["D"], name=data.get("name"))
    except LCSError as e:  # shapes and entries, naming the file
        raise type(e)(f"model file {path}: {e}") from None
    for key, size, what in (("states", lcs.n, "n"), ("inputs", lcs.k, "k")):
        if key in data and len(data[key]) != size:
            raise FormatError(f"model file {path}: {key} has {len(data[key])} names, expected {what} = {size}")
    if "states" in data or "inputs" in data:
        try:
            lcs = LCS(lcs.A, lcs.B, lcs.C, lcs.D, name=lcs.name, state_names=data.get("states"),
                      constraint_names=data.get("inputs"))
        except LCSError as e:  # empty or repeated names, in the file's words
            msg = str(e).replace("state_names", "states").replace("constraint_names", "inputs")
            raise type(e)(f"model file {path}: {msg}") from None
    if "x0" in data and len(data["x0"]) != lcs.n:
        raise FormatError(f"model file {path}: x0 has length {len(data['x0'])}, expected {lcs.n} (n)")
    return lcs, data
