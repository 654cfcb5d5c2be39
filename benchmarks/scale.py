"""Scale (issues 14 and 30): lcs_exact beside Siconos and the SciPy float baseline at the sizes numerical
solvers run, every ratio taken within one run, each measurement printed next to the issue's
target (reported, not judged).  Run from the repository root:

    python benchmarks/scale.py            # full: N = 8, 16, 24, 32 (5 repeats) and 64 (3) (~4 min)
    python benchmarks/scale.py --quick    # N = 8, 16, 24, 32, fewer repeats (~2 min)
    python benchmarks/scale.py --quick --chain 64   # only the chain, only N = 64 (~30 s a repeat)
    python benchmarks/scale.py --write    # also replace the "Scale" section of docs/performance.md
    python benchmarks/scale.py --profile 32   # only: where the time of the N = 32 chain goes

What is measured (the machine has 2 shared cores: every comparison alternates the programs, one
run of each per repeat, and reports medians; a ratio is the median over repeats of the ratio of
the two runs of that repeat):

1. Chain of N unit carts (``systems.chain(N)``: ``lcs_exact.examples.cart_chain(N)``, q0 =
   (1, -1, 1, ...)/2, v0 = 0, T = 10), N = 8, 16, 24, 32, 64 (n = 2N, k = N/2; --quick stops at
   32, --chain chooses the N).  lcs_exact:
   ``simulate(lcs, x0, 10, digits=30)``, each run in a fresh interpreter after a warm-up run of
   a small system (imports, caches), timed around ``simulate`` alone; the same process then
   evaluates every event time and x(T) as 30-digit balls (reported apart).  Siconos: Moreau-Jean,
   theta = 1/2 (the convention of benchmarks/core.py), h = 1e-4, through
   ``benchmarks/siconos_runs.py`` under /usr/bin/python3 with OPENBLAS_NUM_THREADS=1; its time is
   the time loop inside that process (model construction and interpreter start excluded).  SciPy:
   ``float_baseline.simulate_float`` with DOP853, rtol = 1e-10, atol = 1e-12 (run.py's atol =
   rtol/100), in this process after a warm-up run.  Time per event uses lcs_exact's count of
   events; the exponent is the least-squares slope of log(time per event) on log(n), n = 32 to
   128.  Each tool's count is printed: lcs_exact's events, Siconos' switches (a constraint's
   multiplier appears or vanishes between two steps; one per constraint, and the distinct step
   times), SciPy's distinct event times (a cluster of impacts within float resolution is one).
2. The float baseline's LCP is Lemke's method (``float_baseline.lcp``), checked here against the
   former 2^k enumeration on random P-matrix LCPs (``float_baseline.self_test``).
3. 1000 events: ``systems.long_run()`` (two masses, one stop) with max_events = 1000, in a fresh
   interpreter after a warm-up; the time stamps of the events come from the public progress hook
   (``simulate(..., progress=True)`` with a stand-in for tqdm that records perf_counter at every
   update: one update per event, included in the total).  Siconos: Euler-Moreau (the first-order
   formulation, FirstOrderLinearTIDS + EulerMoreauOSI), theta = 1/2, h = 1e-3, to the time of
   lcs_exact's 1000th event.
4. Two carts (section 7: x0 = expm_action(A, -1, (0, -1, -1, 0)), T = 3): lcs_exact
   ``simulate(..., digits=30)`` against the SciPy baseline (DOP853, rtol = 1e-10, atol = 1e-12),
   in this process, alternated, after a warm-up; a fresh LCS and x0 for every lcs_exact repeat
   (built outside the timed region, like SciPy's float x0).
5. Cold start: ``python -m lcs_exact two-carts`` against ``python -c "import lcs_exact"`` as
   whole processes (wall time around ``subprocess.run``), alternated A B A B after one unrecorded
   run of each.
6. First simulate: in a fresh interpreter, ``import lcs_exact``, then ``simulate`` of the two
   carts (section 7, digits = 30) twice, each with a new LCS and x0 built outside the timed
   region; the overhead is the first run's time minus the second's (the modules the first run
   imports are listed: numpy, SymPy and SciPy should not be among them).

Every program here runs with OPENBLAS_NUM_THREADS=1 (set before numpy is imported).

``--profile N`` (N carts): after a warm-up, one run sampled every 2-5 ms of CPU time (SIGPROF,
no profiler's overhead) and attributed to what the engine is doing - the innermost frame of the
main thread's stack that belongs to one of the groups of ``PROFILE_GROUPS`` (mode selection and
the LDCP, spectral data per mode, root search, anchoring and state evaluation, closed forms) -
then one run under cProfile, its top 15 functions by cumulative and by own time.
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

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
BENCH = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(BENCH))

import float_baseline as FB  # noqa: E402
import systems as S  # noqa: E402

SICONOS_PY = "/usr/bin/python3"
SICONOS_SCRIPT = str(BENCH / "siconos_runs.py")
ENV1 = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
MARKER = "<!-- scale -->"
#: the issue's targets (issue 30): lcs_exact / Siconos Moreau-Jean h = 1e-4 and lcs_exact / SciPy
#: DOP853 rtol 1e-10 on the chain of N carts; the exponent of time per event from n = 32 to n = 128
TARGET_SICONOS = {16: "≤ 0.03", 32: "≤ 0.05", 64: "≤ 0.05"}
TARGET_SCIPY = {16: "≤ 3"}
EXPONENT_N = (32, 128)
TARGET_EXPONENT = "≤ 2"
TARGET_FIRST_CALL = "≤ 30 ms"
WHERE_THE_TIME_GOES = (
    '### Where the time goes\n\n'
    '`python benchmarks/scale.py --profile 32` groups the time of the 32-cart chain by what the engine '
    'is doing (a SIGPROF sample every few ms of CPU time, given to the innermost frame in a group), '
    "then prints cProfile's top functions; instruction counts (valgrind's callgrind, "
    '`benchmarks/instructions.py`) are the way to compare two versions on this noisy machine. Since '
    'issue 30 the phases of a system of 32 states or more are evaluated on Taylor steps '
    '(lcs_exact/numbers/taylorsteps.py, lcs_exact/phases/taylorsum.py: J ball matrix-vector products '
    'a step, the polynomials of all monitored rows from one product a column, no eigenvalues), the '
    'modes of small systems, stiff modes and long quiet horizons keep the spectral data. Measured on '
    '2026-12-08 with py-spy (sampling, 2-5 ms a sample, no profiler overhead in the shares; lcs_exact '
    'at cbeb249): at N = 16 the event search takes 53 % of the CPU time (of which the screen of the '
    'phases without an early crossing 16 %), mode selection and re-initialization 23 % (the LDCP '
    'stages 12 %, new modes\' projections 5 %), phase set-up 11 %, anchoring 7 %; at N = 64 the search '
    '53 % (the ordering of roots in a cluster 12 %), selection and re-initialization 30 % (LDCP 14 %, '
    'projections 8 %), phase set-up 13 %; at N = 64 re-evaluations of earlier phases at higher '
    'precision are 27 % (in the clusters some constraints start at 10^-280 with a first derivative '
    'of 10^-185: their starts need 600-1200 bits, and each doubling evaluates the cluster\'s history '
    'again from the exact start: one phase of 64 carts costs 0.25 s that way); no closed forms and no '
    'spectral data. The profiles are flat: the largest own time is the ball products of the steps '
    '(5 % at N = 16, 11 % at N = 64: 35 us a product at n = 128 whatever the precision, the n^2 loop '
    'of a dense matrix with ~4n nonzeros), then per-row steps of the search, the exact forms of the '
    'LDCP stages and the subspaces of each new mode, spread over Python overhead. What took the last '
    'factors (instructions of the run, `benchmarks/instructions.py`, from 507de8f: N = 16 0.835e9 -> '
    '0.564e9, N = 32 3.51e9 -> 2.36e9, N = 64 24.6e9 -> 16.3e9, the 1000 events of the long run '
    '7.79e9 -> 7.03e9; every event of the chains unchanged to the last digit of its radius): mode '
    'selection reads each sign once (the certified signs of Murty\'s last pass give an LDCP stage its '
    'new I and J), membership in a span of relations as one product with its echelon rows and for all '
    'the rows of a phase at once, a mode\'s constraint rows as two blocks, the forms vanishing on a '
    'phase iterated modulo the mode\'s annihilator, F_I as (U S) P_I, steps rebuilt at a higher '
    'precision with a first step that holds the whole phase once its event is bracketed, a ball\'s '
    'rounding past a step\'s end evaluated on that step (every phase\'s start check computed a second '
    'step of ~71 terms for it), the search\'s first step from the screen\'s earliest guess (a crossing '
    'at 0.0129 of a step of length 1: ~30 terms at 181 bits, not 71), Horner before the composed '
    'bound in positivity proofs, each root compared with the first once, and unscaled columns '
    'M^j x_k (the factors h^j / j! on the rows\' coefficients; x_{k+1} summed only when the next step '
    'is asked for). Where the instructions go (callgrind, 32 carts, at 81fc222): half inside FLINT '
    '(exact products fmpq_mat_mul 17 %, of which half is clearing denominators; ball products '
    'arb_mat_mul of the Taylor steps 13 %; fmpq_mat from Python lists 7 %; rref 4 %), a quarter in '
    'the interpreter, the rest in allocation and python-flint\'s wrappers: compiling all the Python '
    'around FLINT would give at most ~2x. Measured and not kept: P_I v as v - T (K v) (fewer '
    'conversions, but wider balls steer the run to higher precisions: 3.6x the steps\' terms on 64 '
    'carts); screens with steps of ||A_I h|| = 8 (a quiet phase of 32 carts is no longer proven at 64 '
    'bits); Murty\'s passes as one ball product, P_I v from P\'s integer numerator, the screen\'s '
    'guesses restricting the search\'s, and fixed-point integer steps (fmpz_mat products: 26-30 us '
    'against 35 at n = 128): no gain in instructions, or none worth the code. The remaining factors '
    'need less arithmetic: a search that treats all rows of a step at once, and for N = 64 a start '
    'that does not re-evaluate a cluster\'s history at each doubling of the precision.'
)

# one lcs_exact point in a fresh interpreter: warm-up, then the timed run; prints one JSON line
CHILD = r"""
import json, sys, time, types
sys.path.insert(0, BENCH)
spec = json.loads(SPEC)
stamps = []
class _Bar:  # stands in for tqdm: simulate(progress=True) calls update once per event
    def __init__(self, *a, **k):
        self.n = 0.0
    def update(self, d):
        stamps.append(time.perf_counter())
        self.n += d
    def close(self):
        pass
