"""Orders of convergence (lcs_exact.display.convergence): the least-squares slope against hand-made error
laws, the figure's points, fitted line and legend, and the same order as compare.convergence_order
on real comparison reports."""
from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402
from flint import arb  # noqa: E402

import lcs_exact as L  # noqa: E402
from lcs_exact.display.convergence import convergence_slope  # noqa: E402


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


class Report:
    """The part of a ComparisonReport the figure reads."""

    def __init__(self, h, e, label=""):
        self.step, self.max_error, self.label = h, arb(e), label


def test_slope_of_exact_power_laws():
    hs = [0.1 / 2 ** k for k in range(5)]
    for p, C in ((1, 3.0), (2, 0.5), (0.5, 7.0)):
        assert convergence_slope(hs, [C * h ** p for h in hs]) == pytest.approx(p, rel=1e-12)
    # least squares through noisy points: e = h^2 (1 + (-1)^k / 10) -> slope by hand
    errs = [h ** 2 * (1 + (-1) ** k / 10) for k, h in enumerate(hs)]
    xs, ys = [math.log(h) for h in hs], [math.log(e) for e in errs]
    mx, my = sum(xs) / 5, sum(ys) / 5
    by_hand = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    assert convergence_slope(hs, errs) == pytest.approx(by_hand, rel=1e-14)
    with pytest.raises(L.FormatError, match="at least 2"):
        convergence_slope([0.1], [1e-3])
    with pytest.raises(L.FormatError, match="positive"):
        convergence_slope([0.1, 0.05], [1e-3, 0])
    with pytest.raises(L.FormatError, match="different steps"):
        convergence_slope([0.1, 0.1], [1e-3, 2e-3])
    with pytest.raises(L.ShapeError):
        convergence_slope([0.1, 0.05], [1e-3])


def test_figure_of_a_second_order_method():
    """Errors 4e-4, 1e-4, 2.5e-5 at h = 0.02, 0.01, 0.005: order 2 in the legend, the points at
    the errors' midpoints, the fitted line through them (exact here), log-log axes."""
    reports = [Report(0.02, 4e-4), Report(0.01, 1e-4), Report(0.005, 2.5e-5)]
    fig = L.plot_convergence(reports)
    ax = fig.axes[0]
    assert (ax.get_xscale(), ax.get_yscale()) == ("log", "log")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["max error", "fit: order 2.00"]
    pts, fit = ax.get_lines()
    assert list(pts.get_xdata()) == [0.02, 0.01, 0.005] and list(pts.get_ydata()) == [4e-4, 1e-4, 2.5e-5]
    assert list(fit.get_xdata()) == [0.005, 0.02]
    assert fit.get_ydata() == pytest.approx([2.5e-5, 4e-4], rel=1e-12)
    # steps given explicitly (as for convergence_order), a second series on the same axes
    again = L.plot_convergence([Report(1, 1e-2), Report(1, 1e-3)], steps=["1/10", "1/100"], ax=ax, label="other")
    assert again is fig
    assert [t.get_text() for t in ax.get_legend().get_texts()][2:] == ["other", "fit: order 1.00"]


def test_same_order_as_compare_on_real_reports():
    """A solver whose error is h * t (x' = -x from 1, no event: the exact solution e^{-t}) is
    first order; plot_convergence's legend shows the order convergence_order computes."""
    lcs = L.LCS([[-1]], [[0]], [[1]], [[1]])   # u = 0, y = x >= 0: x = e^{-t}
    tr = L.simulate(lcs, [1], 1)
    reports = []
    for h in (0.1, 0.05, 0.025):
        ts = [k * h for k in range(round(1 / h) + 1)]
        X = [[math.exp(-t) + h * t] for t in ts]
        reports.append(L.compare(tr, ts, X, label=f"h = {h}"))
    order = L.convergence_order(reports)
    assert order == pytest.approx(1.0, abs=1e-6)
    fig = L.plot_convergence(reports)
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()][1] == f"fit: order {order:.2f}"
    assert convergence_slope([r.step for r in reports], [float(r.max_error.mid()) for r in reports]) == order
