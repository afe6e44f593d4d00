#pragma once
/// @file registration.hpp
/// A model against measurements: predictions, residual statistics, the model moved as a whole, and the
/// closed-form registration of the measurement frame (docs/calibration.md).

#include <vector>

#include "lowpair/measure.hpp"
#include "lowpair/model.hpp"

namespace lowpair {

/// Residual statistics of a model against measurements: position error `|p_meas - p_model|` (length) and
/// rotation error `rotationAngle(R_model^T R_meas)` (rad; 0 for position measurements).
struct ResidualStatistics {
  int count = 0;
  double rms_position = 0.0, max_position = 0.0;
  double rms_rotation = 0.0, max_rotation = 0.0;
};

/// @param target_points for Measure::Targets the targets' points (tool frame; index = Measurement::target): a
/// result's (CalibrationResult::target_points, Registration::target_points) or the targets' own
ResidualStatistics residualStatistics(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Vec3>& target_points = {});

/// The measured point or pose a model predicts for one measurement (Targets: `T(q) point`).
/// @param target_points as residualStatistics
Pose predictedMeasurement(const PoeModel& model, const Measurement& m, Measure measure,
                          const std::vector<Vec3>& target_points = {});

/// `model` moved as a whole by `T_frame_base`: every twist `Ad(T) xi`, the tool `T T_tool`. Its forward
/// kinematics is `T_frame_base T_base_tool(q)`: the same robot seen from another frame.
PoeModel movedModel(const PoeModel& model, const Pose& T_frame_base);

/// The closed-form rigid registration (Horn; Kabsch-Umeyama without scale) of the measurement frame:
/// the pose `T_meas_base` of the model's base frame in the measurement frame that best maps the model's
/// predicted points (tool origins or targets' points; for Pose data the rotations as well, weighted by L^2)
/// onto the measured ones. Targets without a point are estimated in turn (each the mean of its measured
/// points expressed in the predicted tool frame), alternating with the registration until both settle.
struct Registration {
  Pose T_meas_base;
  std::vector<Vec3> target_points;  ///< every target's point (tool frame): given or estimated
  std::vector<bool> estimated;      ///< per target: its point was estimated (it had none)
  int iterations = 0;
  bool determined = true;  ///< false: the predicted points are collinear (and no rotations): identity kept
};

/// @throws std::invalid_argument as calibrate for bad measurements
Registration registerMeasurementFrame(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Target>& targets = {});

}  // namespace lowpair
