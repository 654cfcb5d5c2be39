"""Figures: what a reader must see is checked on the matplotlib objects (lines broken at jumps,
open/closed markers at x(τ-)/x(τ+), events labelled, phases shaded, names, legends outside)."""
from __future__ import annotations

import ast
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402
from matplotlib.patches import Polygon, Rectangle  # noqa: E402

import lcs_exact as L  # noqa: E402
from lcs_exact.examples import two_carts, two_carts_with_hook  # noqa: E402
from lcs_exact.plotting import phase_intervals, plot_mode_map, plot_trajectory  # noqa: E402


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def impact():
    """Section 7: from e^{-A}(0, -1, -1, 0) the free phase ends at t = 1 with an impact
    (q_0' jumps from -1 to 0), the stop holds until 1 + pi/2, then the cart leaves."""
    c = two_carts()
    return L.simulate(c, L.expm_action(c.A, -1, [0, -1, -1, 0]), 3)


def state_lines(ax):
    return [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 2]


def test_phases_from_events(impact):
    ph = phase_intervals(impact)
    assert [(float(p.start), float(p.end)) for p in ph] == [(0.0, 1.0), (1.0, float(impact.events[1].time)),
                                                            (float(impact.events[1].time), 3.0)]
    assert [p.mode for p in ph] == [frozenset(), frozenset({0}), frozenset()]


def test_trajectory_figure(impact):
    fig = impact.plot(points=60)
    assert isinstance(fig, matplotlib.figure.Figure)
    ax_x, ax_u, ax_y = fig.axes[:3]
    assert [a.get_ylabel() for a in (ax_x, ax_u, ax_y)] == ["state", "u", "y"]
    assert ax_y.get_xlabel() == "t" and ax_x.get_shared_x_axes().joined(ax_x, ax_y)
    # no line crosses an event: every sampled line lies within one phase
    events = [float(e.time) for e in impact.events]
    for ax in (ax_x, ax_u, ax_y):
        for ln in state_lines(ax):
            xs = ln.get_xdata()
            for te in events:
                assert max(xs) <= te + 1e-12 or min(xs) >= te - 1e-12
    # the impact at t = 1: q_0' (state 2) jumps from -1 (open marker) to 0 (filled marker)
    markers = [(ln.get_xdata()[0], ln.get_ydata()[0], ln.get_markerfacecolor())
               for ln in ax_x.get_lines() if ln.get_marker() == "o" and len(ln.get_xdata()) == 1]
    assert any(abs(x - 1) < 1e-12 and abs(y + 1) < 1e-9 and fc == "white" for x, y, fc in markers)
    assert any(abs(x - 1) < 1e-12 and abs(y) < 1e-9 and fc != "white" for x, y, fc in markers)
    assert not any(abs(x - events[1]) < 1e-9 for x, _, _ in markers)  # lift-off: no jump, no marker
    # the line of q_0' ends at -1 before the event and starts at 0 after it (a discontinuity)
    q0dot = [ln for ln in state_lines(ax_x) if ln.get_color() == state_lines(ax_x)[2].get_color()]
    before = [ln for ln in q0dot if max(ln.get_xdata()) <= 1 + 1e-12][0]
    after = [ln for ln in q0dot if min(ln.get_xdata()) >= 1 - 1e-12][0]
    assert abs(before.get_ydata()[-1] + 1) < 1e-9 and abs(after.get_ydata()[0]) < 1e-9
    # events labelled with the mode change; the impulse of the impact (u = 1 delta)
    texts = [t.get_text() for t in ax_x.texts]
    assert "∅→{0}" in texts and "{0}→∅" in texts
    assert any("1·δ" == t.get_text() for t in ax_u.texts)
    # phases shaded (one span per phase and axes), names from the builder, legends outside
    spans = sorted((round(p.get_x(), 9), round(p.get_x() + p.get_width(), 9)) for p in ax_x.patches
                   if isinstance(p, Rectangle))
    assert spans == [(0.0, 1.0), (1.0, round(events[1], 9)), (round(events[1], 9), 3.0)]
    labels = [t.get_text() for t in ax_x.get_legend().get_texts()]
    # modes and pairs in the builder's words (mechanical: contact forces and gaps)
    assert labels[:4] == ["q_0", "q_1", "q_0'", "q_1'"] and "stop contact" in labels and "left limit (τ−)" in labels
    assert [t.get_text() for t in ax_u.get_legend().get_texts()] == ["force (stop)", "impulse (weight·δ)"]
    # u jumps from u(1-) = 0 to u(1+) = cos(0) = 1 when the stop engages, and is continuous at the
    # lift-off (u(1 + pi/2) = cos(pi/2) = 0 on both sides): markers at t = 1 only
    u_marks = [(ln.get_xdata()[0], ln.get_ydata()[0], ln.get_markerfacecolor())
               for ln in ax_u.get_lines() if ln.get_marker() == "o"]
    assert sorted((round(x, 9), round(y, 9), fc == "white") for x, y, fc in u_marks) == [(1, 0, True), (1, 1, False)]
    # y = q_0 is continuous: no marker
    assert not [ln for ln in ax_y.get_lines() if ln.get_marker() == "o"]
    # the impulse is a dotted arrow, not a solid segment that reads as part of u
    arrows = [t for t in ax_u.texts if t.arrow_patch is not None]
    assert len(arrows) == 1 and arrows[0].arrow_patch.get_linestyle() == ":"
    fig.canvas.draw()
    for ax in (ax_x, ax_u, ax_y):
        assert ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1


