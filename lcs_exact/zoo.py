"""The zoo: certified fixtures of standard problems: the documented path ``lcs_exact.zoo`` of
:mod:`lcs_exact.verify.zoo`, which holds the code and its documentation (its home since the
package was divided into subpackages)."""
from __future__ import annotations

from .verify.zoo import *  # noqa: F401,F403  (the names of its __all__)
from .verify.zoo import __all__  # noqa: F401
