"""Benchmarks of lcs_exact: speed against digits, per-event cost, LDCP vs RCP selection, and
speed against error for Siconos (Moreau-Jean time-stepping) on the paper's section 7 run.

    python benchmarks/run.py            # prints the tables (Siconos rows need python3-siconos
                                        # for /usr/bin/python3; they are skipped with a note if absent)

Times are medians of a few runs in one process (ratios are what to read: machines are noisy).
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import mpmath as mp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import lcs_exact as L  # noqa: E402
from lcs_exact.models import mechanical, two_carts  # noqa: E402

A2 = [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]]


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


def section7(digits):
    x0 = L.expm_action(A2, -1, [0, -1, -1, 0])
    tr = L.simulate(two_carts(), x0, 3, digits=digits)
    x3 = [c.ball(digits) for c in tr.state(3)]  # force every output to `digits` digits
    return tr, x3


def bench_digits():
    rows = []
    for d in (15, 30, 100, 300, 1000):
        t, (tr, _) = timed(lambda: section7(d), repeat=3 if d < 1000 else 1)
        rows.append((d, f"{t * 1e3:.1f}", len(tr.events), tr.events[1].time.closed_form))
    table("Section 7 run (x0 = e^{-A}(0,-1,-1,0), T = 3): time against digits",
          ["digits", "ms (run + x(3) to digits)", "events", "2nd event"], rows)


def bench_events():
    m2 = mechanical([[2, 0], [0, 3]], [[0, 0], [0, 0]], [[3, -1], [-1, 2]], [[1, 0]])
    rows = []
    for T in (25, 50, 100, 200):
        t, tr = timed(lambda: L.simulate(m2, [1, 0, 0, 1], T, digits=30), repeat=1)
        n = len(tr.events)
        rows.append((T, n, f"{t:.2f}", f"{1e3 * t / max(n, 1):.1f}", tr.certified))
    table("Two masses (2, 3), stop on mass 1: cost per event (30 digits)",
          ["T", "events", "s", "ms / event", "certified"], rows)


def bench_digits_transcendental():
    m2 = mechanical([[2, 0], [0, 3]], [[0, 0], [0, 0]], [[3, -1], [-1, 2]], [[1, 0]])
    rows = []
    for d in (15, 30, 100, 300, 1000):
        def run():
            tr = L.simulate(m2, [1, 0, 0, 1], 50, digits=d)
            for e in tr.events:  # every event time and the final state to d digits
                e.time.ball(d)
            return tr, [c.ball(d) for c in tr.state(50)]
        t, (tr, _) = timed(run, repeat=1)
        rows.append((d, len(tr.events), f"{t:.2f}"))
    table("Two masses (2, 3), T = 50: every event time and x(T) to `digits` (transcendental states)",
          ["digits", "events", "s"], rows)


def bench_stiff():
    rows = []
    for k in (10**2, 10**4, 10**6):
        s = mechanical([[1, 0], [0, 1]], [[0, 0], [0, 0]], [[1 + k, -k], [-k, k]], [[1, 0]])
        t, tr = timed(lambda: L.simulate(s, [1, 1, 0, 0], 5, digits=30), repeat=1)
        rows.append((k, len(tr.events), f"{t:.2f}", tr.events[0].time.decimal(20)))
    table("Stiff chain: wall spring 1, coupling k, stop on mass 1, from q = (1, 1)",
          ["k", "events", "s", "first impact"], rows)
    rows = []
    for k in (10**2, 10**4, 10**6):
        s = mechanical([[1, 0], [0, 1]], [[0, 0], [0, 0]], [[k, -k], [-k, k]], [[1, 0]])
        t, tr = timed(lambda: L.simulate(s, [1, 1, -1, 0], "21/10", digits=30), repeat=1)
        rows.append((k, len(tr.events), f"{t:.2f}", tr.events[0].time.decimal(20)))
    table("Stiff free pair (χ = s²(s² + 2k): repeated eigenvalue 0, Jordan-Chevalley path), "
          "from q = (1, 1), v = (-1, 0)", ["k", "events", "s", "first impact"], rows)


def bench_selection():
    import random
    random.seed(1)
    rows = []
    for k in (2, 4, 6, 8):
        m = k
        M = [[2 if i == j else 0 for j in range(m)] for i in range(m)]
        K = [[2 if i == j else (-1 if abs(i - j) == 1 else 0) for j in range(m)] for i in range(m)]
        E = [[1 if i == j else 0 for j in range(m)] for i in range(k)]
        lcs = mechanical(M, [[0] * m for _ in range(m)], K, E)
        x0 = [0] * m + [random.choice([-2, -1, 1]) for _ in range(m)]
        lcs.select_modes(x0, "ldcp")
        t_l, s_l = timed(lambda: lcs.select_modes(x0, "ldcp"))
        if k <= 6:
            lcs.select_modes(x0, "rcp")  # builds the 2^k mode data once
            t_r, s_r = timed(lambda: lcs.select_modes(x0, "rcp"), repeat=1)
            agree, rcp = s_l == s_r, f"{t_r * 1e3:.1f}"
        else:
            agree, rcp = "-", "(2^k modes: skipped)"
        rows.append((k, f"{t_l * 1e3:.2f}", rcp, agree))
    table("Mode selection at an impact of a k-mass chain (all positions on the stops)",
          ["k", "LDCP_n ms", "RCP over 2^k modes ms (data cached)", "same S(x0)"], rows)


SICONOS = r'''
import json, sys, time
import numpy as np
import siconos.kernel as sk
h, T = float(sys.argv[1]), 3.0
x0 = json.loads(sys.argv[2])
q0, v0 = np.array(x0[:2]), np.array(x0[2:])
ds = sk.LagrangianLinearTIDS(q0, v0, np.eye(2))
ds.setKPtr(np.array([[2.0, -1.0], [-1.0, 1.0]]))
rel = sk.LagrangianLinearTIR(np.array([[1.0, 0.0]]))
inter = sk.Interaction(sk.NewtonImpactNSL(0.0), rel)
model = sk.NonSmoothDynamicalSystem(0.0, T)
model.insertDynamicalSystem(ds); model.link(inter, ds)
td = sk.TimeDiscretisation(0.0, h)
osi = sk.MoreauJeanOSI(0.5)
sim = sk.TimeStepping(model, td, osi, sk.LCP())
t0 = time.perf_counter()
while sim.hasNextEvent():
    sim.computeOneStep(); sim.nextStep()
el = time.perf_counter() - t0
print(json.dumps({"q": list(ds.q()), "v": list(ds.velocity()), "time": el}))
'''


def bench_siconos():
    mp.mp.dps = 40
    want = mp.expm(mp.matrix(A2) * (2 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1])
    x0 = [float(v) for v in mp.expm(mp.matrix(A2) * -1) * mp.matrix([0, -1, -1, 0])]
    py = "/usr/bin/python3"
    probe = subprocess.run([py, "-c", "import siconos.kernel"], capture_output=True) if os.path.exists(py) else None
    rows = []
    t_ex, (tr, x3) = timed(lambda: section7(30))
    err_ex = max(abs(mp.mpf(b.mid().str(35, radius=False)) - want[i]) for i, b in enumerate(x3))
    rows.append(("lcs_exact, 30 digits", "-", f"{t_ex * 1e3:.1f}", mp.nstr(err_ex, 3), "certified, closed-form events"))
    if probe is None or probe.returncode != 0:
        table("Speed against error at x(3), section 7", ["solver", "h", "ms", "max |x(3) error|", "note"], rows)
        print("\n(Siconos rows skipped: `apt-get install python3-siconos` for /usr/bin/python3)")
        return
    for h in (1e-2, 1e-3, 1e-4):
        out = subprocess.run([py, "-c", SICONOS, str(h), json.dumps(x0)], capture_output=True, text=True)
        if out.returncode != 0:
            rows.append(("Siconos Moreau-Jean", h, "-", "-", out.stderr.strip().splitlines()[-1][:60]))
            continue
        r = json.loads(out.stdout.strip().splitlines()[-1])
        got = r["q"] + r["v"]
        err = max(abs(mp.mpf(g) - want[i]) for i, g in enumerate(got))
        rows.append(("Siconos Moreau-Jean (theta 0.5)", h, f"{r['time'] * 1e3:.1f}", mp.nstr(err, 3), "time-stepping"))
    table("Speed against error at x(3), section 7", ["solver", "h", "ms", "max |x(3) error|", "note"], rows)


if __name__ == "__main__":
    print("# lcs_exact benchmarks")
    bench_digits()
    bench_digits_transcendental()
    bench_events()
    bench_stiff()
    bench_selection()
    bench_siconos()
