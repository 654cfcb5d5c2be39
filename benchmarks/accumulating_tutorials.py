"""Siconos' tutorials whose impacts accumulate, run to their horizons by lcs_exact (issue 28): the time
of each run, its events, the accumulations proven and crossed (which proof), and the state at the end.

    python benchmarks/accumulating_tutorials.py                 # all three (the column takes 10-20 min)
    python benchmarks/accumulating_tutorials.py --only two      # LinearOscillatorED and TwoBouncingBalls

* LinearOscillatorED (a mass of 1e-3 on springs k = 100, floor, e = 9/10, T = 8.5): one contact
  bouncing without a geometric law (``lcs_exact.accumulations.bounces``).
* TwoBouncingBalls (m = 1 and 2, R = 0.1, e = 19/20, T = 3): two contacts taking turns, an inelastic
  collapse (``lcs_exact.accumulations.collapses``).
* ColumnOfBeadsTS (10 beads of radius 1/10 from heights 1 + i/4, e = 9/10, g = 9.81, T = 2): beads
  settling one by one onto the stack, the beads above colliding among themselves meanwhile.

Each run is certified (every digit reported is right); the table prints the times to 12 digits.
"""
from __future__ import annotations

import argparse
import sys
import time
from fractions import Fraction as F
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import lcs_exact as L  # noqa: E402
from lcs_exact.examples import ball_column  # noqa: E402


def linear_oscillator_ed():
    m, R, g = F(1, 1000), F(1, 10), F(981, 100)
    M = [[m, 0, 0], [0, m, 0], [0, 0, F(3, 5) * m * R * R]]
    lcs = L.models.mechanical(M, [[100, 0, 0], [0, 100, 0], [0, 0, 0]], [[1, 0, 0]], force=[-m * g, 0, 0],
                              restitution=F(9, 10), name="LinearOscillatorED")
    return lcs, lcs.embed([1, F(1, 1000), 0, 0, 0, 0]), F(17, 2)


def two_bouncing_balls():
    R, g = F(1, 10), F(981, 100)
    lcs = L.models.mechanical([[1, 0], [0, 2]], [[0, 0], [0, 0]], [[1, 0], [-1, 1]], force=[-g, -2 * g],
                              gap=[0, -2 * R], restitution=F(19, 20), name="TwoBouncingBalls")
    return lcs, lcs.embed([R, 3 * R + F(1, 1000), 0, 0]), F(3)


def column_of_beads():
    col = ball_column(10, g="981/100", e="9/10", radius="1/10")
    return col, col.embed([1 + F(i, 4) for i in range(10)] + [0] * 10), F(2)


SCENES = {"LinearOscillatorED": linear_oscillator_ed, "TwoBouncingBalls": two_bouncing_balls,
          "ColumnOfBeadsTS": column_of_beads}


def run(name: str) -> None:
    lcs, x0, T = SCENES[name]()
    t0 = time.perf_counter()
    tr = L.simulate(lcs, x0, T, max_events=10_000)
    wall = time.perf_counter() - t0
    print(f"| {name} | {float(T)} | {wall:.1f} s | {len(tr.events)} | {tr.status.name} | {tr.certified} | "
          f"{len(tr.accumulations)} |", flush=True)
    for a in tr.accumulations:
        kind = type(a.cycle).__name__ if a.cycle is not None else "law"
        print(f"|   T* = {a.time.ball(12).str(13, radius=False)} | after event {a.first_event} | {kind} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", choices=["two", "all"], default="all")
    names = list(SCENES)[:2] if ap.parse_args().only == "two" else list(SCENES)
    print("| scene | horizon | time | events | status | certified | accumulations |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        run(name)


if __name__ == "__main__":
    main()
