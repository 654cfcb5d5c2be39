"""Checking other solvers: events in a solver's data (``solverevents``), comparison with a
fixture (``compare``), the assert helper (``testing``) and the zoo of certified fixtures (``zoo``).

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .compare import compare, ComparisonReport, convergence_order, read_solution_csv
from .testing import assert_matches_fixture
from .zoo import cases, write_zoo, ZooCase

__all__ = ["compare", "ComparisonReport", "convergence_order", "read_solution_csv", "assert_matches_fixture",
           "cases", "write_zoo", "ZooCase"]
