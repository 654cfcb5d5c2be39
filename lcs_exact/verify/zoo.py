"""The zoo: a versioned suite of certified, sampled fixtures of standard problems.

``lcs-exact zoo DIR`` (or :func:`write_zoo`) runs every problem of :data:`PROBLEMS` exactly
(Algorithm 7.1) and writes, into the folder DIR,

* one fixture per problem, ``DIR/<name>.json`` in the format ``lcs-exact/trajectory/1``
  (docs/fixtures.md): the system, the events, the final state and a certified grid of samples;
  each carries its ``provenance`` (the suite, the builder and its parameters, how x0 is made,
  t_end, a reference, the ``lcs_exact`` version) and is validated against the shipped schema;
* ``DIR/index.json``: the suite's version (:data:`SUITE`), the settings and one entry per problem
  (file, n, k, events, closed forms, digests, provenance);
* ``DIR/README.md``: the same as a table (problem, n, k, events, digits, closed forms).

The suite also ships with the package, pre-built (``lcs_exact/zoo_data``): :func:`cases` gives one
:class:`ZooCase` per problem, with the float64 data a numerical solver starts from (A, B, C, D,
x0, the restitution, which states are the plant's and which are sources) and
:meth:`ZooCase.assert_matches` for its test; the pytest plugin ``lcs_exact.pytest_plugin``
(installed with the package) parametrizes the fixture ``lcs_zoo_case`` over every case.

The problems are built from :mod:`lcs_exact.examples` and :mod:`lcs_exact.models` only: the
paper's two carts (section 7) and its hook example (Example 8.3), the bouncing ball with
restitution, a chain of carts, a column of beads, Newton's cradle, RLC-diode circuits, sine
rectifiers, diode bridges (Siconos' DiodeBridgeCapFilter among them), Filippov's spiral (4.12), a
relay system and a stiff RC-diode network.  The suite's content is fixed by its version: a
problem is added or changed only with a new :data:`SUITE`.

Each problem's grid has ``samples`` intervals: the sample step is t_end / samples (exact), so
one setting fits problems on time scales from milliseconds (the bridge) to seconds.

>>> [p.name for p in PROBLEMS][:3]
['two_carts', 'two_carts_hook', 'bouncing_ball']
>>> problem("bouncing_ball").call()
'lcs_exact.examples.bouncing_ball(g="981/100", e="9/10")'
"""
from __future__ import annotations

import json
import time
from functools import cached_property
from importlib.resources import files
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any, Callable, Sequence

from ..numbers import check_digits
from .compare import ComparisonReport, compare
from ..errors import FormatError, InvalidArgument, LCSError
from ..builders import (ball_column, bouncing_ball, buck_converter, cart_chain, diode_bridge, diode_bridge_cap_filter,
                        filippov_spiral, half_wave_rectifier, newtons_cradle, sine_rectifier, two_carts,
                        two_carts_with_hook)
from ..dynamics import MAX_SAMPLES, SCHEMA, validate_fixture
from ..io import FixtureTrajectory, read_fixture
from ..builders import circuit, relay
from ..numbers import expm_action
from ..dynamics import simulate
from ..system import SourceBlock
from ..system import LCS
from .testing import assert_matches_fixture

__all__ = ["SUITE", "DEFAULT_DIGITS", "DEFAULT_SAMPLES", "INDEX_FILE", "README_FILE", "Problem", "PROBLEMS",
           "problem", "version", "write_zoo", "ZooCase", "cases", "DATA"]

#: the suite's name and version: the list of problems, their parameters, x0 and t_end
SUITE = "lcs-exact/zoo/2"
#: significant digits of the numbers in the fixtures (``--digits``)
DEFAULT_DIGITS = 20
#: grid intervals per problem: the sample step is t_end / DEFAULT_SAMPLES (``--sample``)
DEFAULT_SAMPLES = 100
#: the index of the suite written beside the fixtures
INDEX_FILE = "index.json"
#: the table of the suite written beside the fixtures
README_FILE = "README.md"

