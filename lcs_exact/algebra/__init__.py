"""Exact linear algebra over Q and Q(s): coercion of input to rationals, matrices and vectors
(``rational``), functions of a matrix (``matrixfunctions``: p(A), adj(sI - A), eigenvalue moduli),
rational functions and the resolvent (``ratfunc``), subspaces (``subspaces``),
LCPs (``lcp``: P-matrix test, Murty, Lemke, enumeration) and polyhedra (``polyhedra``).
Imports only ``lcs_exact.errors``.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .rational import (MAX_DIMENSION, MAX_HORIZON_FAST, MAX_HORIZON_SLOW, MAX_KAPPA, MAX_MARKOV_INDEX,
                       MAX_PREC_BITS, as_list, check_enumerable, format_form, hstack, identity, is_zero, lex_sign,
                       mat_equal, mat_rows, matrix_to_sympy, selection_matrix, sign_of_form, submatrix, to_fmpq, to_int, to_matrix,
                       to_short, to_vector, vector_entries, vstack, zeros)
from .matrixfunctions import adjugate_coefficients, eigenvalue_moduli, norm_inf, row_norms, poly_at_matrix, polys_at_matrix
from .ratfunc import laurent_coefficients, RationalFunction, RationalMatrix, resolvent
from .subspaces import (image, in_row_span, intersection, invariant_forms, kernel, kernel_basis, left_kernel,
                        orbit_zero_forms, projected_forms, projection, projection_along, pulled_back_forms, rank, row_basis, RowSpan, solve_any)
from .lcp import all_solutions, is_p_matrix, basis_inputs, murty, murty_signs, p_matrix_violation, solve_lcp
from .polyhedra import eliminate, find_point

__all__ = ["MAX_DIMENSION", "MAX_HORIZON_FAST", "MAX_HORIZON_SLOW", "MAX_KAPPA", "MAX_MARKOV_INDEX",
           "MAX_PREC_BITS", "adjugate_coefficients", "as_list", "check_enumerable", "eigenvalue_moduli",
           "format_form", "hstack", "identity", "is_zero", "norm_inf", "row_norms", "lex_sign", "mat_equal", "mat_rows",
           "matrix_to_sympy", "poly_at_matrix", "polys_at_matrix", "selection_matrix", "sign_of_form", "submatrix", "to_fmpq", "to_int", "to_matrix",
           "to_short", "to_vector", "vector_entries", "vstack", "zeros", "laurent_coefficients",
           "RationalFunction", "RationalMatrix", "resolvent", "image", "in_row_span", "intersection",
           "invariant_forms", "kernel", "kernel_basis", "left_kernel", "orbit_zero_forms", "projected_forms", "projection", "projection_along", "pulled_back_forms",
           "rank", "row_basis", "RowSpan", "solve_any", "all_solutions", "is_p_matrix", "murty", "murty_signs", "basis_inputs",
           "p_matrix_violation", "solve_lcp", "eliminate", "find_point"]
