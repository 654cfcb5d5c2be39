"""The figure of a 2-D mode map (Figure 8.2 style): regions filled and labelled with S(x0), jumps
as arrows (:func:`plot_mode_map`, also :meth:`lcs_exact.ModeMap.plot`).

matplotlib is imported inside the function, so ``import lcs_exact`` stays light.  A mode map is
used through its public interface only (``dimension``, ``faces``, ``hyperplanes``, ``regions``,
``locate``, ``slice_jump``, ``variables``, ``lcs``).  Faces are clipped to the window exactly
(rational polygon clipping) and only then rounded to floats for drawing.

The colours of modes and the test for default names are shared with the trajectory figure
(:mod:`lcs_exact.plotting`, which sits above this module and re-exports :func:`plot_mode_map`).
"""
from __future__ import annotations

from typing import Any, Sequence

from flint import fmpq

from ..errors import InvalidArgument
from ..interfaces import SystemLike
from ..algebra import to_fmpq

__all__ = ["plot_mode_map", "MODE_COLORS", "default_names"]

#: the colours of modes (regions of a map, phases of a trajectory), in order
MODE_COLORS = ["#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860", "#da8bc3",
               "#8c8c8c", "#ccb974", "#64b5cd"]


def default_names(names: Sequence[str], prefix: str) -> bool:
    """True when ``names`` are the defaults ``prefix0, prefix1, ...`` (no name was given).

    >>> default_names(("x_0", "x_1"), "x_"), default_names(("q", "v"), "x_")
    (True, False)
    """
    return tuple(names) == tuple(f"{prefix}{i}" for i in range(len(names)))


def _clip(poly: list[tuple[fmpq, fmpq]], a, b, sign: int) -> list[tuple[fmpq, fmpq]]:
    """Sutherland-Hodgman: keep the part of the polygon with sign * (a . p + b) >= 0 (exact)."""
    def val(p):
        return sign * (a[0] * p[0] + a[1] * p[1] + b)
    out = []
    for i in range(len(poly)):
        p, q = poly[i], poly[(i + 1) % len(poly)]
        vp, vq = val(p), val(q)
        if vp >= 0:
            out.append(p)
        if (vp > 0 and vq < 0) or (vp < 0 and vq > 0):
            t = vp / (vp - vq)
            out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    return out


def _segment(face, hyperplanes, window) -> tuple | None:
    """The closure of a 1-D face inside the window: two endpoints (exact) or None."""
    j0 = face.signs.index(0)
    a, b = hyperplanes[j0]
    p = face.point
    d = (-a[1], a[0])
    lo, hi = None, None
    cons = [(hyperplanes[j], face.signs[j]) for j in range(len(face.signs)) if j != j0]
    x0, x1, y0, y1 = window
    cons += [(((fmpq(1), fmpq(0)), -x0), 1), (((fmpq(1), fmpq(0)), -x1), -1),
             (((fmpq(0), fmpq(1)), -y0), 1), (((fmpq(0), fmpq(1)), -y1), -1)]
    for (c, e), s in cons:
        g0 = s * (c[0] * p[0] + c[1] * p[1] + e)  # >= 0 on the closure
        g1 = s * (c[0] * d[0] + c[1] * d[1])
        if g1 == 0:
            if g0 < 0:
                return None
            continue
        t = -g0 / g1
        if g1 > 0:
            lo = t if lo is None or t > lo else lo
        else:
            hi = t if hi is None or t < hi else hi
    if lo is None or hi is None or lo > hi:
        return None
    return ((p[0] + lo * d[0], p[1] + lo * d[1]), (p[0] + hi * d[0], p[1] + hi * d[1]))


def _default_window(mm) -> tuple:
    verts = [f.point for f in mm.faces if f.dimension == 0]
    if not verts:
        verts = [f.point for f in mm.faces if f.dimension <= 1][:1] or [(fmpq(0), fmpq(0))]
    cx = sum((v[0] for v in verts), fmpq(0)) / len(verts)
    cy = sum((v[1] for v in verts), fmpq(0)) / len(verts)
    spread = max([abs(v[0] - cx) for v in verts] + [abs(v[1] - cy) for v in verts] + [fmpq(0)])
    h = max(fmpq(1), fmpq(3, 2) * spread)
    return (cx - h, cx + h, cy - h, cy + h)


def _region_legend(lcs: SystemLike, r) -> str:
    """``S = {0}: stop`` (constraint names of the single admissible mode), ``(ray)``/``(point)``."""
    text = f"S = {r.label}"
    names = getattr(lcs, "constraint_names", None)
    if len(r.modes) == 1 and names and not default_names(names, ""):
        (m,) = r.modes
        text += ": " + ("+".join(names[i] for i in sorted(m)) if m else "free")
    if r.dimension < 2:
        text += " (ray)" if r.dimension == 1 else " (point)"
    return text


