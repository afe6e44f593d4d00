"""lowpair.ik and lowpair.compensate against `lowpair ik --json` / `lowpair compensate --json`, the stated tolerance
(docs/ik.md: 1e-10 L and 1e-10 rad) and the compensation's purpose."""
import json
import re

import numpy as np
import pytest

import lowpair
from conftest import run_cli
from test_kinematics import random_q

PUMA = "models/puma560_corke.yaml"
NOMINAL = "models/puma560_okamura_nominal.yaml"
ACTUAL = "models/puma560_okamura_actual.yaml"
EPS = np.finfo(float).eps
IK_TOLERANCE = 1e-10  # kIkTolerance: position 1e-10 L, rotation 1e-10 rad


def quaternions(R):
    """Unit quaternions qw, qx, qy, qz of rotations (N, 3, 3), qw >= 0 (any accurate formula: the same numbers go to
    the CLI and to Python)."""
    out = []
    for r in R:
        w = np.sqrt(max(0.0, 1.0 + np.trace(r))) / 2
        if w > 0.1:
            x, y, z = (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)
        else:  # near a half turn: from the largest diagonal entry
            i = int(np.argmax(np.diag(r)))
            j, k = (i + 1) % 3, (i + 2) % 3
            v = np.zeros(3)
            v[i] = np.sqrt(max(0.0, 1.0 + r[i, i] - r[j, j] - r[k, k])) / 2
            v[j], v[k] = (r[j, i] + r[i, j]) / (4 * v[i]), (r[k, i] + r[i, k]) / (4 * v[i])
            w = (r[k, j] - r[j, k]) / (4 * v[i])
            x, y, z = v
        qv = np.array([w, x, y, z])
        qv /= np.linalg.norm(qv)
        out.append(qv if qv[0] >= 0 else -qv)
    return np.array(out)


def rotation_angles(R):
    """The angles of rotations (N, 3, 3), accurate near 0 (atan2 of the skew part's norm and the trace)."""
    skew = np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=1)
    return np.arctan2(np.linalg.norm(skew, axis=1) / 2, (np.trace(R, axis1=1, axis2=2) - 1) / 2)


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def without_input_names(d, key):
    """The report but for what names the input: the file (`key`) and each row's line."""
    d = dict(d)
    d.pop(key)
    d["rows"] = [{k: v for k, v in row.items() if k != "line"} for row in d["rows"]]
    return d


@pytest.fixture(scope="module")
def puma_targets():
    robot = lowpair.load(PUMA)
    q = random_q(robot, 12, seed=11)
    T = robot.fk(q, model="poe")
    return robot, q, T[:, :3, 3].copy(), quaternions(T[:, :3, :3])


def test_ik_equals_cli_json(puma_targets, tmp_path):
    robot, q, P, W = puma_targets
    pose_csv, position_csv, seeded_csv = (str(tmp_path / n) for n in ("pose.csv", "position.csv", "seeded.csv"))
    write_csv(pose_csv, ["x", "y", "z", "qw", "qx", "qy", "qz"], np.hstack([P, W]))
    write_csv(position_csv, ["x", "y", "z"], P)
    q0 = q + 0.05
    write_csv(seeded_csv, [f"q{i + 1}" for i in range(6)] + ["x", "y", "z", "qw", "qx", "qy", "qz"], np.hstack([q0, P, W]))
    cases = [(pose_csv, lambda: lowpair.ik(robot, P, rotations=W, seeds=3, seed=5), ["--seeds", "3", "--seed", "5"]),
             (position_csv, lambda: lowpair.ik(robot, P), []),
             (seeded_csv, lambda: lowpair.ik(robot, P, rotations=W, q0=q0), [])]
    for csv, solve, options in cases:
        status, out, _ = run_cli("ik", PUMA, "--poses", csv, "--json", *options, check=False)
        assert status in (0, 1)  # 1: some row not ok
        expected = json.loads(out)
        got = solve()
        assert got.to_dict()["poses"] == "<arrays>" and [r["line"] for r in got.to_dict()["rows"]] == list(range(len(P)))
        assert without_input_names(got.to_dict(), "poses") == without_input_names(expected, "poses"), csv
        assert got.status == [r["status"] for r in expected["rows"]]
        assert np.array_equal(got.q, np.array([r["q"] for r in expected["rows"]]))


