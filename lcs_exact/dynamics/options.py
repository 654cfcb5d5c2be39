"""The options of a run, checked once at the door: :func:`run_options` turns the arguments of
:func:`~lcs_exact.simulate` into a frozen :class:`RunOptions` (the precision policy
:class:`~lcs_exact.numbers.Policy` inside it), before anything is computed.

Every bad option value is an :class:`~lcs_exact.errors.InvalidArgument` (an ``LCSError`` and a
``ValueError``) whose message names the argument; a missing or malformed x0 or t_end is a
:class:`~lcs_exact.errors.ShapeError` / :class:`~lcs_exact.errors.NotRational`, as the data of a
problem rather than an option.  The limits of docs/limits.md are enforced here.
"""
from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from numbers import Real as RealNumber
from typing import Any

from flint import fmpq_mat

from ..algebra import MAX_PREC_BITS, to_fmpq, to_short, vector_entries
from ..errors import InvalidArgument, LCSError, NotRational, ShapeError
from ..numbers import Deadline, ExactVector, Policy, Real, as_real, check_digits
from ..system import LCS

__all__ = ["RunOptions", "run_options", "progress_bar", "CLOSED_FORMS", "ZENO", "BRANCHES"]

#: the spellings of ``closed_forms`` and the policy's meaning of each: ``"lazy"`` (the default)
#: proves a number's closed form on the first access of ``.closed_form``; ``True`` and ``"eager"``
#: prove the closed form of every phase's duration (the root theta that ends it) at its event, as
#: the run goes; ``False`` and ``"off"`` never look for one (the bool spellings are the older ones)
CLOSED_FORMS = {"lazy": "lazy", True: "eager", "eager": "eager", False: "off", "off": "off"}
#: the values of ``zeno``: cross a proven accumulation (Definition 4.10), or stop there
ZENO = ("cross", "stop")
#: the values of ``branches``: the unique continuation, or every branch of a choice
BRANCHES = ("unique", "all")


@dataclass(frozen=True)
class RunOptions:
    """A run's options, checked: the end time (an exact real >= 0), the digits promised, the
    event budget, the precision policy (digits, max_prec, allow_unresolved, closed_forms, the
    deadline), what to do at an accumulation (``zeno``), which branches to follow and whether
    to show a progress bar."""

    t_end: Real
    digits: int
    max_events: int
    policy: Policy
    zeno: str
    branches: str
    progress: bool


def _is_int(v: Any) -> bool:
    return isinstance(v, int) and not isinstance(v, bool)


def run_options(lcs: Any, x0: Any, t_end: Any, digits: Any, *, max_events: Any, time_limit: Any,
                allow_unresolved: Any, closed_forms: Any, zeno: Any, branches: Any, max_prec: Any,
                progress: Any) -> RunOptions:
    """The options of ``simulate(lcs, x0, t_end, digits, ...)``, validated once (the module
    docstring); x0 is checked for its length and entries here and converted by the caller.

    Parameters
    ----------
    lcs : LCS
    x0 : vector of length n, ExactVector, fmpq_mat or iterator
    t_end : rational, exact real or SymPy number >= 0
    digits : int in 1..MAX_DIGITS
    max_events : int >= 0
    time_limit : float >= 0 or None
    allow_unresolved : bool
    closed_forms : 'lazy', True or 'eager', False or 'off' (:data:`CLOSED_FORMS`)
    zeno : 'cross' or 'stop'
    branches : 'unique' or 'all'
    max_prec : int in 64..MAX_PREC_BITS or None
    progress : bool
    """
    _check_option_values(lcs, digits, max_events, time_limit, closed_forms, allow_unresolved, max_prec)
    T = _end_time(lcs, x0, t_end)
    if not isinstance(zeno, str) or zeno not in ZENO:
        raise InvalidArgument(f"zeno must be 'cross' or 'stop', got {to_short(zeno)}")
    if not isinstance(branches, str) or branches not in BRANCHES:
        raise InvalidArgument(f"branches must be 'unique' or 'all', got {to_short(branches)}")
    if not isinstance(progress, bool):
        raise InvalidArgument(f"progress must be True or False, got {progress!r}")
    policy = Policy(digits=digits, max_prec=max_prec or 0, allow_unresolved=allow_unresolved,
                    closed_forms=CLOSED_FORMS[closed_forms], deadline=Deadline(time_limit))
    return RunOptions(T, digits, max_events, policy, zeno, branches, progress)


