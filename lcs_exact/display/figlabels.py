"""The words and colours of figures: texts placed without overlap, modes in the builder's words
with one colour each, the outputs a builder declared (:mod:`lcs_exact.plotting` draws with them).

* Texts are measured (their width in points, from the font, whatever the backend) and placed in
  rows: a text goes in the lowest row where it overlaps nothing already placed, or is left out
  (:class:`Rows`); what it labels stays marked.
* A mode has one colour per system, the same in every figure of that system drawn in the session
  (:func:`mode_colors`; the empty mode, where nothing is in contact or conducting, is grey), and
  one legend text: its index set, then the builder's words (:func:`mode_texts`).
* :func:`derived_outputs`: the outputs w = W_x x + W_u u a builder declared (a relay's w_j),
  read from the LCS or its embedding.

matplotlib is imported inside the functions, so ``import lcs_exact`` stays light.
"""
from __future__ import annotations

import weakref
from typing import Any, Iterable

from ..errors import InvalidArgument
from ..interfaces import SystemLike
from .mapplot import MODE_COLORS, default_names
from ..modes import format_mode, mode_order

__all__ = ["draw_schedule", "SCHEDULE_COLORS", "text_width", "Rows", "mode_colors", "mode_texts", "derived_outputs", "EMPTY_MODE_COLOR", "state_label",
           "pair_label", "impulse_label", "event_text", "selected_indices"]

#: the colour of the empty mode (every pair out: no contact, no diode conducting) and of unknown modes
EMPTY_MODE_COLOR = "#9a9a9a"

#: per system, the colour given to each nonempty mode, in the order the modes were first drawn
_COLORS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def state_label(lcs: SystemLike, i: int) -> str:
    """The name of state i in a legend: the builder's, or ``$x_{i}$`` for default names.

    >>> from lcs_exact.examples import two_carts
    >>> state_label(two_carts(), 2)
    "q_0'"
    """
    names = getattr(lcs, "state_names", None) or tuple(f"x_{j}" for j in range(lcs.n))
    return f"$x_{{{i}}}$" if default_names(names, "x_") else names[i]


def pair_label(lcs: SystemLike, which: str, i: int, latex: bool = True) -> str:
    """The name of u_i or y_i (``which``) in a legend, a table or a state-space system: the
    builder's words (``force (stop)``, ``i(D1)``), ``u (name)`` for a named pair, ``$u_{i}$``
    otherwise (``u_i`` with ``latex=False``).

    Parameters
    ----------
    lcs : LCS
        The system whose pair is named.
    which : {"u", "y"}
        The input u_i or the output y_i of the pair.
    i : int
        The pair's index (0-based).
    latex : bool, optional
        ``$u_{i}$`` (True) or ``u_i`` for an unnamed pair.

    >>> from lcs_exact.examples import two_carts
    >>> pair_label(two_carts(), "u", 0), pair_label(two_carts(), "y", 0)
    ('force (stop)', 'gap (stop)')
    """
    roles = getattr(lcs, "roles", None)
    if roles is not None:
        return roles[i][0 if which == "u" else 1]
    names = getattr(lcs, "constraint_names", None) or tuple(str(j) for j in range(lcs.k))
    if default_names(names, ""):
        return f"${which}_{{{i}}}$" if latex else f"{which}_{i}"
    return f"{which} ({names[i]})"


def impulse_label(lcs: SystemLike, i: int) -> str:
    """``impulse (stop)``: an impulse of pair i, named as the pair (``force (stop)``).

    >>> from lcs_exact.examples import two_carts
    >>> impulse_label(two_carts(), 0)
    'impulse (stop)'
    """
    names = getattr(lcs, "constraint_names", None) or tuple(str(j) for j in range(lcs.k))
    if default_names(names, "") and getattr(lcs, "roles", None) is None:
        return f"impulse u_{i}"
    return f"impulse ({names[i]})"


def event_text(e: Any) -> str:
    """An event's label: ``∅→{0}``; ``start→{1}`` at t = 0; ``∅→∅ via {0}`` when the state jumped
    through modes other than the one entered (an impact followed by lift-off, a chain (4.9)).

    >>> from types import SimpleNamespace as E
    >>> event_text(E(mode_before=frozenset(), mode_after=frozenset(), modes=(frozenset({0}),)))
    '∅→∅ via {0}'
    """
    before = "start" if e.mode_before is None else format_mode(e.mode_before)
    text = f"{before}→{format_mode(e.mode_after)}"
    chain = tuple(getattr(e, "modes", ()) or ())
    if chain and (len(chain) > 1 or chain[-1] != e.mode_after):
        text += " via " + ", ".join(format_mode(m) for m in chain)
    return text


def text_width(text: str, size: float = 8) -> float:
    """The width of ``text`` at ``size`` points, in points (measured on the default font).

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> text_width("{0}→∅") > text_width("{0}") > 0
    True
    """
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import text_to_path

    w, _, _ = text_to_path.get_text_width_height_descent(text, FontProperties(size=size), ismath=False)
    return float(w)


