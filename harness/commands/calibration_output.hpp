#pragma once
/// @file calibration_output.hpp
/// Text and JSON of `lowpair identifiability` and `lowpair calibrate` (README, docs/calibration.md), also
/// used by the calibration section of a scenario report.

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "io/measurements.hpp"
#include "io/robot_file.hpp"
#include "commands/deflection_inputs.hpp"
#include "commands/limits.hpp"
#include "commands/selection.hpp"

namespace lowpair::commands {

/// Upper bound on `identifiability --poses` (the Jacobian has 6 rows per pose).
constexpr int kMaxIdentifiabilityPoses = 10000;
/// Upper bound on the measurements `calibrate` fits (and a scenario's `poses`): the weighted Jacobian and its
/// SVD hold 6 rows per measurement, about 40 MB at this limit for 7 joints. Validation files are read whole
/// (bounded by the CSV reader's limits) and only evaluated.
constexpr int kMaxCalibrationMeasurements = 10000;

/// Residuals of the validation set before (the nominal, registered in the measurement frame) and after
/// (calibrated), with its own measure; `outside`: the validation measurements with a joint value outside the
/// range the fitting measurements cover (extrapolation), their residuals after apart (`inside` the others).
struct ValidationResiduals {
  ResidualStatistics before, after;
  int outside_count = 0;
  ResidualStatistics inside_after, outside_after;
};

/// A validation set that contradicts an accepted calibration by orders of magnitude rejects it (exit 1,
/// nothing written): its RMS position error after the fit above kMaxValidationRatio times the fit's own AND
/// above kMaxValidationRelativeRms of the robot size L. Why both: held-out residuals of a model that fits are
/// of the order of the fit's (0.005 to 1 times them in the walk-throughs of docs/calibration.md and plan.md:
/// noisy or noise-free sets, blunders in the fit; somewhat more where a set extrapolates beyond the fit's joint
/// ranges); a factor 100 is no such spread but a set of other numbers, typically lengths in another
/// unit than its `# length_unit` says (x 1000 for mm written as m, x 25.4 for inches). The L bound keeps a
/// noise-free fit (after ~1e-12 L) from rejecting on a validation set with ordinary noise: it is the
/// verdict's own bound on an accepted fit's RMS without stated noise (kMaxRelativeRmsPosition, 1 %), so a set
/// beyond both is one that calibrate would not have accepted as fitting data either.
constexpr double kMaxValidationRatio = 100.0;
constexpr double kMaxValidationRelativeRms = kMaxRelativeRmsPosition;

/// The calibrated robot in the nominal's base frame (the gauge, base_frame.hpp) and the measurement frame
/// with its standard deviations (numerical propagation, dh_uncertainty.hpp).
struct CalibratedBaseFrame {
  BaseFrameGauge gauge;  ///< rule, T_measurement_base, the calibrated model in the nominal's base frame
  MeasurementFrameUncertainty sd;
};
/// toNominalBase and measurementFrameUncertainty of a calibration of `nominal`.
CalibratedBaseFrame calibratedBaseFrame(const CalibrationResult& result, const PoeModel& nominal);

/// Everything `calibrate` prints: its inputs, the fit, and the numbers derived from them, computed once by
/// makeCalibrationReport (the renderers below only format them).
struct CalibrationReport {
  io::RobotFile nominal;
  io::MeasurementFile fit;
  std::optional<io::MeasurementFile> validation;
  CalibrationResult result;
  DhUncertainty dh;
  double seconds = 0.0;  ///< calibrate + dhUncertainty
  std::optional<ValidationResiduals> validation_residuals;  ///< set when there is a validation file
  /// The validation set contradicts the fit (kMaxValidationRatio): result.accepted was set false and
  /// result.reason says so; rejectionText then names the validation file and the units first.
  bool validation_contradicts = false;
  /// The nominal moved into the measurement frame by the registration (what "before" and the change per
  /// joint compare with).
  std::optional<PoeModel> registered_nominal;
  /// Each target's name and whether its starting point was the nominal file's (else estimated).
  std::vector<std::string> target_names;
  std::vector<bool> target_from_file;
  std::optional<Selection> selection;  ///< `--select cv`: the candidates, their scores, the choice
  std::vector<std::string> notes;  ///< e.g. a unit conversion of the measurements
  /// The warnings in sentences: rank below the count (with the undetermined directions), no convergence,
  /// residuals inconsistent with the stated noise, the D-H conversion's conditioning (its FK check, once).
  std::vector<std::string> warnings;
  /// `calibrate`: the calibrated robot in the nominal's base frame; `dh` is then its table (the change per joint
  /// and the D-H table compare in the base frame). Unset (a scenario's report): all in the measurement frame.
  std::optional<CalibratedBaseFrame> base_frame;
  /// The joints whose compliance and backlash were fitted and where their inputs came from (none: no deflection).
  DeflectionChoice deflections{};
  bool prior_unit_assumed = false;  ///< --prior with a robot of unknown length unit: 1 mm taken as 1 unit
};

/// Moves the inputs in and computes the validation residuals and the warnings; rejects an accepted fit whose
/// validation set contradicts it (kMaxValidationRatio).
/// @param base_frame the calibrated robot in the nominal's base frame, `dh` its table (calibrate), or none
/// @param validation_loads the validation set's deflection inputs (measurementLoads) when the fit has deflections:
/// its residuals are then taken at the deflected joints (before: the nominal file's deflections, after: the fit's)
CalibrationReport makeCalibrationReport(io::RobotFile nominal, io::MeasurementFile fit,
                                        std::optional<io::MeasurementFile> validation, CalibrationResult result,
                                        DhUncertainty dh, double seconds,
                                        std::optional<CalibratedBaseFrame> base_frame = std::nullopt,
                                        const std::vector<PoseLoad>& validation_loads = {});

nlohmann::json identifiabilityJson(const io::RobotFile& file, const Identifiability& id);
void printIdentifiability(std::ostream& out, const Identifiability& id);

/// A D-H table with standard deviations (a calibration's, or a plan's expected ones): the values as
/// `poe2dh` prints them (lengths to about 1e-6 L, angles to 1e-6 deg), then the standard deviations in the
/// same shape under `deviations_title` ("fixed" where the D-H convention sets the entry); 108 columns.
void printDhWithDeviations(std::ostream& out, const io::RobotFile& file, const DhUncertainty& dh,
                           const std::string& deviations_title);
/// The same as JSON: base, joints, tool, each value with `sd` (null = undetermined) and `fixed`.
nlohmann::json dhUncertaintyJson(const DhUncertainty& dh);

/// The rank of a fit against its parameters, as calibrate prints it: "rank 42 of 42" (the full set: of the
/// count), "lines, rank 33 of 33 (the complete set would be 39)" (a level or named parameters: of those fitted).
std::string parameterRankText(const CalibrationResult& result);

nlohmann::json calibrationJson(const CalibrationReport& report);
void printCalibration(std::ostream& out, const CalibrationReport& report);
/// The `#` lines of a calibrated robot file: where it came from and how well it fits.
std::vector<std::string> calibrationProvenance(const CalibrationReport& report);
/// The model `calibrate --out` writes: the base-frame robot (or, `measurement_frame`, the one in the measurement
/// frame), and the `measurement_frame:` key it records (none in the measurement frame).
const PoeModel& calibratedModel(const CalibrationReport& report, bool measurement_frame);
std::optional<Pose> recordedMeasurementFrame(const CalibrationReport& report, bool measurement_frame);
/// The masses `calibrate --out` records: the nominal file's (none without), moved into the measurement frame when
/// the model is written there (centres of mass and gravity turned and moved by T_measurement_base).
std::optional<MassModel> calibratedMasses(const CalibrationReport& report, bool measurement_frame);
/// The calibrated targets as a robot file lists them (tool frame of the calibrated model).
std::vector<Target> calibratedTargets(const CalibrationReport& report);
/// What the calibration determined of the tool frame (CalibrationResult::tool_rank), as `calibrate --out` records it.
io::ToolFrame calibratedToolFrame(const CalibrationResult& result);

/// How many of the worst measurements the text lists.
constexpr int kWorstMeasurementsShown = 5;
/// The indices of the `count` measurements with the largest normalized residuals, largest first.
std::vector<size_t> worstMeasurements(const CalibrationResult& result, size_t count);
/// The verdict's one line for stderr when the fit is rejected: what is wrong (the result's reason), the
/// worst lines of the measurement file, and the likely causes in order.
std::string rejectionText(const CalibrationReport& report);

/// "0.71 j6.scale - 0.50 j5.tilt1 + ..." (the largest coefficients first, at most six terms).
std::string directionText(const std::vector<std::pair<int, double>>& direction, const std::vector<std::string>& names);

}  // namespace lowpair::commands
