"""Every parameter of every public callable is documented (issue 29 item 6; python-control's
practice, its ``control/tests/docstrings_test.py``).

Public callables are the functions and classes named in ``lcs_exact.__all__``, in the ``__all__``
of each subpackage's door (docs/architecture.md), of a module a door names there
(``lcs_exact.numbers.calcium``) and of the documented thin modules (``lcs_exact.models``,
``.examples``, ``.sources``, ``.testing``, ``.zoo``, ``.modelfile``); of each such class, its
public methods (defined in the package, names not starting with ``_``; properties have no
parameters) and its constructor.

The rule: each parameter of ``inspect.signature`` must have an entry in a numpydoc ``Parameters``
or ``Other Parameters`` section of the callable's docstring (``inspect.getdoc``, so a method that
overrides a documented one without a docstring of its own is held to the one it inherits).  An
entry is a line at the section's indentation, ``name : type`` or ``name`` (several names may share
one entry: ``x, y : int``).  Exceptions and their spellings:

* ``self`` and ``cls`` are not parameters of the call;
* ``*args`` is documented by an entry that begins with one star (``*args``, ``*rows``), and
  ``**kwargs`` by an entry that begins with two (``**kwargs``, ``**simulate_options``): the entry
  names the keywords the function passes on, which may be wider than its own name for them;
* a class's constructor (the class's signature, when ``__init__`` or ``__new__`` is the package's,
  not inherited from ``object``, ``Exception``, ``tuple`` or ``Enum``) is documented in the class
  docstring or in ``__init__``'s; a dataclass's fields may be documented in its ``Attributes``
  section, which the constructor's parameters are (one description, not two);
* a function without parameters needs no section.

``PENDING`` lists the callables still to be documented (as python-control's skip lists; empty
since issue 29 item 6 was finished): their gaps are tolerated while the work goes on, every other
callable is held to the rule, and an entry whose callable is complete fails
``test_pending_is_current``, so the list only shrinks.

The sections are read by the small parser below, not by ``numpydoc.docscrape``: the docs are
rendered by Sphinx's napoleon (docs/conf.py), not by numpydoc, and the question asked here (which
names does a section list) takes a dozen lines; a dependency for it would add a second reading of
the docstrings that may disagree with the one the reader sees.  What napoleon makes of the sections
is checked by the docs build (tests/test_docs.py: ``sphinx -W``).
"""
from __future__ import annotations

import dataclasses
import enum
import importlib
import inspect
import re
import types

import pytest

import lcs_exact

SUBPACKAGES = ["algebra", "numbers", "modes", "display", "system", "dynamics", "builders", "io", "verify"]
THIN = ["models", "examples", "sources", "testing", "zoo", "modelfile"]
PARAMETER_SECTIONS = ("Parameters", "Other Parameters")
_HEADER = re.compile(r"^(\s*)([A-Z][A-Za-z ]*)\n\1-{3,}\s*$", re.M)


def sections(doc: str) -> dict[str, str]:
    """The numpydoc sections of a docstring (as ``inspect.getdoc`` gives it), by title: a title line
    underlined with dashes, its body up to the next title."""
    heads = list(_HEADER.finditer(doc))
    out = {}
    for h, nxt in zip(heads, heads[1:] + [None]):
        out[h.group(2).strip()] = doc[h.end():nxt.start() if nxt else len(doc)]
    return out


def entries(body: str) -> set[str]:
    """The names a Parameters-like section lists: its lines at the section's least indentation,
    each ``name : type`` or ``name``, split at commas."""
    lines = [ln for ln in body.splitlines() if ln.strip()]
    if not lines:
        return set()
    indent = min(len(ln) - len(ln.lstrip()) for ln in lines)
    names = set()
    for ln in lines:
        if len(ln) - len(ln.lstrip()) == indent:
            head = ln.strip().split(" :", 1)[0].rstrip(":")
            names.update(n.strip() for n in head.split(","))
    return names


def documented(doc: str | None, extra_sections: tuple[str, ...] = ()) -> set[str]:
    """The names a docstring's Parameters and Other Parameters sections (and ``extra_sections``) list."""
    secs = sections(doc or "")
    return set().union(*(entries(secs[t]) for t in PARAMETER_SECTIONS + extra_sections if t in secs))


def undocumented(params, names: set[str]) -> list[str]:
    """The parameters (``inspect.Parameter``) that ``names`` does not document, by the module's rule."""
    missing = []
    for p in params:
        if p.name in ("self", "cls"):
            continue
        if p.kind is p.VAR_POSITIONAL:
            ok = any(n.startswith("*") and not n.startswith("**") for n in names)
        elif p.kind is p.VAR_KEYWORD:
            ok = any(n.startswith("**") for n in names)
        else:
            ok = p.name in names
        if not ok:
            missing.append({p.VAR_POSITIONAL: "*", p.VAR_KEYWORD: "**"}.get(p.kind, "") + p.name)
    return missing


def _constructor_is_ours(cls: type) -> bool:
    if issubclass(cls, (enum.Enum, BaseException)) and "__init__" not in vars(cls):
        return False
    for name in ("__init__", "__new__"):
        for klass in cls.__mro__:
            if name in vars(klass):
                return klass.__module__ not in ("builtins", "enum", "typing")
    return False


