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
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import lcs_exact as L  # noqa: E402
from lcs_exact.models import two_carts  # noqa: E402


def main(quick: bool) -> None:
    carts = two_carts()
    x0 = L.expm_action(carts.A, -1, [0, -1, -1, 0])
    tr = L.simulate(carts, x0, 3, digits=20)
    print("| grid points | digits | to_fixture s | JSON kB | read_fixture s | compare (samples) s | compare (exact) s |")
    print("|---|---|---|---|---|---|---|")
    for n in ((31, 301) if quick else (31, 301, 3001)):
        h = f"3/{n - 1}"
        t0 = time.perf_counter()
        fx = tr.to_fixture(20, sample=h)
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
        print(f"| {n} | 20 | {t_fx:.2f} | {size} | {t_read:.2f} | {t_cmp:.2f} | {t_exact:.2f} |")


if __name__ == "__main__":
    main("--quick" in sys.argv)
