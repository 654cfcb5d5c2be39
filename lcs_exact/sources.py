# The documented path lcs_exact.sources of the module lcs_exact.system.sources, which holds the code (its
# home since the package was divided into subpackages): its names, and its documentation.
from __future__ import annotations

from .system.sources import *  # noqa: F401,F403  (the names of its __all__)
from .system.sources import __all__, __doc__  # noqa: F401
