"""zoo.py and ``lcs-exact zoo``: the suite of certified fixtures.  The whole suite is written once
(default settings, as a user runs it); every fixture is checked against the shipped JSON Schema,
read back, and its provenance rebuilds its system; the values of several problems are checked
against derivations written here (mpmath, by hand): the two carts of section 7, the bouncing
ball, Filippov's spiral, Newton's cradle, the RLC-diode rectifier and the stiff RC-diode network."""
from __future__ import annotations

import importlib
import json
import re
import time
from fractions import Fraction
from importlib.resources import files

import jsonschema
import mpmath as mp
import pytest

import lcs_exact as L
from lcs_exact.verify import zoo
from lcs_exact.cli import main

SCHEMA = json.loads(files("lcs_exact").joinpath("schemas", "trajectory-1.schema.json").read_text())


@pytest.fixture(scope="module")
def full(tmp_path_factory):
    """The whole zoo at the command's defaults (20 digits, 100 grid intervals per problem)."""
    d = tmp_path_factory.mktemp("zoo")
    t0 = time.perf_counter()
    status = main(["zoo", str(d)])
    elapsed = time.perf_counter() - t0
    assert status == 0
    index = json.loads((d / "index.json").read_text())
    fixtures = {e["name"]: json.loads((d / e["file"]).read_text()) for e in index["problems"]}
    return d, index, fixtures, elapsed


def close(num: dict, true, slack=mp.mpf(10) ** -45) -> bool:
    """|value - true| <= error (the fixture's promise), true computed here to 60 digits."""
    return abs(mp.mpf(num["value"]) - true) <= mp.mpf(num["error"]) + slack


def grid(fx) -> list[Fraction]:
    return [Fraction(s["t"]["exact"]) for s in fx["samples"]]


# ---------------------------------------------------------------------------------------------
# the suite as written
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_every_problem_is_written_validated_and_read_back(full):
    d, index, fixtures, elapsed = full
    print(f"zoo: {len(fixtures)} problems in {elapsed:.1f} s")
    assert index["suite"] == zoo.SUITE and index["fixture_schema"] == "lcs-exact/trajectory/1"
    assert index["lcs_exact_version"] == L.__version__ and index["digits"] == 20 and index["samples"] == 100
    assert [e["name"] for e in index["problems"]] == [p.name for p in zoo.PROBLEMS]
    assert sorted(p.name for p in d.iterdir()) == sorted(["index.json", "README.md"] + [f"{p.name}.json"
                                                                                       for p in zoo.PROBLEMS])
    validator = jsonschema.Draft202012Validator(SCHEMA)
    for entry in index["problems"]:
        fx = fixtures[entry["name"]]
        validator.validate(fx)          # the schema file itself, with every sample
        L.validate_fixture(fx)          # and the checks a schema cannot make
        back = L.read_fixture(str(d / entry["file"]))
        n, k = len(fx["system"]["A"]), len(fx["system"]["C"])
        assert (back.lcs.n, back.lcs.k, entry["n"], entry["k"]) == (n, k, n, k)
        assert len(back.events) == entry["events"] == len(fx["events"])
        assert entry["closed_forms"] == sum(e["time"]["exact"] is not None for e in fx["events"])
        assert fx["certified"] and not fx["partial"] and entry["validated"] and fx["digits"] == 20
        assert entry["digest"] == fx["digest"] and entry["samples_digest"] == fx["samples_digest"]
        # the grid: t_end / 100, 101 exact sample times
        t_end = Fraction(entry["t_end"])
        assert Fraction(fx["sample_step"]) == t_end / 100 == back.sample_step
        assert grid(fx) == [t_end * i / 100 for i in range(101)]
        assert back.provenance == fx["provenance"] == entry["provenance"]


@pytest.mark.slow
def test_provenance_rebuilds_the_system_and_x0(full):
    _, index, fixtures, _ = full
    for entry in index["problems"]:
        fx, pv = fixtures[entry["name"]], fixtures[entry["name"]]["provenance"]
        assert pv["suite"] == zoo.SUITE and pv["problem"] == entry["name"] and pv["lcs_exact_version"] == L.__version__
        module, _, fn = pv["builder"].rpartition(".")
        lcs = getattr(importlib.import_module(module), fn)(**pv["parameters"])   # from the JSON alone
        for key in "ABCD":
            m = getattr(lcs, key)
            assert fx["system"][key] == [[str(m[i, j]) for j in range(m.ncols())] for i in range(m.nrows())]
        assert Fraction(pv["t_end"]) == Fraction(fx["t_end"]["exact"])
        m = re.fullmatch(r"(embed\()?\[(.*)\]\)?", pv["x0"])
        if m is not None:                                  # a rational x0, written out
            vals = [Fraction(v.strip().strip('"')) for v in m.group(2).split(",")]
            x0 = [Fraction(str(c)) for c in (lcs.embed(vals) if m.group(1) else vals)]
            assert [Fraction(c["exact"]) for c in fx["x0"]] == x0
        else:
            assert pv["x0"] == "expm_action(A, -1, [0, -1, -1, 0])" and entry["name"] == "two_carts"


