"""Forward kinematics of many configurations at once from Python (docs/python.md "Batched FK").

The PUMA 560 of models/puma560_corke.yaml, 10,000 random configurations through robot.fk(Q) (one batched SIMD
call, the GIL released), checked against one configuration at a time and against Corke's known pose at q = 0.
Run by ctest (example.python.fk_batch) from the source tree: PYTHONPATH=build/python python3 examples/python/fk_batch.py
"""
import sys

import numpy as np

import lowpair

robot = lowpair.load("models/puma560_corke.yaml")
rng = np.random.default_rng(1)
lo, hi = robot.ranges[:, 0], robot.ranges[:, 1]
Q = rng.uniform(lo, hi, size=(10000, robot.dof))  # within the joint ranges, one configuration per row

T = robot.fk(Q)                                   # (10000, 4, 4)
out = np.empty_like(T)
robot.fk(Q, out=out)                              # into a preallocated array: the same numbers

# the batch against single calls: the same chain in SIMD lanes, another operation order; 1e-14 m is ~50 eps of
# the 0.9 m reach (docs/python.md: within 36 eps L in the tests), where a wrong joint or pose is O(0.1)
single = np.array([robot.fk(q) for q in Q[:500]])
batch_error = np.abs(T[:500] - single).max()
# Corke's fkine(qz): identity rotation, the tool at (a2 + a3, -d3, d4)
T0 = robot.fk(np.zeros(robot.dof))
expected = np.eye(4)
expected[:3, 3] = [0.4521, -0.15005, 0.4318]
zero_error = np.abs(T0 - expected).max()

print(f"{len(Q)} poses, first tool position {T[0, :3, 3]} {robot.length_unit}")
print(f"|batch - single| = {batch_error:.3g}, |T(0) - T_corke| = {zero_error:.3g}")
ok = np.array_equal(T, out) and batch_error <= 1e-14 and zero_error <= 1e-15 and T.shape == (10000, 4, 4)
sys.exit(0 if ok else 1)
