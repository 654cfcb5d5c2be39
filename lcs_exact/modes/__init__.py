"""The modes of an LCS and which one is selected (the paper's sections 3-5): the mode I with
V_I, T_I, P_I, F_I, A_I (``mode``), LDCP_kappa(x0) (``ldcp``), the family of RCP(x0) over Q(s)
(``rcpfamily``) and the selection S(x0), the initial solution and its impulse (``selection``).
Imports ``algebra`` and ``numbers``.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .mode import format_mode, latex_mode, Mode, mode_order
from .selection import (admissibility_conditions, admissibility_forms, impulse_forms, initial_solution,
                        initial_solution_groups, is_regular, ldcp, rcp, rcp_data, select_modes, state_groups,
                        undetermined_inputs)

__all__ = ["format_mode", "latex_mode", "Mode", "mode_order", "admissibility_conditions",
           "admissibility_forms", "impulse_forms", "initial_solution", "initial_solution_groups",
           "is_regular", "ldcp", "rcp", "rcp_data", "select_modes", "state_groups", "undetermined_inputs"]