def test_ik_reaches_fk_targets_within_the_tolerance(puma_targets):
    robot, q, P, W = puma_targets
    T = robot.fk(q, model="poe")
    solutions = lowpair.ik(robot, T)  # (N, 4, 4) transforms
    L = robot.length_scale
    assert solutions.ok.all(), solutions.reason
    reached = robot.fk(solutions.q, model="poe")
    position = np.linalg.norm(reached[:, :3, 3] - T[:, :3, 3], axis=1)
    rotation = rotation_angles(np.einsum("kji,kjl->kil", reached[:, :3, :3], T[:, :3, :3]))
    # the solver's own measure of the error is at most the tolerance; the FK evaluated again agrees with it to the
    # FK's rounding (16 (n + 1) eps L in the position, 16 (n + 1) eps in the rotation)
    assert solutions.position_error.max() <= IK_TOLERANCE * L
    assert solutions.rotation_error.max() <= IK_TOLERANCE
    assert np.all(np.abs(position - solutions.position_error) <= 16 * 7 * EPS * L)
    assert np.all(rotation <= IK_TOLERANCE + 16 * 7 * EPS)
    # a position target: the origin only, the same tolerance
    positions = lowpair.ik(robot, T[:, :3, 3])
    assert positions.ok.all() and positions.to_dict()["task"] == "position"
    assert np.all(np.linalg.norm(robot.fk(positions.q, model="poe")[:, :3, 3] - T[:, :3, 3], axis=1)
                  <= IK_TOLERANCE * L + 16 * 7 * EPS * L)
    assert np.all(positions.rotation_error == 0)
    # a target out of reach is data, not an exception
    far = T[:1].copy()
    far[0, :3, 3] = [10 * L, 0, 0]
    out = lowpair.ik(robot, far, seeds=1)
    assert out.status == ["unreachable"] and not out.ok[0] and "reach" in out.reason[0]


def test_compensate_puts_the_calibrated_tool_on_the_nominal_poses(tmp_path):
    nominal, actual = lowpair.load(NOMINAL), lowpair.load(ACTUAL)
    q = random_q(nominal, 10, seed=12) * 0.5  # well inside the ranges
    before = np.abs(actual.fk(q, model="poe") - nominal.fk(q, model="poe"))[:, :3, 3].max()
    assert before > 1.0  # mm: the two robots differ by more than the compensation's error by ten orders
    comp = lowpair.compensate(actual, nominal, q)
    ok = comp.ok
    assert ok.sum() >= 8, comp.reason  # a row may end elsewhere (not_converged, out_of_range): data, with its reason
    assert all(reason for reason, good in zip(comp.reason, ok) if not good)
    after = actual.fk(comp.q[ok], model="poe")
    target = nominal.fk(q[ok], model="poe")
    L = actual.length_scale
    assert np.linalg.norm(after[:, :3, 3] - target[:, :3, 3], axis=1).max() <= IK_TOLERANCE * L + 16 * 7 * EPS * L
    assert rotation_angles(np.einsum("kji,kjl->kil", after[:, :3, :3], target[:, :3, :3])).max() <= (
        IK_TOLERANCE + 16 * 7 * EPS)
    # the CLI on the same joint values
    q_csv = str(tmp_path / "q.csv")
    write_csv(q_csv, [f"q{i + 1}" for i in range(6)], q)
    for measure in ("pose", "position"):
        expected = json.loads(run_cli("compensate", ACTUAL, "--nominal", NOMINAL, "--q-file", q_csv, "--measure",
                                      measure, "--json", check=False)[1])
        got = lowpair.compensate(actual, nominal, q, measure=measure)
        assert got.to_dict()["q_file"] == "<arrays>"
        assert without_input_names(got.to_dict(), "q_file") == without_input_names(expected, "q_file"), measure
    # one joint vector: one row
    assert len(lowpair.compensate(actual, nominal, q[0])) == 1


def test_ik_and_compensate_errors():
    robot = lowpair.load(PUMA)
    T = robot.fk(np.zeros((2, 6)))
    P = T[:, :3, 3]
    W = np.tile([1.0, 0, 0, 0], (2, 1))
    cases = [
        (lambda: lowpair.ik(robot, np.zeros((2, 4))), "targets: expected shape"),
        (lambda: lowpair.ik(robot, np.zeros((2, 3, 3))), "targets: expected shape"),
        (lambda: lowpair.ik(robot, T, rotations=W), "rotations: the targets are 4 x 4"),
        (lambda: lowpair.ik(robot, P, rotations=W[:1]), r"rotations: expected shape \(2, 4\)"),
        (lambda: lowpair.ik(robot, P, rotations=2 * W), "not a unit quaternion"),
        (lambda: lowpair.ik(robot, np.where(np.arange(16).reshape(4, 4) == 15, 2.0, T)), r"\[0, 0, 0, 1\]"),
        (lambda: lowpair.ik(robot, T * np.array([1, 1, 1.5, 1])), r"targets: \[0\]: inverseKinematics: the target rotation"),
        (lambda: lowpair.ik(robot, np.full((1, 3), np.nan)), r"targets: \[0\]: not finite"),
        (lambda: lowpair.ik(robot, P, q0=np.zeros(5)), "q0: expected 6 joint values"),
        (lambda: lowpair.ik(robot, P, q0=np.zeros((3, 6))), r"q0: expected shape \(2, 6\)"),
        (lambda: lowpair.ik(robot, P, q0=np.array([0, 0, np.inf, 0, 0, 0])), "q0.*is not finite"),
        (lambda: lowpair.ik(robot, P, seeds=0), "seeds: must be in"),
        (lambda: lowpair.ik(robot, P, seed=-1), "seed: must be in"),
        (lambda: lowpair.compensate(robot, lowpair.load("models/panda.yaml"), np.zeros(6)), "has 6 joints but nominal"),
        (lambda: lowpair.compensate(lowpair.load(ACTUAL), robot, np.zeros(6)), "compensation needs one unit"),
        (lambda: lowpair.compensate(robot, robot, np.zeros(6), measure="angles"), "measure: expected"),
        (lambda: lowpair.compensate(robot, robot, np.zeros((2, 5))), r"q: expected shape \(N, 6\)"),
    ]
    for call, message in cases:
        with pytest.raises(lowpair.Error, match=message):
            call()
            pytest.fail(f"no lowpair.Error matching {message!r}")


