"""A mode I of an LCS (section 4): the DAE (4.2)-(4.3) with y_I = 0, u_{I^c} = 0.

For the quadruple (K, L, M, N) = (A, B_{.I}, C_{I.}, D_{II}) this module computes, exactly:

* V_I, the consistent subspace, by the recursion (3.2), kept as the kernel of an annihilator W;
* T_I, the jump space, by the recursion (3.5);
* autonomy (Lemma 3.3), checked both as V_I ⊕ T_I = Q^n with Ker[B_I; D_II] = 0 and as
  det G_II(s) != 0 (the two must agree);
* P_I, the projection onto V_I along T_I (section 4.2);
* a feedback F_I with u_I = F_I x on V_I (section 4.1), chosen with F_I T_I = 0, and the
  closed-loop matrix A_I = A + B_{.I} F_I, so that x(t) = e^{A_I t} z for z in V_I.

Beyond Assumption 4.1 (docs/extensions.md): a mode that is not autonomous only because some
inputs do nothing to the state - Ker[B_I; D_II] != {0} (the *free inputs*: a floating node's
potential, a current that circulates in a loop of diodes) - while V_I ⊕ T_I = Q^n still holds, is
*state-determined*: every solution of (4.2) from a state has the same x, and P_I, F_I and A_I are
defined as above (F_I is one particular feedback: the free inputs w with B_I w = 0, D_II w = 0
may be added to u_I without changing x or y_I).  Such a mode can be followed; the free part of
u is undetermined (:attr:`Mode.free_inputs`).

A Mode is created by ``lcs.mode(I)`` and cached there; all data are computed on first use.
Indices are 0-based.
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass
from functools import cached_property
from typing import Any

from flint import fmpq, fmpq_mat, nmod_mat

from ..errors import LCSError, NotAutonomous
from ..numbers import Spectrum
from ..interfaces import SystemLike
from ..algebra import hstack, matrix_to_sympy, norm_inf, row_norms, selection_matrix, submatrix, vstack, zeros
from ..algebra import image, intersection, kernel, kernel_basis, left_kernel, projection, projection_along, rank, row_basis, solve_any

__all__ = ["Mode", "format_mode", "latex_mode", "mode_order", "LATEX_MAX_N"]

#: a prime for the characteristic polynomial modulo p (a proof that A_I is not nilpotent)
_PRIME = 2 ** 61 - 1
#: per system (weakly held): (||A_i||_1 of each row of A, tr A, tr A^2), shared by its modes
_SYSTEMS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _system_data(lcs) -> tuple[list, fmpq, fmpq]:
    """(row norms of A, tr A, tr A^2) of a system, computed once a system."""
    data = _SYSTEMS.get(lcs)
    if data is None:
        A = lcs.A
        data = (row_norms(A), _trace(A), _trace(A * A))
        _SYSTEMS[lcs] = data
    return data


def _trace(m: fmpq_mat) -> fmpq:
    return sum((m[i, i] for i in range(m.nrows())), fmpq(0))

#: ``_repr_latex_`` of a mode (and of results showing n x n matrices) returns None above this n
LATEX_MAX_N = 12


def format_mode(I) -> str:
    """{0, 2} style (0-based), ∅ for the empty mode.

    Parameters
    ----------
    I : iterable of int
        The mode (0-based indices).

    >>> format_mode({2, 0}), format_mode(set())
    ('{0, 2}', '∅')
    """
    return "{" + ", ".join(str(i) for i in sorted(I)) + "}" if I else "∅"


def mode_order(I) -> tuple:
    """The order in which modes are tried and listed: fewer indices first, then lexicographically
    (the smallest admissible mode of Remark 4.8 is ``min(S, key=mode_order)``).

    Parameters
    ----------
    I : iterable of int
        The mode (0-based indices).

    >>> sorted([{1}, {0, 1}, set(), {0}], key=mode_order)
    [set(), {0}, {1}, {0, 1}]
    """
    return len(I), sorted(I)


def latex_mode(I) -> str:
    """The mode as LaTeX: ``\\{0, 2\\}`` (braces escaped so they render), ``\\emptyset``.

    Parameters
    ----------
    I : iterable of int
        The mode (0-based indices).

    >>> print(latex_mode({0, 2}), latex_mode(()))
    \\{0, 2\\} \\emptyset
    """
    return r"\{" + ", ".join(str(i) for i in sorted(I)) + r"\}" if I else r"\emptyset"


@dataclass(eq=False)
class DerivedData:
    """The data of one mode that the modules above this one compute once and keep on the mode
    (:attr:`Mode.derived`), in named fields rather than under string keys; None until computed.
    Their types live in those modules, which this one may not import (imports point down):

    * ``family``: the RCP family of the mode (``rcpfamily.RCPFamily``);
    * ``rcp``: W_I(s), Z_I(s) and their Laurent forms (5.3)-(5.5) (``selection.RCPData``);
    * ``rcp_rows``: [u(s); y(s)] of the initial solution as rows times x0, 2k x n over Q(s);
    * ``state_response``: X_I(s) with B u(s) = X_I(s) x0, or None when the free inputs move the
      state, so that ``state_response_known`` says whether it was computed;
    * ``input_rows``: (U(s), free): u(s) = U(s) x0 on the rows the family fixes, and the inputs a
      free direction moves;
    * ``constraints``: the monitored functions of a phase in the mode, their rows' norms and the
      rows stacked (``phase.Phase``: a tuple of ``Constraint``, a list of ||g||_1, an fmpq_mat);
    * ``balls``: (prec, A_I, the stacked rows) as ``arb_mat`` balls of ``prec`` bits, kept at the
      highest precision asked (``phase.Phase``'s Taylor steps: balls of more bits serve fewer);
    * ``screen_balls``: (A_I, the stacked rows) as balls of ``phase.SCREEN_PREC`` bits (the
      phases' screens for events).
    """

    family: Any = None
    rcp: Any = None
    rcp_rows: Any = None
    state_response: Any = None
    state_response_known: bool = False
    input_rows: Any = None
    constraints: Any = None
    balls: Any = None
    screen_balls: Any = None


class Mode:
    """Mode I of an LCS: V_I, T_I, P_I, F_I and autonomy, computed lazily and exactly.

    Parameters
    ----------
    lcs : LCS
        The system (A, B, C, D) of (2.1).
    I : iterable of int
        The mode (0-based): y_I = 0, u_{I^c} = 0 in (4.2)-(4.3).

    Examples
    --------
    >>> from lcs_exact import LCS
    >>> carts = LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]], [[0], [0], [1], [0]],
    ...             [[1, 0, 0, 0]], [[0]])
    >>> m = carts.mode({0})
    >>> m.consistent_subspace().transpose()
    [0, 1, 0, 0]
    [0, 0, 0, 1]
    >>> m.projection() * fmpq_mat([[0], [-1], [-1], [0]])
    [ 0]
    [-1]
    [ 0]
    [ 0]
    """

    def __init__(self, lcs: SystemLike, I: frozenset):
        self.lcs = lcs
        self.index_set = frozenset(I)
        self.I = sorted(I)
        self.Ic = [i for i in range(lcs.k) if i not in I]
        self.derived = DerivedData()  # the data of the modules above; the mode's own: cached properties

    # the quadruple (A, B_.I, C_I., D_II), taken once a mode (read by V_I, T_I, F_I, A_I, ...)
    @cached_property
    def _L(self) -> fmpq_mat:
        return submatrix(self.lcs.B, None, self.I)

    @cached_property
    def _M(self) -> fmpq_mat:
        return submatrix(self.lcs.C, self.I, None)

    @cached_property
    def _N(self) -> fmpq_mat:
        return submatrix(self.lcs.D, self.I, self.I)

    # --- V_I (3.2) ---------------------------------------------------------------------------
    def annihilator(self) -> fmpq_mat:
        """W with V_I = Ker W, by (3.2): V_{i+1} = {x : exists u, Kx + Lu in V_i, Mx + Nu = 0}."""
        return self._W

    @cached_property
    def _W(self) -> fmpq_mat:
        n, A = self.lcs.n, self.lcs.A
        L, M, N = self._L, self._M, self._N
        W = zeros(0, n)
        dim = n
        for _ in range(n + 1):
            lhs = vstack(W * A, M, ncols=n)
            rhs = vstack(W * L, N, ncols=len(self.I))
            Q = left_kernel(rhs)  # rows q with q [WL; N] = 0 eliminate u
            W_next = Q * lhs if Q.nrows() else zeros(0, n)
            d = n - rank(W_next)
            W = W_next
            if d == dim:
                break
            dim = d
        return W

    def consistent_subspace(self) -> fmpq_mat:
        """V_I = ``V(A, B_.I, C_I., D_II)`` (Def. 3.1, recursion (3.2)): an n x dim basis (columns)."""
        return self._V

    @cached_property
    def _V(self) -> fmpq_mat:
        return kernel(self._W)

    # --- T_I (3.5) ---------------------------------------------------------------------------
    def jump_space(self) -> fmpq_mat:
        """T_I = ``T(A, B_.I, C_I., D_II)`` (recursion (3.5)): an n x dim basis (columns)."""
        return self._T

    @cached_property
    def _T(self) -> fmpq_mat:
        n, A = self.lcs.n, self.lcs.A
        L, M, N = self._L, self._M, self._N
        T = zeros(n, 0)
        for _ in range(n + 1):
            # T_{i+1} = {A x + L u : x in T_i, M x + N u = 0}; x = T a
            k = kernel(hstack(M * T, N, nrows=len(self.I)))
            T_next = image(hstack(A * T, L, nrows=n) * k) if k.ncols() else zeros(n, 0)
            if T_next.ncols() == T.ncols():
                break
            T = T_next
        return T

    # --- autonomy (Lemma 3.3) ----------------------------------------------------------------
    @cached_property
    def _autonomy(self) -> tuple[bool, str]:
        """(autonomous, the reason when it is not)."""
        wp = self.lcs.well_posedness()
        if wp.M_is_P or wp.N_is_P:  # Lemma 6.6: M or N with nonzero principal minors
            return True, ""
        n, m = self.lcs.n, len(self.I)
        V, T = self._V, self._T
        reason = ""
        if rank(vstack(self._L, self._N, ncols=m)) < m:
            reason = "Ker[B_I; D_II] != {0} (the inputs u_I are not determined by the state)"
        elif intersection(V, T).ncols() > 0:
            reason = f"V_I ∩ T_I != {{0}} (dim V_I = {V.ncols()}, dim T_I = {T.ncols()})"
        elif V.ncols() + T.ncols() != n:
            reason = f"V_I + T_I != Q^{n} (dim V_I = {V.ncols()}, dim T_I = {T.ncols()})"
        # equivalently det G_II(s) != 0 (Lemma 3.3; tests/test_properties.py checks the two
        # agree on random systems: the transfer matrix is not built on the hot path)
        if reason:
            reason += "; G_II(s) is singular"
        return not reason, reason

    @property
    def is_autonomous(self) -> bool:
        """Lemma 3.3: V_I ⊕ T_I = Q^n and Ker[B_I; D_II] = 0, equivalently det G_II(s) != 0."""
        return self._autonomy[0]

    @property
    def autonomy_reason(self) -> str:
        """Why the mode is not autonomous ('' when it is)."""
        return self._autonomy[1]

    def require_autonomous(self) -> None:
        if not self.is_autonomous:
            raise NotAutonomous(f"mode {format_mode(self.I)} is not autonomous: {self.autonomy_reason}")

    def free_inputs(self) -> fmpq_mat:
        """A basis (columns, ``|I| x d``) of ``Ker[B_I; D_II]``: directions of u_I that change neither
        the state nor y_I (d = 0 for an autonomous mode)."""
        return self._free

    @cached_property
    def _free(self) -> fmpq_mat:
        m = len(self.I)
        return kernel(vstack(self._L, self._N, ncols=m)) if m else zeros(0, 0)

    @property
    def is_state_determined(self) -> bool:
        """True when the state of every solution of (4.2) is unique and P_I is defined: autonomous,
        or V_I ⊕ T_I = Q^n with only free inputs left undetermined (module docstring)."""
        return self.is_autonomous or self._splits

    @cached_property
    def _splits(self) -> bool:
        """V_I ⊕ T_I = Q^n."""
        V, T = self._V, self._T
        return V.ncols() + T.ncols() == self.lcs.n and intersection(V, T).ncols() == 0

    def require_state_determined(self) -> None:
        if not self.is_state_determined:
            raise NotAutonomous(f"mode {format_mode(self.I)} is not autonomous ({self.autonomy_reason}) and the "
                                f"state is not determined in it (V_I ⊕ T_I != Q^{self.lcs.n})")

    # --- P_I, F_I, A_I ------------------------------------------------------------------------
    def projection(self) -> fmpq_mat:
        """P_I: projection onto V_I along T_I (section 4.2); x(0+) = P_I x0."""
        return self._P

    @cached_property
    def _P(self) -> fmpq_mat:
        self.require_state_determined()  # raises: nothing is cached
        # I - T (W T)^{-1} W (W a row basis of V_I's annihilator): a d x d solve, d = dim T_I
        P = projection_along(row_basis(self._W), self._T)
        return P if P is not None else projection(self._V, self._T)

    def feedback(self) -> fmpq_mat:
        """F_I (``|I| x n``): u_I = F_I x keeps x in V_I and y_I = 0 (section 4.1); F_I T_I = 0."""
        return self._F

    @cached_property
    def _F(self) -> fmpq_mat:
        self.require_state_determined()
        n, m = self.lcs.n, len(self.I)
        W = self._W
        # a basis of V_I with unit rows (not the canonical one: its second echelon form is not
        # needed here): x = V a + T b with a = (P_I x)[units]
        V, units = kernel_basis(W)
        if m == 0:
            return zeros(0, n)
        # for each basis vector v of V: [W L; N] u = -[W A; M] v (unique when the mode is
        # autonomous; otherwise one solution, up to the free inputs, which change nothing in x)
        lhs = vstack(W * self._L, self._N, ncols=m)
        rhs = -(vstack(W * self.lcs.A, self._M, ncols=n) * V)
        U = solve_any(lhs, rhs)
        if U is None:
            raise LCSError(f"internal inconsistency: V_I of mode {format_mode(self.I)} is not invariant")
        if not V.ncols():
            return zeros(m, n)
        # column c of V is 1 at row units[c], where the other columns are 0: F_I = U P_I[units, :],
        # formed as (U S) P_I with S the 0/1 rows e_units[c] (|I| x n x n, not d x n x n with
        # d = dim V_I taking the rows of P_I)
        return (U * selection_matrix(units, n)) * self._P

    def closed_loop(self) -> fmpq_mat:
        """A_I = ``A + B_.I F_I``: x' = A_I x on V_I."""
        return self._A_I

    @cached_property
    def _A_I(self) -> fmpq_mat:
        return self.lcs.A + self._L * self._F if self.I else self.lcs.A

    @cached_property
    def _changed_rows(self) -> list[int]:
        """The rows i of A_I = A + B_.I F_I that differ from A's can only be those with B_iI != 0."""
        L = self._L
        m = L.ncols()
        e = L.entries()
        return [i for i in range(L.nrows()) if any(e[i * m:(i + 1) * m])]

    @cached_property
    def closed_loop_norm(self):
        """||A_I||_inf exactly (an ``fmpq``): the rate bound of Taylor steps (computed once).  The
        rows A_I shares with A take their norms from the system's (n^2 entries read once a
        system, not once a mode); the others are read here."""
        if not self.I:
            return norm_inf(self._A_I)
        rows = self._changed_rows
        norms = _system_data(self.lcs)[0]
        changed = set(rows)
        kept = max((norms[i] for i in range(len(norms)) if i not in changed), default=fmpq(0))
        return max(kept, norm_inf(submatrix(self._A_I, rows, None))) if rows else kept

    @cached_property
    def closed_loop_nilpotent(self) -> bool:
        """A_I nilpotent (its characteristic polynomial is s^n), decided exactly without the
        spectral data.  A nilpotent matrix has tr A_I = tr A_I^2 = 0, and with A_I = A + L F
        (L = B_.I) both come from k x k products and the system's tr A^2: tr A_I = tr A + tr F L,
        tr A_I^2 = tr A^2 + 2 tr F A L + tr (F L)^2 (a mode of 64 carts: ~0.3 ms, not the 1.6 ms
        of a characteristic polynomial).  Otherwise A_I = Z / d (Z integer) is nilpotent with Z;
        a coefficient of det(sI - Z) that is nonzero modulo a prime is nonzero: most modes are
        told apart by the polynomial modulo 2^61 - 1 (2 ms at n = 128, against 7 ms and more over
        Q)."""
        tr_A, tr_A2 = _system_data(self.lcs)[1:]
        if self.I:
            F, L = self._F, self._L
            FL = F * L
            if tr_A + _trace(FL) != 0 or tr_A2 + 2 * _trace(F * (self.lcs.A * L)) + _trace(FL * FL) != 0:
                return False
        elif tr_A != 0 or tr_A2 != 0:
            return False
        Z, _ = self._A_I.numer_denom()
        if any(c != 0 for c in nmod_mat(Z, _PRIME).charpoly().coeffs()[:-1]):
            return False
        return all(c == 0 for c in self._A_I.charpoly().coeffs()[:-1])

    def spectrum(self) -> Spectrum:
        """The spectral data of e^{A_I t} (:class:`~lcs_exact.expm.Spectrum`), computed once."""
        return self._spectrum

    @cached_property
    def _spectrum(self) -> Spectrum:
        return Spectrum(self._A_I)

    def contains(self, x: fmpq_mat) -> bool:
        """x in V_I (Algorithm 7.1, step two), exact for rational x.

        Parameters
        ----------
        x : fmpq_mat
            A rational state (n x 1).
        """
        return rank(hstack(self.consistent_subspace(), x)) == self.consistent_subspace().ncols()

    # --- display ------------------------------------------------------------------------------
    def __repr__(self):
        aut = "autonomous" if self.is_autonomous else f"NOT autonomous ({self.autonomy_reason})"
        return (f"<Mode {format_mode(self.I)}: dim V_I = {self.consistent_subspace().ncols()}, "
                f"dim T_I = {self.jump_space().ncols()}, {aut}>")

    def _repr_latex_(self):
        import sympy
        if self.lcs.n > LATEX_MAX_N:
            return None
        V, T = self.consistent_subspace(), self.jump_space()
        f = lambda m: sympy.latex(matrix_to_sympy(m)) if m.ncols() else r"\{0\}"  # noqa: E731
        name = latex_mode(self.I)
        s = rf"\text{{mode }} I = {name}:\ V_I = \operatorname{{Im}}{f(V)},\ T_I = \operatorname{{Im}}{f(T)}"
        if self.is_autonomous:
            s += rf",\ P_I = {f(self.projection())}"
        return f"${s}$"

