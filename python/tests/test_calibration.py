"""The README's PUMA walk-through (docs/calibration.md): simulate with the CLI, calibrate from the CSV's arrays."""
import os

import numpy as np
import pytest

import lowpair
from conftest import cli_json, run_cli

NOMINAL = "models/puma560_okamura_nominal.yaml"
ACTUAL = ["models/puma560_okamura_actual.xml", "--tip", "tool", "--joint-variables", "models/puma560_okamura_actual.yaml"]


def read_csv(path, dof):
    """The measurement CSV as arrays: q (N, n), positions (N, 3), rotations (N, 4) qw, qx, qy, qz or None."""
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=0, ndmin=2, dtype=str)
    header, rows = list(data[0]), data[1:].astype(float)
    assert header[:dof] == [f"q{i + 1}" for i in range(dof)] and header[dof:dof + 3] == ["x", "y", "z"]
    rotations = rows[:, dof + 3:dof + 7] if len(header) == dof + 7 else None
    return rows[:, :dof], rows[:, dof:dof + 3], rotations


@pytest.fixture(scope="module")
def walkthrough(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("walkthrough")
    m, v = str(tmp / "m.csv"), str(tmp / "v.csv")
    run_cli("simulate", *ACTUAL, "--poses", "50", "--seed", "1", "--noise-position", "0.01", "--noise-rotation", "1e-5",
            "--out", m)
    run_cli("simulate", *ACTUAL, "--poses", "200", "--seed", "2", "--out", v)
    cal_yaml = str(tmp / "cal_cli.yaml")
    expected = cli_json("calibrate", NOMINAL, "--measurements", m, "--validation", v, "--noise-position", "0.01",
                        "--noise-rotation", "1e-5", "--free-pitch", "--out", cal_yaml)
    return tmp, m, v, expected, cal_yaml


def test_calibration_from_arrays_equals_cli(walkthrough):
    tmp, m, v, expected, _ = walkthrough
    robot = lowpair.load(NOMINAL)
    Q, P, W = read_csv(m, robot.dof)
    Qv, Pv, Wv = read_csv(v, robot.dof)
    cal = lowpair.calibrate(robot, q=Q, positions=P, rotations=W, noise_position=0.01, noise_rotation=1e-5,
                            free_pitch=True, loss="squared", validation_q=Qv, validation_positions=Pv,
                            validation_rotations=Wv)
    assert cal.rank == expected["rank"] == 42 and cal.expected == expected["expected"] == 42
    assert cal.iterations == expected["iterations"]
    assert cal.accepted and expected["accepted"] and cal.reason == ""
    for key in ("rms_position", "max_position", "rms_rotation", "max_rotation"):
        for when in ("before", "after"):
            got, want = getattr(cal, when)[key], expected[when][key]
            assert got == pytest.approx(want, rel=1e-12, abs=0), (when, key)
            assert cal.validation[when][key] == pytest.approx(expected["validation"][when][key], rel=1e-12)
    # the whole report, but for what names the input (paths, time)
    d = cal.to_dict()
    for report in (d, expected):
        report.pop("measurements"), report.pop("validation"), report.pop("seconds", None)
        for r in report["residuals"]:
            r.pop("line")
    assert d.keys() == expected.keys()
    for key in d:
        if key != "warnings":
            assert np.allclose(np.array(_flatten(d[key]), dtype=float), np.array(_flatten(expected[key]), dtype=float),
                               rtol=1e-9, atol=1e-15, equal_nan=True), key


def _flatten(x):
    if isinstance(x, dict):
        return [v for k in sorted(x) for v in _flatten(x[k])]
    if isinstance(x, list):
        return [v for e in x for v in _flatten(e)]
    if isinstance(x, bool):
        return [float(x)]
    if isinstance(x, (int, float)):
        return [float(x)]
    if x is None:
        return [np.nan]
    return [float(hash(x) % 1000003)]  # strings: equal or not


def test_calibrated_robot_saves_and_predicts(walkthrough):
    tmp, m, v, expected, cal_yaml = walkthrough
    robot = lowpair.load(NOMINAL)
    Q, P, W = read_csv(m, robot.dof)
    cal = lowpair.calibrate(robot, q=Q, positions=P, rotations=W, noise_position=0.01, noise_rotation=1e-5,
                            free_pitch=True)
    assert isinstance(cal.robot, lowpair.Robot) and cal.robot.name == robot.name + "-calibrated"
    Qv, Pv, _ = read_csv(v, robot.dof)
    # the robot is in the nominal's base frame; its measurement_frame predicts in the measurements' frame
    assert cal.robot.measurement_frame is not None
    predicted = cal.robot.measurement_frame @ cal.robot.fk(Qv)
    rms = np.sqrt(np.mean(np.sum((predicted[:, :3, 3] - Pv) ** 2, axis=1)))
    assert rms < 0.05  # mm; the walk-through's 0.0155
    saved = str(tmp / "cal_py.yaml")
    cal.robot.save(saved)
    again = lowpair.load(saved)
    cli = lowpair.load(cal_yaml)  # calibrate --out
    for other in (again, cli):
        assert np.array_equal(other.measurement_frame, cal.robot.measurement_frame)
        assert np.allclose(other.measurement_frame @ other.fk(Qv), predicted, rtol=0, atol=1e-12 * robot.length_scale)
    # the same model text as the CLI's file but for the provenance lines
    strip = lambda path: [l for l in open(path) if not l.startswith("#") and not l.startswith("description")]  # noqa: E731
    assert strip(saved) == strip(cal_yaml)


def test_position_measurements(walkthrough):
    tmp, m, v, expected, _ = walkthrough
    pos = str(tmp / "p.csv")
    run_cli("simulate", *ACTUAL, "--poses", "60", "--seed", "3", "--measure", "position", "--noise-position", "0.01",
            "--out", pos)
    import json
    # position data of the helical actual robot: the CLI rejects this fit (exit 1) and still prints the report
    status, out, _ = run_cli("calibrate", NOMINAL, "--measurements", pos, "--noise-position", "0.01", "--free-pitch",
                             "--json", check=False)
    assert status in (0, 1)
    want = json.loads(out)
    robot = lowpair.load(NOMINAL)
    Q, P, W = read_csv(pos, robot.dof)
    assert W is None
    cal = lowpair.calibrate(robot, q=Q, positions=P, noise_position=0.01, free_pitch=True)
    assert (cal.rank, cal.expected, cal.iterations, cal.accepted) == (want["rank"], want["expected"], want["iterations"],
                                                                       want["accepted"])
    assert cal.after["rms_position"] == pytest.approx(want["after"]["rms_position"], rel=1e-12)
    assert cal.reason == ("" if want["accepted"] else want["verdict"])
    # no rotation measured: None in the statistics, as to_dict() (the JSON's null) has it (it was 0.0 here)
    for when in ("before", "after"):
        assert cal.to_dict()[when]["rms_rotation"] is None and want[when]["max_rotation"] is None
        assert getattr(cal, when)["rms_rotation"] is None and getattr(cal, when)["max_rotation"] is None
        assert getattr(cal, when)["count"] == want[when]["count"]
    Qv, Pv = Q[:20], P[:20]
    held = lowpair.calibrate(robot, q=Q, positions=P, noise_position=0.01, free_pitch=True, validation_q=Qv,
                             validation_positions=Pv)
    for when in ("before", "after"):
        assert held.validation[when]["rms_rotation"] is None and held.validation[when]["max_rotation"] is None
        assert held.validation[when]["rms_position"] == held.to_dict()["validation"][when]["rms_position"]
    # pose data keep their numbers
    Qp, Pp, Wp = read_csv(m, robot.dof)
    pose = lowpair.calibrate(robot, q=Qp, positions=Pp, rotations=Wp, noise_position=0.01, noise_rotation=1e-5,
                             free_pitch=True)
    assert pose.after["rms_rotation"] == pose.to_dict()["after"]["rms_rotation"] > 0


def test_save_and_export_round_trip(tmp_path):
    robot = lowpair.load("models/puma560_okamura_actual.yaml")
    q = np.array([0.3, -0.2, 0.1, 0.5, -0.4, 0.2])
    for fmt in ("poe", "dh"):
        path = str(tmp_path / f"r_{fmt}.yaml")
        lowpair.export(robot, path, format=fmt)
        assert np.allclose(lowpair.load(path).fk(q), robot.fk(q), atol=1e-9)
    robot.save(str(tmp_path / "saved.yaml"))
    assert np.allclose(lowpair.load(str(tmp_path / "saved.yaml")).fk(q), robot.fk(q), atol=1e-9)
    # URDF: lengths in m, joint variable the motion (joint_variables file beside it)
    urdf = str(tmp_path / "r.urdf")
    lowpair.export(lowpair.load("models/puma560_corke.yaml"), urdf, format="urdf")
    T = lowpair.load(urdf, tip="tool").fk(q)
    assert np.allclose(T, lowpair.load("models/puma560_corke.yaml").fk(q), atol=1e-12)
    status, out, _ = run_cli("export", "models/puma560_corke.yaml", "--format", "urdf")
    # same body as the CLI's output but for the provenance comment
    assert [l for l in open(urdf) if "Made by" not in l] == [l + "\n" for l in out.split("\n") if l and "Made by" not in l]


def test_validation_contradicting_the_fit_rejects_it(walkthrough):
    # validation positions 1000 times too large (mm read as m and converted): after 1e5 mm against the fit's
    # 0.015 mm, beyond 100 times the fit's and 1 % of L (calibration_output.hpp kMaxValidationRatio): rejected,
    # as `calibrate --validation` is (exit 1); the right arrays stay accepted (the test above)
    _, m, v, _, _ = walkthrough
    robot = lowpair.load(NOMINAL)
    Q, P, W = read_csv(m, robot.dof)
    Qv, Pv, Wv = read_csv(v, robot.dof)
    cal = lowpair.calibrate(robot, q=Q, positions=P, rotations=W, noise_position=0.01, noise_rotation=1e-5,
                            free_pitch=True, validation_q=Qv, validation_positions=Pv * 1000.0, validation_rotations=Wv)
    assert not cal.accepted
    assert cal.reason.startswith("the validation set contradicts the calibrated model"), cal.reason
    assert cal.validation["after"]["rms_position"] > 100 * cal.after["rms_position"]
