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
from lcs_exact.display.plotting import phase_intervals, plot_mode_map, plot_trajectory  # noqa: E402


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
    assert "impulse (stop) = 1" in [t.get_text() for t in ax_u.texts]
    # phases shaded (one span per phase and axes), names from the builder, legends outside
    spans = sorted((round(p.get_x(), 9), round(p.get_x() + p.get_width(), 9)) for p in ax_x.patches
                   if isinstance(p, Rectangle))
    assert spans == [(0.0, 1.0), (1.0, round(events[1], 9)), (round(events[1], 9), 3.0)]
    labels = [t.get_text() for t in ax_x.get_legend().get_texts()]
    # modes (index set, then the builder's words) and pairs in the builder's words (mechanical:
    # contact forces and gaps)
    assert labels[:4] == ["q_0", "q_1", "q_0'", "q_1'"] and "left limit (τ−)" in labels
    assert labels[-2:] == ["∅: stop open", "{0}: stop contact"]
    assert [t.get_text() for t in ax_u.get_legend().get_texts()] == ["force (stop)", "impulse δ (arrow not to scale)"]
    # u jumps from u(1-) = 0 to u(1+) = cos(0) = 1 when the stop engages, and is continuous at the
    # lift-off (u(1 + pi/2) = cos(pi/2) = 0 on both sides): markers at t = 1 only
    u_marks = [(ln.get_xdata()[0], ln.get_ydata()[0], ln.get_markerfacecolor())
               for ln in ax_u.get_lines() if ln.get_marker() == "o"]
    assert sorted((round(x, 9), round(y, 9), fc == "white") for x, y, fc in u_marks) == [(1, 0, True), (1, 1, False)]
    # y = q_0 is continuous: no marker
    assert not [ln for ln in ax_y.get_lines() if ln.get_marker() == "o"]
    # the impulse is a dashed arrow through the panel, not a solid segment that reads as part of u
    arrows = [t for t in ax_u.texts if t.arrow_patch is not None]
    assert len(arrows) == 1 and arrows[0].arrow_patch.get_linestyle() not in ("-", "solid")
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


def test_impulse_arrows_are_labelled_and_not_to_scale():
    """Example 8.3 from (1/10, 1/10, -2, 1): the hook's impulse 3/2 at t = 0 (W = E M^-1 E^T = 2
    on the hook, y'(0-) = -3, lambda = 3/2), then the stop's impulse at the second impact,
    smaller.  A Dirac has no value on the scale of u: both arrows reach the same height (the top
    of the panel), dashed, and each is labelled with its pair's name and weight."""
    tr = L.simulate(two_carts_with_hook(), ["1/10", "1/10", -2, 1], 1)
    stop = [float(e.impulse[0][0]) for e in tr.events if e.impulse and float(e.time) > 0]
    assert len(stop) == 1 and 0 < stop[0] < 1.5
    fig = tr.plot(points=40)
    ax_u = fig.axes[1]
    arrows = [t for t in ax_u.texts if t.arrow_patch is not None]
    assert len(arrows) == 2 and {t.xy[1] for t in arrows} == {0.97}
    assert all(t.arrow_patch.get_linestyle() not in ("-", "solid") for t in arrows)
    texts = [t.get_text() for t in ax_u.texts if t.arrow_patch is None]
    assert texts == ["impulse (hook) = 1.5", f"impulse (stop) = {stop[0]:.3g}"]
    # each text starts at its arrow and keeps off the other texts
    fig.canvas.draw()
    boxes = [t.get_window_extent() for t in ax_u.texts if t.arrow_patch is None]
    assert not boxes[0].overlaps(boxes[1])


