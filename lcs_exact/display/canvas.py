"""The drawing state of a trajectory figure (:func:`lcs_exact.display.plot_trajectory`): its panels,
pens and mode colours, what was drawn (for the legends and the texts placed last), and the batching of a
dense figure's artists (hundreds of phases: one line per component, one marker set per kind, one
shading collection per mode, drawn by :meth:`Canvas.flush`)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Canvas"]


@dataclass
class Canvas:
    """What the parts of a trajectory figure share: the trajectory, the panels (``ax_of``: "x",
    "w", "u", "y" to their axes), the components drawn in each (``comps``) and their pens (colour,
    line style of the pos-th line), the colour of each mode, the declared outputs, the names of
    the states left out (sources), and what was drawn (for the legends and the texts placed last)."""

    traj: Any
    lcs: Any
    fig: Any
    axes: list
    ax_of: dict
    comps: dict
    pens: list
    colors: dict
    outputs: Any = None
    hidden: list = field(default_factory=list)
    t_hi: float = 1.0
    any_jump: bool = False
    any_free: bool = False
    free_of: dict = field(default_factory=dict)  # mode -> inputs undetermined on its phases
    equal: dict = field(default_factory=dict)  # (panel, pos, pos') -> modes where the two lines are equal
    impulses: list = field(default_factory=list)  # (t drawn, text) of each impulse arrow
    stopped: float | None = None  # where a partial run stopped (its mark takes room above the axes)
    # a dense figure (hundreds of phases) batches its artists: one line per component, one set of
    # markers per kind, one collection of shadings per mode (an artist each took 20 s for 700 events)
    batch: bool = False
    pending: dict = field(default_factory=dict)  # (call, key) -> [xs, ys] or the spans, for flush()

    def line(self, which: str, pos: int, tt, vals) -> None:
        """The pos-th line of a panel (a state, an output, or a pair's u or y) over the times tt."""
        if self.batch:  # one Line2D, the phases apart by NaN (no segment joins them)
            xs, ys = self.pending.setdefault(("line", (which, pos)), ([], []))
            xs.extend([math.nan, *tt] if xs else tt)
            ys.extend([math.nan, *vals] if ys else vals)
            return
        color, ls = self.pens[pos]
        self.ax_of[which].plot(tt, vals, color=color, ls=ls, lw=self.width(which, pos))

    def span(self, a: float, b: float, mode) -> None:
        """A phase [a, b] shaded with its mode's colour in every panel."""
        if self.batch:
            self.pending.setdefault(("span", mode), []).append((a, b - a))
            return
        for ax in self.axes:
            ax.axvspan(a, b, color=self.colors[mode], alpha=0.10, lw=0)

    def flush(self) -> None:
        """Draw what a dense figure batched."""
        for (call, key), data in self.pending.items():
            if call == "line":
                color, ls = self.pens[key[1]]
                self.ax_of[key[0]].plot(*data, color=color, ls=ls, lw=self.width(*key))
            elif call == "span":
                for ax in self.axes:
                    ax.broken_barh(data, (0, 1), transform=ax.get_xaxis_transform(), color=self.colors[key],
                                   alpha=0.10, lw=0)
            else:
                which, pos, sizes = key[1:]
                color, style = self.pens[pos][0], dict(mfc="white", mec=self.pens[pos][0], ms=sizes[0], zorder=5) \
                    if key[0] == "left" else dict(color=self.pens[pos][0], ms=sizes[1], zorder=6)
                self.ax_of[which].plot(*data, "o", ls="none", **style)
        self.pending.clear()

    def width(self, which: str, pos: int) -> float:
        """The width of the pos-th line of a panel: the outputs' (relays, often equal: both at +1
        or 0) decrease with pos, so that a line drawn over an equal one leaves it visible."""
        m = len(self.comps[which])
        return 1.6 + (1.6 * (m - 1 - pos) / (m - 1) if which == "w" and 1 < m <= 8 else 0.0)

    def jump(self, which: str, pos: int, t: float, left, right, sizes: tuple) -> None:
        """A jump of the pos-th line of a panel at t: an open circle at the left limit, a filled
        one at the right limit (the trajectory is right-continuous)."""
        if self.batch:
            for side, v in (("left", left), ("right", right)):
                xs, ys = self.pending.setdefault(("mark", (side, which, pos, sizes)), ([], []))
                xs.append(t)
                ys.append(float(v))
            return
        color = self.pens[pos][0]
        self.ax_of[which].plot([t], [float(left)], "o", mfc="white", mec=color, ms=sizes[0], zorder=5)
        self.ax_of[which].plot([t], [float(right)], "o", color=color, ms=sizes[1], zorder=6)
