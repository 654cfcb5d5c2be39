# The documented path lcs_exact.modelfile of the module lcs_exact.io.modelfile, which holds the code (its
# home since the package was divided into subpackages): its names, and its documentation.
from __future__ import annotations

from .io.modelfile import *  # noqa: F401,F403  (the names of its __all__)
from .io.modelfile import __all__, __doc__  # noqa: F401
