"""calibrate(compliance=..., backlash=...): the CLI's --compliance/--backlash from arrays (docs/calibration.md
"Beyond geometry"), on MuJoCo's PUMA 560 with Armstrong-Khatib-Burdick masses resting on joint springs."""
import numpy as np
import pytest

import lowpair
from conftest import run_cli

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
