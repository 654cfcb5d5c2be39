"""Sources (exogenous signals) for driven systems: the documented path ``lcs_exact.sources`` of
:mod:`lcs_exact.system.sources`, which holds the code and its documentation (its home since the
package was divided into subpackages)."""
from __future__ import annotations

from .system.sources import *  # noqa: F401,F403  (the names of its __all__)
from .system.sources import __all__  # noqa: F401