# the builders a problem may name, by their public dotted names
_BUILDERS: dict[str, Callable[..., LCS]] = {
    "lcs_exact.examples." + f.__name__: f
    for f in (two_carts, two_carts_with_hook, bouncing_ball, cart_chain, ball_column, newtons_cradle,
              half_wave_rectifier, diode_bridge, sine_rectifier, diode_bridge_cap_filter, filippov_spiral,
              buck_converter)}
_BUILDERS.update({"lcs_exact.models.circuit": circuit, "lcs_exact.models.relay": relay})


def _show(v: Any) -> str:
    """A JSON-ready value as Python source (strings quoted, lists in brackets)."""
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, bool):
        return str(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_show(e) for e in v) + "]"
    return str(v)


@dataclass(frozen=True, eq=False)
class Problem:
    """One problem of the zoo: how its system and initial state are made, and its horizon.

    Attributes
    ----------
    name : str
        The file name (``<name>.json``) and the name for ``--only``.
    title : str
        A one-line description.
    builder : str
        The public dotted name of the builder (``lcs_exact.examples.two_carts``).
    parameters : dict
        The builder's keyword arguments (JSON: rationals as ``"p/q"`` strings).
    x0 : tuple
        ``("state", values)`` (x0 itself), ``("embed", values)`` (``lcs.embed(values)``: the
        constant states of gravity, sources or relay levels appended) or ``("expm_action", t,
        values)`` (e^{A t} values, exact).
    t_end : str
        The final time, a rational.
    reference : str
        Where the problem comes from.
    """

    name: str
    title: str
    builder: str
    parameters: dict = field(default_factory=dict)
    x0: tuple = ()
    t_end: str = "1"
    reference: str = ""

    def call(self) -> str:
        """The builder call as Python source."""
        return _call({"builder": self.builder, "parameters": self.parameters})

    def x0_text(self) -> str:
        """How x0 is made, as text (``embed([1, 0])``, ``expm_action(A, -1, [0, -1, -1, 0])``)."""
        kind = self.x0[0]
        if kind == "state":
            return _show(self.x0[1])
        if kind == "embed":
            return f"embed({_show(self.x0[1])})"
        return f"expm_action(A, {_show(self.x0[1])}, {_show(self.x0[2])})"

    def system(self) -> LCS:
        """The LCS, built by :attr:`builder` from :attr:`parameters`."""
        return _BUILDERS[self.builder](**self.parameters)

    def initial_state(self, lcs: LCS | None = None) -> Any:
        """x0 for the system (a list of rationals, or an exact vector for ``expm_action``).

        Parameters
        ----------
        lcs : LCS, optional
            The problem's system (built when None).
        """
        lcs = self.system() if lcs is None else lcs
        kind = self.x0[0]
        if kind == "state":
            return list(self.x0[1])
        if kind == "embed":
            return lcs.embed(list(self.x0[1]))
        return expm_action(lcs.A, self.x0[1], list(self.x0[2]))

    def run(self, digits: int = DEFAULT_DIGITS, **kw: Any):
        """The exact run (:func:`lcs_exact.simulate`) on [0, t_end]; keywords go to simulate.

        Parameters
        ----------
        digits : int, optional
            Correct digits (as for simulate).
        **kw
            Passed on to :func:`lcs_exact.simulate`.
        """
        lcs = self.system()
        return simulate(lcs, self.initial_state(lcs), self.t_end, digits=digits, **kw)

    def sample_step(self, samples: int = DEFAULT_SAMPLES) -> Fraction:
        """The grid step t_end / samples.

        Parameters
        ----------
        samples : int, optional
            The number of grid steps.
        """
        return Fraction(self.t_end) / samples

    def provenance(self) -> dict:
        """The fixture's ``provenance``: the suite, problem, builder, parameters, x0, t_end,
        reference and the ``lcs_exact`` version."""
        return {"suite": SUITE, "problem": self.name, "title": self.title, "builder": self.builder,
                "parameters": json.loads(json.dumps(self.parameters)), "x0": self.x0_text(), "t_end": self.t_end,
                "reference": self.reference, "lcs_exact_version": version()}


