"""Many runs of Algorithm 7.1 through any :class:`concurrent.futures.Executor` (docs/paper-to-api.md).

``sweep(lcs, x0s, t_end)`` simulates one system from many initial states; ``param_sweep(make_lcs,
params, x0, t_end)`` simulates a family of systems from one state. The work goes to an existing
engine, never a home-made one: a local :class:`~concurrent.futures.ProcessPoolExecutor` by
default (``os.cpu_count()`` workers, shut down afterwards), or any executor the caller passes —
a Dask ``Client.get_executor()`` when one machine is not enough.

What travels. Neither an :class:`~lcs_exact.system.LCS` nor a flint matrix pickles, so a job is
plain text: the matrices and x0 as rational strings, rebuilt in the worker (each worker keeps
the systems it rebuilt, so mode data is computed once per worker). The trajectory comes back
as bytes from a pickler that knows how to write flint numbers *exactly* (integers and
rationals by value, balls by their binary midpoint and radius), so the parent receives the same
exact definitions, anchors and closed forms a sequential :func:`~lcs_exact.simulate.simulate`
would give. The system, its modes and spectra do not travel back (the trajectory refers to the
caller's own LCS and its modes), nor do ball caches of phases (rebuilt on demand): a few
kilobytes per run. Jobs go out in chunks, a few per CPU, to save round trips. A run that stops
early keeps its :class:`~lcs_exact.errors.LCSError` (same class and message) and the partial
trajectory in ``error.trajectory`` and ``result.trajectory``; the other runs are unaffected.
Results come back in input order.
"""
from __future__ import annotations

import copyreg
import io
import os
import pickle
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Any, Callable, Iterable

import flint

from ..errors import InvalidArgument
from .. import errors as _errors
from ..numbers import Spectrum, spectrum_of
from ..modes import Mode
from .schedule import scheduled
from .simulate import simulate
from ..system import LCS

__all__ = ["SweepResult", "sweep", "param_sweep"]


@dataclass(frozen=True)
class SweepResult:
    """One run of a sweep: its input, its trajectory (partial if the run stopped early) and its
    error (None when the run reached t_end).

    ``param`` is the family parameter of :func:`param_sweep` (None for :func:`sweep`).

    Attributes
    ----------
    x0 : vector
        The run's initial state, as given.
    trajectory : Trajectory or None
        The run (partial if it stopped early).
    error : BaseException or None
        What stopped the run before t_end.
    param : object
        The family parameter (above).
    """

    x0: Any
    trajectory: Any
    error: BaseException | None
    param: Any = None

    @property
    def ok(self) -> bool:
        """True iff the run reached t_end without an error."""
        return self.error is None

    def __repr__(self):
        what = repr(self.trajectory) if self.error is None else f"{type(self.error).__name__}: {self.error}"
        p = "" if self.param is None else f"param={self.param!r}, "
        return f"SweepResult({p}x0={self.x0!r}, {'ok' if self.ok else 'FAILED'}: {what})"


# --- exact pickling of flint values (a private dispatch table: nothing global changes) -------
def _arb_parts(x):
    m, e = x.mid().man_exp()
    r, f = x.rad().man_exp()
    return (int(m), int(e), int(r), int(f))


def _arb_from(parts):
    m, e, r, f = parts
    return flint.arb(flint.arf((m, e)), flint.arf((r, f)))


def _acb_from(re, im):
    return flint.acb(_arb_from(re), _arb_from(im))


def _mat_from(cls_name, rows, cols, entries, kind):
    cls = getattr(flint, cls_name)
    if kind == "arb":
        entries = [_arb_from(p) for p in entries]
    elif kind == "acb":
        entries = [_acb_from(*p) for p in entries]
    M = cls(rows, cols)
    for i in range(rows):
        for j in range(cols):
            M[i, j] = entries[i * cols + j]
    return M


def _poly_from(cls_name, coeffs, kind):
    if kind == "arb":
        coeffs = [_arb_from(p) for p in coeffs]
    elif kind == "acb":
        coeffs = [_acb_from(*p) for p in coeffs]
    return getattr(flint, cls_name)(coeffs)


def _fmpq_from(p, q):
    return flint.fmpq(p, q)


