"""Shared fixtures: the lowpair CLI (LOWPAIR_CLI, set by the ctest), the source tree, a CLI runner."""
import glob
import json
import os
import subprocess

import pytest

SOURCE = os.environ.get("LOWPAIR_SOURCE_DIR") or os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _cli_path():
    if os.environ.get("LOWPAIR_CLI"):
        return os.environ["LOWPAIR_CLI"]
    for build in ("build-py", "build"):
        path = os.path.join(SOURCE, build, "lowpair")
        if os.access(path, os.X_OK):
            return path
    return None


CLI = _cli_path()
ROBOT_FILES = sorted(os.path.relpath(p, SOURCE) for p in glob.glob(os.path.join(SOURCE, "models", "*.yaml")))


@pytest.fixture(autouse=True)
def _in_source_tree(monkeypatch):
    # relative paths ("models/...") as the CLI sees them: the JSON's "source" then matches
    monkeypatch.chdir(SOURCE)


def run_cli(*args, check=True):
    """Runs the CLI; returns (exit status, stdout, stderr)."""
    if CLI is None:
        pytest.skip("no lowpair CLI (set LOWPAIR_CLI)")
    proc = subprocess.run([CLI, *args], cwd=SOURCE, capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise AssertionError(f"lowpair {' '.join(args)} exited {proc.returncode}: {proc.stderr}")
    return proc.returncode, proc.stdout, proc.stderr


def cli_json(*args):
    return json.loads(run_cli(*args, "--json")[1])


def q_text(q):
    """Joint values as --q text that reads back bit for bit."""
    return ",".join(repr(float(x)) for x in q)
