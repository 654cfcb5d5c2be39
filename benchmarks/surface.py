"""Benchmarks of the user's surface: mode maps (exact face enumeration) and figures.

    python benchmarks/surface.py

Prints Markdown tables: mode-map size and time per system, and the time to draw a trajectory
figure against the number of sample points (each sample is a certified evaluation of x, u, y,
so this measures the core's evaluation speed as much as the plotting).  Medians of 3 runs.
"""
from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import lcs_exact as L  # noqa: E402
from lcs_exact.examples import diode_bridge, half_wave_rectifier, two_carts, two_carts_with_hook  # noqa: E402


def timed(fn, repeat=3):
    ts, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts), out


def table(title, head, rows):
    print(f"\n## {title}\n")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print("| " + " | ".join(str(c) for c in r) + " |")


def main():
    fig82 = ([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]])
    cases = [("Figure 8.2 (hook, 2-D slice)", two_carts_with_hook, fig82),
             ("two carts, full R^4", two_carts, None),
             ("hook, full R^4", two_carts_with_hook, None),
             ("half-wave rectifier, R^2", half_wave_rectifier, None),
             ("diode bridge (k = 4), R^2", diode_bridge, None)]
    rows = []
    for name, build, sl in cases:
        lcs = build()
        t, mm = timed(lambda: lcs.mode_map(slice=sl))
        rows.append((name, lcs.n, lcs.k, len(mm.hyperplanes), len(mm.faces), len(mm.regions), f"{t:.3f}"))
    table("mode_map: exact partition by S(x0)", ["system", "n", "k", "hyperplanes", "faces", "regions", "seconds"], rows)

    c = two_carts()
    tr = L.simulate(c, L.expm_action(c.A, -1, [0, -1, -1, 0]), 3)
    rows = []
    tr.plot(points=50)  # first figure: matplotlib's fonts and caches
    plt.close("all")
    for points in (200, 800, 3200):
        t, fig = timed(lambda: tr.plot(points=points), repeat=3)
        plt.close("all")
        rows.append((points, f"{t:.3f}"))
    table("traj.plot(): section 7 run (2 events, 3 panels; 800 is the default)", ["points", "seconds"], rows)

    lcs = L.LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-5, 2, 0, 0], [1, "-3/2", 0, 0]], [[0], [0], [1], [0]],
                [[1, 0, 0, 0]], [[0]])
    try:
        long = L.simulate(lcs, [1, "1/3", 0, "1/2"], 10 ** 6, max_events=200)
    except L.LimitExceeded as e:
        long = e.trajectory
    t, fig = timed(lambda: long.plot(), repeat=1)
    plt.close("all")
    table("traj.plot(): 200 events (a partial run, 800 points plus 6 per phase)", ["events", "seconds"],
          [(len(long.events), f"{t:.2f}")])


if __name__ == "__main__":
    main()
