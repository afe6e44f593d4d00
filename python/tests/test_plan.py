"""lowpair.plan against `lowpair plan --json`, and what a plan must satisfy (docs/plan.md)."""
import numpy as np
import pytest

import lowpair
from conftest import cli_json

NOMINAL = "models/puma560_okamura_nominal.yaml"


def without_times(d):
    d = dict(d)
    d.pop("seconds")
    return d


@pytest.mark.parametrize("options", [
    {"poses": 12, "candidates": 200, "seed": 3},
    {"poses": 15, "candidates": 150, "seed": 4, "measure": "position", "free_pitch": True, "noise_position": 0.02,
     "criterion": "O1"},
    {"poses": 10, "candidates": 120, "seed": 5, "noise_rotation": 2e-5},
])
def test_plan_equals_cli_json(options):
    robot = lowpair.load(NOMINAL)
    args = ["plan", NOMINAL]
    for key, value in options.items():
        flag = "--" + key.replace("_", "-")
        args += [flag] if value is True else [flag, str(value)]
    expected = cli_json(*args)
    got = lowpair.plan(robot, **options)
    assert without_times(got.to_dict()) == without_times(expected)
    assert got.indices == expected["indices"] and np.array_equal(got.q, np.array(expected["q"]))
    assert got.rank == expected["rank"] and got.expected == expected["expected"]
    assert got.log_det == (expected["planned"]["log_det"] if expected["planned"]["log_det"] is not None else -np.inf)


def test_plan_properties():
    robot = lowpair.load(NOMINAL)
    p = lowpair.plan(robot, poses=12, candidates=200, seed=3)
    # the exchange passes never lower log det; the plan beats the median random set of the same candidates
    assert p.log_det >= p.greedy["log_det"]
    assert p.log_det > p.random["log_det"]["median"]
    assert p.rank == p.expected == 36 and len(p.parameters) == len(p.standard_deviation) == 36
    # the planned joint vectors are candidates: inside the joint ranges, and the CLI's sampling stream
    lo, hi = robot.ranges[:, 0], robot.ranges[:, 1]
    assert np.all((p.q >= lo) | np.isnan(lo)) and np.all((p.q <= hi) | np.isnan(hi))
    assert p.indices == sorted(p.indices) and len(set(p.indices)) == 12
    # the expected standard deviations scale with the noise: the covariance is sigma^2 (J^T J)^-1 with the
    # rotation/position weight ratio kept (both noises doubled)
    sigma_p, sigma_r = p.noise["position"], p.noise["rotation"]
    doubled = lowpair.plan(robot, poses=12, candidates=200, seed=3, noise_position=2 * sigma_p, noise_rotation=2 * sigma_r)
    assert doubled.indices == p.indices  # the plan does not depend on the noise
    assert np.allclose(doubled.standard_deviation, 2 * p.standard_deviation, rtol=1e-9, atol=0)
    assert p.noise["source"].startswith("default") and doubled.noise["source"] == "stated"


def test_plan_errors():
    robot = lowpair.load(NOMINAL)
    cases = [
        (dict(poses=0), "poses: must be in"),
        (dict(poses=1001), "poses: must be in"),
        (dict(poses=10, candidates=5), "10 poses cannot be chosen from 5 candidates"),
        (dict(poses=10, candidates=0), "candidates: must be in"),
        (dict(poses=10, criterion="A"), "criterion: expected"),
        (dict(poses=10, measure="angles"), "measure: expected"),
        (dict(poses=10, measure="targets"), "targets"),
        (dict(poses=10, measure="position", noise_rotation=1e-5), "no rotation to weigh"),
        (dict(poses=10, noise_position=-1.0), "noise_position: must be a positive number"),
        (dict(poses=10, seed=-2), "seed: must be in"),
    ]
    for options, message in cases:
        with pytest.raises(lowpair.Error, match=message):
            lowpair.plan(robot, **options)
            pytest.fail(f"no lowpair.Error for {options}")
