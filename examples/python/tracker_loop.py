"""The tracker loop in Python (docs/calibration.md "Tracker data"): simulate -> calibrate -> compensate.

Three SMRs (laser-tracker targets) on the actual PUMA's tool are measured at 50 poses with 0.01 mm of noise and
four blunders of 5 mm; the nominal, which knows nothing of the SMRs, is calibrated with the Huber loss, which flags
the blunders instead of bending the fit, and estimates the SMRs' points; the calibrated robot then compensates a
nominal program: joint values that put its tool frame where the nominal's would be. With target data the tool
frame is the SMRs' (their points are estimated in it, docs/calibration.md), so the check is on the actual robot
with its real SMRs, where the loop ends: where they are against where the program means them to be.
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
nominal = lowpair.load("models/puma560_okamura_nominal.yaml")

# 1. measure: 50 poses x 3 SMRs, in the actual robot's base frame (a tracker anywhere else, frame=[...], works the
#    same: calibrate returns the robot in the nominal's base frame and the measurement frame beside it)
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


def smr_points(T, points):
    """(N, k, 3): each SMR's point (tool frame) carried by the (N, 4, 4) tool poses T."""
    P = np.array([points[name] for name in SMRS])
    return np.einsum("nij,kj->nki", T[:, :3, :3], P) + T[:, None, :3, 3]


def rms(d):
    return np.sqrt(np.mean(np.sum(d ** 2, axis=-1)))


# where the program means the SMRs to be: the nominal's tool frame with the calibrated SMR points, in the
# measurement frame (the actual's base is the nominal's moved by cal.robot.measurement_frame: the rigid motion
# of the actual's base error, which no joint command can undo)
meant = smr_points(cal.robot.measurement_frame @ nominal.fk(program, model="poe"), cal.targets)
real = {name: np.array(p) for name, p in SMRS.items()}
before = smr_points(actual.fk(program, model="poe"), real) - meant                # the actual robot at q
after = smr_points(actual.fk(comp.q, model="poe"), real)[comp.ok] - meant[comp.ok]  # ... at the compensated q
rms_before, rms_after = rms(before), rms(after)
print(f"{int(comp.ok.sum())} of {len(program)} compensated; the actual robot's SMRs off by {rms_before:.4g} -> "
      f"{rms_after:.4g} {nominal.length_unit} RMS")

# the robot is off by millimetres before; after, by the fit's uncertainty (0.01 mm noise)
ok = (cal.accepted and sorted(flagged) == sorted(fit.blunders) and comp.ok.sum() >= 0.9 * len(program)
      and rms_before > 1.0 and rms_after < 0.05)
sys.exit(0 if ok else 1)
