#pragma once
/// @file measure.hpp
/// What a measurement observes of the tool (docs/calibration.md), and one measurement.

#include <optional>
#include <string>

#include "lowpair/types.hpp"

namespace lowpair {

/// What a measurement observes of the tool: its frame, its origin, or points fixed on it (targets: a laser
/// tracker's SMRs, several per pose, each at an unknown or known point of the tool).
enum class Measure { Pose, Position, Targets };

/// "pose" / "position" / "targets".
const char* measureName(Measure measure);
/// "pose measurements" / "position measurements" / "target measurements": for sentences.
const char* measurementsText(Measure measure);

/// Rows per measurement: 6 for Pose (`[dtheta; dp]`), 3 otherwise.
constexpr int rowsPerMeasurement(Measure measure) { return measure == Measure::Pose ? 6 : 3; }

/// Rows per pose: one measurement (Pose, Position) or 3 per target (Targets: `targets` of them).
constexpr int rowsPerPose(Measure measure, int targets) {
  return measure == Measure::Targets ? 3 * targets : rowsPerMeasurement(measure);
}

/// One measurement: joint variables of the model and what was measured in the measurement frame (the base
/// frame of the model being calibrated): the tool frame (Pose), its origin (Position: `T_base_tool.p`), or
/// one target's point (Targets: `T_base_tool.p`, `target` its index). Target data may mix in measurements of
/// the whole tool frame (a 6-DOF probe beside the SMRs): a Targets measurement with `target` kPoseMeasurement.
struct Measurement {
  VecX q;
  Pose T_base_tool;
  int target = -1;  ///< Targets: index into the targets (CalibrationOptions::targets), or kPoseMeasurement
};

/// Measurement::target of a measurement of the tool frame among target measurements (mixed data).
constexpr int kPoseMeasurement = -1;

/// The measurement observes the tool frame's rotation too: Measure::Pose, or a pose among target measurements.
inline bool measuresPose(const Measurement& m, Measure measure) {
  return measure == Measure::Pose || (measure == Measure::Targets && m.target == kPoseMeasurement);
}

/// Its residual rows: 6 for a pose (`[dtheta; dp]`), 3 for a point.
inline int rowsOf(const Measurement& m, Measure measure) { return measuresPose(m, measure) ? 6 : 3; }

/// A point fixed on the tool (an SMR): its name and its position in the tool frame (length): a start for the
/// fit's estimate, or, when `known` (from a calibrated nest), fixed. Unknown points carry the tool frame (it
/// is not determined); three or more non-collinear known points determine it (docs/calibration.md).
///
/// The one targets type of the API: what says which targets there are (names, points or none, known flags)
/// is a `std::vector<Target>`, and every field or parameter named `targets` is one (CalibrationOptions,
/// PlanOptions, ErrorModelSpec, PlanCandidates, registerMeasurementFrame). Where only where the targets are
/// matters, their points are a `std::vector<Vec3>` named `target_points` (index = Measurement::target, the
/// targets described elsewhere): the results (Registration, CalibrationResult, ErrorModel::targetPoints) and
/// what evaluates a model at given points (residualStatistics, predictedMeasurement, ErrorModel::rebased).
struct Target {
  std::string name;
  std::optional<Vec3> point_tool;
  bool known = false;  ///< the point is not estimated (needs point_tool)
};

}  // namespace lowpair
