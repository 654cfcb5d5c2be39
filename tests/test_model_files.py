"""Model files with sources, restitution and roles (lcs_exact.modelfile, lcs_exact.system.modelformat,
``LCS.to_model``, ``lcs_exact.read_model``, the source text of lcs_exact.sources).

The round trip is checked on every builder's scene: the LCS read back has the same exact data and
its run the same events.  The command runs the two scenes written by hand in docs/model-files.md;
their event times are derived here: the ball dropped from h = 1 under g = 981/100 lands at
sqrt(2h/g); the rectifier's diode (v = sin t while it conducts, C = R = 1) carries the current
i = C v' + v/R = cos t + sin t, which vanishes first at the root found here by mpmath."""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import mpmath as mp
import pytest
import sympy
from flint import fmpq, fmpq_mat
from hypothesis import given, settings
from hypothesis import strategies as st

import lcs_exact as L
from lcs_exact import examples, models
from lcs_exact.cli import main
from lcs_exact.modelfile import load_model, read_model_data
from lcs_exact.sources import (AppendedStates, constant, cosine, exosystem, exponential, parse_source, polynomial,
                               sine, state_signals)

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "model-files.md").read_text(encoding="utf-8")


def doc_file(tmp_path, name: str) -> Path:
    """The TOML block of docs/model-files.md that begins with ``# name``, written to tmp_path."""
    m = re.search(r"```toml\n(# " + re.escape(name) + r"\n.*?)```", PAGE, re.S)
    assert m, name
    p = tmp_path / name
    p.write_text(m.group(1), encoding="utf-8")
    return p


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "lcs_exact", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)


# ---------------------------------------------------------------------------------------------
# round trips: every builder's scene, its data and its run
# ---------------------------------------------------------------------------------------------

def _mech_sine():
    return models.mechanical([[1]], [[1]], [[1]], force=[sine(2, 3) + constant(-1)],
                             gap=[polynomial([0, "1/10", "1/10"])], restitution="1/2", q_names=["h"],
                             constraint_names=["floor"])


def _mech_damped():
    return models.mechanical([[2, 0], [0, 1]], [[2, -1], [-1, 1]], [[1, 0], [1, -1]], damping=[["1/10", 0], [0, 0]],
                             force=[constant(-1), exponential(-1, 2)], gap=[0, "1/10"], restitution=[0, "1/2"])


def _circuit():
    return models.circuit([("V1", "in", "0", constant(1) + sine(2, "1/2")), ("D1", "in", "out"),
                           ("R1", "out", "0", 1), ("C1", "out", "0", "1/2")], name="RC with a biased sine")


def _driven():
    return models.driven([[-1]], [[1]], [[1]], [[1]], F=[[-1]], w=[sine(1) + exponential(-1, 2)],
                         state_names=["v"], constraint_names=["D"])


def _compliant():
    return models.mechanical([[1]], [[0]], [[1], [-1]], force=[-10], gap=[0, 2], compliance=[0, "1/100"],
                             restitution=["1/2", None], q_names=["q"], constraint_names=["floor", "ceiling"])


def _relay_belt():
    return models.relay([[0, 1], [-4, 0]], [[0], ["-3/2"]], [[0, 1]], E=[[0], [1]], F=[[-1]],
                        sources=[sine(1, "1/2") + constant("1/2")], state_names=["q", "v"], relay_names=["friction"])


# (builder, plant x0, t_end)
SCENES = {
    "bouncing_ball": (examples.bouncing_ball, [1, 0], 1),
    "two_carts": (examples.two_carts, [0, 1, -1, 0], 2),
    "two_carts_with_hook": (examples.two_carts_with_hook, [0, 0, -1, 2], 1),
    "cart_chain": (lambda: examples.cart_chain(3), ["1/2", "-1/2", "1/2", 0, 0, 0], 2),
    "ball_column": (lambda: examples.ball_column(2), [1, 2, 0, 0], "1/2"),
    "newtons_cradle": (examples.newtons_cradle, [0, 1, 2, 1, 0, 0], 2),
    "newtons_cradle_gap": (lambda: examples.newtons_cradle(3, gap="1/10"), [0, "11/10", "22/10", 1, 0, 0], 2),
    "ball_on_spring": (examples.ball_on_spring, [1, 0], 2),
    "half_wave_rectifier": (examples.half_wave_rectifier, [0, -1], 4),
    "diode_bridge": (examples.diode_bridge, [1, 0], 4),
    "sine_rectifier": (examples.sine_rectifier, [0], 4),
    "sine_rectifier_full_wave": (lambda: examples.sine_rectifier(full_wave=True), [0], 2),
    "diode_bridge_cap_filter": (examples.diode_bridge_cap_filter, [10, 0, 0], "1/1000"),
    "filippov_spiral": (examples.filippov_spiral, [1, 2], 1),
    "mechanical_sine_force_gap": (_mech_sine, [1, 0], 3),
    "mechanical_damped": (_mech_damped, [1, "1/2", 0, 0], 2),
    "circuit": (_circuit, [0], 2),
    "relay": (lambda: models.relay([[0]], [[-1]], [[1]]), [1], 2),
    "relay_belt": (_relay_belt, [0, "1/2"], 2),
    "mechanical_compliant": (_compliant, [1, 7], 1),
    "driven": (_driven, [0], 3),
}


