"""benchmarks/battery.py's verdicts: two runs agree only when their events, states and ends do
(the comparison a broken evaluation path has to get past)."""
import copy
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import battery  # noqa: E402

RUN = dict(n=4, certified=True, status="COMPLETE", end="3",
           events=[dict(t=["1.57079632679489661923132169163975144", 1e-35], trig=["y_0"], mb=[], ma=[0])],
           final=[["0.5", 0.0], ["-1.25", 1e-30]],
           samples={"1/2": [["0.25", 1e-30], ["1", 0.0]]})


def test_identical_runs_agree_and_each_difference_is_named():
    assert battery.differences(RUN, copy.deepcopy(RUN)) == []
    shifted = copy.deepcopy(RUN)
    shifted["events"][0]["t"][0] = "1.57079632679489661923132169163985144"  # 10^-31 away: disjoint balls
    assert battery.differences(RUN, shifted) == ["event 0: times 1.570796326794896619 / 1.570796326794896619"]
    other = copy.deepcopy(RUN)
    other["events"][0]["ma"] = []
    assert battery.differences(RUN, other) == ["event 0: ma [0] / []"]
    wide = copy.deepcopy(RUN)
    wide["samples"]["1/2"][0][1] = 1e-10  # overlaps, but no longer the 24 digits asked
    assert battery.differences(RUN, wide) == ["x_0 at t = 1/2"]
    stopped = dict(copy.deepcopy(RUN), error="UnresolvedSign", events=[])
    assert battery.differences(RUN, stopped) == ["ends: COMPLETE / UnresolvedSign", "1 / 0 events"]
    partial = dict(copy.deepcopy(RUN), status="EVENT_LIMIT")
    assert battery.differences(RUN, partial) == ["ends: COMPLETE / EVENT_LIMIT"]
    huge = copy.deepcopy(RUN)
    huge["final"][1] = ["-1.25e139", 1e110]  # relative radius 1e-29: as narrow as the digits asked
    assert battery.differences(huge, copy.deepcopy(huge)) == []


def test_the_default_list_leaves_out_only_the_known_limits():
    every = battery.scene_names(True)
    default = battery.scene_names(False)
    assert len(default) == 58 and set(every) - set(default) == set(battery.KNOWN_LIMITS)
