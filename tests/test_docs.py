"""The reference docs: the Sphinx build passes with warnings as errors, the API page covers every
public name, the model-file page says what the reader accepts (its examples load), the docs cite
no file outside the repository, and the README links every notebook and docs page.  The pages
that show outputs (the getting-started page, the recipe) and the notebooks are executed by
MyST-NB at every build, a cell that raises failing it; the built pages are checked to show the
outputs their prose refers to."""
from __future__ import annotations

import doctest
import html
import importlib
import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

import lcs_exact as L
from lcs_exact.cli import MODEL_KEYS, load_model

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(p for p in DOCS.iterdir() if p.suffix in (".md", ".rst"))
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
EXECUTED = ("getting-started.md", "testing-solvers.md")   # MyST notebooks: their cells run at every build


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("html")
    p = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", "html", str(DOCS), str(out)],
                       cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-5000:]
    return out


def text_of(page: Path) -> str:
    return html.unescape(re.sub(r"<[^>]+>", "", page.read_text(encoding="utf-8")))


@pytest.mark.slow
def test_sphinx_build_passes_with_warnings_as_errors(built):
    for page in PAGES:
        assert (built / f"{page.stem}.html").is_file(), page.name
    index = (built / "index.html").read_text(encoding="utf-8")
    for page in PAGES:   # every page is reachable from the index
        if page.stem != "index":
            assert f'href="{page.stem}.html' in index, page.name


@pytest.mark.slow
def test_api_reference_covers_every_public_name(built):
    api = (DOCS / "api.rst").read_text(encoding="utf-8")
    documented = set(re.findall(r"^\.\. auto(?:class|function|exception|data)::\s+(\w+)\s*$", api, re.M))
    modules = set(re.findall(r"^\.\. automodule::\s+lcs_exact\.([\w.]+)", api, re.M))
    names = set(L.__all__)
    module_names = {n for n in names if type(getattr(L, n)).__name__ == "module"}
    assert names - module_names - documented == set()
    home = {"models": "models", "examples": "builders.examples", "sources": "system.sources",
            "testing": "verify.testing", "zoo": "verify.zoo"}   # the documented paths and the modules that hold the code
    assert {home[m] for m in module_names} | {"models", "builders.examples", "system.sources", "verify.testing",
                                               "verify.zoo", "dynamics.sweep"} <= modules
    assert {"algebra", "numbers", "modes", "display", "system", "dynamics", "builders", "io", "verify"} <= modules  # the doors
    # and the built page holds each name with its docstring's first words
    page = text_of(built / "api.html")
    for name in sorted(names - module_names):
        obj = getattr(L, name)
        assert f"lcs_exact.{name}" in page, name
        first = (obj.__doc__ or "").strip().split("\n")[0][:25].strip()
        if first and "|" not in first and "`" not in first and "*" not in first:
            assert first in page.replace("\n", " ") or first.replace("'", "\u2019") in page.replace("\n", " "), name
    for mod in ("models", "examples", "sources", "testing", "zoo"):
        public = importlib.import_module(f"lcs_exact.{mod}").__all__
        assert public == importlib.import_module(f"lcs_exact.{home[mod]}").__all__
        assert f"lcs_exact.{mod}" in page, mod
        for name in public:
            if mod == "models" and name not in ("mechanical", "driven", "circuit", "circuit_ports", "relay"):
                continue   # the examples, documented under lcs_exact.examples
            assert f"lcs_exact.{home[mod]}.{name}" in page, (mod, name)


