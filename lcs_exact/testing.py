# The documented path lcs_exact.testing of the module lcs_exact.verify.testing, which holds the code (its
# home since the package was divided into subpackages): its names, and its documentation.
from __future__ import annotations

from .verify.testing import *  # noqa: F401,F403  (the names of its __all__)
from .verify.testing import __all__, __doc__  # noqa: F401
