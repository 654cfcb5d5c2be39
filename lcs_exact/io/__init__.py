"""Reading files back: fixtures (``fixturereader``: a fixture as a trajectory, replayed by
``dynamics``) and model files (``modelfile``).  The writers live with what they write
(``dynamics``: ``Trajectory.to_fixture``; ``system``: ``LCS.to_model``).

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .fixturereader import FixtureTrajectory, read_fixture
from .modelfile import MODEL_KEYS, check_exponents, load_model, read_model, read_model_data

__all__ = ["FixtureTrajectory", "read_fixture", "MODEL_KEYS", "check_exponents", "load_model", "read_model",
           "read_model_data"]
