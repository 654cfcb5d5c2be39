"""Exact subspace arithmetic over Q on ``fmpq_mat`` (sections 3-4 use it for V_I, T_I, P_I).

Representation: a subspace of Q^n is an n x d ``fmpq_mat`` whose d columns are a basis (d = 0
is the zero subspace, an n x 0 matrix).  Every function returns such a basis, reduced
(columns of a reduced row echelon form of the transpose), so equal subspaces have equal bases.
"""
from __future__ import annotations

from functools import lru_cache

from flint import fmpq_mat

from ..errors import ShapeError
from .rational import hstack, identity, is_zero, submatrix, vstack, zeros

__all__ = [
    "rref", "rank", "kernel", "kernel_basis", "image", "left_kernel", "subspace_sum", "intersection",
    "complement", "contains", "same_subspace", "solve_any", "projection",
    "row_basis", "in_row_span", "RowSpan", "orbit_zero_forms", "invariant_forms", "pulled_back_forms",
    "projected_forms", "projection_along",
]


def rref(m: fmpq_mat) -> tuple[fmpq_mat, list[int]]:
    """Reduced row echelon form and the pivot columns."""
    if m.nrows() == 0 or m.ncols() == 0:
        return m, []
    r, rk = m.rref()
    pivots = []
    j = 0
    for i in range(rk):  # pivot columns increase with the row: scan on from the last one
        while r[i, j] == 0:
            j += 1
        pivots.append(j)
    return r, pivots


def rank(m: fmpq_mat) -> int:
    """The rank of m (0 for an empty matrix).

    Parameters
    ----------
    m : fmpq_mat
    """
    return 0 if m.nrows() == 0 or m.ncols() == 0 else m.rank()


def kernel(m: fmpq_mat) -> fmpq_mat:
    """Basis (columns) of Ker m.

    Parameters
    ----------
    m : fmpq_mat

    Examples
    --------
    >>> kernel(fmpq_mat([[1, 0, 0, 0], [0, 0, 1, 0]])).transpose()
    [0, 1, 0, 0]
    [0, 0, 0, 1]
    """
    return image(kernel_basis(m)[0])


def kernel_basis(m: fmpq_mat) -> tuple[fmpq_mat, list[int]]:
    """(K, free): a basis of Ker m read off rref(m) - column c is 1 at row free[c], where every
    other column is 0, and -rref(m)[i, free[c]] at the i-th pivot - without the second echelon
    form that makes :func:`kernel`'s basis canonical (for a caller that needs a basis with unit
    rows, not the canonical one).

    Parameters
    ----------
    m : fmpq_mat

    >>> K, free = kernel_basis(fmpq_mat([[1, 2, 0], [0, 0, 1]]))
    >>> K.transpose(), free
    ([-2, 1, 0], [1])
    """
    n = m.ncols()
    if m.nrows() == 0:
        return identity(n), list(range(n))
    r, piv = rref(m)
    pivots = set(piv)
    free = [j for j in range(n) if j not in pivots]
    out = fmpq_mat(n, len(free))
    for c, f in enumerate(free):
        out[f, c] = 1
        for i, p in enumerate(piv):
            out[p, c] = -r[i, f]
    return out, free


def image(m: fmpq_mat) -> fmpq_mat:
    """Canonical basis (columns) of Im m: the nonzero rows of rref(m^T), transposed.

    Parameters
    ----------
    m : fmpq_mat
    """
    n = m.nrows()
    if m.ncols() == 0:
        return zeros(n, 0)
    r, piv = rref(m.transpose())
    if len(piv) == r.nrows():  # independent columns (a kernel's basis): no zero rows to drop
        return r.transpose()
    return submatrix(r, range(len(piv)), None).transpose() if piv else zeros(n, 0)


def left_kernel(m: fmpq_mat) -> fmpq_mat:
    """Rows spanning {w : w m = 0} (returned as a d x nrows matrix).

    Parameters
    ----------
    m : fmpq_mat
    """
    if m.ncols() == 0:
        return identity(m.nrows())
    return kernel(m.transpose()).transpose()


def subspace_sum(*spaces: fmpq_mat) -> fmpq_mat:
    """V1 + V2 + ..."""
    return image(hstack(*spaces))


