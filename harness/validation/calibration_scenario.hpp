#pragma once
/// @file calibration_scenario.hpp
/// Calibration in the loop (a scenario's `calibration:` cases, docs/calibration.md): measurements of MuJoCo's
/// "actual" robot, the nominal robot file calibrated from them, the result checked on held-out noise-free
/// measurements against the case's acceptance.

#include <array>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/measurements.hpp"
#include "validation/calibration_output.hpp"
#include "validation/sampling.hpp"
#include "validation/scenario.hpp"

namespace lowpair::validation {

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
  /// The calibration as `lowpair calibrate` reports it for the same data (renderers: calibration_output.hpp);
  /// its result's residuals are those of the fitting measurements, in order.
  std::shared_ptr<const CalibrationReport> report;
  /// The fitting measurements given a blunder (0-based, increasing), those of them not flagged as outliers,
  /// and the measurements flagged without one.
  std::vector<size_t> blunders, missed_blunders, false_outliers;
  bool pass = true;
  std::vector<std::string> failures;  ///< the acceptance criteria that failed, in words
};

/// The case's measurement set-up (sampling.hpp): its measure, its frame, its noise when `noisy` (validation
/// measurements are noise-free), and its targets' points in the tip frame (MuJoCo sites, robot.siteInTip).
/// @throws io::RobotFileError for a target that is no site of the model fixed to the tip
MeasurementSetup caseMeasurementSetup(const CalibrationCase& c, const mujoco::MujocoRobot& robot, bool noisy);

/// Poses first .. first+count-1 of the case's stream (sampling.hpp: randomSample with the case's seed over
/// `ranges`), measured by MuJoCo and taken as `setup` says (appendMeasurements: frame, targets, noise): what
/// `lowpair simulate` writes for the same model, joint variable, seed, measure, frame and noise when first = 0.
/// (Blunders are added by the caller: addBlunders with the case's seed.)
io::MeasurementFile simulatedMeasurements(const CalibrationCase& c, const MeasurementSetup& setup,
                                          mujoco::MujocoRobot::Evaluator& mujoco,
                                          const std::vector<JointMotion>& variables, const std::vector<Range>& ranges,
                                          int first, int count, std::string label);

/// @param sampled the scenario's sampled joint variable: its map to MuJoCo's motion, ranges and length unit
/// @throws io::RobotFileError for a nominal robot file that cannot be read, does not match the chain, or is
/// in another length unit than the measurements
CalibrationCaseResult runCalibrationCase(const Scenario& scenario, const CalibrationCase& config,
                                         const mujoco::MujocoRobot& robot, const SampledVariable& sampled);

}  // namespace lowpair::validation
