"""models.circuit: netlists of R, L, C and ideal diodes; every LCS checked against a hand derivation."""
from __future__ import annotations

from fractions import Fraction as Fr

import pytest
from lcs_exact import LCSError
from lcs_exact.errors import NotRational, ShapeError, Unsupported
from lcs_exact.models import circuit, circuit_ports


def data(lcs):
    """(A, B, C, D) as lists of Fractions."""
    return tuple([[Fr(str(m[i, j])) for j in range(m.ncols())] for i in range(m.nrows())]
                 for m in (lcs.A, lcs.B, lcs.C, lcs.D))


def test_capacitor_diode_resistor():
    # C v' = -i_D (the diode current leaves node 1); i_D = u; y = v2 - v1 = R u - v
    lcs = circuit("C1 1 0 1/2\nD1 1 2\nR1 2 0 3")
    assert data(lcs) == ([[0]], [[-2]], [[-1]], [[3]])
    assert lcs.state_names == ("v(C1)",) and lcs.constraint_names == ("D1",)


def test_tank_with_diode_and_load():
    # C v' = -i_L - u, L i_L' = v, y = R u - v
    C, L, R = Fr(1, 3), Fr(2), Fr(5)
    lcs = circuit([("C1", "1", "0", C), ("L1", "1", "0", L), ("D1", "1", "2"), ("R1", "2", "0", R)])
    assert data(lcs) == ([[0, -1 / C], [1 / L, 0]], [[-1 / C], [0]], [[-1, 0]], [[R]])
    assert lcs.state_names == ("v(C1)", "i(L1)")


def test_diode_in_series_with_inductor_is_a_voltage_port():
    # C1 1-0, L1 1->2, D1 2->0: the diode current is the inductor's current (a state), so the
    # diode is a voltage port: u = -v_D = -e(2), y = i_D = i_L; C v' = -i_L, L i_L' = v + u
    net = "C1 1 0 1\nL1 1 2 1/2\nD1 2 0"
    lcs = circuit(net)
    assert data(lcs) == ([[0, -1], [2, 0]], [[0], [2]], [[0, 1]], [[0]])
    (port,) = circuit_ports(net)
    assert (port.kind, port.u, port.y) == ("voltage", "-v(D1)", "i(D1)")
    assert bool(lcs.well_posedness())


def test_two_diodes_by_hand():
    # D2 (0 -> 1) is a freewheeling diode across C: y_1 = -v_D2 = v, and it feeds node 1: C v' = -u0 + u1
    R, C = Fr(2), Fr(1, 4)
    lcs = circuit(f"C1 1 0 {C}\nD1 1 2\nR1 2 0 {R}\nD2 0 1")
    assert data(lcs) == ([[0]], [[-1 / C, 1 / C]], [[-1], [1]], [[R, 0], [0, 0]])
    assert [p.kind for p in circuit_ports(f"C1 1 0 {C}\nD1 1 2\nR1 2 0 {R}\nD2 0 1")] == ["current", "current"]
    assert bool(lcs.well_posedness())  # M = [[R, 0], [-1/C, 1/C]]


def test_netlist_syntax():
    a = circuit("* a comment\n\n# another\nC1 1 0 0.5\nD1 1 2\nR1 2 0 3\n")
    b = circuit([("C1", 1, 0, "1/2"), ("D1", 1, 2), ("R1", 2, 0, 3)])
    c = circuit(["C1 1 0 1/2", "D1 1 2", "R1 2 0 3"])
    assert data(a) == data(b) == data(c)


@pytest.mark.parametrize("net, match", [
    ("", "no elements"),
    ("X1 1 0 1", "must start with R, L, C, D, V or I"),
    ("C1 1 0", "needs exactly one value"),
    ("C1 1 0 1 2", "needs exactly one value"),
    ("D1 1 0 1\nC1 1 0 1", "takes no value"),
    ("C1 1 0 -1\nD1 1 0", "must be positive"),
    ("C1 1 0 0\nD1 1 0", "must be positive"),
    ("C1 1 1 1\nD1 1 0", "both terminals"),
    ("C1 1 0 1\nC1 1 0 2\nD1 1 0", "used twice"),
    ("C1 1 2 1\nD1 1 2", "no ground"),
    ("C1 1 0 1\nD1 1 0\nR1 5 6 1", "not connected"),
    ("C1 1", "expected 'name node\\+ node- \\[value\\]'"),
])
def test_netlist_errors(net, match):
    with pytest.raises(ShapeError, match=match):
        circuit(net)


def test_value_not_rational():
    with pytest.raises(NotRational, match="value of R1"):
        circuit("C1 1 0 1\nD1 1 2\nR1 2 0 1k")


def test_unsupported_topologies():
    with pytest.raises(Unsupported, match="loop of capacitors"):
        circuit("C1 1 0 1\nC2 1 0 2\nD1 1 2\nR1 2 0 1")
    with pytest.raises(Unsupported, match="cutset of inductors"):
        circuit("L1 1 2 1\nL2 2 0 1\nC1 1 3 1\nD1 3 0")
    with pytest.raises(Unsupported, match="no diode"):
        circuit("C1 1 0 1\nR1 1 0 1")
    with pytest.raises(Unsupported, match="no capacitor or inductor"):
        circuit("D1 1 0\nR1 1 0 1")
    err = pytest.raises(NotImplementedError, circuit, "C1 1 0 1\nC2 1 0 2\nD1 1 0").value
    assert isinstance(err, LCSError)