def intersection(v: fmpq_mat, w: fmpq_mat) -> fmpq_mat:
    """V ∩ W from bases: the kernel of [V, -W] mapped through V.

    Parameters
    ----------
    v, w : fmpq_mat
        Bases (columns) of V and W.
    """
    n = v.nrows()
    if v.ncols() == 0 or w.ncols() == 0:
        return zeros(n, 0)
    k = kernel(hstack(v, -w))
    if k.ncols() == 0:
        return zeros(n, 0)
    return image(v * submatrix(k, range(v.ncols()), None))


def complement(v: fmpq_mat) -> fmpq_mat:
    """A complement of V in Q^n spanned by coordinate vectors (the non-pivot coordinates)."""
    n = v.nrows()
    _, piv = rref(v.transpose()) if v.ncols() else (None, [])
    free = [j for j in range(n) if j not in piv]
    return submatrix(identity(n), None, free)


def contains(v: fmpq_mat, x: fmpq_mat) -> bool:
    """x (columns) lies in Im v."""
    return rank(hstack(v, x)) == rank(v)


def same_subspace(v: fmpq_mat, w: fmpq_mat) -> bool:
    return v.ncols() == w.ncols() and contains(v, w) and contains(w, v)


def solve_any(m: fmpq_mat, rhs: fmpq_mat) -> fmpq_mat | None:
    """One solution X of m X = rhs (free variables set to 0), or None when inconsistent.

    Parameters
    ----------
    m : fmpq_mat
    rhs : fmpq_mat
        As many rows as m.
    """
    r, c = m.nrows(), m.ncols()
    if rhs.nrows() != r:
        raise ShapeError(f"solve_any: rhs has {rhs.nrows()} rows, matrix has {r}")
    k = rhs.ncols()
    if r == 0:
        return zeros(c, k)
    aug, piv = rref(hstack(m, rhs))
    if any(p >= c for p in piv):
        return None
    x = zeros(c, k)
    for i, p in enumerate(piv):
        for j in range(k):
            x[p, j] = aug[i, c + j]
    return x


def projection(v: fmpq_mat, t: fmpq_mat) -> fmpq_mat:
    """The projection P onto V along T (requires V ⊕ T = Q^n): P = [V 0] [V T]^{-1}.

    Parameters
    ----------
    v, t : fmpq_mat
        Bases (columns) of V and T (V_I and T_I for P_I, section 4.2).

    Examples
    --------
    >>> v = fmpq_mat([[0, 0], [1, 0], [0, 0], [0, 1]]); t = fmpq_mat([[0, 1], [0, 0], [1, 0], [0, 0]])
    >>> projection(v, t) * fmpq_mat([[0], [-1], [-1], [0]])
    [ 0]
    [-1]
    [ 0]
    [ 0]
    """
    n = v.nrows()
    if v.ncols() + t.ncols() != n:
        raise ShapeError(f"V (dim {v.ncols()}) and T (dim {t.ncols()}) do not split Q^{n}")
    if n == 0:
        return zeros(0, 0)
    # S^{-1} = [C_V; C_T] (the coordinates in the basis [V T]): P = V C_V = I - T C_T.  Only the
    # rows of the smaller block are solved for (S^T Y = E, Y^T those rows): T_I has dimension
    # |I| times the relative degree, so a 128-state mode solves for a few columns, not 128
    d = v.ncols()
    rows = range(d) if d <= n - d else range(d, n)
    E = fmpq_mat(n, len(rows), [int(i == j) for i in range(n) for j in rows])
    St = vstack(v.transpose(), t.transpose())  # S^T = [V^T; T^T]
    try:
        if not rows and St.rank() < n:  # V or T is all of Q^n: no solve to find a dependency
            raise ZeroDivisionError
        C = St.solve(E).transpose()
    except ZeroDivisionError:
        raise ShapeError("V and T intersect: no projection onto V along T") from None
    if d <= n - d:
        return v * C if d else zeros(n, n)
    return identity(n) - t * C