def _p(name, title, builder, parameters, x0, t_end, reference) -> Problem:
    return Problem(name, title, "lcs_exact." + builder, parameters, x0, t_end, reference)


PAPER = "Heemels, Schumacher, Weiland, Linear complementarity systems, SIAM J. Appl. Math. 60(4), 2000"

#: the problems of :data:`SUITE`, in the order of the index
PROBLEMS: tuple[Problem, ...] = (
    _p("two_carts", "two carts, springs and an inelastic stop", "examples.two_carts", {},
       ("expm_action", -1, [0, -1, -1, 0]), "3",
       f"{PAPER}: section 2 (2.1) and the run of section 7 (events at 1 and 1 + pi/2)"),
    _p("two_carts_hook", "two carts with a stop and a hook", "examples.two_carts_with_hook", {},
       ("state", ["1/10", "1/10", -2, 1]), "1", f"{PAPER}: Example 8.3 (8.12), x0 = (eps, eps, -2, 1)"),
    _p("bouncing_ball", "bouncing ball, restitution 9/10, through its accumulation", "examples.bouncing_ball",
       {"g": "981/100", "e": "9/10"}, ("embed", [1, 0]), "10",
       "Siconos' BouncingBall tutorial (g = 9.81, e = 0.9, dropped from h = 1); Newton's impact law"),
    _p("cart_chain_4", "chain of 4 carts on springs, stops on carts 0 and 2", "examples.cart_chain", {"N": 4},
       ("state", ["1/2", "-1/2", "1/2", "-1/2", 0, 0, 0, 0]), "10",
       f"{PAPER}: (8.3); near-coincident impacts"),
    _p("ball_column_3", "column of 3 beads on a floor, restitution 1/2", "examples.ball_column", {"N": 3},
       ("embed", ["1/20", "3/20", "1/2", 0, 0, 0]), "1", "Siconos' column of beads; Newton's law at every contact"),
    _p("newtons_cradle_3", "Newton's cradle of 3 balls, elastic", "examples.newtons_cradle", {"N": 3},
       ("state", [0, 0, 0, 1, 0, 0]), "2", "Newton's impact law with Moreau's generalisation (e = 1)"),
    _p("half_wave_rectifier", "LC tank, ideal diode, resistive load (RLC-diode)", "examples.half_wave_rectifier",
       {}, ("state", [0, -1]), "12", "events at 13 pi/12, 25 pi/12, 19 pi/6 (docstring of the builder)"),
    _p("diode_bridge", "full-wave diode bridge rectifying an LC tank", "examples.diode_bridge", {},
       ("state", [0, -1]), "12", "four diodes with series resistances, events every 13 pi/12"),
    _p("sine_rectifier_half", "half-wave rectifier, sine source, RC load", "examples.sine_rectifier", {},
       ("embed", [0]), "13", "a sine source as an exosystem; turn-off at 3 pi/4"),
    _p("sine_rectifier_full", "full-wave bridge rectifier, floating sine source, RC load",
       "examples.sine_rectifier", {"full_wave": True}, ("embed", [0]), "13",
       "a floating source: undetermined potential while all diodes block, the state unique"),
    _p("diode_bridge_cap_filter", "diode bridge with a capacitor filter (L = 10 mH, C = 1 uF)",
       "examples.diode_bridge_cap_filter", {}, ("state", [10, 0, 0]), "1/200",
       "Siconos' DiodeBridgeCapFilter tutorial (x0 = (10, 0, 0), t_end = 5 ms)"),
    _p("filippov_spiral", "Filippov's spiral: two relays, right-Zeno at t = 3/2", "examples.filippov_spiral", {},
       ("embed", [1, 2]), "2", f"{PAPER}: (4.12), Remark 4.11; switching times 3/2 - (5/2) 3^-k"),
    _p("relay", "two relays x' = -2 sgn(x)", "models.relay",
       {"A": [[0, 0], [0, 0]], "B": [[-2, 0], [0, -2]], "C": [[1, 0], [0, 1]], "name": "two relays"},
       ("embed", [1, 1]), "1", "Siconos' SimpleExampleRelay; both relays slide at 0 from t = 1/2"),
    _p("stiff_rc_diode", "stiff RC network clamped by a diode (time constants 1e-6 and 0.5)", "models.circuit",
       {"netlist": "C1 1 0 1\nR1 1 0 1\nR12 1 2 1\nC2 2 0 1/1000\nR2 2 0 1/1000\nD1 0 2",
        "name": "stiff RC network and a diode"},
       ("state", [-1, 1]), "5", "eigenvalues about -1.001e6 and -1.999; the diode clamps v(C2) at t ~ 7e-6"),
    _p("buck_converter_dcm", "buck converter, PWM switch (duty 1/4), discontinuous conduction",
       "examples.buck_converter", {}, ("embed", [0, 0]), "4",
       "a scheduled LCS (lcs_exact.models.scheduled): the switch's times are exact events; the diode blocks "
       "before every period ends"),
)

