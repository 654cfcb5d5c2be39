# The documented path lcs_exact.zoo of the module lcs_exact.verify.zoo, which holds the code (its
# home since the package was divided into subpackages): its names, and its documentation.
from __future__ import annotations

from .verify.zoo import *  # noqa: F401,F403  (the names of its __all__)
from .verify.zoo import __all__, __doc__  # noqa: F401
