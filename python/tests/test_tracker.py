"""lowpair.simulate and tracker calibration (target measurements, robust loss, cross-validation) against the CLI
(docs/calibration.md "Tracker data")."""
import json
import re
import warnings

import numpy as np
import pytest

import lowpair
from conftest import cli_json, run_cli

NOMINAL = "models/puma560_okamura_nominal.yaml"
ACTUAL = "models/puma560_okamura_actual.yaml"
SMRS = {"smr_a": [71.0, 2.0, -34.0], "smr_b": [-29.0, 67.0, -44.0], "smr_c": [-34.0, -58.0, -24.0]}  # mm, tool frame
FRAME = [0.3, -1.2, 2.0, 3000.0, -800.0, 400.0]  # the tracker's pose in the base: rotation vector rad, mm


def read_measurements(path):
    """A measurement CSV as (header, q, target names or None, positions, quaternions or None)."""
    lines = [l.strip() for l in open(path) if l.strip() and not l.lstrip().startswith("#")]
    header = lines[0].split(",")
    rows = [l.split(",") for l in lines[1:]]
    n = sum(1 for h in header if h.startswith("q") and h[1:].isdigit())
    targets = [r[n] for r in rows] if "target" in header else None
    numbers = np.array([[float(x) for i, x in enumerate(r) if header[i] != "target"] for r in rows])
    rotations = numbers[:, n + 3:n + 7] if "qw" in header else None
    return header, numbers[:, :n], targets, numbers[:, n:n + 3], rotations


@pytest.fixture(scope="module")
def tracker_robot(tmp_path_factory):
    """The actual PUMA's robot file with three SMRs on its tool."""
    path = str(tmp_path_factory.mktemp("tracker") / "actual_smr.yaml")
    with open(path, "w") as f:
        f.write(open(ACTUAL).read() + "targets:\n")
        for name, point in SMRS.items():
            f.write(f"  - {{name: {name}, point: [{', '.join(map(repr, point))}]}}\n")
    return path


