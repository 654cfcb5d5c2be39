"""Mode selection (section 5): RCP(x0), LDCP_kappa(x0), S(x0), the initial solution, regularity.

Everything here is computed as *linear forms in the state*: for a mode I,

    u_I(s) = W_I(s) x0,   W_I = -G_II(s)^{-1} R_I.(s),
    y_Ic(s) = Z_I(s) x0,  Z_I = R_Ic.(s) + G_IcI(s) W_I(s)              (section 5.2)

so the Laurent coefficients at s = oo (5.6) are rational row vectors (forms) that depend on the
mode only and are cached on it.  A state enters only through
:func:`~lcs_exact.rational.sign_of_form` (exact for rational states; certified or refused for
exact-real states).  The same holds for LDCP_kappa: the unique solution of Theorems 6.9-6.10 is
built as forms by a sequence of LCPs on Schur complements of N, each solved by Murty's method
on forms.

Modes that are not autonomous (Assumption 4.1 fails, Lemma 3.3: G_II(s) singular) are decided
exactly as well: RCP(x0) in such a mode is an affine family of u_I(s) over Q(s), and
:mod:`lcs_exact.rcpfamily` decides whether some member satisfies the sign conditions (consistency
of G_II u_I = -R_I x0, then Fourier-Motzkin over the ordered field Q(s)).  A mode that is never
admissible (the relay LCS of :mod:`lcs_exact.relays`) no longer blocks selection.  When such a
mode *is* admissible, its initial solution is not unique.  If only inputs that do nothing to the
state are free (a *state-determined* mode, :attr:`~lcs_exact.modes.Mode.is_state_determined`:
a floating diode bridge whose four diodes block) and every admissible mode gives the same state
(:func:`state_groups`: equal B u(s), so equal x(s)), the state is unique and the run goes on;
the inputs that differ or are free are *undetermined* (:func:`undetermined_inputs`).  Otherwise
the continuation is not defined: :func:`select_modes` raises
:class:`~lcs_exact.errors.NotAutonomous` unless asked to ``include`` such modes.

Results: :func:`rcp` -> list of :class:`RCPSolution`; :func:`ldcp` -> :class:`LDCPSolution`;
:func:`select_modes` -> S(x0), a set of frozensets; :func:`initial_solution` ->
:class:`InitialSolution` (impulse u^{-i} and x(0+) = x0 + sum A^i B u^{-i} (3.8), checked equal
to P_I x0).
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Any

from flint import fmpq_mat

from ..errors import Deadlock, InvalidArgument, LCSError, NotAutonomous
from ..interfaces import SystemLike
from .mode import LATEX_MAX_N, format_mode, latex_mode, mode_order
from .rcpfamily import family, row_series
from .ldcp import LDCPSolution, impulse_forms, ldcp, ldcp_modes
from ..algebra import RationalFunction, RationalMatrix
from ..algebra import (check_enumerable, identity, is_zero, lex_sign, sign_of_form,
                       submatrix, zeros)
from ..numbers import ProjectedVector, as_state

__all__ = ["as_state", "rcp", "RCPSolution", "ldcp", "ldcp_modes", "LDCPSolution", "select_modes",
           "initial_solution", "InitialSolution", "is_regular", "mode_admissible", "rcp_data", "RCPData", "impulse_forms",
           "admissibility_forms", "admissibility_conditions", "NONAUTONOMOUS", "state_response",
           "state_groups", "undetermined_inputs"]

#: what :func:`select_modes` may do when a mode that is not autonomous is admissible at x0
NONAUTONOMOUS = ("raise", "include")


def _apply(P: fmpq_mat, x):
    """P x: rational for a rational x, else an exact vector."""
    q = x.known_rational()
    return P * q if q is not None else ProjectedVector(P, x)


# ---------------------------------------------------------------------------------------------
# RCP (5.3)-(5.5)
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RCPData:
    """The RCP data of an autonomous mode I (5.3)-(5.5), computed once per mode: ``W`` = W_I(s)
    (u_I(s) = W_I(s) x0), ``Z`` = Z_I(s) (y_Ic(s) = Z_I(s) x0), ``u`` and ``y`` their rows'
    Laurent series at s = oo (forms in x0, for the lexicographic signs), and ``impulse``,
    impulse[p] the k x n forms of u^{-p} (the coefficient of s^p in u(s), (3.6))."""

    W: RationalMatrix
    Z: RationalMatrix
    u: tuple
    y: tuple
    impulse: tuple


def rcp_data(mode) -> RCPData:
    """The :class:`RCPData` of mode I (cached on the mode).

    Parameters
    ----------
    mode : Mode
        A mode I of the LCS (``lcs.mode(I)``).
    """
    if mode.derived.rcp is None:
        mode.derived.rcp = _build_rcp_data(mode)
    return mode.derived.rcp


def _build_rcp_data(mode) -> RCPData:
    mode.require_autonomous()
    lcs = mode.lcs
    G, R = lcs.G(), lcs.R()
    I, Ic, n = mode.I, mode.Ic, lcs.n
    if I:
        W = -(G.sub(I, I).solve(R.sub(I, range(n))))
        Z = R.sub(Ic, range(n)) + G.sub(Ic, I) * W if Ic else RationalMatrix([])
    else:
        W = RationalMatrix([])
        Z = R
    u_rows = [row_series(W, r) for r in range(len(I))]
    y_rows = [row_series(Z, r) for r in range(len(Ic))]
    # impulse u^{-p} (coefficient of s^p in u(s)) as k x n forms, p = 0..n-1
    imp = [zeros(lcs.k, n) for _ in range(n)]
    for r, i in enumerate(I):
        for c in range(n):
            poly = W[r, c].polynomial_part().coeffs()
            for p, v in enumerate(poly):
                if p >= n:
                    raise LCSError(f"internal inconsistency: u(s) of mode {format_mode(I)} has "
                                   f"polynomial degree {p} >= n")
                imp[p][i, c] = v
    return RCPData(W, Z, tuple(u_rows), tuple(y_rows), tuple(imp))


def mode_admissible(mode, x) -> bool:
    """I in S_RCP(x0) (5.5): u_I(s) >= 0 and y_Ic(s) >= 0 for all large s (5.4), exactly.

    An autonomous mode: the lexicographic signs of the unique u_I(s) = W_I(s) x0 and
    y_Ic(s) = Z_I(s) x0.  A mode that is not autonomous: some member of the affine family of
    solutions of G_II(s) u_I = -R_I.(s) x0 satisfies the signs (:mod:`lcs_exact.rcpfamily`: the
    equations must be consistent at x0, then Fourier-Motzkin over Q(s) ordered at s = +oo).

    >>> from lcs_exact import LCS
    >>> lazy = LCS([[0]], [[1]], [[0]], [[0]])     # x' = u, y = 0: mode {0} is not autonomous
    >>> from lcs_exact.rational import to_vector
    >>> mode_admissible(lazy.mode({0}), to_vector([1], 1))   # any u >= 0 solves RCP(x0)
    True
    """
    if not mode.is_autonomous:
        return family(mode).admissible(x)
    data = rcp_data(mode)
    return all(r.sign(x) >= 0 for r in data.u) and all(r.sign(x) >= 0 for r in data.y)


def admissibility_forms(mode) -> tuple:
    """The linear forms that decide I in S(x0) (5.4), (5.6)-(5.7), Lemma 5.1.

    Returns one entry per row of u_I(s) = W_I(s) x0 (i in I, in increasing order) followed by
    one per row of y_Ic(s) = Z_I(s) x0 (i not in I): a tuple of 1 x n ``fmpq_mat`` forms
    (f_1, f_2, ...), the Laurent coefficients at s = oo of that row.  I is in S(x0) iff every
    entry is lexicographically nonnegative at x0 (the first nonzero f_j . x0 is positive, or
    all vanish).  Requires the mode to be autonomous (Assumption 4.1).

    Parameters
    ----------
    mode : Mode
        A mode I of the LCS (``lcs.mode(I)``). (autonomous).

    Examples
    --------
    >>> from lcs_exact import LCS
    >>> carts = LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]], [[0], [0], [1], [0]],
    ...             [[1, 0, 0, 0]], [[0]])
    >>> [[str(f) for f in row] for row in admissibility_forms(carts.mode(()))]  # y(s) = R(s) x0
    [['[1, 0, 0, 0]', '[0, 0, 1, 0]', '[-2, 1, 0, 0]', '[0, 0, -2, 1]']]
    """
    data = rcp_data(mode)
    return tuple(r.forms for r in data.u) + tuple(r.forms for r in data.y)


def admissibility_conditions(mode) -> tuple[tuple, tuple]:
    """(equalities, inequalities) in x0 with I in S_RCP(x0) iff both hold, for any mode.

    Each equality is a tuple of 1 x n forms that must all vanish at x0 (consistency of
    G_II(s) u_I = -R_I.(s) x0; none for an autonomous mode); each inequality is a tuple of
    Laurent forms (f_1, f_2, ...) that must be lexicographically nonnegative at x0: for an
    autonomous mode the rows of :func:`admissibility_forms`, otherwise the rows left by
    Fourier-Motzkin elimination of the free inputs (:mod:`lcs_exact.rcpfamily`).

    Parameters
    ----------
    mode : Mode
        A mode I of the LCS (``lcs.mode(I)``).

    Examples
    --------
    >>> from lcs_exact import LCS
    >>> lazy = LCS([[0]], [[1]], [[0]], [[0]])
    >>> admissibility_conditions(lazy.mode({0}))     # G_II = 0 and R_I = 0: always admissible
    ((), ())
    """
    if mode.is_autonomous:
        return (), admissibility_forms(mode)
    return family(mode).conditions()


@dataclass(frozen=True)
class RCPSolution:
    """A solution (u(s), y(s)) of RCP(x0) in mode I (u_Ic = 0, y_I = 0), for a rational x0.

    ``unique`` is False for a mode that is not autonomous: (u, y) is then one member of an
    affine family of solutions (:meth:`lcs_exact.rcpfamily.RCPFamily.solution`).
    """

    mode: frozenset
    u: tuple  # k RationalFunction
    y: tuple  # k RationalFunction
    unique: bool = True

    @property
    def is_strictly_proper(self) -> bool:
        """True iff the initial solution is smooth (no impulse, Def. 6.7)."""
        return all(f.is_strictly_proper() for f in self.u)

    def __repr__(self):
        us = ", ".join(str(f) for f in self.u)
        ys = ", ".join(str(f) for f in self.y)
        extra = "" if self.unique else ", unique=False"
        return f"RCPSolution(mode={format_mode(self.mode)}, u(s)=({us}), y(s)=({ys}){extra})"

    def _repr_latex_(self):
        import sympy
        if len(self.u) > LATEX_MAX_N:
            return None
        u = sympy.latex(sympy.Matrix([f.to_sympy() for f in self.u]))
        y = sympy.latex(sympy.Matrix([f.to_sympy() for f in self.y]))
        name = latex_mode(self.mode)
        return rf"$I = {name}:\ u(s) = {u},\ y(s) = {y}$"


def _all_modes(k: int):
    check_enumerable(k, "RCP for every mode")  # at once, not on the first next()
    return _subsets(k)


def _subsets(k: int):
    for r in range(k + 1):
        for c in combinations(range(k), r):
            yield frozenset(c)


def rcp(lcs: SystemLike, x0: Any) -> list[RCPSolution]:
    """All solutions of RCP(x0), one per admissible mode (5.3)-(5.5), for a rational x0.

    Enumerates the 2^k modes; for small k.  In an autonomous mode the solution is unique; in an
    admissible mode that is not autonomous one member of the family is shown, with
    ``unique=False``.

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational.

    Examples
    --------
    >>> from lcs_exact import LCS
    >>> LCS([[0]], [[1]], [[1]], [[-1]]).rcp([1])     # x' = u, y = x - u
    [RCPSolution(mode=∅, u(s)=(0), y(s)=(1/s)), RCPSolution(mode={0}, u(s)=(1/(s - 1)), y(s)=(0))]
    """
    x = as_state(lcs, x0)
    q = x.known_rational()
    if q is None:
        raise InvalidArgument("rcp() displays u(s), y(s) for a rational x0; use select_modes for exact states")
    out = []
    for I in _all_modes(lcs.k):
        mode = lcs.mode(I)
        if mode_admissible(mode, x):
            if mode.is_autonomous:
                data = rcp_data(mode)
                uI, yIc = data.W.apply(q), data.Z.apply(q)
            else:
                uI, yIc = family(mode).solution(q)
            u = [RationalFunction(0)] * lcs.k
            y = [RationalFunction(0)] * lcs.k
            for r, i in enumerate(mode.I):
                u[i] = uI[r]
            for r, i in enumerate(mode.Ic):
                y[i] = yIc[r]
            out.append(RCPSolution(I, tuple(u), tuple(y), mode.is_autonomous))
    return out


# ---------------------------------------------------------------------------------------------
# S(x0), the initial solution, regular states
# ---------------------------------------------------------------------------------------------


def select_modes(lcs: SystemLike, x0: Any, method: str = "auto", *, nonautonomous: str = "raise") -> set:
    """S(x0) = S_RCP(x0) = S_LDCP^oo(x0) (Theorem 5.2), a set of frozensets (0-based).

    ``"ldcp"``: LDCP_n(x0) by the LCP sequence (Theorem 6.10; needs N to be a P-matrix): the
    unique initial solution evolves in mode I, and S(x0) = {I ∪ K' : K' ⊆ K} with K the indices
    whose u and y vanish (Remarks 4.8, 6.11).  ``"rcp"``: every mode I is tested by the
    lexicographic signs of u_I(s), y_Ic(s) (5.4), :func:`mode_admissible`.  ``"auto"``: LDCP
    when N is a P-matrix (then every mode is autonomous, Lemma 6.6), RCP otherwise.

    Modes that are not autonomous are decided exactly by RCP (S_RCP(x0) of (5.5) does not need
    Assumption 4.1), so one that is never admissible does not block selection.  If one is
    admissible at x0, RCP(x0) has a family of solutions in it (u_I is determined only up to
    Ker G_II(s)), the initial solution is not unique (Definition 3.2), and the continuation of
    Definitions 4.2 and 4.10 (theta, P_I, F_I) is not defined in it; Theorem 5.2 and the rest
    of the paper assume Assumption 4.1.  ``nonautonomous="raise"`` (default) then raises
    :class:`~lcs_exact.errors.NotAutonomous` naming the mode and x0; ``"include"`` returns
    S_RCP(x0) with such modes in it (the caller must not continue in them).

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    method : {"auto", "ldcp", "rcp"}, optional
        How S(x0) is computed (above).
    nonautonomous : {"raise", "include"}, optional
        What an admissible mode that is not autonomous does (above).

    Examples
    --------
    >>> from lcs_exact import LCS
    >>> carts = LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]], [[0], [0], [1], [0]],
    ...             [[1, 0, 0, 0]], [[0]])
    >>> carts.select_modes([0, -1, -1, 0])
    {frozenset({0})}
    """
    if method not in ("auto", "rcp", "ldcp"):
        raise InvalidArgument(f"method must be 'auto', 'rcp' or 'ldcp', got {method!r}")
    if nonautonomous not in NONAUTONOMOUS:
        raise InvalidArgument(f"nonautonomous must be 'raise' or 'include', got {nonautonomous!r}")
    x = as_state(lcs, x0)
    if method == "ldcp" or (method == "auto" and lcs.well_posedness().N_is_P):
        return ldcp_modes(lcs, x)
    S = {I for I in _all_modes(lcs.k) if mode_admissible(lcs.mode(I), x)}
    bad = sorted((I for I in S if not lcs.mode(I).is_autonomous), key=mode_order)
    if bad and nonautonomous == "raise":
        undetermined = [I for I in bad if not _state_determined(lcs.mode(I))]
        if undetermined or len(state_groups(lcs, x, S)) > 1:
            I0 = undetermined[0] if undetermined else bad[0]
            m = lcs.mode(I0)
            raise NotAutonomous(
                f"mode {format_mode(I0)} is not autonomous ({m.autonomy_reason}) and RCP(x0) has "
                f"solutions in it at x0 = {_fmt_state(x)} that differ in the state: u_I(s) is determined only "
                f"up to Ker G_II(s), so the state after x0 is not unique (Definition 3.2) and the continuation "
                f"(P_I, F_I; Definitions 4.2, 4.10) is not defined; S_RCP(x0) = "
                f"{sorted(format_mode(I) for I in S)} (select_modes(x0, nonautonomous='include'))")
    return S


@dataclass(frozen=True)
class InitialSolution:
    """The initial solution from x0 in mode I (Def. 4.7): impulse and re-initialized state.

    ``impulse[i]`` = u^{-i} (k-vector: coefficient of delta^{(i)}), ``state_after`` = x(0+)
    = x0 + sum_i A^i B u^{-i} (3.8) = P_I x0; ``smooth`` iff there is no impulse.
    ``mode`` is the smallest admissible mode {i : u_i != 0} (Remark 4.8); ``modes`` is S(x0).
    """

    mode: frozenset
    modes: frozenset
    impulse: dict
    state_after: Any
    smooth: bool

    def __repr__(self):
        return (f"<InitialSolution mode={format_mode(self.mode)} "
                f"{'smooth' if self.smooth else 'impulsive'} S={sorted(format_mode(m) for m in self.modes)}>")


def _jump_forms(lcs: SystemLike, impulse_forms: list[fmpq_mat]) -> fmpq_mat:
    """I + sum_i A^i B U^{-i}: the map x0 -> x(0+) of (3.8) for impulse forms U^{-i}."""
    out = identity(lcs.n)
    for i, u in enumerate(impulse_forms):
        if not is_zero(u):
            out = out + lcs.a_power_b(i) * u
    return out


def initial_solution(lcs: SystemLike, x0: Any, mode: Any = None) -> InitialSolution:
    """The initial solution from x0 in ``mode`` (default: the smallest mode of S(x0)).

    The impulse is the polynomial part of u_I(s) = W_I(s) x0; x(0+) from (3.8) is checked to be
    P_I x0 as an identity of matrices (it holds for every x0), so the check is exact also for
    exact-real states.  Raises :class:`~lcs_exact.errors.Deadlock` if S(x0) is empty.

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    mode : iterable of int, optional
        The mode I to continue in (a member of S(x0)); default the smallest.
    """
    x = as_state(lcs, x0)
    modes = select_modes(lcs, x)
    if not modes:
        raise Deadlock(f"S(x0) is empty: RCP(x0) has no solution at x0 = {_fmt_state(x)}")
    I = frozenset(mode) if mode is not None else min(modes, key=mode_order)
    if I not in modes:
        raise InvalidArgument(f"mode {format_mode(I)} is not in S(x0) = {sorted(format_mode(m) for m in modes)}")
    m = lcs.mode(I)
    data = rcp_data(m)
    jump = _jump_forms(lcs, data.impulse)
    P = m.projection()
    if jump != P:
        raise LCSError(f"internal inconsistency in mode {format_mode(I)}: x0 + sum A^i B u^(-i) != P_I x0")
    impulse = {i: _apply(u, x) for i, u in enumerate(data.impulse)}
    smooth = all(sign_of_form(submatrix(u, [r], None), x) == 0
                 for u in data.impulse for r in range(lcs.k))
    return InitialSolution(I, frozenset(modes), impulse, _apply(P, x), smooth)


def is_regular(lcs: SystemLike, x0: Any) -> bool:
    """Def. 6.7: x0 admits a smooth initial solution.

    With M a P-matrix, Theorem 6.8: iff (C_i x0, C_i A x0, ..., C_i A^{rho_i - 1} x0) is
    lexicographically nonnegative for every i.  Otherwise: some admissible mode has a strictly
    proper u(s).

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    """
    x = as_state(lcs, x0)
    wp = lcs.well_posedness()
    if wp.M_is_P:
        rho = lcs.leading_row_indices()
        for i in range(lcs.k):
            forms, row = [], submatrix(lcs.C, [i], None)
            for _ in range(rho[i]):
                forms.append(row)
                row = row * lcs.A
            if lex_sign(forms, x) < 0:
                return False
        return True
    for I in select_modes(lcs, x, method="rcp"):
        imp = rcp_data(lcs.mode(I)).impulse
        if all(sign_of_form(submatrix(u, [r], None), x) == 0 for u in imp for r in range(lcs.k)):
            return True
    return False


def _fmt_state(x) -> str:
    q = x.known_rational()
    if q is not None:
        return "(" + ", ".join(str(q[i, 0]) for i in range(q.nrows())) + ")"
    return repr(x)



# ---------------------------------------------------------------------------------------------
# non-uniqueness: which admissible modes carry the same initial solution (Remark 4.8)
# ---------------------------------------------------------------------------------------------


def _full_rcp_rows(mode) -> RationalMatrix:
    """[u(s); y(s)] of mode I as a 2k x n matrix over Q(s): rows W_I on I, Z_I on I^c, zero
    elsewhere (u_{I^c} = 0, y_I = 0), so that the initial solution's transforms are this times x0."""
    if mode.derived.rcp_rows is None:
        lcs, data = mode.lcs, rcp_data(mode)
        zero = [0] * lcs.n
        rows = [list(zero) for _ in range(2 * lcs.k)]
        for r, i in enumerate(mode.I):
            rows[i] = [data.W[r, c] for c in range(lcs.n)]
        for r, i in enumerate(mode.Ic):
            rows[lcs.k + i] = [data.Z[r, c] for c in range(lcs.n)]
        mode.derived.rcp_rows = RationalMatrix(rows)
    return mode.derived.rcp_rows


