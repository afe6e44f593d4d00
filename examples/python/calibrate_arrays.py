"""Calibration from numpy arrays (docs/python.md "Calibration from numpy arrays, end to end").

The actual PUMA of the walk-through (models/puma560_okamura_actual.yaml: the nominal with millimetres and
milliradians of error) is measured at 50 seeded poses with 0.01 mm and 1e-5 rad of noise (lowpair.simulate,
through the library's FK), the nominal is fitted to the arrays, and the fit is checked on 40 poses it did not
see. Run by ctest (example.python.calibrate_arrays) from the source tree.
"""
import sys

import numpy as np

import lowpair

nominal = lowpair.load("models/puma560_okamura_nominal.yaml")
actual = lowpair.load("models/puma560_okamura_actual.yaml")

fit = lowpair.simulate(actual, poses=50, seed=1, noise_position=0.01, noise_rotation=1e-5)  # mm, rad
held_out = lowpair.simulate(actual, poses=40, seed=2)                                      # noise-free
Q, P, W = fit.q, fit.positions, fit.rotations       # (50, 6), (50, 3), (50, 4) qw,qx,qy,qz: the CSV's columns

cal = lowpair.calibrate(nominal, q=Q, positions=P, rotations=W, noise_position=0.01, noise_rotation=1e-5,
                        free_pitch=True, validation_q=held_out.q, validation_positions=held_out.positions,
                        validation_rotations=held_out.rotations)
before, after = cal.validation["before"]["rms_position"], cal.validation["after"]["rms_position"]
print(f"rank {cal.rank} of {cal.expected}, {cal.iterations} iterations, accepted: {cal.accepted} {cal.reason}")
print(f"fit RMS position {cal.before['rms_position']:.4g} -> {cal.after['rms_position']:.4g} {nominal.length_unit}")
print(f"held out RMS position {before:.4g} -> {after:.4g} {nominal.length_unit}")

# the calibrated robot predicts the held-out positions: its FK (in the nominal's base frame) moved into the
# measurement frame by its measurement_frame (T_measurement_base)
T = cal.robot.measurement_frame @ cal.robot.fk(held_out.q, model="poe")
rms = np.sqrt(np.mean(np.sum((T[:, :3, 3] - held_out.positions) ** 2, axis=1)))

# the errors put in are tens of millimetres; after the fit the held-out error is of the order of the noise
# (0.01 mm per coordinate), so at least a thousand times smaller
ok = (cal.accepted and cal.rank == cal.expected and before > 1.0 and after < 0.02 and after < before / 1000
      and abs(rms - after) <= 1e-9 * before)
sys.exit(0 if ok else 1)
