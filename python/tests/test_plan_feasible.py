"""lowpair.plan(..., model=, floor=, ranges=) against `lowpair plan --collisions/--floor/--range --json`
(docs/plan.md "Feasible plans")."""
import pytest

import lowpair
from conftest import cli_json

ARM = "tests/data/mjcf/feasible_arm.xml"


def load(path):
    with pytest.warns(UserWarning, match="not needed for kinematics"):  # the MJCF's geoms, dropped for kinematics
        return lowpair.load(path, tip="tool")


def without_times(d):
    d = dict(d)
    d.pop("seconds")
    if "feasibility" in d:
        d["feasibility"] = {k: v for k, v in d["feasibility"].items() if k != "seconds"}
    return d


def test_feasible_plan_equals_cli_json():
    expected = cli_json("plan", ARM, "--tip", "tool", "--collisions", "--floor", "0", "--range", "2:-2:2",
                        "--range", "j4:-1:1", "--range-margin", "0.1", "--poses", "8", "--candidates", "300",
                        "--seed", "4")
    robot = load(ARM)
    got = lowpair.plan(robot, poses=8, candidates=300, seed=4, model=ARM, tip="tool", floor=0.0,
                       ranges={2: (-2, 2), "j4": (-1, 1)}, range_margin=0.1)
    assert without_times(got.to_dict()) == without_times(expected)
    f = got.to_dict()["feasibility"]
    assert f["checked"] and f["rejected"]["floor"] > 0
    assert f["kept"] + f["rejected"]["total"] == 300
    assert all(-1.9 <= q[1] <= 1.9 and -0.9 <= q[3] <= 0.9 for q in got.q)


def test_feasible_plan_errors():
    robot = load(ARM)
    with pytest.raises(lowpair.Error, match="no candidate of 100 is free of contacts"):
        lowpair.plan(robot, poses=5, candidates=100, model=ARM, tip="tool", floor=0.5)
    with pytest.raises(lowpair.Error, match=r"^range: joint 2 \(j2\): \[-3, 2\] rad is outside the file's range"):
        lowpair.plan(robot, poses=5, candidates=100, ranges={2: (-3, 2)})
    with pytest.raises(lowpair.Error, match="^tip: is required with model="):
        lowpair.plan(robot, poses=5, candidates=100, model=ARM)
    with pytest.raises(lowpair.Error, match="^floor: needs a model"):
        lowpair.plan(robot, poses=5, candidates=100, floor=0.0)
    for floor in (float("nan"), float("inf")):  # not a plane at nan or inf in MuJoCo's XML
        with pytest.raises(lowpair.Error, match="^floor: must be a finite number"):
            lowpair.plan(robot, poses=5, candidates=100, model=ARM, tip="tool", floor=floor)


def test_model_without_collision_geometry_warns():
    model = "tests/data/mjcf/feasible_arm_nocollision.xml"
    robot = load(model)
    with pytest.warns(UserWarning, match="nothing was checked"):
        p = lowpair.plan(robot, poses=5, candidates=50, model=model, tip="tool")
    assert not p.to_dict()["feasibility"]["checked"]