def same_initial_solution(lcs: SystemLike, x0: Any, I, J) -> bool:
    """True when the admissible modes I and J of S(x0) carry the same initial solution: the same
    u(s) and y(s) (Remark 4.8: the modes of one solution differ on its undetermined set only).
    Decided exactly: every Laurent numerator coefficient of the difference vanishes at x0
    (forms in x0; for an exact-real x0 through its certified signs)."""
    x = as_state(lcs, x0)
    D = _full_rcp_rows(lcs.mode(I)) - _full_rcp_rows(lcs.mode(J))
    for r in range(2 * lcs.k):
        coeffs, _ = D.row_forms(r)
        if any(sign_of_form(c, x) != 0 for c in coeffs):
            return False
    return True


def initial_solution_groups(lcs: SystemLike, x0: Any, modes) -> list[list[frozenset]]:
    """The modes of S(x0) grouped by initial solution (smallest modes first): one group means the
    continuation is unique whatever mode is chosen; several groups mean S(x0) leaves a choice that
    changes the trajectory (outside Theorem 6.3).

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    modes : iterable of frozenset
        Admissible modes, each a set of 0-based constraint indices. (S(x0), say)
    """
    groups: list[list[frozenset]] = []
    for I in sorted(modes, key=mode_order):
        for g in groups:
            if same_initial_solution(lcs, x0, g[0], I):
                g.append(I)
                break
        else:
            groups.append([I])
    return groups


