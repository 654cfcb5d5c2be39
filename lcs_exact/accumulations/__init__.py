"""Accumulations of events (Remark 4.11) proven and crossed: scaling symmetries and geometric laws
(``symmetry``, ``accumulation``), impact cascades on families of states (``cascade``), Newton impacts
of one contact (``bounces``) and of several taking turns (``collapsecycles``, ``collapses``), and the
suspicion of an accumulation that nothing proves (``zeno``).  Imports the doors below it (``phases``
for the trajectory's records and the event step).

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .symmetry import symmetry_exponents
from .accumulation import Accumulation, ReferenceStates, ScaledCycle, event_signature, geometric_law
from .cascade import cascade_bound
from .zeno import check_accumulation, shrinking_cycles
from .bounces import BOUNCE_PATIENCE, BounceWindow, bounce_cycle, bounce_window
from .collapsecycles import collapse_cycle, turns_suspected
from .collapses import CollapseWindow, prove_collapse

__all__ = ["symmetry_exponents", "Accumulation", "ReferenceStates", "ScaledCycle", "event_signature", "geometric_law",
           "cascade_bound", "check_accumulation", "shrinking_cycles", "BOUNCE_PATIENCE", "BounceWindow",
           "bounce_cycle", "bounce_window", "collapse_cycle", "turns_suspected", "CollapseWindow", "prove_collapse"]
