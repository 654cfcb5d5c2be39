"""The package's shape (docs/architecture.md): subpackages by subject, each with one door (its
``__init__``, whose ``__all__`` names what others may import); imports point down only, across
subpackages only through doors; no private names cross a module boundary; user errors belong to the
LCSError tree; importing the package stays light.

The import graph is read from the source with ``ast`` and includes imports made inside functions
(a lazy import of a higher module is still a layer that knows one above it)."""
from __future__ import annotations

import ast
import importlib
import pathlib
import subprocess
import sys

import lcs_exact

PKG = pathlib.Path(lcs_exact.__file__).parent


def _name(path: pathlib.Path) -> str:
    """The dotted name of a module under lcs_exact: ``phases.flow``; a door is its package's
    name (``dynamics``), the package's own ``__init__`` is ``__init__``."""
    parts = path.relative_to(PKG).with_suffix("").parts
    if parts[-1] == "__init__" and len(parts) > 1:
        parts = parts[:-1]
    return ".".join(parts)


MODULES = {_name(p): p for p in PKG.rglob("*.py") if p.name != "__main__.py"}

#: the subpackages, bottom up: each imports only the doors of those before it
SUBPACKAGES = ["algebra", "numbers", "modes", "display", "system", "phases", "accumulations", "dynamics", "builders", "io",
               "verify"]

#: each subpackage's modules, bottom up: each imports only modules before it (and lower doors)
LAYERS = {
    "algebra": ["rational", "matrixfunctions", "ratfunc", "subspaces", "lcp", "polyhedra"],
    "numbers": ["balls", "duals", "flintlib", "calcium", "forms", "algebraics", "krylov", "expm", "laplace", "rootforms", "taylorsteps", "nodes", "reals", "relations", "vectors", "algebraicvectors",
                "expvectors", "closedforms", "taylormodels"],
    "modes": ["mode", "ldcp", "rcpfamily", "selection"],
    "display": ["convergence", "mapplot", "figlabels", "canvas", "plotting"],
    "system": ["modemap", "signals", "sources", "modelformat", "statespace", "wellposedness", "lcs", "impacts"],
    "phases": ["guesses", "roots", "taylorsum", "polyroots", "eventstep", "phase", "clock", "flow", "fixnumbers", "fixture", "events",
               "timeline", "undetermined", "exports", "trajectory"],
    "accumulations": ["symmetry", "accumulation", "cascade", "zeno", "bouncecycles", "bounces", "collapsecycles", "collapses"],
    "dynamics": ["schedule", "options", "simulate", "sweep"],
    "builders": ["exosystems", "mechanics", "circuits", "relays", "examples"],
    "io": ["fixturereader", "modelfile"],
    "verify": ["solverevents", "compare", "testing", "zoo"],
}

#: the modules at the top: below every subpackage (any module may import them) ...
BASE = ["interfaces", "errors"]
#: ... and above every subpackage: the package's faces, which import doors
FACES = ["models", "cli", "pytest_plugin", "__init__"]
#: documented module paths kept as thin modules: each re-exports the module behind a door that holds its code
REEXPORTS = {"examples": "builders.examples", "sources": "system.sources", "testing": "verify.testing",
             "zoo": "verify.zoo", "modelfile": "io.modelfile"}


def _package(mod: str) -> str:
    """The package a module's relative imports start from ("" for the top)."""
    if mod in SUBPACKAGES or mod == "__init__":
        return "" if mod == "__init__" else mod
    return mod.rpartition(".")[0]


def _subpackage(mod: str) -> str | None:
    head = mod.split(".")[0]
    return head if head in SUBPACKAGES else None


def _target(dotted: str) -> str:
    return "__init__" if dotted == "" else dotted