_m = types.ModuleType("tqdm.auto")
_m.tqdm = _Bar
sys.modules["tqdm.auto"] = _m
import lcs_exact as L
import systems as S
from lcs_exact.models import two_carts
L.simulate(two_carts(), [1, 0, 0, 0], 2)            # warm-up: imports, caches
case = S.chain(spec["N"]) if spec["what"] == "chain" else S.long_run()
lcs, x0 = case.lcs(), case.exact_x0()
T = case.t_end
out = {"status": "ok"}
t0 = time.perf_counter()
try:
    tr = L.simulate(lcs, x0, T, digits=30, max_events=case.max_events, progress=spec["what"] == "long_run")
except L.LimitExceeded as e:
    tr = e.trajectory
    out["status"] = "max_events" if len(tr.events) >= case.max_events else type(e).__name__
out["time"] = time.perf_counter() - t0
out["events"] = len(tr.events)
out["certified"] = bool(tr.certified)
out["t_last"] = float(tr.events[-1].time) if tr.events else None
if spec["what"] == "chain" and out["status"] == "ok":
    t1 = time.perf_counter()
    for ev in tr.events:
        ev.time.ball(30)
    [c.ball(30) for c in tr.state(T)]
    out["eval"] = time.perf_counter() - t1
if stamps:
    d = [b - a for a, b in zip([t0] + stamps, stamps)]   # d[i]: wall time of event i + 1
    def window(lo, hi):
        w = d[lo:hi]
        return {"median": sorted(w)[len(w) // 2], "mean": sum(w) / len(w), "range": [lo + 1, min(hi, len(d))]}
    out["near100"] = window(75, 125)
    out["near1000"] = window(len(d) - 50, len(d))
    out["stamps"] = len(stamps)
print(json.dumps(out))
"""


def lcs_point(spec, timeout=900):
    code = CHILD.replace("BENCH", repr(str(BENCH))).replace("SPEC", repr(json.dumps(spec)))
    t0 = time.perf_counter()
    try:
        p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                           env=ENV1, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": f"timeout after {timeout} s"}
    if p.returncode != 0:
        return {"status": "error: " + (p.stderr.strip().splitlines() or ["?"])[-1][:120]}
    out = json.loads(p.stdout.strip().splitlines()[-1])
    out["process"] = time.perf_counter() - t0
    return out


# --- Siconos -------------------------------------------------------------------------------------
def siconos_check():
    """None when /usr/bin/python3 imports siconos.kernel, else the reason."""
    if not os.path.exists(SICONOS_PY):
        return f"{SICONOS_PY} not found"
    p = subprocess.run([SICONOS_PY, "-c", "import siconos, siconos.kernel; print(siconos.__file__)"],
                       capture_output=True, text=True, env=ENV1)
    if p.returncode:
        return "siconos not importable: " + (p.stderr.strip().splitlines() or ["?"])[-1]
    return None


def siconos_version():
    p = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "python3-siconos"], capture_output=True,
                       text=True)
    return p.stdout.strip() or "?"


def run_siconos(job, timeout=600):
    try:
        p = subprocess.run([SICONOS_PY, SICONOS_SCRIPT], input=json.dumps(job), capture_output=True,
                           text=True, env=ENV1, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"error": f"timeout after {timeout} s"}
    if p.returncode != 0:
        lines = [ln for ln in p.stderr.strip().splitlines() if ln.strip()]
        return {"error": (lines or [f"exit {p.returncode}"])[-1][:120]}
    return json.loads(p.stdout)


def fl(v):
    return repr(float(Fraction(v)))


def moreau_jean_job(case, T, h):
    x0 = case.float_x0()
    m = len(case.mech["M"])
    return {"kind": "lagrangian", "M": case.mech["M"], "K": case.mech["K"], "E": case.mech["E"],
            "q0": [repr(v) for v in x0[:m]], "v0": [repr(v) for v in x0[m:]], "t_end": float(T),
            "method": "moreau_jean", "theta": 0.5, "h": h, "grid_stride": 1000}


def euler_moreau_job(case, T, h):
    mat = lambda M: [[fl(v) for v in row] for row in M]  # noqa: E731
    return {"kind": "first_order", "A": mat(case.A), "B": mat(case.B), "C": mat(case.C),
            "D": mat(case.D), "x0": [repr(v) for v in case.float_x0()], "t_end": float(T),
            "method": "euler_moreau", "theta": 0.5, "h": h, "grid_stride": 1000}


# --- SciPy ---------------------------------------------------------------------------------------
def scipy_run(case, T):
    A, B, C, D = ([[float(Fraction(v)) for v in row] for row in M] for M in (case.A, case.B, case.C, case.D))
    segs, evs, wall = FB.simulate_float(A, B, C, D, case.float_x0(), float(T), case.r, rtol=1e-10,
                                        atol=1e-12, method="DOP853")
    return wall, len(evs)


# --- helpers -------------------------------------------------------------------------------------
def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def paired_ratio(a, b):
    """Median over repeats of a[i] / b[i] (the two runs of one repeat)."""
    return med([x / y for x, y in zip(a, b) if x is not None and y])


def fit(xs, ys):
    """Least-squares slope of log y against log x (None with fewer than 2 points)."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x and y and x > 0 and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx else None


def ts(s):
    if s is None:
        return "—"
    return f"{s * 1e3:.1f} ms" if s < 1 else f"{s:.2f} s"


def rs(r):
    return "—" if r is None else (f"{r:.3g}" if r < 100 else f"{r:.0f}")


class Out:
    """Collects markdown lines and prints them as they come."""

    def __init__(self):
        self.lines = []

    def __call__(self, s=""):
        self.lines.append(s)
        print(s, flush=True)

    def table(self, head, rows):
        self("| " + " | ".join(head) + " |")
        self("|" + "---|" * len(head))
        for r in rows:
            self("| " + " | ".join(str(c) for c in r) + " |")
        self()


def git_state():
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                              cwd=ROOT).stdout.strip()
        dirty = subprocess.run(["git", "status", "--short", "--", "lcs_exact"], capture_output=True,
                               text=True, cwd=ROOT).stdout.split("\n")
        dirty = [ln[3:].strip() for ln in dirty if ln.strip()]
    except OSError:
        return "?"
    if not dirty:
        return head
    shown = [f for f in dirty if (ROOT / f).is_file()]   # the docs cite only files that exist
    gone = len(dirty) - len(shown)
    return (head + f" with uncommitted changes in {', '.join(shown)}"
            + (f" and {gone} removed or renamed files" if gone else ""))


# --- the five measurements ------------------------------------------------------------------------
def chain_section(out, Ns, repeat, sic_ok, summary, log):
    res = {N: {"lcs": [], "eval": [], "sic": [], "sp": [], "events": None, "cert": [], "status": [],
               "sp_events": None, "sic_events": None} for N in Ns}
    cases = {N: S.chain(N) for N in Ns}
    for N in Ns:   # SciPy warm-up (imports, first-call costs) in this process
        scipy_run(cases[N], cases[N].t_end)
    for rep in range(repeat):
        for N in Ns:
            if rep >= (min(repeat, 3) if N >= 64 else repeat):   # N = 64: 2-3 min a repeat, 3 at most
                continue
            c = cases[N]
            r = lcs_point({"what": "chain", "N": N})
            d = res[N]
            d["status"].append(r["status"])
            if "time" in r:
                d["lcs"].append(r["time"])
                d["eval"].append(r.get("eval"))
                d["events"] = r["events"]
                d["cert"].append(r["certified"])
            else:
                d["lcs"].append(None)
            if sic_ok:
                s = run_siconos(moreau_jean_job(c, c.t_end, 1e-4))
                d["sic"].append(s.get("wall"))
                if "error" in s:
                    d.setdefault("sic_err", s["error"])
                else:
                    sw = s.get("switch_times", [])
                    d["sic_events"] = f"{len(sw)} ({len(set(sw))} times)"
            w, ne = scipy_run(c, c.t_end)
            d["sp"].append(w)
            d["sp_events"] = ne
            log(f"  repeat {rep + 1}/{repeat}, N = {N}: lcs_exact {ts(d['lcs'][-1])} ({r['status']}), "
                f"Siconos {ts(d['sic'][-1]) if sic_ok else '—'}, SciPy {ts(w)}")
    rows, xs, ys = [], [], []
    for N in Ns:
        d = res[N]
        t = med(d["lcs"])
        ev = d["events"]
        per = t / ev if t and ev else None
        cert = ("yes" if all(d["cert"]) else f"NO ({sum(not c for c in d['cert'])} of {len(d['cert'])})") \
            if d["cert"] else "—"
        st = ", ".join(sorted(set(d["status"])))
        r_sic = paired_ratio(d["lcs"], d["sic"]) if sic_ok else None
        r_sp = paired_ratio(d["lcs"], d["sp"])
        d.update(t=t, per=per, r_sic=r_sic, r_sp=r_sp, cert_s=cert)
        rows.append((N, 2 * N, N // 2, ts(t) + ("" if st == "ok" else f" ({st})"), ev, cert, ts(per),
                     ts(med(d["eval"])), ts(med(d["sic"])) if sic_ok else d.get("sic_err", "not run"),
                     d["sic_events"] if sic_ok else "—", ts(med(d["sp"])), d["sp_events"], rs(r_sic),
                     TARGET_SICONOS.get(N, ""), rs(r_sp), TARGET_SCIPY.get(N, "")))
        if per and EXPONENT_N[0] <= 2 * N <= EXPONENT_N[1]:
            xs.append(2 * N)
            ys.append(per)
    out("### Chain of N carts to t = 10: lcs_exact (30 digits) beside Siconos and SciPy\n")
    reps = ", ".join(f"{min(repeat, 3)} for N = {N}" for N in Ns if N >= 64 and repeat > 3)
    out(f"Medians of {repeat} repeats{' (' + reps + ')' if reps else ''}; in each repeat lcs_exact (fresh "
        "interpreter after a warm-up), Siconos and SciPy run one after the other for each N. *+ balls*: "
        "every event time and x(10) evaluated as 30-digit balls after `simulate` (same process, not in "
        "the time). Ratios are medians of the per-repeat ratios. Events: lcs_exact's; Siconos' "
        "switches (one per constraint whose multiplier appears or vanishes between two steps) and their "
        "distinct step times; SciPy's distinct event times.\n")
    out.table(["N", "n", "k", "lcs_exact", "events", "certified", "per event", "+ balls",
               "Siconos MJ h=1e-4", "Siconos switches", "SciPy DOP853 1e-10", "SciPy events",
               "lcs/Siconos", "target", "lcs/SciPy", "target"], rows)
    e = fit(xs, ys)
    lo, hi = EXPONENT_N
    out(f"Fitted exponent of lcs_exact's time per event against n (least squares on log-log, "
        f"n = {', '.join(map(str, xs))}): **{'—' if e is None else f'{e:.2f}'}** (target: {TARGET_EXPONENT} "
        f"from n = {lo} to n = {hi}"
        f"{'' if hi in xs else '; this run stops at n = ' + str(max(xs, default=0))}).\n")
    for N in Ns:
        d = res[N]
        if N in TARGET_SICONOS:
            summary.append((f"chain of {N} carts: lcs_exact / Siconos MJ h=1e-4", rs(d["r_sic"]),
                            TARGET_SICONOS[N], f"{ts(d['t'])} vs {ts(med(d['sic']))}; events "
                            f"{d['events']} vs {d['sic_events']} switches; certified: {d['cert_s']}"))
        if N in TARGET_SCIPY:
            summary.append((f"chain of {N} carts: lcs_exact / SciPy DOP853 rtol 1e-10", rs(d["r_sp"]),
                            TARGET_SCIPY[N], f"{ts(d['t'])} vs {ts(med(d['sp']))}; events {d['events']} "
                            f"vs {d['sp_events']}"))
    summary.append((f"time per event against n (exponent, n = {lo} to {hi})", "—" if e is None else f"{e:.2f}",
                    TARGET_EXPONENT, f"n = {', '.join(map(str, xs))}"))
    return res, e


def long_run_section(out, repeat, sic_ok, summary, log):
    lcs, sic = [], []
    runs = []
    for rep in range(repeat):
        r = lcs_point({"what": "long_run"}, timeout=1800)
        runs.append(r)
        lcs.append(r.get("time"))
        if sic_ok and r.get("t_last"):
            s = run_siconos(euler_moreau_job(S.long_run(), r["t_last"], 1e-3), timeout=900)
            sic.append(s.get("wall"))
            if "error" in s:
                log(f"  Siconos Euler-Moreau failed: {s['error']}")
        log(f"  repeat {rep + 1}/{repeat}: lcs_exact {ts(r.get('time'))} ({r.get('status')}, "
            f"{r.get('events')} events), Siconos {ts(sic[-1]) if sic else '—'}")
    ok = [r for r in runs if "near100" in r]
    t = med(lcs)
    n_ev = runs[-1].get("events")
    t_last = runs[-1].get("t_last")
    n100 = med([r["near100"]["median"] for r in ok])
    n1000 = med([r["near1000"]["median"] for r in ok])
    m100 = med([r["near100"]["mean"] for r in ok])
    m1000 = med([r["near1000"]["mean"] for r in ok])
    ratio = paired_ratio(lcs, sic) if sic_ok else None
    flat = n1000 / n100 if n100 and n1000 else None
    out("### 1000 events: two masses, one stop (`systems.long_run()`, max_events = 1000)\n")
    out(f"Medians of {repeat} alternated repeats (lcs_exact in a fresh interpreter after a warm-up, then "
        f"Siconos). Siconos: Euler-Moreau (first-order formulation), θ = 1/2, h = 1e-3, to the time of "
        f"lcs_exact's 1000th event, t = {t_last:.4f} ({round(t_last / 1e-3)} steps). Per event: the "
        "wall time between consecutive events (progress-hook time stamps), median and mean over "
        f"events {ok[0]['near100']['range'][0]}-{ok[0]['near100']['range'][1]} and "
        f"{ok[0]['near1000']['range'][0]}-{ok[0]['near1000']['range'][1]}, then the median over "
        "repeats.\n" if ok and t_last else "")
    rows = [("lcs_exact, 30 digits: total", f"{ts(t)} for {n_ev} events ({ts(t / n_ev if t and n_ev else None)} "
             f"per event), status {', '.join(sorted({str(r.get('status')) for r in runs}))}", ""),
            ("Siconos Euler-Moreau h = 1e-3, same horizon", ts(med(sic)) if sic_ok else "not run", ""),
            ("lcs_exact / Siconos", rs(ratio), "≤ 0.2"),
            ("lcs_exact per event near event 100 (median / mean)", f"{ts(n100)} / {ts(m100)}", ""),
            ("lcs_exact per event near event 1000 (median / mean)", f"{ts(n1000)} / {ts(m1000)}", ""),
            ("per event, event ~1000 / event ~100 (medians)", rs(flat), "flat (≈ 1)")]
    out.table(["measure", "value", "target"], rows)
    summary.append(("1000 events: lcs_exact / Siconos Euler-Moreau h=1e-3", rs(ratio), "≤ 0.2",
                    f"{ts(t)} vs {ts(med(sic))}"))
    summary.append(("1000 events: per event near 1000 / near 100", rs(flat), "flat",
                    f"{ts(n100)} → {ts(n1000)}"))


def two_carts_section(out, repeat, summary):
    import lcs_exact as L
    case = S.two_carts()
    T = case.t_end
    same_lcs, same_x0 = case.lcs(), case.exact_x0()

    def lcs_run(balls=False, fresh=True):
        lcs, x0 = (case.lcs(), case.exact_x0()) if fresh else (same_lcs, same_x0)
        t0 = time.perf_counter()
        tr = L.simulate(lcs, x0, T, digits=30)
        if balls:
            for ev in tr.events:
                ev.time.ball(30)
            [c.ball(30) for c in tr.state(T)]
        return time.perf_counter() - t0, tr

    for _ in range(3):      # warm-up
        lcs_run(True)
        lcs_run(fresh=False)
        scipy_run(case, T)
    a, ab, ar, b = [], [], [], []
    cert = True
    for _ in range(repeat):
        t, tr = lcs_run()
        a.append(t)
        cert = cert and tr.certified
        b.append(scipy_run(case, T)[0])
        ab.append(lcs_run(True)[0])
        ar.append(lcs_run(fresh=False)[0])
    r, rb, rr = paired_ratio(a, b), paired_ratio(ab, b), paired_ratio(ar, b)
    out("### Two carts (section 7), T = 3: lcs_exact at 30 digits beside SciPy, in this process\n")
    out(f"Medians of {repeat} alternated repeats after 3 warm-up runs of each; {len(tr.events)} events, "
        f"certified: {'yes' if cert else 'NO'}. lcs_exact gets a new `LCS` and x0 for every run (built "
        "outside the timed region) except on the *same LCS* row, which reuses one LCS object and x0 "
        "(what benchmarks/run.py and benchmarks/core.py time).\n")
    out.table(["measure", "value", "target"],
              [("lcs_exact `simulate(..., digits=30)`", ts(med(a)), ""),
               ("lcs_exact, + event times and x(3) as 30-digit balls", ts(med(ab)), ""),
               ("lcs_exact, same LCS object and x0 every run", ts(med(ar)), ""),
               ("SciPy DOP853 rtol 1e-10 (float baseline)", ts(med(b)), ""),
               ("lcs_exact / SciPy (simulate)", rs(r), "≤ 1"),
               ("lcs_exact / SciPy (+ balls)", rs(rb), ""),
               ("lcs_exact / SciPy (same LCS)", rs(rr), "")])
    summary.append(("two carts: lcs_exact 30 digits / SciPy DOP853 rtol 1e-10", rs(r), "≤ 1",
                    f"{ts(med(a))} vs {ts(med(b))} (with 30-digit balls: {rs(rb)}; same LCS: {rs(rr)})"))


def cold_section(out, repeat, summary):
    A = [sys.executable, "-m", "lcs_exact", "two-carts"]
    B = [sys.executable, "-c", "import lcs_exact"]

    def run(cmd):
        t0 = time.perf_counter()
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=ROOT, env=ENV1)
        el = time.perf_counter() - t0
        if p.returncode:
            raise RuntimeError(f"{' '.join(cmd[1:])} exited {p.returncode}: {p.stderr[-200:]}")
        return el
    run(A)
    run(B)
    ta, tb = [], []
    for _ in range(repeat):
        ta.append(run(A))
        tb.append(run(B))
    r = paired_ratio(ta, tb)
    out("### Cold start: whole processes\n")
    out(f"Wall time of each process (`subprocess.run`), {repeat} alternated pairs A B A B after one "
        "unrecorded run of each; medians.\n")
    out.table(["measure", "value", "target"],
              [("A: `python -m lcs_exact two-carts`", ts(med(ta)), ""),
               ("B: `python -c \"import lcs_exact\"`", ts(med(tb)), ""),
               ("A / B", rs(r), "≤ 2")])
    summary.append(("cold start: `python -m lcs_exact two-carts` / `import lcs_exact`", rs(r), "≤ 2",
                    f"{ts(med(ta))} vs {ts(med(tb))}"))


