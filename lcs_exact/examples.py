"""The paper's examples and the scenes of the docs: the documented path ``lcs_exact.examples`` of
:mod:`lcs_exact.builders.examples` (its home since the package was divided into subpackages), which holds the code and the
documentation."""
from __future__ import annotations

from .builders.examples import *  # noqa: F401,F403  (the names of its __all__)
from .builders.examples import __all__  # noqa: F401
