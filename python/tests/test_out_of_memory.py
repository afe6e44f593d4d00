"""Out of memory is a MemoryError, never a dead interpreter (docs/python.md): the audit's 10^7-row `ik` grew to
7.7 GB and died with SIGABRT (std::bad_alloc escaped). Here the address space is capped (RLIMIT_AS) a little above
what the interpreter holds once its inputs exist, so the call's own buffers cannot be had: each call must raise
MemoryError and leave the interpreter running. 10^6 rows (the row limit) need far more than the cap: the outputs of
`ik` and `compensate` alone are over 100 MB (N x (6 joints + flags + errors) doubles), `fk` writes N x 16 doubles."""
import os
import subprocess
import sys

import pytest

from conftest import SOURCE

PUMA = os.path.join(SOURCE, "models/puma560_corke.yaml")
ROWS = 1_000_000
HEADROOM_MB = 20  # above the interpreter's size after the inputs exist; the calls need > 100 MB

SCRIPT = """
import os, resource, sys
import numpy as np
import lowpair
robot = lowpair.load({puma!r})
q = np.random.default_rng(1).uniform(-1.0, 1.0, ({rows}, 6))
T = robot.fk(q)
size = int(open("/proc/self/statm").read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
cap = size + {headroom} * 2**20
resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
calls = {{"ik": lambda: lowpair.ik(robot, T), "compensate": lambda: lowpair.compensate(robot, robot, q),
          "fk": lambda: robot.fk(q)}}
try:
    calls[sys.argv[1]]()
    print("returned")
except MemoryError:
    print("MemoryError")
print("alive")
"""


@pytest.mark.parametrize("call", ["ik", "compensate", "fk"])
def test_a_call_beyond_the_address_space_raises_memory_error(call):
    script = SCRIPT.format(puma=PUMA, rows=ROWS, headroom=HEADROOM_MB)
    out = subprocess.run([sys.executable, "-c", script, call], capture_output=True, text=True, timeout=300,
                         env=dict(os.environ))
    # before: SIGABRT (returncode -6) with "terminate called after throwing an instance of 'std::bad_alloc'"
    assert out.returncode == 0, (out.returncode, out.stderr[-2000:])
    assert out.stdout.split() == ["MemoryError", "alive"], out.stdout
