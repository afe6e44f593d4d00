// The fit of calibrate for the CLI and the Python module (calibration_run.hpp).
#include "commands/calibration_run.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "lowpair/cross_validation.hpp"

#include "io/output.hpp"
#include "commands/calibration_inputs.hpp"
#include "commands/deflection_inputs.hpp"
#include "commands/selection.hpp"

namespace lowpair::commands {

std::optional<std::string> calibrationSizeProblem(const io::MeasurementFile& fit, int dof) {
  const size_t measurements = fit.measurements.size();
  const IdentificationSize s = identificationSize(static_cast<double>(measurements), dof, 7.0, fit.measure,
                                                  static_cast<double>(fit.target_names.size()));
  if (measurements <= static_cast<size_t>(kMaxCalibrationMeasurements) && s.entries() <= kMaxJacobianEntries &&
      s.work() <= kMaxIdentificationWork) {
    return std::nullopt;
  }
  return std::to_string(measurements) + " measurements of " + std::to_string(dof) + " joints" +
         (fit.target_names.empty() ? std::string() : " and " + std::to_string(fit.target_names.size()) + " targets") +
         "; calibrate fits at most " + std::to_string(kMaxCalibrationMeasurements) + " measurements, at most " +
         io::shortest(kMaxJacobianEntries) + " numbers at once and at most " + io::shortest(kMaxIdentificationWork) +
         " work per SVD (rows columns^2 + 5 columns^3, here " + io::shortest(s.work()) + ")";
}

CalibrationReport runCalibration(const io::RobotFile& nominal_file, const PoeModel& nominal, io::MeasurementFile fit,
                                 std::optional<io::MeasurementFile> validation, const CalibrationRequest& request,
                                 const ArgumentSpelling& spelling) {
  const CalibrationRequest& a = request;
  checkStatedNoise(a.noise_position, a.noise_rotation, spelling);
  const bool rotations = std::any_of(fit.measurements.begin(), fit.measurements.end(),
                                     [&](const Measurement& m) { return measuresPose(m, fit.measure); });
  if (a.noise_rotation && !rotations) {  // (mixed data: the poses among the targets' points have one)
    throw UsageError(spelling.name("noise_rotation"), fit.path + " holds " + measurementsText(fit.measure) +
                                                          ": there is no rotation to weigh");
  }
  if (!(a.outlier_threshold >= 1e-3 && a.outlier_threshold <= 1e6)) {
    throw UsageError(spelling.name("outlier_threshold"), "must be in [0.001, 1e6], got " + io::shortest(a.outlier_threshold));
  }
  if (a.loss != "squared" && a.loss != "huber" && a.loss != "cauchy") {
    throw UsageError(spelling.name("loss"), "expected 'squared', 'huber' or 'cauchy', got " + io::quotedFileText(a.loss));
  }
  if (a.select && *a.select != "cv") {
    throw UsageError(spelling.name("select"), "expected 'cv' or None, got " + io::quotedFileText(*a.select));
  }
  if (!(a.folds >= 2 && a.folds <= kMaxCrossValidationFolds)) {
    throw UsageError(spelling.name("folds"), "must be in [2, " + std::to_string(kMaxCrossValidationFolds) + "], got " +
                                                 std::to_string(a.folds));
  }
  if (!(a.repeats >= 1 && a.repeats <= kMaxCrossValidationRepeats)) {
    throw UsageError(spelling.name("repeats"), "must be in [1, " + std::to_string(kMaxCrossValidationRepeats) +
                                                   "], got " + std::to_string(a.repeats));
  }
  CalibrationOptions options;
  options.measure = fit.measure;
  options.free_pitch = a.free_pitch;
  options.sigma_position = a.noise_position;
  options.sigma_rotation = a.noise_rotation;
  options.loss = a.loss == "huber" ? Loss::Huber : a.loss == "cauchy" ? Loss::Cauchy : Loss::Squared;
  options.outlier_threshold = a.outlier_threshold;
  if (a.prior) options.prior = parsePrior(*a.prior, io::metresPerUnit(nominal_file.length_unit), spelling);
  checkSelectionArguments(SelectionRequest{a.folds, a.repeats, a.prior_grid, a.cv_score}, a.select.has_value(),
                          a.prior.has_value(), spelling);
  if (a.parameters) {
    if (a.select) {
      throw UsageError(spelling.name("select"), "choose the parameters by " + spelling.name("parameters") + " or by " +
                                                    spelling.name("select") + ", not both");
    }
    parseParameters(*a.parameters, options, spelling);
  }
  // targets: the fit's names; a point from the nominal's targets: list of the same name, else estimated
  options.targets = nominalTargets(nominal_file, fit.target_names);
  DeflectionChoice deflections = chooseDeflections(nominal_file, nominal, a.compliance, a.backlash, fit.measurements,
                                                   fit.sign_columns, fit.signs, fit.path, options, spelling);
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  std::optional<Selection> selection;
  if (a.select) {
    selection = selectByCrossValidation(nominal_file, nominal, fit, SelectionRequest{a.folds, a.repeats, a.prior_grid, a.cv_score},
                                        options, deflections, spelling);
  }
  CalibrationResult result = calibrate(nominal, fit.measurements, options);
  std::vector<PoseLoad> validation_loads;  // the validation set's deflection inputs, as the fit's
  if (validation && options.deflects()) {
    CalibrationOptions held_out = options;
    held_out.move_signs = measurementMoveSigns(validation->measurements, options.backlash_joints, validation->sign_columns,
                                               validation->signs);
    validation_loads = measurementLoads(nominal, validation->measurements, held_out);
  }
  // the calibrated robot in the nominal's base frame (the gauge) and its D-H table there
  CalibratedBaseFrame base_frame = calibratedBaseFrame(result, nominal);
  DhUncertainty dh = dhUncertainty(result, nominal);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CalibrationReport report = makeCalibrationReport(nominal_file, std::move(fit), std::move(validation), std::move(result),
                                                   std::move(dh), seconds, std::move(base_frame), validation_loads);
  report.selection = std::move(selection);
  report.deflections = std::move(deflections);
  report.prior_unit_assumed = !report.result.prior.none() && !io::metresPerUnit(nominal_file.length_unit);
  return report;
}

std::string calibratedName(const io::RobotFile& nominal) {
  return (nominal.name.empty() ? std::filesystem::path(nominal.path).stem().string() : nominal.name) + "-calibrated";
}

}  // namespace lowpair::commands
