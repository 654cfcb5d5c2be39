"""Siconos side of the benchmarks: run by the Debian interpreter (/usr/bin/python3, which has
``python3-siconos``), never imported by lcs_exact.

Reads one JSON job on stdin, writes one JSON result on stdout::

    job = {"kind": "lagrangian", "M": [[..]], "K": [[..]], "E": [[..]], "q0": [..], "v0": [..],
           # or "kind": "first_order", "A", "B", "C", "D", "x0"
           "t_end": 3, "method": "moreau_jean" | "euler_moreau" | "event_driven",
           "theta": 0.5, "h": 1e-3, "tol": 1e-8 (event_driven), "grid_stride": 10}
    result = {"wall": seconds of the time loop only, "setup": seconds to build the model,
              "t": [...], "x": [[...], ...] (state at every grid_stride-th step),
              "switch_times": [...] (times where some constraint becomes active or inactive:
              its multiplier crosses a threshold; event-driven: the non-grid event times),
              "steps": int}

Numbers arrive as decimal strings (exact rationals printed to 17+ digits) and are read with
float(). Wall time is measured inside this process with time.perf_counter around the time loop
(model construction and interpreter start are reported apart). Methods:

* ``moreau_jean``: LagrangianLinearTIDS + LagrangianLinearTIR + NewtonImpactNSL(e = 0) (one
  interaction per row of E) + MoreauJeanOSI(theta) + TimeStepping + LCP.
* ``euler_moreau``: FirstOrderLinearTIDS + FirstOrderLinearTIR(C, B) with D +
  ComplementarityConditionNSL(k) + EulerMoreauOSI(theta) + TimeStepping + LCP.
* ``event_driven``: the Lagrangian model with LsodarOSI + EventDriven and two LCPs (impact and
  acceleration level); ``tol`` sets Lsodar's rtol = atol, ``h`` the output time step.
"""
import json
import sys
import time

import numpy as np
import siconos.kernel as sk


def arr(v):
    return np.array([[float(c) for c in row] for row in v]) if isinstance(v[0], list) \
        else np.array([float(c) for c in v])


def lagrangian(job):
    M, K, E = arr(job["M"]), arr(job["K"]), arr(job["E"])
    ds = sk.LagrangianLinearTIDS(arr(job["q0"]), arr(job["v0"]), M)
    ds.setKPtr(K)
    T = float(job["t_end"])
    nsds = sk.NonSmoothDynamicalSystem(0.0, T)
    nsds.insertDynamicalSystem(ds)
    inters = []
    for row in E:
        inter = sk.Interaction(sk.NewtonImpactNSL(0.0), sk.LagrangianLinearTIR(row.reshape(1, -1)))
        nsds.link(inter, ds)
        inters.append(inter)
    return ds, nsds, inters, T