def projection_along(w: fmpq_mat, t: fmpq_mat) -> fmpq_mat | None:
    """The projection onto Ker W along Im T, P = I - T (W T)^{-1} W, or None when W T is not square
    and invertible (then Ker W and Im T do not split Q^n, or W has dependent rows: the caller
    goes through bases, :func:`projection`).  One d x d solve (d = dim T) instead of n x n.

    Parameters
    ----------
    w : fmpq_mat
        d x n rows with Ker W = V (the annihilator of V_I).
    t : fmpq_mat
        n x d, a basis of T (T_I).

    Examples
    --------
    >>> projection_along(fmpq_mat([[1, 0, 0, 0], [0, 0, 1, 0]]), fmpq_mat([[0, 1], [0, 0], [1, 0], [0, 0]])
    ...                  ) * fmpq_mat([[0], [-1], [-1], [0]])
    [ 0]
    [-1]
    [ 0]
    [ 0]
    """
    n, d = t.nrows(), t.ncols()
    if w.nrows() != d:
        return None
    if d == 0:
        return identity(n)
    try:
        return identity(n) - t * (w * t).solve(w)
    except ZeroDivisionError:
        return None


# ---------------------------------------------------------------------------------------------
# linear forms (rows) known to vanish on a vector, an orbit or a projection (section 4)
# ---------------------------------------------------------------------------------------------


def row_basis(*ms: fmpq_mat) -> fmpq_mat:
    """A canonical basis (rows) of the span of the rows of all the matrices.

    Parameters
    ----------
    *ms : fmpq_mat
        Matrices with the same number of columns.

    Examples
    --------
    >>> row_basis(fmpq_mat([[1, 1], [2, 2]]), fmpq_mat([[0, 1]]))
    [1, 0]
    [0, 1]
    """
    nonempty = [m for m in ms if m.nrows()]
    if not nonempty:
        return zeros(0, ms[0].ncols() if ms else 0)
    m = vstack(*nonempty) if len(nonempty) > 1 else nonempty[0]
    return image(m.transpose()).transpose()


class RowSpan:
    """The row span of R, built once (rref rows and pivots) for many membership tests: a phase
    or an exact vector tests many forms against the same known relations.

    Parameters
    ----------
    R : fmpq_mat
        The relations (rows).

    Examples
    --------
    >>> Z = RowSpan(fmpq_mat([[1, 1, 0], [0, 0, 1]]))
    >>> fmpq_mat([[2, 2, 0]]) in Z, fmpq_mat([[1, 0, 0]]) in Z, Z.dim
    (True, False, 2)
    """

    __slots__ = ("_rows", "pivots", "n", "_units", "_basis", "_at_pivots")

    def __init__(self, R: fmpq_mat):
        self.n = n = R.ncols()
        r, piv = rref(R) if R.nrows() else (R, [])
        self._rows = None
        self.pivots = piv
        self._units = None
        self._basis = r if r.nrows() == len(piv) else submatrix(r, range(len(piv)), None)
        self._at_pivots = _selection(piv, n) if piv else None  # X S = X[:, pivots]

    @property
    def dim(self) -> int:
        return len(self.pivots)

    @property
    def rows(self) -> list[list]:
        """The rows of the reduced row echelon basis, as lists of entries (read on first use)."""
        if self._rows is None:
            n, e = self.n, self._basis.entries()
            self._rows = [e[i * n:(i + 1) * n] for i in range(len(self.pivots))]
        return self._rows

    def __contains__(self, form: fmpq_mat) -> bool:
        return is_zero(self._residual(form))

    def rows_inside(self, F: fmpq_mat) -> list[int]:
        """The indices of the rows of F that lie in the span: one product for all of them, a
        row's residual read only where its product with a fixed integer column is 0 (a nonzero
        value proves the row outside; a zero one is checked exactly).

        Parameters
        ----------
        F : fmpq_mat
            Rows (m x n).

        >>> RowSpan(fmpq_mat([[1, 1, 0], [0, 0, 1]])).rows_inside(fmpq_mat([[2, 2, 5], [1, 0, 0], [0, 0, 0]]))
        [0, 2]
        """
        if F.nrows() == 0:
            return []
        res = self._residual(F)
        probe = (res * _probe_column(self.n)).entries()
        return [i for i, v in enumerate(probe) if v == 0 and is_zero(submatrix(res, [i], None))]

    def _residual(self, form: fmpq_mat) -> fmpq_mat:
        # the rref rows are 1 at their own pivot and 0 at the others: subtracting f[p] times row
        # p for every pivot p at once is one product in C (a row at a time in Python cost ~1 ms
        # a form at n = 128 with a hundred relations: the LDCP's exact signs at events)
        if self._at_pivots is None:
            return form
        return form - (form * self._at_pivots) * self._basis

    def reduce(self, form: fmpq_mat) -> list:
        """The entries of form minus its part in the span along the pivots: a linear map whose
        kernel is the span (two forms agree modulo the span iff their reductions are equal).

        Parameters
        ----------
        form : fmpq_mat
            A 1 x n row.
        """
        return self._residual(form).entries()

    def proportional(self, fa: fmpq_mat, fb: fmpq_mat) -> bool:
        """fa = c fb modulo the span for some c != 0, neither form in the span.

        Parameters
        ----------
        fa, fb : fmpq_mat
            1 x n rows.

        Examples
        --------
        >>> Z = RowSpan(fmpq_mat([[0, 0, 1]]))
        >>> Z.proportional(fmpq_mat([[2, 4, 7]]), fmpq_mat([[1, 2, 0]]))
        True
        >>> Z.proportional(fmpq_mat([[0, 0, 1]]), fmpq_mat([[0, 0, 2]]))  # both in the span
        False
        """
        a, b = self.reduce(fa), self.reduce(fb)
        j = next((i for i, v in enumerate(b) if v != 0), None)
        if j is None or a[j] == 0:
            return False
        c = a[j] / b[j]
        return all(x == c * y for x, y in zip(a, b))

    def has_unit(self, i: int) -> bool:
        """e_i in the span (coordinate i vanishes wherever the relations hold).

        Parameters
        ----------
        i : int
            A coordinate (0-based).
        """
        return i in self.units()

    def units(self) -> frozenset:
        """{i : e_i in the span}: in reduced row echelon form e_i reduces to 0 exactly when i is a
        pivot whose row is e_i itself (any other entry of that row stays in the reduction), so
        one pass over the rows finds them all."""
        if self._units is None:
            self._units = frozenset(p for row, p in zip(self.rows, self.pivots)
                                    if sum(1 for e in row if e != 0) == 1)
        return self._units


