"""The test oracles (tests/reference) stay independent of the library, and the exact linear
algebra they share checks out on values known by hand."""
from __future__ import annotations

import ast
import pathlib
from fractions import Fraction

from reference.linalg import det, inverse, is_P, mm, nullspace, rank, same_span, solve, span_le

REFERENCE = pathlib.Path(__file__).parent / "reference"


def test_reference_modules_do_not_import_the_library():
    modules = sorted(REFERENCE.glob("*.py"))
    assert {p.stem for p in modules} >= {"__init__", "linalg", "polynomials", "rcp", "lcp", "polyhedra",
                                         "mechanics", "flows"}
    for path in modules:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else []
            assert not any(n == "lcs_exact" or n.startswith("lcs_exact.") for n in names), (path.name, names)


def test_exact_linear_algebra_by_hand():
    a = [[2, 1, 0], [1, 2, 1], [0, 1, 2]]             # det = 2*3 - 1*2 = 4, leading minors 2, 3, 4
    assert det(a) == 4 and is_P(a) and rank(a) == 3
    assert mm(a, inverse(a)) == [[int(i == j) for j in range(3)] for i in range(3)]
    assert solve(a, [1, 0, 0]) == [Fraction(3, 4), Fraction(-1, 2), Fraction(1, 4)]
    assert det([[0, 1], [1, 0]]) == -1 and not is_P([[0, 1], [1, 0]])   # a row swap; m11 = 0
    b = [[1, 2, 3], [2, 4, 6]]                        # rank 1: x + 2y + 3z = 0
    assert rank(b) == 1 and solve([[1, 2], [2, 4]], [1, 2]) is None
    ker = nullspace(b, 3)
    assert same_span(ker, [[-2, 1, 0], [-3, 0, 1]]) and all(v == 0 for k in ker for r in mm(b, [[x] for x in k]) for v in r)
    assert span_le([[1, 1, 0]], [[1, 0, 0], [0, 1, 0]]) and not span_le([[0, 0, 1]], [[1, 0, 0], [0, 1, 0]])