_BY_NAME = {p.name: p for p in PROBLEMS}


def version() -> str:
    """The installed ``lcs_exact`` version (the package's metadata), written into the provenance."""
    from importlib import metadata  # stdlib, but 10+ ms to import: only when a fixture is written
    try:
        return metadata.version("lcs_exact")
    except metadata.PackageNotFoundError:  # pragma: no cover - run from a source tree, not installed
        return "unknown"


def problem(name: str) -> Problem:
    """The problem called ``name`` (:class:`~lcs_exact.errors.InvalidArgument` if there is none).

    Parameters
    ----------
    name : str
        The problem's name.
    """
    if name not in _BY_NAME:
        raise InvalidArgument(f"the zoo has no problem {str(name)[:40]!r} (it has: {', '.join(_BY_NAME)})")
    return _BY_NAME[name]


def _selected(only: str | Sequence[str] | None) -> list[Problem]:
    if only is None:
        return list(PROBLEMS)
    names = only.split(",") if isinstance(only, str) else list(only)
    names = [str(n).strip() for n in names if str(n).strip()]
    if not names:
        raise InvalidArgument(f"no problem given (the zoo has: {', '.join(_BY_NAME)})")
    chosen = [problem(n) for n in dict.fromkeys(names)]  # repeated names once
    return sorted(chosen, key=PROBLEMS.index)


def _check_settings(digits: Any, samples: Any) -> None:
    check_digits(digits)
    if isinstance(samples, bool) or not isinstance(samples, int) or not 1 <= samples < MAX_SAMPLES:
        raise InvalidArgument(f"samples (grid intervals per problem) must be an int in 1..{MAX_SAMPLES - 1}, "
                              f"got {samples!r}")


def _closed_form_times(fx: dict) -> int:
    return sum(1 for e in fx["events"] if e["time"]["exact"] is not None)


def _entry(p: Problem, fx: dict, lcs: LCS, validated: bool) -> dict:
    return {"name": p.name, "title": p.title, "file": f"{p.name}.json", "n": lcs.n, "k": lcs.k,
            "events": len(fx["events"]), "accumulations": len(fx["accumulations"]),
            "closed_forms": _closed_form_times(fx), "t_end": p.t_end, "sample_step": fx.get("sample_step"),
            "samples": len(fx.get("samples", ())), "certified": fx["certified"], "partial": fx["partial"],
            "stop_reason": fx["stop_reason"], "validated": validated, "digest": fx["digest"],
            "samples_digest": fx.get("samples_digest"), "provenance": fx["provenance"]}