def same_system(a: L.LCS, b: L.LCS) -> None:
    assert (a.A, a.B, a.C, a.D) == (b.A, b.B, b.C, b.D)
    assert a.restitution == b.restitution and a.name == b.name and a.roles == b.roles
    assert a.state_names == b.state_names and a.constraint_names == b.constraint_names
    assert a.plant == b.plant
    sa, sb = a.sources, b.sources
    assert (sa is None) == (sb is None)
    if sa is not None:
        assert sa.states == sb.states and sa.S == sb.S and sa.z0 == sb.z0
        assert sa.expressions == sb.expressions and sa.names == sb.names


@pytest.mark.parametrize("suffix", [".toml", ".json"])
@pytest.mark.parametrize("scene", sorted(SCENES))
def test_round_trip_keeps_the_exact_data(tmp_path, scene, suffix):
    build, x0, t_end = SCENES[scene]
    lcs = build()
    path = lcs.to_model(tmp_path / f"m{suffix}", x0=x0, t_end=t_end)
    back, data = load_model(str(path))
    same_system(lcs, back)
    same_system(lcs, L.read_model(str(path)))
    assert back.embed(x0) == lcs.embed(x0) and back.embed(data["x0"]) == lcs.embed(x0)
    assert ("w" in data) == (lcs.sources is not None)
    if lcs.roles is not None:   # the modes read in the builder's words after the round trip
        assert back.describe_mode({0}) == lcs.describe_mode({0})


def _events(traj):
    return [(e.mode_before, e.mode_after, tuple(e.modes)) for e in traj.events]


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_round_trip_runs_the_same_events(tmp_path, scene):
    build, x0, t_end = SCENES[scene]
    lcs = build()
    back = L.read_model(str(lcs.to_model(tmp_path / "m.toml")))
    a = L.simulate(lcs, lcs.embed(x0), t_end, digits=15)
    b = L.simulate(back, back.embed(x0), t_end, digits=15)
    assert _events(a) == _events(b)
    assert all(ea.time.ball(15).overlaps(eb.time.ball(15)) for ea, eb in zip(a.events, b.events))
    assert a.certified == b.certified


def test_round_trip_scenes_have_events():
    """The runs above compare something: the fast scenes with sources have events before t_end."""
    for scene in ("bouncing_ball", "sine_rectifier", "filippov_spiral", "relay", "mechanical_sine_force_gap",
                  "relay_belt", "mechanical_compliant"):
        build, x0, t_end = SCENES[scene]
        lcs = build()
        assert L.simulate(lcs, lcs.embed(x0), t_end, digits=10).events, scene


def test_every_example_builder_is_in_the_round_trip():
    scheduled = {"buck_converter"}  # data that switch at scheduled times: a model file holds one system
    assert all(any(scene.startswith(name) for scene in SCENES) for name in examples.__all__ if name not in scheduled)
    with pytest.raises(L.Unsupported, match="one system"):
        examples.buck_converter().to_model("unused.json")


