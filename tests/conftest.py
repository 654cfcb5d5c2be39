"""Shared test set-up: every test starts from the same precision state.

flint's ``ctx.prec`` and mpmath's ``mp.dps`` are process-global; a test that changes one (or a
library bug that leaks a change) must not change the next test's arithmetic.  The tests' default
mpmath precision is 60 digits (independent derivations are checked to 25-30 digits)."""
from __future__ import annotations

import mpmath
import pytest
from flint import ctx

TEST_DPS = 60

pytest_plugins = ["pytester"]  # tests/test_zoo_cases.py runs a solver's four-line test file with the zoo plugin


@pytest.fixture(autouse=True)
def _reset_precision():
    old_prec, old_dps = ctx.prec, mpmath.mp.dps
    ctx.prec, mpmath.mp.dps = 53, TEST_DPS
    yield
    leaked = ctx.prec != 53
    ctx.prec, mpmath.mp.dps = old_prec, old_dps
    assert not leaked, "flint's ctx.prec was left changed by the code under test"


# ---------------------------------------------------------------------------------------------
# the fast loop: ``pytest -m "not slow"`` (README).  Slow tests carry @pytest.mark.slow in their
# files; the notebooks (nbmake items, where a decorator cannot go) are marked here.
# ---------------------------------------------------------------------------------------------

def pytest_collection_modifyitems(config, items):
    """The notebooks (nbmake: whole kernels, seconds each) are slow."""
    for item in items:
        if item.path.suffix == ".ipynb":
            item.add_marker(pytest.mark.slow)
