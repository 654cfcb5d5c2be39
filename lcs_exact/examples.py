"""The paper's systems and the standard scenes: the documented path ``lcs_exact.examples`` of
:mod:`lcs_exact.builders.examples`, which holds the code and its documentation (its home since the
package was divided into subpackages)."""
from __future__ import annotations

from .builders.examples import *  # noqa: F401,F403  (the names of its __all__)
from .builders.examples import __all__  # noqa: F401
