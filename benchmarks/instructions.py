"""Instruction counts of lcs_exact runs (valgrind's callgrind): a deterministic measure for
comparing two versions of the engine on a noisy shared machine, where wall-clock ratios of a few
percent are lost in the noise.  Run from the repository root (needs ``valgrind``; Debian:
``apt-get install valgrind``):

    python benchmarks/instructions.py                 # chain16, long300 (~3 min)
    python benchmarks/instructions.py chain32         # ~10 min
    python benchmarks/instructions.py --tree ../old chain16   # the same scene on another checkout

Each scene runs in a fresh interpreter under callgrind (PYTHONHASHSEED=0); the table prints the
instructions of the whole process and of the run alone (the whole process minus one that only
imports lcs_exact and builds the scene).  Scenes: ``chainN`` (``systems.chain(N)``, t = 10, 30
digits), ``longK`` (``systems.long_run()`` stopped after K events, 30 digits) and ``cartsK`` (the
two carts of section 7, ``systems.two_carts()``, t = 3, 30 digits, K runs each on a new LCS and x0:
the per-run cost the SciPy comparison of ``scale.py`` measures).
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

SCENE = r"""
import sys
sys.path.insert(0, {bench!r})
import lcs_exact as L, systems as S
kind, size = {kind!r}, {size}
case = {{"chain": lambda: S.chain(size), "long": S.long_run, "carts": S.two_carts}}[kind]()
lcs, x0 = case.lcs(), case.exact_x0()
if {run} and kind == "carts":
    runs = [(case.lcs(), case.exact_x0()) for _ in range(size)]
    for lcs, x0 in runs:
        tr = L.simulate(lcs, x0, case.t_end, digits=30)
    print(len(tr.events), tr.certified)
elif {run}:
    try:
        tr = L.simulate(lcs, x0, case.t_end, digits=30,
                        max_events=size if kind == "long" else case.max_events)
    except L.LimitExceeded as e:
        tr = e.trajectory
    print(len(tr.events), tr.certified)
"""


def count(tree: Path, kind: str, size: int, run: bool) -> tuple[int, str]:
    """(instructions, the scene's output) of one process under callgrind."""
    code = SCENE.format(bench=str(tree / "benchmarks"), kind=kind, size=size, run=run)
    env = dict(os.environ, PYTHONHASHSEED="0", PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    p = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                        sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tree)
    m = re.search(r"Collected : (\d+)", p.stderr)
    if p.returncode or not m:
        raise SystemExit(f"{kind}{size}: callgrind failed: {(p.stderr.strip().splitlines() or ['?'])[-1]}")
    return int(m.group(1)), p.stdout.strip()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenes", nargs="*", default=["chain16", "long300"], help="chainN, longK or cartsK")
    ap.add_argument("--tree", type=Path, default=ROOT, help="checkout to measure (default: this one)")
    args = ap.parse_args()
    if shutil.which("valgrind") is None:
        raise SystemExit("valgrind not found (Debian: apt-get install valgrind)")
    tree = args.tree.resolve()
    print(f"lcs_exact at {tree}\n")
    print("| scene | events, certified | instructions (process) | instructions (run) |")
    print("|---|---|---|---|")
    for scene in args.scenes:
        m = re.fullmatch(r"(chain|long|carts)(\d+)", scene)
        if not m:
            raise SystemExit(f"unknown scene {scene!r}: chainN, longK or cartsK")
        kind, size = m.group(1), int(m.group(2))
        base, _ = count(tree, kind, size, run=False)
        total, out = count(tree, kind, size, run=True)
        print(f"| {scene} | {out} | {total / 1e9:.3f} G | {(total - base) / 1e9:.3f} G |", flush=True)


if __name__ == "__main__":
    main()
