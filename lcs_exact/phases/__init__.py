"""Continuous phases and their events: real roots of exponential sums (``guesses``, ``roots``,
``polyroots``), one event step of Algorithm 7.1 over two arithmetics (``eventstep``), the continuous
phase (``phase``, ``clock``), the next event (``flow``), the records of a run and the trajectory
(``events``, ``timeline``, ``undetermined``, ``trajectory``), the fixture format and the other exports
it writes (``fixture``, ``fixnumbers``, ``exports``).  Imports the doors below it.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .fixnumbers import (ball_number, ball_text, number_ball, number_exact, number_rational, short_text,
                         to_fraction)
from .fixture import MAX_SAMPLES, SCHEMA, check_digest, sample_grid, validate_fixture
from .eventstep import ExactStates, FamilyState, FamilyStates, apply_forms, event_step, vanishes
from .phase import Phase, PhaseFunction, phase_horizon
from .clock import SourceClock, autonomous_block
from .flow import next_event
from .events import Event, PhaseRecord, Status
from .trajectory import Branches, Trajectory, full_feedback

__all__ = ["ball_number", "ball_text", "number_ball", "number_exact", "number_rational", "short_text",
           "to_fraction", "MAX_SAMPLES", "SCHEMA", "check_digest", "sample_grid", "validate_fixture",
           "ExactStates", "FamilyState", "FamilyStates", "apply_forms", "event_step", "vanishes",
           "Phase", "PhaseFunction", "phase_horizon", "SourceClock", "autonomous_block", "next_event",
           "Event", "PhaseRecord", "Status", "Branches", "Trajectory", "full_feedback"]
