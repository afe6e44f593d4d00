#pragma once
/// @file scenario.hpp
/// Scenarios (scenarios/*.yaml, README "Scenario format"): what `lowpair validate` compares, over which
/// samples, with which tolerances, and the singular poses it checks.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/plan.hpp"
#include "commands/plan_report.hpp"  // a case's plan: the limits of `lowpair plan` (kMaxPlanCandidates, ...)
#include "commands/sampling.hpp"

namespace lowpair::validation {

struct NamedPose {
  std::string name;
  std::vector<double> q;
};

/// A singular configuration with the Paden–Sastry classes it must show (conventions.md ids, or "other").
struct SingularPose {
  std::string name;
  std::vector<double> q;
  std::vector<std::string> classes;
};

/// Upper bound on `samples` (a scenario or --samples).
constexpr int kMaxSamples = 100000000;


/// `plan: {criterion: D|O1, candidates: M}` (or `plan: D`): the fitting poses are chosen by planPoses on the
/// nominal from the candidates, samples 0 .. M-1 of the case's stream (the candidates `lowpair plan --seed
/// SEED --candidates M` draws when the nominal's ranges are the scenario's).
struct CasePlan {
  PlanCriterion criterion = PlanCriterion::D;
  int candidates = commands::kDefaultPlanCandidates;
};

/// `compensate: {tolerance: T, allowed_not_ok: K, base_frame: B}`: the validation joint vectors taken as a
/// nominal program, compensated on the calibrated model (lowpair/ik.hpp compensate) and commanded on MuJoCo's
/// actual robot.
struct CaseCompensation {
  double tolerance = 0.0;  ///< acceptance: RMS position error after compensation (length)
  int allowed_not_ok = 0;  ///< acceptance: rows whose compensation status is not ok, at most
  /// `base_frame: true`: compensate with the robot `calibrate --out` writes (the nominal's base frame,
  /// lowpair/base_frame.hpp), not with the case's known frame, and judge the tool against the nominal program
  /// up to one rigid motion (the actual's base error, registered in closed form and reported).
  bool base_frame = false;
};

/// A calibration in the loop (docs/calibration.md): the nominal robot file is calibrated from `poses`
/// measurements of the scenario's MuJoCo model (the "actual" robot; q is the scenario's joint variable),
/// then checked on `validation_poses` noise-free measurements of it.
///
/// Samples of the case's stream (seed): without `plan`, the fitting poses are samples 0 .. poses-1 and the
/// validation poses samples poses .. poses+validation_poses-1; with `plan`, the candidates are samples
/// 0 .. M-1, the fitting poses the planned ones among them (in sample order; fitting row k gets the noise of
/// row k, as `simulate --q-file`), and the validation poses samples M .. M+validation_poses-1 (disjoint from
/// every candidate).
struct CalibrationCase {
  std::string name;
  std::string nominal;            ///< robot file
  int poses = 50;                 ///< fitting poses (see above)
  int validation_poses = 200;     ///< noise-free validation poses (see above)
  unsigned long long seed = 1;
  bool position_only = false;     ///< `measure: position`
  bool free_pitch = false;
  double noise_position = 0.0;    ///< length (the nominal's unit), per coordinate
  double noise_rotation = 0.0;    ///< rad
  double tolerance_position = 0.0;  ///< acceptance: validation RMS position after calibration (length)
  std::optional<double> tolerance_rotation;  ///< acceptance: validation RMS rotation after (rad), pose only
  std::optional<double> min_improvement;     ///< acceptance: validation RMS position before / after
  /// `targets:` sites of the model, fixed to the tip, measured as points (Measure::Targets, one measurement per
  /// site per pose, in this order); their points are estimated unless the nominal lists targets of the same names.
  std::vector<std::string> targets;
  /// `frame: {rotation: [rx, ry, rz], translation: [x, y, z]}`: the measurement frame's pose relative to the
  /// model's base (rotation vector, rad; translation, length): every measurement is expressed in it
  /// (commands/sampling.hpp measurementFrame). Unset: the base frame.
  std::optional<std::array<double, 6>> frame;
  long long blunders = 0;     ///< `blunders: {count, size}`: fitting measurements moved by `blunder_size` (addBlunders)
  double blunder_size = 0.0;  ///< length
  Loss loss = Loss::Squared;  ///< `loss:`
  std::optional<CasePlan> plan;                  ///< `plan:`
  std::optional<CaseCompensation> compensation;  ///< `compensate:`
  /// The first validation sample of the stream: `poses`, or M with a plan.
  int firstValidationSample() const { return plan ? plan->candidates : poses; }
  Measure measure() const {
    return !targets.empty() ? Measure::Targets : position_only ? Measure::Position : Measure::Pose;
  }
};

/// Upper bound on a calibration case's validation poses (its fitting `poses`: kMaxCalibrationMeasurements).
constexpr int kMaxCalibrationPoses = 100000;

struct Scenario {
  std::string path;  ///< the scenario file ("" for a model given on the command line)
  std::string name;
  std::string model;  ///< MJCF or URDF path
  std::string tip, base;
  std::string joint_variables;           ///< robot file whose scales/offsets define the sampled q ("" = MuJoCo's)
  std::vector<std::string> robot_files;  ///< cross-checked robot files
  int samples = 10000;
  unsigned long long seed = 1;
  std::vector<std::array<double, 2>> ranges;  ///< per joint, in the sampled variable (empty = defaults)
  /// The model's length unit (YAML `length_unit`, `validate --length-unit`): robot files that state another
  /// are converted into it before the comparison. A URDF's is "m" (URDF fixes it); "" for an MJCF that
  /// states none: robot files are compared as they are.
  std::string length_unit;
  double tol_rotation = 1e-12;                ///< rad
  double tol_translation = 1e-12;             ///< times the robot size L
  double tol_jacobian_rotation = 1e-12;       ///< rad (per unit joint rate)
  double tol_jacobian_translation = 1e-12;    ///< times L
  std::vector<NamedPose> poses;
  std::vector<SingularPose> singular_poses;
  /// Singularity map: log10(sigma_min) over joints (1-based) map_joints on [-pi, pi]^2 (or their ranges),
  /// the other joints at map_fixed (default: 0.4 rad / mid-range). Empty map_joints: joints 2 and 3.
  std::vector<int> map_joints;
  std::vector<double> map_fixed;
  std::vector<CalibrationCase> calibrations;
};

/// @throws io::RobotFileError ("FILE: line N: what")
Scenario readScenario(const std::string& path);

}  // namespace lowpair::validation
