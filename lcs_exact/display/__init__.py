"""Drawing: mode colours and labels (``mapplot``, ``figlabels``), trajectory and mode-map
figures (``plotting``), convergence plots and slopes (``convergence``).  matplotlib is imported
inside the drawing functions only.  Imports ``algebra``, ``numbers``, ``modes``.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .figlabels import derived_outputs, pair_label
from .plotting import plot_mode_map, plot_trajectory
from .convergence import convergence_slope, plot_convergence

__all__ = ["derived_outputs", "pair_label", "plot_mode_map", "plot_trajectory", "convergence_slope",
           "plot_convergence"]
