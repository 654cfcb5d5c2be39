"""The scenes beyond the paper (DESIGN.md section 7), timed, beside Siconos' runs of its own
tutorials where /usr/bin/python3 has python3-siconos (benchmarks/siconos_scenes.py).

    python benchmarks/scenes.py            # a table: scene, events, lcs_exact time (best of 3),
                                           # Siconos' method, time and error against the exact run

Times are wall-clock on this machine, best of three runs in one process; Siconos' errors are
measured on its own output grid (t > 0) against lcs_exact's certified samples (17 digits).
"""
from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import time

from lcs_exact import examples as ex
from lcs_exact import models, simulate
from lcs_exact.algebra import to_fmpq

HERE = pathlib.Path(__file__).resolve().parent


def best(f, n=3):
    out, dt = None, float("inf")
    for _ in range(n):
        t0 = time.perf_counter()
        out = f()
        dt = min(dt, time.perf_counter() - t0)
    return out, dt


def siconos(job):
    py = shutil.which("python3", path="/usr/bin")
    if py is None:
        return None
    p = subprocess.run([py, str(HERE / "siconos_scenes.py")], input=json.dumps(job), capture_output=True, text=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    return json.loads(p.stdout) if p.returncode == 0 else None


def error(traj, run, component, stride=1):
    """Max |x_component| error on Siconos' grid for t > 0 (at t = 0 the exact state may jump)."""
    ts, xs = run["t"][stride::stride], run["x"][stride::stride]
    exact = traj.sample([to_fmpq(t) for t in ts], 17)
    return max(abs(float(b[component].mid()) - x[component]) for b, x in zip(exact, xs))


def main():
    rows = []
    ball = ex.bouncing_ball()
    tr, dt = best(lambda: simulate(ball, ball.embed([1, 0]), 10))
    run = siconos({"scene": "bouncing_ball", "h": 0.005})
    rows.append(("bouncing ball (h=1, e=0.9, T=10)", tr, dt, "Moreau-Jean h=5e-3", run,
                 None if run is None else error(tr, run, 0, 5)))
    relays = models.relay([[0, 0], [0, 0]], [[-2, 0], [0, -2]], [[1, 0], [0, 1]])
    tr, dt = best(lambda: simulate(relays, relays.embed([1, 1]), 1))
    run = siconos({"scene": "relay", "h": 1e-3})
    rows.append(("SimpleExampleRelay (T=1)", tr, dt, "Euler-Moreau h=1e-3", run, None if run is None else error(tr, run, 0)))
    bridge = ex.diode_bridge_cap_filter()
    tr, dt = best(lambda: simulate(bridge, [10, 0, 0], "1/200"), 1)
    for theta in (1.0, 0.5):
        run = siconos({"scene": "diode_bridge_cap_filter", "h": 1e-6, "theta": theta, "stride": 50})
        rows.append((f"DiodeBridgeCapFilter (T=5 ms)", tr, dt, f"Euler-Moreau theta={theta} h=1e-6", run,
                     None if run is None else error(tr, run, 0)))
    for name, lcs, x0, T in (("half-wave rectifier, sine (T=20)", ex.sine_rectifier(), None, 20),
                             ("full-wave floating bridge, sine (T=20)", ex.sine_rectifier(full_wave=True), None, 20),
                             ("column of 3 beads (T=1)", ex.ball_column(3), ["1/20", "3/20", "1/2", 0, 0, 0], 1),
                             ("ball on a spring (T=30)", ex.ball_on_spring(), [6, 0], 30)):
        x = lcs.embed(x0 if x0 is not None else [0])
        tr, dt = best(lambda: simulate(lcs, x, T))
        rows.append((name, tr, dt, "", None, None))
    print(f"| scene | events | accumulations | lcs_exact (certified) | Siconos | Siconos time | Siconos max error |")
    print("|---|---|---|---|---|---|---|")
    for name, tr, dt, method, run, err in rows:
        sic = "not installed" if method and run is None else method or "—"
        st = f"{run['wall']:.3f} s" if run is not None else "—"
        se = f"{err:.3g}" if err is not None else "—"
        print(f"| {name} | {len(tr.events)} | {len(tr.accumulations)} | {dt * 1000:.1f} ms | {sic} | {st} | {se} |")


if __name__ == "__main__":
    main()