def plot_mode_map(mm, ax=None, *, window: Sequence[Any] | None = None, arrows: bool = True,
                  grid: int = 9, title: str | None = None):
    """Draw a 2-D mode map: regions filled and labelled with S(x0), jumps as arrows.

    Faces are clipped to the window exactly (rational polygon clipping) before they are drawn;
    1-D regions are thick lines and 0-D regions dots, in the colour of their S(x0).  An arrow
    goes from a grid point s to the point where the re-initialization takes it (P_I x0 - x0 in
    slice coordinates, exact, then rounded for drawing; its projection onto the slice when the
    jump leaves the slice, as the title then says).  Grid points are rational and located
    exactly, so points on boundaries get their own region.  Returns the Figure.

    Parameters
    ----------
    mm : ModeMap
        A map with two coordinates (``slice=(base, [d_0, d_1])``, or an LCS with n = 2).
    window : (xmin, xmax, ymin, ymax), optional
        Rationals; by default a square around the vertices of the arrangement.
    arrows : bool
    grid : int
        Arrows on a grid x grid lattice (offset by half a step).
    ax : matplotlib Axes, optional
        Where to draw (None: a new figure).
    title : str, optional
        The axes' title.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from lcs_exact.examples import two_carts_with_hook
    >>> fig = two_carts_with_hook().mode_map(slice=([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]])).plot()
    >>> fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel()
    ("q_0'", "q_1'")
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import to_rgb

    if mm.dimension != 2:
        raise InvalidArgument(f"plot draws a 2-D map; this map has {mm.dimension} coordinates "
                         "(give slice=(base, [d_0, d_1]))")
    window = _map_window(mm, window)
    x0, x1, y0, y1 = window
    own_figure = ax is None
    if own_figure:
        fig, ax = plt.subplots(figsize=(8.2, 5.0), layout="constrained")
    else:
        fig = ax.figure
    color = {r.modes: MODE_COLORS[i % len(MODE_COLORS)] for i, r in enumerate(mm.regions)}
    pastel = {m: tuple(0.62 + 0.38 * v for v in to_rgb(c)) for m, c in color.items()}
    centres = _draw_faces(ax, mm, window, color, pastel)
    for r in mm.regions:
        if r.modes in centres:
            cx, cy = centres[r.modes][1]
            ax.text(cx, cy, r.label, ha="center", va="center", fontsize=11, weight="bold",
                    bbox=dict(boxstyle="round,pad=0.25", fc="white", ec=color[r.modes], alpha=0.85), zorder=6)
    leaves = _draw_jump_arrows(ax, mm, window, grid) if arrows and grid > 0 else False
    ax.set_xlim(float(x0), float(x1))
    ax.set_ylim(float(y0), float(y1))
    ax.set_xlabel(mm.variables[0])
    ax.set_ylabel(mm.variables[1])
    ax.set_aspect("equal", adjustable="box")
    _map_legend(fig, ax, mm, color, pastel, arrows, own_figure)
    name = title if title is not None else f"{getattr(mm.lcs, 'name', None) or 'LCS'}: mode map (exact)"
    if leaves:
        name += "\n(jumps leave the slice: arrows show their projection)"
    ax.set_title(name, fontsize=11)
    return fig


def _map_window(mm, window: Sequence[Any] | None) -> tuple:
    """The drawn window (xmin, xmax, ymin, ymax) as rationals: the given one, checked, or a square
    around the vertices of the arrangement."""
    if window is None:
        window = _default_window(mm)
    window = tuple(to_fmpq(w, "window") for w in window)
    x0, x1, y0, y1 = window
    if not (x0 < x1 and y0 < y1):
        raise InvalidArgument("window must be (xmin, xmax, ymin, ymax) with xmin < xmax and ymin < ymax")
    return window


def _draw_faces(ax, mm, window: tuple, color: dict, pastel: dict) -> dict:
    """Draw every face of the arrangement inside the window in the colour of its S(x0): 2-D faces
    filled, rays of their own S thick (a boundary between two regions thin), points of their own
    S as dots.  Returns, per S, the largest drawn polygon's (area, centre) for its label."""
    from matplotlib.patches import Polygon

    x0, x1, y0, y1 = window
    rect = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    region_of = {f.signs: r.modes for r in mm.regions for f in r.faces}
    best_poly: dict = {}
    for r in mm.regions:
        for f in r.faces:
            if f.dimension == 2:
                poly = _clipped_face(f, mm.hyperplanes, rect)
                if len(poly) >= 3:
                    pts = [(float(p[0]), float(p[1])) for p in poly]
                    # opaque pastel with an edge of the same colour: no seams between faces
                    ax.add_patch(Polygon(pts, closed=True, facecolor=pastel[r.modes], edgecolor=pastel[r.modes],
                                         lw=0.8, zorder=1))
                    area, centre = _area_and_centre(pts)
                    if area > best_poly.get(r.modes, (0, None))[0]:
                        best_poly[r.modes] = (area, centre)
            elif f.dimension == 1:
                _draw_ray(ax, mm, r, f, region_of, window, color)
            elif f.dimension == 0 and r.dimension == 0:  # a vertex inside a larger region is not special
                p = f.point
                if x0 <= p[0] <= x1 and y0 <= p[1] <= y1:
                    ax.plot([float(p[0])], [float(p[1])], "o", color=color[r.modes], mec="black", ms=8, zorder=4)
    return best_poly


