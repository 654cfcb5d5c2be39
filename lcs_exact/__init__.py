"""lcs_exact: an exact engine for linear complementarity systems (Heemels, Schumacher, Weiland 2000)."""
from __future__ import annotations

from .compare import ComparisonReport, compare, convergence_order
from .convergence import plot_convergence
from .errors import (Deadlock, FixtureMismatch, FormatError, HorizonExceeded, IllPosed, InvalidArgument, LCSError,
                     LimitExceeded, NotAutonomous, NotRational, ShapeError, Undetermined, UnresolvedSign,
                     TimeLimitExceeded, Unsupported, WorkerDied, ZenoDetected)
from .fixture import validate_fixture
from .fixturereader import FixtureTrajectory, read_fixture
from .lcp import all_solutions, is_p_matrix, solve_lcp
from .modes import Mode
from .ratfunc import RationalFunction, RationalMatrix
from .reals import Real
from .vectors import ExactVector, expm_action
from .simulate import simulate
from .sweep import SweepResult, param_sweep, sweep
from .system import LCS
from .wellposedness import WellPosedness
from .accumulation import Accumulation
from .trajectory import Branches, Event, Status, Trajectory
from .modemap import ModeMap, Region
from .modelfile import read_model
from . import examples, models, sources, zoo  # lcs_exact.examples, .models, .sources, .zoo as attributes

__all__ = [
    "LCS", "Mode", "simulate", "Branches", "Accumulation", "Status", "sweep", "param_sweep", "SweepResult", "expm_action", "Trajectory", "Event", "Real", "ExactVector", "WellPosedness", "RationalFunction", "RationalMatrix",
    "solve_lcp", "all_solutions", "is_p_matrix",
    "LCSError", "ShapeError", "NotRational", "NotAutonomous", "IllPosed", "Deadlock",
    "ZenoDetected", "UnresolvedSign", "LimitExceeded", "FormatError", "FixtureMismatch",
    "Unsupported", "InvalidArgument", "Undetermined", "WorkerDied", "HorizonExceeded", "TimeLimitExceeded",
    "read_fixture", "validate_fixture", "compare", "convergence_order", "plot_convergence", "ComparisonReport",
    "FixtureTrajectory", "ModeMap", "Region", "read_model", "examples", "models", "sources", "zoo",
]

__version__ = "0.1.0"