# the first simulate in a fresh interpreter against the second (two carts, section 7)
FIRST_CALL = r"""
import json, sys, time
import lcs_exact as L
from lcs_exact.examples import two_carts
def run():
    c = two_carts()
    x0 = L.expm_action(c.A, -1, [0, -1, -1, 0])
    before = set(sys.modules)
    t0 = time.perf_counter()
    tr = L.simulate(c, x0, 3, digits=30)
    el = time.perf_counter() - t0
    return el, sorted({m.split(".")[0] for m in set(sys.modules) - before}), len(tr.events)
first, new, ev = run()
second, _, _ = run()
print(json.dumps({"first": first, "second": second, "imported": new, "events": ev}))
"""


def first_call_section(out, repeat, summary):
    firsts, seconds, diffs, imported = [], [], [], set()
    for _ in range(repeat):
        p = subprocess.run([sys.executable, "-c", FIRST_CALL], capture_output=True, text=True, cwd=ROOT,
                           env=ENV1, check=True)
        r = json.loads(p.stdout.strip().splitlines()[-1])
        firsts.append(r["first"])
        seconds.append(r["second"])
        diffs.append(r["first"] - r["second"])
        imported |= set(r["imported"])
    heavy = sorted(imported & {"numpy", "sympy", "scipy", "matplotlib"})
    out("### First simulate in a process: the two carts (section 7), digits = 30\n")
    out(f"{repeat} fresh interpreters: `import lcs_exact`, then `simulate` twice (a new LCS and x0 "
        "each time, built outside the timed region); medians. Overhead: first run minus second, "
        "per process.\n")
    out.table(["measure", "value", "target"],
              [("first `simulate`", ts(med(firsts)), ""),
               ("second `simulate`", ts(med(seconds)), ""),
               ("first - second (median; range)", f"{ts(med(diffs))} ({ts(min(diffs))} .. {ts(max(diffs))})",
                TARGET_FIRST_CALL),
               ("modules the first run imports (top level)", ", ".join(sorted(imported)) or "none", ""),
               ("numpy, SymPy, SciPy, matplotlib among them", ", ".join(heavy) or "none", "none")])
    summary.append(("first simulate in a process - second (two carts)", ts(med(diffs)), TARGET_FIRST_CALL,
                    f"{ts(med(firsts))} vs {ts(med(seconds))}; heavy imports: {', '.join(heavy) or 'none'}"))


