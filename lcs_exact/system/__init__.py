"""The LCS and what it carries: ``LCS`` (``lcs``), its sources (``signals``: the signals;
``sources``: signals as exosystem states), the model-file writer (``modelformat``),
python-control state spaces (``statespace``), well-posedness (``wellposedness``), Newton's
impact law (``impacts``) and mode maps (``modemap``).  Imports the doors below it.

This is the subpackage's door: other subpackages and users import what ``__all__`` names,
from here; the modules behind it are its own.
"""
from __future__ import annotations

from .signals import as_source, constant, cosine, exponential, parse_source, polynomial, sine, Source
from .sources import AppendedStates, exosystem, Exosystem, source_block, SourceBlock
from .modelformat import MATRIX_KEYS, MODEL_KEYS, model_data, write_model_file
from .statespace import signal_names, time_response
from .wellposedness import WellPosedness
from .lcs import LCS
from .impacts import newton_impact
from .modemap import ModeMap, Region

__all__ = ["AppendedStates", "as_source", "constant", "cosine", "exosystem", "Exosystem", "exponential",
           "parse_source", "polynomial", "sine", "Source", "source_block", "SourceBlock", "MATRIX_KEYS",
           "MODEL_KEYS", "model_data", "write_model_file", "signal_names", "time_response", "WellPosedness",
           "LCS", "newton_impact", "ModeMap", "Region"]
