"""Exact and certified numbers: the precision policy and balls (``balls``), FLINT's Calcium
through ctypes (``flintlib``, ``calcium``), balls with derivatives (``duals``), light closed
forms (``forms``), algebraic numbers pickled and in radicals (``algebraics``), e^{At}
(``expm``, symbolically ``laplace``; on Taylor steps, ``taylorsteps``), exact reals and vectors (``nodes``, ``reals``, ``relations``, ``vectors``, ``expvectors``),
closed-form candidates and their proofs (``closedforms``, symbolic candidates ``rootforms``) and Taylor models (``taylormodels``).
Imports ``algebra``.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .balls import (ACCURACY_HEADROOM, DEFAULT_POLICY, MAX_DIGITS, accuracy_bits, ball_sign, check_digits, Deadline,
                    digits_to_bits, dyadic, dyadic_lower, dyadic_upper, Policy, workprec)
from .duals import Dual, norm2_bound, vector_norm2_bound
from . import calcium
from .forms import Closed, sympy_proves_zero
from .expm import Spectrum, spectrum_of
from .taylorsteps import STEP_NORM, TaylorSteps, first_step
from .algebraics import ca_from_state, ca_state
from .reals import AlgebraicReal, as_real, RationalReal, Real
from .vectors import (as_exact_vector, as_state, ca_matvec, ComponentsVector, ExactVector,
                      homogenized, ProjectedVector, RationalVector, ScaledVector)
from .algebraicvectors import algebraic_vector
from .expvectors import expm_action, ExpVector, orbit_start
from .closedforms import (candidates, prove_flat_touch, prove_root, prove_root_is, prove_touch, prove_zero_at,
                          symbolic_candidates)
from .taylormodels import (Box, interval, ipow, Model, NoProof, positive_on, series_root, shift, Space, terms,
                           truncate, WorkBudget)

__all__ = ["ACCURACY_HEADROOM", "DEFAULT_POLICY", "MAX_DIGITS", "accuracy_bits", "ball_sign", "check_digits", "Deadline",
           "digits_to_bits", "dyadic", "dyadic_lower", "dyadic_upper", "Policy", "workprec", "Dual", "norm2_bound",
           "vector_norm2_bound", "calcium",
           "Closed", "sympy_proves_zero", "Spectrum", "spectrum_of", "STEP_NORM", "TaylorSteps", "first_step", "AlgebraicReal", "as_real", "ca_from_state", "ca_state",
           "RationalReal", "Real", "algebraic_vector", "as_exact_vector", "as_state", "ca_matvec",
           "ComponentsVector", "ExactVector", "expm_action", "ExpVector", "homogenized", "orbit_start",
           "ProjectedVector", "RationalVector", "ScaledVector", "candidates", "prove_root", "prove_root_is",
           "prove_flat_touch", "prove_touch", "prove_zero_at", "symbolic_candidates", "Box", "interval", "ipow", "Model",
           "NoProof", "positive_on", "series_root", "shift", "Space", "terms", "truncate", "WorkBudget"]