def in_row_span(form: fmpq_mat, R: fmpq_mat) -> bool:
    """True when the row ``form`` lies in the row span of R (exact); see :class:`RowSpan` for
    many tests against one R.

    Parameters
    ----------
    form : fmpq_mat
        A 1 x n row.
    R : fmpq_mat
        Rows.
    """
    return form in RowSpan(R)


def orbit_zero_forms(M: fmpq_mat, q: fmpq_mat) -> fmpq_mat:
    """Every form g with g e^{Mt} q = 0 for all t: the left kernel of the Krylov matrix
    [q, Mq, ..., M^{n-1} q] (Cayley-Hamilton), exact.

    Parameters
    ----------
    M : fmpq_mat
        n x n.
    q : fmpq_mat
        n x 1.

    Examples
    --------
    >>> orbit_zero_forms(fmpq_mat([[0, 1, 0], [-1, 0, 0], [0, 0, 1]]), fmpq_mat([[1], [0], [0]]))
    [0, 0, 1]
    """
    cols, v = [], q
    for _ in range(M.nrows()):
        cols.append(v)
        v = M * v
    return left_kernel(hstack(*cols))


def invariant_forms(R: fmpq_mat, M: fmpq_mat, known: fmpq_mat | None = None) -> fmpq_mat:
    """The largest subspace U of rowspan(R) with U M in U (rows): R x = 0 implies U e^{Mt} x = 0.

    With ``known``, forms whose span is invariant already (K M in span K) and that vanish at x
    too: the largest invariant subspace of span(R) + span(K), computed modulo span(K) (a mode's
    annihilator is invariant under A_I, section 3: the few forms of R beyond it are iterated,
    not all of them).

    Parameters
    ----------
    R : fmpq_mat
        Forms (rows) vanishing at x.
    M : fmpq_mat
        n x n.
    known : fmpq_mat, optional
        Forms (rows) vanishing at x with an M-invariant span (the caller's fact).

    Examples
    --------
    >>> M = fmpq_mat([[0, 1, 0], [-1, 0, 0], [0, 0, 2]])
    >>> invariant_forms(fmpq_mat([[1, 0, 0], [0, 0, 1]]), M)      # e_3 only: e_1 M = e_2
    [0, 0, 1]
    >>> invariant_forms(fmpq_mat([[1, 0, 0]]), M, fmpq_mat([[0, 0, 1]]))
    [0, 0, 1]
    """
    n = M.nrows()
    if known is not None and known.nrows():
        return _invariant_modulo(R, M, known)
    U = R
    while U.nrows():
        # U in reduced row echelon form: a row y reduces modulo span(U) to y - y[:, piv] U, so
        # the residual of U M says which combinations a U stay in span(U) under M (a Res = 0);
        # no kernel when span(U) is invariant already (the constraints of the mode, mostly)
        r, piv = rref(U)
        U = submatrix(r, range(len(piv)), None) if piv else zeros(0, n)
        if not piv:
            return U
        Y = U * M
        Res = Y - (Y * _selection(piv, n)) * U
        if is_zero(Res):
            return U
        a = left_kernel(Res)
        U = a * U if a.nrows() else zeros(0, n)
    return U