def run_time_stepping(job):
    t_setup = time.perf_counter()
    h = float(job["h"])
    stride = int(job["grid_stride"])
    if job["kind"] == "lagrangian":
        ds, nsds, inters, T = lagrangian(job)
        osi = sk.MoreauJeanOSI(float(job["theta"]))
        level = 1
        n = 2 * len(job["q0"])

        def state():
            return np.concatenate((ds.q(), ds.velocity()))
    else:
        A, B, C, D = arr(job["A"]), arr(job["B"]), arr(job["C"]), arr(job["D"])
        T = float(job["t_end"])
        ds = sk.FirstOrderLinearTIDS(arr(job["x0"]), A)
        rel = sk.FirstOrderLinearTIR(C, B)
        rel.setDPtr(D)
        inter = sk.Interaction(sk.ComplementarityConditionNSL(C.shape[0]), rel)
        nsds = sk.NonSmoothDynamicalSystem(0.0, T)
        nsds.insertDynamicalSystem(ds)
        nsds.link(inter, ds)
        inters = [inter]
        osi = sk.EulerMoreauOSI(float(job["theta"]))
        level = 0
        n = len(job["x0"])

        def state():
            return np.array(ds.x())
    td = sk.TimeDiscretisation(0.0, h)
    sim = sk.TimeStepping(nsds, td, osi, sk.LCP())
    steps = int(round(T / h))
    k_total = sum(len(it.lambda_(level)) if it.lambda_(level) is not None else 1 for it in inters)
    lam = np.zeros((steps + 1, k_total))
    xs = np.zeros((steps // stride + 1, n))
    xs[0] = state()
    setup = time.perf_counter() - t_setup
    t0 = time.perf_counter()
    k = 0
    while sim.hasNextEvent() and k < steps:
        sim.computeOneStep()
        k += 1
        j = 0
        for it in inters:
            lv = it.lambda_(level)
            lam[k, j:j + len(lv)] = lv
            j += len(lv)
        if k % stride == 0:
            xs[k // stride] = state()
        sim.nextStep()
    wall = time.perf_counter() - t0
    ts = [i * stride * h for i in range(k // stride + 1)]
    scale = max(float(np.abs(lam).max()), 1e-300)
    active = lam[: k + 1] > 1e-9 * scale
    switches = []
    for i in range(k_total):
        # the multiplier appears or vanishes between steps c - 1 and c: report the midpoint
        ch = np.nonzero(active[1:, i] != active[:-1, i])[0] + 1
        switches.extend(float((c - 0.5) * h) for c in ch)
    return {"wall": wall, "setup": setup, "t": ts, "x": xs[: k // stride + 1].tolist(),
            "switch_times": switches, "steps": k}


def run_event_driven(job):
    t_setup = time.perf_counter()
    ds, nsds, inters, T = lagrangian(job)
    h = float(job["h"])
    td = sk.TimeDiscretisation(0.0, h)
    sim = sk.EventDriven(nsds, td)
    osi = sk.LsodarOSI()
    tol = float(job.get("tol", 1e-8))
    osi.setTol(1, tol, tol)
    sim.insertIntegrator(osi)
    sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
    sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
    sim.setPrintStat(False)
    n = 2 * len(job["q0"])
    setup = time.perf_counter() - t_setup
    rec_t, rec_x, rec_l = [0.0], [np.concatenate((ds.q(), ds.velocity()))], []
    t0 = time.perf_counter()
    k = 0
    while sim.hasNextEvent():
        sim.advanceToEvent()
        try:
            sim.processEvents()
        except Exception as e:  # SWIG turns Siconos' exceptions into a bare std::exception
            raise RuntimeError(f"EventDriven.processEvents raised {e} at t = {sim.startingTime():.6g} "
                               f"(event near {sim.nextTime():.9g}, after {k} steps)") from None
        k += 1
        rec_t.append(sim.startingTime())
        rec_x.append(np.concatenate((ds.q(), ds.velocity())))
        rec_l.append([float(it.lambda_(2)[0]) if it.lambda_(2) is not None else 0.0 for it in inters]
                     + [float(it.lambda_(1)[0]) if it.lambda_(1) is not None else 0.0 for it in inters])
        if k > 10 * int(T / h) + 100000:
            raise RuntimeError("event-driven run does not advance")
    wall = time.perf_counter() - t0
    # keep the output grid (multiples of h); events in between are reported as switch times
    ts = np.array(rec_t)
    grid_t, grid_x = [], []
    stride = int(job["grid_stride"])
    for i in range(0, int(round(T / h)) + 1, stride):
        j = int(np.argmin(np.abs(ts - i * h)))
        grid_t.append(i * h)
        grid_x.append(list(rec_x[j]))
    m = len(inters)
    lam = np.array(rec_l) if rec_l else np.zeros((0, 2 * m))
    on_grid = np.abs(ts[1:] / h - np.round(ts[1:] / h)) < 1e-9
    switches = [float(t) for t, g in zip(ts[1:], on_grid) if not g]
    return {"wall": wall, "setup": setup, "t": grid_t, "x": grid_x, "switch_times": switches,
            "steps": k, "lambda_max": float(np.abs(lam).max()) if lam.size else 0.0}


def main():
    job = json.loads(sys.stdin.read())
    if job["method"] == "event_driven":
        out = run_event_driven(job)
    else:
        out = run_time_stepping(job)
    sys.stdout.write(json.dumps(out))


if __name__ == "__main__":
    main()