def check(obj, qualname: str) -> list[str]:
    """The undocumented parameters of one callable, as ``qualname(param)`` strings."""
    if inspect.isclass(obj):
        if not _constructor_is_ours(obj):
            return []
        try:
            params = inspect.signature(obj).parameters.values()
        except (TypeError, ValueError):
            return []
        extra = ("Attributes",) if dataclasses.is_dataclass(obj) else ()
        init = vars(obj).get("__init__")
        names = documented(inspect.getdoc(obj), extra) | documented(getattr(init, "__doc__", None)
                                                                     and inspect.getdoc(init))
    else:
        params = inspect.signature(obj).parameters.values()
        names = documented(inspect.getdoc(obj))
    return [f"{qualname}({name})" for name in undocumented(params, names)]


def public_callables() -> dict[str, object]:
    """The public callables (the module docstring's list), by qualified name, each once."""
    modules = [lcs_exact] + [importlib.import_module(f"lcs_exact.{s}") for s in SUBPACKAGES + THIN]
    found: dict[int, tuple[str, object]] = {}

    def add(qual, obj):
        found.setdefault(id(obj), (qual, obj))

    while modules:
        mod = modules.pop(0)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if isinstance(obj, types.ModuleType):
                if hasattr(obj, "__all__") and obj.__name__.startswith("lcs_exact."):
                    modules.append(obj)
            elif inspect.isclass(obj):
                if not obj.__module__.startswith("lcs_exact"):
                    continue
                add(f"{obj.__module__}.{obj.__qualname__}", obj)
                for attr, value in vars(obj).items():
                    if isinstance(value, (staticmethod, classmethod)):
                        value = value.__func__
                    if not attr.startswith("_") and inspect.isfunction(value):
                        add(f"{obj.__module__}.{value.__qualname__}", value)
            elif inspect.isfunction(obj) and obj.__module__.startswith("lcs_exact"):
                add(f"{obj.__module__}.{obj.__qualname__}", obj)
    return dict(sorted(found.values(), key=lambda qo: qo[0]))


PUBLIC = public_callables()

#: callables not yet documented: their gaps are tolerated, the list only shrinks (an entry whose
#: callable is now fully documented fails test_pending_is_current).  Empty since issue 29 item 6
#: was finished: every public callable is held to the rule.
PENDING: frozenset[str] = frozenset()


def test_the_public_callables_are_found():
    """The walk reaches the top-level names, the doors' names and the methods of classes."""
    names = set(PUBLIC)
    for q in ("lcs_exact.dynamics.simulate.simulate", "lcs_exact.system.lcs.LCS", "lcs_exact.system.lcs.LCS.mode",
              "lcs_exact.algebra.lcp.solve_lcp", "lcs_exact.builders.mechanics.mechanical",
              "lcs_exact.numbers.calcium.real_roots"):
        assert q in names, q
    assert len(PUBLIC) > 300


def test_every_parameter_is_documented():
    """Each public callable's parameters each have an entry in its Parameters (or Other Parameters)."""
    missing = [m for q, obj in PUBLIC.items() if q.removeprefix("lcs_exact.") not in PENDING for m in check(obj, q)]
    assert not missing, f"{len(missing)} undocumented parameters:\n" + "\n".join(missing)


def test_pending_is_current():
    """Each pending callable is public and still has an undocumented parameter."""
    short = {q.removeprefix("lcs_exact."): q for q in PUBLIC}
    assert not PENDING - set(short), "not public: " + ", ".join(sorted(PENDING - set(short)))
    done = sorted(q for q in PENDING if not check(PUBLIC[short[q]], q))
    assert not done, "documented now, remove from PENDING: " + ", ".join(done)


# ---- the test of the test ----------------------------------------------------------------------

def _half_documented(x, y, *rows, digits=30, **options):
    """A function that documents some of its parameters.

    Parameters
    ----------
    x, *rows : int
        Documented (two names in one entry).
    digits : int, optional
        Documented.

        An indented paragraph; ``y : float`` here is not an entry.
    """


def _all_documented(x, *args, **simulate_options):
    """A function with every parameter documented.

    Parameters
    ----------
    x
        An entry without a type.

    Other Parameters
    ----------------
    *args : object
        The positional rest.
    **simulate_options
        Passed on to ``simulate`` (a wider name for the keywords).
    """


@dataclasses.dataclass
class _Fields:
    """A dataclass whose fields are documented as attributes.

    Attributes
    ----------
    a : int
        The first field.
    """
    a: int
    b: int = 0


class _Documented:
    """A class whose constructor is documented in ``__init__``; one method misses a parameter."""

    def __init__(self, n):
        """Parameters
        ----------
        n : int
            The size.
        """

    def method(self, k):
        """A method that does not document ``k``."""


def test_the_check_reports_a_missing_parameter():
    """An undocumented parameter, ``*args`` and ``**kwargs`` are each reported; documented ones, in
    either section, under a shared entry or a wider ``**`` name, are not; ``self`` is skipped."""
    assert check(_half_documented, "f") == ["f(y)", "f(**options)"]
    assert check(_all_documented, "g") == []
    assert check(_Fields, "F") == ["F(b)"]
    assert check(_Documented, "D") == []
    assert check(_Documented.method, "D.method") == ["D.method(k)"]
    assert check(lambda: None, "h") == []


def test_the_parser_reads_sections():
    """Sections end at the next title; an entry without a type and indented prose are told apart."""
    doc = inspect.getdoc(_half_documented)
    assert set(sections(doc)) == {"Parameters"}
    assert documented(doc) == {"x", "*rows", "digits"}
    assert documented("Summary.\n\nReturns\n-------\nx : int\n    Not a parameter.") == set()
