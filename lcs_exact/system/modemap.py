"""The exact mode map (docs/paper-to-api.md): where each S(x0) and each re-initialization holds.

Mode I is in S(x0) iff, for every row of u_I(s) = W_I(s) x0 and y_Ic(s) = Z_I(s) x0
(section 5.2), the Laurent coefficients at s = oo are lexicographically nonnegative (5.4),
(5.6)-(5.7), Lemma 5.1.  Those coefficients are rational linear forms f . x0
(:func:`lcs_exact.selection.admissibility_forms`), so S(x0) depends only on the signs of finitely
many forms: it is constant on every face of the central hyperplane arrangement {f . x0 = 0}.
The re-initialization x(0+) = P_I x0 of the selected (smallest) mode I (Remark 4.8) is then
constant on the same faces.

Representation.  On an affine slice x0 = base + sum_i s_i d_i (the whole space when no slice is
given: base 0, d_i = e_i) each form becomes an affine form a . s + b; forms that are positive
multiples of one another are one hyperplane.  The faces are enumerated exactly: a face is a
sign vector (one of -1, 0, +1 per hyperplane) that some point realizes, found by exact LP
feasibility (:func:`lcs_exact.polyhedra.find_point`), each with a rational witness point.  A
:class:`Region` is the union of the faces with one value of S(x0); its ``inequalities`` are a
disjunction of conjunctions, each conjunction the largest box of sign conditions grown from a
face whose realizable faces all lie in the region (then irredundant), with relations ``>``,
``>=`` and ``=`` and rational coefficients in the slice coordinates.  Everything is exact; the
cost grows with the number of faces (2^k modes, hyperplanes in n dimensions), so this is for
small systems and 2-D slices.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import combinations
from typing import Any, Sequence

from flint import fmpq, fmpq_mat

from ..errors import NotAutonomous, ShapeError, Unsupported
from ..interfaces import SystemLike
from ..modes import format_mode, latex_mode, mode_order
from ..display import plot_mode_map
from ..algebra import find_point
from ..algebra import hstack, identity, to_fmpq, to_vector, zeros
from ..modes import admissibility_forms
from ..algebra import kernel, rank

__all__ = ["mode_map", "ModeMap", "Region", "Inequality", "Face", "MAX_PAIRS"]

#: mode maps enumerate all 2^k modes; refuse beyond this k
MAX_PAIRS = 8

_ALL = frozenset((-1, 0, 1))


@dataclass(frozen=True)
class Inequality:
    """``sum_i coefficients[i] * z_i + constant  relation  0`` with ``relation`` in ``>``, ``>=``, ``=``.

    ``variables`` names the coordinates z_i (state names, or slice coordinates s_i).

    >>> q = Inequality((fmpq(1), fmpq(-2)), fmpq(1), ">=", ("a", "b"))
    >>> str(q), q.holds([1, 1]), q.holds([0, 1])
    ('a - 2*b >= -1', True, False)
    """

    coefficients: tuple
    constant: Any
    relation: str
    variables: tuple

    def value(self, point: Sequence[Any]) -> fmpq:
        """The exact value of the affine form at ``point``."""
        return sum((c * to_fmpq(p) for c, p in zip(self.coefficients, point)), fmpq(0)) + self.constant

    def holds(self, point: Sequence[Any]) -> bool:
        """True iff the (rational) point satisfies the inequality, exactly."""
        v = self.value(point)
        return v == 0 if self.relation == "=" else v > 0 if self.relation == ">" else v >= 0

    def __str__(self):
        terms = []
        for c, name in zip(self.coefficients, self.variables):
            if c == 0:
                continue
            mag = "" if abs(c) == 1 else f"{abs(c)}*"
            terms.append((c < 0, f"{mag}{name}"))
        lhs = ("-" if terms[0][0] else "") + terms[0][1] if terms else "0"
        for neg, t in terms[1:]:
            lhs += (" - " if neg else " + ") + t
        return f"{lhs} {self.relation} {-self.constant}"

    def __repr__(self):
        return f"<Inequality {self}>"


@dataclass(frozen=True)
class Face:
    """A face of the arrangement: its sign vector, a rational point in it and its dimension."""

    signs: tuple
    point: tuple
    dimension: int


@dataclass(frozen=True)
class Region:
    """The set of points (of the map's coordinates) where S(x0) equals ``modes``.

    ``mode`` is the mode the simulation selects there (the smallest of S(x0), Remark 4.8; None
    when S(x0) is empty, a deadlock); ``jump`` is its projection P_I (n x n, x(0+) = P_I x0,
    section 4.2; None for a deadlock).  ``inequalities``: a tuple of conjunctions (tuples of
    :class:`Inequality`); the region is their union.  ``faces``: the faces of the arrangement
    that make it up; ``dimension``: the largest face dimension.  ``unique_jump``: every mode
    of S(x0) gives the same x(0+) on the region (Theorem 6.10 makes it so when N is a P-matrix;
    otherwise the choice of mode matters and simulate reports IllPosed).

    Attributes
    ----------
    modes : frozenset of frozenset
        S(x0) on the region (section 4).
    mode : frozenset or None
        The selected mode (above).
    jump : fmpq_mat or None
        P_I (above).
    inequalities : tuple of tuple of Inequality
        A union of conjunctions (above).
    faces : tuple of Face
    dimension : int
    unique_jump : bool
    """

    modes: frozenset
    mode: frozenset | None
    jump: fmpq_mat | None
    inequalities: tuple
    faces: tuple
    dimension: int
    unique_jump: bool = True

    def contains(self, point: Sequence[Any]) -> bool:
        """True iff the rational point (map coordinates) lies in the region, by its inequalities.

        Parameters
        ----------
        point : sequence of rationals
            A point in the map's coordinates.

        >>> from lcs_exact.examples import two_carts
        >>> mm = two_carts().mode_map(slice=([0, 0, 0, 0], [[1, 0, 0, 0], [0, 0, 1, 0]]))
        >>> [r.contains([0, 0]) for r in mm.regions]   # only the origin's region
        [False, False, True]
        """
        return any(all(q.holds(point) for q in conj) for conj in self.inequalities)

    @property
    def label(self) -> str:
        """S(x0) as text: ``{0}``, ``{0} | {0, 1}`` (several admissible modes), ``none``."""
        return " | ".join(format_mode(m) for m in _sorted_modes(self.modes)) if self.modes else "none (deadlock)"

    def describe(self) -> str:
        """The inequalities as text: conjunctions joined by ``or``."""
        parts = [" and ".join(str(q) for q in conj) or "everywhere" for conj in self.inequalities]
        return " or ".join(f"({p})" if len(self.inequalities) > 1 else p for p in parts)

    def __repr__(self):
        sel = "" if self.mode is None else f", jump P_{format_mode(self.mode)}"
        return f"<Region S = {self.label} (dim {self.dimension}){sel}: {self.describe()}>"

    def _repr_latex_(self):
        if sum(len(c) for c in self.inequalities) > 40:
            return None
        modes = r",\ ".join(latex_mode(m) for m in _sorted_modes(self.modes)) or r"\emptyset"
        conj = [r" \wedge ".join(_latex_ineq(q) for q in c) or r"\text{everywhere}" for c in self.inequalities]
        return rf"$S(x_0) = \{{{modes}\}}:\quad " + r" \ \vee\ ".join(f"({c})" for c in conj) + "$"


def _latex_ineq(q: Inequality) -> str:
    rel = {">": ">", ">=": r"\ge", "=": "="}[q.relation]
    txt = str(q).rsplit(f" {q.relation} ", 1)[0]
    return f"{txt} {rel} {-q.constant}".replace("*", r"\,")


def _sorted_modes(modes) -> list:
    return sorted(modes, key=mode_order)


class ModeMap:
    """The exact partition of a slice of the state space by S(x0) (see the module docstring).

    Attributes: ``lcs``; ``base`` (n x 1) and ``directions`` (n x d) of the slice (identity
    for the whole space); ``variables`` (names of the d coordinates); ``hyperplanes`` (the
    distinct affine forms (a, b), a . s + b, that decide S); ``faces``; ``regions`` (sorted
    by decreasing dimension, then by mode).

    Parameters
    ----------
    lcs : LCS
    base : fmpq_mat
        n x 1, the slice's origin.
    directions : fmpq_mat
        n x d, the slice's directions.
    variables : tuple of str
        The names of the d coordinates.
    hyperplanes : tuple of (tuple, fmpq)
        The affine forms (a, b) that decide S.
    faces : tuple of Face
    regions : tuple of Region
    face_region : dict
        Maps a face's sign vector to its region.
    """

    def __init__(self, lcs: SystemLike, base: fmpq_mat, directions: fmpq_mat, variables: tuple,
                 hyperplanes: tuple, faces: tuple, regions: tuple, face_region: dict):
        self.lcs, self.base, self.directions, self.variables = lcs, base, directions, variables
        self.hyperplanes, self.faces, self.regions = hyperplanes, faces, regions
        self._face_region = face_region

    @property
    def dimension(self) -> int:
        """d, the number of slice coordinates."""
        return self.directions.ncols()

    def state(self, point: Sequence[Any]) -> fmpq_mat:
        """x0 = base + sum_i s_i d_i for the map coordinates s (exact, n x 1).

        Parameters
        ----------
        point : sequence of rationals
            The map coordinates s.
        """
        s = to_vector(point, self.dimension, "point")
        return self.base + self.directions * s

    def signs(self, point: Sequence[Any]) -> tuple:
        """The sign vector of the point (map coordinates) on the hyperplanes.

        Parameters
        ----------
        point : sequence of rationals
            A point in the map's coordinates.
        """
        s = [to_fmpq(v, "point") for v in _flat(point, self.dimension)]
        return tuple(_sign(sum((ai * si for ai, si in zip(a, s)), fmpq(0)) + b) for a, b in self.hyperplanes)

    def locate(self, point: Sequence[Any]) -> Region:
        """The region containing the rational point (in the map's coordinates: s for a slice).

        Parameters
        ----------
        point : sequence of rationals
            A point in the map's coordinates.

        >>> from lcs_exact.examples import two_carts
        >>> mm = two_carts().mode_map(slice=([0, 0, 0, 0], [[1, 0, 0, 0], [0, 0, 1, 0]]))
        >>> mm.locate([0, -1]).label, mm.locate([1, -1]).label
        ('{0}', '∅')
        """
        return self._face_region[self.signs(point)]

    def admissible(self, mode: Any) -> tuple:
        """The regions where ``mode`` is in S(x0) (their union is where the mode may be entered).

        Parameters
        ----------
        mode : iterable of int
            A mode (0-based indices).
        """
        I = frozenset(mode)
        return tuple(r for r in self.regions if I in r.modes)

    def slice_jump(self, region: Region) -> tuple | None:
        """The jump P x0 - x0 in slice coordinates on ``region``: (c0, C1, exact).

        For x0 = base + D s, P x0 - x0 = (P - I)(base + D s); its least-squares coordinates in
        the directions are c0 + C1 s (c0: d x 1, C1: d x d, exact rationals).  ``exact`` is True
        iff the jump stays in the slice (then c0 + C1 s is the jump itself).  None for a deadlock.

        Parameters
        ----------
        region : Region
            A region of this map.
        """
        if region.jump is None:
            return None
        D, n = self.directions, self.lcs.n
        J0 = (region.jump - identity(n)) * self.base
        J1 = (region.jump - identity(n)) * D
        G = D.transpose() * D
        c0, C1 = G.solve(D.transpose() * J0), G.solve(D.transpose() * J1)
        exact = (D * c0 == J0) and (D * C1 == J1)
        return c0, C1, exact

    def plot(self, ax=None, **kw):
        """Draw a 2-D map (regions filled and labelled, jump arrows); see plotting.plot_mode_map.

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Where to draw (None: a new figure).
        **kw
            Passed on to :func:`~lcs_exact.plotting.plot_mode_map` (``window``, ``arrows``, ...).
        """
        return plot_mode_map(self, ax=ax, **kw)

    def __repr__(self):
        return (f"<ModeMap of {self.lcs.name or 'LCS'} on {'the state space' if self._whole() else 'a slice'} "
                f"({', '.join(self.variables)}): {len(self.regions)} regions, {len(self.hyperplanes)} "
                f"hyperplanes, {len(self.faces)} faces>")

    def __str__(self):
        lines = [repr(self)] + [f"  S = {r.label} (dim {r.dimension}): {r.describe()}" for r in self.regions]
        return "\n".join(lines)

    def _whole(self) -> bool:
        return self.base == zeros(self.lcs.n, 1) and self.directions == identity(self.lcs.n)


def _flat(point, d):
    if isinstance(point, fmpq_mat):
        return [point[i, 0] for i in range(point.nrows())] if point.ncols() == 1 else [point[0, j] for j in range(point.ncols())]
    pts = list(point)
    if len(pts) != d:
        raise ShapeError(f"point has length {len(pts)}, expected {d} (the map's coordinates)")
    return pts


def _sign(v) -> int:
    return (v > 0) - (v < 0)


def _canonical(vals: list[fmpq]) -> tuple[tuple, int] | None:
    """The primitive integer vector on the ray of vals (first nonzero entry positive) and the
    sign s with vals = s * (positive multiple); None for the zero vector."""
    if all(v == 0 for v in vals):
        return None
    den = 1
    for v in vals:
        den = den * int(v.q) // math.gcd(den, int(v.q))
    ints = [int((v * den).p) for v in vals]
    g = 0
    for i in ints:
        g = math.gcd(g, abs(i))
    ints = [i // g for i in ints]
    s = 1 if next(i for i in ints if i != 0) > 0 else -1
    return tuple(fmpq(s * i) for i in ints), s


def _slice(lcs: SystemLike, slice_) -> tuple[fmpq_mat, fmpq_mat, tuple]:
    n = lcs.n
    if slice_ is None:
        return zeros(n, 1), identity(n), tuple(lcs.state_names)
    if not isinstance(slice_, (tuple, list)) or len(slice_) not in (2, 3):
        raise ShapeError("slice must be (base, directions) or (base, directions, names)")
    base = to_vector(slice_[0], n, "slice base")
    dirs = list(slice_[1])
    if not dirs:
        raise ShapeError("slice needs at least one direction")
    D = hstack(*[to_vector(d, n, f"slice direction {i}") for i, d in enumerate(dirs)])
    if rank(D) < D.ncols():
        raise ShapeError(f"the {D.ncols()} slice directions are linearly dependent")
    if len(slice_) == 3:
        names = tuple(slice_[2])
        if len(names) != D.ncols() or len(set(names)) != len(names) or not all(isinstance(x, str) and x for x in names):
            raise ShapeError(f"slice names must be {D.ncols()} distinct nonempty strings, got {names!r}")
        return base, D, names
    names = []
    for i in range(D.ncols()):
        col = [D[r, i] for r in range(n)]
        nz = [r for r in range(n) if col[r] != 0]
        # a coordinate along e_j through base_j = 0 is x_j itself: use the state's name
        if len(nz) == 1 and col[nz[0]] == 1 and base[nz[0], 0] == 0:
            names.append(lcs.state_names[nz[0]])
        else:
            names.append(f"s_{i}")
    if len(set(names)) != len(names):
        names = [f"s_{i}" for i in range(D.ncols())]
    return base, D, tuple(names)


def mode_map(lcs: SystemLike, slice: Any = None) -> ModeMap:
    """The exact partition of the state space, or of an affine slice, by S(x0) (section 5).

    Parameters
    ----------
    lcs : LCS
        Every mode must be autonomous (Assumption 4.1); k <= ``MAX_PAIRS``.
    slice : (base, directions) or (base, directions, names), optional
        The affine slice {base + sum_i s_i d_i}; regions are then described in the coordinates
        s (named after the state when d_i = e_j and base_j = 0, else ``s_i``).

    Returns
    -------
    ModeMap

    Examples
    --------
    Figure 8.2 (the hook, x1 = x2 = 0; the paper's x3, x4 are the velocities q_0', q_1'):

    >>> from lcs_exact.examples import two_carts_with_hook
    >>> mm = mode_map(two_carts_with_hook(), slice=([0, 0, 0, 0], [[0, 0, 1, 0], [0, 0, 0, 1]]))
    >>> print(mm.locate([-1, -1]))
    <Region S = {0} (dim 2), jump P_{0}: -q_0' >= 0 and -q_1' > 0>
    """
    if lcs.k > MAX_PAIRS:
        raise Unsupported(f"mode_map enumerates the 2^k modes; k = {lcs.k} > {MAX_PAIRS} is too many")
    base, D, names = _slice(lcs, slice)
    d = D.ncols()
    modes = [frozenset(c) for r in range(lcs.k + 1) for c in combinations(range(lcs.k), r)]
    planes: dict[tuple, int] = {}
    plane_list: list[tuple] = []
    rows_of: dict[frozenset, list] = {}
    for I in modes:
        try:
            rows = admissibility_forms(lcs.mode(I))
        except NotAutonomous as e:
            raise NotAutonomous(f"the mode map needs every mode autonomous (Assumption 4.1): {e}") from None
        terms_rows = []
        for row in rows:
            terms = []
            for f in row:
                a, b = f * D, (f * base)[0, 0]
                vals = [a[0, j] for j in range(d)] + [b]
                can = _canonical(vals)
                if can is None:
                    terms.append(("c", 0))
                elif all(v == 0 for v in vals[:d]):
                    terms.append(("c", _sign(b)))
                else:
                    key, s = can
                    if key not in planes:
                        planes[key] = len(plane_list)
                        plane_list.append(key)
                    terms.append(("h", planes[key], s))
            terms_rows.append(terms)
        rows_of[I] = terms_rows
    hyperplanes = tuple((key[:d], key[d]) for key in plane_list)
    faces = _enumerate_faces(d, hyperplanes)

    def selected(signs: tuple) -> frozenset:
        out = []
        for I in modes:
            ok = True
            for terms in rows_of[I]:
                lex = 0
                for t in terms:
                    lex = t[1] if t[0] == "c" else t[2] * signs[t[1]]
                    if lex:
                        break
                if lex < 0:
                    ok = False
                    break
            if ok:
                out.append(I)
        return frozenset(out)

    by_value: dict[frozenset, list[Face]] = {}
    value_of: dict[tuple, frozenset] = {}
    for f in faces:
        S = selected(f.signs)
        value_of[f.signs] = S
        by_value.setdefault(S, []).append(f)
    regions = []
    face_region: dict[tuple, Region] = {}
    for S, fs in by_value.items():
        conj = _cover(S, fs, faces, value_of, hyperplanes, names)
        mode = min(S, key=mode_order) if S else None
        jump = lcs.mode(mode).projection() if mode is not None else None
        unique = all(_agree_on(lcs.mode(I).projection(), jump, base, D, fs, hyperplanes) for I in S if I != mode)
        reg = Region(S, mode, jump, conj, tuple(fs), max(f.dimension for f in fs), unique)
        regions.append(reg)
        for f in fs:
            face_region[f.signs] = reg
    regions.sort(key=lambda r: (-r.dimension, len(r.modes), [sorted(m) for m in _sorted_modes(r.modes)]))
    return ModeMap(lcs, base, D, names, hyperplanes, tuple(faces), tuple(regions), face_region)


def _agree_on(P: fmpq_mat, Q: fmpq_mat, base: fmpq_mat, D: fmpq_mat, faces: list[Face],
              hyperplanes: tuple) -> bool:
    """P x0 = Q x0 on every face, exactly: on the face's affine hull s = point + K t (K spans the
    kernel of the face's equalities), i.e. (P - Q)(base + D point) = 0 and (P - Q) D K = 0."""
    d = D.ncols()
    R = P - Q
    for f in faces:
        s = fmpq_mat(d, 1, list(f.point))
        if R * (base + D * s) != zeros(R.nrows(), 1):
            return False
        eq = [hyperplanes[j][0] for j, sg in enumerate(f.signs) if sg == 0]
        K = kernel(fmpq_mat(len(eq), d, [v for row in eq for v in row])) if eq else identity(d)
        if K.ncols() and R * D * K != zeros(R.nrows(), K.ncols()):
            return False
    return True


def _constraint(a: tuple, b: fmpq, sign: int) -> tuple:
    if sign == 0:
        return (list(a), b, "=")
    return ([sign * v for v in a], sign * b, ">")


def _enumerate_faces(d: int, hyperplanes: tuple) -> list[Face]:
    """All realizable sign vectors, hyperplane by hyperplane, each with an exact witness point."""
    partial = [((), [], tuple(fmpq(0) for _ in range(d)))]
    for a, b in hyperplanes:
        nxt = []
        for signs, cons, p in partial:
            at_p = _sign(sum((ai * pi for ai, pi in zip(a, p)), fmpq(0)) + b)
            for s in (-1, 0, 1):
                c = _constraint(a, b, s)
                q = p if s == at_p else find_point(d, cons + [c])
                if q is not None:
                    nxt.append((signs + (s,), cons + [c], q))
        partial = nxt
    faces = []
    for signs, cons, p in partial:
        eq = [c[0] for c in cons if c[2] == "="]
        r = rank(fmpq_mat(len(eq), d, [v for row in eq for v in row])) if eq and d else 0
        faces.append(Face(signs, p, d - r))
    return faces


def _hull(boxes_or_signs) -> tuple:
    """The smallest sign box containing the given sign vectors / boxes: per coordinate the union
    of the signs, closed to 'any sign' when both strict signs occur (a segment from one side of
    a hyperplane to the other crosses it)."""
    out = None
    for b in boxes_or_signs:
        b = tuple(x if isinstance(x, frozenset) else frozenset((x,)) for x in b)
        out = b if out is None else tuple(p | q for p, q in zip(out, b))
    return tuple(_ALL if (1 in al and -1 in al) else al for al in out)


def _inside(signs: tuple, box: tuple) -> bool:
    return all(s in al for s, al in zip(signs, box))


def _mask(box_or_signs) -> int:
    """Bit 3j + (s + 1) set for each sign s allowed at hyperplane j (one bit per j for a face):
    a face lies in a box iff face_mask & ~box_mask == 0 (one integer operation, not m tests)."""
    out = 0
    for j, al in enumerate(box_or_signs):
        for sg in (al if isinstance(al, frozenset) else (al,)):
            out |= 1 << (3 * j + sg + 1)
    return out


def _cover(S: frozenset, own: list[Face], faces: list[Face], value_of: dict, hyperplanes: tuple,
           names: tuple) -> tuple:
    """Conjunctions of sign conditions whose realizable faces all have S(x0) = S, covering ``own``.

    A conjunction is a sign box (per hyperplane: >, <, =, >=, <= or no condition).  Each is
    grown from an uncovered face of largest dimension by adding faces of the region while the
    box hull of the added faces admits only faces of the region (the whole region first: a
    convex region gives one conjunction).  Conditions implied by the others (relaxing them
    admits no further face) are then dropped, the most complicated hyperplanes first, so the
    conjunction is irredundant.
    """
    order = sorted(own, key=lambda f: -f.dimension)
    masks = [(_mask(f.signs), value_of[f.signs] == S, f.signs) for f in faces]
    foreign = [m for m, mine, _ in masks if not mine]

    def valid(box) -> bool:
        bm = ~_mask(box)
        return not any(m & bm == 0 for m in foreign)

    def members(box) -> list:
        bm = ~_mask(box)
        return [sg for m, _, sg in masks if m & bm == 0]

    covered: set[tuple] = set()
    boxes = []
    whole = _hull(f.signs for f in own)
    if valid(whole):
        boxes.append(whole)
        covered = {f.signs for f in own}
    for seed in order:
        if seed.signs in covered:
            continue
        box = _hull([seed.signs])
        grown = True
        while grown:
            grown = False
            for f in order:
                if not _inside(f.signs, box):
                    trial = _hull([box, f.signs])
                    if valid(trial):
                        box, grown = trial, True
        boxes.append(box)
        covered |= set(members(box))
    height = [sum(abs(int(v.p)) for v in a) + abs(int(b.p)) for a, b in hyperplanes]
    out = []
    for box in boxes:
        box = list(box)
        count = len(members(box))
        for j in sorted(range(len(box)), key=lambda j: -height[j]):
            for loose in (_ALL, *(frozenset((0, s)) for s in (1, -1) if box[j] == frozenset((s,)))):
                if box[j] == loose:
                    continue
                trial = box[:j] + [loose] + box[j + 1:]
                if len(members(trial)) == count:
                    box = trial
                    break
        out.append(tuple(_conditions(box, hyperplanes, names)))
    return tuple(out)


def _conditions(box, hyperplanes, names) -> list[Inequality]:
    conj = []
    for j, al in enumerate(box):
        if al == _ALL:
            continue
        a, b = hyperplanes[j]
        if al == frozenset((0,)):
            conj.append(Inequality(tuple(a), b, "=", names))
        elif len(al) == 1:
            s = next(iter(al))
            conj.append(Inequality(tuple(s * v for v in a), s * b, ">", names))
        else:
            s = 1 if 1 in al else -1
            conj.append(Inequality(tuple(s * v for v in a), s * b, ">=", names))
    return conj
