"""The calibrated robot in its own base frame (docs/calibration.md "The base frame as the gauge"): calibrate returns
the base-frame robot with its measurement frame; Robot.transformed, twists, tool_pose, measurement_frame."""
import numpy as np
import pytest

import lowpair
from conftest import run_cli

NOMINAL = "models/puma560_okamura_nominal.yaml"
ACTUAL = "models/puma560_okamura_actual.yaml"
# the actual's twists as its file prints them (unnormalized [w; v]) and its tool, models/puma560_okamura_actual.yaml
ACTUAL_TWISTS = np.array([[0.04, -0.02, 0.999, 0.02, 0.04, 0], [0, -1.00002, 0, -0.02, 0, 0.05],
                          [0.178, -0.984, -0.001, -0.07, 0.009, -101], [0.062, 0.013, -0.998, -51, 249, 0.0752],
                          [0.001, -1.00004, 0, -20.6, -0.0206, -249], [0.095, 0.031, -0.995, -51, 249, 0]])
FRAME = "0.3,-1.2,2.0,3000,-800,400"  # a tracker 3.2 m away, turned 130 deg (base_frame_cli_test)


def read_pose_csv(path, dof):
    data = np.loadtxt(path, delimiter=",", comments="#", ndmin=2, dtype=str)
    assert list(data[0][:dof]) == [f"q{i + 1}" for i in range(dof)]
    rows = data[1:].astype(float)
    return rows[:, :dof], rows[:, dof:dof + 3], rows[:, dof + 3:dof + 7]


def random_motion(rng, translation):
    w = rng.normal(size=3)
    w *= rng.uniform(0.1, 3.0) / np.linalg.norm(w)
    K = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    theta = np.linalg.norm(w)
    K /= theta
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(theta) * K + (1 - np.cos(theta)) * K @ K
    T[:3, 3] = rng.normal(size=3) * translation
    return T


@pytest.fixture(scope="module")
def far_tracker(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("base_frame")
    fit = str(tmp / "fit.csv")
    run_cli("simulate", ACTUAL, "--poses", "60", "--seed", "3", "--noise-position", "0.01", "--noise-rotation", "1e-5",
            "--frame", FRAME, "--out", fit)
    nominal = lowpair.load(NOMINAL)
    Q, P, W = read_pose_csv(fit, nominal.dof)
    cal = lowpair.calibrate(nominal, q=Q, positions=P, rotations=W, noise_position=0.01, noise_rotation=1e-5,
                            free_pitch=True)
    assert cal.accepted
    measurement_yaml = str(tmp / "cal_measurement.yaml")
    run_cli("calibrate", NOMINAL, "--measurements", fit, "--noise-position", "0.01", "--noise-rotation", "1e-5",
            "--free-pitch", "--frame", "measurement", "--out", measurement_yaml)
    return tmp, nominal, cal, lowpair.load(measurement_yaml)


def test_calibrate_returns_the_robot_in_the_nominals_base_frame(far_tracker):
    tmp, nominal, cal, in_measurement_frame = far_tracker
    robot = cal.robot
    # joint 1's line is the nominal's: the base z through the origin (the nominal's joints 1 and 2 meet there)
    w, v = robot.twists[0, :3], robot.twists[0, 3:]
    assert np.allclose(w / np.linalg.norm(w), nominal.twists[0, :3] / np.linalg.norm(nominal.twists[0, :3]),
                       rtol=0, atol=1e-12)
    assert np.linalg.norm(np.cross(w, v)) / np.dot(w, w) <= 1e-9 * nominal.length_scale
    # the measurement frame is recorded: the tracker's 3.2 m, and the JSON's base_frame
    F = robot.measurement_frame
    assert F.shape == (4, 4) and np.linalg.norm(F[:3, 3]) > 3000
    assert np.array_equal(F, np.array(cal.to_dict()["base_frame"]["T_measurement_base"]))
    # moved into the measurement frame it is the robot `calibrate --frame measurement` writes
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, size=(50, nominal.dof))
    assert np.allclose(robot.transformed(F).fk(q), in_measurement_frame.fk(q), rtol=0, atol=1e-9 * nominal.length_scale)
    # the old code returned that robot: metres from the base-frame one, not the actual's base error
    assert np.max(np.abs(robot.fk(q)[:, :3, 3] - in_measurement_frame.fk(q)[:, :3, 3])) > 1000
    # saved and loaded, the key reads back bit for bit
    path = str(tmp / "cal_base.yaml")
    robot.save(path)
    again = lowpair.load(path)
    assert np.array_equal(again.measurement_frame, F)
    assert np.array_equal(again.twists, robot.twists) and np.array_equal(again.tool_pose, robot.tool_pose)


def test_transformed_moves_fk_by_T_exactly(far_tracker):
    _, nominal, cal, _ = far_tracker
    rng = np.random.default_rng(7)
    for robot in (lowpair.load(ACTUAL), cal.robot):
        q = rng.uniform(-np.pi, np.pi, size=(100, robot.dof))
        T = random_motion(rng, 3000.0)
        moved = robot.transformed(T)
        expected = T @ robot.fk(q)
        reach = robot.length_scale + np.linalg.norm(T[:3, 3])
        assert np.max(np.abs(moved.fk(q)[:, :3, :3] - expected[:, :3, :3])) <= 1e-13
        assert np.max(np.abs(moved.fk(q)[:, :3, 3] - expected[:, :3, 3])) <= 1e-13 * reach
        assert np.allclose(moved.tool_pose, T @ robot.tool_pose, rtol=0, atol=1e-13 * reach)
        # the identity moves nothing, T then T^-1 comes back (to rounding: the twists are normalized again)
        assert np.allclose(robot.transformed(np.eye(4)).fk(q), robot.fk(q), rtol=0, atol=1e-13 * reach)
        back = moved.transformed(np.linalg.inv(T))
        assert np.max(np.abs(back.fk(q)[:, :3, 3] - robot.fk(q)[:, :3, 3])) <= 1e-12 * reach
        # a recorded measurement frame follows: the tracker's prediction is unchanged
        if robot.measurement_frame is not None:
            assert np.allclose(moved.measurement_frame @ moved.fk(q), robot.measurement_frame @ robot.fk(q), rtol=0,
                               atol=1e-12 * reach)
        else:
            assert moved.measurement_frame is None


def test_transformed_refuses_what_is_not_a_rigid_motion():
    robot = lowpair.load(NOMINAL)
    for bad in (np.eye(3), np.diag([1.0, 1.0, -1.0, 1.0]), np.diag([2.0, 1.0, 1.0, 1.0]),
                np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1.0]]),
                np.full((4, 4), np.nan)):
        with pytest.raises(lowpair.Error):
            robot.transformed(bad)


def test_twists_tool_pose_and_measurement_frame_read_back():
    actual = lowpair.load(ACTUAL)
    # twist times scale: the file's numbers to rounding
    assert actual.twists.shape == (6, 6)
    assert np.allclose(actual.twists, ACTUAL_TWISTS, rtol=1e-14, atol=1e-14 * actual.length_scale)
    # the tool pose is fk at the zero configuration (the file has no offsets)
    assert np.allclose(actual.fk(np.zeros(actual.dof), model="poe"), actual.tool_pose, rtol=0,
                       atol=1e-13 * actual.length_scale)
    assert actual.measurement_frame is None
    nominal = lowpair.load(NOMINAL)
    assert np.array_equal(nominal.twists[:2], np.array([[0, 0, 1, 0, 0, 0], [0, -1, 0, 0, 0, 0]], dtype=float))