# ---------------------------------------------------------------------------------------------
# modes that are not autonomous: the state they give, the inputs they leave undetermined
# ---------------------------------------------------------------------------------------------


def _state_determined(mode) -> bool:
    """State-determined (modes.py) and the family's free inputs leave B u(s) unchanged."""
    return mode.is_state_determined and state_response(mode) is not None


def _rmat(m: fmpq_mat) -> RationalMatrix:
    return RationalMatrix([[m[i, j] for j in range(m.ncols())] for i in range(m.nrows())])


def state_response(mode) -> RationalMatrix | None:
    """X_I(s) (n x n over Q(s)) with B u(s) = X_I(s) x0 for every solution (u(s), y(s)) of
    RCP(x0) in mode I, so that x(s) = (sI - A)^{-1} (x0 + X_I(s) x0) (5.1); None when the free
    inputs of a mode that is not autonomous do move the state (then the state is not unique)."""
    if not mode.derived.state_response_known:
        mode.derived.state_response = _build_state_response(mode)
        mode.derived.state_response_known = True
    return mode.derived.state_response


def _build_state_response(mode) -> RationalMatrix | None:
    """X_I(s) of :func:`state_response`, computed (None when the free inputs move the state)."""
    lcs = mode.lcs
    n = lcs.n
    if not mode.I:
        return _rmat(zeros(n, n))
    if mode.is_autonomous:
        return _rmat(submatrix(lcs.B, None, mode.I)) * rcp_data(mode).W
    fam = family(mode)
    Q, F = list(fam.pivot_cols), list(fam.free)
    if F:
        moved = _rmat(submatrix(lcs.B, None, F))
        if Q:
            moved = moved + _rmat(submatrix(lcs.B, None, Q)) * fam.directions
        if any(not e.is_zero() for r in moved.rows for e in r):
            return None
    return _rmat(submatrix(lcs.B, None, Q)) * fam.particular if Q else _rmat(zeros(n, n))