def _reduce_arb(x):
    return _arb_from, (_arb_parts(x),)


def _reduce_acb(x):
    return _acb_from, (_arb_parts(x.real), _arb_parts(x.imag))


def _entry(x, kind):
    if kind == "arb":
        return _arb_parts(x)
    if kind == "acb":
        return (_arb_parts(x.real), _arb_parts(x.imag))
    if kind == "fmpq":
        return flint.fmpq(x)
    return int(x)


def _reducer_mat(kind):
    def reduce(M):
        r, c = M.nrows(), M.ncols()
        return _mat_from, (type(M).__name__, r, c, [_entry(M[i, j], kind) for i in range(r) for j in range(c)], kind)
    return reduce


def _reducer_poly(kind):
    def reduce(p):
        return _poly_from, (type(p).__name__, [_entry(c, kind) for c in p.coeffs()], kind)
    return reduce


_DISPATCH = dict(copyreg.dispatch_table)
_DISPATCH.update({
    flint.arb: _reduce_arb, flint.acb: _reduce_acb,
    flint.fmpq: lambda x: (_fmpq_from, (int(x.p), int(x.q))),
    flint.fmpz_mat: _reducer_mat("fmpz"), flint.fmpq_mat: _reducer_mat("fmpq"),
    flint.arb_mat: _reducer_mat("arb"), flint.acb_mat: _reducer_mat("acb"),
    flint.fmpz_poly: _reducer_poly("fmpz"), flint.fmpq_poly: _reducer_poly("fmpq"),
    flint.arb_poly: _reducer_poly("arb"), flint.acb_poly: _reducer_poly("acb"),
})


class _Pickler(pickle.Pickler):
    """Writes a trajectory exactly, leaving out what the parent has or can rebuild: the system
    itself and its modes (the parent's own objects stand in for them), and spectra (a pure
    function of their rational matrix).  Results shrink from tens of kilobytes to a few, and
    the parent - which unpickles every result alone - stops being the bottleneck of a sweep."""

    dispatch_table = _DISPATCH

    def __init__(self, file, lcs: LCS | None):
        super().__init__(file, protocol=pickle.HIGHEST_PROTOCOL)
        self._lcs = lcs
        # a scheduled system's phases are systems of their own: the parent's stand in for them too
        schedule = getattr(lcs, "schedule", None)
        self._phases = {} if schedule is None else {id(p.lcs): k for k, p in enumerate(schedule.phases)}

    def persistent_id(self, obj):
        if self._lcs is not None:
            if obj is self._lcs:
                return ("lcs",)
            if isinstance(obj, Mode) and obj.lcs is self._lcs:
                return ("mode", tuple(sorted(obj.I)))
            if isinstance(obj, LCS) and id(obj) in self._phases:
                return ("phase", self._phases[id(obj)])
            if isinstance(obj, Mode) and id(obj.lcs) in self._phases:
                return ("phase mode", self._phases[id(obj.lcs)], tuple(sorted(obj.I)))
        if isinstance(obj, Spectrum):
            M = obj.M
            return ("spectrum", M.nrows(), tuple(str(c) for c in M.entries()))
        return None


class _Unpickler(pickle.Unpickler):
    def __init__(self, file, lcs: LCS | None):
        super().__init__(file)
        self._lcs = lcs

    def persistent_load(self, pid):
        kind = pid[0]
        if kind == "lcs" and self._lcs is not None:
            return self._lcs
        if kind == "mode" and self._lcs is not None:
            return self._lcs.mode(pid[1])
        if kind == "phase" and self._lcs is not None:
            return self._lcs.schedule.phases[pid[1]].lcs
        if kind == "phase mode" and self._lcs is not None:
            return self._lcs.schedule.phases[pid[1]].lcs.mode(pid[2])
        if kind == "spectrum":
            n, entries = pid[1], pid[2]
            return spectrum_of(flint.fmpq_mat(n, n, [flint.fmpq(c) for c in entries]))
        raise pickle.UnpicklingError(f"unknown persistent id {pid[:1]!r}")


def _dumps(obj, lcs: LCS | None = None) -> bytes:
    buf = io.BytesIO()
    _Pickler(buf, lcs).dump(obj)
    return buf.getvalue()


