"""Speed against error: lcs_exact beside Siconos and a scipy float baseline, on every kind of
system (issue 10). Writes docs/performance.md and docs/performance.png.

    python benchmarks/run.py            # full run (~30-60 min on 2 shared cores)
    python benchmarks/run.py --quick    # a few minutes: fewer steps, digits and repeats
    python benchmarks/run.py --only two_carts,rlc_diode --no-write

For each system: lcs_exact at 15, 30, 100, 1000 digits (median wall time in this process, the
first run in a fresh process, the certified error bound, events, peak memory); Siconos
(``/usr/bin/python3`` with python3-siconos, run through ``benchmarks/siconos_runs.py``;
skipped with a note when it is not importable) with Moreau-Jean (mechanical systems) or
Euler-Moreau (circuits and general LCS) at theta = 1/2 and 1 and several steps h, and the
event-driven scheme (Lsodar) for mechanical systems; the scipy baseline of
``benchmarks/float_baseline.py``. Errors are measured against the certified 30-digit trajectory
on a common grid (``benchmarks/compare_grid.py``).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import lcs_exact as L  # noqa: E402

import compare_grid as CG  # noqa: E402
import float_baseline as FB  # noqa: E402
import systems as S  # noqa: E402

SICONOS_PY = "/usr/bin/python3"
SICONOS_SCRIPT = str(Path(__file__).resolve().parent / "siconos_runs.py")
ENV1 = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")


# --- lcs_exact ------------------------------------------------------------------------------
def log10_rad(b) -> float:
    """log10 of the radius of an arb ball (no float underflow at 1000 digits)."""
    r = b.rad()
    if r == 0:
        return -math.inf
    m, _, e = r.mid_rad_10exp(6)
    return math.log10(int(m)) + int(e)


def exact_run(lcs, x0, T, digits, max_events=1000, time_limit=None):
    """simulate, then every event time and x(T) as balls of `digits` digits: the work a user
    does to obtain certified numbers. Returns (trajectory, log10 of the largest radius)."""
    tr = L.simulate(lcs, x0, T, digits=digits, max_events=max_events, time_limit=time_limit)
    balls = [e.time.ball(digits) for e in tr.events] + [c.ball(digits) for c in tr.state(T)]
    return tr, max(log10_rad(b) for b in balls)


def settle_t_end(case, quick, log):
    """Run at 30 digits to the nominal t_end; if today's engine cannot (time limit, recursion),
    fall back to case.fallback_t_end and say why. Returns (T, stop note, 30-digit trajectory)."""
    lcs, x0 = case.lcs(), case.exact_x0()
    limit = 30 if quick else 120
    t0 = time.perf_counter()
    try:
        tr = L.simulate(lcs, x0, case.t_end, digits=30, max_events=case.max_events, time_limit=limit)
        return case.t_end, "", tr
    except L.LimitExceeded as e:
        tr = e.trajectory
        if len(tr.events) >= case.max_events:
            # the run is meant to stop at max_events: benchmark up to the last whole time unit
            last = Fraction(math.floor(float(tr.events[-1].time)))
            return last, f"max_events = {case.max_events} reached before t = {last}", tr
        why = (f"t = {case.t_end}: {type(e).__name__} after {time.perf_counter() - t0:.0f} s "
               f"with {len(tr.events)} events")
    except RecursionError:
        crashed_after = time.perf_counter() - t0
        n = recursion_count(case, quick, log)
        why = (f"t = {case.t_end}: RecursionError after {crashed_after:.1f} s"
               + (f" (the run reaches {n[0]} events, crashes by {n[1]})" if n else ""))
    log(f"  {case.name}: {why}; benchmarked to t = {case.fallback_t_end}")
    T = case.fallback_t_end
    tr = L.simulate(lcs, x0, T, digits=30, max_events=case.max_events)
    return T, why, tr


def recursion_count(case, quick, log):
    """Largest max_events reached (LimitExceeded, with its partial trajectory) before the
    RecursionError, on a ladder of max_events: (last reached, first crashed)."""
    lcs, x0 = case.lcs(), case.exact_x0()
    ok, step = 0, 40 if quick else 20
    m = 100
    while m <= case.max_events:
        try:
            L.simulate(lcs, x0, case.t_end, digits=30, max_events=m)
            return None
        except L.LimitExceeded:
            ok = m
        except RecursionError:
            return (ok, m)
        m += step
    return None


def time_exact(case, T, digits, repeat):
    lcs, x0 = case.lcs(), case.exact_x0()
    ts, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = exact_run(lcs, x0, T, digits, case.max_events)
        ts.append(time.perf_counter() - t0)
        if ts[-1] > 5:
            break
    return statistics.median(ts), out


COLD = r"""
import json, sys, time
def hwm():  # peak RSS of this process image in kB (ru_maxrss would include the forking parent's)
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1])
from fractions import Fraction
t0 = time.perf_counter()
import lcs_exact
imp = time.perf_counter() - t0
sys.path.insert(0, BENCH)
import run, systems
case = next(c for c in systems.all_cases() if c.name == NAME)
rss0 = hwm()
t0 = time.perf_counter()
tr, bound = run.exact_run(case.lcs(), case.exact_x0(), Fraction(T), DIGITS, case.max_events)
first = time.perf_counter() - t0
rss1 = hwm()
print(json.dumps({"import": imp, "first": first, "rss_mb": rss1 / 1024,
                  "rss_run_mb": (rss1 - rss0) / 1024, "events": len(tr.events)}))
