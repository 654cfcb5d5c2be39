"""Fixtures and compare: time to write a sampled fixture, to read it back, and to compare a
solution against it (section 7 run of the two carts).

    python benchmarks/fixtures.py            # prints the table (about a minute today)
    python benchmarks/fixtures.py --quick    # grids up to 301 points

The target of issue 9: a 3001-point grid in well under a second (one exponential sum per phase,
not a fresh e^{At} per point); compare through samples is linear in the points.
"""
from __future__ import annotations

import json
import sys
import time
from fractions import Fraction
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import lcs_exact as L  # noqa: E402
from lcs_exact.models import two_carts  # noqa: E402


def main(quick: bool) -> None:
    carts = two_carts()
    x0 = L.expm_action(carts.A, -1, [0, -1, -1, 0])
    tr = L.simulate(carts, x0, 3, digits=30)
    t0 = time.perf_counter()
    tr.to_fixture(20)  # the events' closed forms are proven on first access (SymPy, Calcium): once
    print(f"first fixture without samples (proves the closed forms 1, 1 + pi/2): {time.perf_counter() - t0:.2f} s\n")
    print("| grid points | digits | traj.sample s | to_fixture s | JSON kB | read_fixture s | compare (samples) s | compare (exact) s |")
    print("|---|---|---|---|---|---|---|---|")
    for n in ((31, 301) if quick else (31, 301, 3001)):
        for digits in (17, 30):
            h = f"3/{n - 1}"
            grid = [Fraction(3 * j, n - 1) for j in range(n)]
            t0 = time.perf_counter()
            tr.sample(grid, digits)
            t_s = time.perf_counter() - t0
            t0 = time.perf_counter()
            fx = tr.to_fixture(digits, sample=h)
            t_fx = time.perf_counter() - t0
            size = len(json.dumps(fx)) // 1024
            t0 = time.perf_counter()
            back = L.read_fixture(fx)
            t_read = time.perf_counter() - t0
            ts = [s.t for s in back.samples]
            X = [[float(b.mid()) for b in s.x] for s in back.samples]
            t0 = time.perf_counter()
            L.compare(back, ts, X)
            t_cmp = time.perf_counter() - t0
            t0 = time.perf_counter()
            L.compare(tr, ts, X)  # the live trajectory: exact evaluation at every time
            t_exact = time.perf_counter() - t0
            print(f"| {n} | {digits} | {t_s:.3f} | {t_fx:.3f} | {size} | {t_read:.2f} | {t_cmp:.2f} | {t_exact:.2f} |")


if __name__ == "__main__":
    main("--quick" in sys.argv)
