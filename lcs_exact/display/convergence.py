"""Orders of convergence: the least-squares slope of log(error) against log(step)
(:func:`convergence_slope`) and its figure (:func:`plot_convergence`).

A numerical solver compared against certified references at several steps h gives errors
e(h) ~ C h^p; the order p is the slope of the least-squares line through (log h, log e).
:func:`lcs_exact.compare.convergence_order` is that slope over comparison reports.

This module sits low in the import order: reports are used through their public interface only
(``step``, the solver's largest step; ``max_error``, a ball with ``mid()`` or a number), so it
knows nothing of :mod:`lcs_exact.compare`.  matplotlib is imported inside
:func:`plot_convergence`, so ``import lcs_exact`` stays light.
"""
from __future__ import annotations

import math
from typing import Any, Sequence

from ..errors import FormatError, InvalidArgument, ShapeError
from ..algebra import to_fmpq

__all__ = ["convergence_slope", "plot_convergence"]


def convergence_slope(steps: Sequence[float], errors: Sequence[float]) -> float:
    """The least-squares slope p of log(error) against log(step): error ~ C step^p.

    Parameters
    ----------
    steps, errors : sequences of positive floats
        Of the same length: at least 2 points, with two different steps.

    Returns
    -------
    float
        The slope p (the order of convergence).

    Raises
    ------
    ShapeError
        When the two sequences differ in length.
    FormatError
        Fewer than 2 points, a step or an error that is not positive and finite, or all steps equal.

    Examples
    --------
    The errors of a second-order method:

    >>> round(convergence_slope([0.02, 0.01, 0.005], [4e-4, 1e-4, 2.5e-5]), 9)
    2.0
    """
    hs, errs = [float(h) for h in steps], [float(e) for e in errors]
    if len(hs) != len(errs):
        raise ShapeError(f"{len(errs)} errors but {len(hs)} steps")
    if len(errs) < 2:
        raise FormatError("the order of convergence needs at least 2 solutions")
    if any(e <= 0 or not math.isfinite(e) for e in errs) or any(h <= 0 or not math.isfinite(h) for h in hs):
        raise FormatError(f"the order of convergence needs positive errors and steps, got errors {errs}")
    xs, ys = [math.log(h) for h in hs], [math.log(e) for e in errs]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0:
        raise FormatError("the order of convergence needs solutions with different steps")
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def _error_of(report: Any) -> float:
    e = getattr(report, "max_error", None)
    if e is None:
        raise InvalidArgument(f"a report needs max_error (a ComparisonReport of lcs_exact.compare), "
                              f"got {type(report).__name__}")
    return float(e.mid()) if hasattr(e, "mid") else float(e)


def plot_convergence(reports: Sequence[Any], steps: Sequence[Any] | None = None, *, ax: Any = None,
                     label: str | None = None, title: str | None = None):
    """Error against step on log-log axes, with the fitted order in the legend.  Returns the Figure.

    Parameters
    ----------
    reports : sequence of ComparisonReport
        The comparisons of one solver at several steps (:func:`lcs_exact.compare`): each gives
        ``max_error`` (a certified ball; its midpoint is drawn) and ``step``.
    steps : sequence of rationals, optional
        The steps to use instead of each report's largest step (as for
        :func:`lcs_exact.convergence_order`).
    ax : matplotlib Axes, optional
        Draw into these axes (another solver's series on the same figure); a new figure otherwise.
    label : str, optional
        The series' name in the legend (default ``"max error"``).
    title : str, optional
        The axes' title (default ``"order of convergence"`` on a new figure).

    Notes
    -----
    The points are the errors; the dashed line is the least-squares fit C h^p
    (:func:`convergence_slope`, the same as ``convergence_order(reports, steps)``), with p in
    the legend.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> class R:  # anything with step and max_error (a ComparisonReport)
    ...     def __init__(self, h, e): self.step, self.max_error = h, e
    >>> fig = plot_convergence([R(0.02, 4e-4), R(0.01, 1e-4), R(0.005, 2.5e-5)])
    >>> [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    ['max error', 'fit: order 2.00']
    """
    reports = list(reports)
    if steps is None:
        hs = [float(getattr(r, "step")) for r in reports]
    else:
        hs = [float(to_fmpq(h, "step")) for h in steps]
    errs = [_error_of(r) for r in reports]
    p = convergence_slope(hs, errs)
    import matplotlib.pyplot as plt

    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
        ax.set_title("order of convergence" if title is None else title, fontsize=11)
    else:
        fig = ax.figure
        if title is not None:
            ax.set_title(title, fontsize=11)
    (pts,) = ax.loglog(hs, errs, "o", ms=6, label=label or "max error")
    # the fit through the centroid of (log h, log e), over the range of the steps
    mx = sum(math.log(h) for h in hs) / len(hs)
    my = sum(math.log(e) for e in errs) / len(errs)
    lo, hi = min(hs), max(hs)
    ax.loglog([lo, hi], [math.exp(my + p * (math.log(h) - mx)) for h in (lo, hi)], "--", lw=1.2,
              color=pts.get_color(), label=f"fit: order {p:.2f}")
    ax.set_xlabel("step h")
    ax.set_ylabel("max error")
    ax.grid(True, which="both", lw=0.3, alpha=0.6)
    ax.legend(fontsize=8, loc="best")
    return fig