def _imports(path: pathlib.Path) -> set[tuple[str, str]]:
    """(module, name) pairs this file imports from the package, anywhere in the file; a module
    imported as a name (``from . import calcium``) is (that module, "*")."""
    mod = _name(path)
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            base = _package(mod).split(".") if _package(mod) else []
            base = base[:len(base) - (node.level - 1)] if node.level > 1 else base
            pkg = ".".join(base + ([node.module] if node.module else []))
        elif node.module == "lcs_exact" or (node.module or "").startswith("lcs_exact."):
            pkg = node.module[len("lcs_exact."):] if "." in node.module else ""
        else:
            continue
        for a in node.names:
            sub = f"{pkg}.{a.name}" if pkg else a.name
            if sub in MODULES and (a.name not in _door(pkg) or _subpackage(mod) == pkg):
                out.add((sub, "*"))
            else:
                out.add((_target(pkg), a.name))
    return out


def _door(pkg: str) -> set[str]:
    """The names a subpackage's door exports (``from .dynamics import simulate`` is the function
    of the door, not the module dynamics/simulate.py)."""
    return set(importlib.import_module(f"lcs_exact.{pkg}").__all__) if pkg in SUBPACKAGES else set()


GRAPH = {m: {dep for dep, _ in _imports(p)} - {m} for m, p in MODULES.items()}


def _cycles() -> list[list[str]]:
    """The cycles a depth-first walk meets (none, or at least one of each strongly connected part)."""
    found, state = [], {}

    def walk(m, path):
        state[m] = "open"
        for n in sorted(GRAPH.get(m, ())):
            if state.get(n) == "open":
                found.append(path[path.index(n):] + [n])
            elif n not in state:
                walk(n, path + [n])
        state[m] = "done"

    for m in sorted(GRAPH):
        if m not in state:
            walk(m, [m])
    return found


def test_every_import_names_a_module_of_the_package():
    """No import of a path that is not a file (an old path before the subpackages, say)."""
    missing = sorted((m, dep) for m, deps in GRAPH.items() for dep in deps if dep not in MODULES)
    assert missing == []


def test_no_import_cycles():
    assert _cycles() == []


def test_every_module_lives_in_a_subpackage_or_is_named_at_the_top():
    top = {m for m in MODULES if "." not in m and m not in SUBPACKAGES}
    assert top == set(BASE) | set(FACES) | set(REEXPORTS)
    assert {m.split(".")[0] for m in MODULES if "." in m} == set(SUBPACKAGES)
    assert all((PKG / sub / "__init__.py").exists() for sub in SUBPACKAGES)
    inside = {m for m in MODULES if "." in m}
    assert inside == {f"{sub}.{m}" for sub, mods in LAYERS.items() for m in mods}


