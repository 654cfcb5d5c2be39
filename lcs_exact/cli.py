"""The ``lcs-exact`` command (also ``python -m lcs_exact``).

    lcs-exact two-carts                   the paper's two-carts run of section 7, its events
    lcs-exact simulate MODEL [--x0 a,b,c] [--t-end T] [--digits D] [--sample H]
                             [--max-events N] [--time-limit S] [-o OUT.json]
    lcs-exact select MODEL [--x0 a,b,c]   S(x0) and the initial solution for a model file
    lcs-exact check MODEL                 Theorem 6.3, leading indices, Markov parameters, modes
    lcs-exact compare FIXTURE SOL.csv [MORE.csv ...] [--json] [--event-tol W]
    lcs-exact zoo DIR [--digits D] [--sample N] [--only NAME,...]
                                          the suite of certified fixtures (lcs_exact.zoo) into DIR
    lcs-exact --version

A model file (TOML or JSON) has ``A``, ``B``, ``C``, ``D`` as lists of rows of numbers or
rational strings ("1/3"), and optionally sources (``E``, ``F``, ``w``: a driven system),
``x0``, ``t_end``, ``restitution``, ``name``, ``states``, ``inputs`` and ``roles``; any other
key is an error.  Numbers are read exactly: a JSON or TOML decimal such as 1e-400 is the
rational 10^-400 (never a float).  ``x0`` (in the file or ``--x0``) is what ``lcs.embed`` takes:
with sources, the plant's state (the sources' states are appended).  The format is
:mod:`lcs_exact.modelfile` (``load_model``, ``read_model``, ``read_model_data`` and
``MODEL_KEYS`` are importable from here); this module parses arguments, runs and prints.

``--digits`` is 1..10000 (MAX_DIGITS, that of :mod:`lcs_exact.balls`), ``--max-events`` >= 0,
``--time-limit`` > 0 seconds; ``--x0 -1,2`` needs no ``=``.  For ``zoo``, ``--sample N`` is the
number of grid intervals of each problem (the step is t_end / N: one setting fits problems on any
time scale).

Exit status: 0 on success; 2 with a one-line reason on bad input; 3 when a run stops early (a
limit, an accumulation of events, a deadlock, an unresolved sign) - the partial fixture is still
written with ``-o``.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import sys
import time
from pathlib import Path

from . import __version__
from .numbers import MAX_DIGITS, check_digits
from .verify import compare, convergence_order, read_solution_csv
from .errors import FormatError, InvalidArgument, LCSError, UnresolvedSign
from .dynamics import MAX_SAMPLES, ball_number, sample_grid
from .io import read_fixture
from .interfaces import SystemLike
from .io import MODEL_KEYS, check_exponents, load_model, read_model, read_model_data
from .builders import two_carts
from .modes import format_mode
from .algebra import to_vector
from .numbers import expm_action
from .dynamics import simulate
from .system import LCS
from .verify import write_zoo

__all__ = ["main", "load_model", "read_model", "read_model_data", "MAX_DIGITS", "MODEL_KEYS"]  # all but main: modelfile


class _UsageError(Exception):
    """Bad command-line syntax (argparse's own errors), reported in one line with exit 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, no usage dump; main() turns it into exit status 2
        raise _UsageError(message)


# ---------------------------------------------------------------------------------------------
# arguments and model files
# ---------------------------------------------------------------------------------------------

def _x0_of(args, data: dict, lcs: LCS):
    """The full initial state: --x0 or the file's x0, as ``lcs.embed`` takes it (with sources,
    the plant's state; the sources' initial state is appended)."""
    n = len(lcs.plant)
    if args.x0 is not None:
        x0 = [v.strip() for v in args.x0.split(",")]
        check_exponents(x0, "--x0")
        if len(x0) != n:
            what = f"{n} (the plant's states {', '.join(lcs.state_names[:n])}; the sources' states " \
                   f"follow from w)" if n < lcs.n else f"{n} (n)"
            raise FormatError(f"--x0 has length {len(x0)}, expected {what}")
    elif "x0" not in data:
        raise FormatError("no initial state: give --x0 or put x0 in the model file")
    else:
        x0 = data["x0"]
    return lcs.embed(to_vector(x0, n, "x0"))


# ---------------------------------------------------------------------------------------------
# printing
# ---------------------------------------------------------------------------------------------

def _fmt_vec(x) -> str:
    return "(" + ", ".join(str(x[i, 0]) for i in range(x.nrows())) + ")"


def _fmt_mat(m) -> str:
    return "[" + "; ".join(" ".join(str(m[i, j]) for j in range(m.ncols())) for i in range(m.nrows())) + "]"


def report_selection(lcs: LCS, x0, out=print) -> None:
    """Print S(x0), the RCP solutions (k <= 4) and the re-initialized state."""
    modes = lcs.select_modes(x0)
    out(f"x0 = {_fmt_vec(to_vector(x0, lcs.n, 'x0'))}:  S(x0) = "
        f"{{{', '.join(sorted(format_mode(m) for m in modes))}}}")
    if lcs.k <= 4:
        for sol in lcs.rcp(x0):
            us = ", ".join(str(f) for f in sol.u)
            ys = ", ".join(str(f) for f in sol.y)
            out(f"    RCP in mode {format_mode(sol.mode)}: u(s) = ({us}),  y(s) = ({ys})")
    init = lcs.initial_solution(x0)
    kind = "smooth continuation" if init.smooth else f"jump to x(0+) = P_I x0 = {_fmt_vec(init.state_after)}"
    out(f"    initial solution in mode {format_mode(init.mode)}: {kind}")


def print_events(traj, digits: int, out=print) -> None:
    """One line per event: time (closed form when proven), modes, states."""
    for e in traj.events:
        closed = e.time.closed  # first: a proven rational time then prints exactly (no SymPy)
        t = e.time.decimal(digits)
        cf = f" = {closed}" if closed is not None and str(closed) != t else ""
        mb = "start" if e.mode_before is None else format_mode(e.mode_before)
        jumps = " -> ".join(format_mode(m) for m in e.modes) or "none"
        triggers = ", ".join(_trigger_label(traj.lcs, tr) for tr in e.triggers) or "-"
        out(f"event t = {t}{cf}")
        out(f"    mode {mb} => {format_mode(e.mode_after)}; re-initialization chain: {jumps} "
            f"(multiplicity {e.multiplicity}); triggered by {triggers}")
        out(f"    x(t-) = {_fmt_exact(e.state_before, digits)}")
        out(f"    x(t+) = {_fmt_exact(e.state_after, digits)}")
    status = "certified" if traj.certified else f"NOT certified: {traj.assumptions}"
    if traj.partial:  # the computed part is certified (or not), but the run did not reach t_end
        status = f"PARTIAL ({traj.status.value}, up to t = {_fmt_t(traj.t_last)}); the computed part is {status}"
    out(f"{len(traj.events)} events, {status}, {traj.elapsed:.3f} s")


def _trigger_label(lcs: SystemLike, trigger: str) -> str:
    """``y_0`` -> ``y_0 (stop)`` when the pairs have names."""
    m = re.fullmatch(r"([uy])_(\d+)", trigger)
    names = getattr(lcs, "constraint_names", ())
    if m is None or int(m.group(2)) >= len(names) or names == tuple(str(i) for i in range(len(names))):
        return trigger
    return f"{trigger} ({names[int(m.group(2))]})"


def _fmt_exact(v, digits: int) -> str:
    q = v.rational()
    if q is not None:
        return _fmt_vec(q)
    return "(" + ", ".join(c.decimal(digits).split(" +/-")[0] for c in v) + ")"


def two_carts_demo(out=print, digits: int = 30) -> None:
    carts = two_carts()
    out("Section 7: two carts from x0 = e^{-A} (0, -1, -1, 0), T_e = 3, " f"{digits} digits")
    x0 = expm_action(carts.A, -1, [0, -1, -1, 0])
    traj = simulate(carts, x0, 3, digits=digits)
    print_events(traj, digits, out)
    out(f"x(3) = {_fmt_exact(traj.state(3), digits)}")
    out("")
    out(repr(carts))
    out(str(carts.well_posedness()))
    out("H_0, H_1, H_2 = " + ", ".join(str(carts.markov(i)[0, 0]) for i in range(3)))
    m = carts.mode({0})
    out(f"mode {{0}} (stop active): {m!r}")
    out("Mode selection at the states of section 7:")
    for x0 in ([0, -1, -1, 0], [0, -1, 0, 0], [0, 0, 0, 1], [0, 1, -1, 0], [0, 1, 0, 0]):
        report_selection(carts, x0, out)
    out("LDCP_4 at (0, 0, 0, 1):")
    sol = carts.ldcp([0, 0, 0, 1], 4)
    for line in sol.equations_text().splitlines():
        out("    " + line)
    out(f"    S^4_LDCP = {{{', '.join(sorted(format_mode(m) for m in sol.modes))}}}")


def check_report(lcs: LCS, out=print, max_k: int = 8) -> None:
    """Theorem 6.3's report, leading indices and matrices, H_0..H_n (5.8), the autonomy of each
    mode (Lemma 3.3) for k <= ``max_k``, else a summary.

    >>> from lcs_exact.models import two_carts
    >>> check_report(two_carts())   # doctest: +ELLIPSIS
    two carts (section 2): n = 4 states (q_0, q_1, q_0', q_1'), k = 1 complementarity pairs (stop)
    Theorem 6.3 well-posedness: WELL-POSED
    ...
    H_2 = [1]
    H_3 = [0]
    H_4 = [-2]
    modes: 2 of 2 autonomous (Lemma 3.3)
    """
    out(f"{lcs}")
    out(str(lcs.well_posedness()))
    for i in range(lcs.n + 1):
        out(f"H_{i} = {_fmt_mat(lcs.markov(i))}")
    k = lcs.k
    if k > max_k:
        out(f"modes: 2^{k} = {2 ** k} index sets; autonomy not enumerated for k > {max_k} "
            f"(ask lcs.mode(I).is_autonomous for the ones you need)")
        return
    bad = []
    for bits in range(2 ** k):
        I = frozenset(i for i in range(k) if bits >> i & 1)
        m = lcs.mode(I)
        if not m.is_autonomous:
            bad.append(f"{format_mode(I)}: {m.autonomy_reason}")
    out(f"modes: {2 ** k - len(bad)} of {2 ** k} autonomous (Lemma 3.3)")
    for line in bad:
        out(f"    not autonomous {line}")


# ---------------------------------------------------------------------------------------------
# argument types (validated at the boundary, one-line errors)
# ---------------------------------------------------------------------------------------------

def _digits(text: str) -> int:
    try:
        return check_digits(_int(text), "--digits")
    except InvalidArgument as e:
        raise argparse.ArgumentTypeError(str(e).removeprefix("--digits ")) from None


def _max_events(text: str) -> int:
    v = _int(text)
    if v < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {v}")
    return v


def _int(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be an integer, got {text[:30]!r}") from None


def _intervals(text: str) -> int:
    v = _int(text)
    if not 1 <= v < MAX_SAMPLES:
        raise argparse.ArgumentTypeError(f"must be a number of grid intervals in 1..{MAX_SAMPLES - 1}, got {v}")
    return v


def _seconds(text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of seconds, got {text[:30]!r}") from None
    if not math.isfinite(v) or v <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive number of seconds, got {text[:30]}")
    return v


# options whose values may begin with '-' (argparse would read "-1,2" as an option)
_VALUE_OPTIONS = ("--x0", "--t-end", "--digits", "--max-events", "--time-limit", "--sample", "--event-tol", "--only")


def _join_values(argv: list[str]) -> list[str]:
    """``--x0 -1,2`` -> ``--x0=-1,2`` so that a negative first entry is a value, not an option."""
    out, i = [], 0
    while i < len(argv):
        a = argv[i]
        if a in _VALUE_OPTIONS and i + 1 < len(argv):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


_MODEL_HELP = ("model file, TOML (.toml) or JSON: A, B, C, D and optional sources, x0, t_end, names "
               "(docs/model-files.md)")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="lcs-exact", description="Exact linear complementarity systems "
                     "(Heemels, Schumacher, Weiland 2000)")
    parser.add_argument("--version", action="version", version=f"lcs-exact {__version__}")
    sub = parser.add_subparsers(dest="cmd", required=True, metavar="COMMAND")
    tc = sub.add_parser("two-carts", help="the paper's two-carts run of section 7 and its events")
    tc.add_argument("--digits", type=_digits, default=30)
    sim = sub.add_parser("simulate", help="Algorithm 7.1 on a model file; prints events and x(t_end)")
    sim.add_argument("model", help=_MODEL_HELP)
    sim.add_argument("--t-end", help="final time (default: the file's t_end)")
    sim.add_argument("--digits", type=_digits, default=30, help=f"correct digits, 1..{MAX_DIGITS}")
    sim.add_argument("--x0", help="comma-separated initial state (default: the file's x0)")
    sim.add_argument("--sample", help="certified samples on the grid 0, H, 2H, ... (in the fixture "
                     "with -o, else printed)")
    sim.add_argument("-o", "--output", help="write the fixture JSON here")
    sim.add_argument("--max-events", type=_max_events, default=1000)
    sim.add_argument("--time-limit", type=_seconds, help="wall-clock limit in seconds")
    sel = sub.add_parser("select", help="S(x0) and the initial solution for a model file")
    sel.add_argument("model", help=_MODEL_HELP)
    sel.add_argument("--x0", help="comma-separated initial state (default: the file's x0)")
    chk = sub.add_parser("check", help="well-posedness (Theorem 6.3), Markov parameters, modes")
    chk.add_argument("model", help=_MODEL_HELP)
    cmp_ = sub.add_parser("compare", help="error of other solvers' solutions (CSV: t, x_0..x_{n-1}) "
                          "against a fixture; several CSVs give the order of convergence")
    cmp_.add_argument("fixture", help="a certified fixture (JSON), as written by `lcs-exact simulate MODEL -o "
                      "FIXTURE.json` or `lcs-exact zoo`")
    cmp_.add_argument("solutions", nargs="+", help="one or more CSV solutions of another solver: a row per time, "
                      "t then one column per state (an optional header line, # comments); several give the "
                      "order of convergence")
    cmp_.add_argument("--json", action="store_true", help="print JSON instead of tables")
    cmp_.add_argument("--event-tol", help="half-width of the window left out around each event "
                      "(default: twice the solution's largest step)")
    zoo = sub.add_parser("zoo", help="write the suite of certified fixtures of standard problems, "
                         "an index.json and a README.md into DIR")
    zoo.add_argument("dir", metavar="DIR", help="folder to write the fixtures, index.json and README.md into "
                     "(created if missing)")
    zoo.add_argument("--digits", type=_digits, default=20, help=f"correct digits, 1..{MAX_DIGITS} (default 20)")
    zoo.add_argument("--sample", type=_intervals, default=100, metavar="N",
                     help="grid intervals per problem: the sample step is t_end / N (default 100)")
    zoo.add_argument("--only", metavar="NAME,...", help="comma-separated problem names (default: all)")
    return parser


# ---------------------------------------------------------------------------------------------
# commands
# ---------------------------------------------------------------------------------------------

def _simulate(args) -> int:
    lcs, data = load_model(args.model)
    x0 = _x0_of(args, data, lcs)
    t_end = args.t_end if args.t_end is not None else data.get("t_end")
    if t_end is None:
        raise FormatError("no final time: give --t-end or put t_end in the model file")
    check_exponents(str(t_end), "t_end")
    if args.sample is not None:
        check_exponents(args.sample, "--sample")
        sample_grid(t_end, args.sample)  # a bad step or too many points: an input error before the run
    if args.output:
        _check_writable(args.output)  # before the run: nothing computed is lost to a bad path
    opts = {"digits": args.digits, "max_events": args.max_events, "time_limit": args.time_limit}
    try:
        traj = simulate(lcs, x0, t_end, **opts)
    except KeyboardInterrupt as e:  # a quick exit: a summary, and the fixture without new closed forms
        partial = getattr(e, "trajectory", None)
        if partial is not None:
            print(f"{len(partial.events)} events, PARTIAL (interrupted, up to t = "
                  f"{partial.t_last.decimal(15).split(' +/-')[0]})")
            if args.output:
                _write_fixture(partial, args, closed_forms=False)
        print("lcs-exact: interrupted" + (f" (partial fixture written to {args.output})"
                                          if args.output and partial is not None else ""), file=sys.stderr)
        return 130
    except LCSError as e:
        partial = getattr(e, "trajectory", None)
        if partial is None:
            raise
        print_events(partial, args.digits)
        if args.output:
            _write_fixture(partial, args)
        print(f"lcs-exact: run stopped early: {_one_line(e)}"
              + (f" (partial fixture written to {args.output})" if args.output else ""), file=sys.stderr)
        return 3
    print_events(traj, args.digits)
    names = list(lcs.state_names)
    x_end = traj.state(traj.t_end)
    print(f"x({_fmt_t(traj.t_end)}) = {_fmt_exact(x_end, args.digits)}   [{', '.join(names)}]")
    if args.output:
        _write_fixture(traj, args)
    elif args.sample is not None:
        _print_samples(traj, args, names)
    return 0


def _print_samples(traj, args, names) -> None:
    """The certified grid as a table (each value correct to --digits digits)."""
    grid = sample_grid(traj.t_end, args.sample)
    print("samples: t  " + "  ".join(names))
    for t, row in zip(grid, traj.sample(grid, args.digits)):
        print(f"{t}  " + "  ".join(ball_number(b, args.digits)["value"] for b in row))


def _fmt_t(t) -> str:
    cf = t.closed
    return str(cf) if cf is not None else t.decimal(15).split(" +/-")[0]


def _check_writable(path: str) -> None:
    """-o must name a file that can be written: its folder exists and a regular file opens for
    appending (an existing file is left as it is; a new one is removed again; links, FIFOs and
    devices get the permission test only)."""
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    if p.is_dir():
        raise InvalidArgument(f"-o {path}: is a directory; give a file name")
    if not folder.is_dir():
        raise InvalidArgument(f"-o {path}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise InvalidArgument(f"-o {path}: not writable")
    if p.is_symlink() or (p.exists() and not p.is_file()):
        return  # a link or a FIFO/device: opening it here could create its target or consume a reader
    existed = p.exists()
    try:  # the real test (permission bits say yes to root, and /sys or /proc say no later)
        with open(p, "a", encoding="utf-8"):
            pass
    except OSError as e:
        raise InvalidArgument(f"-o {path}: not writable ({e.strerror or e})") from None
    if not existed:
        p.unlink()


def _write_fixture(traj, args, closed_forms: bool = True) -> None:
    try:
        fx = traj.to_fixture(args.digits, sample=args.sample, closed_forms=closed_forms)
    except UnresolvedSign as e:  # a number the fixture needs cannot be evaluated: refused at once, named
        raise UnresolvedSign(f"-o {args.output}: the fixture is not written: {e}") from None
    Path(args.output).write_text(json.dumps(fx, indent=1) + "\n", encoding="utf-8")


def _compare(args) -> int:
    if args.event_tol is not None:
        check_exponents(args.event_tol, "--event-tol")
    try:
        fx = read_fixture(args.fixture)
    except FormatError:
        kind = _document_kind(args.fixture)
        if kind is not None and "model file" in kind:  # a model file given as the fixture
            raise FormatError(f"{args.fixture}: expected a fixture, got {kind}") from None
        raise
    reports = []
    for path in args.solutions:
        t, X = _read_solution(path, fx.lcs.n)
        reports.append(compare(fx, t, X, event_tol=args.event_tol, label=path))
    order = convergence_order(reports) if len(reports) > 1 else None
    if args.json:
        print(json.dumps({"fixture": args.fixture, "reports": [r.to_dict() for r in reports],
                          "order": order}, indent=1))
        return 0
    for r in reports:
        print(r)
    if order is not None:
        print("order of convergence (least-squares slope of log max error against log step): "
              f"{order:.3f}")
        for r in reports:
            print(f"    step {r.step:<12.6g} max error {float(r.max_error.mid()):.4e}   {r.label}")
    return 0


def _read_solution(path: str, n: int) -> tuple:
    """A CSV solution for ``compare`` (:func:`lcs_exact.compare.read_solution_csv`); a file that is
    not one (a model file, a fixture, JSON or TOML given in its place) is named for what it is."""
    layout = f"a row per time: t, then one column per state, {n + 1} columns for the fixture's {n} states"
    try:
        return read_solution_csv(path)
    except (LCSError, UnicodeDecodeError) as e:
        kind = _document_kind(path)
        if kind is not None:
            raise FormatError(f"{path}: expected a CSV solution ({layout}), got {kind}; the arguments are "
                              f"`lcs-exact compare FIXTURE.json SOLUTION.csv [MORE.csv ...]`") from None
        if isinstance(e, UnicodeDecodeError):
            raise FormatError(f"{path}: expected a CSV solution ({layout}), got bytes that are not UTF-8 text "
                              f"(byte {e.start})") from None
        raise type(e)(f"{_one_line(e)} (a CSV solution has {layout})") from None


def _document_kind(path: str) -> str | None:
    """What a JSON or TOML file is (a fixture, a model file, another JSON/TOML document), or None
    for anything else."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return None
    data, syntax = None, None
    if text.lstrip()[:1] in ("{", "["):
        syntax = "JSON"
        try:
            data = json.loads(text)
        except (ValueError, RecursionError):
            return "a file that looks like JSON (it begins with a bracket)"
    else:
        try:
            import tomllib
            data, syntax = tomllib.loads(text), "TOML"
        except (ImportError, ValueError, RecursionError):
            return None
        if not data:
            return None
    if isinstance(data, dict):
        schema = data.get("schema")
        if isinstance(schema, str) and schema.startswith("lcs-exact/"):
            return f"a fixture ({schema}): give it first, as FIXTURE"
        if all(k in data for k in "ABCD"):
            return f"a {syntax} model file (keys {', '.join(list(data)[:6])}): simulate it with `lcs-exact simulate " \
                   f"{path} -o FIXTURE.json` to make a fixture"
    return f"a {syntax} document"


def _zoo(args) -> int:
    t0 = time.perf_counter()
    index = write_zoo(args.dir, digits=args.digits, samples=args.sample, only=args.only, out=print)
    partial = [e["name"] for e in index["problems"] if e["partial"]]
    print(f"{len(index['problems'])} fixtures ({index['suite']}, {args.digits} digits, {args.sample} grid "
          f"intervals each), index.json and README.md written to {args.dir} in {time.perf_counter() - t0:.1f} s")
    if partial:
        print(f"lcs-exact: runs stopped early (partial fixtures written): {', '.join(partial)}", file=sys.stderr)
        return 3
    return 0


def _one_line(e: BaseException) -> str:
    return " ".join(str(e).split())


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns the exit status (0 success, 2 bad input, 3 run stopped early,
    130 interrupted: Ctrl-C writes the partial fixture of a run, as a stopped run does).

    >>> main(["--version"])                      # doctest: +ELLIPSIS
    lcs-exact ...
    0
    >>> main(["simulate", "no-such-model.json"])   # one line on stderr, no traceback
    2
    """
    try:
        return _main(argv)
    except KeyboardInterrupt:  # Ctrl-C outside a run: one line, the shell's 130
        print("lcs-exact: interrupted", file=sys.stderr)
        return 130


def _main(argv: list[str] | None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = _parser().parse_args(_join_values(argv))
    except _UsageError as e:
        print(f"lcs-exact: error: {_one_line(e)}", file=sys.stderr)
        return 2
    except SystemExit as e:  # --help, --version
        return int(e.code or 0)
    try:
        if args.cmd == "two-carts":
            two_carts_demo(digits=args.digits)
        elif args.cmd == "simulate":
            return _simulate(args)
        elif args.cmd == "select":
            lcs, data = load_model(args.model)
            report_selection(lcs, _x0_of(args, data, lcs))
        elif args.cmd == "check":
            lcs, _ = load_model(args.model)
            check_report(lcs)
        elif args.cmd == "compare":
            return _compare(args)
        elif args.cmd == "zoo":
            return _zoo(args)
    except BrokenPipeError:  # the reader went away (`lcs-exact ... | head`): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (LCSError, OSError, ValueError) as e:  # LCSError: named input errors; OSError: files;
        # ValueError: the builtins of parsing (JSON/TOML decoding, text encodings)
        print(f"lcs-exact: error: {_one_line(e)}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