@pytest.mark.parametrize("options,cli_options", [
    (dict(measure="targets", targets=["smr_b", "smr_a"], frame=FRAME, noise_position=0.01, blunders=(3, 5.0)),
     ["--measure", "targets", "--targets", "smr_b,smr_a", "--frame", ",".join(map(repr, FRAME)),
      "--noise-position", "0.01", "--blunders", "3,5"]),
    (dict(measure="pose", frame=FRAME, noise_position=0.01, noise_rotation=1e-5),
     ["--frame", ",".join(map(repr, FRAME)), "--noise-position", "0.01", "--noise-rotation", "1e-5"]),
    (dict(measure="position"), ["--measure", "position"]),
])
def test_simulate_equals_cli(tracker_robot, tmp_path, options, cli_options):
    cli_csv = str(tmp_path / "cli.csv")
    run_cli("simulate", tracker_robot, "--poses", "20", "--seed", "3", *cli_options, "--out", cli_csv)
    sim = lowpair.simulate(lowpair.load(tracker_robot), poses=20, seed=3, **options)
    header, q, targets, positions, rotations = read_measurements(cli_csv)
    # the CSV holds 17 significant digits: the numbers read back bit for bit
    assert np.array_equal(sim.q, q) and np.array_equal(sim.positions, positions)
    assert sim.targets == targets
    assert (sim.rotations is None) == (rotations is None)
    if rotations is not None:
        assert np.array_equal(sim.rotations, rotations)
    assert len(sim) == len(q) == (40 if options["measure"] == "targets" else 20)
    # the same joint vectors given as q: the same measurements (the noise of row k depends on (seed, k) only)
    again = lowpair.simulate(lowpair.load(tracker_robot), q=sim.q[::len(sim) // 20], seed=3, **options)
    assert np.array_equal(again.positions, sim.positions)
    # save() writes the CSV the CLI writes, but for the comment lines
    py_csv = str(tmp_path / "py.csv")
    sim.save(py_csv)
    strip = lambda path: [l for l in open(path) if not l.startswith("#")]  # noqa: E731
    assert strip(py_csv) == strip(cli_csv)
    assert "# length_unit: mm\n" in open(py_csv).readlines()


def test_simulate_blunders_are_the_cli_rows(tracker_robot):
    sim = lowpair.simulate(lowpair.load(tracker_robot), poses=20, seed=3, measure="targets", noise_position=0.01,
                           blunders=(3, 5.0))
    clean = lowpair.simulate(lowpair.load(tracker_robot), poses=20, seed=3, measure="targets", noise_position=0.01)
    moved = np.linalg.norm(sim.positions - clean.positions, axis=1)
    assert sim.blunders == sorted(np.nonzero(moved)[0].tolist()) and len(sim.blunders) == 3
    assert np.allclose(moved[sim.blunders], 5.0, rtol=1e-12)  # each moved by exactly the size


@pytest.fixture(scope="module")
def tracker_data(tracker_robot, tmp_path_factory):
    """Tracker data of the actual robot (3 SMRs, a far frame, 0.01 mm noise, 4 blunders of 5 mm), as arrays and
    as the CSVs the CLI reads."""
    tmp = tmp_path_factory.mktemp("tracker_data")
    actual = lowpair.load(tracker_robot)
    fit = lowpair.simulate(actual, poses=50, seed=3, measure="targets", frame=FRAME, noise_position=0.01,
                           blunders=(4, 5.0))
    held_out = lowpair.simulate(actual, poses=60, seed=4, measure="targets", frame=FRAME)
    fit_csv, held_out_csv = str(tmp / "fit.csv"), str(tmp / "held_out.csv")
    fit.save(fit_csv)
    held_out.save(held_out_csv)
    return fit, held_out, fit_csv, held_out_csv


def comparable(report):
    """A calibrate report but for what names the input (paths, lines) and the time."""
    report = json.loads(json.dumps(report))
    report.pop("measurements"), report.pop("seconds", None)
    if report.get("validation"):
        report["validation"].pop("path")
    for r in report["residuals"]:
        r.pop("line")
    return report


def test_tracker_calibration_equals_cli(tracker_data):
    fit, held_out, fit_csv, held_out_csv = tracker_data
    nominal = lowpair.load(NOMINAL)  # lists no targets: the three points are estimated
    status, out, _ = run_cli("calibrate", NOMINAL, "--measurements", fit_csv, "--validation", held_out_csv,
                             "--noise-position", "0.01", "--free-pitch", "--loss", "huber", "--json", check=False)
    expected = json.loads(out)
    cal = lowpair.calibrate(nominal, fit.q, fit.positions, targets=fit.targets, noise_position=0.01, free_pitch=True,
                            loss="huber", validation_q=held_out.q, validation_positions=held_out.positions,
                            validation_targets=held_out.targets)
    assert status == (0 if cal.accepted else 1)
    assert comparable(cal.to_dict()) == comparable(expected)
    assert cal.measure == "targets" and cal.loss == "huber"
    # 45 = 5 x 6 helical (free pitch) + 6 scales + 3 x 3 target coordinates
    assert cal.rank == cal.expected == 45 and cal.accepted
    # the blunders, 500 noise units each, are exactly the flagged rows; the others are within the threshold
    assert np.nonzero(cal.residuals["outlier"])[0].tolist() == fit.blunders and cal.outliers == 4
    assert np.all(cal.residuals["normalized"][fit.blunders] > 100)
    assert np.all(np.isnan(cal.residuals["rotation"]))  # points have no rotation
    # held-out prediction: the fitted parameters' error carried to a point is about sigma sqrt(p / rows) =
    # 0.01 sqrt(45 / 150) = 0.0055 mm RMS; the noise itself (0.01 mm per coordinate) bounds it
    assert cal.validation["after"]["rms_position"] < 0.01
    assert sorted(cal.targets) == sorted(SMRS) and all(v.shape == (3,) for v in cal.targets.values())
    # the frame registered: the nominal's base seen from the tracker is ~3.2 m away (the frame's translation)
    assert np.linalg.norm(cal.measurement_frame[:3, 3]) == pytest.approx(np.linalg.norm(FRAME[3:]), rel=0.01)
    # the calibrated robot (in the nominal's base frame) with its measurement_frame predicts the held-out
    # points in the tracker frame
    robot = cal.robot
    assert sorted(robot.targets) == sorted(SMRS)
    T = robot.measurement_frame @ robot.fk(held_out.q, model="poe")
    points = np.array([T[k, :3, :3] @ robot.targets[name] + T[k, :3, 3] for k, name in enumerate(held_out.targets)])
    rms = np.sqrt(np.mean(np.sum((points - held_out.positions) ** 2, axis=1)))
    assert rms == pytest.approx(cal.validation["after"]["rms_position"], rel=1e-6)


def test_cross_validation_equals_cli(tmp_path):
    m = str(tmp_path / "m.csv")
    run_cli("simulate", ACTUAL, "--poses", "40", "--seed", "6", "--noise-position", "0.01", "--noise-rotation", "1e-5",
            "--out", m)
    _, q, _, positions, rotations = read_measurements(m)
    status, out, _ = run_cli("calibrate", NOMINAL, "--measurements", m, "--noise-position", "0.01", "--noise-rotation",
                             "1e-5", "--free-pitch", "--select", "cv", "--folds", "4", "--repeats", "3", "--json",
                             check=False)
    expected = json.loads(out)
    cal = lowpair.calibrate(lowpair.load(NOMINAL), q, positions, rotations, noise_position=0.01, noise_rotation=1e-5,
                            free_pitch=True, select="cv", folds=4, repeats=3)
    assert comparable(cal.to_dict()) == comparable(expected)
    cv = cal.cross_validation
    assert cv["folds"] == 4 and cv["repeats"] == 3 and cv["chosen"] in ("full", "lines", "offsets")
    fitted = [c for c in cv["candidates"] if not c["failed"]]
    assert cv["chosen"] == min(fitted, key=lambda c: (c["score"], c["count"]))["parameters"]
    named = lowpair.calibrate(lowpair.load(NOMINAL), q, positions, rotations, noise_position=0.01, noise_rotation=1e-5,
                              free_pitch=True, parameters="offsets")
    assert named.to_dict()["parameter_set"] == "offsets" and named.cross_validation is None
    # repr says what the CLI's text says ("parameters: offsets, rank 19 of 21 (the complete set would be 39)"),
    # not the count as if the complete set had been fitted
    status, text, _ = run_cli("calibrate", NOMINAL, "--measurements", m, "--noise-position", "0.01", "--noise-rotation",
                              "1e-5", "--free-pitch", "--parameters", "offsets", check=False)
    line = next(x for x in text.splitlines() if x.startswith("parameters: "))
    assert "(the complete set would be " in line
    assert repr(named) == "<lowpair.Calibration " + line[len("parameters: "):] + (", accepted>" if named.accepted else ", rejected>")
    full = lowpair.calibrate(lowpair.load(NOMINAL), q, positions, rotations, noise_position=0.01, noise_rotation=1e-5,
                             free_pitch=True)
    assert repr(full).startswith(f"<lowpair.Calibration rank {full.rank} of {full.expected}, ")


def test_tracker_and_simulate_errors(tracker_robot, tracker_data):
    fit, held_out, _, _ = tracker_data
    nominal = lowpair.load(NOMINAL)
    actual = lowpair.load(tracker_robot)
    puma = lowpair.load("models/puma560_corke.yaml")  # has joint ranges
    W = np.tile([1.0, 0, 0, 0], (len(fit), 1))
    names = list(fit.targets)
    three = lowpair.simulate(nominal, poses=3, seed=4, measure="position")  # three poses
    cases = [
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, targets=names[:-1]), "targets: expected 150 target names"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, targets=["bad name"] + names[1:]),
         r"targets: \[0\]: .*target name"),
        # rotations with targets: mixed data, where a target's row must hold NaN (its point has no rotation)
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, W, targets=names),
         r"rotations: \[0\]: the row of target 'smr_\w' must be NaN"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, targets=names, validation_q=held_out.q,
                                   validation_positions=held_out.positions), "validation_targets: the fit has target"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, targets=names, validation_q=held_out.q,
                                   validation_positions=held_out.positions,
                                   validation_targets=["smr_x"] * len(held_out)), "target smr_x is not measured"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, targets=names, noise_rotation=1e-5),
         "no rotation to weigh"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, select="aic"), "select: expected 'cv'"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, select="cv", parameters="full"), "not both"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, select="cv", folds=1), "folds: must be in"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, select="cv", repeats=0), "repeats: must be in"),
        (lambda: lowpair.calibrate(nominal, three.q, three.positions, select="cv", folds=20),
         r"^folds: 20 folds but <arrays> holds 3 poses; .* \(at most 3 folds here, or more poses\)$"),
        (lambda: lowpair.calibrate(nominal, np.repeat(three.q[:1], 40, axis=0),
                                   np.repeat(three.positions[:1], 40, axis=0), select="cv"),
         "^folds: 5 folds but <arrays> holds 1 pose: its 40 measurements repeat joint vectors, 1 distinct"),
        (lambda: lowpair.calibrate(nominal, fit.q, fit.positions, parameters="j1.offset,,j2.offset"), "an empty name"),
        (lambda: lowpair.calibrate(puma, np.where(np.eye(4, 6) > 0, 100.0, 0.0), np.zeros((4, 3))),
         r"q: \[0, 0\] = 100 is outside joint 1's range .* by more than 10 times its width"),
        (lambda: lowpair.simulate(actual), "poses: give poses=N or q="),
        (lambda: lowpair.simulate(actual, poses=3, q=fit.q), "poses: give poses=N or q="),
        (lambda: lowpair.simulate(actual, poses=0), "poses: must be in"),
        (lambda: lowpair.simulate(actual, poses=3, noise_position=-1.0), "noise_position: expected a finite number"),
        (lambda: lowpair.simulate(actual, poses=3, noise_rotation=4.0), "noise_rotation: 4 is above"),
        (lambda: lowpair.simulate(actual, poses=3, measure="position", noise_rotation=1e-5), "no rotation to perturb"),
        (lambda: lowpair.simulate(actual, poses=3, targets=["smr_a"]), "targets: goes with measure='targets'"),
        (lambda: lowpair.simulate(actual, poses=3, measure="targets", targets=["smr_z"]), "is not a target of"),
        (lambda: lowpair.simulate(actual, poses=3, measure="targets", targets=["smr_a", "smr_a"]), "given twice"),
        (lambda: lowpair.simulate(nominal, poses=3, measure="targets"), "lists no targets"),
        (lambda: lowpair.simulate(actual, poses=3, frame=[0.0] * 5), "frame: expected 6 numbers"),
        (lambda: lowpair.simulate(actual, poses=3, blunders=(4, 1.0)), "COUNT 4 is more than the 3 measurements"),
        (lambda: lowpair.simulate(actual, poses=3, blunders=(1.5, 1.0)), "COUNT must be a whole number"),
        (lambda: lowpair.simulate(actual, poses=3, blunders=(1, 0.0)), "SIZE must be positive"),
        (lambda: lowpair.simulate(actual, q=np.zeros((2, 5))), r"q: expected shape \(N, 6\)"),
        (lambda: lowpair.simulate(actual, poses=3, measure="angles"), "measure: expected"),
    ]
    for call, message in cases:
        with pytest.raises(lowpair.Error, match=message):
            call()
            pytest.fail(f"no lowpair.Error matching {message!r}")


