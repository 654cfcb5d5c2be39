"""The pytest plugin of lcs_exact (entry point ``pytest11``, installed with the package): the
fixture ``lcs_zoo_case`` is parametrized over the shipped zoo (:func:`lcs_exact.zoo.cases`), one
test per case with the case's name as its id, so a numerical solver's test is::

    def test_my_solver(lcs_zoo_case):
        t, X = my_solver(lcs_zoo_case.A, lcs_zoo_case.B, lcs_zoo_case.C, lcs_zoo_case.D,
                         lcs_zoo_case.x0, lcs_zoo_case.t_end)
        lcs_zoo_case.assert_matches(t, X, atol=1e-3)

``--lcs-zoo NAME,...`` runs only some cases.  pytest loads every installed plugin at its start:
the zoo (and the engine) is imported only when a test asks for ``lcs_zoo_case``.
"""
from __future__ import annotations

import pytest

__all__ = ["lcs_zoo_case", "pytest_addoption", "pytest_generate_tests"]


def pytest_addoption(parser):
    parser.getgroup("lcs_exact").addoption(
        "--lcs-zoo", metavar="NAME,...", default=None,
        help="run the lcs_zoo_case tests on these zoo cases only (comma-separated names; default: all)")


@pytest.fixture
def lcs_zoo_case(request):
    """A case of the lcs_exact zoo (:class:`lcs_exact.zoo.ZooCase`): float64 A, B, C, D, x0,
    t_end, restitution, plant, sources, and ``assert_matches(t, X, atol=...)``."""
    return request.param


def pytest_generate_tests(metafunc):
    if "lcs_zoo_case" in metafunc.fixturenames:
        from lcs_exact import zoo  # only when a test asks for a case (see the module docstring)
        chosen = zoo.cases(metafunc.config.getoption("lcs_zoo"))
        metafunc.parametrize("lcs_zoo_case", chosen, ids=[c.name for c in chosen], indirect=True)