def _loads(data: bytes, lcs: LCS | None = None):
    return _Unpickler(io.BytesIO(data), lcs).load()


# --- jobs ---------------------------------------------------------------------------------------
def _text_matrix(M) -> list:
    if hasattr(M, "nrows"):
        return [[str(M[i, j]) for j in range(M.ncols())] for i in range(M.nrows())]
    return [[str(c) for c in row] for row in M]


def _text_vector(x, where: str) -> list:
    if hasattr(x, "rational") and callable(x.rational):   # an exact vector
        q = x.rational()
        if q is None:
            raise InvalidArgument(f"{where}: an exact irrational vector cannot be sent to a worker; "
                            "pass a rational vector")
        return [str(q[i, 0]) for i in range(q.nrows())]
    if hasattr(x, "nrows"):
        return [str(x[i, 0]) for i in range(x.nrows())]
    out = []
    for c in x:
        if isinstance(c, float):
            c = repr(c)   # LCS reads a float as its shortest decimal repr
        out.append(str(c))
    return out


def _system_text(lcs: LCS) -> tuple:
    """What the worker needs to rebuild the dynamics exactly: the matrices, names and restitution
    (Newton's law changes every impact), and for a scheduled system every phase, its duration
    and reset, and the period."""
    schedule = getattr(lcs, "schedule", None)
    if schedule is not None:
        phases = tuple((None if p.duration is None else str(p.duration), _system_text(p.lcs),
                        None if p.reset is None else tuple(map(tuple, _text_matrix(p.reset))))
                       for p in schedule.phases)
        return ("scheduled", phases, None if schedule.period is None else str(schedule.period), lcs.name)
    rest = None if lcs.restitution is None else tuple(str(e) for e in lcs.restitution)
    return (tuple(map(tuple, _text_matrix(lcs.A))), tuple(map(tuple, _text_matrix(lcs.B))),
            tuple(map(tuple, _text_matrix(lcs.C))), tuple(map(tuple, _text_matrix(lcs.D))),
            lcs.name, tuple(lcs.state_names), tuple(lcs.constraint_names), rest)


#: chunks per CPU of the parent in a sweep (see ``_drive``)
CHUNKS_PER_CPU = 8

_SYSTEMS: dict = {}   # per worker process: rebuilt systems keep their mode caches


def _rebuild(system: tuple) -> LCS:
    lcs = _SYSTEMS.get(system)
    if lcs is None and system[0] == "scheduled":
        _, phases, period, name = system
        lcs = scheduled([(d, _rebuild(text)) if reset is None else (d, _rebuild(text), [list(r) for r in reset])
                         for d, text, reset in phases], period, name=name)
    elif lcs is None:
        A, B, C, D, name, state_names, constraint_names, rest = system
        lcs = LCS([list(r) for r in A], [list(r) for r in B], [list(r) for r in C],
                  [list(r) for r in D], name=name, state_names=list(state_names),
                  constraint_names=list(constraint_names), restitution=None if rest is None else list(rest))
    if system not in _SYSTEMS:
        if len(_SYSTEMS) > 64:
            _SYSTEMS.clear()
        _SYSTEMS[system] = lcs
    return lcs


def run_job(system: tuple, x0: list, t_end: str, options: dict) -> tuple:
    """Worker side: one simulate run; returns (status, payload) made of bytes and strings.

    status "ok": payload is the pickled trajectory; "lcs_error": (class name, message, pickled
    partial trajectory or None); "error": the pickled exception (or its repr).
    """
    lcs = _rebuild(system)
    try:
        traj = simulate(lcs, x0, t_end, **options)
    except _errors.LCSError as e:
        tr = getattr(e, "trajectory", None)
        return "lcs_error", (type(e).__name__, str(e), None if tr is None else _safe_dumps(tr, lcs))
    except Exception as e:   # RecursionError, ... : keep it, lose nothing else
        try:
            return "error", pickle.dumps(e)
        except Exception:
            return "error", pickle.dumps(RuntimeError(f"{type(e).__name__}: {e}"))
    return "ok", _safe_dumps(traj, lcs)


