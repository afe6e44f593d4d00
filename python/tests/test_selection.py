"""calibrate(select="cv", prior_grid=..., cv_score=..., compliance=...): the CLI's --select cv over levels x prior
widths x deflections on and off (docs/calibration.md "Selection by cross-validation"): the same table, the same
choice, repr saying what the CLI's last line says."""
import json

import pytest

import lowpair
from conftest import run_cli
from test_deflection import read_positions

NOMINAL = "models/puma560_masses.yaml"


@pytest.fixture(scope="module")
def compliant_csv(tmp_path_factory):
    m = str(tmp_path_factory.mktemp("selection") / "m.csv")
    run_cli("simulate", "models/puma560_masses.xml", "--tip", "tool", "--poses", "20", "--seed", "2", "--measure",
            "position", "--noise-position", "1e-5", "--stiffness", "0,8e4,4e4,0,1e4,0", "--out", m)
    return m


def cli_selection(m, *args):
    status, out, err = run_cli("calibrate", NOMINAL, "--measurements", m, "--noise-position", "1e-5", "--select", "cv",
                               "--folds", "5", "--repeats", "2", *args, check=False)
    assert status in (0, 1), err
    return status, out


@pytest.mark.parametrize("grid, score", [("1,10", "median"), ([1.0, 10.0], "trimmed"), ("default", None)])
def test_selection_table_equals_the_clis(compliant_csv, grid, score):
    q, p = read_positions(compliant_csv, 6)
    text_grid = grid if isinstance(grid, str) else ",".join(repr(w) for w in grid)
    extra = ["--prior-grid", text_grid, "--compliance", "2,3"] + (["--cv-score", score] if score else [])
    _, out = cli_selection(compliant_csv, *extra, "--json")
    expected = json.loads(out)["cross_validation"]
    cal = lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, select="cv", folds=5, repeats=2,
                            prior_grid=grid, compliance="2,3", cv_score=score)
    assert cal.to_dict()["cross_validation"] == expected
    assert cal.cross_validation == expected
    widths = 5 if grid == "default" else 2
    assert len(expected["candidates"]) == 3 * (1 + widths) * 2
    assert expected["score"] == (score or "rms")
    assert sum(c["chosen"] for c in expected["candidates"]) == 1
    # repr ends with the CLI text's last line of the table ("chosen: lines, prior 10, compliance on")
    _, text = cli_selection(compliant_csv, *extra)
    line = next(x for x in text.splitlines() if x.startswith("chosen: "))
    assert repr(cal).endswith(", " + line + ">"), (repr(cal), line)


def test_default_selection_keeps_its_repr_and_keys(compliant_csv):
    q, p = read_positions(compliant_csv, 6)
    cal = lowpair.calibrate(lowpair.load(NOMINAL), q, p, noise_position=1e-5, select="cv", folds=5, repeats=2)
    assert "chosen:" not in repr(cal)
    cv = cal.cross_validation
    assert [c["parameters"] for c in cv["candidates"]] == ["full", "lines", "offsets"]
    assert all(c["prior"] is None and not c["compliance"] and not c["backlash"] for c in cv["candidates"])


def test_selection_arguments_are_the_clis(compliant_csv):
    q, p = read_positions(compliant_csv, 6)
    robot = lowpair.load(NOMINAL)
    with pytest.raises(ValueError, match="prior_grid: .*select"):
        lowpair.calibrate(robot, q, p, noise_position=1e-5, prior_grid="1,3")
    with pytest.raises(ValueError, match="cv_score: expected 'rms', 'trimmed' or 'median'"):
        lowpair.calibrate(robot, q, p, noise_position=1e-5, select="cv", cv_score="mean")
    with pytest.raises(ValueError, match="prior_grid: .*not both"):
        lowpair.calibrate(robot, q, p, noise_position=1e-5, select="cv", prior_grid=[1.0], prior="3")