def _equal_at(X: RationalMatrix, Y: RationalMatrix, x) -> bool:
    """X(s) x0 == Y(s) x0 as rational vectors (every Laurent numerator form vanishes at x0)."""
    D = X - Y
    for r in range(D.shape[0]):
        coeffs, _ = D.row_forms(r)
        if any(sign_of_form(c, x) != 0 for c in coeffs):
            return False
    return True


def state_groups(lcs: SystemLike, x0: Any, modes) -> list[list[frozenset]]:
    """The admissible modes grouped by the state of their initial solutions (equal B u(s) at x0,
    smallest modes first); one group means the state after x0 is unique whatever mode and free
    inputs are chosen.  A mode whose free inputs move the state is a group of its own.

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    modes : iterable of frozenset
        Admissible modes, each a set of 0-based constraint indices.
    """
    x = as_state(lcs, x0)
    groups: list[list[frozenset]] = []
    for I in sorted(modes, key=mode_order):
        X = state_response(lcs.mode(I))
        for g in groups:
            Y = state_response(lcs.mode(g[0]))
            if X is not None and Y is not None and _equal_at(X, Y, x):
                g.append(I)
                break
        else:
            groups.append([I])
    return groups


def _input_rows(mode) -> tuple[RationalMatrix, frozenset]:
    """(U(s), free): u(s) = U(s) x0 (k x n, zero rows off I) for the rows that the family fixes,
    and the inputs a free direction moves (none for an autonomous mode)."""
    if mode.derived.input_rows is None:
        mode.derived.input_rows = _build_input_rows(mode)
    return mode.derived.input_rows