class Rows:
    """Rows of texts along one axis (positions in points): :meth:`place` puts an interval in the
    lowest row where it keeps ``gap`` points from every interval there, or returns None.

    >>> rows = Rows(2, gap=2)
    >>> rows.place(0, 10), rows.place(5, 15), rows.place(11, 20), rows.place(1, 4)
    (0, 1, None, None)
    >>> rows.place(13, 20)
    0
    """

    def __init__(self, count: int, gap: float = 3.0):
        self.rows: list[list[tuple[float, float]]] = [[] for _ in range(count)]
        self.gap = gap

    def free(self, row: int, lo: float, hi: float) -> bool:
        """True when [lo, hi] keeps the gap from every interval of the row."""
        return all(hi + self.gap <= a or lo >= b + self.gap for a, b in self.rows[row])

    def place(self, lo: float, hi: float) -> int | None:
        """The row given to [lo, hi] (now occupied), or None when every row is taken there."""
        for r in range(len(self.rows)):
            if self.free(r, lo, hi):
                self.rows[r].append((lo, hi))
                return r
        return None

    def place_text(self, X: float, w: float, W: float, off: float = 3, avoid: Iterable[float] = (),
                   left: bool = False, beyond: float = 0.0) -> tuple[int, str, bool] | None:
        """A text ``w`` points wide that labels the position X of an axis W points long: ``off``
        points to the right of X (to its left if ``left``, or when it would end more than
        ``beyond`` points past W, or when that keeps it off the positions ``avoid``: lines that
        cross every row).  Returns (row, its alignment ``"left"`` or ``"right"``, True when it
        ends past W), or None when no row has room.

        >>> rows = Rows(2)
        >>> rows.place_text(10, 50, 100), rows.place_text(90, 50, 100), rows.place_text(90, 50, 100, beyond=60)
        ((0, 'left', False), (1, 'right', False), (0, 'left', True))
        """
        sides = [(lo, ha) for lo, ha in ((X + off, "left"), (X - off - w, "right"))[::-1 if left else 1]
                 if lo >= 0 and lo + w <= W + beyond]
        sides.sort(key=lambda s: any(s[0] - 3 < a < s[0] + w + 3 for a in avoid))
        for lo, ha in sides:
            row = self.place(lo, lo + w)
            if row is not None:
                return row, ha, lo + w > W
        return None


def mode_colors(lcs: Any, modes: Iterable) -> dict:
    """One colour per mode, the same in every figure of the same system: nonempty modes get the
    colours of :data:`~lcs_exact.mapplot.MODE_COLORS` in the order they are first drawn (by index
    set within one figure); the empty mode and unknown modes (None) are grey.

    >>> from lcs_exact.examples import two_carts_with_hook
    >>> hook = two_carts_with_hook()
    >>> first = mode_colors(hook, [frozenset({1}), frozenset()])
    >>> again = mode_colors(hook, [frozenset({0}), frozenset({1})])
    >>> again[frozenset({1})] == first[frozenset({1})] != again[frozenset({0})], first[frozenset()]
    (True, '#9a9a9a')
    """
    modes = list(modes)
    try:
        reg = _COLORS.setdefault(lcs, {})
    except TypeError:  # neither hashable nor weakly referable: colours for this figure alone
        reg = {}
    for m in sorted({m for m in modes if m}, key=mode_order):
        if m not in reg:
            reg[m] = MODE_COLORS[len(reg) % len(MODE_COLORS)]
    return {m: reg[m] if m else EMPTY_MODE_COLOR for m in modes}


def _wrap(text: str, width: int = 46) -> str:
    """Break a long description into lines at its separators ("; ", then ", ")."""
    if len(text) <= width:
        return text
    for sep in ("; ", ", "):
        parts = text.split(sep)
        if len(parts) > 1:
            lines, cur = [], parts[0]
            for p in parts[1:]:
                if len(cur) + len(sep) + len(p) <= width:
                    cur += sep + p
                else:
                    lines.append(cur + sep.rstrip())
                    cur = "   " + p
            lines.append(cur)
            if all(len(ln) <= width + 4 for ln in lines):
                return "\n".join(lines)
    return text


def mode_texts(lcs: SystemLike, modes: Iterable, free_of: dict | None = None) -> tuple[dict, list[str]]:
    """The legend text of each mode and notes on them.

    A mode reads ``"{0}: stop contact"``: its index set (as in the event labels ``∅→{0}``), then
    the words of the declared outputs (``"w_0 = +1"``, a relay) or of the builder's roles
    (:meth:`~lcs_exact.LCS.describe_mode`, with the inputs left undetermined on its phases,
    ``free_of[mode]``, said so), or ``"mode {0}"`` without roles.  Two modes with the same words
    differ only in inputs the state leaves undetermined (a floating network written in two
    modes): a note says so.

    >>> from lcs_exact.examples import two_carts
    >>> mode_texts(two_carts(), [frozenset({0}), frozenset()])
    ({frozenset({0}): '{0}: stop contact', frozenset(): '∅: stop open'}, [])
    """
    free_of = free_of or {}
    outputs = derived_outputs(lcs)
    texts, words = {}, {}
    for m in modes:
        if m is None:
            texts[m] = "mode ?"
            continue
        free = free_of.get(m, frozenset())
        desc = outputs.describe_mode(m) if outputs is not None and hasattr(outputs, "describe_mode") else None
        if desc is None and getattr(lcs, "roles", None) is not None and hasattr(lcs, "describe_mode"):
            desc = lcs.describe_mode(m, free)
        if desc is None:
            texts[m] = f"mode {format_mode(m)}" + (f" ({format_mode(free)} undetermined)" if free else "")
            continue
        texts[m] = _wrap(f"{format_mode(m)}: {desc}")
        words.setdefault(desc, []).append(m)
    notes = [" and ".join(format_mode(m) for m in sorted(ms, key=mode_order)) + " differ only in\n"
             "   inputs the state leaves undetermined" for ms in words.values() if len(ms) > 1]
    return texts, notes


