"""Ctrl-C during a long call (lowpair/interrupt.hpp, docs/cli.md): Python raises KeyboardInterrupt within about a
second, the CLI ends with exit 130 and writes nothing. The call interrupted: --select cv of 300 PUMA poses at 10
folds and 15 repeats (451 fits), 15 s uninterrupted on the 2-core machine this was written on; SIGINT comes after
1 s. Before, the Python call ignored it until the end (the audit: 14.3 s for a SIGINT at 1 s)."""
import os
import signal
import subprocess
import sys
import time

from conftest import CLI, SOURCE

NOMINAL = os.path.join(SOURCE, "models/puma560_okamura_nominal.yaml")
ACTUAL = os.path.join(SOURCE, "models/puma560_okamura_actual.yaml")
# the interrupted call must end well before the 15 s it needs: a call that does not poll fails this
LATEST = 5.0

SCRIPT = """
import os, signal, threading, time
import lowpair
nominal, actual = lowpair.load({nominal!r}), lowpair.load({actual!r})
sim = lowpair.simulate(actual, poses=300, seed=3, noise_position=0.01, noise_rotation=1e-5)
threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
t = time.monotonic()
try:
    lowpair.calibrate(nominal, sim.q, sim.positions, sim.rotations, noise_position=0.01, noise_rotation=1e-5,
                      free_pitch=True, select="cv", folds=10, repeats=15)
    print("finished", time.monotonic() - t)
except KeyboardInterrupt:
    print("interrupted", time.monotonic() - t)
"""


def test_python_ctrl_c_raises_keyboard_interrupt_within_a_second():
    out = subprocess.run([sys.executable, "-c", SCRIPT.format(nominal=NOMINAL, actual=ACTUAL)], capture_output=True,
                         text=True, timeout=120, env=dict(os.environ))
    assert out.returncode == 0, out.stderr
    what, seconds = out.stdout.split()
    assert what == "interrupted" and float(seconds) < LATEST, out.stdout


def test_cli_sigint_exits_130_and_writes_nothing(tmp_path):
    fit, cal = str(tmp_path / "fit.csv"), str(tmp_path / "cal.yaml")
    subprocess.run([CLI, "simulate", ACTUAL, "--poses", "300", "--seed", "3", "--noise-position", "0.01",
                    "--noise-rotation", "1e-5", "--out", fit], check=True, capture_output=True)
    start = time.monotonic()
    p = subprocess.Popen([CLI, "calibrate", NOMINAL, "--measurements", fit, "--noise-position", "0.01",
                          "--noise-rotation", "1e-5", "--free-pitch", "--select", "cv", "--folds", "10", "--repeats",
                          "15", "--out", cal], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert time.monotonic() - start < LATEST
    assert err == "error: interrupted (SIGINT): stopped, nothing written\n"
    assert os.listdir(tmp_path) == ["fit.csv"]  # no cal.yaml, no temporary beside it
