"""Linear RLC networks with ideal diodes as LCSs (the paper's sections 1 and 9: electrical
networks with ideal diodes, each diode switching between conducting and blocking).

Input: a netlist in the style of SPICE, one element per line (or a sequence of tuples)::

    name  node+  node-  [value]

The first letter of ``name`` is the kind: ``R`` (resistance, ohm), ``L`` (inductance, henry),
``C`` (capacitance, farad), ``D`` (ideal diode: anode = node+, cathode = node-, no value),
``V`` (voltage source: e(node+) - e(node-) = w(t)), ``I`` (current source: w(t) flows from node+
through the source to node-).  Values of R, L, C are exact positive rationals (``1/2``, ``0.25``,
``3``); a source's value is a rational (DC), a :class:`~lcs_exact.sources.Source` (in the tuple
form of a netlist) or text such as ``sine(100, 10)``, ``cosine(2)``, ``exponential(-1, 5)``,
``constant(5) + sine(1, 2)`` (:mod:`lcs_exact.sources`).  Node ``0`` is ground and must occur;
lines starting with ``*`` or ``#`` are comments.

State.  x = (capacitor voltages v(C) = e(node+) - e(node-), inductor currents i(L) flowing
node+ -> node- through the inductor), in netlist order; named ``v(C1)``, ``i(L1)``.

Complementarity pairs, one per diode (named after it).  An ideal diode has a current i_D >= 0
(anode -> cathode), a reverse voltage -v_D = e(cathode) - e(anode) >= 0 and i_D (-v_D) = 0.
Which of the two is the LCS input u is fixed by a *normal tree* (a spanning tree taking
capacitors first, then resistors, then diodes, then inductors):

* a diode outside the tree is a current port:  u = i_D,   y = -v_D (reverse voltage);
* a diode in the tree is a voltage port:       u = -v_D,  y = i_D.

Both satisfy 0 <= y ⊥ u >= 0; the tree choice is what makes (A, B, C, D) exist (a diode in
series with an inductor must be a voltage port: its current is the inductor's state).
:func:`circuit_ports` says which convention each diode got.  Every capacitor must be in the
tree and every inductor outside it (no loop of capacitors, no cutset of inductors: their
voltages / currents would not be independent states); such circuits are refused with a
:class:`~lcs_exact.errors.Unsupported` error naming the elements.  Voltage sources come first
in the tree and current sources last, outside it (a loop of voltage sources or a cutset of
current sources is refused likewise).  Sources enter as x' = A x + B u + E w(t),
y = C x + D u + F w(t): the LCS carries them by exosystem states (:mod:`lcs_exact.exosystems`),
and ``lcs.embed(x)`` appends their initial state.

Equations: Kirchhoff's laws on the node potentials, the branch laws v = R i, i = C v',
v = L i', and the port definitions, solved exactly for (x', y) in terms of (x, u).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

from flint import fmpq, fmpq_mat

from ..errors import NotRational, ShapeError, Unsupported
from .exosystems import extend
from ..algebra import to_fmpq
from ..system import Source, as_source, constant, cosine, exponential, exosystem, polynomial, sine
from ..system import LCS

__all__ = ["circuit", "circuit_ports", "Element", "Port", "parse_netlist"]

_KINDS = {"R": "resistor", "L": "inductor", "C": "capacitor", "D": "diode", "V": "voltage source",
          "I": "current source"}
_SOURCE_FUNCS = {"sine": sine, "cosine": cosine, "exponential": exponential, "constant": constant,
                 "polynomial": lambda *cs: polynomial(cs)}


@dataclass(frozen=True)
class Element:
    """One netlist element: ``kind`` in R, L, C, D, V, I; nodes ``plus`` -> ``minus``; ``value``
    (None for D; a :class:`~lcs_exact.sources.Source` for V and I)."""

    name: str
    kind: str
    plus: str
    minus: str
    value: Any


@dataclass(frozen=True)
class Port:
    """The complementarity pair of a diode: what u and y are (``"current"`` port: u = i_D,
    y = -v_D; ``"voltage"`` port: u = -v_D, y = i_D)."""

    name: str
    kind: str
    u: str
    y: str


def parse_netlist(netlist: Any) -> tuple[Element, ...]:
    """Read a netlist (a string of lines, or a sequence of (name, node+, node-[, value])).

    >>> [e.kind for e in parse_netlist("C1 1 0 1\\nL1 1 0 1\\nD1 1 2\\nR1 2 0 1/2")]
    ['C', 'L', 'D', 'R']
    """
    if isinstance(netlist, str):
        items = []
        for num, line in enumerate(netlist.splitlines(), 1):
            line = line.strip()
            if not line or line[0] in "*#":
                continue
            items.append((num, line.split()))
    else:
        try:
            items = [(num, list(e) if not isinstance(e, str) else e.split()) for num, e in enumerate(netlist, 1)]
        except TypeError:
            raise ShapeError(f"a netlist is a string or a sequence of elements, got {type(netlist).__name__}") from None
    out, seen = [], set()
    for num, parts in items:
        where = f"netlist element {num} ({' '.join(str(p) for p in parts)!r})"
        if len(parts) < 3:
            raise ShapeError(f"{where}: expected 'name node+ node- [value]'")
        name = str(parts[0])
        kind = name[:1].upper()
        if kind not in _KINDS:
            raise ShapeError(f"{where}: the name must start with R, L, C, D, V or I (the element kind), got {name!r}")
        if name in seen:
            raise ShapeError(f"{where}: element name {name!r} is used twice")
        seen.add(name)
        plus, minus = str(parts[1]), str(parts[2])
        if plus == minus:
            raise ShapeError(f"{where}: both terminals on node {plus!r}")
        if kind == "D":
            if len(parts) != 3:
                raise ShapeError(f"{where}: an ideal diode takes no value ('D1 anode cathode')")
            out.append(Element(name, kind, plus, minus, None))
            continue
        if kind in "VI":
            if len(parts) < 4:
                raise ShapeError(f"{where}: a {_KINDS[kind]} needs a value (a number or a source)")
            out.append(Element(name, kind, plus, minus, _source_value(parts[3:], where)))
            continue
        if len(parts) != 4:
            raise ShapeError(f"{where}: a {_KINDS[kind]} needs exactly one value")
        value = to_fmpq(parts[3], f"value of {name}")
        if value <= 0:
            raise ShapeError(f"{where}: the {_KINDS[kind]} value must be positive, got {value}")
        out.append(Element(name, kind, plus, minus, value))
    if not out:
        raise ShapeError("the netlist has no elements")
    nodes = {e.plus for e in out} | {e.minus for e in out}
    if "0" not in nodes:
        raise ShapeError("the netlist has no ground node '0'")
    return tuple(out)


def _source_value(parts: list, where: str) -> Source:
    """A source from the value fields of a V or I element: a Source, a rational, or text such as
    ``sine(100, 10)`` or ``constant(5) + sine(1, 2)`` (one field or several, joined)."""
    if len(parts) == 1 and isinstance(parts[0], Source):
        return parts[0]
    text = " ".join(str(p) for p in parts)
    out = as_source(0)
    for term in _split_terms(text):
        term = term.strip()
        if "(" not in term:
            try:
                out = out + to_fmpq(term, "source value")
            except NotRational:
                raise ShapeError(f"{where}: cannot read the source value {term!r} (a number, or sine(omega, "
                                 "amplitude), cosine(...), exponential(rate, amplitude), constant(c))") from None
            continue
        fname, _, rest = term.partition("(")
        fn = _SOURCE_FUNCS.get(fname.strip())
        if fn is None or not rest.endswith(")"):
            raise ShapeError(f"{where}: unknown source {term!r}: use sine(omega, amplitude), cosine(omega, "
                             "amplitude), exponential(rate, amplitude), constant(c) or polynomial(c0, c1, ...)")
        args = [a.strip() for a in rest[:-1].split(",") if a.strip()]
        try:
            out = out + fn(*args)
        except TypeError:
            raise ShapeError(f"{where}: wrong number of arguments in {term!r}") from None
    return out


def _split_terms(text: str) -> list[str]:
    """Split 'a + b(1, 2) + c' at the top-level '+' signs."""
    terms, depth, cur = [], 0, ""
    for ch in text:
        depth += ch == "("
        depth -= ch == ")"
        if ch == "+" and depth == 0 and cur.strip():
            terms.append(cur)
            cur = ""
        else:
            cur += ch
    terms.append(cur)
    return [t for t in terms if t.strip()]


def _normal_tree(elements: Sequence[Element]) -> set[str]:
    """Names of the tree branches: Kruskal on the priority V, C, R, D, L, I (a normal tree)."""
    parent: dict[str, str] = {}

    def find(a):
        while parent.setdefault(a, a) != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    tree = set()
    for kind in "VCRDLI":
        for e in elements:
            if e.kind == kind:
                ra, rb = find(e.plus), find(e.minus)
                if ra != rb:
                    parent[ra] = rb
                    tree.add(e.name)
    roots = {find(v) for e in elements for v in (e.plus, e.minus)}
    if len(roots) > 1:
        far = sorted({v for e in elements for v in (e.plus, e.minus) if find(v) != find("0")})
        raise ShapeError(f"the circuit is not connected: nodes {far} have no path to ground '0'")
    return tree


def _structure(elements: Sequence[Element]):
    tree = _normal_tree(elements)
    vloops = [e.name for e in elements if e.kind == "V" and e.name not in tree]
    if vloops:
        raise Unsupported(f"voltage sources {vloops} close a loop of voltage sources: their voltages are "
                          "not independent; merge them or add a series resistor")
    loops = [e.name for e in elements if e.kind == "C" and e.name not in tree]
    if loops:
        caps = [e.name for e in elements if e.kind in "CV"]
        raise Unsupported(f"capacitors {loops} close a loop of capacitors and voltage sources (of {caps}): "
                          "their voltages are not independent states; merge parallel capacitors or add a "
                          "series resistor")
    cuts = [e.name for e in elements if e.kind == "L" and e.name in tree]
    if cuts:
        raise Unsupported(f"inductors {cuts} lie in a cutset of inductors (and current sources): their "
                          "currents are not independent states; merge series inductors or add a parallel resistor")
    icuts = [e.name for e in elements if e.kind == "I" and e.name in tree]
    if icuts:
        raise Unsupported(f"current sources {icuts} lie in a cutset of current sources: their currents are "
                          "not independent; add a parallel resistor")
    ports = []
    for e in elements:
        if e.kind == "D":
            if e.name in tree:
                ports.append(Port(e.name, "voltage", f"-v({e.name})", f"i({e.name})"))
            else:
                ports.append(Port(e.name, "current", f"i({e.name})", f"-v({e.name})"))
    return tree, tuple(ports)


def circuit_ports(netlist: Any) -> tuple[Port, ...]:
    """Which of (current, reverse voltage) is u and which is y for each diode (module docstring).

    Parameters
    ----------
    netlist : str
        The netlist, in :func:`circuit`'s format.

    >>> [(p.name, p.u, p.y) for p in circuit_ports("C1 1 0 1\\nL1 1 0 1\\nD1 1 2\\nR1 2 0 1")]
    [('D1', 'i(D1)', '-v(D1)')]
    >>> [(p.name, p.u, p.y) for p in circuit_ports("C1 1 0 1\\nL1 1 2 1\\nD1 2 0")]
    [('D1', '-v(D1)', 'i(D1)')]
    """
    return _structure(parse_netlist(netlist))[1]


def circuit(netlist: Any, *, name: str | None = None) -> LCS:
    """The LCS of a linear RLC network with ideal diodes (see the module docstring).

    Parameters
    ----------
    netlist : str or sequence
        SPICE-style lines ``name node+ node- [value]`` (R, L, C with a positive rational value;
        D anode cathode), or a sequence of such tuples.  Node ``0`` is ground.
    name : str, optional

    Returns
    -------
    LCS
        States ``v(C..)``, ``i(L..)`` in netlist order; one complementarity pair per diode,
        named after it, with the port convention of :func:`circuit_ports`.

    Examples
    --------
    A capacitor discharging through a diode into a resistor: u = i_D = v/R while conducting,
    y = R u - v (the reverse voltage), so D = R:

    >>> rc = circuit("C1 1 0 1/2\\nD1 1 2\\nR1 2 0 3")
    >>> rc.A, rc.B, rc.C, rc.D
    ([0], [-2], [-1], [3])
    >>> rc.state_names, rc.constraint_names
    (('v(C1)',), ('D1',))
    """
    elements = parse_netlist(netlist)
    _, ports = _structure(elements)
    net = _Network(elements, ports)
    if net.ns == 0:
        raise Unsupported("the circuit has no capacitor or inductor: an LCS needs at least one state")
    if net.k == 0:
        raise Unsupported("the circuit has no diode: an LCS needs at least one complementarity pair")
    Z = _solved_network(net, _kirchhoff_rows(net) + _branch_law_rows(net))
    A, B, E = _state_equation(net, Z)
    Cm, Dm, F = _port_outputs(net, Z)
    names = tuple(f"v({e.name})" if e.kind == "C" else f"i({e.name})" for e in net.states)
    cnames = tuple(p.name for p in ports)
    # in the mode (y = 0): a current port's reverse voltage is 0 (conducting), a voltage port's
    # current is 0 (blocking)
    roles = tuple((p.u, p.y, "conducting", "blocking") if p.kind == "current" else (p.u, p.y, "blocking", "conducting")
                  for p in ports)
    if net.nw == 0:
        return LCS(A, B, Cm, Dm, name=name, state_names=names, constraint_names=cnames, roles=roles)
    ex = exosystem([e.value for e in net.sources])
    return extend(A, B, Cm, Dm, E * ex.W, F * ex.W, ex, name=name, state_names=names, constraint_names=cnames,
                  roles=roles)


class _Network:
    """A netlist's unknowns and knowns, numbered.  Unknowns: the node potentials e (nn), the
    branch voltages v (nb), the branch currents i (nb), the state derivatives x' (ns), at offsets
    0, ``V``, ``I``, ``XD``; knowns: the states x (ns: capacitor voltages, inductor currents), the
    diode ports u (k) and the sources w (nw)."""

    def __init__(self, elements: Sequence[Element], ports: tuple):
        self.elements, self.ports = elements, ports
        self.nodes = sorted({v for e in elements for v in (e.plus, e.minus)} - {"0"})
        self.node_ix = {v: i for i, v in enumerate(self.nodes)}
        self.states = [e for e in elements if e.kind in "CL"]
        self.st_ix = {e.name: i for i, e in enumerate(self.states)}
        self.port_ix = {p.name: i for i, p in enumerate(ports)}
        self.ports_by = {p.name: p for p in ports}
        self.sources = [e for e in elements if e.kind in "VI"]
        self.src_ix = {e.name: i for i, e in enumerate(self.sources)}
        self.nn, self.nb, self.ns = len(self.nodes), len(elements), len(self.states)
        self.k, self.nw = len(ports), len(self.sources)
        self.V, self.I, self.XD = self.nn, self.nn + self.nb, self.nn + 2 * self.nb
        self.nz = self.nn + 2 * self.nb + self.ns


#: one circuit equation: (unknowns, x, u, w) coefficients, the unknowns' side equal to the sum of the others
_Row = tuple[dict, dict, dict, dict]


def _kirchhoff_rows(net: _Network) -> list[_Row]:
    """Kirchhoff's laws: KCL at each node (the currents leaving it sum to zero), KVL on each
    branch (v_b = e(plus) - e(minus))."""
    rows: list[_Row] = []
    V, I = net.V, net.I
    for v in net.nodes:  # KCL: sum of currents leaving the node is zero
        c = {}
        for b, e in enumerate(net.elements):
            if e.plus == v:
                c[I + b] = c.get(I + b, 0) + 1
            if e.minus == v:
                c[I + b] = c.get(I + b, 0) - 1
        rows.append((c, {}, {}, {}))
    for b, e in enumerate(net.elements):  # KVL: v_b = e(plus) - e(minus)
        c = {V + b: fmpq(1)}
        if e.plus != "0":
            c[net.node_ix[e.plus]] = c.get(net.node_ix[e.plus], 0) - 1
        if e.minus != "0":
            c[net.node_ix[e.minus]] = c.get(net.node_ix[e.minus], 0) + 1
        rows.append((c, {}, {}, {}))
    return rows


def _branch_law_rows(net: _Network) -> list[_Row]:
    """Each element's law: Ohm's (v = R i), a capacitor's (v = x, i = C x'), an inductor's (i = x,
    v = L x'), a source's (v or i = w) and a diode's port (i = u for a current port, v = -u for a
    voltage port)."""
    rows: list[_Row] = []
    V, I, XD = net.V, net.I, net.XD
    for b, e in enumerate(net.elements):  # branch laws
        if e.kind == "R":
            rows.append(({V + b: 1, I + b: -e.value}, {}, {}, {}))
        elif e.kind == "C":
            s = net.st_ix[e.name]
            rows.append(({V + b: 1}, {s: 1}, {}, {}))
            rows.append(({I + b: 1, XD + s: -e.value}, {}, {}, {}))
        elif e.kind == "L":
            s = net.st_ix[e.name]
            rows.append(({I + b: 1}, {s: 1}, {}, {}))
            rows.append(({V + b: 1, XD + s: -e.value}, {}, {}, {}))
        elif e.kind == "V":
            rows.append(({V + b: 1}, {}, {}, {net.src_ix[e.name]: 1}))
        elif e.kind == "I":
            rows.append(({I + b: 1}, {}, {}, {net.src_ix[e.name]: 1}))
        else:
            p = net.port_ix[e.name]
            if net.ports_by[e.name].kind == "current":
                rows.append(({I + b: 1}, {}, {p: 1}, {}))
            else:
                rows.append(({V + b: 1}, {}, {p: -1}, {}))
    return rows


def _solved_network(net: _Network, rows: list[_Row]) -> fmpq_mat:
    """Z (nz x (ns + k + nw)): every unknown as a linear map of (x, u, w), from the circuit
    equations M_z z = R (x, u, w)."""
    nz, ns, k, nw = net.nz, net.ns, net.k, net.nw
    if len(rows) != nz:
        raise ShapeError(f"internal inconsistency: {len(rows)} circuit equations for {nz} unknowns")
    Mz = fmpq_mat(nz, nz)
    R = fmpq_mat(nz, ns + k + nw)
    for r, (c, cx, cu, cw) in enumerate(rows):
        for j, v in c.items():
            Mz[r, j] = v
        for j, v in cx.items():
            R[r, j] = v
        for j, v in cu.items():
            R[r, ns + j] = v
        for j, v in cw.items():
            R[r, ns + k + j] = v
    if Mz.rank() < nz:
        raise Unsupported("the circuit equations do not determine the branch voltages and currents "
                          "from the states and the diode ports (a degenerate network)")
    return Mz.solve(R)  # every unknown as a linear map of (x, u, w)


def _state_equation(net: _Network, Z: fmpq_mat) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat]:
    """(A, B, E) of x' = A x + B u + E w: the rows of Z for the state derivatives."""
    ns, k, nw, XD = net.ns, net.k, net.nw, net.XD
    A = fmpq_mat(ns, ns, [Z[XD + i, j] for i in range(ns) for j in range(ns)])
    B = fmpq_mat(ns, k, [Z[XD + i, ns + j] for i in range(ns) for j in range(k)])
    E = fmpq_mat(ns, nw, [Z[XD + i, ns + k + j] for i in range(ns) for j in range(nw)])
    return A, B, E


def _port_outputs(net: _Network, Z: fmpq_mat) -> tuple[fmpq_mat, fmpq_mat, fmpq_mat]:
    """(C, D, F) of y = C x + D u + F w: y = -v_D for a current port, y = i_D for a voltage port."""
    ns, k, nw = net.ns, net.k, net.nw
    Cm, Dm, F = fmpq_mat(k, ns), fmpq_mat(k, k), fmpq_mat(k, nw)
    for b, e in enumerate(net.elements):
        if e.kind != "D":
            continue
        p = net.port_ix[e.name]
        # y = -v_D for a current port, y = i_D for a voltage port
        row, sign = (net.V + b, -1) if net.ports_by[e.name].kind == "current" else (net.I + b, 1)
        for j in range(ns):
            Cm[p, j] = sign * Z[row, j]
        for j in range(k):
            Dm[p, j] = sign * Z[row, ns + j]
        for j in range(nw):
            F[p, j] = sign * Z[row, ns + k + j]
    return Cm, Dm, F