def derived_outputs(lcs: Any) -> Any:
    """The outputs w = W_x x + W_u u a builder declared (``names``, ``Wx``, ``Wu``, ``symbol``;
    :class:`lcs_exact.relays.RelayOutputs` for relays), or None: ``lcs.outputs`` when the LCS
    carries them, else its embedding's.

    Parameters
    ----------
    lcs : LCS
        The system (or anything with its public interface).

    >>> from lcs_exact.models import relay, two_carts
    >>> derived_outputs(relay([[0]], [[-1]], [[1]])).names, derived_outputs(two_carts())
    (('w_0',), None)
    """
    out = getattr(lcs, "outputs", None)
    if out is None or not hasattr(out, "Wx"):
        out = getattr(getattr(lcs, "embedding", None), "outputs", None)
    return out if out is not None and hasattr(out, "Wx") else None


#: colours of the schedule's phases in the band over a figure (lcs_exact.schedule)
SCHEDULE_COLORS = ("#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860")


def draw_schedule(ax: Any, schedule: Any, t_hi: float) -> int:
    """A band along the top of ``ax`` with one coloured segment per segment of ``schedule`` (a
    :class:`~lcs_exact.schedule.Schedule`) up to ``t_hi``, each labelled with its phase (the
    phase's system name, else ``phase k``) where it has room; returns the segments drawn (none
    for a schedule of one phase: sampling, whose instants the event lines mark).

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> from lcs_exact import LCS, models
    >>> pwm = models.scheduled([("1/2", LCS([[-1]], [[1]], [[1]], [[0]], name="on")),
    ...                         ("1/2", LCS([[-2]], [[1]], [[1]], [[0]], name="off"))], period=1)
    >>> fig, ax = plt.subplots()
    >>> draw_schedule(ax, pwm.schedule, 2.0), sorted({t.get_text() for t in ax.texts})
    (4, ['off', 'on'])
    """
    if len(schedule.phases) == 1:  # one phase repeated (sampling): the event lines say it all
        return 0
    index = {id(p): k for k, p in enumerate(schedule.phases)}
    fig = ax.figure
    width = ax.get_position().width * fig.get_figwidth() * 72 / (1.03 * t_hi)  # points per time unit
    drawn = 0
    for start, end, ph in schedule.segments():
        a = float(start)
        if a >= t_hi:
            break
        b = t_hi if end is None else min(float(end), t_hi)
        k = index[id(ph)]
        ax.axvspan(a, b, ymin=0.955, ymax=1.0, color=SCHEDULE_COLORS[k % len(SCHEDULE_COLORS)], alpha=0.35, lw=0)
        label = ph.lcs.name or f"phase {k}"
        if len(schedule.phases) > 1 and text_width(label, 7) + 4 < (b - a) * width:  # only where it fits
            ax.text((a + b) / 2, 0.978, label, transform=ax.get_xaxis_transform(),
                    ha="center", va="center", fontsize=7, color="black", clip_on=True)
        drawn += 1
    return drawn


def selected_indices(sel: Any, names: Any, count: int, what: str) -> list[int]:
    """The indices a figure's selection names: all ``count`` when ``sel`` is None, else each entry
    as a 0-based index or as one of ``names``.

    Parameters
    ----------
    sel : sequence of int or str, or None
        The selection (``states=`` or ``constraints=`` of a plot).
    names : sequence of str
        The names a string entry may take (the system's state or pair names).
    count : int
        The number of states or pairs.
    what : str
        What is selected, for the error message (``"state"``, ``"constraint"``).

    >>> selected_indices(["b", 0], ("a", "b"), 2, "state"), selected_indices(None, (), 3, "state")
    ([1, 0], [0, 1, 2])
    """
    if sel is None:
        return list(range(count))
    out = []
    for v in sel:
        if isinstance(v, str):
            if v not in names:
                raise InvalidArgument(f"unknown {what} name {v!r}; the names are {tuple(names)}")
            out.append(tuple(names).index(v))
        else:
            i = int(v)
            if not 0 <= i < count:
                raise InvalidArgument(f"{what} index {i} outside 0..{count - 1} (indices are 0-based)")
            out.append(i)
    return out
