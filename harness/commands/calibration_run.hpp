#pragma once
/// @file calibration_run.hpp
/// The fit of `lowpair calibrate`, shared by the CLI and the Python module's lowpair.calibrate: the size
/// limit, the checks of the arguments, the options filled from them, the optional cross-validation, the fit,
/// the D-H uncertainty and the report; and the name of the calibrated robot.

#include <optional>
#include <string>

#include "io/measurements.hpp"
#include "io/robot_file.hpp"
#include "lowpair/calibration.hpp"
#include "commands/arguments.hpp"
#include "commands/calibration_output.hpp"

namespace lowpair::commands {

/// The arguments of a calibration beyond its measurements, as the CLI's options and Python's keywords give
/// them (named in messages by their Python names, as an ArgumentSpelling spells them).
struct CalibrationRequest {
  std::optional<double> noise_position, noise_rotation;  ///< stated noise: length, rad
  bool free_pitch = false;
  std::string loss = "squared";                   ///< squared, huber or cauchy
  double outlier_threshold = 5.0;                 ///< in [1e-3, 1e6]
  std::optional<std::string> parameters, select;  ///< parseParameters' text; select: "cv"
  int folds = 5;                                  ///< in [2, kMaxCrossValidationFolds]
  int repeats = kCrossValidationRepeats;          ///< in [1, kMaxCrossValidationRepeats]
  /// Joint deflections to fit (deflection_inputs.hpp parseJointList): compliance `all` or joints, backlash joints.
  std::optional<std::string> compliance, backlash;
  /// A prior on the nominal (parsePrior's text: WIDTH or tilt=..,shift=..,scale=..,offset=..); none: no prior.
  std::optional<std::string> prior;
  /// `--select cv`'s candidates and score (selection.hpp): the prior widths compared (parsePriorGrid's text: `default`
  /// or WIDTHs; none: no grid), the score (rms, trimmed or median; none: rms).
  std::optional<std::string> prior_grid, cv_score;
};

/// What is wrong with fitting `fit`'s measurements of a `dof`-joint robot at once (more than
/// kMaxCalibrationMeasurements, or an identification above kMaxJacobianEntries or kMaxIdentificationWork:
/// limits.hpp, with 3 columns per target), without a subject; nothing when it fits.
std::optional<std::string> calibrationSizeProblem(const io::MeasurementFile& fit, int dof);

/// Checks `request` against the fit's measurements (stated noise, rotation noise with pose measurements
/// only, the ranges and choices, parameters or select but not both), fills the options, chooses the
/// parameters by cross-validation when select is "cv", fits, and makes the report (its `seconds`: the
/// cross-validation, the fit and the D-H uncertainty). The validation set's targets must already be the
/// fit's (mapValidationTargets).
/// @param nominal_file the nominal robot file (its targets: start the fit's targets of the same names)
/// @param nominal its POE model
/// @throws UsageError naming the argument as `spelling` spells it; std::invalid_argument as calibrate does
CalibrationReport runCalibration(const io::RobotFile& nominal_file, const PoeModel& nominal, io::MeasurementFile fit,
                                 std::optional<io::MeasurementFile> validation, const CalibrationRequest& request,
                                 const ArgumentSpelling& spelling);

/// The name of the robot a calibration of `nominal` makes: its name (else its file's stem) + "-calibrated".
std::string calibratedName(const io::RobotFile& nominal);

}  // namespace lowpair::commands