def write_zoo(directory: Any, digits: int = DEFAULT_DIGITS, samples: int = DEFAULT_SAMPLES,
              only: str | Sequence[str] | None = None, out: Callable[[str], Any] | None = None) -> dict:
    """Write the zoo's fixtures, ``index.json`` and ``README.md`` into ``directory``.

    Parameters
    ----------
    directory : str or Path
        The folder (created with its parents if missing; files of the same names are replaced).
    digits : int
        Significant digits of every number in the fixtures (certified).
    samples : int
        Grid intervals per problem: the sample step is t_end / samples.
    only : str or sequence of str, optional
        Problem names (a comma-separated string or a list); default: every problem.
    out : callable, optional
        Called with one line per problem written (e.g. ``print``).

    Returns
    -------
    dict
        The index (also written as ``index.json``).  A run that stops early (a limit) is written
        as a partial fixture and marked ``"partial": true`` in the index.

    Examples
    --------
    >>> import pathlib, shutil, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> index = write_zoo(d, digits=10, samples=4, only="filippov_spiral")
    >>> entry = index["problems"][0]
    >>> entry["events"], entry["closed_forms"], entry["accumulations"], entry["provenance"]["builder"]
    (9, 9, 1, 'lcs_exact.examples.filippov_spiral')
    >>> sorted(p.name for p in d.iterdir())
    ['README.md', 'filippov_spiral.json', 'index.json']
    >>> shutil.rmtree(d)
    """
    _check_settings(digits, samples)
    chosen = _selected(only)
    folder = Path(directory)
    if folder.exists() and not folder.is_dir():
        raise InvalidArgument(f"{directory}: is a file, not a folder")
    folder.mkdir(parents=True, exist_ok=True)
    entries = []
    for p in chosen:
        t0 = time.perf_counter()
        lcs = p.system()
        try:
            traj = simulate(lcs, p.initial_state(lcs), p.t_end, digits=digits)
        except LCSError as e:  # stopped early: the computed part is still ground truth, marked partial
            if getattr(e, "trajectory", None) is None:
                raise
            traj = e.trajectory
        fx = traj.to_fixture(digits, sample=p.sample_step(samples), provenance=p.provenance())
        try:
            validate_fixture(fx)
            validated = True
        except ModuleNotFoundError:  # jsonschema (the fixtures extra) not installed
            validated = False
        path = folder / f"{p.name}.json"
        path.write_text(json.dumps(fx, indent=1) + "\n", encoding="utf-8")
        entries.append(_entry(p, fx, lcs, validated))
        if out is not None:
            e = entries[-1]
            out(f"{p.name}: n = {e['n']}, k = {e['k']}, {e['events']} event{'' if e['events'] == 1 else 's'} "
                f"({e['closed_forms']} in closed form)"
                f"{', PARTIAL' if e['partial'] else ''}, {time.perf_counter() - t0:.2f} s -> {path}")
    index = {"suite": SUITE, "fixture_schema": SCHEMA, "lcs_exact_version": version(), "digits": digits,
             "samples": samples, "problems": entries}
    (folder / INDEX_FILE).write_text(json.dumps(index, indent=1) + "\n", encoding="utf-8")
    (folder / README_FILE).write_text(_readme(index), encoding="utf-8")
    return index