def run_jobs(jobs: list) -> list:
    """Worker side of a chunk of jobs (:func:`run_job` each): one round trip for several runs."""
    return [run_job(*job) for job in jobs]


def _safe_dumps(traj, lcs):
    try:
        return _dumps(traj, lcs)
    except Exception as e:   # an object the exact pickler does not know: say so, keep the run
        return ("unpicklable", f"{type(e).__name__}: {e}")


def _load_traj(payload, lcs):
    if payload is None:
        return None
    if isinstance(payload, tuple) and payload and payload[0] == "unpicklable":
        return None
    return _loads(payload, lcs)


def _result(x0, param, lcs, status, payload) -> SweepResult:
    """The parent side of :func:`run_job`; ``lcs`` is the parent's system, which the returned
    trajectory refers to (its modes are the parent's modes)."""
    if status == "ok":
        traj = _load_traj(payload, lcs)
        err = None
        if traj is None:
            err = RuntimeError(f"the trajectory could not be sent back from the worker ({payload[1]})")
        return SweepResult(x0, traj, err, param)
    if status == "lcs_error":
        name, msg, tr_bytes = payload
        cls = getattr(_errors, name, _errors.LCSError)
        traj = _load_traj(tr_bytes, lcs)
        err = cls(msg, trajectory=traj) if issubclass(cls, _errors.LCSError) else cls(msg)
        return SweepResult(x0, traj, err, param)
    if status == "died":
        return SweepResult(x0, None, _errors.WorkerDied(
            f"the worker process died while running this job (killed by a signal, out of memory?): {payload}"),
            param)
    return SweepResult(x0, None, pickle.loads(payload), param)


def _progress(total, enabled, desc):
    if not enabled:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:   # the bar is a convenience: no tqdm, no bar
        return None
    return tqdm(total=total, desc=desc)


