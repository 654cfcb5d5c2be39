"""Writing model files: the data of a system as the keys of docs/model-files.md, in TOML or JSON.

:func:`model_data` reads what a model file holds off a system (duck-typed on the attributes of
:class:`~lcs_exact.system.LCS`: ``A``, ``B``, ``C``, ``D``, ``plant``, ``sources``, names, roles,
``restitution``), :func:`write_model_file` writes it (``.toml``: TOML, any other name: JSON, as
the reader reads them).  ``LCS.to_model`` is the two in one; the reader is
:mod:`lcs_exact.modelfile`.

A system whose last states are a builder's exosystem (``lcs.sources``) is written as the driven
system x' = A x + B u + E w(t), y = C x + D u + F w(t) of its plant (``lcs.plant``): A, B, C, D
of the plant, E and F the columns of the exosystem's states, and ``w`` one source per state
(its function of time, :func:`~lcs_exact.sources.state_signals`, as text).  The reader rebuilds
the exosystem from ``w`` (:func:`~lcs_exact.sources.exosystem`); a block it would not rebuild
exactly as it stands (an S of another shape, an initial state that is not each atom's own, two
blocks of one atom) is refused with :class:`~lcs_exact.errors.Unsupported`, never approximated.

Numbers are written exactly: integers as numbers (within 64 bits: TOML's integers), every other
rational as a string ``"p/q"``.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from flint import fmpq

from ..errors import InvalidArgument, ShapeError, Unsupported
from ..algebra import identity, mat_rows, submatrix, to_fmpq, to_vector
from .sources import exosystem, state_signals

__all__ = ["MODEL_KEYS", "MATRIX_KEYS", "model_data", "write_model_file", "toml_text", "json_text"]

#: the keys of a model file, in the order of docs/model-files.md: the system, its sources, the
#: run, the impact law, the names
MODEL_KEYS = ("A", "B", "C", "D", "E", "F", "w", "x0", "t_end", "restitution", "name", "states", "inputs", "roles")
#: the keys whose values are matrices (lists of rows)
MATRIX_KEYS = ("A", "B", "C", "D", "E", "F")
_WRITE_ORDER = ("name",) + tuple(k for k in MODEL_KEYS if k != "name")
_INT64 = 2 ** 63


def _number(q: fmpq) -> Any:
    """An exact rational as a file value: an int (within 64 bits) or the string "p/q"."""
    if q.q == 1 and -_INT64 <= int(q.p) < _INT64:
        return int(q.p)
    return str(q)


def _rows(m) -> list:
    return [[_number(e) for e in row] for row in mat_rows(m)]


def _appended(lcs: Any) -> tuple:
    """(plant indices, exosystem indices, the exosystem states' sources or None): refuses what a
    model file cannot carry."""
    n = lcs.n
    plant = tuple(lcs.plant)
    J = tuple(range(len(plant), n))
    embedding = getattr(lcs, "embedding", None)
    if embedding is None or (not J and getattr(embedding, "n", None) == n):
        return plant, (), None
    sb = lcs.sources
    names = ", ".join(repr(lcs.state_names[j]) for j in J) or "none"
    if sb is None:
        raise Unsupported(f"a model file carries an LCS's appended states only as sources (an exosystem no "
                          f"plant state and no u enters); this LCS's embedding ({type(embedding).__name__}, "
                          f"appended states {names}) is not one: write LCS(lcs.A, lcs.B, lcs.C, lcs.D) and the "
                          f"full initial state instead")
    signals = state_signals(sb.S, sb.z0)
    why = None
    if signals is None:
        why = ("their S is not made of the blocks the sources' exosystem builds (chains of integrators, "
               "exponentials, rotations s' = w c, c' = -w s)")
    else:
        ex = exosystem(signals)
        if ex.size != len(J) or ex.S != sb.S or ex.z0 != sb.z0 or ex.W != identity(len(J)):
            kinds = ", ".join(f"{sb.names[i] if i < len(sb.names) else J[i]!r} = {sb.expressions[i]}"
                              for i in range(len(J)))
            why = (f"each state must be one atom with its own initial value (1, t, t^2/2, exp(r t), sin(w t), "
                   f"cos(w t)), each atom once; here {kinds}")
    if why is not None:
        raise Unsupported(f"the appended states {names} cannot be written as the sources w of a model file: {why}. "
                          f"Write LCS(lcs.A, lcs.B, lcs.C, lcs.D) and the full initial state instead")
    return plant, J, signals


def model_data(lcs: Any, x0: Any = None, t_end: Any = None) -> dict:
    """The keys of a model file for ``lcs`` (docs/model-files.md), every number exact.

    ``x0`` is the modelled system's state (what ``lcs.embed`` takes: the plant's states when the
    LCS has sources), ``t_end`` a final time; both optional.  Names, roles and restitution are
    written when the LCS has them (names only when they are not the defaults).

    Parameters
    ----------
    lcs : LCS
    x0 : vector, optional
        The modelled system's state (above).
    t_end : rational, optional
        A final time.

    >>> from lcs_exact import examples
    >>> d = model_data(examples.bouncing_ball(), x0=[1, 0], t_end=1)
    >>> d["A"], d["E"], d["w"], d["restitution"], d["states"]
    ([[0, 1], [0, 0]], [[0], ['-981/100']], ['constant(1)'], '9/10', ['q', "q'", '1'])
    """
    if getattr(lcs, "schedule", None) is not None:
        raise Unsupported("a model file holds one system: a ScheduledLCS (data that switch at scheduled times) "
                          "is not written as one; its fixtures (traj.to_fixture) carry the whole schedule")
    plant, J, signals = _appended(lcs)
    n, k = lcs.n, lcs.k
    data: dict = {}
    if getattr(lcs, "name", None) is not None:
        data["name"] = lcs.name
    P, K = list(plant), list(range(k))
    data["A"] = _rows(submatrix(lcs.A, P, P))
    data["B"] = _rows(submatrix(lcs.B, P, K))
    data["C"] = _rows(submatrix(lcs.C, K, P))
    data["D"] = _rows(lcs.D)
    if J:
        data["E"] = _rows(submatrix(lcs.A, P, list(J)))
        data["F"] = _rows(submatrix(lcs.C, K, list(J)))
        data["w"] = [repr(s) for s in signals]
    if x0 is not None:
        what = f"x0 (the plant's {len(P)} states; the sources' states follow from w)" if J else "x0"
        if isinstance(x0, (list, tuple)) and len(x0) != len(P):
            raise ShapeError(f"{what} has {len(x0)} entries, expected {len(P)}")
        v = to_vector(x0, len(P), what)
        data["x0"] = [_number(v[i, 0]) for i in range(len(P))]
    if t_end is not None:
        data["t_end"] = _number(to_fmpq(t_end, "t_end"))
    es = getattr(lcs, "restitution", None)
    if es is not None:
        data["restitution"] = _number(es[0]) if len(set(es)) == 1 else [_number(e) for e in es]
    names = tuple(lcs.state_names)
    if names != tuple(f"x_{i}" for i in range(n)):
        data["states"] = list(names)
    if tuple(lcs.constraint_names) != tuple(str(i) for i in range(k)):
        data["inputs"] = list(lcs.constraint_names)
    if getattr(lcs, "roles", None) is not None:
        data["roles"] = [list(r) for r in lcs.roles]
    return {key: data[key] for key in _WRITE_ORDER if key in data}


# ---------------------------------------------------------------------------------------------
# the two syntaxes: strings, integers, lists (nothing else occurs in model data)
# ---------------------------------------------------------------------------------------------

def _toml_string(s: str) -> str:
    out = []
    for ch in s:
        if ch == '"' or ch == "\\":
            out.append("\\" + ch)
        elif ch in "\b\t\n\f\r":
            out.append({"\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}[ch])
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04X}")
        elif 0xD800 <= ord(ch) <= 0xDFFF:
            raise InvalidArgument(f"the name {s[:40]!r} holds a lone surrogate (U+{ord(ch):04X}): not text a "
                                  f"model file can hold")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _value(v: Any, string) -> str:
    if isinstance(v, str):
        return string(v)
    if isinstance(v, bool) or not isinstance(v, (int, list, tuple)):
        raise InvalidArgument(f"model data hold strings, integers and lists, got {type(v).__name__}")
    if isinstance(v, int):
        return str(v)
    return "[" + ", ".join(_value(e, string) for e in v) + "]"


def _lines(data: dict, string, key, indent: str, sep: str, trailing: str) -> list:
    """``key sep value`` lines; a matrix of several rows (and the roles) one row a line."""
    out = []
    for k, v in data.items():
        if k in MATRIX_KEYS + ("roles",) and len(v) > 1:
            rows = (",\n").join(f"{indent}  {_value(r, string)}" for r in v)
            value = f"[\n{rows}{trailing}\n{indent}]"
        else:
            value = _value(v, string)
        out.append(f"{indent}{key(k)}{sep}{value}")
    return out


def toml_text(data: dict) -> str:
    """Model data as TOML (top-level keys; strings, integers and lists only).

    >>> print(toml_text({"name": 'a "b"', "A": [[0, 1], [-1, 0]], "w": ["sine(2)"]}), end="")
    name = "a \\"b\\""
    A = [
      [0, 1],
      [-1, 0],
    ]
    w = ["sine(2)"]
    """
    return "\n".join(_lines(data, _toml_string, str, "", " = ", ",")) + "\n"


def _json_string(s: str) -> str:
    try:
        s.encode("utf-8")
    except UnicodeEncodeError:
        raise InvalidArgument(f"the name {s[:40]!r} is not text a model file can hold (a lone surrogate)") from None
    return json.dumps(s, ensure_ascii=False)


def json_text(data: dict) -> str:
    """Model data as JSON, one key a line (a matrix one row a line).

    >>> print(json_text({"A": [[0, 1], [-1, 0]], "x0": ["1/2", 0]}), end="")
    {
      "A": [
        [0, 1],
        [-1, 0]
      ],
      "x0": ["1/2", 0]
    }
    """
    return "{\n" + ",\n".join(_lines(data, _json_string, _json_string, "  ", ": ", "")) + "\n}\n"


def write_model_file(data: dict, path: Any) -> Path:
    """Write model data to ``path``: TOML when the name ends in ``.toml`` (any case), JSON
    otherwise (as :mod:`lcs_exact.modelfile` reads them).  Returns the path.

    Parameters
    ----------
    data : dict
        What :func:`model_data` returns.
    path : str or Path
        The file (``.toml``: TOML, else JSON).
    """
    p = Path(path)
    text = toml_text(data) if p.suffix.lower() == ".toml" else json_text(data)
    p.write_text(text, encoding="utf-8")
    return p
