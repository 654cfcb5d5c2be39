"""Model files (JSON or TOML) read back as an LCS: the documented path ``lcs_exact.modelfile`` of
:mod:`lcs_exact.io.modelfile`, which holds the code and its documentation (its home since the
package was divided into subpackages)."""
from __future__ import annotations

from .io.modelfile import *  # noqa: F401,F403  (the names of its __all__)
from .io.modelfile import __all__  # noqa: F401