def test_default_resolution_and_exact_phase_ends(impact):
    """800 points by default (sampling is cheap); every line starts and ends at the exact phase
    ends, so u on the constrained phase starts at exactly u(1+) = 1 and ends at u(1 + pi/2-) = 0."""
    fig = impact.plot()
    ax_x, ax_u, _ = fig.axes[:3]
    assert sum(len(ln.get_xdata()) for ln in state_lines(ax_x)) >= 4 * 790
    t2 = float(impact.events[1].time)
    on = [ln for ln in state_lines(ax_u) if abs(ln.get_xdata()[0] - 1) < 1e-12]
    assert len(on) == 1
    xs, ys = on[0].get_xdata(), on[0].get_ydata()
    assert (xs[0], ys[0]) == (1.0, 1.0) and abs(xs[-1] - t2) < 1e-15 and abs(ys[-1]) < 1e-15
    with pytest.raises(L.InvalidArgument, match="points"):
        impact.plot(points=0)
    # y = q_0 is identically 0 while the stop holds: drawn flat at exactly 0 (no rounding noise)
    ax_y = fig.axes[2]
    held = [ln for ln in state_lines(ax_y) if abs(ln.get_xdata()[0] - 1) < 1e-12][0]
    assert set(held.get_ydata()) == {0.0}


def test_impulse_arrows_scale_with_their_weights():
    """Example 8.3 from (1/10, 1/10, -2, 1): the hook's impulse 3/2 at t = 0, then the stop's
    impulse at the second impact, smaller: arrow heights in proportion, weights written."""
    tr = L.simulate(two_carts_with_hook(), ["1/10", "1/10", -2, 1], 1)
    w = [float(e.impulse[0][i, 0]) if hasattr(e.impulse[0], "nrows") else float(e.impulse[0][i])
         for e in tr.events for i in range(2) if e.impulse]
    w = [v for v in w if v]
    assert w[0] == 1.5 and 0 < w[1] < 1.5
    ax_u = tr.plot(points=40).axes[1]
    tops = [t.xy[1] for t in ax_u.texts if t.arrow_patch is not None]
    assert tops[0] == pytest.approx(0.97) and tops[1] == pytest.approx(0.03 + 0.94 * (0.15 + 0.85 * w[1] / 1.5))
    assert [t.get_text() for t in ax_u.texts if t.arrow_patch is None] == [f"{w[0]:.4g}·δ", f"{w[1]:.4g}·δ"]


