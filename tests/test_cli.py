"""cli.py: the lcs-exact command, in-process (``main([...])``) and as ``python -m lcs_exact``:
commands, exact reading of model files, one-line errors with a non-zero exit for every bad input,
partial fixtures when a run stops early (DESIGN.md section 5)."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import mpmath as mp
import pytest
from flint import fmpq
from helpers import mpmath_digits
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lcs_exact as L
from lcs_exact.cli import MAX_DIGITS, MODEL_KEYS, load_model, main

_mp = mpmath_digits(40)
ROOT = Path(__file__).resolve().parents[1]
CARTS = {"A": [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]], "B": [[0], [0], [1], [0]],
         "C": [[1, 0, 0, 0]], "D": [[0]], "name": "two carts"}
OSC = {"A": [[0, 1], [-1, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]], "x0": [1, 0], "t_end": "4",
       "name": "oscillator and stop", "states": ["q", "v"]}


def run(*args: str) -> subprocess.CompletedProcess:
    """``python -m lcs_exact ARGS`` from the worktree root (this checkout's package)."""
    return subprocess.run([sys.executable, "-m", "lcs_exact", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)


def write(tmp_path, obj, name="m.json") -> str:
    p = tmp_path / name
    if isinstance(obj, bytes):
        p.write_bytes(obj)
    else:
        p.write_text(obj if isinstance(obj, str) else json.dumps(obj))
    return str(p)


def one_line_error(err: str) -> bool:
    err = err.strip()
    return err.startswith("lcs-exact") and "\n" not in err and "Traceback" not in err


# ---------------------------------------------------------------------------------------------
# commands
# ---------------------------------------------------------------------------------------------

def test_two_carts_as_a_module():
    """The README's main job: python -m lcs_exact two-carts."""
    p = run("two-carts", "--digits", "12")
    assert p.returncode == 0 and p.stderr == ""
    assert "event t = 1\n" in p.stdout and "= 1 + pi/2" in p.stdout and "2 events, certified" in p.stdout
    assert "triggered by y_0 (stop)" in p.stdout and "triggered by u_0 (stop)" in p.stdout


@pytest.mark.slow
def test_version():
    p = run("--version")
    assert p.returncode == 0 and p.stdout.strip() == f"lcs-exact {L.__version__}"
    assert main(["--version"]) == 0


def test_simulate_with_samples_prints_the_final_state(tmp_path, capsys):
    model, out = write(tmp_path, OSC), tmp_path / "fx.json"
    assert main(["simulate", model, "--digits", "20", "--sample", "1/2", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "x(4) = (0, 0)   [q, v]" in printed and "= pi/2" in printed
    fx = json.loads(out.read_text())
    L.validate_fixture(fx)
    assert fx["sample_step"] == "1/2" and len(fx["samples"]) == 9 and fx["digits"] == 20
    c = Fraction(fx["samples"][1]["x"][0]["value"])  # cos(1/2) to 20 digits
    assert abs(mp.mpf(c.numerator) / c.denominator - mp.cos(0.5)) <= mp.mpf(fx["samples"][1]["x"][0]["error"])


def test_samples_printed_without_output_file(tmp_path, capsys):
    assert main(["simulate", write(tmp_path, OSC), "--digits", "12", "--sample", "1"]) == 0
    out = capsys.readouterr().out.splitlines()
    i = out.index("samples: t  q  v")
    assert out[i + 1] == "0  1  0" and out[i + 2] == f"1  {mp.nstr(mp.cos(1), 12)}  {mp.nstr(-mp.sin(1), 12)}"
    assert out[i + 3:] == ["2  0  0", "3  0  0", "4  0  0"]


@pytest.mark.parametrize("argv", [["--x0", "-1,2", "--t-end", "1"], ["--x0=-1,2", "--t-end=1"]])
def test_negative_x0_without_equals(tmp_path, capsys, argv):
    """--x0 -1,2 is a value, not an option: the initial jump (-1, 2) -> (0, 0) at t = 0."""
    assert main(["simulate", write(tmp_path, OSC)] + argv) == 0
    out = capsys.readouterr().out
    assert "x(t-) = (-1, 2)" in out and "x(1) = (0, 0)" in out


@pytest.mark.slow
def test_negative_x0_as_a_module(tmp_path):
    p = run("select", write(tmp_path, OSC), "--x0", "-1,2")
    assert p.returncode == 0 and "jump to x(0+) = P_I x0 = (0, 0)" in p.stdout


def test_check_report(tmp_path, capsys):
    assert main(["check", write(tmp_path, CARTS)]) == 0
    out = capsys.readouterr().out
    # two carts: H_i = C A^{i-1} B: 0, 0, 1, 0, -2 (Markov parameters (5.8), n = 4)
    for i, h in enumerate([0, 0, 1, 0, -2]):
        assert f"H_{i} = [{h}]" in out
    assert "WELL-POSED" in out and "rho = (2), M = [1]" in out and "eta = (2), N = [1]" in out
    assert "modes: 2 of 2 autonomous" in out


def test_names_from_the_model_file_reach_every_command(tmp_path, capsys):
    """``states`` and ``inputs`` of a model file name the states and pairs in check, select and
    simulate (they were read, checked for length, then dropped)."""
    model = write(tmp_path, {**OSC, "inputs": ["wall"]})
    assert main(["check", model]) == 0
    assert capsys.readouterr().out.startswith(
        "oscillator and stop: n = 2 states (q, v), k = 1 complementarity pairs (wall)")
    assert main(["simulate", model]) == 0
    out = capsys.readouterr().out
    assert "triggered by y_0 (wall)" in out and "[q, v]" in out
    lcs, _ = load_model(model)
    assert (lcs.state_names, lcs.constraint_names) == (("q", "v"), ("wall",))


def test_check_reports_modes_that_are_not_autonomous(tmp_path, capsys):
    # B = 0: G(s) = 0, the mode {0} has Ker[B_I; D_II] != 0 (Lemma 3.3)
    model = {"A": [[0, 1], [0, 0]], "B": [[0], [0]], "C": [[1, 0]], "D": [[0]]}
    assert main(["check", write(tmp_path, model)]) == 0
    out = capsys.readouterr().out
    assert "NOT ESTABLISHED" in out and "modes: 1 of 2 autonomous" in out and "not autonomous {0}" in out


def test_check_summarises_many_modes(tmp_path, capsys):
    k = 9
    model = {"A": [[0]], "B": [[1] * k], "C": [[1]] * k, "D": [[int(i == j) for j in range(k)] for i in range(k)]}
    assert main(["check", write(tmp_path, model)]) == 0
    assert "2^9 = 512 index sets; autonomy not enumerated" in capsys.readouterr().out


@pytest.mark.slow
def test_compare_command(tmp_path, capsys):
    model, fx = write(tmp_path, OSC), tmp_path / "fx.json"
    assert main(["simulate", model, "--digits", "20", "--sample", "1/20", "-o", str(fx)]) == 0
    capsys.readouterr()
    paths = []
    for h, header in ((Fraction(1, 20), True), (Fraction(1, 40), False)):
        # explicit Euler on [0, 1] (before the stop): a first-order method
        q, v, lines = 1.0, 0.0, ["t,q,v"] if header else []
        for k in range(int(1 / h) + 1):
            lines.append(f"{float(k * h)!r},{q!r},{v!r}")
            q, v = q + float(h) * v, v - float(h) * q
        p = tmp_path / f"euler{len(paths)}.csv"
        p.write_text("\n".join(lines) + "\n")
        paths.append(str(p))
    assert main(["compare", str(fx), *paths]) == 0
    out = capsys.readouterr().out
    assert "against the fixture's samples" in out and "order of convergence" in out
    assert main(["compare", str(fx), *paths, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    errs = [float(Fraction(r["max_error"]["value"])) for r in d["reports"]]
    # Euler's order from its own two errors and steps, derived here
    import math
    assert d["order"] == pytest.approx(math.log(errs[0] / errs[1]) / math.log(2), rel=1e-4)  # 6-digit errors
    assert 0.8 < d["order"] < 1.2
    p = run("compare", str(fx), paths[0])
    assert p.returncode == 0 and "max state error" in p.stdout


@pytest.mark.slow
def test_run_stopped_by_a_limit_writes_a_partial_fixture(tmp_path, capsys):
    model, out = write(tmp_path, OSC), tmp_path / "partial.json"
    assert main(["simulate", model, "--max-events", "0", "-o", str(out)]) == 3
    cap = capsys.readouterr()
    assert one_line_error(cap.err) and "max_events = 0" in cap.err and "partial fixture written" in cap.err
    fx = json.loads(out.read_text())
    L.validate_fixture(fx)
    assert fx["partial"] is True and fx["events"] == [] and "LimitExceeded" in fx["stop_reason"]
    p = run("simulate", model, "--time-limit", "1e-9")
    assert p.returncode == 3 and one_line_error(p.stderr) and "time_limit" in p.stderr


def test_run_stopped_before_its_first_phase_writes_its_fixture(tmp_path, capsys):
    """The carts from x0 = (0, 1, -1, 0) jump at t = 0 (cart 0 at the wall moving into it); with
    max_events = 0 the run stops before that jump and before any phase, and still writes the
    partial fixture: no events, final state x0 exactly (it used to fail: 'no continuous phase')."""
    model, out = write(tmp_path, {**CARTS, "x0": [0, 1, -1, 0], "t_end": 5}), tmp_path / "p.json"
    assert main(["simulate", model, "--max-events", "0", "-o", str(out)]) == 3
    assert "partial fixture written" in capsys.readouterr().err
    fx = L.read_fixture(str(out))
    assert fx.partial and len(fx.events) == 0
    assert [c["exact"] for c in json.loads(out.read_text())["final_state"]] == ["0", "1", "-1", "0"]
    tr = L.simulate(L.LCS(CARTS["A"], CARTS["B"], CARTS["C"], CARTS["D"]), [0, 1, -1, 0], 2)
    assert [c.rational() for c in tr.state(0)] == [0, 1, 0, 0]  # x(0+) after the jump, by hand
    sampled = tmp_path / "s.json"  # with samples too: the grid [0] holds x0
    assert main(["simulate", model, "--max-events", "0", "--sample", "1/10", "-o", str(sampled)]) == 3
    capsys.readouterr()
    samples = json.loads(sampled.read_text())["samples"]
    assert [[c["exact"] for c in s["x"]] for s in samples] == [["0", "1", "-1", "0"]]


def test_output_through_a_link_is_written_where_the_link_points(tmp_path, capsys):
    """-o naming a symbolic link to a file not yet there: the pre-run check neither creates the
    target nor removes the link; the fixture is written through the link."""
    target, link = tmp_path / "target.json", tmp_path / "link.json"
    link.symlink_to(target)
    assert main(["simulate", write(tmp_path, OSC), "-o", str(link)]) == 0
    capsys.readouterr()
    assert link.is_symlink() and json.loads(target.read_text())["certified"] is True


def test_outputs_and_sample_counts_are_checked_before_the_run(tmp_path, capsys):
    """A step giving more than MAX_SAMPLES grid points on [0, t_end], and an -o the system refuses
    although its permission bits (as root) say yes, are errors before the run: nothing printed,
    nothing computed."""
    model = write(tmp_path, {**OSC, "t_end": 100000})
    assert main(["simulate", model, "--sample", "1e-9"]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and one_line_error(cap.err) and "100000000000001 grid points" in cap.err
    assert main(["simulate", model, "-o", "/proc/lcs-exact-test.json"]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and one_line_error(cap.err) and "not writable" in cap.err
    existing = tmp_path / "keep.json"
    existing.write_text("old")
    assert main(["simulate", write(tmp_path, OSC, "o.json"), "--max-events", "0", "-o", str(existing)]) == 3
    assert json.loads(existing.read_text())["partial"] is True  # checked, then written once


# ---------------------------------------------------------------------------------------------
# model files are read exactly
# ---------------------------------------------------------------------------------------------

def test_json_and_toml_decimals_are_exact_rationals(tmp_path):
    lcs, data = load_model(write(tmp_path, '{"A": [[1e-400]], "B": [[0.1]], "C": [[1]], "D": [[0]], '
                                           '"x0": [2.5e3], "t_end": 0.3}'))
    assert lcs.A[0, 0] == fmpq(1, 10 ** 400) and lcs.B[0, 0] == fmpq(1, 10)
    assert data["x0"] == [2500] and data["t_end"] == Fraction(3, 10)
    toml = tmp_path / "m.toml"
    toml.write_text('A = [[1e-400]]\nB = [[0.1]]\nC = [[1]]\nD = [["1/3"]]\nx0 = [1_000.5]\nt_end = 0.3\n')
    lcs, data = load_model(str(toml))
    assert lcs.A[0, 0] == fmpq(1, 10 ** 400) and lcs.D[0, 0] == fmpq(1, 3)
    assert data["x0"] == [Fraction(2001, 2)] and data["t_end"] == Fraction(3, 10)


def test_integers_beyond_pythons_digit_limit(tmp_path, capsys):
    """A 5001-digit JSON integer is read exactly (Python's int(str) stops at 4300 digits); TOML
    cannot, and says how to write it instead."""
    big = 10 ** 5000
    path = write(tmp_path, '{"A": [[0, 1], [-1, 0]], "B": [[0], [1]], "C": [[1, 0]], "D": [[0]], "x0": [1'
                 + "0" * 5000 + ', "1/3"]}')
    lcs, data = load_model(path)
    assert L.rational.to_fmpq(data["x0"][0]) == fmpq(big)
    assert main(["select", path]) == 0
    out = capsys.readouterr().out
    assert out.startswith("x0 = (1" + "0" * 5000 + ", 1/3):  S(x0) = {∅}")
    toml = tmp_path / "big.toml"
    toml.write_text("A = [[1" + "0" * 5000 + "]]\nB = [[1]]\nC = [[1]]\nD = [[0]]\n")
    assert main(["check", str(toml)]) == 2
    err = capsys.readouterr().err
    assert one_line_error(err) and "more than 4300 digits" in err and "set_int_max_str_digits" not in err


# ---------------------------------------------------------------------------------------------
# every bad input: one line on stderr, exit 2, no traceback
# ---------------------------------------------------------------------------------------------

NESTED = "[" * 100_000 + "]" * 100_000
BAD_MODELS = [
    ({**CARTS, "colour": "red"}, "unknown key 'colour'"),
    ({**CARTS, "x0": [0, 1]}, "x0 has length 2, expected 4"),
    ([1, 2, 3], "must hold an object with keys A, B, C, D, got a list"),
    ("null", "got null"),
    ("5", "got a number"),
    ({**CARTS, "x0": 5}, "x0 must be a list of numbers, got a number"),
    ({**CARTS, "x0": "0,-1,-1,0"}, "x0 must be a list of numbers, got a string"),
    ({**CARTS, "x0": None}, "got null"),
    (NESTED, "nested too deeply"),
    ('{"A": [[NaN]], "B": [[1]], "C": [[1]], "D": [[0]]}', "NaN is not a finite number"),
    ('{"A": [[1e999999999]], "B": [[1]], "C": [[1]], "D": [[0]]}', "exponent beyond"),
    ({**CARTS, "A": [["1e999999999"] * 4] * 4}, "exponent beyond"),
    ({k: v for k, v in CARTS.items() if k != "D"}, "lacks D"),
    ({**CARTS, "A": 3}, "A must be a list of rows"),
    ({**CARTS, "A": [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, "x"]]}, "A[3, 3]"),
    ({**CARTS, "B": [[True], [0], [0], [0]]}, "B[0, 0] is a bool"),
    ({**CARTS, "C": [[1, 0, 0]]}, "C has shape 1x3, expected 1x4"),
    ({**CARTS, "t_end": [1]}, "t_end must be a number"),
    ({**CARTS, "name": 7}, "name must be a string"),
    ({**CARTS, "states": ["a"]}, "states has 1 names, expected n = 4"),
    ({**CARTS, "states": ["a", "b", "a", "c"]}, "states must be distinct: 'a' occurs more than once"),
    ({**CARTS, "inputs": [""]}, "inputs must be nonempty strings"),
    ({**CARTS, "x0": [[0], -1, -1, 0]}, "x0[0] is a list, not a number"),
    ({**CARTS, "x0": [0, None, -1, 0]}, "x0[1] is null, not a number"),
    ({**CARTS, "A": [[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, [0]]]}, "A[3, 3] is a list"),
    ({**CARTS, "B": [[0], [0], [1], [0], [0]]}, "model file"),
    ({"schema": "lcs-exact/trajectory/1", "system": {}}, "is a fixture (lcs-exact/trajectory/1), not a model file"),
    (b"\xff\xfe{}", "is not UTF-8 text"),
    ("{not json", "model file"),
]


@pytest.mark.parametrize("model, fragment", BAD_MODELS, ids=[f"model{i}" for i in range(len(BAD_MODELS))])
def test_bad_model_files(tmp_path, capsys, model, fragment):
    path = write(tmp_path, model)
    assert main(["check", path]) == 2
    cap = capsys.readouterr()
    assert one_line_error(cap.err) and fragment in cap.err and cap.out == ""


def test_bad_toml(tmp_path, capsys):
    p = tmp_path / "m.toml"
    for text, fragment in (('A = [[nan]]\nB = [[1]]\nC = [[1]]\nD = [[0]]\n', "'nan' is not a finite number"),
                           ('A = [[0]]\nB = [[1]]\nC = [[1]]\nD = [[0]]\nzzz = 1\n', "unknown key 'zzz'"),
                           ("A = [[0]\n", "model file")):
        p.write_text(text)
        assert main(["check", str(p)]) == 2
        err = capsys.readouterr().err
        assert one_line_error(err) and fragment in err


@pytest.mark.parametrize("argv, fragment", [
    (["--digits", "0"], f"must be an integer in 1..{MAX_DIGITS}, got 0"),
    (["--digits", str(MAX_DIGITS + 1)], f"must be an integer in 1..{MAX_DIGITS}"),
    (["--digits", "abc"], "must be an integer, got 'abc'"),
    (["--digits", "-5"], "must be an integer in 1.."),
    (["--max-events", "-1"], "must be >= 0, got -1"),
    (["--time-limit", "0"], "must be a positive number of seconds"),
    (["--time-limit", "-1"], "must be a positive number of seconds"),
    (["--time-limit", "nan"], "must be a positive number of seconds"),
    (["--time-limit", "soon"], "must be a number of seconds"),
    (["--x0", "1,2,3"], "--x0 has length 3, expected 2"),
    (["--x0", "1,abc"], "x0[1]"),
    (["--x0", "1,1e999999999"], "exponent beyond"),
    (["--sample", "0"], "the sample step must be > 0"),
    (["--sample", "abc"], "sample step"),
    (["--t-end", "-1"], "t_end must be >= 0"),
    (["--bogus"], "unrecognized arguments: --bogus"),
])
def test_bad_simulate_arguments(tmp_path, capsys, argv, fragment):
    assert main(["simulate", write(tmp_path, OSC), *argv]) == 2
    cap = capsys.readouterr()
    assert one_line_error(cap.err) and fragment in cap.err


@pytest.mark.parametrize("argv, fragment", [
    ([], "the following arguments are required: COMMAND"),
    (["frobnicate"], "invalid choice: 'frobnicate'"),
    (["check"], "the following arguments are required: model"),
    (["check", "/nonexistent/model.json"], "No such file or directory"),
])
def test_bad_command_lines(capsys, argv, fragment):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert one_line_error(err) and fragment in err


@pytest.mark.slow
def test_bad_inputs_as_a_module(tmp_path):
    """The same through ``python -m lcs_exact``: exit 2, one line, no traceback."""
    for args, fragment in ((["check", write(tmp_path, [1, 2], "list.json")], "got a list"),
                           (["check", write(tmp_path, NESTED, "deep.json")], "nested too deeply"),
                           (["simulate", write(tmp_path, OSC), "--digits", "0"], "must be an integer in 1.."),
                           (["compare", write(tmp_path, {"schema": "x"}, "fx.json"), "nope.csv"], "schema")):
        p = run(*args)
        assert p.returncode == 2 and one_line_error(p.stderr) and fragment in p.stderr, (args, p.stderr)


def test_compare_against_a_partial_fixture(tmp_path, capsys):
    """A run stopped by max_events covers [0, pi/2] only (the impact is the next event): a
    solution on [0, 4] is compared up to there and the rest is counted, not an error."""
    fx = tmp_path / "partial.json"
    assert main(["simulate", write(tmp_path, OSC), "--max-events", "0", "--sample", "1/10", "-o", str(fx)]) == 3
    lines = ["t,q,v"] + [f"{k / 10!r},{math.cos(k / 10)!r},{-math.sin(k / 10)!r}" for k in range(41)]
    (tmp_path / "s.csv").write_text("\n".join(lines) + "\n")
    capsys.readouterr()
    assert main(["compare", str(fx), str(tmp_path / "s.csv"), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)["reports"][0]
    # times 0, 0.1, ..., 1.5 are before pi/2 = 1.5707...: 16 compared; 1.6 ... 4.0 beyond
    assert (r["compared"], r["beyond_last_time"]) == (16, 25)
    with mp.workdps(40):
        half_pi = mp.pi / 2
        v, e = mp.mpf(r["last_time"]["value"]), mp.mpf(r["last_time"]["error"])
        assert v - e <= half_pi <= v + e and e < mp.mpf("1e-16")  # the last time is pi/2
    assert float(Fraction(r["max_error"]["value"])) < 1e-15  # the solver is the exact cosine here
    assert main(["compare", str(fx), str(tmp_path / "s.csv")]) == 0
    assert "25 after the reference's last time 1.5707963267949" in capsys.readouterr().out


def test_bad_compare_inputs(tmp_path, capsys):
    fx = tmp_path / "fx.json"
    assert main(["simulate", write(tmp_path, OSC), "--sample", "1/2", "-o", str(fx)]) == 0
    capsys.readouterr()
    csv = tmp_path / "s.csv"
    for text, fragment in (("t,q\n0,1\n1,0.5\n", "row 0 has 1 values, expected 2"),
                           ("0,1,0\n1,x,0\n", "'x' is not a number"),
                           ("0,1,0\n", "at least 2 rows")):
        csv.write_text(text)
        assert main(["compare", str(fx), str(csv)]) == 2
        err = capsys.readouterr().err
        assert one_line_error(err) and fragment in err, err
    csv.write_text("0,1,0\n0.5,0.9,-0.5\n")
    assert main(["compare", str(fx), str(csv), "--event-tol", "-1"]) == 2
    assert "event_tol must be >= 0" in capsys.readouterr().err


# ---------------------------------------------------------------------------------------------
# fuzzing the model reader
# ---------------------------------------------------------------------------------------------

json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-10 ** 30, 10 ** 30) | st.floats(allow_nan=True)
    | st.text(max_size=12) | st.sampled_from(["1/3", "-2", "0.5", "1e-400", "1e99999", "x", ""]),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=4), inner, max_size=4),
    max_leaves=24)
small_matrix = st.lists(st.lists(st.integers(-3, 3), min_size=1, max_size=3), min_size=1, max_size=3)
models = st.one_of(
    json_values,
    st.fixed_dictionaries({k: small_matrix for k in "ABCD"},
                          optional={k: json_values for k in MODEL_KEYS[4:] + ("other",)}),
)


@pytest.mark.slow
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(models)
def test_fuzz_model_reader(tmp_path, capsys, model):
    """Random JSON as a model file: success or a one-line error with exit 2, never a traceback."""
    path = tmp_path / "fuzz.json"
    path.write_text(json.dumps(model))
    rc = main(["check", str(path)])  # anything not caught by main would raise here
    cap = capsys.readouterr()
    assert rc in (0, 2)
    if rc == 2:
        assert one_line_error(cap.err) and cap.out == ""
    else:
        assert "Theorem 6.3" in cap.out and cap.err == ""


# ---------------------------------------------------------------------------------------------
# issue 15: interrupts, limits at their boundaries, outputs checked before the run
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_sigint_writes_the_partial_fixture(tmp_path):
    """Ctrl-C during a long run: exit 130, one line on stderr, the partial fixture written."""
    import signal
    import time
    model = write(tmp_path, {**CARTS, "x0": [0, 1, -1, 0], "t_end": 100000})
    out = tmp_path / "partial.json"
    # the child must see SIGINT as a terminal does: a parent (a test runner, a process pool) may
    # have left it ignored, and an ignored signal is inherited across exec
    p = subprocess.Popen([sys.executable, "-m", "lcs_exact", "simulate", model, "--max-events", "1000000",
                          "-o", str(out)], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    time.sleep(4)
    p.send_signal(signal.SIGINT)
    try:
        stdout, stderr = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 130 and one_line_error(stderr) and "interrupted" in stderr
    fx = json.loads(out.read_text())
    assert fx["partial"] is True and "interrupted" in fx["stop_reason"] and len(fx["events"]) >= 1
    assert "PARTIAL (interrupted" in stdout


@pytest.mark.slow
def test_limits_at_their_boundaries_and_outputs_checked_first(tmp_path, capsys):
    model = write(tmp_path, {**CARTS, "x0": [0, 1, -1, 0], "t_end": 1})
    # an unwritable output is an input error before the run: nothing is printed of a run
    assert main(["simulate", model, "-o", str(tmp_path / "no" / "such" / "dir.json")]) == 2
    cap = capsys.readouterr()
    assert "does not exist" in cap.err and cap.out == ""
    # a time limit before the first phase: the partial run says so (not 'certified' alone)
    assert main(["simulate", model, "--time-limit", "1e-9"]) == 3
    assert "PARTIAL (time limit" in capsys.readouterr().out
    # a solution time beyond a double's range is a one-line format error
    fx = tmp_path / "fx.json"
    assert main(["simulate", model, "-o", str(fx)]) == 0
    csv = write(tmp_path, "t,x1,x2,x3,x4\n0,0,1,-1,0\n1e400,0,0,0,0\n", "sol.csv")
    capsys.readouterr()
    assert main(["compare", str(fx), csv]) == 2
    assert "beyond the range of a double" in capsys.readouterr().err


@pytest.mark.slow
def test_the_documented_maximum_of_digits_is_accepted(capsys):
    assert main(["two-carts", "--digits", str(MAX_DIGITS)]) == 0
    out = capsys.readouterr().out
    first = out.split("x(3) = (")[1].split(",")[0]  # 0.0128177824...: all significant digits printed
    significant = first.replace("-", "").replace(".", "").lstrip("0").split(" ")[0]
    assert len(significant) == MAX_DIGITS