def test_read_measurements_reads_what_the_csv_holds(tracker_data, tracker_robot, tmp_path):
    fit, _, fit_csv, _ = tracker_data
    header, q, targets, positions, _ = read_measurements(fit_csv)  # this file's own reader
    m = lowpair.read_measurements(fit_csv)
    assert m.measure == "targets" and len(m) == len(q) == 150
    # 17 significant digits, read by strtod here and by float() there: bit for bit
    assert np.array_equal(m.q, q) and np.array_equal(m.positions, positions) and m.targets == targets
    assert m.rotations is None and m.blunders == [] and m.notes == [] and m.length_unit == "mm"
    data_lines = [k + 1 for k, line in enumerate(open(fit_csv)) if line.strip() and not line.lstrip().startswith("#")]
    assert m.lines == data_lines[1:]  # the header is the first
    # pose data: the quaternions too
    pose_csv = str(tmp_path / "pose.csv")
    lowpair.simulate(lowpair.load(tracker_robot), poses=10, seed=5, noise_position=0.01, noise_rotation=1e-5).save(pose_csv)
    _, q, _, positions, rotations = read_measurements(pose_csv)
    pose = lowpair.read_measurements(pose_csv, lowpair.load(NOMINAL))
    assert pose.measure == "pose" and pose.targets is None and pose.notes == []
    assert np.array_equal(pose.q, q) and np.array_equal(pose.positions, positions)
    # the rotation passes through a matrix (quaternion -> R -> quaternion): a few roundings of entries of at most 1
    assert np.abs(pose.rotations - rotations).max() <= 16 * np.finfo(float).eps
    # what calibrate fits from the arrays is what the CLI fits from the file
    status, out, _ = run_cli("calibrate", NOMINAL, "--measurements", fit_csv, "--noise-position", "0.01",
                             "--free-pitch", "--loss", "huber", "--json", check=False)
    cal = lowpair.calibrate(lowpair.load(NOMINAL), m.q, m.positions, targets=m.targets, noise_position=0.01,
                            free_pitch=True, loss="huber")
    assert status == (0 if cal.accepted else 1)
    assert comparable(cal.to_dict()) == comparable(json.loads(out))


