#pragma once
/// @file calibration_internal.hpp (internal, not installed)
/// What the calibration's files share: joint tags, input checks, a model's prediction of a measurement,
/// the registration with or without the frame, and the rank analysis of a dimensionless Jacobian.

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/kinematics.hpp"

namespace lowpair::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline bool hasPitch(const JointMotion& joint, bool free_pitch) {
  return joint.type == JointType::Helical || (free_pitch && joint.type == JointType::Revolute);
}

inline std::string jointTag(int i) { return "j" + std::to_string(i + 1); }

// error_model.cpp: Measure::Targets with the spec's targets (each with a finite point: ErrorModelSpec::validate),
// and only it; at least one pose, each of `dof` finite joint values
void checkTargets(Measure measure, const ErrorModelSpec& spec);
void checkPoses(const std::vector<VecX>& q, int dof);

// registration.cpp: a measurement's target index within `targets`; every measurement's size and numbers
void checkTargetIndex(const Measurement& m, Measure measure, size_t targets);
void checkMeasurements(const PoeModel& nominal, const std::vector<Measurement>& measurements, Measure measure,
                       size_t targets);

// The measured quantity the model predicts (Targets: the point `T p_t`, rotation `T.R`).
Pose predict(const PoeModel& model, Data& data, const Measurement& m, Measure measure,
             const std::vector<Vec3>& target_points);

// A measurement's errors against its prediction: position (length) and rotation (rad; 0 for points).
struct MeasurementErrors {
  double position = 0.0, rotation = 0.0;
};
MeasurementErrors measurementErrors(const Pose& predicted, const Measurement& m, Measure measure);

// registerMeasurementFrame, with `frame` false: the identity frame (only the unknown targets estimated)
Registration registration(const PoeModel& model, const std::vector<Measurement>& measurements, Measure measure,
                          const std::vector<Target>& targets, bool frame);

// identifiability.cpp: the analysis of a matrix whose rows are already dimensionless (analyzeRank after
// its row scaling). `column_scale` receives the column factors (1 / norm, 1 for a zero column) and `V` the
// full right singular vectors of the scaled matrix.
RankAnalysis analyzeDimensionless(const MatX& A, int poses, VecX* column_scale = nullptr, MatX* V = nullptr);

// deflection.cpp: the deflection parameters of a spec in column order, per joint its compliance then its backlash
// (true: compliance); a parameter's input at a pose (0 when not given); the spec's deflection joints (in range, each
// once per kind) and values (empty or one per joint)
std::vector<std::pair<int, bool>> deflectionOrder(int dof, const ErrorModelSpec& spec);
double deflectionInput(const PoseLoad& load, int joint, bool compliance);
void checkDeflectionSpec(const PoeModel& model, const ErrorModelSpec& spec);

}  // namespace lowpair::detail
