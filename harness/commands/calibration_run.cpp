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
  if (options.deflects() && a.select) {
    throw UsageError(spelling.name("select"), "cross-validation does not fit joint deflections (compliance, backlash: "
                                             "given or in " + nominal_file.path + "): choose the parameters by " +
                                                 spelling.name("parameters"));
  }
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  std::optional<CrossValidation> cv;
  if (a.select) {
    // at least one pose per fold: said with the argument's name, and with the cause when joint vectors repeat
    const int poses = crossValidationPoses(fit.measurements);
    if (poses < a.folds) {
      std::vector<VecX> qs;
      for (const Measurement& m : fit.measurements) qs.push_back(m.q);
      std::sort(qs.begin(), qs.end(), [](const VecX& x, const VecX& y) {
        return std::lexicographical_compare(x.data(), x.data() + x.size(), y.data(), y.data() + y.size());
      });
      const auto distinct = static_cast<size_t>(std::unique(qs.begin(), qs.end()) - qs.begin());
      const size_t n = fit.measurements.size();
      const bool repeats = (fit.measure != Measure::Targets && static_cast<size_t>(poses) < n) ||
                           distinct < static_cast<size_t>(poses);
      std::string text = std::to_string(a.folds) + " folds but " + fit.path + " holds " + std::to_string(poses) +
                         (poses == 1 ? " pose" : " poses");
      if (repeats) {
        text += ": its " + std::to_string(n) + " measurements repeat joint vectors, " + std::to_string(distinct) +
                " distinct (duplicates: consecutive measurements at one joint vector are one pose)";
      }
      text += "; cross-validation deals poses to folds and needs at least as many poses as folds";
      if (poses >= 2) text += " (at most " + std::to_string(poses) + " folds here, or more poses)";
      throw UsageError(spelling.name("folds"), text);
    }
    if (const auto problem = crossValidationSizeProblem(fit.measurements.size(), nominal.dof(), fit.measure,
                                                        static_cast<int>(fit.target_names.size()), a.folds, a.repeats)) {
      throw UsageError(spelling.name("repeats"), *problem);
    }
    cv = crossValidate(nominal, fit.measurements, options, a.folds, a.repeats);
    options.parameters = cv->chosen;
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
  report.cross_validation = std::move(cv);
  report.deflections = std::move(deflections);
  report.prior_unit_assumed = a.prior && !io::metresPerUnit(nominal_file.length_unit);
  return report;
}

std::string calibratedName(const io::RobotFile& nominal) {
  return (nominal.name.empty() ? std::filesystem::path(nominal.path).stem().string() : nominal.name) + "-calibrated";
}

}  // namespace lowpair::commands