def test_read_measurements_for_a_robot_converts_and_checks(tracker_data, tmp_path):
    _, _, fit_csv, _ = tracker_data
    header, q, targets, positions, _ = read_measurements(fit_csv)
    in_m = tmp_path / "in_m.csv"  # the same measurements in metres, written here
    with open(in_m, "w") as f:
        f.write("# length_unit: m\n" + ",".join(header) + "\n")
        for k in range(len(q)):
            f.write(",".join([*(repr(float(x)) for x in q[k]), targets[k], *(repr(x / 1000.0) for x in positions[k])]) + "\n")
    raw = lowpair.read_measurements(str(in_m))  # no robot: as written
    assert raw.length_unit == "m" and raw.notes == [] and np.array_equal(raw.positions, positions / 1000.0)
    mm = lowpair.read_measurements(str(in_m), lowpair.load(NOMINAL))
    assert mm.length_unit == "mm" and len(mm.notes) == 1
    assert "lengths converted from m (its length_unit comment) to mm (the nominal's), x 1000" in mm.notes[0]
    # x / 1000 written, then x 1000: two roundings of at most eps/2 each
    assert np.allclose(mm.positions, positions, rtol=np.finfo(float).eps, atol=0.0)
    # the robot's checks, with the CLI's messages
    with pytest.raises(lowpair.Error, match=r"has 6 joint columns but tests/data/bench/rrpr_arm.yaml has 4 joints"):
        lowpair.read_measurements(fit_csv, lowpair.load("tests/data/bench/rrpr_arm.yaml"))
    with pytest.raises(lowpair.Error, match=r"nope\.csv: cannot open"):
        lowpair.read_measurements(str(tmp_path / "nope.csv"))
    corke = lowpair.load("models/puma560_corke.yaml")  # joint 1's range [-2.7925, 2.7925] rad
    near, far = tmp_path / "near.csv", tmp_path / "far.csv"
    near.write_text("q1,q2,q3,q4,q5,q6,x,y,z\n2.9,0,0,0,0,0,0.1,0.2,0.3\n")
    far.write_text("q1,q2,q3,q4,q5,q6,x,y,z\n100,0,0,0,0,0,0.1,0.2,0.3\n")
    with pytest.warns(UserWarning, match=r"near\.csv:2: q1 = 2\.9 is outside joint 1's range"):
        assert len(lowpair.read_measurements(str(near), corke)) == 1
    with pytest.raises(lowpair.Error, match=r"far\.csv:2: q1 = 100 is outside .* by more than 10 times its width"):
        lowpair.read_measurements(str(far), corke)
    # seven near rows: five warnings and the count; a near row before a far one: its warning, then the error
    many, both = tmp_path / "many.csv", tmp_path / "both.csv"
    many.write_text("q1,q2,q3,q4,q5,q6,x,y,z\n" + "2.9,0,0,0,0,0,0.1,0.2,0.3\n" * 7)
    both.write_text("q1,q2,q3,q4,q5,q6,x,y,z\n2.9,0,0,0,0,0,0.1,0.2,0.3\n100,0,0,0,0,0,0.1,0.2,0.3\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lowpair.read_measurements(str(many), corke)
    texts = [str(w.message) for w in caught]
    assert len(texts) == 6 and all(f"many.csv:{k}: q1 = 2.9" in texts[k - 2] for k in range(2, 7))
    assert texts[5].endswith("many.csv: 7 joint values outside the ranges in all")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(lowpair.Error, match=r"both\.csv:3: q1 = 100"):
            lowpair.read_measurements(str(both), corke)
    assert len(caught) == 1 and "both.csv:2: q1 = 2.9" in str(caught[0].message)
    with warnings.catch_warnings():  # -W error: the first warning raises, as a UserWarning
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match=r"near\.csv:2"):
            lowpair.read_measurements(str(near), corke)
    # a robot without a path (a calibration's) is named by its name in the messages
    calibrated = lowpair.calibrate(lowpair.load(NOMINAL), q, positions, targets=targets, noise_position=0.01,
                                   free_pitch=True, loss="huber").robot
    furlong = tmp_path / "furlong.csv"
    furlong.write_text("# length_unit: furlong\n" + "".join(l for l in open(fit_csv) if "length_unit" not in l))
    with pytest.raises(lowpair.Error, match=r"lengths in furlong \(its length_unit comment\) but [^ ]+ is in mm"):
        lowpair.read_measurements(str(furlong), calibrated)