"""


def cold(case_name, T, digits):
    """First run in a fresh interpreter (the import timed apart) and the process's peak RSS."""
    code = COLD.replace("BENCH", repr(str(Path(__file__).resolve().parent))).replace(
        "NAME", repr(case_name)).replace("Fraction(T)", f"Fraction({str(T)!r})").replace("DIGITS", str(digits))
    try:
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=1800)
    except subprocess.TimeoutExpired:
        return {"error": "timeout"}
    if out.returncode != 0:
        return {"error": (out.stderr.strip().splitlines() or ["?"])[-1][:80]}
    return json.loads(out.stdout.strip().splitlines()[-1])


# --- Siconos ----------------------------------------------------------------------------------
def siconos_available():
    if not os.path.exists(SICONOS_PY):
        return f"{SICONOS_PY} not found"
    p = subprocess.run([SICONOS_PY, "-c", "import siconos.kernel"], capture_output=True, text=True,
                       env=ENV1)
    return None if p.returncode == 0 else "python3-siconos not importable: " + \
        (p.stderr.strip().splitlines() or ["?"])[-1]


def siconos_jobs(case, T, grid_dt, quick):
    """(label, job) pairs: the schemes and steps that fit in ~30 s per run."""
    max_steps = 2 * 10**5 if quick else 2 * 10**6
    hs = [Fraction(1, 10**j) for j in range(2, 6)]
    hs = [h for h in hs if T / h <= max_steps and (grid_dt / h).denominator == 1]
    x0 = case.float_x0()
    jobs = []
    if case.mech is not None:
        m = len(case.mech["M"])
        base = {"kind": "lagrangian", "M": case.mech["M"], "K": case.mech["K"], "E": case.mech["E"],
                "q0": [repr(v) for v in x0[:m]], "v0": [repr(v) for v in x0[m:]], "t_end": float(T)}
        for theta in (0.5, 1.0):
            for h in hs:
                jobs.append((f"Moreau-Jean θ={theta:g}", float(h),
                             dict(base, method="moreau_jean", theta=theta, h=float(h),
                                  grid_stride=int(grid_dt / h))))
        tols = (1e-6, 1e-10) if quick else (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
        for tol in tols:
            jobs.append(("event-driven (Lsodar)", tol,
                         dict(base, method="event_driven", h=float(grid_dt), tol=tol, grid_stride=1)))
    else:
        fl = [[repr(float(Fraction(v))) for v in row] for row in (case.A)]
        base = {"kind": "first_order", "A": fl,
                "B": [[repr(float(Fraction(v))) for v in row] for row in case.B],
                "C": [[repr(float(Fraction(v))) for v in row] for row in case.C],
                "D": [[repr(float(Fraction(v))) for v in row] for row in case.D],
                "x0": [repr(v) for v in x0], "t_end": float(T)}
        for theta in (0.5, 1.0):
            for h in hs:
                jobs.append((f"Euler-Moreau θ={theta:g}", float(h),
                             dict(base, method="euler_moreau", theta=theta, h=float(h),
                                  grid_stride=int(grid_dt / h))))
    return jobs


def run_siconos(job, timeout=120):
    t0 = time.perf_counter()
    try:
        p = subprocess.run([SICONOS_PY, SICONOS_SCRIPT], input=json.dumps(job), capture_output=True,
                           text=True, env=ENV1, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout after {timeout} s"}
    if p.returncode != 0:
        lines = [ln for ln in p.stderr.strip().splitlines() if ln.strip()]
        return {"error": (lines or [f"exit {p.returncode}"])[-1][:120]}
    out = json.loads(p.stdout)
    out["process"] = time.perf_counter() - t0
    return out


# --- one system ---------------------------------------------------------------------------------
def bench_case(case, args, log):
    quick = args.quick
    digits_list = (15, 30, 100) if quick else (15, 30, 100, 1000)
    log(f"\n### {case.label}")
    T, stop_note, tr30 = settle_t_end(case, quick, log)
    grid_dt = CG.grid_step(T)
    ref = CG.reference(tr30, T, grid_dt)
    rows = {"case": case.name, "label": case.label, "T": str(T), "note": case.note,
            "stop_note": stop_note, "n": len(case.A), "k": len(case.C), "exact": [], "methods": []}
    for d in digits_list:
        rep = 1 if (quick and d >= 100) else (3 if quick else 5)
        t, (tr, bound) = time_exact(case, T, d, rep)
        c = cold(case.name, T, d) if (not quick or d == 30) else {}
        rows["exact"].append({"digits": d, "time": t, "bound_log10": bound, "events": len(tr.events),
                              "certified": tr.certified, "cold": c})
        log(f"  lcs_exact {d:>4} digits: {t * 1e3:9.1f} ms (cold {c.get('first', float('nan')) * 1e3:.0f} ms,"
            f" peak RSS {c.get('rss_mb', float('nan')):.0f} MB), bound 1e{bound:.0f}, {len(tr.events)} events")
    ours30 = next(r["time"] for r in rows["exact"] if r["digits"] == 30)
    # Siconos
    if args.siconos_missing is None:
        for label, setting, job in siconos_jobs(case, T, grid_dt, quick):
            out = run_siconos(job)
            if "error" in out:
                rows["methods"].append({"method": "Siconos " + label, "setting": setting,
                                        "error": out["error"]})
                log(f"  Siconos {label} {setting:g}: FAILED {out['error']}")
                continue
            err = CG.errors(ref, out["t"], out["x"], out["switch_times"],
                            window=2 * job["h"] if job["method"] != "event_driven" else 1e-6)
            rows["methods"].append({"method": "Siconos " + label, "setting": setting,
                                    "time": out["wall"], "process": out["process"], **err})
            log(f"  Siconos {label} {setting:g}: {out['wall'] * 1e3:9.1f} ms, state err "
                f"{err['state_err']:.1e}, event err {err['event_err']:.1e}")
    # scipy baseline
    rtols = (1e-6, 1e-10) if quick else (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
    method = "Radau" if case.stiff else "DOP853"
    A, B, C, D = ([[float(Fraction(v)) for v in row] for row in M] for M in (case.A, case.B, case.C, case.D))
    for rtol in rtols:
        try:
            ts_ = []
            for _ in range(1 if quick else 3):
                segs, evs, wall = FB.simulate_float(A, B, C, D, case.float_x0(), float(T), case.r,
                                                    rtol=rtol, atol=rtol * 1e-2, method=method)
                ts_.append(wall)
            xs = FB.sample(segs, ref["t"])
            err = CG.errors(ref, ref["t"], xs.tolist(), evs, window=1e-6)
            rows["methods"].append({"method": f"scipy {method} + mode logic", "setting": rtol,
                                    "time": statistics.median(ts_), **err})
            log(f"  scipy {method} rtol {rtol:g}: {statistics.median(ts_) * 1e3:9.1f} ms, state err "
                f"{err['state_err']:.1e}, event err {err['event_err']:.1e}")
        except Exception as e:  # a float run that fails is a result too
            rows["methods"].append({"method": f"scipy {method} + mode logic", "setting": rtol,
                                    "error": f"{type(e).__name__}: {e}"[:120]})
    for m in rows["methods"]:
        if "time" in m:
            m["ratio"] = ours30 / m["time"]
    return rows


ED_NOTE = (
    "Siconos' event-driven scheme (EventDriven + LsodarOSI, impact and acceleration LCPs, "
    "Debian python3-siconos 4.4.0) raises a bare `std::exception` in `processEvents` at the first "
    "impact that is followed by a persistent contact (e = 0), on every mechanical system here. "
    "Reduced by hand: one mass on a spring (`LagrangianLinearTIDS` with `setKPtr([[1]])`, "
    "`setFExtPtr([-1])`) falling on a stop fails the same way, also with K = 1e-9, while the "
    "same mass with gravity only and no K (the Siconos bouncing-ball example with e = 0) runs "
    "to the end. So the failure is tied to a stiffness matrix K in the event-driven path, not "
    "to tolerances (Lsodar rtol = atol from 1e-4 to 1e-12 and `setToleranceED` from 1e-12 to "
    "1e-4 change nothing). The event-driven rows are therefore absent from the plot.")


# --- output -------------------------------------------------------------------------------------
def fmt_t(s):
    return f"{s * 1e3:.1f} ms" if s < 1 else f"{s:.2f} s"


def fmt_e(e):
    if e is None or (isinstance(e, float) and math.isnan(e)):
        return "—"
    return "inf" if e == math.inf else f"{e:.1e}"


def markdown(results, args, siconos_note, elapsed):
    out = []
    w = out.append
    w("# Performance: speed against error\n")
    w(f"Generated by `python benchmarks/run.py{' --quick' if args.quick else ''}` on "
      f"{time.strftime('%Y-%m-%d')} ({os.cpu_count()} shared cores, total {elapsed / 60:.1f} min). "
      "Times are wall-clock medians in one process (lcs_exact, scipy) or inside the Siconos "
      "process around its time loop (model construction and interpreter start excluded); "
      "machines are noisy, ratios are what to read. Load average at the end of the run "
      f"(other jobs share the machine): {os.getloadavg()[0]:.1f}.\n")
    w("**What is timed for lcs_exact:** `simulate` plus every event time and x(T) evaluated as "
      "balls of `digits` digits; the *certified bound* is the largest radius of those balls (every "
      "digit shown is right). *Cold* is the first run in a fresh interpreter (the `import lcs_exact` "
      "cost is listed apart); *peak RSS* is that process's maximum resident set.\n")
    w("**How errors are measured:** against the certified 30-digit lcs_exact trajectory on a "
      "uniform grid (`traj.state(t)` balls at every grid time; `benchmarks/compare_grid.py`); "
      "*state error* = max over grid points farther than 2h (time-stepping) or 1e-6 "
      "(event-locating methods) from an exact event of max_i |x_i - x_i^exact|; *event error* = "
      "max over exact events of the distance to the nearest switch of the method (for time-stepping, "
      "the middle of the step where a multiplier appears or vanishes). *ratio* = lcs_exact's "
      "30-digit time / the method's time: at every row lcs_exact's error (≤ 1e-30) is at least as "
      "good, so ratio < 1 means lcs_exact is faster at equal or better error.\n")
    if siconos_note:
        w(f"**Siconos:** {siconos_note}\n")
    w("![error against time](performance.png)\n")
    w("## Summary: lcs_exact at 30 digits against each method's most accurate run\n")
    w("| system | n, k | T | events | lcs_exact 30 digits | method | best setting | its time | "
      "state error | event error | ratio |")
    w("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        e30 = next(e for e in r["exact"] if e["digits"] == 30)
        by = {}
        for m in r["methods"]:
            if "time" in m and math.isfinite(m.get("state_err", math.inf)):
                b = by.get(m["method"])
                if b is None or m["state_err"] < b["state_err"]:
                    by[m["method"]] = m
        first = True
        for name, m in by.items():
            w(f"| {r['label'] if first else ''} | {str(r['n']) + ', ' + str(r['k']) if first else ''} | "
              f"{r['T'] if first else ''} | {e30['events'] if first else ''} | "
              f"{fmt_t(e30['time']) if first else ''} | {name} | {m['setting']:g} | {fmt_t(m['time'])} | "
              f"{fmt_e(m['state_err'])} | {fmt_e(m['event_err'])} | {m['ratio']:.2g} |")
            first = False
        if first:
            w(f"| {r['label']} | {r['n']}, {r['k']} | {r['T']} | {e30['events']} | {fmt_t(e30['time'])} "
              "| — | | | | | |")
    w("")
    w("## lcs_exact by digits\n")
    w("| system | T | digits | time (median) | cold (first run) | import | certified bound | events | "
      "peak RSS | RSS growth of the run |")
    w("|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        for e in r["exact"]:
            c = e["cold"] or {}
            w(f"| {r['label']} | {r['T']} | {e['digits']} | {fmt_t(e['time'])} | "
              f"{fmt_t(c['first']) if 'first' in c else c.get('error', '—')} | "
              f"{fmt_t(c['import']) if 'import' in c else '—'} | 1e{e['bound_log10']:.0f} | "
              f"{e['events']}{'' if e['certified'] else ' (not certified)'} | "
              f"{str(round(c['rss_mb'])) + ' MB' if 'rss_mb' in c else '—'} | "
              f"{str(round(c['rss_run_mb'])) + ' MB' if 'rss_run_mb' in c else '—'} |")
    w("")
    notes = [r for r in results if r["stop_note"]]
    if notes:
        w("**Runs benchmarked to a shorter t_end than the nominal one, and why** (a run meant to "
          "stop at max_events is benchmarked to the last whole time unit before that):\n")
        for r in notes:
            w(f"- {r['label']}: {r['stop_note']}; benchmarked to T = {r['T']}.")
        w("")
    failed = sorted({(r["label"], m["method"], m["error"]) for r in results for m in r["methods"]
                     if "error" in m})
    if failed:
        w("**What did not run.**\n")
        for label, meth, err in failed:
            w(f"- {label}, {meth}: {err}")
        w("")
        if any("event-driven" in f[1] for f in failed):
            w(ED_NOTE + "\n")
    w("## Every run, side by side\n")
    w("| system | method | setting (h, or tolerance) | time | state error | event error | ratio |")
    w("|---|---|---|---|---|---|---|")
    for r in results:
        for m in r["methods"]:
            if "error" in m:
                w(f"| {r['label']} | {m['method']} | {m['setting']:g} | failed: {m['error']} | | | |")
            else:
                w(f"| {r['label']} | {m['method']} | {m['setting']:g} | {fmt_t(m['time'])} | "
                  f"{fmt_e(m['state_err'])} | {fmt_e(m['event_err'])} | {m['ratio']:.2g} |")
    w("")
    w("## Systems\n")
    for r in results:
        w(f"- **{r['label']}** (n = {r['n']}, k = {r['k']}): {r['note']}.")
    w("")
    return "\n".join(out)


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    styles = {"Siconos Moreau-Jean θ=0.5": ("C0", "o-"), "Siconos Moreau-Jean θ=1": ("C1", "s-"),
              "Siconos Euler-Moreau θ=0.5": ("C0", "o-"), "Siconos Euler-Moreau θ=1": ("C1", "s-"),
              "Siconos event-driven (Lsodar)": ("C2", "^-")}
    FLOOR = 1e-40
    ncol = 4
    nrow = math.ceil(len(results) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.6 * nrow), squeeze=False)
    for ax, r in zip(axes.flat, results):
        byname = {}
        for m in r["methods"]:
            if "time" in m and math.isfinite(m["state_err"]):
                byname.setdefault(m["method"], []).append(m)
        for name, ms in byname.items():
            ms = sorted(ms, key=lambda m: m["time"])
            col, st = styles.get(name, ("C4", "d-"))
            ax.loglog([m["time"] for m in ms], [max(m["state_err"], FLOOR) for m in ms], st, color=col,
                      ms=4, lw=1.2, label=name.replace("Siconos ", "Siconos: ").replace(" + mode logic", ""))
        for e in r["exact"]:
            y = 10.0 ** e["bound_log10"] if e["bound_log10"] > math.log10(FLOOR) else FLOOR
            mk = "*" if y > FLOOR else "v"
            ax.loglog([e["time"]], [y], mk, color="C3", ms=11 if mk == "*" else 8, zorder=5,
                      label="lcs_exact (certified bound)" if e["digits"] == r["exact"][0]["digits"] else None)
            txt = f"{e['digits']}d" if mk == "*" else f"{e['digits']}d\n(1e{e['bound_log10']:.0f})"
            k = [x["digits"] for x in r["exact"]].index(e["digits"])
            ax.annotate(txt, (e["time"], y), textcoords="offset points", ha="center",
                        xytext=(0, 8 if mk == "*" else 6 + 16 * (k % 2)), fontsize=6.5, color="C3")
        failed = sorted({m["method"].replace("Siconos ", "") for m in r["methods"] if "error" in m})
        if failed:
            ax.text(0.02, 0.03, "failed: " + ", ".join(failed), transform=ax.transAxes, fontsize=6.5,
                    va="bottom", color="0.35")
        ax.set_ylim(FLOOR / 3, 10)
        ax.set_title(f"{r['label']}  (T = {r['T']})", fontsize=9)
        ax.set_xlabel("wall time [s]", fontsize=8)
        ax.set_ylabel("max state error", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="major", alpha=0.3)
    for ax in list(axes.flat)[len(results):]:
        ax.axis("off")
    handles, labels = {}, {}
    for ax in axes.flat:
        for h, l in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(l, h)
    fig.legend(list(handles.values()), list(handles.keys()), loc="lower center", ncol=3, fontsize=8,
               frameon=False)
    fig.suptitle("Error against wall time (log-log), lower left is better. lcs_exact: red stars at the "
                 "certified bound (triangles: bound below 1e-40, drawn at the floor)", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 0.97))
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="a few minutes: fewer steps and digits")
    ap.add_argument("--only", help="comma-separated case names (two_carts, rlc_diode, d_positive, "
                    "stiff_rc, chain2, chain4, chain8, chain16, chain24, chain32, long_run)")
    ap.add_argument("--no-write", action="store_true", help="print only; do not write docs/")
    ap.add_argument("--json", help="also dump the raw results to this file")
    args = ap.parse_args()
    start = time.perf_counter()
    args.siconos_missing = siconos_available()
    siconos_note = ("not run: " + args.siconos_missing) if args.siconos_missing else \
        ("python3-siconos (Debian's package, run by the system Python) with OPENBLAS_NUM_THREADS=1, one "
         "subprocess per run; Moreau-Jean and event-driven for the mechanical systems, "
         "Euler-Moreau for circuits and general LCS (see the doc's notes for what does not run).")

    def log(s):
        print(s, flush=True)

    cases = S.all_cases(quick=args.quick)
    if args.only:
        want = args.only.split(",")
        cases = [c for c in S.all_cases() if c.name in want]
    results = []
    for case in cases:
        results.append(bench_case(case, args, log))
    elapsed = time.perf_counter() - start
    md = markdown(results, args, siconos_note, elapsed)
    print("\n" + md)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1, default=str))
    if not args.no_write:
        (ROOT / "docs").mkdir(exist_ok=True)
        perf = ROOT / "docs" / "performance.md"
        from docsections import write_section
        write_section(perf, "<!-- head -->", md)
        plot(results, ROOT / "docs" / "performance.png")
        print(f"\nwrote {perf} and docs/performance.png")


if __name__ == "__main__":
    main()
