"""The cycle of an inelastic collapse: which contacts take turns, and the exact split of the state.

The last events of a run are Newton impacts of single contacts b from a set P, in one mode J of
resting contacts, repeating a pattern b_1 ... b_p (:func:`pattern_of`).  :func:`collapse_cycle`
derives the exact data the proof of :mod:`lcs_exact.accumulations.collapses` needs: the impulse
directions r_b = B_C W_CC^-1 e_b (C = J + {b}, Newton's law pushing the resting contacts, section
8's impact LCP), the gaps and speeds G of P, the basis E of S = span{r_b, A r_b} with G E = I (so
x = x_bg + E G x), the background's generator (I - E G) A, the constant accelerations c_i A^2 and
the rows that must stay positive (resting forces, far gaps) - or None when a condition fails.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

from flint import fmpq_mat

from ..algebra import hstack, identity, image, is_zero, submatrix, vstack
from .accumulation import event_signature

__all__ = ["MAX_PATTERN", "CollapseCycle", "collapse_cycle", "hits", "pattern_of", "push", "row", "turns_suspected"]

#: the longest pattern of contacts looked for (a bead bouncing ~30 times on a stack per landing of the
#: one above it)
MAX_PATTERN = 40


def row(M: fmpq_mat, i: int) -> fmpq_mat:
    """Row i of M, as a 1 x n matrix.

    Parameters
    ----------
    M : fmpq_mat
    i : int
    """
    return submatrix(M, [i], None)


@dataclass(frozen=True)
class CollapseCycle:
    """The exact data of a pattern of impacts at contacts ``P`` (the module docstring)."""

    lcs: Any
    J: frozenset  # the contacts resting between impacts
    pattern: tuple  # positions in P of the contacts hit over one period; pattern[-1] hit last
    P: tuple  # the contacts taking turns
    e: tuple  # their restitution coefficients
    G: fmpq_mat  # 2|P| x n: the gaps c_i, then the speeds c_i A
    E: fmpq_mat  # n x 2|P|: G E = I, x = (I - E G) x + E G x
    W: fmpq_mat  # |P| x |P|: W[i, j] = c_i A r_j, the speed of gap i an impact of j adds per unit
    acc: fmpq_mat  # |P| x n: c_i A^2 (the gaps' accelerations, acc x = acc x_bg)
    monitors: tuple  # rows that must stay positive: resting forces F_J, far gaps
    Abg: fmpq_mat  # (I - E G) A: x_bg' = Abg x_bg on the flights (0 on V_J: a background at rest)
    moving: bool  # Abg is not 0 on V_J (a body falling beside the collapse)

    @property
    def background(self) -> fmpq_mat:
        """I - E G: x -> x_bg, the part of the state the impacts keep and the flights move alone."""
        return identity(self.lcs.n) - self.E * self.G


def hits(events: Sequence) -> list:
    """[(J, b)] of the last events that are single Newton impacts of a contact b in one mode J of
    resting contacts (J before and after, the chain one set with one contact more than J)."""
    out = []
    for ev in reversed(events[-4 * MAX_PATTERN:]):
        J, chain, after, triggers = event_signature(ev)
        J = frozenset(J or ())
        if after != J or len(chain) != 1 or len(chain[0] - J) != 1:
            break
        b = next(iter(chain[0] - J))
        if triggers != (f"y_{b}",) or (out and out[-1][0] != J):
            break
        out.append((J, b))
    return out[::-1]


def pattern_of(events: Sequence) -> tuple | None:
    """(J, contacts hit in order over one period) when the last events are single Newton impacts
    in one mode J of resting contacts repeating with a period of 2..MAX_PATTERN and at least two
    contacts, else None."""
    found = hits(events)
    seq = [b for _, b in found]
    for p in range(2, MAX_PATTERN + 1):  # the last 3p impacts repeat with period p
        if len(seq) >= 3 * p and len(set(seq[-p:])) > 1 and all(seq[-j] == seq[-j - p] for j in range(1, 2 * p + 1)):
            return found[0][0], tuple(seq[-p:])
    return None


def turns_suspected(events: Sequence) -> bool:
    """The last 24 events are single Newton impacts of two to four contacts taking turns in one
    mode of resting contacts: a collapse may be forming (its pattern not yet repeated).  Only the
    last 24 count: in a column of beads the beads above collide among themselves before the two
    lowest start taking turns.

    Parameters
    ----------
    events : sequence of Event
    """
    found = hits(events)[-24:]
    return len(found) == 24 and 2 <= len({b for _, b in found}) <= 4


def collapse_cycle(lcs, events: Sequence) -> CollapseCycle | None:
    """The exact data of the pattern the last events repeat (the module docstring), or None when
    they repeat none or a condition fails: 0 < e_b < 1, D = 0 on the contacts involved, Theorem
    6.3, W_CC^-1 e_b >= 0, S = span{r_b, A r_b} of dimension 2|P| with G invertible on it and A S
    in S, constant accelerations (c_i A^2 E = 0, c_i A^2 Abg = 0).

    Parameters
    ----------
    lcs : LCS
        The system, with Newton's restitution.
    events : sequence of Event
        The run's events so far.
    """
    rest = getattr(lcs, "restitution", None)
    found = pattern_of(events) if rest is not None and len(events) >= 6 else None
    if found is None:
        return None
    J, seq = found
    P = tuple(sorted(set(seq)))
    if any(not 0 < rest[b] < 1 for b in P) or any(lcs.D[i, j] != 0 for i in list(J) + list(P) for j in range(lcs.k)):
        return None
    if not lcs.well_posedness():
        return None
    mode = lcs.mode(J)
    A = mode.closed_loop() if J else lcs.A
    K = mode.consistent_subspace() if J else identity(lcs.n)
    rs = [push(lcs, J, b) for b in P]
    if any(r is None for r in rs):
        return None
    G = vstack(*[row(lcs.C, b) for b in P], *[row(lcs.C, b) * A for b in P])
    S = image(hstack(*rs, *[A * r for r in rs], nrows=lcs.n))
    if S.ncols() != 2 * len(P) or (G * S).det() == 0:
        return None
    E = S * (G * S).inv()
    bg = identity(lcs.n) - E * G
    acc = vstack(*[row(lcs.C, b) * A * A for b in P])
    Abg = bg * A
    if not (is_zero(bg * A * E) and is_zero(acc * E) and is_zero(acc * Abg * K)):
        return None  # the fast part feeds the background, or the accelerations vary (a spring)
    W = fmpq_mat([[(row(lcs.C, i) * lcs.A * r)[0, 0] for r in rs] for i in P])
    F, I = (mode.feedback(), list(mode.I)) if J else (None, [])
    monitors = tuple(row(F, k) for k in range(len(I))) + tuple(
        row(lcs.C, i) + submatrix(lcs.D, [i], I) * F if I else row(lcs.C, i)
        for i in range(lcs.k) if i not in P and i not in J)
    return CollapseCycle(lcs, J, tuple(P.index(b) for b in seq), P, tuple(rest[b] for b in P), G, E, W, acc,
                         monitors, Abg, not is_zero(Abg * K))


def push(lcs, J: frozenset, b: int) -> fmpq_mat | None:
    """r_b = B_C W_CC^-1 e_b (C = J + {b}, every closed contact: the impact's LCP) when W_CC^-1 e_b
    >= 0 with its b-th entry > 0 (the resting contacts pushed or untouched, their speeds kept at 0),
    else None."""
    closed = sorted(J | {b})
    W = submatrix(lcs.C * lcs.A * lcs.B, closed, closed)
    if W.det() == 0:
        return None
    z = W.inv() * fmpq_mat([[int(i == b)] for i in closed])
    if any(z[i, 0] < 0 for i in range(len(closed))) or z[closed.index(b), 0] <= 0:
        return None
    return submatrix(lcs.B, None, closed) * z