def test_simulate_caps_the_target_list(tracker_robot):
    # at most 1000 targets, as the CLI's --targets (checked after each name's own checks)
    names = [f"t{k}" for k in range(1001)]
    with pytest.raises(lowpair.Error, match=r"^targets: 1001 targets, more than 1000$"):
        lowpair.simulate(lowpair.load(tracker_robot), poses=1, measure="targets", targets=names)
    status, _, err = run_cli("simulate", tracker_robot, "--poses", "1", "--measure", "targets", "--targets",
                             ",".join(names), check=False)
    assert status == 2 and err.strip() == "error: --targets: 1001 targets, more than 1000"


def test_calibrate_warns_about_joint_values_just_outside_the_ranges():
    # as read_measurements warns for a file: each value outside a range (the first five, then the count)
    corke = lowpair.load("models/puma560_corke.yaml")  # joint 1's range [-2.7925, 2.7925] rad
    sim = lowpair.simulate(corke, poses=30, seed=2, measure="position")
    q = sim.q.copy()
    q[3, 0] = 2.9
    outside = r"is outside joint 1's range \[-2\.79\d*, 2\.79\d*\] of models/puma560_corke\.yaml"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lowpair.calibrate(corke, q, sim.positions)
    texts = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    assert len(texts) == 1 and re.fullmatch(r"q: \[3, 0\] = 2\.9 " + outside, texts[0])
    held_out = sim.q.copy()
    held_out[:7, 0] = 2.9
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        lowpair.calibrate(corke, sim.q, sim.positions, validation_q=held_out, validation_positions=sim.positions)
    texts = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    assert len(texts) == 6 and all(re.fullmatch(rf"validation_q: \[{k}, 0\] = 2\.9 " + outside, texts[k]) for k in range(5))
    assert texts[5] == "validation_q: 7 joint values outside the ranges in all"
    with warnings.catch_warnings():  # -W error: the first warning raises, as a UserWarning, before the fit
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match=r"^q: \[3, 0\] = 2\.9 "):
            lowpair.calibrate(corke, q, sim.positions)


