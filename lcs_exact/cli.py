"""The ``lcs-exact`` command (also ``python -m lcs_exact``).

    lcs-exact two-carts                   the paper's two-carts run of section 7, its events
    lcs-exact simulate MODEL --t-end T --digits D [--x0 "a,b,c"] [-o OUT.json]
    lcs-exact select MODEL --x0 "a,b,c"   S(x0) and the initial solution for a model file

A model file (TOML or JSON) has ``A``, ``B``, ``C``, ``D`` as lists of rows of numbers or
rational strings, and optionally ``x0`` and ``name`` (DESIGN.md section 5).  Exit status 0 on
success, 2 with a one-line reason on bad input.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .errors import LCSError
from .modes import format_mode
from .system import LCS

__all__ = ["main", "load_model"]


def load_model(path: str) -> tuple[LCS, dict]:
    """Read a model file (TOML or JSON) into an LCS and the raw dict."""
    p = Path(path)
    text = p.read_text()
    if p.suffix.lower() == ".toml":
        import tomllib
        data = tomllib.loads(text)
    else:
        data = json.loads(text)
    missing = [key for key in "ABCD" if key not in data]
    if missing:
        raise LCSError(f"model file {path} lacks {', '.join(missing)}")
    return LCS(data["A"], data["B"], data["C"], data["D"], name=data.get("name")), data


def _fmt_vec(x) -> str:
    return "(" + ", ".join(str(x[i, 0]) for i in range(x.nrows())) + ")"


def report_selection(lcs: LCS, x0, out=print) -> None:
    """Print S(x0), the RCP solutions (k <= 4) and the re-initialized state."""
    modes = lcs.select_modes(x0)
    out(f"x0 = ({', '.join(str(v) for v in x0)}):  S(x0) = "
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
        t = e.time.decimal(digits)
        cf = f"  = {e.time.closed_form}" if e.time.closed_form is not None else ""
        mb = "start" if e.mode_before is None else format_mode(e.mode_before)
        jumps = " -> ".join(format_mode(m) for m in e.modes) or "none"
        out(f"event t = {t}{cf}")
        out(f"    mode {mb} => {format_mode(e.mode_after)}; re-initialization chain: {jumps} "
            f"(multiplicity {e.multiplicity}); triggered by {', '.join(e.triggers) or '-'}")
        out(f"    x(t-) = {_fmt_exact(e.state_before, digits)}")
        out(f"    x(t+) = {_fmt_exact(e.state_after, digits)}")
    status = "certified" if traj.certified else f"NOT certified: {traj.assumptions}"
    out(f"{len(traj.events)} events, {status}, {traj.elapsed:.3f} s")


def _fmt_exact(v, digits: int) -> str:
    q = v.rational()
    if q is not None:
        return _fmt_vec(q)
    return "(" + ", ".join(c.decimal(digits).split(" +/-")[0] for c in v) + ")"


def two_carts_demo(out=print, digits: int = 30) -> None:
    from .models import two_carts
    from .reals import expm_action
    from .simulate import simulate
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="lcs-exact", description="Exact linear complementarity systems")
    sub = parser.add_subparsers(dest="cmd", required=True)
    tc = sub.add_parser("two-carts", help="the paper's two-carts run of section 7 and its events")
    tc.add_argument("--digits", type=int, default=30)
    sim = sub.add_parser("simulate", help="Algorithm 7.1 on a model file")
    sim.add_argument("model")
    sim.add_argument("--t-end", required=False, help="final time (default: the file's t_end)")
    sim.add_argument("--digits", type=int, default=30)
    sim.add_argument("--x0", help="comma-separated initial state (default: the file's x0)")
    sim.add_argument("-o", "--output", help="write the fixture JSON here")
    sim.add_argument("--max-events", type=int, default=1000)
    sel = sub.add_parser("select", help="S(x0) and the initial solution for a model file")
    sel.add_argument("model")
    sel.add_argument("--x0", help="comma-separated initial state (default: the file's x0)")
    args = parser.parse_args(argv)
    try:
        if args.cmd == "two-carts":
            two_carts_demo(digits=args.digits)
        elif args.cmd == "simulate":
            from .simulate import simulate
            lcs, data = load_model(args.model)
            x0 = args.x0.split(",") if args.x0 else data.get("x0")
            t_end = args.t_end if args.t_end is not None else data.get("t_end")
            if x0 is None or t_end is None:
                raise LCSError("give --x0 and --t-end, or put x0 and t_end in the model file")
            traj = simulate(lcs, [v.strip() if isinstance(v, str) else v for v in x0],
                            str(t_end), digits=args.digits, max_events=args.max_events)
            print_events(traj, args.digits)
            if args.output:
                Path(args.output).write_text(json.dumps(traj.to_fixture(args.digits), indent=1))
        elif args.cmd == "select":
            lcs, data = load_model(args.model)
            x0 = args.x0.split(",") if args.x0 else data.get("x0")
            if x0 is None:
                raise LCSError("no initial state: give --x0 or put x0 in the model file")
            report_selection(lcs, [v.strip() if isinstance(v, str) else v for v in x0])
    except (LCSError, OSError, ValueError) as e:
        print(f"lcs-exact: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