def test_impulse_at_an_unlabelled_event_keeps_its_weight():
    """With fewer event labels than events (label_events=1), the impulse 3/2 of the hook at t = 0
    and the stop's later impulse are still written."""
    tr = L.simulate(two_carts_with_hook(), ["1/10", "1/10", -2, 1], 1)
    fig = tr.plot(points=40, label_events=1)
    weights = [t.get_text() for t in fig.axes[1].texts if t.get_text().startswith("impulse")]
    assert weights[0] == "impulse (hook) = 1.5" and len(weights) == 2
    assert len([t for t in fig.axes[0].texts if "→" in t.get_text()]) == 1
    assert fig.axes[-1].get_xlabel() == "t    (2 events (dashed), 1 labelled above)"


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
    """display/plotting.py is below trajectory.py: it must not import dynamics (trajectory,
    simulate) or the builders."""
    src = (pathlib.Path(L.__file__).parent / "display" / "plotting.py").read_text()
    mods = {n.module for n in ast.walk(ast.parse(src)) if isinstance(n, ast.ImportFrom) and n.module}
    assert mods and not mods & {"trajectory", "simulate", "flow", "models", "examples", "dynamics", "builders"}


def test_import_does_not_load_matplotlib():
    code = "import sys, lcs_exact; print('matplotlib' in sys.modules, 'numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=str(pathlib.Path(L.__file__).parent.parent))
    assert out.stdout.split() == ["False", "False"]


# ---------------------------------------------------------------------------------------------
# modes, event labels, sources (the diode bridges: many events, floating networks, a sine source)
# ---------------------------------------------------------------------------------------------

def mode_entries(ax) -> dict:
    """Legend text -> RGB of the mode patches of a panel's legend."""
    from matplotlib.colors import to_rgb
    return {t.get_text(): to_rgb(h.get_facecolor()) for t, h in zip(ax.get_legend().get_texts(),
                                                                     ax.get_legend().legend_handles)
            if isinstance(h, Rectangle)}


@pytest.fixture(scope="module")
def full_wave():
    rect = L.examples.sine_rectifier(full_wave=True)
    return L.simulate(rect, rect.embed([0]), 20)


