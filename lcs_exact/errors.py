"""Exceptions of lcs_exact: one root, :class:`LCSError`, mixed with the matching builtin.

Every message names the object and the reason (``mode {0, 2} is not autonomous: G_II(s) is
singular``).  Errors raised by a run that stops early carry what was computed so far in
``.trajectory`` (marked partial); errors of the algebra layer carry ``None`` there.
"""
from __future__ import annotations

__all__ = [
    "LCSError", "ShapeError", "NotRational", "NotAutonomous", "IllPosed", "Deadlock",
    "ZenoDetected", "UnresolvedSign", "LimitExceeded", "FormatError", "FixtureMismatch",
    "Unsupported", "InvalidArgument", "Undetermined", "WorkerDied", "HorizonExceeded",
]


class LCSError(Exception):
    """Root of every error raised by lcs_exact.

    Parameters
    ----------
    message : str
        What failed and why, naming the object.
    trajectory : Trajectory or None
        The run up to the error (partial), or None (the algebra layer).
    """

    def __init__(self, message: str, *, trajectory=None):
        super().__init__(message)
        self.trajectory = trajectory


class ShapeError(LCSError, ValueError):
    """A matrix or vector has the wrong shape (names the object, the shape and the expected one)."""


class NotRational(LCSError, TypeError):
    """An entry cannot be read as an exact rational number."""


class NotAutonomous(LCSError, ValueError):
    """A mode I is not autonomous (Lemma 3.3 fails); the message says which condition fails."""


class IllPosed(LCSError, ValueError):
    """The conditions of Theorem 6.3 / 6.9 fail where a computation requires them, or S(z) leaves
    a choice between initial solutions that changes the trajectory (non-uniqueness).  In the
    latter case ``alternatives`` lists (mode, initial solution) for each distinct initial
    solution, and ``trajectory`` holds the run up to the choice.

    Parameters
    ----------
    message : str
    trajectory : Trajectory or None
        The run up to the failure or the choice (partial).
    alternatives : iterable of (frozenset, ExactVector)
        (mode, initial solution) per distinct initial solution in S(z) (section 6).
    """

    def __init__(self, message: str, *, trajectory=None, alternatives=()):
        super().__init__(message, trajectory=trajectory)
        self.alternatives = tuple(alternatives)


class Deadlock(LCSError):
    """S(z) is empty: no initial solution exists from the current state (Remark 7.2 (1))."""


class ZenoDetected(LCSError):
    """Event times accumulate, or re-initializations do not terminate (Remark 7.2 (2), (3)).

    ``time`` is the accumulation time as an exact real when a geometric law proves it; ``lower``
    and ``upper`` (rationals, or None) enclose it, certified: equal to it for a geometric law (or
    a tight dyadic enclosure of an algebraic one), an interval as narrow as the event times'
    digits for an impact cascade proven without a law (docs/numerics.md), and otherwise ``lower``
    the last event computed with ``upper`` None (nothing bounds the accumulation time from above
    but t_end).  ``estimate`` is a float near the enclosure (rounded: not certified to lie in
    it), or an uncertified guess from the shrinking gaps when ``upper`` is None (for messages
    only); with ``upper`` None the accumulation itself is suspected, not proven.

    Parameters
    ----------
    message : str
    trajectory : Trajectory or None
        The run up to the accumulation (partial).
    lower, upper : fmpq or None
        The certified enclosure of the accumulation time (above).
    estimate : float or None
        Not certified (above).
    time : Real or None
        The accumulation time, exact, when a geometric law proves it.
    """

    def __init__(self, message: str, *, trajectory=None, lower=None, upper=None, estimate=None, time=None):
        super().__init__(message, trajectory=trajectory)
        self.lower, self.upper, self.estimate, self.time = lower, upper, estimate, time


class UnresolvedSign(LCSError, ArithmeticError):
    """A sign decision could be neither certified by a ball nor proven zero by structure."""


class LimitExceeded(LCSError):
    """A user limit (events, wall-clock time) was reached before t_end."""


class TimeLimitExceeded(LimitExceeded):
    """The wall-clock limit (``time_limit``) was reached: by a run (its trajectory so far is kept,
    status ``time limit``) or by a query after it."""


class HorizonExceeded(LimitExceeded):
    """A phase has no event within the horizon limit of its rates (docs/limits.md) while t_end
    is further: the run stops there, its trajectory computed up to that time."""


class FormatError(LCSError, ValueError):
    """A model file, a fixture or a solution file is malformed (names the file, key or line)."""


class FixtureMismatch(FormatError):
    """A fixture disagrees with the trajectory recomputed exactly from its own system and x0."""


class Unsupported(LCSError, NotImplementedError):
    """A valid request that this version cannot serve (the message says what is missing and where
    it is planned), e.g. a circuit with a loop of capacitors, or an example that needs a builder
    not written yet."""


class InvalidArgument(LCSError, ValueError, TypeError):
    """An argument has a wrong type or value that is not a matter of shape or exactness (names,
    options, a malformed constraint); the message names the argument.  Also a ValueError and a
    TypeError, so code catching either keeps working."""


class Undetermined(LCSError, ValueError):
    """A value the solution does not determine was asked for: an input u_j (or an output y_i that
    depends on it) on a phase where it is free - the potential of a floating node while all its
    diodes block.  The state is unique there; this number is not (docs/extensions.md)."""


class WorkerDied(LCSError, RuntimeError):
    """A sweep's worker process died while running a job (killed by a signal, out of memory), and
    died again when the job was run alone on a fresh worker; the sweep's other results are kept."""