def test_ik_takes_float32_transforms_and_rotation_matrices():
    """float32 (N, 4, 4) transforms (rotation rounding ~6e-8, above the double-precision rule) are taken as the
    nearest rotation, and (N, 3, 3) rotation matrices with (N, 3) positions are the same task as the transforms;
    before, the first was refused as 'not a rotation' and the second as a shape error."""
    robot = lowpair.load("models/puma560_corke.yaml")
    q = np.array([[0.1, -0.5, 0.3, 0.2, 0.4, -0.1], [0.3, -0.2, 0.1, -0.4, 0.6, 0.2]])
    T = robot.fk(q)
    T32 = T.astype(np.float32)
    got = lowpair.ik(robot, T32, q0=q)
    assert got.ok.all()
    # the solution reaches the float32 target to the float32 rounding of its entries (positions ~1 m: 1e-7 m)
    reached = robot.fk(got.q)
    assert np.abs(reached[:, :3, 3] - T32[:, :3, 3].astype(float)).max() <= 64 * np.finfo(np.float32).eps
    by_matrices = lowpair.ik(robot, T[:, :3, 3], rotations=T[:, :3, :3], q0=q)
    assert np.array_equal(by_matrices.q, lowpair.ik(robot, T, q0=q).q)
    with pytest.raises(lowpair.Error, match=re.escape("(2, 3, 3) (rotation matrices)")):
        lowpair.ik(robot, T[:, :3, 3], rotations=np.zeros((2, 3)))


def test_ik_all_equals_cli_json_and_reaches_every_target(puma_targets, tmp_path):
    robot, q, P, W = puma_targets
    pose_csv = str(tmp_path / "pose.csv")
    write_csv(pose_csv, ["x", "y", "z", "qw", "qx", "qy", "qz"], np.hstack([P, W]))
    expected = json.loads(run_cli("ik", PUMA, "--poses", pose_csv, "--all", "--json")[1])
    got = lowpair.ik_all(robot, P, rotations=W)
    assert got.closed_form == "spherical_wrist" and len(got) == len(P)
    assert without_input_names(got.to_dict(), "poses") == without_input_names(expected, "poses")
    # every solution reaches its target through FK: the closed form is exact to the FK's rounding, 1e-12 L
    T = robot.fk(q, model="poe")
    L = robot.length_scale
    for k, solutions in enumerate(got.q):
        assert solutions.shape == (got.count[k], 6) and got.count[k] == 8
        reached = robot.fk(solutions, model="poe")
        assert np.linalg.norm(reached[:, :3, 3] - T[k, :3, 3], axis=1).max() <= 1e-12 * L
        wrapped = np.abs(np.remainder(solutions - q[k] + np.pi, 2 * np.pi) - np.pi)
        assert wrapped.max(axis=1).min() <= 1e-9  # the configuration the target came from is among them
    with pytest.raises(lowpair.Error, match="ik_all needs poses"):
        lowpair.ik_all(robot, P)


def test_compensate_keeps_the_nominal_branch_as_the_cli(tmp_path):
    nominal = lowpair.load("models/puma560_corke_poe.yaml")
    calibrated = lowpair.load("tests/data/puma560_corke_calibrated.yaml")
    t = np.linspace(0, 1, 11)[:, None]
    q = np.array([0.2, 0.2, -0.9, 0.3, 0.8, 0.1]) * (1 - t) + np.array([1.0, 0.5, -0.3, 1.0, 1.2, 1.0]) * t
    q_csv = str(tmp_path / "q.csv")
    write_csv(q_csv, [f"q{i + 1}" for i in range(6)], q)
    for seeded in (False, True):
        extra = ["--seeded"] if seeded else []
        expected = json.loads(run_cli("compensate", "tests/data/puma560_corke_calibrated.yaml", "--nominal",
                                      "models/puma560_corke_poe.yaml", "--q-file", q_csv, "--json", *extra)[1])
        got = lowpair.compensate(calibrated, nominal, q, seeded=seeded)
        assert without_input_names(got.to_dict(), "q_file") == without_input_names(expected, "q_file")
        assert got.to_dict()["branch_kept"] == (0 if seeded else 11) and got.ok.all()
        if not seeded:
            assert len({json.dumps(r["branch"]) for r in got.to_dict()["rows"]}) == 1
