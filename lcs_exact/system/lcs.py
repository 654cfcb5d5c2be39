"""The linear complementarity system (4.1) and its exact system-theoretic data.

    x' = A x + B u,   y = C x + D u,   0 <= y ⊥ u >= 0.

:class:`LCS` holds A, B, C, D as ``fmpq_mat`` and computes, exactly and on demand (cached):
the Markov parameters H_i (5.8), G(s) = C(sI - A)^{-1} B + D and R(s) = C(sI - A)^{-1} (5.3),
the leading row/column indices and coefficient matrices (Def. 6.2, (6.1)), the well-posedness
report of Theorem 6.3, and the modes I (``lcs.mode(I)``, built lazily; never all 2^k).
Mode selection (section 5) is in :mod:`lcs_exact.selection`; the methods here delegate to it.
"""
from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sized
from functools import cached_property
from itertools import islice
from typing import Any, Iterable

from flint import fmpq, fmpq_mat, fmpq_poly

from ..errors import IllPosed, InvalidArgument, ShapeError
from .modelformat import model_data, write_model_file
from .modemap import mode_map
from ..modes import Mode, format_mode
from ..algebra import RationalFunction, RationalMatrix
from ..algebra import (MAX_DIMENSION, MAX_MARKOV_INDEX, adjugate_coefficients, as_list, eigenvalue_moduli, mat_rows,
                       matrix_to_sympy, to_fmpq, to_int, to_matrix, to_short, to_vector)
from ..modes import initial_solution, is_regular, ldcp, rcp, select_modes
from .sources import SourceBlock, source_block
from .statespace import read_statespace, to_arrays, to_statespace
from .wellposedness import WellPosedness, leading_indices

__all__ = ["LCS", "LATEX_MAX_CHARS"]

#: ``_repr_latex_`` of a system returns None when its entries take more characters than this
#: (a page of digits is not math anyone reads; the repr still pastes back)
LATEX_MAX_CHARS = 3000


def _as_column(data: Any, n: int) -> Any:
    """A flat length-n list given for B (k = 1) is read as a column."""
    if isinstance(data, (list, tuple)) and data and not isinstance(data[0], (list, tuple)) and n > 1:
        return [[e] for e in data]
    return data


def _as_row(data: Any) -> Any:
    if isinstance(data, (list, tuple)) and data and not isinstance(data[0], (list, tuple)):
        return [list(data)]
    return data


def _names(names: Any, count: int, what: str, prefix: str) -> tuple:
    """Validated names (distinct nonempty strings, one per index) as a tuple; defaults prefix+i."""
    if names is None:
        return tuple(f"{prefix}{i}" for i in range(count))
    if isinstance(names, str) or not isinstance(names, Iterable):
        raise InvalidArgument(f"{what} must be a sequence of {count} strings, got {type(names).__name__}")
    # a sized sequence is read whole; an iterator is cut off (it may be endless)
    sized = isinstance(names, Sized)
    names = tuple(names) if sized else tuple(islice(iter(names), count + 1))
    if len(names) != count:
        got = str(len(names)) if sized or len(names) < count else f"more than {count}"
        raise ShapeError(f"{what} has {got} names, expected {count}")
    bad = [nm for nm in names if not isinstance(nm, str) or not nm]
    if bad:
        raise InvalidArgument(f"{what} must be nonempty strings, got {bad[0]!r}")
    dup = sorted({nm for nm in names if names.count(nm) > 1})
    if dup:
        raise InvalidArgument(f"{what} must be distinct: {dup[0]!r} occurs more than once")
    return names