@pytest.mark.slow
def test_readme_table_and_index_agree_with_the_fixtures(full):
    d, index, fixtures, _ = full
    text = (d / "README.md").read_text()
    assert zoo.SUITE in text and "| problem | n | k | events |" in text
    for name, fx in fixtures.items():
        row = re.search(rf"^\| \[{name}\]\({name}\.json\) \|(.*)\|$", text, re.M)
        assert row is not None, name
        n, k, events, accumulations, digits, closed, samples, cert = [c.strip() for c in row.group(1).split("|")]
        assert (int(n), int(k), int(events), int(accumulations), int(digits), int(samples)) == (
            len(fx["system"]["A"]), len(fx["system"]["C"]), len(fx["events"]), len(fx["accumulations"]), 20,
            len(fx["samples"]))
        assert int(closed) == sum(e["time"]["exact"] is not None for e in fx["events"]) and cert == "yes"
        assert f"**{name}**" in text and fx["provenance"]["builder"] in text


# ---------------------------------------------------------------------------------------------
# values against independent derivations
# ---------------------------------------------------------------------------------------------

A_CARTS = mp.matrix([[0, 0, 1, 0], [0, 0, 0, 1], [-2, 1, 0, 0], [1, -1, 0, 0]])


def carts_state(t):
    """Section 7 by hand: x(t) = e^{A(t-1)}(0,-1,-1,0) up to the impact at t = 1, which stops the
    left cart (velocity 0); on the stop the right cart swings, q1 = -cos(t-1), until the contact
    force u = -q1 vanishes at t = 1 + pi/2 with x = (0, 0, 0, 1); then free motion from there."""
    t = mp.mpf(t)
    if t <= 1:
        return mp.expm(A_CARTS * (t - 1)) * mp.matrix([0, -1, -1, 0])
    if t <= 1 + mp.pi / 2:
        return mp.matrix([0, -mp.cos(t - 1), 0, mp.sin(t - 1)])
    return mp.expm(A_CARTS * (t - 1 - mp.pi / 2)) * mp.matrix([0, 0, 0, 1])


@pytest.mark.slow
def test_two_carts_against_section_7(full):
    fx = full[2]["two_carts"]
    e1, e2 = fx["events"]
    assert e1["time"]["exact"] == "1" and close(e1["time"], 1)
    assert [c["exact"] for c in e1["state_before"]] == ["0", "-1", "-1", "0"]
    assert [c["exact"] for c in e1["state_after"]] == ["0", "-1", "0", "0"]        # P_{1}: the impact
    assert (e1["mode_before"], e1["modes"], e1["mode_after"]) == ([], [[0]], [0])
    assert close(e2["time"], 1 + mp.pi / 2) and e2["mode_after"] == [] and e2["modes"] == []
    assert [c["exact"] for c in e2["state_after"]] == ["0", "0", "0", "1"]
    for s in fx["samples"] + [{"t": fx["final_time"], "x": fx["final_state"]}]:
        want = carts_state(mp.mpf(Fraction(s["t"]["exact"]).numerator) / Fraction(s["t"]["exact"]).denominator)
        assert all(close(c, want[i]) for i, c in enumerate(s["x"])), s["t"]


@pytest.mark.slow
def test_two_carts_fixture_passes_the_testing_helper_with_independent_values(full):
    d, _, fixtures, _ = full
    ts = [Fraction(s["t"]["exact"]) for s in fixtures["two_carts"]["samples"]]
    X = [[float(v) for v in carts_state(mp.mpf(t.numerator) / t.denominator)] for t in ts]
    from lcs_exact.testing import assert_matches_fixture
    assert_matches_fixture(str(d / "two_carts.json"), ts, X, atol=1e-14)
    X[37][1] += 1e-9                    # a solver off by 1e-9 is caught
    with pytest.raises(AssertionError):
        assert_matches_fixture(str(d / "two_carts.json"), ts, X, atol=1e-12)


