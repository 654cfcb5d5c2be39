"""The model-file format: a system, its sources, a run and names in TOML or JSON (docs/model-files.md).

A model file is an object with ``A``, ``B``, ``C``, ``D`` as lists of rows of numbers or rational
strings ("1/3"), and optionally the sources of a driven system (``E``, ``F``, ``w``: x' = A x +
B u + E w(t), y = C x + D u + F w(t), :func:`lcs_exact.models.driven`), ``x0``, ``t_end``,
``restitution``, ``name``, ``states``, ``inputs`` and ``roles``; any other key is an error
(:data:`MODEL_KEYS`).  Numbers are read exactly: a JSON or TOML decimal such as 1e-400 is the
rational 10^-400 (never a float); exponents beyond +/-10^4 are refused before anything turns them
into rationals.  Sources are text (``"sine(100, 10)"``, the repr of
:mod:`lcs_exact.sources` objects) read by :func:`~lcs_exact.sources.parse_source`, never
evaluated.  A fixture (``"schema": "lcs-exact/trajectory/1"``) is refused with a hint to
``lcs-exact compare``.

:func:`read_model` returns the :class:`~lcs_exact.LCS`, :func:`load_model` the LCS and the
checked data, :func:`read_model_data` the checked data alone; every error is a
:class:`~lcs_exact.errors.FormatError` (or the LCS's own error) naming the file.  Files are
written by ``LCS.to_model`` (:mod:`lcs_exact.modelformat`).  The command ``lcs-exact``
(:mod:`lcs_exact.cli`) reads its models here.
"""
from __future__ import annotations

import json
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

from flint import fmpz

from ..errors import FormatError, LCSError
from ..builders import driven
from ..system import MATRIX_KEYS, MODEL_KEYS
from ..system import AppendedStates, parse_source
from ..system import LCS

__all__ = ["MODEL_KEYS", "read_model", "read_model_data", "load_model", "check_exponents"]
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

    Parameters
    ----------
    v : str, number or nested list
        The values to check.
    where : str
        What they are, for the error message.

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


def read_model_data(path: str) -> dict:
    """The model file's data, checked: an object with A, B, C, D and only the known keys, each of
    its kind (shapes and values are checked by :func:`load_model`).

    Parameters
    ----------
    path : str
        The model file (TOML or JSON).

    >>> import json, os, tempfile
    >>> with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
    ...     json.dump({"A": [[0]], "B": [[1]], "C": [[1]], "D": [[0]], "x0": ["1/2"]}, f)
    >>> read_model_data(f.name)["x0"]; os.unlink(f.name)
    ['1/2']
    """
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
    for key in MATRIX_KEYS:
        v = data.get(key, [])
        if not isinstance(v, list) or not all(isinstance(r, list) for r in v):
            raise FormatError(f"model file {path}: {key} must be a list of rows (lists of numbers), got {_kind(v)}")
        for i, row in enumerate(v):  # entries are scalars: [[1], 0] is not read as 1
            j = next((j for j, e in enumerate(row) if not _is_scalar(e)), None)
            if j is not None:
                raise FormatError(f"model file {path}: {key}[{i}, {j}] is {_kind(row[j])}, not a number "
                                  f"or a rational string")
    for key, what, items in (("x0", "a number or a rational string", "numbers"),
                             ("w", "a source (a string such as \"sine(2)\") or a number", "sources")):
        if key in data and not isinstance(data[key], list):
            raise FormatError(f"model file {path}: {key} must be a list of {items}, got {_kind(data[key])}")
        j = next((j for j, v in enumerate(data.get(key, ())) if not _is_scalar(v)), None)
        if j is not None:
            raise FormatError(f"model file {path}: {key}[{j}] is {_kind(data[key][j])}, not {what}")
    if "w" in data and not data["w"]:
        raise FormatError(f"model file {path}: w is empty: leave out w, E and F for a system without sources")
    if "w" in data and "E" not in data and "F" not in data:
        raise FormatError(f"model file {path}: w needs E or F (how the sources enter x' and y)")
    if "w" not in data and ("E" in data or "F" in data):
        raise FormatError(f"model file {path}: {'E' if 'E' in data else 'F'} needs w (the sources it multiplies)")
    if "t_end" in data and not _is_scalar(data["t_end"]):
        raise FormatError(f"model file {path}: t_end must be a number, got {_kind(data['t_end'])}")
    if "restitution" in data:
        e = data["restitution"]
        if not (_is_scalar(e) or (isinstance(e, list) and all(_is_scalar(v) for v in e))):
            raise FormatError(f"model file {path}: restitution must be a number in [0, 1] or a list of them "
                              f"(one per complementarity pair), got {_kind(e)}")
    if "name" in data and not isinstance(data["name"], str):
        raise FormatError(f"model file {path}: name must be a string, got {_kind(data['name'])}")
    for key in ("states", "inputs"):
        if key in data and (not isinstance(data[key], list) or not all(isinstance(s, str) for s in data[key])):
            raise FormatError(f"model file {path}: {key} must be a list of names (strings)")
    if "roles" in data and (not isinstance(data["roles"], list) or not all(
            isinstance(r, list) and len(r) == 4 and all(isinstance(w, str) for w in r) for r in data["roles"])):
        raise FormatError(f"model file {path}: roles must be a list of [u label, y label, in-mode word, "
                          f"out-of-mode word] (four strings) per complementarity pair")
    for key in MATRIX_KEYS + ("x0", "t_end", "restitution"):
        if key in data:
            check_exponents(data[key], f"model file {path}: {key}")
    return data