def test_model_file_page_matches_the_reader(tmp_path):
    text = (DOCS / "model-files.md").read_text(encoding="utf-8")
    keys = re.findall(r"^\| `(\w+)` \| (?:yes|no) \|", text, re.M)
    assert tuple(keys) == MODEL_KEYS
    blocks = re.findall(r"```(json|toml)\n(.*?)```", text, re.S)
    assert [k for k, _ in blocks] == ["json", "toml", "toml", "toml"]
    seen = set()
    for i, (kind, body) in enumerate(blocks):
        path = tmp_path / f"model{i}.{kind}"
        path.write_text(body, encoding="utf-8")
        lcs, data = load_model(str(path))
        seen |= set(data)
        tr = L.simulate(lcs, lcs.embed(data["x0"]), data["t_end"], digits=10)
        assert tr.certified and len(tr.events) >= 1
    assert seen == set(MODEL_KEYS)   # together the examples use every key
    # the page's unknown-key message is the reader's
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"A": [[0]], "B": [[1]], "C": [[1]], "D": [[0]], "x": 1}))
    with pytest.raises(L.FormatError) as err:
        load_model(str(bad))
    message = "unknown key 'x' (allowed: A, B, C, D, E, F, w, x0, t_end, restitution, name, states, inputs, roles)"
    assert message in str(err.value)
    assert message in " ".join(text.split())


PATH = re.compile(r"(?<![\w/.:-])((?:[\w.-]+/)+[\w.-]+\.(?:md|py|ipynb|json|toml|png|rst|csv|txt|cfg|ini))\b")


@pytest.mark.slow
def test_docs_cite_only_files_in_the_repository(built):
    texts = {p.name: p.read_text(encoding="utf-8") for p in PAGES}
    texts["conf.py"] = (DOCS / "conf.py").read_text(encoding="utf-8")
    texts["api.html (docstrings)"] = text_of(built / "api.html")
    for name, text in texts.items():
        assert "DESIGN" not in text, name
        assert not re.search(r"(?<![\w.])(/usr/|/opt/|/home/|/etc/|/tmp/|/work/|~/|[A-Z]:\\)", text), name
        for path in PATH.findall(text):
            if path.startswith(("docs/_build", "fixtures/", "DIR/")):   # outputs the pages tell the reader to make
                continue
            assert (ROOT / path).exists() or (DOCS / path).exists(), (name, path)


def test_readme_links_every_notebook_and_docs_page():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    links = set(re.findall(r"\]\(([^)\s]+)\)", readme))
    for link in links:
        if not link.startswith(("http://", "https://", "#")):
            assert (ROOT / link.split("#")[0]).exists(), link
    for nb in sorted((ROOT / "notebooks").glob("*.ipynb")):
        assert f"notebooks/{nb.name}" in links, nb.name
    for page in PAGES:
        assert f"docs/{page.name}" in links, page.name
    assert "lcs-exact zoo" in readme and "sphinx-build -W -b html docs" in readme


def test_executed_pages_run_every_python_block():
    """Every Python block of the pages that show outputs is a code cell, run at build time (a plain
    python fence would be shown unrun); the build executes them, and the notebooks, and fails on
    an error."""
    conf = (DOCS / "conf.py").read_text(encoding="utf-8")
    for setting in ('"myst_nb"', 'nb_execution_mode = "force"', "nb_execution_raise_on_error = True"):
        assert setting in conf, setting
    assert '"myst_parser"' not in conf   # myst-nb loads it: not both
    assert (DOCS / "notebooks").resolve() == (ROOT / "notebooks").resolve()
    for name in EXECUTED:
        text = (DOCS / name).read_text(encoding="utf-8")
        assert text.startswith("---\nfile_format: mystnb\n"), name
        fences = set(re.findall(r"^```(\S*)", text, re.M))
        assert "{code-cell}" in fences and fences <= {"{code-cell}", "bash", ""}, (name, fences)
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    guide = index.split(":caption: Guide")[1].split("```")[0].split()
    assert guide[0] == "getting-started" and "testing-solvers" in guide


def shown(built: Path, page: str) -> str:
    """The text of a built page, tags removed and whitespace runs made single spaces."""
    return " ".join(text_of(built / page).split())