def _invariant_modulo(R: fmpq_mat, M: fmpq_mat, known: fmpq_mat) -> fmpq_mat:
    """:func:`invariant_forms` of span(R) + span(K), K invariant: forms are reduced modulo K
    (zero at its pivot columns), and the iteration U <- {a U : a U M in span(U) + span(K)} runs
    on the reduced forms; the answer is K with the last U."""
    K = RowSpan(known)
    U = K._residual(R)  # R minus its part in span K (zero at K's pivots)
    while True:
        span = RowSpan(U)  # its rows are zero at K's pivots, so its own pivots are others
        if not span.dim:
            return K._basis
        U = span._basis
        Res = span._residual(K._residual(U * M))
        if is_zero(Res):
            return vstack(K._basis, U)
        a = left_kernel(Res)
        if not a.nrows():
            return K._basis
        U = a * U


@lru_cache(maxsize=16)
def _probe_column(n: int) -> fmpq_mat:
    """An n x 1 column of distinct integers (a row r with r p != 0 is not zero; r p = 0 is a
    question for the row's entries)."""
    return fmpq_mat(n, 1, [(7919 * (i + 1)) % 65521 + 1 for i in range(n)])


def _selection(cols: list[int], n: int) -> fmpq_mat:
    """The n x len(cols) 0/1 matrix with X S = X[:, cols] (one product in C)."""
    S = fmpq_mat(n, len(cols))
    for c, i in enumerate(cols):
        S[i, c] = 1
    return S


def projected_forms(W: fmpq_mat, T: fmpq_mat, Z: fmpq_mat) -> fmpq_mat:
    """:func:`pulled_back_forms` for P the projection onto V = Ker W along T (P_I of section 4.2,
    V_I = Ker W, T = T_I): r P is the form equal to r on V and 0 on T, so r P in rowspan(Z) exactly
    when r is in rowspan(W) + (rowspan(Z) ∩ T^⊥), and rowspan(Z) ∩ T^⊥ = {a Z : a Z T = 0} comes
    from the left kernel of the small matrix Z T (no kernel of an n x (n + m) matrix).

    Parameters
    ----------
    W : fmpq_mat
        Rows with Ker W = V.
    T : fmpq_mat
        A basis (columns) of T, V ⊕ T = Q^n.
    Z : fmpq_mat
        Forms (rows) vanishing on v.

    Examples
    --------
    >>> W, T = fmpq_mat([[1, 0, 0]]), fmpq_mat([[1], [1], [0]])   # P (x, y, z) = (0, y - x, z)
    >>> projected_forms(W, T, fmpq_mat([[0, 0, 1]]))  # z = 0 on v: P v = (0, y - x, 0)
    [1, 0, 0]
    [0, 0, 1]
    """
    n = W.ncols()
    if Z.nrows() == 0:
        return row_basis(W) if W.nrows() else zeros(0, n)
    A = left_kernel(Z * T) if T.ncols() else identity(Z.nrows())
    ZT = A * Z if A.nrows() else zeros(0, n)
    return row_basis(W, ZT) if W.nrows() or ZT.nrows() else zeros(0, n)


def pulled_back_forms(P: fmpq_mat, Z: fmpq_mat) -> fmpq_mat:
    """Rows r with r P in rowspan(Z): the forms that vanish on P v whenever Z v = 0.

    Parameters
    ----------
    P : fmpq_mat
        m x n.
    Z : fmpq_mat
        Forms (rows) vanishing on v.
    """
    m = P.nrows()
    if not Z.nrows():
        return left_kernel(P)
    k = kernel(hstack(P.transpose(), -Z.transpose()))  # (r, s) with P^T r = Z^T s
    if not k.ncols():
        return zeros(0, m)
    return row_basis(submatrix(k, range(m), None).transpose())