def test_written_file_reads_as_the_driven_system_it_states(tmp_path):
    """The plant block, E = A[plant, J], F = C[:, J] and one atom per exosystem state: written by
    hand here for the sine-forced oscillator with a growing gap."""
    lcs = _mech_sine()
    data = read_model_data(str(lcs.to_model(tmp_path / "m.json", x0=[1, 0])))
    # h'' = -h + 3 sin 2t - 1 + u, y = h + t/10 + t^2/10; exosystem (1, t, t^2/2, sin 2t, cos 2t)
    assert data["A"] == [[0, 1], [-1, 0]] and data["B"] == [[0], [1]] and data["C"] == [[1, 0]]
    assert data["E"] == [[0, 0, 0, 0, 0], [-1, 0, 0, 3, 0]]
    assert data["F"] == [[0, "1/10", "1/5", 0, 0]]        # t^2/10 = (1/5) (t^2/2)
    assert data["w"] == ["constant(1)", "polynomial([0, 1])", "polynomial([0, 0, '1/2'])", "sine(2)", "cosine(2)"]
    assert data["restitution"] == "1/2" and data["x0"] == [1, 0]
    assert data["states"] == ["h", "h'", "1", "t", "t^2/2", "sin(2t)", "cos(2t)"]


def test_plant_names_alone_get_the_sources_names(tmp_path):
    p = tmp_path / "m.json"
    p.write_text(json.dumps({"A": [[-1]], "B": [[1]], "C": [[1]], "D": [[1]], "F": [[-1]], "w": ["sine(1)"],
                             "states": ["v"]}))
    assert L.read_model(str(p)).state_names == ("v", "sin(t)", "cos(t)")
    p.write_text(json.dumps({"A": [[-1]], "B": [[1]], "C": [[1]], "D": [[1]], "F": [[-1]], "w": [-2]}))
    lcs = L.read_model(str(p))   # a bare number is a constant source
    assert lcs.state_names == ("x_0", "1") and lcs.C == fmpq_mat([[1, 2]])


# ---------------------------------------------------------------------------------------------
# appended states that are not atoms: refused, never approximated
# ---------------------------------------------------------------------------------------------

def _appended(S, z0, extra_A=None):
    """A one-state plant x' = -x + (first appended state), with the block (S, z0) appended."""
    m = len(S)
    A = [[-1] + [1] + [0] * (m - 1)] + [[(extra_A or [0] * m)[i]] + list(S[i]) for i in range(m)]
    B = [[1]] + [[0]] * m
    C = [[1] + [0] * m]
    names = ("x",) + tuple(f"z{i}" for i in range(m))
    return L.LCS(A, B, C, [[1]], state_names=names, embedding=AppendedStates(1, z0, names[1:]))


@pytest.mark.parametrize("S, z0, why", [
    ([[0]], [2], "own initial value"),                       # the constant 2, not the atom 1
    ([[0, 1], [-1, 0]], [1, 0], "own initial value"),        # (cos t, -sin t)
    ([[1, 1], [0, 1]], [0, 1], "not made of the blocks"),    # a Jordan block: t e^t is no atom here
    ([[0, 0], [0, 0]], [1, 1], "own initial value"),         # the atom 1 twice
])
def test_appended_states_that_are_not_atoms_are_refused(tmp_path, S, z0, why):
    lcs = _appended(S, z0)
    assert lcs.sources is not None
    with pytest.raises(L.Unsupported, match=why) as err:
        lcs.to_model(tmp_path / "m.toml")
    assert "LCS(lcs.A, lcs.B, lcs.C, lcs.D)" in str(err.value) and not (tmp_path / "m.toml").exists()


def test_embeddings_a_file_cannot_carry_are_refused(tmp_path):
    plant_driven = _appended([[0]], [1], extra_A=[1])   # x enters the appended state: no exosystem
    assert plant_driven.sources is None
    with pytest.raises(L.Unsupported, match="not one"):
        plant_driven.to_model(tmp_path / "m.json")
    custom = L.LCS([[0]], [[1]], [[1]], [[0]], embedding=lambda x: x)
    with pytest.raises(L.Unsupported, match="embedding"):
        custom.to_model(tmp_path / "m.json")


def test_atoms_with_their_own_values_round_trip(tmp_path):
    """An LCS built by hand with the builder's block (z0 = each atom's own value) is carried."""
    lcs = _appended([[0, 3], [-3, 0]], [0, 1])
    back = L.read_model(str(lcs.to_model(tmp_path / "m.toml", x0=["1/3"])))
    same_system(lcs, back)
    assert back.sources.expressions == ("sin(3*t)", "cos(3*t)")


# ---------------------------------------------------------------------------------------------
# source text
# ---------------------------------------------------------------------------------------------

