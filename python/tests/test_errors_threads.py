"""Every documented error is lowpair.Error with the CLI's message; calls from several threads agree."""
import glob
import os
import threading

import numpy as np
import pytest

import lowpair
from conftest import SOURCE, run_cli

PUMA = "models/puma560_corke.yaml"


def test_error_is_a_value_error():
    assert issubclass(lowpair.Error, ValueError)


@pytest.mark.parametrize("path", ["models/nonexistent.yaml", "tests/data", "README.md", "models/puma560_corke.xml"])
def test_bad_files_raise_the_cli_message(path):
    status, _, stderr = run_cli("fk", path, "--q", "0,0,0,0,0,0", check=False)
    assert status == 2 and stderr.startswith("error: ")
    with pytest.raises(lowpair.Error) as info:
        lowpair.load(path)
    cli = stderr.strip()[len("error: "):]
    if path.endswith(".xml"):
        assert "tip" in str(info.value)  # the CLI says --tip, Python tip=
    else:
        assert str(info.value) == cli


GOOD = open("models/elbow_mls.yaml").read()
HOSTILE = {
    "syntax.yaml": "name: [unclosed\n",
    "duplicate.yaml": "name: a\nname: b\n" + GOOD,
    "unknown_key.yaml": GOOD + "colour: red\n",
    "short_twist.yaml": GOOD.replace("twist: [0, 0, 1, 0, 0, 0]", "twist: [0, 0, 1, 0, 0]"),
    "not_finite.yaml": GOOD.replace("twist: [0, 0, 1, 0, 0, 0]", "twist: [0, 0, .nan, 0, 0, 0]"),
    "wrong_type.yaml": GOOD.replace("{name: j1, type: revolute", "{name: j1, type: prismatic"),
    "empty.yaml": "",
    "huge.yaml": GOOD.replace("twist: [0, 0, 1, 2, 0, 0]", "twist: [0, 0, 1, 2e300, 0, 0]"),
}


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_robot_files_raise_the_cli_message(tmp_path, name):
    path = str(tmp_path / name)
    with open(path, "w") as f:
        f.write(HOSTILE[name])
    status, _, stderr = run_cli("poe2dh", path, check=False)
    assert status == 2
    with pytest.raises(lowpair.Error) as info:
        lowpair.load(path).dh()
    assert str(info.value) == stderr.strip()[len("error: "):]


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(SOURCE, "tests", "data", "mjcf", "*.xml")))
                         + sorted(glob.glob(os.path.join(SOURCE, "tests", "data", "urdf", "*.urdf"))))
def test_model_files_raise_the_cli_message(path):
    tip = "tool"
    status, _, stderr = run_cli("poe2dh", path, "--tip", tip, check=False)
    if status == 0:
        lowpair.load(path, tip=tip).dh()
        return
    with pytest.raises(lowpair.Error) as info:
        lowpair.load(path, tip=tip).dh()
    assert str(info.value) == stderr.strip().splitlines()[-1][len("error: "):]


def test_model_file_tip_errors():
    with pytest.raises(lowpair.Error, match="no_such_site|no_such"):
        lowpair.load("models/puma560_corke.xml", tip="no_such_site")
    with pytest.raises(lowpair.Error, match="tip/base go with a model file"):
        lowpair.load(PUMA, tip="tool")
    # no tip: the candidates, as a wrong tip lists them
    with pytest.raises(lowpair.Error, match=r"^models/panda.xml: tip='NAME' is required with a model file; sites: 'tool'; "
                                            r"bodies: 'link1', "):
        lowpair.load("models/panda.xml")


@pytest.mark.parametrize("bad", [np.zeros(5), np.zeros((2, 5)), np.zeros((2, 3, 6)), np.zeros(7), np.array(3.0)])
def test_wrong_shapes(bad):
    robot = lowpair.load(PUMA)
    with pytest.raises(lowpair.Error, match="q: expected"):
        robot.fk(bad)


def test_non_finite_joint_values():
    robot = lowpair.load(PUMA)
    for value in (np.nan, np.inf, -np.inf):
        q = np.zeros(6)
        q[2] = value
        for call in (robot.fk, robot.jacobian, robot.singular):
            with pytest.raises(lowpair.Error, match="is not finite"):
                call(q)
        Q = np.zeros((9, 6))
        Q[7, 1] = value
        with pytest.raises(lowpair.Error, match=r"q\[7, 1\]"):
            robot.fk(Q)


