"""Shared test set-up: every test starts from the same precision state.

flint's ``ctx.prec`` and mpmath's ``mp.dps`` are process-global; a test that changes one (or a
library bug that leaks a change) must not change the next test's arithmetic.  The tests' default
mpmath precision is 60 digits (independent derivations are checked to 25-30 digits)."""
from __future__ import annotations

import mpmath
import pytest
from flint import ctx

TEST_DPS = 60


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
# files; the hook below adds the marker where a decorator cannot go.
# ---------------------------------------------------------------------------------------------

#: tests marked here rather than in their files (those files were being edited elsewhere when the
#: fast loop was set up; the markers can move into them): file name -> test function names
SLOW_ELSEWHERE = {
    "test_calcium.py": {"test_memory_is_returned", "test_memory_of_enclosures_strings_and_roots"},
    "test_cascades.py": {"test_cascade_from_the_wall_ends_as_a_certified_accumulation",
                         "test_cascade_after_a_flight_stops_at_the_certified_enclosure",
                         "test_cascade_with_releases_used_to_end_in_an_unresolved_sign",
                         "test_the_proof_does_not_follow_a_wrong_cycle"},
    "test_simulate_scenes.py": {"test_period_pi_return_from_an_irrational_release",
                                "test_impact_cascade_stops_with_a_certified_lower_bound"},
}


def pytest_collection_modifyitems(config, items):
    """The notebooks (nbmake: whole kernels, seconds each) and the tests in SLOW_ELSEWHERE are slow."""
    for item in items:
        path = item.path
        name = getattr(item, "originalname", None) or item.name
        if path.suffix == ".ipynb" or name in SLOW_ELSEWHERE.get(path.name, ()):
            item.add_marker(pytest.mark.slow)