rationals = st.fractions(min_value=-999, max_value=999, max_denominator=50)  # bounded: no filter to trip the health check
nonzero = rationals.filter(lambda q: q != 0)
atoms = st.one_of(
    st.builds(constant, rationals),
    st.builds(lambda cs: polynomial(cs), st.lists(rationals, min_size=1, max_size=5)),
    st.builds(exponential, nonzero, rationals),
    st.builds(sine, nonzero, rationals),
    st.builds(cosine, nonzero, rationals),
)
source_sums = st.lists(atoms, min_size=1, max_size=4).map(lambda xs: sum(xs[1:], xs[0]))


@settings(max_examples=150, deadline=None)
@given(source_sums)
def test_the_repr_of_a_source_parses_back_to_it(w):
    assert parse_source(repr(w)) == w


def test_huge_integers_parse_back():
    """Python's parser refuses integer literals of 4300 digits or more: the repr quotes them."""
    w = constant(10 ** 5000) + sine(3 ** 9000, -(7 ** 5000))
    assert parse_source(repr(w)) == w


@pytest.mark.parametrize("text, expected", [
    ("sine(100, 10)", sine(100, 10)),
    ("cosine('1/2', amplitude=4)", cosine(fmpq(1, 2), 4)),
    ("constant(-981/100)", constant(fmpq(-981, 100))),
    ("polynomial([0, 2])", polynomial([0, 2])),
    ("exponential(-1, 3)", exponential(-1, 3)),
    ("constant(1) + sine(2, amplitude=3)", constant(1) + sine(2, 3)),
    ("-3/4", constant(fmpq(-3, 4))),
    ("0.1", constant(fmpq(1, 10))),                       # the decimal, not the double nearest to it
    ("2 * sine(3) - cosine(3) / 4", sine(3, 2) + cosine(3, fmpq(-1, 4))),
    ("-(sine(1) + 1)", sine(1, -1) + constant(-1)),
    ("'1/2' * exponential(rate=-2)", exponential(-2, fmpq(1, 2))),
])
def test_source_text(text, expected):
    assert parse_source(text) == expected


@pytest.mark.parametrize("text, fragment", [
    ("__import__('os').system('true')", "is not a source"),
    ("sin(2)", "'sin' is not a source"),
    ("sine(2) * sine(3)", "not by a source"),
    ("sine(2) ** 2", "is not allowed"),
    ("sine(0)", "omega = 0"),
    ("sine(2, phase=1)", "no argument 'phase'"),
    ("polynomial(3)", "a list of coefficients"),
    ("constant('x')", "not a rational number"),
    ("1 / 0", "division by 0"),
    ("sine(", "not an expression"),
    ("t", "'t' is not a source"),
])
def test_source_text_refused(text, fragment):
    with pytest.raises((L.InvalidArgument, L.NotRational), match=re.escape(fragment)):
        parse_source(text)


@settings(max_examples=60, deadline=None)
@given(source_sums)
def test_state_signals_solve_the_exosystem(w):
    """Each state's signal is z_i(t) = (e^{St} z0)_i: at t = 0 it is z0, and its derivative is
    (S z)_i (checked with SymPy on the signals' expressions)."""
    ex = exosystem([w])
    sig = state_signals(ex.S, ex.z0)
    assert sig is not None and len(sig) == ex.size
    t = sympy.Symbol("t", real=True)
    z = [s.to_sympy() for s in sig]
    q = lambda v: sympy.Rational(int(v.p), int(v.q))  # noqa: E731
    for i in range(ex.size):
        assert sympy.simplify(z[i].subs(t, 0) - q(ex.z0[i, 0])) == 0
        rhs = sum((q(ex.S[i, j]) * z[j] for j in range(ex.size)), sympy.Integer(0))
        assert sympy.simplify(sympy.diff(z[i], t) - rhs) == 0


# ---------------------------------------------------------------------------------------------
# the writer's syntax: names of any text, numbers exact
# ---------------------------------------------------------------------------------------------

names = st.text(st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=8)


@settings(max_examples=60, deadline=None)
@given(st.lists(names, min_size=2, max_size=2, unique=True), names, names)
def test_names_of_any_text_round_trip(tmp_path_factory, states, pair, title):
    lcs = L.LCS([[0, 1], [-1, 0]], [[0], [1]], [[1, 0]], [[0]], name=title, state_names=states,
                constraint_names=[pair], roles=[(pair, "y " + pair, "in\n", 'out"\\')])
    d = tmp_path_factory.mktemp("names")
    for suffix in (".toml", ".json"):
        same_system(lcs, L.read_model(str(lcs.to_model(d / f"m{suffix}"))))


