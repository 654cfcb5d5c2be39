"""Sphinx configuration: the reference docs of lcs_exact.

Build (what the tests run, warnings are errors)::

    python -m pip install -e ".[docs]"
    sphinx-build -W -b html docs docs/_build/html
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

# the docs (and the kernels that execute the notebooks, which inherit PYTHONPATH) document the
# checkout they are built from, not whichever lcs_exact is installed
ROOT = str(Path(__file__).resolve().parents[1])
sys.path.insert(0, ROOT)
os.environ["PYTHONPATH"] = os.pathsep.join([ROOT] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])

import lcs_exact  # noqa: E402

project = "lcs_exact"
author = "the lcs_exact authors"
copyright = "the lcs_exact authors"
release = version = lcs_exact.__version__

extensions = [
    "myst_nb",                # the Markdown pages (MyST) and the notebooks, executed at build time
    "sphinx.ext.autodoc",     # the API reference from the docstrings
    "sphinx.ext.napoleon",    # numpydoc-style docstrings
]
root_doc = "index"
exclude_patterns = ["_build", "notebooks/.ipynb_checkpoints"]

# Markdown: the pages write formulas in plain text (no dollar math); headings get anchors
myst_heading_anchors = 3
myst_enable_extensions = ["colon_fence"]

# Notebooks (docs/notebooks is a link to the repository's notebooks/) and the getting-started
# page (a MyST text notebook) are executed at every build: every number and figure shown is the
# one this checkout computes; a cell that raises fails the build.
nb_execution_mode = "force"
nb_execution_timeout = 300          # seconds per cell
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_preserve_defaults = True
autoclass_content = "both"
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_ivar = True       # "Attributes" sections as fields: no second description of a property
napoleon_use_rtype = False

html_theme = "alabaster"
html_theme_options = {"page_width": "1240px", "sidebar_width": "240px", "body_max_width": "none"}  # room for outputs
html_title = f"lcs_exact {release}"
html_static_path = ["_static"]
html_css_files = ["outputs.css"]   # long lines of cell outputs (failure messages) wrap instead of scrolling


# ---------------------------------------------------------------------------------------------
# Plain-text formulas in docstrings
# ---------------------------------------------------------------------------------------------
# The docstrings write formulas as plain text, as the paper's notation reads in a terminal:
# absolute values |x|, index sets B_.I, norms |X - x|.  In reStructuredText "|x|" is a
# substitution and "B_" a hyperlink reference, so each such formula would be an error.  This
# hook escapes "|" and a word's trailing "_" in prose lines only: doctests, literal blocks,
# inline literals and roles are left as they are.  Nothing is hidden: every docstring renders.

import re

_KEEP = re.compile(r"(``.+?``|:[\w:.+-]+:`[^`]*`|`[^`]*`_{0,2})")
_TRAILING_UNDERSCORE = re.compile(r"(?<=\w)_(?=[^\w]|$)")


def _escape_prose(segment: str) -> str:
    segment = re.sub(r"(?<!\\)\|", r"\\|", segment)
    return _TRAILING_UNDERSCORE.sub(r"\\_", segment)


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def plain_text_formulas(app, what, name, obj, options, lines):
    literal_indent = None   # inside a literal block: the indentation of the line that opened it
    doctest = False
    for i, line in enumerate(lines):
        stripped = line.strip()
        if literal_indent is not None:
            if not stripped or _indent(line) > literal_indent:
                continue
            literal_indent = None
        if stripped.startswith(">>>"):
            doctest = True
        if doctest:
            if not stripped:
                doctest = False
            continue
        if stripped.startswith(".. "):   # a directive line (its own syntax)
            continue
        parts = _KEEP.split(line)
        lines[i] = "".join(p if j % 2 else _escape_prose(p) for j, p in enumerate(parts))
        if stripped.endswith("::"):
            literal_indent = _indent(line)


def setup(app):
    app.connect("autodoc-process-docstring", plain_text_formulas)