def _drive(jobs: list, executor: Executor | None, progress: bool, desc: str) -> list:
    """Submit (system, x0_text, t_end, options) jobs; collect results in input order."""
    own = executor is None
    if own:
        executor = ProcessPoolExecutor(max_workers=os.cpu_count() or 1)
    bar = _progress(len(jobs), progress, desc)
    out: list = [None] * len(jobs)
    # chunks of about 1/CHUNKS_PER_CPU of a worker's share: fewer round trips through the parent
    # (which serves every worker alone), still enough chunks to balance uneven runs
    size = max(1, len(jobs) // (CHUNKS_PER_CPU * (os.cpu_count() or 1)))
    starts = range(0, len(jobs), size)
    failed: list = []  # chunks whose future raised: a worker died (BrokenProcessPool), ...
    try:
        futures = {executor.submit(run_jobs, jobs[i:i + size]): i for i in starts}
        for f in as_completed(futures):
            i = futures[f]
            try:
                rs = f.result()
            except Exception as e:  # noqa: BLE001 - the run's own errors come back as results
                failed.append((i, jobs[i:i + size], e))
                continue
            out[i:i + len(rs)] = rs
            if bar is not None:
                bar.update(len(rs))
        # a dead worker breaks its pool and every chunk still pending in it: each of their jobs
        # is run again, alone, on a fresh one-worker pool; a job that kills its worker again is
        # reported as failed (WorkerDied) and every other result is kept
        for i, chunk, e in failed:
            for j, job in enumerate(chunk):
                out[i + j] = _rerun(job, e)
                if bar is not None:
                    bar.update(1)
    finally:
        if bar is not None:
            bar.close()
        if own:
            executor.shutdown(wait=not failed)
    return out


def _rerun(job: tuple, first: BaseException) -> tuple:
    """One job again on a fresh single-worker process pool: its (status, payload), or
    ("died", reason) when the worker dies again."""
    try:
        with ProcessPoolExecutor(max_workers=1) as one:
            return one.submit(run_job, *job).result()
    except Exception as e:  # noqa: BLE001
        return "died", f"{type(first).__name__} ({first}); again on a fresh worker: {type(e).__name__} ({e})"


def _options(simulate_options: dict) -> dict:
    opts = dict(simulate_options)
    if "x0" in opts or "t_end" in opts:
        raise InvalidArgument("x0 and t_end are arguments of the sweep, not simulate options")
    return opts


def sweep(lcs: LCS, x0s: Iterable, t_end: Any, executor: Executor | None = None, *,
          progress: bool = True, **simulate_options) -> list[SweepResult]:
    """Run :func:`~lcs_exact.simulate.simulate` (Algorithm 7.1) from every state in ``x0s``.

    Parameters
    ----------
    lcs : LCS
    x0s : iterable of rational vectors (any input LCS accepts)
    t_end : rational
    executor : concurrent.futures.Executor, optional
        Where the runs go. Default: a local ProcessPoolExecutor with ``os.cpu_count()`` workers,
        shut down afterwards. A Dask ``Client.get_executor()`` works the same way. Use
        processes, not threads: flint's working precision is per process, so a thread pool
        with more than one thread would let runs change each other's precision.
    progress : bool
        Show a tqdm progress bar (when tqdm is installed).
    **simulate_options
        Passed to every ``simulate`` call (``digits``, ``max_events``, ``time_limit``, ...).

    Returns
    -------
    list of SweepResult, in the order of ``x0s``. A run that stopped early has ``.ok`` False,
    its error in ``.error`` (the same LCSError subclass and message) and its partial trajectory
    in ``.trajectory`` and ``.error.trajectory``.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> from lcs_exact.models import two_carts
    >>> with ThreadPoolExecutor(1) as ex:
    ...     rs = sweep(two_carts(), [[0, 1, -1, 0], [0, 1, -2, 0]], 1, ex, progress=False)
    >>> [r.trajectory.events[0].state_after for r in rs]
    [(0, 1, 0, 0), (0, 1, 0, 0)]
    """
    x0s = list(x0s)
    system = _system_text(lcs)
    opts = _options(simulate_options)
    texts = [_text_vector(x, f"x0s[{i}]") for i, x in enumerate(x0s)]
    raw = _drive([(system, x, str(t_end), opts) for x in texts], executor, progress, "sweep")
    return [_result(x0, None, lcs, *r) for x0, r in zip(x0s, raw)]


def param_sweep(make_lcs: Callable[[Any], LCS], params: Iterable, x0: Any, t_end: Any,
                executor: Executor | None = None, *, progress: bool = True,
                **simulate_options) -> list[SweepResult]:
    """Run :func:`~lcs_exact.simulate.simulate` on the family ``make_lcs(p)`` for p in ``params``.

    ``make_lcs`` runs here (it need not pickle); only the systems' rational data travel.
    Results are in the order of ``params``, each with ``.param`` set.

    Parameters
    ----------
    make_lcs : callable
        p -> LCS: the family of systems; it runs in this process (it need not pickle).
    params : iterable
        The family parameters p, one run each, results in this order.
    x0 : vector
        The initial state of every run (any form :func:`simulate` accepts).
    t_end : rational
        The horizon of every run.
    executor : concurrent.futures.Executor, optional
        Where the runs go (a process or thread pool, a dask client's executor); None: in turn,
        in this process.
    progress : bool, optional
        A tqdm progress bar (needs the extra ``data``).
    **simulate_options
        Passed on to :func:`~lcs_exact.simulate.simulate` (``digits``, ``max_events``, ...).

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> from lcs_exact import LCS
    >>> def spring(k):  # a cart on a spring of stiffness k, a stop at 0
    ...     return LCS([[0, 1], [-k, 0]], [[0], [1]], [[1, 0]], [[0]])
    >>> with ThreadPoolExecutor(1) as ex:
    ...     rs = param_sweep(spring, [1, 4], [1, 0], 3, ex, progress=False)
    >>> [str(r.trajectory.events[0].time.closed_form) for r in rs]
    ['pi/2', 'pi/4']
    """
    params = list(params)
    opts = _options(simulate_options)
    xt = _text_vector(x0, "x0")
    systems = [make_lcs(p) for p in params]
    jobs = [(_system_text(lcs), xt, str(t_end), opts) for lcs in systems]
    raw = _drive(jobs, executor, progress, "param_sweep")
    return [_result(x0, p, lcs, *r) for p, lcs, r in zip(params, systems, raw)]
