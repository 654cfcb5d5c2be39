"""The package's shape (DESIGN.md section 3): imports point down only, no private names cross a
module boundary, user errors belong to the LCSError tree, and importing the package stays light.

The import graph is read from the source with ``ast`` and includes imports made inside functions
(a lazy import of a higher module is still a layer that knows one above it)."""
from __future__ import annotations

import ast
import pathlib
import subprocess
import sys

import lcs_exact

PKG = pathlib.Path(lcs_exact.__file__).parent
MODULES = {p.stem: p for p in PKG.glob("*.py") if p.stem not in ("__init__", "__main__")}


def _imports(path: pathlib.Path) -> set[tuple[str, str]]:
    """(module, name) pairs imported from sibling modules, anywhere in the file."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level == 1 and node.module:
                mod = node.module.split(".")[0]
                out |= {(mod, a.name) for a in node.names}
            elif node.level == 1:  # from . import x
                out |= {(a.name, "*") for a in node.names}
            elif (node.module or "").startswith("lcs_exact."):
                out |= {(node.module.split(".")[1], a.name) for a in node.names}
    return {(m, n) for m, n in out if m in MODULES}


GRAPH = {m: {dep for dep, _ in _imports(p)} for m, p in MODULES.items()}


def _cycles() -> list[list[str]]:
    found, seen = [], set()

    def walk(m, path):
        for n in sorted(GRAPH[m]):
            if n in path:
                cyc = path[path.index(n):] + [n]
                key = frozenset(cyc)
                if key not in seen:
                    seen.add(key)
                    found.append(cyc)
            else:
                walk(n, path + [n])

    for m in sorted(GRAPH):
        walk(m, [m])
    return found


def test_no_import_cycles():
    assert _cycles() == []


#: every module in one order (DESIGN.md section 3 for the core): each imports only modules before it
LAYERS = ["interfaces", "errors", "rational", "convergence", "ratfunc", "subspaces", "lcp", "polyhedra", "balls", "flintlib", "calcium",
          "forms", "expm", "nodes", "reals", "vectors", "modes", "ldcp", "rcpfamily", "selection", "mapplot", "figlabels", "plotting",
          "modemap", "sources", "modelformat", "statespace", "wellposedness", "system", "impacts", "guesses", "roots", "polyroots", "closedforms", "phase", "clock", "flow", "fixnumbers", "fixture",
          "trajectory", "accumulation", "taylormodels", "cascade", "zeno", "bounces", "schedule", "simulate", "fixturereader", "exosystems",
          "mechanics", "circuits", "relays", "examples", "models", "solverevents", "compare", "testing", "sweep", "zoo", "modelfile",
          "cli", "pytest_plugin"]


def test_every_module_has_a_layer_and_the_layers_point_down():
    assert sorted(LAYERS) == sorted(MODULES)
    rank = {m: i for i, m in enumerate(LAYERS)}
    bad = [(m, d) for m in LAYERS for d in GRAPH[m] if rank[d] >= rank[m]]
    assert bad == []


def test_no_function_level_imports_of_the_package():
    """The package's own modules are imported at the top of each module (the command and the
    package face aside): an import inside a function hides a layer."""
    inside = []
    for m, p in MODULES.items():
        if m in ("cli", "pytest_plugin"):  # faces: the plugin loads the engine only when a test asks for it
            continue
        for f in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef)):
                inside += [(m, f.name, node.lineno) for node in ast.walk(f) if isinstance(node, ast.ImportFrom)
                           and (node.level == 1 or (node.module or "").startswith("lcs_exact"))]
    assert inside == []


def test_no_module_over_700_lines():
    long = {m: n for m, p in MODULES.items() if (n := len(p.read_text(encoding="utf-8").splitlines())) > 700}
    assert long == {}


def test_no_private_names_across_modules():
    private = [(m, dep, name) for m, p in MODULES.items() for dep, name in _imports(p)
               if name.startswith("_") and name != "*"]
    assert private == []


def test_user_errors_are_lcs_errors():
    """No bare ValueError/TypeError raised by the library (calcium's documented contract and its
    ctypes layer aside: their callers catch them); every user error is an LCSError subclass that
    is also the builtin."""
    offenders = []
    for m, p in MODULES.items():
        if m in ("calcium", "flintlib"):
            continue
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call) and \
                    isinstance(node.exc.func, ast.Name) and node.exc.func.id in ("ValueError", "TypeError",
                                                                                 "KeyError", "RuntimeError"):
                offenders.append((m, node.lineno, node.exc.func.id))
    assert offenders == []
    assert issubclass(lcs_exact.InvalidArgument, ValueError) and issubclass(lcs_exact.ShapeError, ValueError)


def test_import_is_light():
    """``import lcs_exact`` loads neither SymPy nor matplotlib, numpy, jsonschema or dask."""
    code = ("import sys, lcs_exact; heavy = [m for m in ('sympy', 'matplotlib', 'numpy', 'jsonschema', "
            "'dask') if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_large_chain_runs_without_sympy():
    """A run whose spectra have irreducible factors of degree > 4 (an 8-cart chain) decides that
    no symbolic e^{At} exists from the factor degrees alone (every root is asked for a closed form,
    closed_forms="eager") and never imports SymPy: the import
    alone cost half a second of a 64 x 64 run."""
    code = ("import sys, lcs_exact as L; lcs = L.examples.cart_chain(8); "
            "x0 = [str((-1) ** i) + '/2' for i in range(8)] + [0] * 8; "
            "tr = L.simulate(lcs, x0, 2, digits=20, closed_forms='eager'); "
            "print(len(tr.events), tr.certified, 'sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split()[1:] == ["True", "False"]
    assert int(out.stdout.split()[0]) > 0
