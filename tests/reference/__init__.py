"""Independent reference implementations (oracles) for the tests.

Each module computes, from scratch and without importing ``lcs_exact``, what the library computes:
expected values in the tests come from here, from hand derivations written in the tests, or from
SymPy / mpmath / SciPy applied to formulas written in the tests.

* :mod:`reference.linalg`      exact linear algebra over Q in ``fractions.Fraction`` (lists of rows):
                               products, rref, rank, determinant, solve, inverse, kernels, spans,
                               P-matrices
* :mod:`reference.polynomials` polynomials over Q (coefficient lists, lowest degree first)
* :mod:`reference.rcp`         RCP(x0) (5.3)-(5.5) from scratch (Faddeev-LeVerrier, Cramer over
                               Q[s]), Markov parameters and the leading matrices (6.1)
* :mod:`reference.lcp`         every solution of a small LCP by enumerating supports
* :mod:`reference.polyhedra`   feasibility of linear inequalities by Fourier-Motzkin elimination
* :mod:`reference.mechanics`   Moreau's impact rule (Fractions, KKT active sets), contact forces of
                               a constrained mode, and an mpmath event-driven simulator of
                               M q'' + D q' + K q = E^T u with inelastic impacts
* :mod:`reference.flows`       mpmath event location on e^{At} x and event-driven simulators of
                               index-one (piecewise-linear) systems

The tests import them as ``from reference.linalg import rank`` (``tests/`` is on ``sys.path``
under pytest's default import mode, as for ``helpers``).  Shared helpers that are not oracles
(conversions of the library's objects, the paper's systems, tolerances) live in
``tests/helpers.py``.
"""