def test_impulse_at_an_unlabelled_event_keeps_its_weight():
    """With fewer event labels than events (label_events=1), the impulse 3/2 of the hook at t = 0
    (Example 8.3: W = E M^-1 E^T = 2 on the hook, y'(0-) = -3, lambda = 3/2) and the stop's later
    impulse are still written; drawing them used to fail on the missing label line."""
    tr = L.simulate(two_carts_with_hook(), ["1/10", "1/10", -2, 1], 1)
    ax_u = tr.plot(points=40, label_events=1).axes[1]
    weights = [t.get_text() for t in ax_u.texts if t.arrow_patch is None and t.get_text().endswith("·δ")]
    assert weights[0] == "1.5·δ" and len(weights) == 2


@pytest.mark.slow
def test_close_events_get_separate_label_lines():
    """Four events within 0.17 of each other (a 6-cart chain with three stops): labels stacked on
    separate lines, none drawn over another; more than ten states get dashed line styles."""
    N = 6
    K = [[2 if i == j else -1 if abs(i - j) == 1 else 0 for j in range(N)] for i in range(N)]
    K[N - 1][N - 1] = 1
    chain = L.models.mechanical([[int(i == j) for j in range(N)] for i in range(N)], K,
                                [[int(j == i) for j in range(N)] for i in range(0, N, 2)])
    tr = L.simulate(chain, [L.rational.to_fmpq(f"{(-1) ** i}/2") for i in range(N)] + [0] * N, 2)
    assert len(tr.events) >= 3 and float(tr.events[-1].time) - float(tr.events[0].time) < 0.2
    fig = tr.plot(points=100)
    fig.canvas.draw()
    labels = [t for t in fig.axes[0].texts if t.get_text().count("→") == 1]
    assert len(labels) == len(tr.events)
    boxes = [t.get_window_extent() for t in labels]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            assert not boxes[i].overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
    styles = [ln.get_linestyle() for ln in state_lines(fig.axes[0])[:12]]
    assert styles[:10] == ["-"] * 10 and styles[10:] == ["--", "--"]
    # 12 states + markers + modes: two columns, so the legend is no taller than its panel
    legend = fig.axes[0].get_legend()
    assert len({round(t.get_window_extent().x0) for t in legend.get_texts()}) == 2
    assert legend.get_window_extent().height <= fig.axes[0].get_window_extent().height


def test_impact_with_lift_off_is_labelled_with_its_chain():
    """The oscillator from (1, 0) hits the stop at pi/2 and rests (mode ∅ after, via the
    projection of {0}); the two carts from (0, 1, -1, 0) jump at t = 0 through {0} into ∅."""
    osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    assert [t.get_text() for t in L.simulate(osc, [1, 0], 3).plot(points=20).axes[0].texts] == ["∅→∅ via {0}"]
    tr = L.simulate(two_carts(), [0, 1, -1, 0], 2)
    assert [t.get_text() for t in tr.plot(points=20).axes[0].texts] == ["start→∅ via {0}"]


def test_partial_trajectory_is_drawn_up_to_where_it_stopped():
    """A run stopped by max_events covers up to its t_last (the next event's time): the phase
    after its last event is drawn (it was dropped), and a run stopped before any event is drawn
    at all (it was an empty figure)."""
    c = two_carts()
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(c, L.expm_action(c.A, -1, [0, -1, -1, 0]), 3, max_events=1)
    tr = err.value.trajectory
    ph = phase_intervals(tr)
    lift = 1 + 3.141592653589793 / 2
    assert [(float(p.start), round(float(p.end), 12), p.mode) for p in ph] == [
        (0.0, 1.0, frozenset()), (1.0, round(lift, 12), frozenset({0}))]
    fig = tr.plot(points=50)
    ax = fig.axes[0]
    assert max(max(ln.get_xdata()) for ln in state_lines(ax)) == pytest.approx(lift, abs=1e-12)
    assert "partial: event limit" in fig.get_suptitle()
    assert any(t.get_text() == "run stopped" for t in ax.texts)
    osc = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]])
    with pytest.raises(L.LimitExceeded) as err:
        L.simulate(osc, [1, 0], 4, max_events=0)
    ph = phase_intervals(err.value.trajectory)
    assert [(float(p.start), round(float(p.end), 12), p.mode) for p in ph] == [(0.0, round(lift - 1, 12), frozenset())]
    fig = err.value.trajectory.plot(points=30)
    assert len(state_lines(fig.axes[0])) == 2  # x and v on [0, pi/2]


