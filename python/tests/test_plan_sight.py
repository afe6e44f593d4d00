"""lowpair.plan(..., tracker=, smr_angle=, partial=) against `lowpair plan --tracker --smr-angle --partial --json`
(docs/plan.md "Line of sight")."""
import pytest

import lowpair
from conftest import cli_json

YAML = "tests/data/collision/puma560_smr_normals.yaml"
XML = "tests/data/collision/puma560_capsules.xml"


def without_times(d):
    d = dict(d)
    d.pop("seconds")
    d["feasibility"] = {k: v for k, v in d["feasibility"].items() if k != "seconds"}
    return d


def test_sight_plan_equals_cli_json():
    expected = cli_json("plan", YAML, "--model", XML, "--tip", "tool", "--measure", "targets", "--tracker", "800,-200,0",
                        "--smr-angle", "35", "--partial", "--range", "2:0:3.14", "--poses", "10", "--candidates", "1500")
    got = lowpair.plan(lowpair.load(YAML), poses=10, candidates=1500, measure="targets", model=XML, tip="tool",
                       ranges={2: (0, 3.14)}, tracker=(800, -200, 0), smr_angle=35, partial=True)
    assert without_times(got.to_dict()) == without_times(expected)
    sight = got.to_dict()["feasibility"]["line_of_sight"]
    assert sight["partial"] and sight["smr_angle_deg"] == 35 and sight["tracker"] == [800, -200, 0]
    assert len(got.measured) == 10 and all(1 <= len(m) <= 3 for m in got.measured)


def test_sight_plan_errors():
    robot = lowpair.load(YAML)
    with pytest.raises(lowpair.Error, match="tracker: expected"):
        lowpair.plan(robot, poses=3, measure="targets", model=XML, tip="tool", tracker=(1, 2))
    with pytest.raises(lowpair.Error, match="smr_angle: must be in"):
        lowpair.plan(robot, poses=3, measure="targets", model=XML, tip="tool", tracker=(800, 0, 0), smr_angle=0)
    with pytest.raises(lowpair.Error, match="partial: goes with tracker="):
        lowpair.plan(robot, poses=3, measure="targets", model=XML, tip="tool", partial=True)
    with pytest.raises(lowpair.Error, match="tracker: the tracker is inside geom 'pedestal'"):
        lowpair.plan(robot, poses=3, measure="targets", model=XML, tip="tool", tracker=(0, 0, -300))
    with pytest.raises(lowpair.Error, match="tracker: needs target measurements"):
        lowpair.plan(robot, poses=3, model=XML, tip="tool", tracker=(800, 0, 0))