def load_model(path: str) -> tuple[LCS, dict]:
    """Read a model file (TOML or JSON) into an LCS and its checked data (see :func:`read_model_data`).

    ``states`` and ``inputs`` become the LCS's ``state_names`` and ``constraint_names`` (shown by
    ``check``, ``select`` and ``simulate``); with sources (``w``) the LCS is the driven system of
    :func:`lcs_exact.models.driven`, its state (x, z) and ``x0`` the plant's state x (what
    ``lcs.embed`` takes).  An error in the data names the file.

    Parameters
    ----------
    path : str
        The model file (TOML or JSON).

    >>> import json, os, tempfile
    >>> with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
    ...     json.dump({"A": [[0, 1], [-1, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]],
    ...                "states": ["x", "v"], "inputs": ["wall"]}, f)
    >>> lcs, data = load_model(f.name); os.unlink(f.name)
    >>> lcs.state_names, lcs.constraint_names
    (('x', 'v'), ('wall',))
    """
    data = read_model_data(path)
    where = f"model file {path}"
    try:
        plain = LCS(data["A"], data["B"], data["C"], data["D"])
    except LCSError as e:  # shapes and entries, naming the file
        raise type(e)(f"{where}: {e}") from None
    n_plant, k = plain.n, plain.k
    srcs = []
    for i, text in enumerate(data.get("w", ())):
        try:
            srcs.append(parse_source(text))
        except LCSError as e:
            raise type(e)(f"{where}: w[{i}]: {e}") from None
    states = data.get("states")
    if srcs:
        try:
            base = driven(plain.A, plain.B, plain.C, plain.D, data.get("E"), data.get("F"), w=srcs,
                          state_names=states if states is not None and len(states) == n_plant else None)
        except LCSError as e:  # E, F: shapes and entries; plant names that repeat
            raise type(e)(f"{where}: {str(e).replace('state_names', 'states')}") from None
    else:
        base = plain
    n = base.n
    if states is not None and len(states) not in (n_plant, n):
        expected = f"n = {n}" if n == n_plant else f"{n_plant} (the plant's states) or {n} (with the sources' states)"
        raise FormatError(f"{where}: states has {len(states)} names, expected {expected}")
    if "inputs" in data and len(data["inputs"]) != k:
        raise FormatError(f"{where}: inputs has {len(data['inputs'])} names, expected k = {k}")
    if "roles" in data and len(data["roles"]) != k:
        raise FormatError(f"{where}: roles has {len(data['roles'])} entries, expected k = {k} (one per pair)")
    if "x0" in data and len(data["x0"]) != n_plant:
        what = f"{n_plant} (the plant's states: the sources' states follow from w)" if srcs else f"{n} (n)"
        raise FormatError(f"{where}: x0 has length {len(data['x0'])}, expected {what}")
    # the plant's names (or the defaults x_0, ...) with the sources' atoms ('1', 'sin(2t)'), or all n
    names = base.state_names if states is None or (srcs and len(states) == n_plant) else states
    embedding = None if not srcs else AppendedStates(n_plant, base.embedding.tail, tuple(names)[n_plant:])
    try:
        lcs = LCS(base.A, base.B, base.C, base.D, name=data.get("name"), state_names=names,
                  constraint_names=data.get("inputs"), embedding=embedding, restitution=data.get("restitution"),
                  roles=data.get("roles"))
    except LCSError as e:  # empty or repeated names, restitution, in the file's words
        msg = str(e).replace("state_names", "states").replace("constraint_names", "inputs")
        raise type(e)(f"{where}: {msg}") from None
    return lcs, data


def read_model(path: str) -> LCS:
    """The :class:`~lcs_exact.LCS` of a model file (TOML or JSON, docs/model-files.md): the
    inverse of :meth:`LCS.to_model <lcs_exact.LCS.to_model>`.  Its ``x0`` and ``t_end`` are in
    :func:`load_model`'s data.

    Parameters
    ----------
    path : str
        The model file (TOML or JSON).

    >>> import os, tempfile
    >>> from lcs_exact import examples
    >>> rect = examples.sine_rectifier()
    >>> path = rect.to_model(os.path.join(tempfile.mkdtemp(), "rect.json"))
    >>> back = read_model(path)
    >>> back.A == rect.A, back.sources.expressions, back.describe_mode({0})
    (True, ('sin(t)', 'cos(t)'), 'D1 conducting')
    """
    return load_model(path)[0]
