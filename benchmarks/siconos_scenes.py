"""Siconos' own tutorial scenes, run by the Debian interpreter (/usr/bin/python3 with
``python3-siconos``; never imported by lcs_exact), for notebook 06 and the scene benchmarks.

Reads one JSON job on stdin, writes one JSON result ``{"t": [...], "x": [[...], ...], "wall": s}``
on stdout.  Jobs (the tutorials' parameters unless overridden):

* ``{"scene": "bouncing_ball", "h": 0.005, "e": 0.9, "g": 9.81, "T": 10, "q0": 1, "theta": 0.5}``:
  BouncingBallTS.py (LagrangianLinearTIDS, NewtonImpactNSL(e), MoreauJeanOSI(theta)); x = (q, q').
* ``{"scene": "relay", "h": 1e-3, "T": 1, "theta": 0.5}``: SimpleExampleRelay.py
  (FirstOrderLinearDS A = 0, relation C = I, B = 2 I, RelayNSL, EulerMoreauOSI); x = (x1, x2).
* ``{"scene": "diode_bridge_cap_filter", "h": 1e-6, "T": 5e-3, "theta": 1}``: DiodeBridgeCapFilter
  (two FirstOrderLinearDS, FirstOrderLinearTIR, ComplementarityConditionNSL(4), EulerMoreauOSI);
  x = (v_C, i_L, v_Cf).
"""
import json
import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import numpy as np  # noqa: E402
import siconos.kernel as sk  # noqa: E402


def bouncing_ball(job):
    h, e, g, T = job.get("h", 0.005), job.get("e", 0.9), job.get("g", 9.81), job.get("T", 10.0)
    ball = sk.LagrangianLinearTIDS([job.get("q0", 1.0)], [0.0], np.eye(1))
    ball.setFExtPtr([-g])
    inter = sk.Interaction(sk.NewtonImpactNSL(e), sk.LagrangianLinearTIR([[1.0]]))
    nsds = sk.NonSmoothDynamicalSystem(0.0, T)
    nsds.insertDynamicalSystem(ball)
    nsds.link(inter, ball)
    s = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), sk.MoreauJeanOSI(job.get("theta", 0.5)), sk.LCP())
    return s, lambda: [float(ball.q()[0]), float(ball.velocity()[0])], [1.0, 0.0]


def relay(job):
    h, T = job.get("h", 1e-3), job.get("T", 1.0)
    ds = sk.FirstOrderLinearDS(np.array([1.0, 1.0]), np.zeros((2, 2)))
    inter = sk.Interaction(sk.RelayNSL(2), sk.FirstOrderLinearR(np.eye(2), 2.0 * np.eye(2)))
    nsds = sk.NonSmoothDynamicalSystem(0.0, T)
    nsds.insertDynamicalSystem(ds)
    nsds.link(inter, ds)
    s = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), sk.EulerMoreauOSI(job.get("theta", 0.5)), sk.Relay())
    return s, lambda: [float(v) for v in ds.x()], [1.0, 1.0]


def diode_bridge_cap_filter(job):
    h, T = job.get("h", 1e-6), job.get("T", 5e-3)
    L, C, R, Cf = 1e-2, 1e-6, 1e3, 300.0e-9
    A1 = np.array([[0.0, -1.0 / C], [1.0 / L, 0.0]])
    ls1 = sk.FirstOrderLinearDS(np.array([10.0, 0.0]), A1)
    ls2 = sk.FirstOrderLinearDS(np.array([0.0]), np.array([[-1.0 / (R * Cf)]]))
    Cm = np.zeros((4, 3))
    Cm[0, 2], Cm[2, 0], Cm[2, 2], Cm[3, 0] = 1.0, -1.0, 1.0, 1.0
    Dm = np.zeros((4, 4))
    Dm[0, 1], Dm[1, 0], Dm[1, 2], Dm[1, 3], Dm[2, 1], Dm[3, 1] = -1.0, 1.0, 1.0, -1.0, -1.0, 1.0
    Bm = np.zeros((3, 4))
    Bm[0, 2], Bm[0, 3], Bm[2, 0], Bm[2, 2] = -1.0 / C, 1.0 / C, 1.0 / Cf, 1.0 / Cf
    rel = sk.FirstOrderLinearTIR(Cm, Bm)
    rel.setDPtr(Dm)
    inter = sk.Interaction(sk.ComplementarityConditionNSL(4), rel)
    nsds = sk.NonSmoothDynamicalSystem(0.0, T)
    nsds.insertDynamicalSystem(ls1)
    nsds.insertDynamicalSystem(ls2)
    nsds.link(inter, ls1, ls2)
    s = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, h), sk.EulerMoreauOSI(job.get("theta", 1.0)), sk.LCP())
    return s, lambda: [float(ls1.x()[0]), float(ls1.x()[1]), float(ls2.x()[0])], [10.0, 0.0, 0.0]


SCENES = {"bouncing_ball": bouncing_ball, "relay": relay, "diode_bridge_cap_filter": diode_bridge_cap_filter}


def main():
    job = json.loads(sys.stdin.read())
    s, state, x0 = SCENES[job["scene"]](job)
    stride = int(job.get("stride", 1))
    ts, xs = [0.0], [x0]
    k = 0
    start = time.perf_counter()
    while s.hasNextEvent():
        s.computeOneStep()
        k += 1
        if k % stride == 0:
            ts.append(float(s.nextTime()))
            xs.append(state())
        s.nextStep()
    wall = time.perf_counter() - start
    json.dump({"t": ts, "x": xs, "wall": wall, "steps": k}, sys.stdout)


if __name__ == "__main__":
    main()
