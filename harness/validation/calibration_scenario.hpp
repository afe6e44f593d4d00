#pragma once
/// @file calibration_scenario.hpp
/// Calibration in the loop (a scenario's `calibration:` cases, docs/calibration.md): measurements of MuJoCo's
/// "actual" robot, the nominal robot file calibrated from them, the result checked on held-out noise-free
/// measurements against the case's acceptance.

#include <array>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/plan.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/measurements.hpp"
#include "commands/calibration_output.hpp"
#include "commands/sampling.hpp"
#include "validation/scenario.hpp"

namespace lowpair::validation {

/// A case's `plan:` (CasePlan): the poses planPoses chose on the nominal among the candidates.
struct CasePlanResult {
  PlanResult plan;    ///< `plan.indices`: the chosen candidates, i.e. samples of the case's stream, increasing
  /// The criterion of candidates 0 .. poses-1: the samples the case would fit without `plan:`.
  PlanValue first;
  double seconds = 0.0;  ///< planCandidates + planPoses
};

/// A case's `compensate:` (CaseCompensation). Every validation joint vector q is a nominal program: its target
/// is the nominal's FK at q (in the robot's base frame: the tool frame for pose measurements and for targets
/// that determined the tool frame (three known points), the tool origin for position measurements, the first
/// target's point for targets that did not). `q' = compensate(nominal, calibrated, q)` (lowpair/ik.hpp; the
/// calibrated model moved from the measurement frame into the base frame by the case's known `frame:`, or with
/// `base_frame: true` the nominal's base frame of calibrate --out), and MuJoCo's actual robot is commanded at q
/// (before) and at q' (after), through the scenario's joint-variable map. A row whose status is not ok is
/// counted and listed, never commanded.
struct CompensationResult {
  Measure measure = Measure::Pose;  ///< the compensated task: Pose, or Position (of `point_tool`)
  /// The calibration determined the tool frame (CalibrationResult::tool_rank 6); false: the tool frame is the
  /// nominal's, what `compensate` flags ("compensated for the flange"), and the task is a target's point.
  bool tool_determined = true;
  bool base_frame = false;  ///< CaseCompensation::base_frame
  /// base_frame: the rigid motion (actual's tool seen from the nominal program's base) registered before the
  /// statistics, commanding q and q'; identity otherwise.
  Pose rigid_before, rigid_after;
  std::string point_name;           ///< the target compensated (target measurements), else ""
  Vec3 point_tool = Vec3::Zero();   ///< its point in the calibrated (and nominal) tool frame
  double length_scale = 1.0;        ///< the nominal's L (the IK's position tolerance is relative to it)
  /// MuJoCo's tool against the nominal's target: commanding q (every row), commanding q' (the ok rows; NaN when
  /// there is none). Rotation for Pose only.
  ResidualStatistics before, after;
  std::array<int, 5> statuses{};  ///< rows per IkStatus (indexed by its value)
  struct Row {
    int row = 0;  ///< 0-based validation pose
    IkStatus status = IkStatus::Ok;
    std::string reason;
  };
  std::vector<Row> not_ok;  ///< the rows whose status is not ok, in order
  double seconds = 0.0;     ///< compensation and the MuJoCo evaluations
  int count() const { return before.count; }
};

struct CalibrationCaseResult {
  CalibrationCase config;
  int rank = 0, expected = 0, iterations = 0;
  bool converged = false;
  double seconds = 0.0;  ///< calibrate + D-H standard deviations
  /// Validation: the nominal registered in the measurement frame (before) and the calibrated model (after),
  /// residualStatistics over the noise-free validation measurements (targets: of the targets' points).
  ResidualStatistics fit_before, fit_after, validation_before, validation_after;
  /// Position error (length) of every validation measurement before and after, for the report's picture.
  std::vector<double> validation_position_before, validation_position_after;
  /// The calibration as `lowpair calibrate` reports it for the same data (renderers: commands/calibration_output.hpp);
  /// its result's residuals are those of the fitting measurements, in order.
  std::shared_ptr<const commands::CalibrationReport> report;
  /// The fitting measurements given a blunder (0-based, increasing), those of them not flagged as outliers,
  /// and the measurements flagged without one.
  std::vector<size_t> blunders, missed_blunders, false_outliers;
  std::optional<CasePlanResult> plan;                  ///< with `plan:`
  std::optional<CompensationResult> compensation;     ///< with `compensate:`
  bool pass = true;
  std::vector<std::string> failures;  ///< the acceptance criteria that failed, in words
};

/// The case's measurement set-up (commands/sampling.hpp): its measure, its frame, its noise when `noisy` (validation
/// measurements are noise-free), and its targets' points in the tip frame (MuJoCo sites, robot.siteInTip).
/// @throws io::RobotFileError for a target that is no site of the model fixed to the tip
commands::MeasurementSetup caseMeasurementSetup(const CalibrationCase& c, const mujoco::MujocoRobot& robot, bool noisy);

/// Poses first .. first+count-1 of the case's stream (commands/sampling.hpp: randomSample with the case's seed over
/// `ranges`), measured by MuJoCo and taken as `setup` says (appendMeasurements: frame, targets, noise): what
/// `lowpair simulate` writes for the same model, joint variable, seed, measure, frame and noise when first = 0.
/// (Blunders are added by the caller: addBlunders with the case's seed.)
io::MeasurementFile simulatedMeasurements(const CalibrationCase& c, const commands::MeasurementSetup& setup,
                                          mujoco::MujocoRobot::Evaluator& mujoco,
                                          const std::vector<JointMotion>& variables, const std::vector<commands::Range>& ranges,
                                          int first, int count, std::string label);

/// The joint vectors `q` measured by MuJoCo and taken as `setup` says, pose k with the noise of row k of the
/// case's stream (appendMeasurements): what `lowpair simulate --q-file` writes for the same q, model, joint
/// variable, seed, measure, frame and noise.
io::MeasurementFile measuredAt(const CalibrationCase& c, const commands::MeasurementSetup& setup,
                               mujoco::MujocoRobot::Evaluator& mujoco, const std::vector<JointMotion>& variables,
                               const std::vector<VecX>& q, std::string label);

/// @param sampled the scenario's sampled joint variable: its map to MuJoCo's motion, ranges and length unit
/// @throws io::RobotFileError for a nominal robot file that cannot be read, does not match the chain, or is
/// in another length unit than the measurements
CalibrationCaseResult runCalibrationCase(const Scenario& scenario, const CalibrationCase& config,
                                         const mujoco::MujocoRobot& robot, const commands::SampledVariable& sampled);

}  // namespace lowpair::validation
