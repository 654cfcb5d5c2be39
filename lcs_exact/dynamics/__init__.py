"""Runs of an LCS: real roots of exponential sums (``guesses``, ``roots``, ``polyroots``),
the continuous phase (``phase``, ``clock``), the next event (``flow``), the records of a run and
the trajectory (``events``, ``timeline``, ``undetermined``, ``trajectory``), the fixture format
and the other exports it writes (``fixture``, ``fixnumbers``, ``exports``), accumulations and
cascades (``symmetry``, ``accumulation``, ``cascade``, ``bounces``, ``collapses``, ``zeno``),
scheduled systems (``schedule``), Algorithm 7.1 (``simulate``) and sweeps (``sweep``).  Imports
the doors below it.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .fixnumbers import (ball_number, ball_text, number_ball, number_exact, number_rational, short_text,
                         to_fraction)
from .fixture import MAX_SAMPLES, SCHEMA, check_digest, sample_grid, validate_fixture
from .events import Event, Status
from .trajectory import Branches, Trajectory
from .accumulation import Accumulation
from .schedule import sampled, scheduled
from .simulate import simulate, simulate_branches
from .sweep import param_sweep, sweep, SweepResult

__all__ = ["ball_number", "ball_text", "number_ball", "number_exact", "number_rational", "short_text",
           "to_fraction", "MAX_SAMPLES", "SCHEMA", "check_digest", "sample_grid", "validate_fixture",
           "Branches", "Event", "Status", "Trajectory", "Accumulation", "sampled", "scheduled", "simulate", "simulate_branches",
           "param_sweep", "sweep", "SweepResult"]
