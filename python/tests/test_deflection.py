"""calibrate(compliance=..., backlash=...): the CLI's --compliance/--backlash from arrays (docs/calibration.md
"Beyond geometry"), on MuJoCo's PUMA 560 with Armstrong-Khatib-Burdick masses resting on joint springs."""
import numpy as np
import pytest

import lowpair
from conftest import cli_json, q_text, run_cli

NOMINAL = "models/puma560_masses.yaml"
STIFFNESS = {2: 8e4, 3: 4e4}  # N m/rad, the compliant actual's springs


def read_positions(path, dof):
    with open(path, encoding="ascii") as f:
        lines = [line for line in f if not line.startswith("#")]
    assert lines[0].strip().split(",")[:dof + 3] == [f"q{i + 1}" for i in range(dof)] + ["x", "y", "z"]
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return rows[:, :dof], rows[:, dof:dof + 3]


@pytest.fixture(scope="module")
def compliant_arm(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("compliant")
    m = str(tmp / "m.csv")
    springs = ",".join(str(STIFFNESS.get(j, 0)) for j in range(1, 7))
    run_cli("simulate", "models/puma560_masses.xml", "--tip", "tool", "--poses", "100", "--seed", "3", "--measure",
            "position", "--noise-position", "1e-5", "--stiffness", springs, "--out", m)
    return read_positions(m, 6)


def test_compliance_from_arrays_recovers_the_springs(compliant_arm):
    q, p = compliant_arm
    cal = lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, compliance="2,3")
    assert cal.accepted, cal.reason
    found = {(x["joint"], x["kind"]): x for x in cal.to_dict()["deflections"]}
    assert sorted(found) == [(2, "compliance"), (3, "compliance")]
    for j, k in STIFFNESS.items():
        c = found[(j, "compliance")]
        # the estimate within 4 standard deviations of the spring's 1/k (a 1-in-15,000 chance to fail by noise)
        assert abs(c["value"] - 1.0 / k) <= 4.0 * c["sd"], c


def test_without_compliance_the_same_data_are_not_explained(compliant_arm):
    q, p = compliant_arm
    rigid = lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5)
    assert not rigid.accepted and "variance factor" in rigid.reason
    assert "deflections" not in rigid.to_dict()


def test_a_joint_without_varying_load_is_refused_by_name(compliant_arm):
    q, p = compliant_arm
    with pytest.raises(ValueError, match="joint 1"):
        lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, compliance="1")


def test_prior_reports_the_effective_parameter_count(compliant_arm):
    q, p = compliant_arm
    free = lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, compliance="2,3")
    held = lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, compliance="2,3", prior="5")
    assert "prior" not in free.to_dict() and "effective_parameters" not in free.to_dict()
    d = held.to_dict()
    # the trace of the hat matrix: at most the parameters the data and the prior determine, at least the free ones
    # (the measurement frame's 6 and the 2 compliances stay free)
    assert 8 <= d["effective_parameters"] <= len(held.parameter_names)
    assert "prior" in d


def test_a_malformed_prior_is_refused(compliant_arm):
    q, p = compliant_arm
    with pytest.raises(ValueError, match="prior"):
        lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, prior="tilt=-1")


COMPLIANT_FILE = "tests/data/puma560_masses_compliant.yaml"  # compliance on joints 2 and 3, link masses, payload


def test_fk_of_a_compliant_file_is_where_the_cli_puts_the_tool(tmp_path):
    """robot.fk applies a file's compliance as `lowpair fk` does (the joints stand at q + c tau(q)), single and batched."""
    robot = lowpair.load(COMPLIANT_FILE)
    rng = np.random.default_rng(7)
    Q = rng.uniform(-1.0, 1.0, size=(5, 6))
    batch = robot.fk(Q)
    for k, q in enumerate(Q):
        cli = np.array(cli_json("fk", COMPLIANT_FILE, "--q", q_text(q))["T_base_tool"])
        # the same joint values through the same chain: FK's rounding allowance 16 (n + 1) eps S apart, S <= 1000 mm
        atol = 16 * 7 * np.finfo(float).eps * 1000.0
        np.testing.assert_allclose(robot.fk(q), cli, rtol=0, atol=atol)
        np.testing.assert_allclose(batch[k], cli, rtol=0, atol=atol)
    # and not the rigid pose: the same file without its compliance keys puts the tool elsewhere (c ~ 1e-4 rad/(N m)
    # times gravity torques of tens of N m on joints 2 and 3: tenths of a millimetre at 300 mm)
    with open(COMPLIANT_FILE, encoding="ascii") as f:
        text = f.read()
    rigid_path = tmp_path / "rigid.yaml"
    rigid_path.write_text(text.replace(", compliance: 5.0e-5", "").replace(", compliance: 1.0e-4", ""), encoding="ascii")
    rigid = lowpair.load(str(rigid_path))
    assert np.linalg.norm(robot.fk(Q[0])[:3, 3] - rigid.fk(Q[0])[:3, 3]) > 1e-2


def test_compensate_for_a_compliant_file_puts_the_deflected_tool_on_the_nominal_pose(tmp_path):
    """compensate applies the calibrated file's compliance as `lowpair compensate` does: the commands, deflected under
    the file's masses, stand where the nominal program puts the tool."""
    calibrated = lowpair.load(COMPLIANT_FILE)
    nominal = lowpair.load("models/puma560_okamura_nominal.yaml")  # the same geometry without masses or compliance
    rng = np.random.default_rng(11)
    Q = rng.uniform(-0.5, 0.5, size=(4, 6))
    s = lowpair.compensate(calibrated, nominal, Q)
    assert s.to_dict()["compliance_applied"] is True
    q_file = tmp_path / "q.csv"
    q_file.write_text("q1,q2,q3,q4,q5,q6\n" + "".join(q_text(q) + "\n" for q in Q), encoding="ascii")
    cli = cli_json("compensate", COMPLIANT_FILE, "--nominal", "models/puma560_okamura_nominal.yaml", "--q-file", str(q_file))
    assert cli["compliance_applied"] is True
    np.testing.assert_array_equal(s.q, np.array([row["q"] for row in cli["rows"]]))
    # independent of both: the compliant robot's fk (which applies c tau) at each command is the nominal's pose, to the
    # IK's tolerance (1e-10 L in position and rad in rotation) plus FK rounding
    L = calibrated.length_scale
    for k in range(len(Q)):
        reached, target = calibrated.fk(s.q[k]), nominal.fk(Q[k])
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) <= 1e-10 * L + 16 * 7 * np.finfo(float).eps * 1000.0
        assert np.linalg.norm(reached[:3, :3] - target[:3, :3]) <= 2e-10