def test_read_measurements_finds_columns_by_name(tmp_path):
    # columns in any order, the robot's joint names (j1..j6), a quaternion in ROS's order, an ignored column
    robot = lowpair.load("models/puma560_okamura_nominal.yaml")
    canonical = tmp_path / "c.csv"
    canonical.write_text("q1,q2,q3,q4,q5,q6,x,y,z,qw,qx,qy,qz\n0.1,0.2,0.3,0.4,0.5,0.6,1,2,3,0.6,0,0.8,0\n")
    shuffled = tmp_path / "s.csv"
    shuffled.write_text("time,qx,qy,qz,qw,z,y,x,j6,j5,j4,j3,j2,j1\n7,0,0.8,0,0.6,3,2,1,0.6,0.5,0.4,0.3,0.2,0.1\n")
    a = lowpair.read_measurements(str(canonical), robot)
    b = lowpair.read_measurements(str(shuffled), robot)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.rotations, b.rotations)
    assert a.notes == []
    assert b.notes == [str(shuffled) + ":1: ignored the column 'time' (not a column lowpair reads)"]
    # without a robot: q1..qn only, the note as well
    plain = tmp_path / "p.csv"
    plain.write_text("x,y,z,time,q1\n1,2,3,7,0.5\n")
    assert lowpair.read_measurements(str(plain), None).notes == [str(plain) + ":1: ignored the column 'time' (not a column lowpair reads)"]
    with pytest.raises(lowpair.Error, match=r"joint columns 'q1' and 'j2': q1..qn or the robot's joint names, not both"):
        mixed = tmp_path / "m.csv"
        mixed.write_text("q1,j2,q3,q4,q5,q6,x,y,z\n0,0,0,0,0,0,1,2,3\n")
        lowpair.read_measurements(str(mixed), robot)


