"""models.mechanical: (8.3) from M, K, E (damping optional), names, and the old (M, D, K, E) call."""
from __future__ import annotations

import pytest
from flint import fmpq_mat

from lcs_exact.errors import InvalidArgument, ShapeError
from lcs_exact.models import mechanical


def test_one_dof_damped_by_hand():
    # 2 q'' + q' + 4 q = u, y = q:  A = [[0, 1], [-2, -1/2]], B = [[0], [1/2]], C = [1, 0], D = 0
    lcs = mechanical([[2]], [[4]], [[1]], damping=[[1]])
    assert lcs.A == fmpq_mat([[0, 1], [-2, -1]]) + fmpq_mat([[0, 0], [0, 1]]) / 2
    assert lcs.B == fmpq_mat([[0], [1]]) / 2
    assert lcs.C == fmpq_mat([[1, 0]]) and lcs.D == fmpq_mat([[0]])
    assert lcs.state_names == ("q_0", "q_0'") and lcs.constraint_names == ("0",)


def test_two_masses_matches_8_3():
    M, K, E, Dm = [[2, 0], [0, 1]], [[3, -1], [-1, 1]], [[1, -1]], [[1, 0], [0, 0]]
    lcs = mechanical(M, K, E, damping=Dm, q_names=["left", "right"], constraint_names=["gap"], name="pair")
    Minv = fmpq_mat([[1, 0], [0, 2]]) / 2
    assert lcs.A == fmpq_mat([[0, 0, 1, 0], [0, 0, 0, 1],
                              [-(Minv * fmpq_mat(K))[0, 0], -(Minv * fmpq_mat(K))[0, 1], -(Minv * fmpq_mat(Dm))[0, 0], 0],
                              [-(Minv * fmpq_mat(K))[1, 0], -(Minv * fmpq_mat(K))[1, 1], 0, 0]])
    assert lcs.B == fmpq_mat([[0], [0], [1], [-2]]) / 2   # M^{-1} E^T = (1/2, -1)
    assert lcs.C == fmpq_mat([[1, -1, 0, 0]])
    assert lcs.state_names == ("left", "right", "left'", "right'")
    assert lcs.constraint_names == ("gap",) and lcs.name == "pair"
    assert bool(lcs.well_posedness())  # Theorem 8.2: M = N = E M^{-1} E^T = 3/2 > 0


def test_old_call_orders_keep_working():
    M, Dm, K, E = [[1, 0], [0, 1]], [[1, 0], [0, 2]], [[2, -1], [-1, 1]], [[1, 0], [1, -1]]
    new = mechanical(M, K, E, damping=Dm)
    old_positional = mechanical(M, Dm, K, E)
    old_keywords = mechanical(M=M, D=Dm, K=K, E=E)
    for other in (old_positional, old_keywords):
        assert (other.A, other.B, other.C, other.D) == (new.A, new.B, new.C, new.D)
    # the square-E case that positional order alone could not tell apart is read as the old order
    sq = mechanical(M, Dm, K, [[1, 0], [0, 1]])
    assert sq.C == fmpq_mat([[1, 0, 0, 0], [0, 1, 0, 0]]) and sq.A[2, 2] == -1


def test_flat_E_is_one_constraint():
    assert mechanical([[1, 0], [0, 1]], [[2, -1], [-1, 1]], [1, 0]).k == 1


def test_errors():
    M, K, E = [[1, 0], [0, 1]], [[2, -1], [-1, 1]], [[1, 0]]
    with pytest.raises(ShapeError, match="singular"):
        mechanical([[1, 1], [1, 1]], K, E)
    with pytest.raises(ShapeError, match="K has shape"):
        mechanical(M, [[1]], E)
    with pytest.raises(ShapeError, match="E has shape"):
        mechanical(M, K, [[1, 0, 0]])
    with pytest.raises(ShapeError, match="damping has shape"):
        mechanical(M, K, E, damping=[[1]])
    with pytest.raises(InvalidArgument, match="once"):
        mechanical(M, K, E, damping=M, D=M)
    with pytest.raises(InvalidArgument, match="once"):
        mechanical(M, M, K, E, damping=M)
    with pytest.raises(InvalidArgument, match="positional"):
        mechanical(M, M, K, E, E)
    with pytest.raises(ShapeError, match="q_names"):
        mechanical(M, K, E, q_names=["a"])
    with pytest.raises(ShapeError, match="q_names must be"):  # not a bare TypeError
        mechanical(M, K, E, q_names=5)
    with pytest.raises(ShapeError, match="square"):
        mechanical([[1, 0]], K, E)