def _md(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", "; ")


def _readme(index: dict) -> str:
    lines = [
        f"# lcs_exact zoo ({index['suite']})",
        "",
        f"Certified fixtures (format `{index['fixture_schema']}`) of standard linear complementarity problems,",
        f"written by lcs_exact {index['lcs_exact_version']} with `lcs-exact zoo` at {index['digits']} significant "
        f"digits, each sampled on {index['samples']} grid intervals (step t_end / {index['samples']}).",
        "Every number is a decimal with a certified error bound; `exact` holds a proven closed form.",
        "Each fixture carries its provenance (builder, parameters, x0, t_end, lcs_exact version) and digests of",
        "its content; `index.json` lists the same data as this table.",
        "",
        "```python",
        "import lcs_exact as L",
        "fx = L.read_fixture(\"two_carts.json\")            # validated, digests checked",
        "from lcs_exact.testing import assert_matches_fixture",
        "assert_matches_fixture(\"two_carts.json\", t, X, atol=1e-6)   # your solver's states X at times t",
        "```",
        "",
        "*events*: events of the run (Definition 4.3); *closed forms*: event times with a proven closed form;",
        "*accumulations*: accumulation points of events crossed exactly (Remark 4.11).",
        "",
        "| problem | n | k | events | accumulations | digits | closed forms | samples | certified |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for e in index["problems"]:
        cert = "yes" if e["certified"] else "no"
        if e["partial"]:
            cert += " (partial)"
        lines.append(f"| [{e['name']}]({e['file']}) | {e['n']} | {e['k']} | {e['events']} | {e['accumulations']} | "
                     f"{index['digits']} | {e['closed_forms']} | {e['samples']} | {cert} |")
    lines += ["", "## Provenance", ""]
    for e in index["problems"]:
        pv = e["provenance"]
        lines.append(f"* **{e['name']}**: {_md(pv['title'])}. `{_md(_call(pv))}`, x0 = `{_md(pv['x0'])}`, "
                     f"t_end = {pv['t_end']}. {_md(pv['reference'])}.")
    lines.append("")
    return "\n".join(lines)


def _call(pv: dict) -> str:
    args = ", ".join(f"{k}={_show(v)}" for k, v in pv["parameters"].items())
    return f"{pv['builder']}({args})"


# ---------------------------------------------------------------------------------------------
# the shipped suite: one case per problem, for other solvers' test suites
# ---------------------------------------------------------------------------------------------

#: the folder of the pre-built suite inside the package (written by :func:`write_zoo` at the
#: defaults; a test regenerates it and compares the digests)
DATA = "zoo_data"


def _floats(m: Any):
    import numpy as np  # numpy is not loaded by ``import lcs_exact``
    return np.array([[float(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())], dtype=np.float64)


class ZooCase:
    """One problem of the shipped zoo, as a numerical solver's test sees it (made by :func:`cases`).

    Parameters
    ----------
    problem : Problem
        The problem (its name and title).
    path : path-like
        Its certified fixture file (read on first use of :attr:`fixture`).

    Attributes
    ----------
    name, title : str
        The problem's name (the test id) and a one-line description.
    fixture : FixtureTrajectory
        The certified fixture (events, accumulations, samples on t_end / 100).
    A, B, C, D : numpy.ndarray
        The LCS x' = A x + B u, y = C x + D u, 0 <= y ⊥ u >= 0 in float64 (n x n, n x k, k x n, k x k).
    x0 : numpy.ndarray
        The initial state (all n states, float64).
    t_end : float
        The horizon.
    restitution : numpy.ndarray or None
        Newton's restitution coefficient per constraint (None: the paper's inelastic P_I).
    plant : tuple of int
        Indices of the modelled system's states; the others are the sources' (``sources``).
    sources : SourceBlock or None
        The exosystem inside the state (``sin(t)``, ``cos(t)``, a constant ``1`` of gravity):
        ``sources(t)`` gives their values, so a solver need not integrate them.
    step : float
        The fixture's sample step (a solver whose times hit this grid is compared on the samples).
    state_names : tuple of str
        The names of the n states (the component names of a failure message).
    schedule : tuple or None
        For a case whose data switch at scheduled times (a PWM switch): the phases in order from
        t = 0, each ``(duration, A, B, C, D, reset)`` in float64 (reset None or an n x n matrix
        applied when the phase starts), repeated every ``period`` (a float, or None); A, B, C, D
        above are the first phase's.  None otherwise.

    Examples
    --------
    >>> case = cases(["bouncing_ball"])[0]
    >>> case.name, case.A.shape, case.plant, case.sources.expressions, case.restitution.tolist()
    ('bouncing_ball', (3, 3), (0, 1), ('1',), [0.9])
    """

    def __init__(self, problem: Problem, path: Any):
        self.problem, self.name, self.title, self._path = problem, problem.name, problem.title, path

    @cached_property
    def fixture(self) -> FixtureTrajectory:
        return read_fixture(str(self._path))

    @cached_property
    def _data(self) -> tuple:
        fx = self.fixture
        lcs = fx.lcs
        import numpy as np
        x0 = np.array([float(b.mid()) for b in fx.x0], dtype=np.float64)
        e = None if lcs.restitution is None else np.array([float(q) for q in lcs.restitution], dtype=np.float64)
        return (_floats(lcs.A), _floats(lcs.B), _floats(lcs.C), _floats(lcs.D), x0, e)

    A = property(lambda self: self._data[0].copy())
    B = property(lambda self: self._data[1].copy())
    C = property(lambda self: self._data[2].copy())
    D = property(lambda self: self._data[3].copy())
    x0 = property(lambda self: self._data[4].copy())
    restitution = property(lambda self: None if self._data[5] is None else self._data[5].copy())

    @property
    def t_end(self) -> float:
        return float(self.fixture.t_end.mid())

    @property
    def plant(self) -> tuple:
        return tuple(self.fixture.lcs.plant)

    @property
    def sources(self) -> SourceBlock | None:
        return self.fixture.sources

    @property
    def step(self) -> float:
        return float(self.fixture.sample_step)

    @property
    def state_names(self) -> tuple:
        return tuple(self.fixture.lcs.state_names)

    @cached_property
    def _schedule(self) -> tuple:
        sched = getattr(self.fixture.lcs, "schedule", None)
        if sched is None:
            return None, None
        phases = tuple((None if p.duration is None else float(p.duration), _floats(p.lcs.A), _floats(p.lcs.B),
                        _floats(p.lcs.C), _floats(p.lcs.D), None if p.reset is None else _floats(p.reset))
                       for p in sched.phases)
        return phases, None if sched.period is None else float(sched.period)

    schedule = property(lambda self: self._schedule[0])
    period = property(lambda self: self._schedule[1])

    def compare(self, t: Any, X: Any, **options: Any) -> ComparisonReport:
        """:func:`lcs_exact.compare` of a solution (times t, states X: all n, or the plant's)
        against the case (``event_tol``, ``atol``, ``rtol``, ``label`` as there).

        Parameters
        ----------
        t, X : sequences
            The solver's times and states.
        **options
            Passed on to :func:`lcs_exact.compare`.
        """
        return compare(self.fixture, t, X, **options)

    def assert_matches(self, t: Any, X: Any, atol: float = 1e-6, rtol: float = 0.0,
                       event_tol: Any = None) -> ComparisonReport:
        """:func:`lcs_exact.testing.assert_matches_fixture` against the case: AssertionError
        naming the worst point outside ``|X - x| <= atol + rtol |x|``, away from the windows
        around every event (twice the solver's largest step by default, widened to the solver's
        own switch; those an accumulation implies included).  X: all n states, or the plant's.

        Parameters
        ----------
        t, X : sequences
            The solver's times and states (all n, or the plant's).
        atol, rtol : float, optional
            The tolerance ``|X - x| <= atol + rtol |x|``.
        event_tol : float, optional
            The half-width of the windows around events (default above).
        """
        return assert_matches_fixture(self.fixture, t, X, atol=atol, rtol=rtol, event_tol=event_tol)

    def __repr__(self):
        return f"<ZooCase {self.name!r}: {self.title}>"


def cases(names: str | Sequence[str] | None = None) -> list[ZooCase]:
    """The shipped zoo's cases (:class:`ZooCase`), in the order of :data:`PROBLEMS`; ``names``
    (a list, or a comma-separated string) selects some.  The fixtures are read on first use.

    Parameters
    ----------
    names : str or sequence of str, optional
        The cases to select (all when None).

    >>> [c.name for c in cases("relay,two_carts")]
    ['two_carts', 'relay']
    """
    folder = files("lcs_exact").joinpath(DATA)
    out = []
    for p in _selected(names):
        path = folder.joinpath(f"{p.name}.json")
        if not path.is_file():
            raise FormatError(f"the shipped zoo lacks {p.name}.json (a broken install?)")
        out.append(ZooCase(p, path))
    return out