def _clipped_face(f, hyperplanes, rect: list) -> list:
    """A 2-D face clipped to the window exactly: the window's rectangle cut by each hyperplane on
    the face's side (empty when nothing is left)."""
    poly = rect
    for (a, b), s in zip(hyperplanes, f.signs):
        poly = _clip(poly, a, b, s)
        if not poly:
            break
    return poly


def _area_and_centre(pts: list) -> tuple[float, tuple[float, float]]:
    """The area of a polygon (the shoelace formula) and the mean of its vertices."""
    area = abs(sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
                   for i in range(len(pts)))) / 2
    return area, (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))


def _draw_ray(ax, mm, r, f, region_of: dict, window: tuple, color: dict) -> None:
    """A ray of its own S is drawn thick; a boundary ray of a 2-D region thin, in the colour of the
    region that owns it; a ray inside one region not at all."""
    j0 = f.signs.index(0)
    sides = {region_of.get(f.signs[:j0] + (s,) + f.signs[j0 + 1:]) for s in (-1, 1)}
    if r.dimension == 1:
        lw = 4.0
    elif len(sides) > 1:
        lw = 1.8
    else:
        return
    seg = _segment(f, mm.hyperplanes, window)
    if seg is not None:
        ax.plot([float(seg[0][0]), float(seg[1][0])], [float(seg[0][1]), float(seg[1][1])],
                color=color[r.modes], lw=lw, solid_capstyle="butt", zorder=3)


def _draw_jump_arrows(ax, mm, window: tuple, grid: int) -> bool:
    """Arrows of the re-initializations x0 -> P_I x0 (in slice coordinates, exact, rounded for
    drawing) from a grid x grid lattice of rational points offset by half a step; True when some
    jump leaves the slice (its arrow is then its projection)."""
    x0, x1, y0, y1 = window
    leaves = False
    us, vs, xs, ys = [], [], [], []
    for i in range(grid):
        for j in range(grid):
            s = (x0 + (x1 - x0) * fmpq(2 * i + 1, 2 * grid), y0 + (y1 - y0) * fmpq(2 * j + 1, 2 * grid))
            reg = mm.locate(s)
            jm = mm.slice_jump(reg)
            if jm is None:
                continue
            c0, C1, exact = jm
            dx = c0[0, 0] + C1[0, 0] * s[0] + C1[0, 1] * s[1]
            dy = c0[1, 0] + C1[1, 0] * s[0] + C1[1, 1] * s[1]
            if dx == 0 and dy == 0:
                continue
            leaves = leaves or not exact
            xs.append(float(s[0]))
            ys.append(float(s[1]))
            us.append(float(dx))
            vs.append(float(dy))
    if xs:
        ax.quiver(xs, ys, us, vs, angles="xy", scale_units="xy", scale=1, width=0.004, color="0.15",
                  zorder=5, alpha=0.8)
    return leaves


def _map_legend(fig, ax, mm, color: dict, pastel: dict, arrows: bool, own_figure: bool) -> None:
    """One legend entry per region (its S and, for a single mode, the constraints active in it),
    and the jump arrows'."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = [Patch(facecolor=pastel[r.modes] if r.dimension == 2 else color[r.modes], label=_region_legend(mm.lcs, r))
               for r in mm.regions]
    if arrows:
        handles.append(Line2D([], [], color="0.15", marker=r"$\rightarrow$", ls="", ms=12, label="jump x0 → x(0+)"))
    if own_figure:
        fig.legend(handles=handles, loc="outside right upper", fontsize=9, frameon=False)
    else:
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=9, frameon=False)