@pytest.mark.slow
def test_bouncing_ball_against_free_flights(full):
    """g = 9.81, e = 0.9, dropped from h = 1 at rest: first impact at t1 = sqrt(2h/g) with speed
    sqrt(2gh); flight k (k >= 1) starts at s_k = t1 (1 + 2e + ... + 2e^(k-1)) with upward speed
    e^k sqrt(2gh); the impacts accumulate at t1 (1 + e)/(1 - e), after which the ball rests."""
    fx = full[2]["bouncing_ball"]
    g, e, h = mp.mpf(981) / 100, mp.mpf(9) / 10, mp.mpf(1)
    t1, v = mp.sqrt(2 * h / g), mp.sqrt(2 * g * h)
    starts = [t1 * (1 + 2 * sum(e ** j for j in range(1, k))) if k else 0 for k in range(60)]
    t_star = t1 * (1 + e) / (1 - e)
    assert len(fx["events"]) >= 1 and close(fx["events"][0]["time"], t1)
    for k, ev in enumerate(fx["events"], 1):
        assert close(ev["time"], starts[k])
        assert close(ev["state_before"][1], -(e ** (k - 1)) * v) and close(ev["state_after"][1], e ** k * v)
    (acc,) = fx["accumulations"]
    assert close(acc["time"], t_star) and [c["value"] for c in acc["state"]] == ["0", "0", "1"]

    def state(t):
        if t >= t_star:
            return (0, 0)
        if t <= t1:
            return (h - g * t ** 2 / 2, -g * t)
        k = max(j for j in range(1, 60) if starts[j] <= t)
        tau, w = t - starts[k], e ** k * v
        return (w * tau - g * tau ** 2 / 2, w - g * tau)

    for s in fx["samples"]:
        t = Fraction(s["t"]["exact"])
        q, dq = state(mp.mpf(t.numerator) / t.denominator)
        assert close(s["x"][0], q, mp.mpf(10) ** -40) and close(s["x"][1], dq, mp.mpf(10) ** -40), t


@pytest.mark.slow
def test_filippov_spiral_law(full):
    """(4.12) from (1, 2): switching times 3/2 - (5/2) 3^-k, accumulation at 3/2 at the origin."""
    fx = full[2]["filippov_spiral"]
    for k, ev in enumerate(fx["events"], 1):
        assert Fraction(ev["time"]["exact"]) == Fraction(3, 2) - Fraction(5, 2) / 3 ** k
    (acc,) = fx["accumulations"]
    assert Fraction(acc["time"]["exact"]) == Fraction(3, 2) and [c["exact"] for c in acc["state"]] == ["0", "0", "1"]
    assert [c["exact"] for c in fx["final_state"]] == ["0", "0", "1"]


@pytest.mark.slow
def test_newtons_cradle_impact_by_hand(full):
    """Three touching unit balls, ball 0 at speed 1, e = 1: Moreau's law on both contacts at once.
    Impulses P >= 0 with w = y'+ + e y'- >= 0, w . P = 0; v+ = (1 - P0, P0 - P1, P1), y'- = (-1, 0),
    y'+ = (2 P0 - P1 - 1, 2 P1 - P0): both contacts active gives 2 P0 - P1 = 2, 2 P1 = P0, so
    P = (4/3, 2/3) > 0 and v+ = (-1/3, 2/3, 2/3) (momentum 1 and energy 1/2 kept)."""
    fx = full[2]["newtons_cradle_3"]
    (ev,) = fx["events"]
    assert ev["time"]["exact"] == "0" and ev["mode_before"] is None
    v = [Fraction(c["exact"]) for c in ev["state_after"][3:]]
    assert v == [Fraction(-1, 3), Fraction(2, 3), Fraction(2, 3)] and sum(v) == 1 and sum(x * x for x in v) == 1
    for s in fx["samples"]:   # free flight after t = 0: q = v+ t
        t = Fraction(s["t"]["exact"])
        assert all(close(c, mp.mpf(w.numerator) / w.denominator) for c, w in zip(s["x"], [x * t for x in v] + v))


@pytest.mark.slow
def test_half_wave_rectifier_times_by_hand(full):
    """The tank from v = 0, v' = 1 conducts as a damped RLC (decay 5/13, omega_d = 12/13) for
    pi / omega_d, then oscillates freely for pi: events at 13 pi/12, 25 pi/12, 19 pi/6."""
    fx = full[2]["half_wave_rectifier"]
    want = [13 * mp.pi / 12, 25 * mp.pi / 12, 38 * mp.pi / 12]
    assert len(fx["events"]) == 3 and all(close(ev["time"], w) for ev, w in zip(fx["events"], want))
    for s in fx["samples"]:
        t = Fraction(s["t"]["exact"])
        if t <= 1:   # v = e^(-5t/13) sin(12t/13) / (12/13) while conducting
            tt = mp.mpf(t.numerator) / t.denominator
            assert close(s["x"][0], mp.e ** (-5 * tt / 13) * mp.sin(12 * tt / 13) * 13 / 12)