@pytest.mark.slow
def test_notebooks_are_pages_with_their_outputs(built):
    index = (built / "index.html").read_text(encoding="utf-8")
    for nb in NOTEBOOKS:
        page = built / "notebooks" / f"{nb.stem}.html"
        assert page.is_file() and f'href="notebooks/{nb.stem}.html' in index, nb.name
        html_text = page.read_text(encoding="utf-8")
        cells = sum(1 for c in json.loads(nb.read_text(encoding="utf-8"))["cells"] if c["cell_type"] == "code")
        assert html_text.count('class="cell_output') >= cells - 2, nb.name   # (a cell may print nothing)
        assert html_text.count("<img") >= 1, nb.name                        # its figures
        assert "Traceback" not in html_text, nb.name


@pytest.mark.slow
def test_getting_started_shows_what_it_says(built):
    page = shown(built, "getting-started.html")
    for text in ("['1', '1 + pi/2']",                                   # the closed forms 1 and 1 + pi/2
                 "x(1-) = [0, -1, -1, 0] x(1+) = [0, -1, 0, 0]",         # the velocity x_2 from -1 to 0
                 "x(2) = [0, -cos(1), 0, sin(1)]",
                 "WELL-POSED", "S(z) = {frozenset({0})}", "u(s)=((s^2 + s + 1)/(s^2 + 1))",
                 "S(0) = {frozenset(), frozenset({0})} S(-1) = set()", "Deadlock: deadlock at t = 0",
                 "t* = 190*sqrt(218)/327", "x(9) = (0, 0, 1)", "True",
                 "closed form: 3*pi/4", "closed form: 11*pi/4", "sources: SourceBlock(states=(1, 2)",
                 "301 samples", "1 + pi/2", "every compared point inside"):
        assert text in page, text
    assert page.count("closed form: -") == 2   # the diode's turn-on times: certified, no closed form claimed
    assert (built / "getting-started.html").read_text(encoding="utf-8").count("<img") == 3


@pytest.mark.slow
def test_recipe_shows_what_it_says(built):
    page = shown(built, "testing-solvers.html")
    assert "8 failed, 7 passed" in page and "4 passed" in page
    for name in ("bouncing_ball", "ball_column_3", "newtons_cradle_3",   # restitution: inelastic impacts fail
                 "cart_chain_4", "half_wave_rectifier", "diode_bridge_cap_filter", "filippov_spiral",
                 "buck_converter_dcm"):  # the schedule ignored
        assert f"FAILED test_my_solver.py::test_backward_euler[{name}]" in page, name
    for text in ("integrated: amplitude 0.918978 at t = 13; case.sources: 1.000000",
                 "{'atol': 0.01} passed", "{'atol': 0.001} AssertionError", "{'atol': 0.01, 'event_tol': 0} AssertionError",
                 "component q': solver 0.0, exact -3.74845"):
        assert text in page, text
    order = float(re.search(r"order (\d\.\d\d)", page).group(1))
    assert 0.9 <= order <= 1.1
    assert (built / "testing-solvers.html").read_text(encoding="utf-8").count("<img") == 1


@pytest.mark.slow
def test_extensions_page_examples_run():
    """The worked examples of docs/extensions.md (its ``>>>`` blocks: the compliant ball, the
    moving plane, the belt) run and print what the page shows; the values they show are the
    page's hand derivations (sqrt(2h/g), pi/6 and 13 pi/6, mu N / (k v_b) = 3/4, asin(2/3)/2),
    checked against mpmath in tests/test_compliance.py and tests/test_sourced_scenes.py."""
    text = (DOCS / "extensions.md").read_text(encoding="utf-8")
    blocks = [textwrap.dedent(body) for indent, body in re.findall(r"^( *)```python\n(.*?)^\1```", text, re.S | re.M)
              if ">>>" in body]
    assert len(blocks) >= 3
    test = doctest.DocTestParser().get_doctest("\n\n".join(blocks), {}, "extensions.md", str(DOCS / "extensions.md"), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.failures == 0 and runner.tries >= 15
