"""Feasibility of a system of linear inequalities over Q by Fourier-Motzkin elimination."""
from __future__ import annotations

from fractions import Fraction as Fr


def fm_feasible(nvars, constraints) -> bool:
    """Fourier-Motzkin with strictness: constraints (a, b, rel) mean a . z + b > 0 (rel '>'),
    >= 0 (rel '>='), or = 0 (rel '=', two '>=')."""
    rows = []
    for a, b, rel in constraints:
        a, b = [Fr(v) for v in a], Fr(b)
        if rel == "=":
            rows += [(a, b, False), ([-v for v in a], -b, False)]
        else:
            rows.append((a, b, rel == ">"))
    for j in range(nvars):
        pos = [r for r in rows if r[0][j] > 0]
        neg = [r for r in rows if r[0][j] < 0]
        new = [r for r in rows if r[0][j] == 0]
        for ap, bp, sp in pos:
            for an, bn, sn in neg:
                cp, cn = -an[j], ap[j]  # both positive
                new.append(([cp * x + cn * y for x, y in zip(ap, an)], cp * bp + cn * bn, sp or sn))
        rows = new
    return all((b > 0) if strict else (b >= 0) for _, b, strict in rows)
