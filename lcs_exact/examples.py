# The documented path lcs_exact.examples of the module lcs_exact.builders.examples, which holds the code (its
# home since the package was divided into subpackages): its names, and its documentation.
from __future__ import annotations

from .builders.examples import *  # noqa: F401,F403  (the names of its __all__)
from .builders.examples import __all__, __doc__  # noqa: F401
