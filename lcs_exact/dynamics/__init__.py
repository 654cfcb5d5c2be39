"""Runs of an LCS: the options of a run (``options``), scheduled systems (``schedule``), Algorithm 7.1
(``simulate``) and sweeps (``sweep``), over the continuous phases and their events (``lcs_exact.phases``)
and the accumulations they prove and cross (``lcs_exact.accumulations``).  Imports the doors below it;
re-exports the records and fixture helpers of ``phases`` and the ``Accumulation`` record, the names
this door has always offered.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from ..phases import (ball_number, ball_text, number_ball, number_exact, number_rational, short_text,
                      to_fraction, MAX_SAMPLES, SCHEMA, check_digest, sample_grid, validate_fixture,
                      Event, Status, Branches, Trajectory)
from ..accumulations import Accumulation
from .schedule import sampled, scheduled
from .simulate import simulate, simulate_branches
from .sweep import param_sweep, sweep, SweepResult

__all__ = ["ball_number", "ball_text", "number_ball", "number_exact", "number_rational", "short_text",
           "to_fraction", "MAX_SAMPLES", "SCHEMA", "check_digest", "sample_grid", "validate_fixture",
           "Branches", "Event", "Status", "Trajectory", "Accumulation", "sampled", "scheduled", "simulate", "simulate_branches",
           "param_sweep", "sweep", "SweepResult"]