def rigid_rms(a, b):
    """RMS distance between point sets a and b (N, 3) left after the best rigid motion (Kabsch)."""
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((b - cb).T @ (a - ca))
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    r = u @ d @ vt
    return np.sqrt(np.mean(np.sum((a @ r.T + (cb - r @ ca) - b) ** 2, axis=1)))


def test_known_targets_pin_the_tool_and_equal_the_cli(tracker_data, tmp_path):
    fit, held_out, fit_csv, _ = tracker_data
    nominal = lowpair.load(NOMINAL)
    known = nominal.with_targets(SMRS, known=True)  # the actual's points in its tool frame: a calibrated nest
    assert known.known_targets == list(SMRS) and nominal.known_targets == []
    cal = lowpair.calibrate(known, fit.q, fit.positions, targets=fit.targets, noise_position=0.01, free_pitch=True,
                            loss="huber")
    assert cal.accepted and cal.rank == cal.expected == 42  # 5 x 6 + 6 scales + the tool's 6
    assert cal.to_dict()["tool_frame"]["determined"] and cal.robot.tool_frame == "defined"
    assert all(np.array_equal(cal.targets[name], np.array(p)) for name, p in SMRS.items())  # fixed
    # the CLI on a nominal file with the same known targets: the same report
    path = str(tmp_path / "nominal_known.yaml")
    known.save(path)
    assert "known: true" in open(path).read()
    status, out, _ = run_cli("calibrate", path, "--measurements", fit_csv, "--noise-position", "0.01", "--free-pitch",
                             "--loss", "huber", "--json", check=False)
    cli = comparable(json.loads(out))
    assert status == 0 and cli.pop("nominal") == path
    assert {k: v for k, v in comparable(cal.to_dict()).items() if k != "nominal"} == cli
    # the compensated program puts the actual's TCP on the nominal's to within 3x the noise (the base error aside)
    actual = lowpair.load(ACTUAL)
    q = held_out.q[::3][:40] * 0.8
    comp = lowpair.compensate(cal.robot, nominal, q)
    assert comp.tool_note is None and comp.ok.sum() >= 36
    reached, wanted = actual.fk(comp.q[comp.ok])[:, :3, 3], nominal.fk(q[comp.ok])[:, :3, 3]
    assert rigid_rms(reached, wanted) <= 3 * 0.01
    # unknown points on the same data: the tool frame stays the nominal's, and compensate says so
    free = lowpair.calibrate(nominal, fit.q, fit.positions, targets=fit.targets, noise_position=0.01, free_pitch=True,
                             loss="huber")
    assert free.robot.tool_frame == "nominal" and not free.to_dict()["tool_frame"]["determined"]
    note = lowpair.compensate(free.robot, nominal, q).tool_note
    assert note is not None and note.startswith("compensated for the flange")


def test_with_targets_refuses_bad_names_and_points():
    nominal = lowpair.load(NOMINAL)
    for targets, message in [({"a b": [1, 2, 3]}, "holds a space"), ({"a": [1, 2]}, "expected a (3,) point"),
                             ({"a": [1, np.nan, 3]}, "is not finite"), ({1: [1, 2, 3]}, "keys must be target names")]:
        with pytest.raises(lowpair.Error, match=re.escape(message)):
            nominal.with_targets(targets)