def test_trajectory_selection_and_defaults():
    tr = L.simulate(L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[1]]), [1, 0], 4)
    fig = plot_trajectory(tr, states=[1], panels=("x", "y"), points=30)
    assert len(fig.axes) == 2
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()][:1] == ["$x_{1}$"]
    assert [t.get_text() for t in fig.axes[1].get_legend().get_texts()] == ["$y_{0}$"]
    with pytest.raises(L.InvalidArgument, match="unknown state name"):
        plot_trajectory(tr, states=["nope"])
    with pytest.raises(ValueError, match="outside"):
        plot_trajectory(tr, states=[5])
    with pytest.raises(ValueError, match="panels"):
        plot_trajectory(tr, panels=())


def test_jump_at_time_zero_is_visible():
    tr = L.simulate(two_carts_with_hook(), [0, 0, -2, 1], 1)  # jump to the origin at t = 0
    fig = tr.plot(points=20)
    ax = fig.axes[0]
    assert ax.get_xlim()[0] < 0  # a margin so that markers at t = 0 are not clipped
    opened = [ln for ln in ax.get_lines() if ln.get_marker() == "o" and ln.get_markerfacecolor() == "white"]
    assert sorted(round(ln.get_ydata()[0], 9) for ln in opened) == [-2, 1]


@pytest.mark.slow
def test_mode_map_figure():
    mm = two_carts_with_hook().mode_map(slice=([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]]))
    fig = mm.plot(grid=5)
    ax = fig.axes[0]
    assert {t.get_text() for t in ax.texts} == {"∅", "{0}", "{1}", "{0, 1}"}
    polys = [p for p in ax.patches if isinstance(p, Polygon)]
    assert len(polys) >= 4
    total = 0.0
    for p in polys:
        xy = p.get_xy()[:-1] if (p.get_xy()[0] == p.get_xy()[-1]).all() else p.get_xy()
        total += abs(sum(xy[i][0] * xy[(i + 1) % len(xy)][1] - xy[(i + 1) % len(xy)][0] * xy[i][1]
                         for i in range(len(xy)))) / 2
    assert abs(total - 4.0) < 1e-9  # the 2-D faces tile the window [-1, 1]^2 exactly
    assert ax.collections  # the jump arrows
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("q_0'", "q_1'")
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "S = {0}: stop" in legend and "S = {0, 1}: stop+hook" in legend and "S = ∅: free" in legend
    with pytest.raises(L.InvalidArgument, match="2-D"):
        plot_mode_map(two_carts().mode_map())
    with pytest.raises(ValueError, match="window"):
        mm.plot(window=(1, 0, 0, 1))


def test_plotting_imports_point_down():
    """plotting.py is below trajectory.py: it must not import trajectory or simulate."""
    src = pathlib.Path(L.__file__).with_name("plotting.py").read_text()
    mods = {n.module for n in ast.walk(ast.parse(src)) if isinstance(n, ast.ImportFrom) and n.module}
    assert not mods & {"trajectory", "simulate", "flow", "models", "examples"}


def test_import_does_not_load_matplotlib():
    code = "import sys, lcs_exact; print('matplotlib' in sys.modules, 'numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=str(pathlib.Path(L.__file__).parent.parent))
    assert out.stdout.split() == ["False", "False"]
