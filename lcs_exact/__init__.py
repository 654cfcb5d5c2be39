"""lcs_exact: an exact engine for linear complementarity systems (Heemels, Schumacher, Weiland 2000)."""
from __future__ import annotations

import sys as _sys
from importlib import import_module as _import_module

from .errors import (Deadlock, FixtureMismatch, FormatError, HorizonExceeded, IllPosed, InvalidArgument, LCSError,
                     LimitExceeded, NotAutonomous, NotRational, ShapeError, Undetermined, UnresolvedSign,
                     TimeLimitExceeded, Unsupported, WorkerDied, ZenoDetected)
from .algebra import RationalFunction, RationalMatrix, all_solutions, is_p_matrix, solve_lcp
from .numbers import ExactVector, Real, expm_action
from .modes import Mode
from .display import plot_convergence
from .system import LCS, ModeMap, Region, WellPosedness
from .dynamics import (Accumulation, Branches, Event, Status, SweepResult, Trajectory, param_sweep, simulate,
                       simulate_branches, sweep, validate_fixture)
from .io import FixtureTrajectory, read_fixture, read_model
from .verify import ComparisonReport, compare, convergence_order
from . import examples, modelfile, models, sources, testing, zoo  # the documented modules, as attributes

__all__ = [
    "LCS", "Mode", "simulate", "simulate_branches", "Branches", "Accumulation", "Status", "sweep", "param_sweep", "SweepResult", "expm_action", "Trajectory", "Event", "Real", "ExactVector", "WellPosedness", "RationalFunction", "RationalMatrix",
    "solve_lcp", "all_solutions", "is_p_matrix",
    "LCSError", "ShapeError", "NotRational", "NotAutonomous", "IllPosed", "Deadlock",
    "ZenoDetected", "UnresolvedSign", "LimitExceeded", "FormatError", "FixtureMismatch",
    "Unsupported", "InvalidArgument", "Undetermined", "WorkerDied", "HorizonExceeded", "TimeLimitExceeded",
    "read_fixture", "validate_fixture", "compare", "convergence_order", "plot_convergence", "ComparisonReport",
    "FixtureTrajectory", "ModeMap", "Region", "read_model", "examples", "models", "sources", "zoo",
]

__version__ = "0.1.0"

# The modules' paths before the package was divided into subpackages (``lcs_exact.rational``, ...,
# named by earlier documentation and by code written against it), each the module at its new
# home: ``lcs_exact.rational is lcs_exact.algebra.rational``.  New code imports through the
# subpackages' doors (docs/architecture.md).
_MOVED = {
    "rational": "algebra.rational", "ratfunc": "algebra.ratfunc", "subspaces": "algebra.subspaces",
    "lcp": "algebra.lcp", "polyhedra": "algebra.polyhedra",
    "balls": "numbers.balls", "flintlib": "numbers.flintlib", "calcium": "numbers.calcium", "forms": "numbers.forms",
    "expm": "numbers.expm", "nodes": "numbers.nodes", "reals": "numbers.reals", "vectors": "numbers.vectors",
    "closedforms": "numbers.closedforms", "taylormodels": "numbers.taylormodels",
    "ldcp": "modes.ldcp", "rcpfamily": "modes.rcpfamily", "selection": "modes.selection",
    "mapplot": "display.mapplot", "figlabels": "display.figlabels", "plotting": "display.plotting",
    "convergence": "display.convergence",
    "modelformat": "system.modelformat", "statespace": "system.statespace", "wellposedness": "system.wellposedness",
    "impacts": "system.impacts", "modemap": "system.modemap",
    "guesses": "phases.guesses", "roots": "phases.roots", "polyroots": "phases.polyroots",
    "phase": "phases.phase", "clock": "phases.clock", "flow": "phases.flow", "fixnumbers": "phases.fixnumbers",
    "fixture": "phases.fixture", "trajectory": "phases.trajectory", "accumulation": "accumulations.accumulation",
    "cascade": "accumulations.cascade", "zeno": "accumulations.zeno", "schedule": "dynamics.schedule",
    "simulate": "dynamics.simulate", "sweep": "dynamics.sweep",
    "exosystems": "builders.exosystems", "mechanics": "builders.mechanics", "circuits": "builders.circuits",
    "relays": "builders.relays", "fixturereader": "io.fixturereader", "solverevents": "verify.solverevents",
    "compare": "verify.compare",
}
for _old, _new in _MOVED.items():
    _sys.modules[f"{__name__}.{_old}"] = _import_module(f"{__name__}.{_new}")
    globals().setdefault(_old, _sys.modules[f"{__name__}.{_old}"])   # the functions simulate, sweep stay
# the modules that left ``dynamics`` when it was divided (phases below it, accumulations between), at
# their earlier paths too: ``lcs_exact.dynamics.bounces is lcs_exact.accumulations.bounces``
for _old in ("guesses", "roots", "polyroots", "eventstep", "phase", "clock", "flow", "fixnumbers", "fixture", "events",
             "timeline", "undetermined", "exports", "trajectory"):
    _sys.modules[f"{__name__}.dynamics.{_old}"] = _import_module(f"{__name__}.phases.{_old}")
for _old in ("symmetry", "accumulation", "cascade", "zeno", "bounces", "collapsecycles", "collapses"):
    _sys.modules[f"{__name__}.dynamics.{_old}"] = _import_module(f"{__name__}.accumulations.{_old}")
del _old, _new