def _build_input_rows(mode) -> tuple[RationalMatrix, frozenset]:
    """(U(s), free) of :func:`_input_rows`, computed."""
    lcs = mode.lcs
    n, k = lcs.n, lcs.k
    rows = [[RationalFunction(0)] * n for _ in range(k)]
    free: set = set()
    if mode.is_autonomous:
        W = rcp_data(mode).W
        for r, i in enumerate(mode.I):
            rows[i] = list(W.rows[r])
    else:
        fam = family(mode)
        free |= set(fam.free)
        for r, i in enumerate(fam.pivot_cols):
            rows[i] = list(fam.particular.rows[r])
            if fam.free and any(not e.is_zero() for e in fam.directions.rows[r]):
                free.add(i)
    return RationalMatrix(rows), frozenset(free)


def undetermined_inputs(lcs: SystemLike, x0: Any, modes) -> frozenset:
    """The inputs u_j not determined by the state among the admissible ``modes`` of one state
    group: free in a mode that is not autonomous, or different between two of the modes.

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    x0 : vector
        The initial state, rational or exact.
    modes : iterable of frozenset
        Admissible modes, each a set of 0-based constraint indices. (one state group)
    """
    x = as_state(lcs, x0)
    out: set = set()
    data = [_input_rows(lcs.mode(I)) for I in modes]
    for U, free in data:
        out |= free
    U0 = data[0][0]
    for U, _ in data[1:]:
        D = U - U0
        for j in range(lcs.k):
            if j in out:
                continue
            coeffs, _ = D.row_forms(j)
            if any(sign_of_form(c, x) != 0 for c in coeffs):
                out.add(j)
    return frozenset(out)
