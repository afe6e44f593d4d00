"""The tracker loop in Python (docs/calibration.md "Tracker data"): simulate -> calibrate -> compensate.

Three SMRs (laser-tracker targets) on the actual PUMA's tool are measured at 50 poses with 0.01 mm of noise and
four blunders of 5 mm; the nominal (with the SMRs' points on its tool, as measured on the bench) is calibrated
with the Huber loss, which flags the blunders instead of bending the fit; the calibrated robot then compensates
a nominal program: joint values that put the actual robot's tool where the nominal's would be. The check is on
the actual robot, where the loop ends: its tool error against the program before and after.
Run by ctest (example.python.tracker_loop) from the source tree.
"""
import os
import sys
import tempfile

import numpy as np

import lowpair

SMRS = {"smr_a": [71.0, 2.0, -34.0], "smr_b": [-29.0, 67.0, -44.0], "smr_c": [-34.0, -58.0, -24.0]}  # mm, tool


def with_targets(path, folder):
    """A copy of a robot file with the SMRs added (a robot file's targets: list, docs/file_formats.md)."""
    copy = os.path.join(folder, os.path.basename(path))
    with open(copy, "w") as f:
        f.write(open(path).read() + "targets:\n")
        for name, point in SMRS.items():
            f.write(f"  - {{name: {name}, point: [{', '.join(map(repr, point))}]}}\n")
    return copy


with tempfile.TemporaryDirectory() as folder:
    actual = lowpair.load(with_targets("models/puma560_okamura_actual.yaml", folder))
    nominal = lowpair.load(with_targets("models/puma560_okamura_nominal.yaml", folder))

# 1. measure: 50 poses x 3 SMRs, in the robot's base frame (a tracker set up on the base; with frame=[...] the
#    calibrated robot would be in the tracker's frame, and compensation needs the nominal's frame)
fit = lowpair.simulate(actual, poses=50, seed=3, measure="targets", noise_position=0.01, blunders=(4, 5.0))

# 2. calibrate with a robust loss: the blunders are flagged, not fitted
cal = lowpair.calibrate(nominal, fit.q, fit.positions, targets=fit.targets, noise_position=0.01, free_pitch=True,
                        loss="huber")
flagged = np.nonzero(cal.residuals["outlier"])[0].tolist()
print(f"rank {cal.rank} of {cal.expected}, accepted: {cal.accepted} {cal.reason}")
print(f"flagged rows {flagged}, the blunders were {fit.blunders}")

# 3. compensate a nominal program (40 joint vectors the nominal was taught) for the calibrated robot
program = lowpair.simulate(nominal, poses=40, seed=5).q
comp = lowpair.compensate(cal.robot, nominal, program)
target = nominal.fk(program, model="poe")                 # where the program means the tool to be
before = actual.fk(program, model="poe")[:, :3, 3] - target[:, :3, 3]
after = actual.fk(comp.q, model="poe")[comp.ok][:, :3, 3] - target[comp.ok][:, :3, 3]
rms_before = np.sqrt(np.mean(np.sum(before ** 2, axis=1)))
rms_after = np.sqrt(np.mean(np.sum(after ** 2, axis=1)))
print(f"{int(comp.ok.sum())} of {len(program)} compensated; actual tool error RMS {rms_before:.4g} -> "
      f"{rms_after:.4g} {nominal.length_unit}")

# the robot is off by millimetres before; after, by the fit's uncertainty (0.01 mm noise)
ok = (cal.accepted and sorted(flagged) == sorted(fit.blunders) and comp.ok.sum() >= 0.9 * len(program)
      and rms_before > 1.0 and rms_after < 0.05)
sys.exit(0 if ok else 1)
