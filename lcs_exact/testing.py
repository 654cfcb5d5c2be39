"""Test helpers for other solvers' test suites: the documented path ``lcs_exact.testing`` of
:mod:`lcs_exact.verify.testing`, which holds the code and its documentation (its home since the
package was divided into subpackages)."""
from __future__ import annotations

from .verify.testing import *  # noqa: F401,F403  (the names of its __all__)
from .verify.testing import __all__  # noqa: F401