def test_the_thin_modules_at_documented_paths_only_re_export():
    """``lcs_exact.examples`` and the like hold no code: a docstring and the import of their home."""
    for mod, home in REEXPORTS.items():
        tree = ast.parse(MODULES[mod].read_text(encoding="utf-8"))
        body = [n for n in tree.body if not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
        assert all(isinstance(n, ast.ImportFrom) for n in body), mod
        assert {dep for dep, _ in _imports(MODULES[mod])} == {home}, mod
        assert importlib.import_module(f"lcs_exact.{mod}").__all__ == importlib.import_module(f"lcs_exact.{home}").__all__
        assert getattr(lcs_exact, mod) is importlib.import_module(f"lcs_exact.{mod}")   # after import lcs_exact alone


def test_layers_point_down_and_cross_subpackages_only_through_doors():
    """Inside a subpackage a module imports the ones before it in LAYERS; across subpackages it
    imports a lower subpackage's door, never a module behind it; the base modules (errors,
    interfaces) import nothing of the package; the faces import doors."""
    rank = {sub: i for i, sub in enumerate(SUBPACKAGES)}
    bad = []
    for m, deps in GRAPH.items():
        sub = _subpackage(m)
        for d in deps:
            if d in BASE:
                if m in BASE and BASE.index(d) >= BASE.index(m):
                    bad.append((m, d))
                continue
            dsub = _subpackage(d)
            if m in REEXPORTS:
                ok = d == REEXPORTS[m]
            elif m in BASE:
                ok = False
            elif sub is None:                               # a face: doors, and the package itself
                ok = d in SUBPACKAGES or d in FACES or d in REEXPORTS
            elif dsub == sub:                               # inside a subpackage
                order = LAYERS[sub]
                ok = m == sub or order.index(d.split(".")[1]) < order.index(m.split(".")[1])
            else:                                           # another subpackage: its door, lower
                ok = d == dsub and rank[dsub] < rank[sub]
            if not ok:
                bad.append((m, d))
    assert sorted(bad) == []


def test_a_door_names_what_others_import_through_it():
    """Every name imported through a door is in the door's ``__all__``, and each of those names
    is the package's own (a door re-exports its modules, or a lower door)."""
    missing = []
    for m, p in MODULES.items():
        for dep, name in _imports(p):
            if dep in SUBPACKAGES and _subpackage(m) != dep and name != "*":
                if name not in importlib.import_module(f"lcs_exact.{dep}").__all__:
                    missing.append((m, dep, name))
    assert missing == []
    for sub in SUBPACKAGES:
        door = importlib.import_module(f"lcs_exact.{sub}")
        assert len(door.__all__) == len(set(door.__all__)), sub
        assert all(hasattr(door, n) for n in door.__all__), sub


def test_old_module_paths_are_the_moved_modules():
    """The paths of the modules before the subpackages (``lcs_exact.rational``, ...) still import,
    as the module itself (so a monkeypatch through either reaches the same module)."""
    for old, new in lcs_exact._MOVED.items():
        assert not (PKG / f"{old}.py").exists(), old
        assert importlib.import_module(f"lcs_exact.{old}") is importlib.import_module(f"lcs_exact.{new}")
        assert old in lcs_exact.__all__ or getattr(lcs_exact, old) is importlib.import_module(f"lcs_exact.{new}")
    from lcs_exact.simulate import CASCADE_BUDGET  # noqa: F401  the module, while lcs_exact.simulate is the function
    assert callable(lcs_exact.simulate) and callable(lcs_exact.sweep) and callable(lcs_exact.compare)


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


def test_no_function_over_100_lines():
    """No function or method in the package is longer than 100 lines, counted from its ``def`` to
    its last line (``end_lineno - lineno + 1`` of the ``ast`` node: the signature, the docstring
    and the body, decorators aside); a nested function counts in its parent too.  A function that
    grows past it is split into functions named after what they compute."""
    long = {}
    for m, p in MODULES.items():
        for f in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef)) and f.end_lineno - f.lineno + 1 > 100:
                long[f"{m}.{f.name}:{f.lineno}"] = f.end_lineno - f.lineno + 1
    assert long == {}


def test_no_private_names_across_modules():
    private = [(m, dep, name) for m, p in MODULES.items() for dep, name in _imports(p)
               if name.startswith("_") and not name.startswith("__")]
    assert private == []


def test_user_errors_are_lcs_errors():
    """No bare ValueError/TypeError raised by the library (calcium's documented contract and its
    ctypes layer aside: their callers catch them); every user error is an LCSError subclass that
    is also the builtin."""
    offenders = []
    for m, p in MODULES.items():
        if m in ("numbers.calcium", "numbers.flintlib"):
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


def test_simulate_of_the_two_carts_is_light():
    """``simulate`` of the paper's two carts (section 7) and of the two carts with the hook
    (Example 8.3) imports neither numpy nor SymPy or SciPy: the float estimates that guide the
    root search of a small system use Python's complex arithmetic (numpy's import was 50-100 ms of
    the first simulate in a process; a large system's estimates still use numpy)."""
    code = ("import sys, lcs_exact as L; from lcs_exact.examples import two_carts, two_carts_with_hook; "
            "c = two_carts(); tr = L.simulate(c, L.expm_action(c.A, -1, [0, -1, -1, 0]), 3, digits=30); "
            "tr2 = L.simulate(two_carts_with_hook(), [0, 0, -1, 2], 3); "
            "print(len(tr.events), tr.certified, len(tr2.events) > 0, "
            "[m for m in ('numpy', 'sympy', 'scipy') if m in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "2 True True []"


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