def _check_option_values(lcs, digits, max_events, time_limit, closed_forms, allow_unresolved, max_prec) -> None:
    """Each option value of a run, checked: an InvalidArgument naming the first bad one."""
    if not isinstance(lcs, LCS):
        raise InvalidArgument(f"lcs must be an LCS (lcs_exact.LCS), got {type(lcs).__name__}")
    check_digits(digits)
    if not _is_int(max_events) or max_events < 0:
        raise InvalidArgument(f"max_events must be a nonnegative Python int, got {to_short(max_events)}")
    if time_limit is not None:
        try:  # the deadline adds it to a float clock: it must be a real number a float can hold
            seconds = float(time_limit) if isinstance(time_limit, RealNumber) else math.nan
        except OverflowError:
            seconds = math.nan
        if isinstance(time_limit, bool) or type(time_limit).__name__ == "bool_" or not seconds >= 0:
            raise InvalidArgument("time_limit must be a nonnegative number of seconds (a float can hold) or "
                                  f"None, got {to_short(time_limit)}")
    if not isinstance(closed_forms, (str, bool)) or closed_forms not in CLOSED_FORMS:
        raise InvalidArgument("closed_forms must be 'lazy' (the default), True or 'eager', False or 'off', "
                              f"got {to_short(closed_forms)}")
    if not isinstance(allow_unresolved, bool):
        raise InvalidArgument(f"allow_unresolved must be True or False, got {to_short(allow_unresolved)}")
    if max_prec is not None and (not _is_int(max_prec) or not 64 <= max_prec <= MAX_PREC_BITS):
        raise InvalidArgument(f"max_prec must be None or an int in 64..{MAX_PREC_BITS} (bits), got {to_short(max_prec)}")


def _end_time(lcs, x0, t_end) -> Real:
    """t_end as an exact real >= 0, after checking that x0 is given (its length and entries)."""
    if x0 is None:
        raise ShapeError("x0 is required: a vector of length n (rational entries or an exact vector)")
    if not isinstance(x0, (ExactVector, fmpq_mat, Iterator)):  # an iterator is read once, later
        vector_entries(x0, lcs.n, "x0")
    if t_end is None:
        raise NotRational("t_end is required: a rational number or an exact real >= 0")
    T = t_end if isinstance(t_end, Real) or type(t_end).__module__.startswith("sympy") else to_fmpq(t_end, "t_end")
    try:
        T = as_real(T)
    except LCSError as e:
        raise type(e)(f"t_end: {e}") from e
    except (TypeError, ValueError) as e:
        raise NotRational(f"t_end: {e}") from e
    if T.sign() < 0:
        raise InvalidArgument(f"t_end must be >= 0, got {T.label()}")
    return T


def progress_bar(T: Real) -> Any:
    """The bar of ``progress=True``: a tqdm bar over [0, t_end], in time units (the run advances it
    at every event); an InvalidArgument when tqdm is not installed.

    Parameters
    ----------
    T : Real
        t_end.
    """
    try:
        from tqdm.auto import tqdm
    except ImportError:
        raise InvalidArgument("progress=True needs tqdm: pip install tqdm (or lcs_exact[sweep])") from None
    return tqdm(total=float(T), desc="simulate", unit="t", bar_format="{l_bar}{bar}| t = {n:.4g} of {total:.4g} "
                                                                        "[{elapsed}<{remaining}]")