#: what the engine is doing, by the innermost frame of the stack in one of these groups: (file
#: under lcs_exact/, function names or None for all of the file)
PROFILE_GROUPS = [
    ("spectral data per mode", [("numbers/expm.py", None), ("modes/mode.py", {"spectrum"})]),
    ("root search", [("phases/roots.py", None), ("phases/polyroots.py", None),
                     ("phases/guesses.py", None), ("phases/flow.py", None)]),
    ("anchoring / state evaluation", [("numbers/nodes.py", None), ("numbers/reals.py", None),
                                      ("numbers/vectors.py", None), ("numbers/taylormodels.py", None),
                                      ("phases/phase.py", {"_compute", "state", "ball_state", "event_state",
                                                             "_exact_state", "_jacobian_over"}),
                                      ("dynamics/simulate.py", {"anchor"})]),
    ("mode selection / LDCP (and re-initialization)",
     [("modes/", None), ("algebra/lcp.py", None), ("system/impacts.py", None),
      ("dynamics/simulate.py", {"select_and_reinitialize", "choose", "_impulse"})]),
    ("closed forms", [("numbers/closedforms.py", None), ("numbers/calcium.py", None)]),
]


def _group_of(frame, pkg):
    """The group of the innermost frame of the stack that belongs to one (None: none does)."""
    while frame is not None:
        code = frame.f_code
        fn = code.co_filename
        if fn.startswith(pkg):
            rel = fn[len(pkg):].replace(os.sep, "/")
            for name, rules in PROFILE_GROUPS:
                for prefix, funcs in rules:
                    if rel.startswith(prefix) and (funcs is None or code.co_name in funcs):
                        return name
        frame = frame.f_back
    return None


