"""Where a time falls among the phases of a run: the phase holding t, by certified signs.

The phases of a trajectory follow one another, [t_0, t_1], [t_1, t_2], ...  A time t is located by
bisecting the phases' ends as floats (a guess only: a plot asks thousands of times, and a walk of
certified signs over 700 phases took seconds) and walking from there with the certified signs of
t - t_i (an event time equal to t is proven equal through closed forms, Real.sign).
"""
from __future__ import annotations

import bisect
from typing import Sequence

from ..numbers import Real

__all__ = ["Timeline"]


class Timeline:
    """The ends of a sequence of phases (records with ``t0``, ``t1``), for :meth:`locate`.

    Parameters
    ----------
    phases : sequence of PhaseRecord
        The phases in time order, each ending where the next starts.
    """

    def __init__(self, phases: Sequence):
        self.phases = phases
        self.ends = [float(rec.t1.arb(64).mid()) for rec in phases]

    def end_sign(self, t: Real, i: int) -> int:
        """The certified sign of t - t_{i+1} (the end of phase i).

        Parameters
        ----------
        t : Real
        i : int
            A phase index.
        """
        end = self.phases[i].t1
        return 0 if t is end else (t - end).sign()

    def locate(self, t: Real, start: int = 0) -> tuple[int, bool] | None:
        """(index of the phase holding t, True when t is exactly its end), or None when t is after
        the last phase; t is at or after the start of phase ``start``.

        Parameters
        ----------
        t : Real
        start : int
            The first phase the answer may be.
        """
        i = min(max(bisect.bisect_left(self.ends, float(t.arb(64).mid()), lo=start), start), len(self.ends) - 1)
        while i > start and self.end_sign(t, i - 1) <= 0:
            i -= 1
        while i < len(self.phases):
            s = self.end_sign(t, i)
            if s <= 0:
                return i, s == 0
            i += 1
        return None