class LCS:
    """A linear complementarity system (4.1) with exact rational data.

    Parameters
    ----------
    A, B, C, D : matrix-like
        n x n, n x k, k x n, k x k.  Entries: int, ``"p/q"`` strings, Fraction, sympy Rational,
        fmpq; a float is read as its shortest decimal repr (0.1 -> 1/10).  For k = 1, B and C may
        be flat lists and D a scalar.
    name : str, optional
        A title shown by ``str`` and in reprs.
    state_names : sequence of str, optional
        Names of x_0, ..., x_{n-1} (plots, tables, reprs).  Default ``("x_0", ..., "x_{n-1}")``:
        0-based, like every index in the library (the paper's x_1 is ``x_0`` here).
    constraint_names : sequence of str, optional
        Names of the complementarity pairs (u_i, y_i), i = 0..k-1.  Default ``("0", ..., "k-1")``,
        so that plots label the pairs u_0, y_0, ...; a name such as ``"stop"`` labels them
        u (stop), y (stop).

    embedding : callable, optional
        Set by builders that append states (:func:`lcs_exact.models.relay` appends the constant
        relay level c): maps a state of the modelled system to the full initial state, see
        :meth:`embed`.  Default: none (``embed`` reads x as it is).
    restitution : rational or sequence of k rationals in [0, 1], optional
        Newton's impact law, generalised by Moreau to simultaneous impacts (docs/extensions.md;
        :mod:`lcs_exact.impacts`): at a state where closed constraints (y_i = 0) approach
        (y_i' < 0), the velocities jump by the impact LCP E q'+ + e E q'- >= 0 ⊥ impulse >= 0
        instead of the paper's P_I.  Needs every constraint of relative degree 2 (D = 0,
        C B = 0, C A B with a positive diagonal and a P-matrix on the contacts that close together:
        mechanical contacts), except compliant ones (D_ii > 0, relative degree 0: they never
        take an impulse, and their coefficient must be None or 0).  e = 0 gives exactly the
        paper's re-initialization (Theorem 8.2); None (default) is the paper's LCS.
    roles : sequence of k (u_label, y_label, in_word, out_word), optional
        What each pair means, set by the builders so that results and plots speak their
        language: a contact is ``("force (floor)", "gap (floor)", "contact", "open")``, a diode
        ``("i(D1)", "-v(D1)", "conducting", "blocking")`` (``in_word`` describes i in the mode,
        y_i = 0; ``out_word`` i outside it, u_i = 0).  See :meth:`describe_mode`.

    Names must be distinct nonempty strings; they are stored as tuples.

    Examples
    --------
    The two-carts system of section 2:

    >>> carts = LCS([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]],
    ...             [[0], [0], [1], [0]], [[1, 0, 0, 0]], [[0]])
    >>> carts.n, carts.k
    (4, 1)
    >>> [carts.markov(i)[0, 0] for i in range(3)]
    [0, 0, 1]
    >>> bool(carts.well_posedness())
    True
    """

    def __init__(self, A: Any, B: Any, C: Any, D: Any, *, name: str | None = None,
                 state_names: Any = None, constraint_names: Any = None, embedding: Any = None,
                 restitution: Any = None, roles: Any = None):
        self.A = to_matrix(A, "A")
        n = self.A.nrows()
        if n == 0 or self.A.ncols() != n:
            raise ShapeError(f"A must be a nonempty square matrix, got shape {n}x{self.A.ncols()}")
        self.B = to_matrix(_as_column(B, n), "B", (n, None))
        k = self.B.ncols()
        if k == 0:
            raise ShapeError("B has no columns: an LCS needs at least one complementarity pair (k >= 1)")
        self.C = to_matrix(_as_row(C), "C", (k, n))
        if getattr(D, "ndim", None) == 0 or not isinstance(D, (list, tuple)) and not hasattr(D, "tolist") and \
                not isinstance(D, fmpq_mat):  # a scalar (a numpy scalar too) for k = 1
            D = [[D]]
        self.D = to_matrix(_as_row(D), "D", (k, k))
        self.n, self.k = n, k
        if name is not None and not isinstance(name, str):
            raise InvalidArgument(f"name must be a str, got {type(name).__name__}")
        self.name = name
        self.state_names = _names(state_names, n, "state_names", "x_")
        self.constraint_names = _names(constraint_names, k, "constraint_names", "")
        if embedding is not None and not callable(embedding):
            raise InvalidArgument(f"embedding must be callable, got {type(embedding).__name__}")
        self.embedding = embedding
        self._markov: list[fmpq_mat] = [self.D]
        self._apow_b: list[fmpq_mat] = [self.B]  # A^i B
        self._output_maps: list[fmpq_mat] = [self.C]  # C A^i
        self._modes: dict[frozenset, Any] = {}
        self.restitution = self._restitution(restitution)
        self.roles = self._roles(roles)

    def _roles(self, roles: Any) -> tuple | None:
        if roles is None:
            return None
        try:
            out = tuple(tuple(str(w) for w in r) for r in roles)
        except TypeError:
            raise InvalidArgument("roles must be a sequence of k tuples (u_label, y_label, in_word, out_word)") from None
        if len(out) != self.k or any(len(r) != 4 for r in out):
            raise ShapeError(f"roles must be {self.k} tuples (u_label, y_label, in_word, out_word)")
        return out

    def describe_mode(self, I: Iterable[int], undetermined: Iterable[int] = ()) -> str:
        """A mode in the builder's words (``"D1, D4 conducting; D2, D3 blocking"``, ``"floor
        contact"``), or ``{0, 2}`` when the LCS has no roles.  Pairs in ``undetermined`` (inputs
        the state leaves free on a phase, :meth:`Trajectory.undetermined`) are said so
        (``"D1 undetermined"``): their mode membership is a representative, not a fact.

        Parameters
        ----------
        I : iterable of int
            The mode (0-based indices of the active pairs, section 4).
        undetermined : iterable of int, optional
            Pairs whose input the state leaves free.

        >>> from lcs_exact.examples import two_carts
        >>> two_carts().describe_mode({0}), LCS([[0]], [[1]], [[1]], [[0]]).describe_mode({0})
        ('stop contact', '{0}')
        """
        key = self._index_set(I)
        free = self._index_set(undetermined)
        if self.roles is None:
            return format_mode(key) + (f" ({format_mode(free)} undetermined)" if free else "")
        groups: dict = {}
        for j in range(self.k):
            word = "undetermined" if j in free else self.roles[j][2] if j in key else self.roles[j][3]
            groups.setdefault(word, []).append(self.constraint_names[j])
        return "; ".join(f"{', '.join(names)} {word}" for word, names in groups.items())

    def _restitution(self, e: Any) -> tuple | None:
        """Validated restitution coefficients (one fmpq per constraint), or None (docs/extensions.md)."""
        if e is None:
            return None
        if isinstance(e, (list, tuple)) or hasattr(e, "tolist") and getattr(e, "ndim", None) != 0:
            e = list(as_list(e) if hasattr(e, "tolist") else e)
            if len(e) != self.k:
                raise ShapeError(f"restitution has {len(e)} coefficients, expected one per constraint (k = {self.k})")
            es = tuple(fmpq(0) if x is None else to_fmpq(x, f"restitution[{i}]") for i, x in enumerate(e))
        else:
            es = (to_fmpq(e, "restitution"),) * self.k
        for i, x in enumerate(es):
            if not 0 <= x <= 1:
                raise InvalidArgument(f"restitution coefficient of constraint {self.constraint_names[i]!r} must be "
                                      f"in [0, 1], got {x}")
        # Newton's law acts on velocities: y = C x, y' = C A x, the impulse jumps x by B lambda
        # and y' by C A B lambda (relative degree 2: D = 0, C B = 0, as for (8.3)); a compliant
        # contact (D_ii > 0, relative degree 0) takes no impulse and is left out of the law
        CB = self.C * self.B
        rigid = [i for i in range(self.k) if self.D[i, i] <= 0]
        if not rigid:
            raise InvalidArgument("restitution needs a constraint of relative degree 2 (a mechanical contact: D = 0, "
                                  "C B = 0) to act on; every constraint here has D_ii > 0 (relative degree 0: no "
                                  "impulses)")
        for i in set(range(self.k)) - set(rigid):
            if es[i] != 0:
                raise InvalidArgument(f"restitution of constraint {self.constraint_names[i]!r} must be None or 0: it "
                                      f"is compliant (D_ii = {self.D[i, i]} > 0, relative degree 0), so it never "
                                      f"takes an impulse for Newton's law to act on (its spring is elastic)")
        for i in rigid:
            what = ("restitution needs every constraint of relative degree 2 (mechanical contacts: D = 0, C B = 0) "
                    "or compliant (D_ii > 0)")
            if any(self.D[i, j] != 0 or self.D[j, i] != 0 for j in range(self.k)):
                raise InvalidArgument(f"{what}; constraint {self.constraint_names[i]!r} has a nonzero entry in D")
            if any(CB[i, j] != 0 or CB[j, i] != 0 for j in range(self.k)):
                raise InvalidArgument(f"{what}; constraint {self.constraint_names[i]!r} has a nonzero entry in C B")
        # each contact alone must be able to take an impulse (W_ii > 0); contacts that can close
        # together need W_JJ to be a P-matrix, checked at the impact (impacts.newton_impact):
        # a floor and a ceiling (dependent rows of E) never close together
        W = self.C * self.A * self.B
        for i in rigid:
            if W[i, i] <= 0:
                raise InvalidArgument(f"restitution needs C A B (the Delassus matrix E M^-1 E^T of (8.7)) to have a "
                                      f"positive diagonal; entry ({i}, {i}) of constraint "
                                      f"{self.constraint_names[i]!r} is {W[i, i]}")
        return es

    def output_map(self, i: int) -> fmpq_mat:
        """C A^i (k x n, exact, kept): the first term of stage i + 1 of the LCP sequence (Theorem 6.9).

        Parameters
        ----------
        i : int
        """
        i = to_int(i, "power i of A", 0, MAX_MARKOV_INDEX)
        while len(self._output_maps) <= i:
            self._output_maps.append(self._output_maps[-1] * self.A)
        return self._output_maps[i]

    def markov(self, i: int) -> fmpq_mat:
        """H_i (5.8): H_0 = D, H_i = C A^{i-1} B (exact, k x k); 0 <= i <= MAX_MARKOV_INDEX (4096).

        Parameters
        ----------
        i : int

        >>> LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]).markov(2)
        [1]
        """
        i = to_int(i, "Markov parameter index i", 0, MAX_MARKOV_INDEX)
        while len(self._markov) <= i:
            j = len(self._markov)  # H_j = C A^{j-1} B
            while len(self._apow_b) < j:
                self._apow_b.append(self.A * self._apow_b[-1])
            self._markov.append(self.C * self._apow_b[j - 1])
        return self._markov[i]

    def a_power_b(self, i: int) -> fmpq_mat:
        """A^i B (used for the state jump (3.8)); 0 <= i <= MAX_MARKOV_INDEX.

        Parameters
        ----------
        i : int
        """
        i = to_int(i, "power i of A^i B", 0, MAX_MARKOV_INDEX)
        while len(self._apow_b) <= i:
            self._apow_b.append(self.A * self._apow_b[-1])
        return self._apow_b[i]

    def charpoly(self) -> fmpq_poly:
        """det(sI - A)."""
        return self._charpoly

    @cached_property
    def _charpoly(self) -> fmpq_poly:
        return self.A.charpoly()

    def spectral_scales(self):
        """(smallest nonzero ``|lambda|``, largest ``|lambda|``) over the eigenvalues lambda of A, as
        certified ``arb`` balls, or None when A is nilpotent: the slowest and fastest rates of
        mode 0 (x' = Ax), which bound the horizons ``simulate`` accepts (docs/limits.md).

        >>> lo, hi = LCS([[0, 1], [-4, 0]], [[0], [1]], [[1, 0]], [[0]]).spectral_scales()
        >>> lo.contains(2) and hi.contains(2)
        True
        """
        return self._scales

    @cached_property
    def _scales(self) -> tuple | None:
        return eigenvalue_moduli(self.A, self._charpoly)

    @cached_property
    def _adjugate_coeffs(self) -> list[fmpq_mat]:
        return adjugate_coefficients(self.A, self._charpoly)

    def _poly_matrix_over_chi(self, left: fmpq_mat, right: fmpq_mat | None) -> RationalMatrix:
        bs, chi, n = self._adjugate_coeffs, self._charpoly, self.n
        mats = [left * b * right if right is not None else left * b for b in bs]
        r, c = mats[0].nrows(), mats[0].ncols()
        rows = []
        for i in range(r):
            row = []
            for j in range(c):
                num = fmpq_poly([mats[n - 1 - d][i, j] for d in range(n)])  # coefficient of s^d
                row.append(RationalFunction(num, chi))
            rows.append(row)
        return RationalMatrix(rows)

    def R(self) -> RationalMatrix:
        """R(s) = C (sI - A)^{-1}, k x n, strictly proper (section 5.2)."""
        return self._R

    @cached_property
    def _R(self) -> RationalMatrix:
        return self._poly_matrix_over_chi(self.C, None)

    def G(self) -> RationalMatrix:
        """G(s) = C (sI - A)^{-1} B + D, k x k, proper (5.3, 5.9)."""
        return self._G

    @cached_property
    def _G(self) -> RationalMatrix:
        g = self._poly_matrix_over_chi(self.C, self.B)
        return RationalMatrix([[g[i, j] + RationalFunction(self.D[i, j]) for j in range(self.k)] for i in range(self.k)])

    @cached_property
    def _rho(self) -> tuple:
        return leading_indices(self, rows=True)

    @cached_property
    def _eta(self) -> tuple:
        return leading_indices(self, rows=False)

    def leading_row_indices(self) -> tuple:
        """(rho_1, ..., rho_k): rho_j = inf{i : H^i_{j.} != 0} (Def. 6.2); math.inf if never."""
        return self._rho

    def leading_column_indices(self) -> tuple:
        """(eta_1, ..., eta_k): eta_j = inf{i : H^i_{.j} != 0} (Def. 6.2); math.inf if never."""
        return self._eta

    def leading_row_matrix(self) -> fmpq_mat:
        """M (6.1): row j is row j of H_{rho_j}.  IllPosed if a row of G(s) is identically zero."""
        rho = self.leading_row_indices()
        if math.inf in rho:
            j = rho.index(math.inf)
            raise IllPosed(f"row {j} of G(s) is identically zero (all Markov parameters vanish in "
                           f"row {j}): the leading row index rho_{j} is infinite and M is undefined")
        return fmpq_mat(self.k, self.k, [self.markov(rho[j])[j, l] for j in range(self.k) for l in range(self.k)])

    def leading_column_matrix(self) -> fmpq_mat:
        """N (6.1): column j is column j of H_{eta_j}.  IllPosed if a column of G(s) is zero."""
        eta = self.leading_column_indices()
        if math.inf in eta:
            j = eta.index(math.inf)
            raise IllPosed(f"column {j} of G(s) is identically zero: the leading column index "
                           f"eta_{j} is infinite and N is undefined")
        return fmpq_mat(self.k, self.k, [self.markov(eta[l])[j, l] for j in range(self.k) for l in range(self.k)])

    def well_posedness(self) -> "WellPosedness":
        """Theorem 6.3: M and N both P-matrices => well-posed (and every mode autonomous, Lemma 6.6).

        Returns a report that is truthy iff the conditions hold; it lists M, N, their P-matrix
        verdicts and, when one fails, a principal minor that is not positive.
        """
        return self._well_posedness

    @cached_property
    def _well_posedness(self) -> WellPosedness:
        return WellPosedness.of(self)

    @classmethod
    def from_statespace(cls, sys: Any, **options: Any) -> "LCS":
        """The LCS of a python-control ``StateSpace`` (or anything with ``A``, ``B``, ``C``, ``D`` arrays):
        x' = A x + B u, y = C x + D u with 0 <= y ⊥ u >= 0 (inputs and outputs paired, so the system must be
        square).  Floats are read as their shortest decimals (0.1 is 1/10); ``options`` go to :class:`LCS`
        (names, restitution, ...).  State and pair names come from the system's labels when it has them
        (:func:`~lcs_exact.statespace.read_statespace`): ``LCS.from_statespace(lcs.to_statespace())`` gives
        back the names and, for decimal data of up to 15 significant digits, the exact matrices.

        Parameters
        ----------
        sys : control.StateSpace or object with A, B, C, D
            The system x' = A x + B u, y = C x + D u (square: k inputs, k outputs).
        **options
            Passed on to :class:`LCS` (``names``, ``restitution``, ...).

        >>> class SS:  # a stand-in with the attributes of control.StateSpace
        ...     A, B, C, D = [[0.0, 1.0], [-2.5, -0.1]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]]
        >>> LCS.from_statespace(SS()).A
        [   0,     1]
        [-5/2, -1/10]
        """
        mats, names = read_statespace(sys)
        return cls(*mats, **{**names, **options})

    def to_statespace(self):
        """The linear part x' = A x + B u, y = C x + D u as a python-control ``StateSpace`` (needs
        the extra ``control``): A, B, C, D rounded to float64, states named ``state_names``,
        inputs and outputs as in tables and plots (``u_0``, ``u (stop)``, the builder's
        ``force (stop)``; :func:`~lcs_exact.statespace.signal_names`).  The complementarity
        conditions stay here: python-control sees u as a free input.

        >>> ss = LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]], constraint_names=["stop"]).to_statespace()
        >>> ss.state_labels, ss.input_labels, ss.output_labels
        (['x_0', 'x_1'], ['u (stop)'], ['y (stop)'])
        >>> LCS.from_statespace(ss).constraint_names
        ('stop',)
        """
        return to_statespace(self)

    def to_numpy(self):
        """(A, B, C, D) as float64 arrays (rounded: the exact data stay in ``lcs.A`` ...); an entry
        beyond float64's range is an InvalidArgument naming it (not infinity).

        >>> [m.shape for m in LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]]).to_numpy()]
        [(2, 2), (2, 1), (1, 2), (1, 1)]
        """
        return to_arrays(self)

    def embed(self, x: Any) -> fmpq_mat:
        """The full initial state (n x 1) for a state x of the modelled system.

        Builders that append states set the embedding: for a relay LCS (x, c) with the constant relay level
        c, ``embed(x)`` is (x, 1).  Without one, x itself (read as a rational vector of length n).

        Parameters
        ----------
        x : vector of rationals
            A state of the modelled system (or the full n-vector).

        >>> LCS([[0]], [[1]], [[1]], [[0]]).embed(["1/2"])
        [1/2]
        """
        if self.embedding is None:
            return to_vector(x, self.n, "x")
        return self.embedding(x)

    def to_model(self, path: Any, x0: Any = None, t_end: Any = None):
        """Write the system as a model file (docs/model-files.md): TOML when ``path`` ends in
        ``.toml``, JSON otherwise; :func:`lcs_exact.read_model` reads it back to an LCS with the
        same exact matrices, names, roles, restitution, sources and :meth:`embed`.

        Parameters
        ----------
        path : str or path-like
        x0 : vector, optional
            The initial state, as :meth:`embed` takes it (the plant's states when the LCS has
            sources); exact rationals only.
        t_end : rational, optional

        Returns
        -------
        pathlib.Path
            The file written.  ``Unsupported`` when the LCS's appended states are not sources a
            file can carry (:mod:`lcs_exact.modelformat`).

        Examples
        --------
        >>> import os, tempfile
        >>> from lcs_exact import examples, read_model
        >>> ball = examples.bouncing_ball()
        >>> path = os.path.join(tempfile.mkdtemp(), "ball.toml")
        >>> print(ball.to_model(path, x0=[1, 0], t_end=1).read_text(), end="")
        name = "bouncing ball"
        A = [
          [0, 1],
          [0, 0],
        ]
        B = [
          [0],
          [1],
        ]
        C = [[1, 0]]
        D = [[0]]
        E = [
          [0],
          ["-981/100"],
        ]
        F = [[0]]
        w = ["constant(1)"]
        x0 = [1, 0]
        t_end = 1
        restitution = "9/10"
        states = ["q", "q'", "1"]
        inputs = ["floor"]
        roles = [["force (floor)", "gap (floor)", "contact", "open"]]
        >>> read_model(path).A == ball.A
        True
        """
        return write_model_file(model_data(self, x0, t_end), path)

    @property
    def plant(self) -> tuple:
        """Indices of the modelled system's states (the builder's x, what :meth:`embed` takes):
        all states but those a builder appended (an exosystem, a relay level).

        >>> from lcs_exact import models, sources
        >>> models.driven([[-1]], [[1]], [[1]], [[1]], F=[[-1]], w=[sources.sine(1)]).plant
        (0,)
        """
        n = getattr(self.embedding, "n", None)
        return tuple(range(self.n if n is None else n))

    @property
    def sources(self) -> SourceBlock | None:
        """The exosystem a builder appended (:class:`~lcs_exact.sources.SourceBlock`: its states,
        S, z0 = the tail of :meth:`embed`, the states' expressions), or None.  The appended states
        form an autonomous block (no plant state and no u enters them), which is checked.

        >>> from lcs_exact import models, sources
        >>> sb = models.driven([[-1]], [[1]], [[1]], [[1]], F=[[-1]], w=[sources.sine(1)]).sources
        >>> sb.states, sb.expressions
        ((1, 2), ('sin(t)', 'cos(t)'))
        """
        return self._sources

    @cached_property
    def _sources(self) -> SourceBlock | None:
        plant = self.plant
        tail = getattr(self.embedding, "tail", None)
        J = list(range(len(plant), self.n))
        if not J or tail is None or tail.nrows() != len(J):
            return None
        if any(self.A[i, j] != 0 for i in J for j in plant) or any(self.B[i, c] != 0 for i in J for c in range(self.k)):
            return None  # not an exosystem: something drives the appended states
        S = fmpq_mat([[self.A[i, j] for j in J] for i in J])
        return source_block(J, S, tail, [self.state_names[i] for i in J])

    def _index_set(self, I: Iterable[int]) -> frozenset:
        if isinstance(I, (str, bytes, Mapping)) or not isinstance(I, Iterable):
            raise ShapeError(f"a mode is a set of constraint indices (0-based ints), got {to_short(I)}")
        items = list(islice(iter(I), MAX_DIMENSION + 1))  # an endless iterator is cut off
        if len(items) > MAX_DIMENSION:
            raise ShapeError(f"a mode is a set of at most k = {self.k} constraint indices, got more than "
                             f"{MAX_DIMENSION} items")
        s = frozenset(to_int(i, "a mode's constraint index") for i in items)
        bad = [i for i in s if not 0 <= i < self.k]
        if bad:
            raise ShapeError(f"mode {set(sorted(s))} has indices {bad} outside 0..{self.k - 1} (indices are 0-based)")
        return s

    def mode(self, I: Iterable[int]):
        """The mode I (0-based index set): V_I, T_I, P_I, F_I, autonomy.  Built once, on demand.

        Parameters
        ----------
        I : iterable of int
            The mode: the 0-based indices of the pairs with y_i = 0 (section 4).
        """
        key = self._index_set(I)
        m = self._modes.get(key)
        if m is None:
            m = self._modes[key] = Mode(self, key)
        return m

    def built_modes(self) -> frozenset:
        """The modes whose data have been built so far (modes are built lazily, on first use: a
        run of a large system builds only those it visits).

        >>> from lcs_exact.models import two_carts_with_hook
        >>> h = two_carts_with_hook()
        >>> h.built_modes(), h.mode({1}).index_set in h.built_modes()
        (frozenset(), True)
        """
        return frozenset(self._modes)

    def select_modes(self, x0: Any, method: str = "auto", *, nonautonomous: str = "raise") -> set:
        """S(x0) as a set of frozensets (Theorem 5.2: S = S_RCP = S_LDCP^oo); see
        :func:`lcs_exact.selection.select_modes`.

        Parameters
        ----------
        x0 : vector of rationals or exact vector
        method : {"auto", "rcp", "ldcp"}, optional
            ``"rcp"`` solves RCP(x0) exactly for every mode (a mode that is not autonomous is decided
            exactly too); ``"ldcp"`` solves LDCP_n by the LCP sequence of Theorems 6.9-6.10 (needs N to be a
            P-matrix); ``"auto"`` uses LDCP_n when N is a P-matrix and RCP otherwise.
        nonautonomous : {"raise", "include"}, optional
            ``"raise"`` (NotAutonomous) or ``"include"`` a mode admissible at x0 that is not autonomous.
        """
        return select_modes(self, x0, method=method, nonautonomous=nonautonomous)

    def rcp(self, x0: Any):
        """All solutions of RCP(x0) (5.3)-(5.4), one per admissible mode; see selection.rcp.

        Parameters
        ----------
        x0 : vector of rationals"""
        return rcp(self, x0)

    def ldcp(self, x0: Any, kappa: int | None = None):
        """LDCP_kappa(x0) (5.10)-(5.12), N a P-matrix (Theorems 6.9, 6.10).  See selection.ldcp.

        Parameters
        ----------
        x0 : vector of rationals or exact vector
        kappa : int, optional
            The number of stages (default n: Theorem 6.10)."""
        return ldcp(self, x0, self.n if kappa is None else kappa)

    def initial_solution(self, x0: Any):
        """The initial solution from x0 (unique when N is a P-matrix): mode, impulse, x(0+).

        Parameters
        ----------
        x0 : vector of rationals or exact vector"""
        return initial_solution(self, x0)

    def mode_map(self, slice: Any = None):
        """The exact partition of the state space (or of ``slice=(base, directions)``) into the
        polyhedral regions where S(x0) and the re-initialization are constant (docs/paper-to-api.md).
        See :func:`lcs_exact.modemap.mode_map`.

        Parameters
        ----------
        slice : (base, directions), optional
            An affine slice x0 = base + sum s_i d_i (None: the whole state space).
        """
        return mode_map(self, slice)

    def is_regular(self, x0: Any) -> bool:
        """Theorem 6.8: x0 admits a smooth initial solution.

        Parameters
        ----------
        x0 : vector of rationals or exact vector"""
        return is_regular(self, x0)

    def __repr__(self):
        # non-integers are quoted: "1/3" pastes back exactly (an unquoted 1/3 would be a float)
        q = lambda e: str(e) if e.q == 1 else f"'{e}'"  # noqa: E731
        f = lambda m: "[" + ", ".join("[" + ", ".join(q(e) for e in r) + "]" for r in mat_rows(m)) + "]"  # noqa: E731
        extra = f", name={self.name!r}" if self.name is not None else ""
        if self.state_names != _names(None, self.n, "", "x_"):
            extra += f", state_names={self.state_names!r}"
        if self.constraint_names != _names(None, self.k, "", ""):
            extra += f", constraint_names={self.constraint_names!r}"
        if self.roles is not None:
            extra += f", roles={self.roles!r}"
        if self.restitution is not None:
            es = self.restitution
            extra += f", restitution={q(es[0])}" if len(set(es)) == 1 else \
                f", restitution=[{', '.join(q(e) for e in es)}]"
        return f"LCS(A={f(self.A)}, B={f(self.B)}, C={f(self.C)}, D={f(self.D)}{extra})"

    def __str__(self):
        title = self.name or "LCS"
        return (f"{title}: n = {self.n} states ({', '.join(self.state_names)}), "
                f"k = {self.k} complementarity pairs ({', '.join(self.constraint_names)})")

    def _repr_latex_(self):
        """The equations (4.1) in LaTeX; None (Jupyter then shows the repr) above a size cap:
        more than 400 entries in A and B, or more than LATEX_MAX_CHARS characters of entries."""
        import sympy
        if self.n * (self.n + self.k) > 400:
            return None
        if sum(len(str(m[i, j])) for m in (self.A, self.B, self.C, self.D)
               for i in range(m.nrows()) for j in range(m.ncols())) > LATEX_MAX_CHARS:
            return None
        L = lambda m: sympy.latex(matrix_to_sympy(m))  # noqa: E731
        out = (rf"\dot x = {L(self.A)} x + {L(self.B)} u,\quad y = {L(self.C)} x + {L(self.D)} u,"
               rf"\quad 0 \le y \perp u \ge 0")
        if self.state_names != _names(None, self.n, "", "x_"):
            out += r",\quad x = (" + r",\ ".join(_latex_name(nm) for nm in self.state_names) + ")"
        if self.constraint_names != _names(None, self.k, "", ""):
            out += r",\quad \text{pairs } (" + r",\ ".join(_latex_name(nm) for nm in self.constraint_names) + ")"
        return f"${out}$"


def _latex_name(name: str) -> str:
    """x_0, q_1' (one letter, a subscript, primes) as math; anything else as escaped \\text{...}."""
    if re.fullmatch(r"[A-Za-z](_[A-Za-z0-9]+)?'*", name):
        base, _, sub = name.rstrip("'").partition("_")
        primes = "'" * (len(name) - len(name.rstrip("'")))
        return base + (f"_{{{sub}}}" if sub else "") + primes
    for c, r in (("\\", r"\textbackslash "), ("{", r"\{"), ("}", r"\}"), ("_", r"\_"), ("^", r"\^{}"),
                 ("$", r"\$"), ("&", r"\&"), ("%", r"\%"), ("#", r"\#"), ("~", r"\~{}")):
        name = name.replace(c, r)
    return rf"\text{{{name}}}"