def test_each_mode_has_one_legend_entry_with_its_own_words_and_one_colour(full_wave):
    """The full-wave bridge visits ∅ and {0} with D1's input left undetermined by the state (a
    floating source, docs/extensions.md), {3} and {0, 1, 2}: four modes, four legend entries,
    each led by its index set (as the event labels) and all different; every phase is shaded
    with the colour of its own mode's entry (read from the run's phases, not from the figure)."""
    from matplotlib.colors import to_rgb
    from lcs_exact.modes.mode import format_mode

    fig = full_wave.plot(points=200)
    ax = fig.axes[0]
    entries = mode_entries(ax)
    modes = {rec.mode for rec in full_wave.phases}
    assert modes == {frozenset(), frozenset({0}), frozenset({3}), frozenset({0, 1, 2})}
    assert len(entries) == len(modes)
    by_mode = {m: [text for text in entries if text.startswith(format_mode(m) + ":")] for m in modes}
    assert all(len(v) == 1 for v in by_mode.values()), by_mode
    assert len(set(entries.values())) == len(modes)  # distinct colours
    floating = [rec for rec in full_wave.phases if rec.undetermined]
    assert {rec.mode for rec in floating} == {frozenset(), frozenset({0})}
    for m in (frozenset(), frozenset({0})):
        assert "D1 undetermined" in by_mode[m][0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(text.startswith("(∅ and {0} differ only in") for text in legend)
    spans = {(round(p.get_x(), 9), round(p.get_x() + p.get_width(), 9)): to_rgb(p.get_facecolor())
             for p in ax.patches if isinstance(p, Rectangle)}
    for rec in full_wave.phases:
        color = spans[(round(float(rec.t0), 9), round(float(rec.t1), 9))]
        assert color == entries[by_mode[rec.mode][0]], rec


def test_a_mode_keeps_its_colour_in_every_figure_of_its_system():
    """The LC bridge from (0, -1) conducts through D1, D4 ({0, 3}) first, from (0, 1) through D2, D3
    ({1, 2}) first: {1, 2} has the same colour in both figures."""
    bridge = L.examples.diode_bridge()
    figs = [L.simulate(bridge, x0, 5).plot(points=50) for x0 in ([0, -1], [0, 1])]
    colors = [{text.split(":")[0]: c for text, c in mode_entries(f.axes[0]).items()} for f in figs]
    assert set(colors[0]) == set(colors[1]) == {"{0, 3}", "{1, 2}"}
    assert colors[0] == colors[1]
    assert figs[1].axes[0].patches[0].get_facecolor()[:3] == pytest.approx(colors[0]["{1, 2}"])


def assert_no_overlaps(texts):
    boxes = [t.get_window_extent() for t in texts]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            assert not boxes[i].overlaps(boxes[j]), (texts[i].get_text(), texts[j].get_text())


def test_event_labels_of_a_dense_run_never_overlap_and_every_event_is_marked():
    """Siconos' bridge with a capacitor filter has 40 events in 5 ms: the labels that have room are
    drawn above the axes, none over another nor over the title; every event keeps its dashed
    line in every panel, and the axis label says how many are labelled."""
    bridge = L.examples.diode_bridge_cap_filter()
    tr = L.simulate(bridge, [10, 0, 0], "1/200")
    n = len(tr.events)
    assert n == 40
    fig = tr.plot(panels=("x", "u"), points=300)
    fig.canvas.draw()
    labels = [t for t in fig.axes[0].texts if "→" in t.get_text()]
    assert 10 <= len(labels) < n
    assert_no_overlaps(labels + [t for t in fig.texts if t.get_text() == fig.get_suptitle()])
    assert fig.axes[-1].get_xlabel() == f"t    ({n} events (dashed), {len(labels)} labelled above)"
    top = fig.axes[0].get_window_extent()
    assert all(t.get_window_extent().y0 >= top.y1 for t in labels)  # above the data, inside the figure
    assert all(fig.bbox.x0 <= t.get_window_extent().x0 and t.get_window_extent().x1 <= fig.bbox.x1 for t in labels)
    # each label starts at its event's line (the first ones, left of the last 15 % of the axis)
    x_of = fig.axes[0].transData.transform
    for t in labels:
        if t.xy[0] < 0.85 * float(tr.events[-1].time):
            assert t.get_ha() == "left" and 0 < t.get_window_extent().x0 - x_of((t.xy[0], 0))[0] < 6
    for ax in fig.axes:
        dashed = sorted(ln.get_xdata()[0] for ln in ax.get_lines()
                        if ln.get_linestyle() == "--" and len(set(ln.get_xdata())) == 1)
        assert dashed == pytest.approx(sorted(float(e.time) for e in tr.events), abs=1e-15)


def test_event_labels_of_the_full_wave_bridge_never_overlap(full_wave):
    fig = full_wave.plot(points=200)
    fig.canvas.draw()
    labels = [t for t in fig.axes[0].texts if "→" in t.get_text()]
    assert len(labels) >= 10
    assert_no_overlaps(labels + [t for t in fig.texts if t.get_text() == fig.get_suptitle()])


def test_sources_are_hidden_unless_asked(full_wave):
    """The full-wave rectifier's states are v(C1) and the source's sin(t), cos(t): by default one
    line per phase (v(C1)), the legend says which states are left out; with sources=True the
    lines of sin(t) and cos(t) are there, equal to sin and cos (numpy) at their times."""
    import numpy as np

    fig = full_wave.plot(points=200)
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "v(C1)" in legend and "sin(t)" not in legend and "cos(t)" not in legend
    assert any("not drawn: sin(t), cos(t)" in text for text in legend)
    assert len(state_lines(ax)) == len(full_wave.phases)
    fig = full_wave.plot(points=200, sources=True)
    ax = fig.axes[0]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend[:3] == ["v(C1)", "sin(t)", "cos(t)"]
    lines = state_lines(ax)
    assert len(lines) == 3 * len(full_wave.phases)
    for fn, pos in ((np.sin, 1), (np.cos, 2)):
        mine = lines[pos::3]
        assert all(np.allclose(ln.get_ydata(), fn(ln.get_xdata()), atol=1e-12) for ln in mine)
    # an explicit selection draws what it names
    fig = full_wave.plot(points=50, states=["sin(t)"])
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()][0] == "sin(t)"


def test_panels_are_checked():
    tr = L.simulate(two_carts(), [0, 1, -1, 0], 1)
    with pytest.raises(L.InvalidArgument, match="declares none"):
        tr.plot(panels=("x", "w"))
    with pytest.raises(L.InvalidArgument, match="subset"):
        tr.plot(panels="x")