def test_bad_arguments():
    robot = lowpair.load(PUMA)
    with pytest.raises(lowpair.Error, match="frame"):
        robot.jacobian(np.zeros(6), frame="world")
    with pytest.raises(lowpair.Error, match="model"):
        robot.fk(np.zeros(6), model="urdf")
    with pytest.raises(lowpair.Error, match="measure"):
        lowpair.identifiability(robot, measure="angles")
    with pytest.raises(lowpair.Error, match="poses"):
        lowpair.identifiability(robot, poses=0)
    with pytest.raises(lowpair.Error, match="targets"):
        lowpair.identifiability(robot, measure="targets")
    with pytest.raises(lowpair.Error, match="format"):
        lowpair.export(robot, "/tmp/x.sdf", format="sdf")
    with pytest.raises(lowpair.Error, match="parallel_threshold|threshold"):
        robot.dh(parallel_threshold=2.0)
    with pytest.raises(TypeError):
        robot.fk("not an array")


def test_bad_calibration_input():
    robot = lowpair.load(PUMA)
    Q = np.zeros((10, 6))
    P = np.zeros((10, 3))
    W = np.tile([1.0, 0.0, 0.0, 0.0], (10, 1))
    with pytest.raises(lowpair.Error, match="positions: expected shape"):
        lowpair.calibrate(robot, q=Q, positions=P[:, :2])
    with pytest.raises(lowpair.Error, match="rotations: expected shape"):
        lowpair.calibrate(robot, q=Q, positions=P, rotations=W[:5])
    with pytest.raises(lowpair.Error, match="not a unit quaternion"):
        lowpair.calibrate(robot, q=Q, positions=P, rotations=2 * W)
    with pytest.raises(lowpair.Error, match="noise_position: must be a positive number"):
        lowpair.calibrate(robot, q=Q, positions=P, rotations=W, noise_position=-1.0)
    with pytest.raises(lowpair.Error, match="no rotation to weigh"):
        lowpair.calibrate(robot, q=Q, positions=P, noise_rotation=1e-5)
    with pytest.raises(lowpair.Error, match="loss"):
        lowpair.calibrate(robot, q=Q, positions=P, loss="l1")
    with pytest.raises(lowpair.Error, match="is not finite"):
        lowpair.calibrate(robot, q=Q, positions=np.full((10, 3), np.nan))
    with pytest.raises(lowpair.Error, match="no measurements"):
        lowpair.calibrate(robot, q=Q[:0], positions=P[:0])


def test_four_threads_give_the_sequential_results():
    robot = lowpair.load(PUMA)
    other = lowpair.load("models/panda.yaml")  # another dof on the same threads
    rng = np.random.default_rng(7)
    Q = rng.uniform(-np.pi, np.pi, (2000, 6))
    Q7 = rng.uniform(-1, 1, (2000, other.dof))
    expected_single = [robot.fk(q) for q in Q[:300]]
    expected_batch = robot.fk(Q)
    expected_jac = [robot.jacobian(q, frame="geometric") for q in Q[:300]]
    expected_other = [other.fk(q) for q in Q7[:300]]
    failures = []
    barrier = threading.Barrier(4)

    def work(t):
        try:
            barrier.wait()
            for _ in range(3):
                for k in range(300):
                    if not np.array_equal(robot.fk(Q[k]), expected_single[k]):
                        failures.append((t, "fk", k))
                    if not np.array_equal(other.fk(Q7[k]), expected_other[k]):
                        failures.append((t, "fk other", k))
                    if not np.array_equal(robot.jacobian(Q[k], frame="geometric"), expected_jac[k]):
                        failures.append((t, "jacobian", k))
                if not np.array_equal(robot.fk(Q), expected_batch):
                    failures.append((t, "batch"))
        except Exception as e:  # noqa: BLE001
            failures.append((t, repr(e)))

    threads = [threading.Thread(target=work, args=(t,)) for t in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert not failures, failures[:5]


def test_mjcf_loading_notes_are_python_warnings():
    """The loader's notes (attributes newer than MuJoCo 2.2.2 dropped from a kinematics copy) are UserWarnings,
    which warnings.catch_warnings sees (before: printed to the C-level stderr), four for this file as the CLI's
    note: lines; a robot file gives none."""
    import warnings
    path = os.path.join(SOURCE, "tests/data/mjcf/newer_mujoco.xml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = lowpair.load(path, tip="tool")
    notes = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    assert len(notes) == 4 and all(n.startswith(path + ": ") for n in notes), notes
    assert any("dropped <option integrator='implicitfast'>" in n for n in notes)
    assert robot.dof == 3
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lowpair.load(os.path.join(SOURCE, "models/puma560_corke.yaml"))
    assert not caught
