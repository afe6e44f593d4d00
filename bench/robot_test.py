#!/usr/bin/env python3
"""ctest bench_robot and bench_robot_bad_file: `make bench BENCH_ROBOT=FILE` as bench/run.sh runs it, in smoke
mode on the existing binary (BENCH_SMOKE=1 BENCH_NO_BUILD=1), a few seconds.

  robot_test.py run BUILD ROBOT   ROBOT (a robot file with its MJCF ROBOT.xml beside it), copied into a
                                  directory whose name holds a space: every benchmark a bundled robot gets runs
                                  for it without error, peers included, and nothing else; report.py prints its
                                  ratios. Copied without its MJCF: MuJoCo is skipped with one `note:` line.
  robot_test.py bad BUILD ROBOT   files that cannot be benchmarked (missing, a directory, invalid, YAML syntax,
                                  a URDF, an MJCF, a name with a newline): exit 2, one line `error: FILE: what`
                                  on stderr, nothing on stdout, no JSON written.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
NAME = "RrprArm"  # tests/data/bench/rrpr_arm.yaml's name: rrpr-arm, as a benchmark name
EXPECTED = {f"BM_{family}_{NAME}" for family in (
    "Fk_Poe", "Fk_Dh", "Jacobian_Spatial", "Jacobian_Body", "Jacobian_Geometric",
    "FkBatch_Scalar", "FkBatch_Soa", "FkBatch_SoaDh", "FkBatch_SoaThreads2", "Ik_Pose", "Ik_Position",
    "Ik_KdlNrJl", "Ik_KdlLma",  # (no Ik_ClosedFormAll: the RRPR arm has no closed form)
    "Fk_PoeBaseline", "Jacobian_SpatialBaseline", "Jacobian_GeometricBaseline", "FkBatch_SoaAvx2",
    "FkBatch_SoaAvx2Baseline", "FkBatch_SoaBaseline", "JacobianBatch_Geometric",
    "Fk_Mujoco", "Jacobian_Mujoco", "Fk_Kdl", "Jacobian_Kdl")}


def run_sh(build, robot, out, bench_filter=""):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("BENCH_", "BENCHMARK_"))}
    env.update(BUILD=build, BENCH_SMOKE="1", BENCH_NO_BUILD="1", BENCH_OUT=out, BENCH_ROBOT=robot,
               BENCH_FILTER=bench_filter)
    return subprocess.run(["bash", os.path.join(HERE, "run.sh")], env=env, capture_output=True, text=True)


def fail(message, result=None):
    if result is not None:
        message += f"\n--- exit {result.returncode}, stdout:\n{result.stdout}\n--- stderr:\n{result.stderr}"
    sys.exit("FAIL: " + message)


def ran(out):
    """{benchmark name: error message or ""} of a run's JSON."""
    with open(out) as f:
        data = json.load(f)
    return {b["run_name"].split("/")[0]: b.get("error_message", "") if b.get("error_occurred") else ""
            for b in data["benchmarks"]}


def test_run(build, robot, tmp):
    stem = os.path.splitext(os.path.basename(robot))[0]
    with_mjcf = os.path.join(tmp, "my robots")
    os.mkdir(with_mjcf)
    shutil.copy(robot, with_mjcf)
    shutil.copy(os.path.splitext(robot)[0] + ".xml", with_mjcf)
    out = os.path.join(tmp, "bench robot.json")
    result = run_sh(build, os.path.join(with_mjcf, stem + ".yaml"), out)
    if result.returncode != 0:
        fail("run.sh with BENCH_ROBOT did not exit 0", result)
    runs = ran(out)
    if set(runs) != EXPECTED:
        fail(f"benchmarks run: missing {sorted(EXPECTED - set(runs))}, unexpected {sorted(set(runs) - EXPECTED)}")
    errors = {name: error for name, error in runs.items() if error}
    if errors:
        fail(f"benchmarks with errors: {errors}")
    for row in (f"BM_Fk_Poe_{NAME}", f"BM_Jacobian_Geometric_{NAME}", f"BM_FkBatch_Soa_{NAME}"):
        # real, cpu, x MuJoCo, x KDL, x previous (a ratio, or '-' where no previous kernel is timed)
        if not re.search(rf"^{row} +\S+ +\S+ +\S+x +\S+x +(\S+x|-)$", result.stdout, re.M):
            fail(f"report.py printed no ratios to MuJoCo and KDL for {row}", result)
    if "note:" in result.stderr:
        fail("a note with the MJCF beside the robot file", result)

    without_mjcf = os.path.join(tmp, "no mjcf")
    os.mkdir(without_mjcf)
    shutil.copy(robot, without_mjcf)
    out = os.path.join(tmp, "no mjcf.json")
    path = os.path.join(without_mjcf, stem + ".yaml")
    result = run_sh(build, path, out, bench_filter=f"^BM_Fk_Poe_{NAME}$")
    notes = [line for line in result.stderr.splitlines() if line.startswith("note:")]
    if result.returncode != 0 or notes != [f"note: {NAME}: MuJoCo skipped: no {os.path.splitext(path)[0]}.xml "
                                           "(the robot as MJCF, with a site named tool)"]:
        fail("without its MJCF: exit 0 and one note line naming the missing MJCF expected", result)
    if ran(out) != {f"BM_Fk_Poe_{NAME}": ""}:
        fail(f"BENCH_FILTER with BENCH_ROBOT: ran {ran(out)}")


def test_bad(build, robot, tmp):
    cases = {}
    cases[os.path.join(tmp, "no such robot.yaml")] = "cannot open file"
    directory = os.path.join(tmp, "a directory.yaml")
    os.mkdir(directory)
    cases[directory] = "is a directory"
    invalid = os.path.join(tmp, "no joints.yaml")
    with open(invalid, "w") as f:
        f.write("name: broken\npoe:\n  joints: []\n  tool: [0, 0, 0, 0, 0, 0]\n")
    cases[invalid] = "poe.joints must be a non-empty list"
    syntax = os.path.join(tmp, "syntax.yaml")
    with open(syntax, "w") as f:
        f.write("poe: [\n")
    cases[syntax] = "YAML syntax error"
    urdf = os.path.join(tmp, "arm.urdf")
    with open(urdf, "w") as f:
        f.write('<robot name="arm"><link name="base"/></robot>\n')
    cases[urdf] = "an MJCF or URDF is not benchmarked"
    cases[os.path.splitext(robot)[0] + ".xml"] = "an MJCF or URDF is not benchmarked"
    cases[os.path.join(tmp, "new\nline.yaml")] = "cannot open file"
    for path, what in cases.items():
        out = os.path.join(tmp, "bad.json")
        result = run_sh(build, path, out)
        shown = path.replace("\n", " ")
        lines = result.stderr.splitlines()
        if (result.returncode != 2 or result.stdout or len(lines) != 1
                or not lines[0].startswith(f"error: {shown}: ") or what not in lines[0]):
            fail(f"{shown!r}: exit 2 and one line 'error: {shown}: ...{what}...' expected", result)
        if os.path.exists(out):
            fail(f"{shown!r}: benchmarks ran (JSON written) for a file that cannot be benchmarked")


def main(mode, build, robot):
    with tempfile.TemporaryDirectory(prefix="bench robot ") as tmp:
        (test_run if mode == "run" else test_bad)(os.path.abspath(build), os.path.abspath(robot), tmp)
    print("ok")


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in ("run", "bad"):
        sys.exit(__doc__)
    main(*sys.argv[1:])