def sampled_run(L, case, interval=0.002):
    """One simulate of ``case`` sampled every ``interval`` seconds of CPU time (SIGPROF, at the
    kernel timer's granularity: the handler runs in the main thread between bytecodes, with the
    frame it interrupted; a thread that sampled instead slowed the run by 20-40 % through the
    GIL): ({group: samples}, samples, wall seconds, CPU seconds, trajectory)."""
    import signal
    pkg = os.path.dirname(os.path.abspath(L.__file__)) + os.sep
    counts = {}

    def handler(signum, frame):
        g = _group_of(frame, pkg)
        counts[g] = counts.get(g, 0) + 1
    lcs, x0 = case.lcs(), case.exact_x0()
    old = signal.signal(signal.SIGPROF, handler)
    signal.setitimer(signal.ITIMER_PROF, interval, interval)
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        tr = L.simulate(lcs, x0, case.t_end, digits=30)
    finally:
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        signal.setitimer(signal.ITIMER_PROF, 0, 0)
        signal.signal(signal.SIGPROF, old)
    return counts, sum(counts.values()), wall, cpu, tr


def profile(N):
    """Where the time of the N-cart chain goes (after a warm-up): a sampled run grouped by what
    the engine is doing (PROFILE_GROUPS), then cProfile's top 15 by cumulative and by own time."""
    import cProfile
    import pstats
    import lcs_exact as L
    from lcs_exact.models import two_carts
    L.simulate(two_carts(), [1, 0, 0, 0], 2)
    case = S.chain(N)
    counts, total, wall, cpu, tr = sampled_run(L, case)
    print(f"chain of {N} carts (n = {2 * N}, k = {N // 2}): {len(tr.events)} events, certified "
          f"{tr.certified}, {wall:.2f} s ({wall / max(1, len(tr.events)):.3f} s an event) without a "
          f"profiler ({cpu:.2f} s CPU); {total} samples, one every {1e3 * cpu / max(1, total):.1f} ms of CPU "
          f"time, each given to the innermost frame in a group (time: that share of the CPU time):\n")
    print("| group | share | time |\n|---|---|---|")
    for name in [g for g, _ in PROFILE_GROUPS] + [None]:
        c = counts.get(name, 0)
        print(f"| {name or 'other (event loop, phase set-up, trajectory, exact algebra outside the groups)'} "
              f"| {100 * c / max(1, total):.0f} % | {ts(cpu * c / max(1, total))} |")
    print()
    lcs, x0 = case.lcs(), case.exact_x0()
    pr = cProfile.Profile()
    t0 = time.perf_counter()
    pr.enable()
    tr = L.simulate(lcs, x0, case.t_end, digits=30)
    pr.disable()
    print(f"under cProfile: {time.perf_counter() - t0:.2f} s")
    st = pstats.Stats(pr)
    st.sort_stats("cumulative").print_stats(15)
    st.sort_stats("tottime").print_stats(15)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N up to 32, fewer repeats (~2 min)")
    ap.add_argument("--chain", metavar="N,N,...", help="only the chain, at these N (e.g. 16,32,64)")
    ap.add_argument("--write", action="store_true", help="replace the Scale section of docs/performance.md")
    ap.add_argument("--profile", type=int, metavar="N", help="only: where the time of the N-cart chain goes")
    args = ap.parse_args()
    if args.write and args.chain:
        ap.error("--write replaces the whole Scale section: not with --chain")
    if args.profile:
        profile(args.profile)
        return
    q = args.quick
    Ns = tuple(int(v) for v in args.chain.split(",")) if args.chain else \
        (8, 16, 24, 32) if q else (8, 16, 24, 32, 64)
    reps = {"chain": 3 if q else 5, "long": 2 if q else 5, "carts": 11 if q else 31, "cold": 5 if q else 9,
            "first": 7 if q else 15}
    start = time.perf_counter()
    load0 = os.getloadavg()[0]
    out = Out()
    summary = []

    def log(s):
        print(s, file=sys.stderr, flush=True)

    sic_err = siconos_check()
    sic_ok = sic_err is None
    n_trials, worst, resid = FB.self_test()
    out("## Scale (issue 30 targets)\n")
    flags = (" --quick" if q else "") + (f" --chain {args.chain}" if args.chain else "")
    out(f"Generated by `python benchmarks/scale.py{flags}` on {time.strftime('%Y-%m-%d')} "
        f"(lcs_exact at {git_state()}; {os.cpu_count()} cores shared with other jobs, load average "
        f"{load0:.1f} at the start). The machine is noisy: the compared programs "
        "alternate, every time is a median of repeats and every ratio the median of the ratios within "
        "a repeat. Targets are the issue's, printed beside the measurements, not judged. Siconos: "
        + (f"python3-siconos {siconos_version()} (Debian's package, run by the system Python), time "
           "loop only." if sic_ok else f"not run ({sic_err}).") + " All programs run with "
        "OPENBLAS_NUM_THREADS=1.\n")
    out(f"The SciPy baseline's LCP is Lemke's pivoting method (`float_baseline.lcp`); against the former "
        f"2^k enumeration on {n_trials} random P-matrix LCPs (k = 1..8, symmetric, nonsymmetric and "
        f"Delassus-like, degenerate q) the largest difference is {worst:.1e} and the largest "
        f"complementarity residual {resid:.1e}.\n")
    log("chain ...")
    chain_section(out, Ns, reps["chain"], sic_ok, summary, log)
    if not args.chain:
        log("1000 events ...")
        long_run_section(out, reps["long"], sic_ok, summary, log)
        log("two carts ...")
        two_carts_section(out, reps["carts"], summary)
        log("cold start ...")
        cold_section(out, reps["cold"], summary)
        log("first simulate ...")
        first_call_section(out, reps["first"], summary)
    out("### Summary: measurements beside the issue's targets\n")
    out.table(["measurement", "value", "target", "times"], summary)
    out(f"Whole run: {(time.perf_counter() - start) / 60:.1f} min; load average at the end "
        f"{os.getloadavg()[0]:.1f}.\n")
    out(WHERE_THE_TIME_GOES)
    text = "\n".join(out.lines)
    if args.write:
        from docsections import write_section
        write_section(ROOT / "docs" / "performance.md", MARKER, text)
        print("wrote docs/performance.md (Scale section)")


if __name__ == "__main__":
    main()