def test_mixed_pose_and_target_rows_equal_the_cli(tracker_data, tmp_path):
    """Poses of a 6-DOF probe among the SMR points (a row with the target '' and NaN-free rotation; the points'
    rows NaN rotations): fitted together as `calibrate` fits the mixed CSV."""
    fit, _, _, _ = tracker_data
    actual = lowpair.load(ACTUAL)
    probe = lowpair.simulate(actual, poses=10, seed=13, frame=FRAME, noise_position=0.01, noise_rotation=1e-5)
    q = np.vstack([fit.q, probe.q])
    positions = np.vstack([fit.positions, probe.positions])
    rotations = np.vstack([np.full((len(fit), 4), np.nan), probe.rotations])
    targets = list(fit.targets) + [""] * len(probe)
    # the CSV: target and qw..qz columns, each row one of them
    path = str(tmp_path / "mixed.csv")
    with open(path, "w") as f:
        f.write("# length_unit: mm\n" + ",".join([f"q{i + 1}" for i in range(6)] + ["target", "x", "y", "z", "qw", "qx", "qy", "qz"]) + "\n")
        for k in range(len(q)):
            rot = ["", "", "", ""] if targets[k] else [repr(x) for x in rotations[k]]
            f.write(",".join([repr(x) for x in q[k]] + [targets[k]] + [repr(x) for x in positions[k]] + rot) + "\n")
    read = lowpair.read_measurements(path)
    assert read.targets == targets and np.array_equal(read.positions, positions)
    assert np.all(np.isnan(read.rotations[:len(fit)])) and np.allclose(read.rotations[len(fit):], rotations[len(fit):])
    cal = lowpair.calibrate(lowpair.load(NOMINAL), q, positions, rotations=rotations, targets=targets,
                            noise_position=0.01, noise_rotation=1e-5, free_pitch=True, loss="huber")
    status, out, _ = run_cli("calibrate", NOMINAL, "--measurements", path, "--noise-position", "0.01",
                             "--noise-rotation", "1e-5", "--free-pitch", "--loss", "huber", "--json", check=False)
    assert status == 0 and cal.accepted and cal.rank == cal.expected == 51  # 5 x 6 + 6 + the tool's 6 + 3 x 3
    assert cal.to_dict()["tool_frame"]["determined"] and cal.robot.tool_frame == "defined"
    assert comparable(cal.to_dict()) == comparable(json.loads(out))
    # a point's row with a rotation is refused by name
    bad = rotations.copy()
    bad[0] = [1, 0, 0, 0]
    with pytest.raises(lowpair.Error, match=re.escape("rotations: [0]: the row of target 'smr_a' must be NaN")):
        lowpair.calibrate(lowpair.load(NOMINAL), q, positions, rotations=bad, targets=targets)


def test_identification_work_limit_is_the_clis():
    """1000 targets on 2 poses: refused before any work, as `identifiability` refuses them (docs/cli.md, Limits)."""
    nominal = lowpair.load(NOMINAL)
    points = {f"t{k}": [(k * 37) % 160 - 80, (k * 61) % 160 - 80, (k * 89) % 160 - 80] for k in range(1000)}
    with pytest.raises(lowpair.Error, match="exceed the identification"):
        lowpair.identifiability(nominal.with_targets(points), measure="targets", poses=2)
    # known targets count too: three known ones give the tool's 6 columns (30 + 6 + 6 with free pitch)
    known = nominal.with_targets(SMRS, known=True)
    assert lowpair.identifiability(known, measure="targets", poses=20, free_pitch=True).expected == 42


def test_simulate_frame_as_a_4x4_rigid_motion_equals_the_6_numbers(tracker_robot):
    """frame=T (4, 4), the measurement frame's pose in the base, measures what frame=(rx, ry, rz, x, y, z) of the
    same pose measures (here a turn about z: exp of the rotation vector and cos/sin round apart by a few eps
    of the positions' size, 4 m)."""
    theta, t = 1.1, [3000.0, -800.0, 400.0]
    c, s = np.cos(theta), np.sin(theta)
    T = np.array([[c, -s, 0, t[0]], [s, c, 0, t[1]], [0, 0, 1, t[2]], [0, 0, 0, 1]])
    robot = lowpair.load(tracker_robot)
    a = lowpair.simulate(robot, poses=20, seed=3, frame=T)
    b = lowpair.simulate(robot, poses=20, seed=3, frame=[0, 0, theta] + t)
    assert np.abs(a.positions - b.positions).max() <= 64 * np.finfo(float).eps * 4000.0
    for bad, message in [(np.eye(3), "or a (4, 4) rigid motion, got shape (3, 3)"), (np.diag([1.0, 1, 2, 1]), "rigid motion"),
                         ([1.0, 2.0], "expected 6 numbers")]:
        with pytest.raises(lowpair.Error, match=re.escape(message)):
            lowpair.simulate(robot, poses=2, frame=bad)