@pytest.mark.slow
def test_stiff_rc_diode_by_mpmath(full):
    """A = [[-2, 1], [1000, -1001000]] from (-1, 1): v2 (the diode's reverse voltage) reaches 0 at
    the root tau of (e^{A t} x0)_2, found here by mpmath; then the diode clamps v2 = 0 and
    v1 = v1(tau) e^{-2 (t - tau)}."""
    fx = full[2]["stiff_rc_diode"]
    A = mp.matrix([[-2, 1], [1000, -1001000]])
    x0 = mp.matrix([-1, 1])
    tau = mp.findroot(lambda t: (mp.expm(A * t) * x0)[1], (mp.mpf("1e-7"), mp.mpf("1e-4")), solver="anderson")
    assert 5e-6 < tau < 1e-5
    (ev,) = fx["events"]
    assert close(ev["time"], tau, mp.mpf(10) ** -40)
    v1 = (mp.expm(A * tau) * x0)[0]
    for s in fx["samples"][1:]:
        t = Fraction(s["t"]["exact"])
        tt = mp.mpf(t.numerator) / t.denominator
        assert close(s["x"][0], v1 * mp.e ** (-2 * (tt - tau)), mp.mpf(10) ** -40) and s["x"][1]["value"] == "0"


# ---------------------------------------------------------------------------------------------
# the command's options and errors
# ---------------------------------------------------------------------------------------------

def test_only_digits_and_sample(tmp_path, capsys):
    assert main(["zoo", str(tmp_path / "new" / "dir"), "--only", "relay, filippov_spiral,relay", "--digits", "12",
                 "--sample", "8"]) == 0
    out = capsys.readouterr()
    assert out.err == "" and "2 fixtures" in out.out and "relay: n = 3, k = 4, 1 event" in out.out
    index = json.loads((tmp_path / "new" / "dir" / "index.json").read_text())
    assert [e["name"] for e in index["problems"]] == ["filippov_spiral", "relay"]   # the suite's order, once
    relay = json.loads((tmp_path / "new" / "dir" / "relay.json").read_text())
    assert relay["digits"] == 12 and len(relay["samples"]) == 9 and relay["sample_step"] == "1/8"
    # x' = -2 sgn(x) from (1, 1): both relays reach 0 at t = 1/2 and slide there
    (ev,) = relay["events"]
    assert ev["time"]["exact"] == "1/2" and [c["exact"] for c in relay["final_state"]] == ["0", "0", "1"]
    assert relay["samples"][2]["t"]["exact"] == "1/4"
    assert all(close(c, w) for c, w in zip(relay["samples"][2]["x"], [mp.mpf(1) / 2, mp.mpf(1) / 2, 1]))  # 1 - 2/4


@pytest.mark.parametrize("args, fragment", [
    (["--only", "nope"], "no problem 'nope'"),
    (["--only", ","], "no problem given"),
    (["--sample", "0"], "--sample"),
    (["--sample", "1/10"], "--sample"),
    (["--digits", "0"], "--digits"),
])
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, args, fragment):
    assert main(["zoo", str(tmp_path / "z"), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lcs-exact: error:") and "\n" not in err and fragment in err
    assert not (tmp_path / "z").exists()       # refused before anything is written


def test_dir_that_is_a_file(tmp_path, capsys):
    f = tmp_path / "f"
    f.write_text("x")
    assert main(["zoo", str(f), "--only", "relay"]) == 2
    assert "is a file" in capsys.readouterr().err and main(["zoo"]) == 2


def test_a_run_stopped_early_is_written_partial_and_exits_3(tmp_path, capsys, monkeypatch):
    real = zoo.simulate
    monkeypatch.setattr(zoo, "simulate", lambda *a, **kw: real(*a, max_events=1, **kw))
    assert main(["zoo", str(tmp_path), "--only", "two_carts", "--digits", "10", "--sample", "4"]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "two_carts" in err
    fx = L.read_fixture(str(tmp_path / "two_carts.json"))
    assert fx.partial and len(fx.events) == 1 and json.loads((tmp_path / "index.json").read_text())["problems"][0]["partial"]


def test_library_arguments_are_checked():
    with pytest.raises(L.InvalidArgument, match="digits"):
        zoo.write_zoo("unused", digits=0)
    with pytest.raises(L.InvalidArgument, match="samples"):
        zoo.write_zoo("unused", samples=True)
    with pytest.raises(L.InvalidArgument, match="no problem 'x'"):
        zoo.problem("x")
