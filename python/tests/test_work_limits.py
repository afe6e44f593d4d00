"""The rows of docs/cli.md's Limits table that Python shares (issue 30): just beyond each limit, lowpair.Error
naming the argument before the work starts (well under a second where the work refused takes minutes or
gigabytes); where cheap, the limit itself is accepted. Array rows and values: test_array_safety.py; plan's poses
and candidates: test_plan.py; MemoryError: test_out_of_memory.py."""
import time

import numpy as np
import pytest

import lowpair

PUMA = "models/puma560_corke.yaml"
NOMINAL = "models/puma560_okamura_nominal.yaml"
AT_ONCE = 2.0  # seconds: generous; the work refused takes minutes to hours


def chain(tmp_path, n):
    """A planar chain of n revolute joints, every axis 1 mm from the last."""
    lines = ["name: chain", "length_unit: m", "angle_unit: rad", "poe:", "  joints:"]
    lines += [f"    - {{type: revolute, twist: [0, 0, 1, 0, {-0.001 * k!r}, 0]}}" for k in range(n)]
    lines.append(f"  tool: [0, 0, 0, {0.001 * n!r}, 0, 0]")
    path = tmp_path / f"chain{n}.yaml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def refused_at_once(call, match):
    start = time.monotonic()
    with pytest.raises(lowpair.Error, match=match):
        call()
    assert time.monotonic() - start < AT_ONCE


def test_model_files_of_more_than_two_mib_are_refused_unread(tmp_path):
    big = tmp_path / "big.yaml"
    with open(big, "wb") as f:
        f.truncate((2 << 20) + 1)  # sparse: nothing is read when the size is checked first
    refused_at_once(lambda: lowpair.load(str(big)), r"2097153 bytes: over the 2 MiB a model file may have")


def test_robots_of_more_than_ten_thousand_joints_are_refused(tmp_path):
    path = chain(tmp_path, 10001)
    refused_at_once(lambda: lowpair.load(path), r"10001 joints, more than the 10000 a robot may have")


def test_ik_seeds_beyond_the_work_limit_are_refused_naming_seeds():
    robot = lowpair.load(PUMA)
    targets = np.broadcast_to(np.array([0.3, 0.1, 0.2]), (9334, 3))
    refused_at_once(lambda: lowpair.ik(robot, targets, seeds=1000),
                    r"^seeds: 1000 seeds x 9334 rows x 100 iterations x 6 joints = 5600400000 exceed the IK work limit")
    with pytest.raises(lowpair.Error, match=r"^seeds: must be in \[1, 1000\], got 1001"):
        lowpair.ik(robot, targets[:1], seeds=1001)
    far = lowpair.ik(robot, np.array([[5.0, 5.0, 5.0]]), seeds=1000)  # the most seeds, one row: taken
    assert far.status == ["unreachable"]


def test_compensate_beyond_the_work_limit_is_refused_before_the_copy(tmp_path):
    robot = lowpair.load(chain(tmp_path, 1000))
    q = np.broadcast_to(np.zeros(1000), (56001, 1000))  # a view: 448 MB if it were copied
    refused_at_once(lambda: lowpair.compensate(robot, robot, q),
                    r"^q: 56001 rows x 100 iterations x 1000 joints = 5600100000 exceed the IK work limit")


def test_ik_with_given_seeds_names_the_targets(tmp_path):
    robot = lowpair.load(chain(tmp_path, 1000))
    targets = np.broadcast_to(np.array([0.3, 0.1, 0.0]), (56001, 3))
    q0 = np.zeros(1000)
    refused_at_once(lambda: lowpair.ik(robot, targets, q0=q0),
                    r"^targets: 56001 rows x 100 iterations x 1000 joints")


def test_simulate_writes_only_what_a_measurement_file_holds(tmp_path):
    wide = lowpair.load(chain(tmp_path, 1001))
    refused_at_once(lambda: lowpair.simulate(wide, poses=1), r"1001 joints, more than the 1000 a measurement file holds")
    at = lowpair.load(chain(tmp_path, 1000))
    refused_at_once(lambda: lowpair.simulate(at, poses=100001),
                    r"^poses: 100001 measurements x 1000 joints = 100001000 joint values, more than the 100000000")
    assert len(lowpair.simulate(at, poses=2)) == 2


def test_identifiability_poses_at_most_ten_thousand():
    robot = lowpair.load(NOMINAL)
    with pytest.raises(lowpair.Error, match=r"^poses: must be in \[1, 10000\]"):
        lowpair.identifiability(robot, poses=10001)


def test_plan_candidates_at_most_a_hundred_thousand():
    robot = lowpair.load(NOMINAL)
    with pytest.raises(lowpair.Error, match=r"^candidates: must be in"):
        lowpair.plan(robot, poses=5, candidates=100001)


@pytest.mark.parametrize("options, match", [
    (dict(folds=21), r"^folds"),
    (dict(folds=1), r"^folds"),
    (dict(repeats=101), r"^repeats"),
])
def test_cross_validation_folds_and_repeats_are_bounded(options, match):
    robot = lowpair.load(NOMINAL)
    q = np.zeros((30, 6))
    with pytest.raises(lowpair.Error, match=match):
        lowpair.calibrate(robot, q=q, positions=np.zeros((30, 3)), select="cv", **options)