def test_numbers_are_written_exactly(tmp_path):
    big = 2 ** 70
    lcs = L.LCS([[fmpq(1, 3), big], [-big, "-7/2"]], [[0], [1]], [[1, 0]], [[0]])
    for suffix in (".toml", ".json"):
        path = lcs.to_model(tmp_path / f"m{suffix}", x0=["1/7", 1], t_end="1e-3")
        data = read_model_data(str(path))
        assert data["A"] == [["1/3", str(big)], [str(-big), "-7/2"]]   # beyond 64 bits: a string
        assert data["x0"] == ["1/7", 1] and data["t_end"] == "1/1000"
        assert L.read_model(str(path)).A == lcs.A


def test_to_model_x0_is_the_plant_state(tmp_path):
    ball = examples.bouncing_ball()
    with pytest.raises(L.ShapeError, match="plant"):
        ball.to_model(tmp_path / "m.toml", x0=[1, 0, 1])
    with pytest.raises(L.NotRational):
        ball.to_model(tmp_path / "m.toml", x0=[L.simulate(ball, ball.embed([1, 0]), "1/10").state("1/10")[0], 0])


# ---------------------------------------------------------------------------------------------
# the hand-written files of docs/model-files.md through the command
# ---------------------------------------------------------------------------------------------

def test_the_docs_ball_is_the_bouncing_ball_and_lands_at_sqrt_2h_over_g(tmp_path):
    path = doc_file(tmp_path, "ball.toml")
    lcs, data = load_model(str(path))
    ref = examples.bouncing_ball()   # g = 981/100, e = 9/10
    assert (lcs.A, lcs.B, lcs.C, lcs.D, lcs.restitution) == (ref.A, ref.B, ref.C, ref.D, ref.restitution)
    assert lcs.state_names == ("q", "q'", "1") and lcs.plant == (0, 1)
    h, g = mp.mpf(1), mp.mpf(981) / 100
    with mp.workdps(40):
        t1 = mp.sqrt(2 * h / g)
        digits = mp.nstr(t1, 25, strip_zeros=False)
    assert digits.startswith("0.4515236409857309")
    p = run("simulate", str(path), "--digits", "20")
    assert p.returncode == 0, p.stderr
    first = re.search(r"event t = (\S+)", p.stdout).group(1)
    assert first[:20] == digits[:20]       # 18 correct digits at least: the rounding is the run's
    assert "1 events, certified" in p.stdout and "triggered by y_0 (floor)" in p.stdout


def test_the_docs_rectifier_turns_off_where_the_diode_current_vanishes(tmp_path):
    path = doc_file(tmp_path, "rectifier.toml")
    lcs = L.read_model(str(path))
    ref = examples.sine_rectifier()
    assert (lcs.A, lcs.B, lcs.C, lcs.D, lcs.roles) == (ref.A, ref.B, ref.C, ref.D, ref.roles)
    assert lcs.state_names == ("v(C1)", "sin(t)", "cos(t)")
    with mp.workdps(40):
        t_off = mp.findroot(lambda t: mp.cos(t) + mp.sin(t), 2)   # i(D1) = C v' + v / R with v = sin t
        digits = mp.nstr(t_off, 25, strip_zeros=False)
    assert t_off > 0 and mp.cos(t_off / 2) > 0   # the first positive zero (t < pi)
    p = run("simulate", str(path), "--digits", "20")
    assert p.returncode == 0, p.stderr
    first = re.search(r"event t = (\S+)", p.stdout).group(1)
    assert first[:20] == digits[:20]
    assert "triggered by u_0 (D1)" in p.stdout and "[v(C1), sin(t), cos(t)]" in p.stdout
    # --x0 is the plant's state too: one entry
    p = run("simulate", str(path), "--digits", "10", "--x0", "1/2", "--t-end", "1")
    assert p.returncode == 0, p.stderr
    p = run("simulate", str(path), "--x0", "0,0,1")
    assert p.returncode == 2 and "expected 1 (the plant's states v(C1)" in p.stderr


