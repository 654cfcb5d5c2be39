"""Linear relations among exact reals that their definitions prove (no number is evaluated).

An exact real unfolds into const + sum q_k r_k over base reals (:func:`~lcs_exact.reals.linear_terms`);
the component i of one exact vector is one base however often it was taken, and the forms proven to
vanish on that vector relate its components.  :func:`component_relations` gives the forms that
vanish on a vector of such reals: the zero forms of a start given as exact reals
(:class:`~lcs_exact.vectors.ComponentsVector`), from which a phase keeps its invariant part
(section 4: signs at the state are decided on these exact relations first).
"""
from __future__ import annotations

from flint import fmpq_mat

from .reals import ComponentReal, Real, linear_terms
from ..algebra import left_kernel, row_basis

__all__ = ["component_relations"]


def component_relations(comps: list[Real]) -> fmpq_mat:
    """The forms w with sum_j w_j c_j = 0 that the definitions of the reals c_j prove, as rows.

    Each c_j is const_j + sum_k q_jk r_k over base reals r_k (:func:`~lcs_exact.reals.linear_terms`:
    sums and rational multiples unfolded), the component i of one exact vector v counted as one base
    (v, i) however often it was taken, and the zero forms of such a v relate its components
    (rho . (v_0, ..., v_{n-1}) = 0).  w vanishes on c when w . const = 0 and w Q lies in the span of
    those relations: the left kernel of [[Q, const], [R, 0]], restricted to w.  A start x0 given as
    copies of one exact state (a system of identical blocks; the state built once, or twice as
    e^{M t} q with the same rational M, t, q) gets the relations x_i = x_j, and a
    phase from it their invariant part, so that the copies' simultaneous events are proven equal
    (:meth:`~lcs_exact.phases.phase.Phase.proportional`) instead of refused.

    Parameters
    ----------
    comps : list of Real
        The components c_0, ..., c_{n-1}.
    """
    n = len(comps)
    keys: dict = {}  # base key -> column (1 + k)
    vectors: dict = {}  # definition of v -> v, for the components of one exact vector
    defs: dict = {}  # definition -> a small number (a definition holds M's n^2 entries: hashed once a vector)
    ids: dict = {}  # id(v) -> that number
    rows = []
    for c in comps:
        const, terms = linear_terms(c)
        row = {0: const}
        for q, r in terms:
            if isinstance(r, ComponentReal):
                if id(r.vec) not in ids:
                    ids[id(r.vec)] = defs.setdefault(_definition(r.vec), len(defs))
                vid = ids[id(r.vec)]
                key = ("component", vid, r.i)
                vectors[vid] = r.vec
            else:
                key = ("real", id(r))
            col = keys.setdefault(key, 1 + len(keys))
            row[col] = row.get(col, 0) + q
        rows.append(row)
    relations = []  # rho over the bases, from the zero forms of the vectors the components are of
    for vid, v in vectors.items():
        for a in range(v.zero_forms.nrows()):
            rho = {}
            for i in range(v.n):
                if v.zero_forms[a, i] != 0:
                    rho[keys.setdefault(("component", vid, i), 1 + len(keys))] = v.zero_forms[a, i]
            relations.append(rho)
    m = fmpq_mat(n + len(relations), 1 + len(keys))
    for i, row in enumerate(rows + relations):
        for col, q in row.items():
            m[i, col] = q
    L = left_kernel(m)
    W = fmpq_mat(L.nrows(), n, [L[a, j] for a in range(L.nrows()) for j in range(n)])
    return row_basis(W) if W.nrows() else W


def _definition(vec) -> tuple:
    """A key equal for two vectors with one exact definition e^{M t} q (M, t and q rational: two
    calls of ``expm_action`` with the same arguments), else the vector's identity."""
    M, t, v = getattr(vec, "M", None), getattr(vec, "t", None), getattr(vec, "v", None)
    if isinstance(M, fmpq_mat) and t is not None and v is not None:
        tq, q = t.known_rational(), v.known_rational()
        if tq is not None and q is not None:
            return ("exp", M.nrows(), tuple(M.entries()), tq, tuple(q.entries()))
    return ("id", id(vec))