def test_check_and_select_read_files_with_sources(tmp_path, capsys):
    ball, rect = doc_file(tmp_path, "ball.toml"), doc_file(tmp_path, "rectifier.toml")
    assert main(["check", str(rect)]) == 0
    out = capsys.readouterr().out
    assert "n = 3 states (v(C1), sin(t), cos(t))" in out and "WELL-POSED" in out
    assert main(["select", str(rect)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("x0 = (0, 0, 1):  S(x0) = {{0}}")   # (v, sin 0, cos 0): the diode conducts
    assert main(["select", str(ball), "--x0", "0,-1"]) == 0     # on the floor, falling: an impact
    out = capsys.readouterr().out
    assert "x0 = (0, -1, 1)" in out and "jump to x(0+)" in out


@pytest.mark.parametrize("change, fragment", [
    ({"E": [[0], [1]]}, "E needs w"),
    ({"w": ["sine(1)"]}, "w needs E or F"),
    ({"w": [], "F": [[1]]}, "w is empty"),
    ({"w": "sine(1)", "F": [[1]]}, "w must be a list of sources"),
    ({"w": [["sine(1)"]], "F": [[1]]}, "w[0] is a list"),
    ({"w": ["sin(1)"], "F": [[1]]}, "w[0]: source text 'sin(1)'"),
    ({"w": ["sine(1)"], "F": [[1, 2]]}, "F"),
    ({"w": ["sine(1)"], "F": [[1]], "x0": [0, 0, 1]}, "x0 has length 3, expected 2 (the plant's states"),
    ({"w": ["sine(1)"], "F": [[1]], "states": ["a", "b", "c"]}, "states has 3 names, expected 2"),
    ({"restitution": 2}, "must be in [0, 1]"),
    ({"restitution": [0, 1]}, "restitution has 2 coefficients"),
    ({"restitution": True}, "restitution must be a number"),
    ({"roles": [["a", "b", "c"]]}, "roles must be a list of"),
    ({"roles": [["a", "b", "c", "d"]] * 2}, "roles has 2 entries, expected k = 1"),
    ({"E": [[0], ["1e99999"]], "w": [1]}, "exponent"),
])
def test_bad_files_with_sources(tmp_path, capsys, change, fragment):
    model = {"A": [[0, 1], [0, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]]}
    model.update(change)
    path = tmp_path / "m.json"
    path.write_text(json.dumps(model))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("lcs-exact: error: model file") and err.count("\n") == 1, err
    assert fragment in err and str(path) in err, err


# ---------------------------------------------------------------------------------------------
# the command's defects: compare given a model file; help for the positional arguments
# ---------------------------------------------------------------------------------------------

def test_compare_says_what_a_solution_is(tmp_path, capsys):
    model = tmp_path / "model.json"
    model.write_text(json.dumps({"A": [[0, 1], [-1, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]],
                                 "x0": [1, 0], "t_end": 4}, indent=2))
    fx = tmp_path / "fx.json"
    assert main(["simulate", str(model), "-o", str(fx)]) == 0
    capsys.readouterr()
    assert main(["compare", str(fx), str(model)]) == 2
    err = capsys.readouterr().err
    assert "line 2 has" not in err and err.count("\n") == 1
    assert "expected a CSV solution (a row per time: t, then one column per state, 3 columns" in err
    assert "got a JSON model file" in err
    assert main(["compare", str(fx), str(fx)]) == 2
    assert "got a fixture (lcs-exact/trajectory/1)" in capsys.readouterr().err
    assert main(["compare", str(model), str(fx)]) == 2
    assert "expected a fixture, got a JSON model file" in capsys.readouterr().err
    toml = doc_file(tmp_path, "ball.toml")
    assert main(["compare", str(fx), str(toml)]) == 2
    assert "got a TOML model file" in capsys.readouterr().err
    csv = tmp_path / "s.csv"
    csv.write_text("t,x1,x2\n0,1,0\n0.5,0.9,-0.5,7\n")
    assert main(["compare", str(fx), str(csv)]) == 2
    err = capsys.readouterr().err
    assert "line 3 has 4 columns, expected 3" in err and "a CSV solution has a row per time" in err


@pytest.mark.parametrize("command, positionals", [
    ("simulate", ["model"]), ("select", ["model"]), ("check", ["model"]),
    ("compare", ["fixture", "solutions"]), ("zoo", ["DIR"]),
])
def test_positional_arguments_have_help(capsys, command, positionals):
    assert main([command, "--help"]) == 0
    out = capsys.readouterr().out
    section = out.split("positional arguments:")[1].split("options:")[0]
    for name in positionals:
        line = re.search(rf"^  {name}\b(.*)$", section, re.M)
        assert line and len(line.group(1).strip()) > 10, (command, name, section)
