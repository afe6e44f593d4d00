// lowpair.calibrate (`lowpair calibrate` from arrays) and the class Calibration.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common.hpp"
#include "expose.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "lowpair/calibration.hpp"
#include "robot.hpp"
#include "commands/calibration_inputs.hpp"
#include "commands/calibration_output.hpp"
#include "commands/calibration_run.hpp"

namespace lowpair::python {

namespace {

struct Calibration {
  commands::CalibrationReport report;
  RobotPtr robot;
  json j;
};

// The target names of target measurements (the CSV's `target` column, one per row), numbered in order of first
// appearance as the CSV reader numbers them: sets each measurement's index and returns the names.
std::vector<std::string> numberTargets(const std::vector<std::string>& names, std::vector<Measurement>& measurements,
                                       const std::string& subject, bool mixed) {
  if (names.size() != measurements.size()) {
    throw UsageError(subject, "expected " + std::to_string(measurements.size()) + " target names (one per row), got " +
                                  std::to_string(names.size()));
  }
  io::TargetNumbering numbering;
  for (size_t k = 0; k < names.size(); ++k) {
    if (mixed && names[k].empty()) {  // a pose of the tool frame among the target measurements
      measurements[k].target = kPoseMeasurement;
      continue;
    }
    std::string problem;
    measurements[k].target = numbering.number(names[k], problem);
    if (measurements[k].target >= 0) continue;
    if (problem.empty()) throw UsageError(subject, "more than " + std::to_string(io::kMaxTargets) + " distinct targets");
    throw UsageError(subject, "[" + std::to_string(k) + "]: " + io::quotedFileText(names[k]) + " " + problem + " (" +
                                  io::kTargetNameRule + ")");
  }
  return std::move(numbering.names);
}

// The measurement CSV's columns as arrays: q (N, n); positions (N, 3); rotations (N, 4) qw..qz for pose
// measurements; targets (N names) for target measurements (positions are then the targets' points); both for
// mixed data: a row with the target '' is a pose (its rotation given), a target's row has NaN rotations.
io::MeasurementFile measurementArrays(const Robot& r, const InArray& q, const InArray& positions,
                                      const std::optional<InArray>& rotations,
                                      const std::optional<std::vector<std::string>>& targets, const std::string& prefix) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject(), prefix + "q", &r.poe);
  requireAccepted(positions, "", prefix + "positions");
  if (rotations) requireAccepted(*rotations, "", prefix + "rotations");
  const auto N = Q.rows();
  if (N == 0) throw UsageError(prefix + "q", "no measurements");
  if (positions.ndim() != 2 || positions.shape(0) != N || positions.shape(1) != 3) {
    throw UsageError(prefix + "positions", "expected shape (" + std::to_string(N) + ", 3), got shape " +
                                               shapeText(positions));
  }
  if (rotations && (rotations->ndim() != 2 || rotations->shape(0) != N || rotations->shape(1) != 4)) {
    throw UsageError(prefix + "rotations", "expected shape (" + std::to_string(N) +
                                               ", 4) (unit quaternions qw, qx, qy, qz), got shape " +
                                               shapeText(*rotations));
  }
  io::MeasurementFile file;
  file.path = prefix.empty() ? "<arrays>" : "<validation arrays>";
  file.dof = r.dof();
  file.measure = targets ? Measure::Targets : rotations ? Measure::Pose : Measure::Position;
  const bool mixed = rotations && targets;
  file.length_unit = r.file.length_unit;
  file.measurements.resize(static_cast<size_t>(N));
  auto p = positions.unchecked<2>();
  for (Eigen::Index k = 0; k < N; ++k) {
    Measurement& m = file.measurements[static_cast<size_t>(k)];
    m.q = Q.row(k).transpose();
    for (int a = 0; a < 3; ++a) {
      m.T_base_tool.p(a) = p(k, a);
      if (!std::isfinite(p(k, a))) {
        throw UsageError(prefix + "positions", "[" + std::to_string(k) + ", " + std::to_string(a) + "]: '" +
                                                   io::shortest(p(k, a)) + "' is not finite");
      }
    }
    if (rotations) {
      auto w = rotations->unchecked<2>();
      const bool target_row = mixed && k < static_cast<Eigen::Index>(targets->size()) && !(*targets)[static_cast<size_t>(k)].empty();
      if (target_row) {  // a point: its rotation is not measured
        if (!(std::isnan(w(k, 0)) && std::isnan(w(k, 1)) && std::isnan(w(k, 2)) && std::isnan(w(k, 3)))) {
          throw UsageError(prefix + "rotations", "[" + std::to_string(k) + "]: the row of target " +
                                                     io::quotedFileText((*targets)[static_cast<size_t>(k)]) +
                                                     " must be NaN (a point has no rotation; a row with the target '' is a pose)");
        }
      } else {
        m.T_base_tool.R = quaternionRotation(w(k, 0), w(k, 1), w(k, 2), w(k, 3), prefix + "rotations", k);
      }
    }
    file.lines.push_back(static_cast<long long>(k));
  }
  if (targets) file.target_names = numberTargets(*targets, file.measurements, prefix + "targets", mixed);
  return file;
}

// The joint values against the nominal's ranges, as `lowpair calibrate` checks a measurement file's
// (commands::checkJointRanges): one beyond kFarOutsideRange range widths outside is a wrong column or unit,
// never fitted silently; nearer ones are UserWarnings (the first few, then their count).
void checkRanges(const Robot& r, const io::MeasurementFile& m, const std::string& prefix) {
  const std::string subject = prefix + "q";
  const int outside = commands::checkJointRanges(
      r.poe, m.measurements, r.subject(),
      [](const commands::OutsideRange& x) {
        return "[" + std::to_string(x.row) + ", " + std::to_string(x.joint) + "]";
      },
      [&](const std::string& text) { throw UsageError(subject, text); },
      [&](const std::string& text) { warnUser(subject + ": " + text); });
  if (outside > commands::kMaxRangeWarnings) {
    warnUser(subject + ": " + std::to_string(outside) + " joint values outside the ranges in all");
  }
}

Calibration calibrateArrays(const Robot& r, io::MeasurementFile fit, std::optional<io::MeasurementFile> held_out,
                            const commands::CalibrationRequest& request) {
  if (const auto problem = commands::calibrationSizeProblem(fit, r.dof())) {
    throw UsageError("q", *problem);
  }
  checkRanges(r, fit, "");
  if (held_out) {
    checkRanges(r, *held_out, "validation_");
    // targets by name: the validation rows' indices mapped to the fit's
    if (const auto unknown = commands::mapValidationTargets(*held_out, fit.target_names)) {
      throw UsageError("validation_targets", "target " + *unknown + " is not measured in the fit (targets)");
    }
  }
  std::optional<commands::CalibrationReport> report;
  {
    py::gil_scoped_release release;
    report.emplace(commands::runCalibration(r.file, r.poe, std::move(fit), std::move(held_out), request,
                                              pythonSpelling()));
  }
  // the calibrated robot, as `calibrate --out` writes it
  io::RobotFile calibrated;
  calibrated.name = commands::calibratedName(r.file);
  calibrated.length_unit = r.file.length_unit;
  calibrated.angle_unit = r.file.angle_unit;
  calibrated.description = "calibrated by lowpair.calibrate (Python) from arrays";
  // in the nominal's base frame, with the measurement frame recorded (calibrate --out's default)
  calibrated.poe = commands::calibratedModel(*report, false);
  calibrated.measurement_frame = commands::recordedMeasurementFrame(*report, false);
  calibrated.targets = commands::calibratedTargets(*report);
  calibrated.tool_frame = commands::calibratedToolFrame(report->result);
  auto robot = std::make_shared<Robot>(std::move(calibrated), commands::calibrationProvenance(*report));
  json j = commands::calibrationJson(*report);
  return Calibration{std::move(*report), std::move(robot), std::move(j)};
}

Calibration calibrateFromArrays(const Robot& r, const InArray& q, const InArray& positions,
                                const std::optional<InArray>& rotations, std::optional<double> noise_position,
                                std::optional<double> noise_rotation, bool free_pitch, const std::string& loss,
                                double outlier_threshold, const std::optional<std::string>& parameters,
                                const std::optional<InArray>& validation_q,
                                const std::optional<InArray>& validation_positions,
                                const std::optional<InArray>& validation_rotations,
                                const std::optional<std::vector<std::string>>& targets,
                                const std::optional<std::vector<std::string>>& validation_targets,
                                const std::optional<std::string>& select, int folds, int repeats,
                                const std::optional<std::string>& compliance, const std::optional<std::string>& backlash,
                                const std::optional<std::string>& prior) {
  io::MeasurementFile fit = measurementArrays(r, q, positions, rotations, targets, "");
  std::optional<io::MeasurementFile> held_out;
  if (validation_q || validation_positions || validation_rotations || validation_targets) {
    if (!validation_q || !validation_positions) {
      throw UsageError("validation_q", "give validation_q and validation_positions (and validation_rotations or "
                                       "validation_targets as the fit has rotations or targets)");
    }
    if (validation_rotations.has_value() != rotations.has_value()) {
      throw UsageError("validation_rotations", rotations ? "the fit has pose measurements: give validation_rotations too"
                                                         : "the fit has no pose measurements: no validation_rotations");
    }
    if (validation_targets.has_value() != targets.has_value()) {
      throw UsageError("validation_targets", targets ? "the fit has target measurements: give validation_targets too"
                                                     : "the fit has no target measurements: no validation_targets");
    }
    held_out = measurementArrays(r, *validation_q, *validation_positions, validation_rotations, validation_targets,
                                 "validation_");
  }
  const commands::CalibrationRequest request{noise_position, noise_rotation, free_pitch, loss,       outlier_threshold,
                                               parameters,     select,         folds,      repeats,    compliance,
                                               backlash,       prior};
  return calibrateArrays(r, std::move(fit), std::move(held_out), request);
}

// The statistics as to_dict() has them: rotation None where no rotation was measured (position or target data).
py::dict statisticsDict(const ResidualStatistics& s, Measure measure) {
  const bool rotation = measure == Measure::Pose;
  py::dict d;
  d["count"] = s.count;
  d["rms_position"] = s.rms_position;
  d["max_position"] = s.max_position;
  d["rms_rotation"] = rotation ? py::object(py::float_(s.rms_rotation)) : py::object(py::none());
  d["max_rotation"] = rotation ? py::object(py::float_(s.max_rotation)) : py::object(py::none());
  return d;
}

// The class Calibration: the fit's summary (its arrays are exposeCalibrationArrays').
py::class_<Calibration> exposeCalibrationSummary(py::module_& m) {
  return py::class_<Calibration>(m, "Calibration", "lowpair.calibrate(...): the result of `lowpair calibrate`.")
      .def("to_dict", [](const Calibration& c) { return toPython(c.j); },
           "to_dict() -> dict: the content of `lowpair calibrate --json` (measurements.path '<arrays>', validation.path\n"
           "'<validation arrays>'; every `line` is the 0-based row of the arrays).")
      .def_property_readonly("robot", [](const Calibration& c) { return c.robot; },
                             "The calibrated Robot (in the nominal's base frame, its measurement_frame the base in the measurement frame); save() writes what `calibrate --out` "
                             "writes. Present even when not accepted: check `accepted`.")
      .def_property_readonly("measure", [](const Calibration& c) { return measureName(c.report.result.measure); },
                             "'pose', 'position' or 'targets': what the arrays held.")
      .def_property_readonly("rank", [](const Calibration& c) { return c.report.result.rank.rank; },
                             "Rank of the weighted identification Jacobian at the nominal (int).")
      .def_property_readonly("expected", [](const Calibration& c) { return c.report.result.expected.total(); },
                             "The count 5h + 4r + 2t + n + 6 (+ 3 for positions, + 3k for k targets).")
      .def_property_readonly("iterations", [](const Calibration& c) { return c.report.result.iterations; },
                             "Levenberg-Marquardt iterations (int).")
      .def_property_readonly("converged", [](const Calibration& c) { return c.report.result.converged; },
                             "Whether the iteration converged (bool).")
      .def_property_readonly("accepted", [](const Calibration& c) { return c.report.result.accepted; },
                             "The verdict (docs/calibration.md): converged and the residuals consistent with the "
                             "stated noise (or below 1 % of L and 0.01 rad without it). `lowpair calibrate` exits 1 "
                             "and writes nothing when False.")
      .def_property_readonly("reason", [](const Calibration& c) { return c.report.result.reason; },
                             "Why not accepted ('' when accepted).")
      .def_property_readonly("variance_factor", [](const Calibration& c) { return c.report.result.variance_factor; },
                             "cost / (rows - rank): 1 expected when the stated noise is right (inf or NaN without "
                             "redundancy; to_dict() has null).")
      .def_property_readonly("before", [](const Calibration& c) { return statisticsDict(c.report.result.before, c.report.fit.measure); },
                             "dict count, rms_position, max_position (length_unit), rms_rotation, max_rotation (rad; "
                             "None when no rotation was measured: position or target data, as in to_dict()): "
                             "the nominal (registered) against the measurements.")
      .def_property_readonly("after", [](const Calibration& c) { return statisticsDict(c.report.result.after, c.report.fit.measure); },
                             "dict as `before`, for the calibrated model.")
      .def_property_readonly("validation",
                             [](const Calibration& c) -> py::object {
                               if (!c.report.validation_residuals) return py::none();
                               py::dict d;
                               const Measure measure = c.report.validation->measure;
                               d["before"] = statisticsDict(c.report.validation_residuals->before, measure);
                               d["after"] = statisticsDict(c.report.validation_residuals->after, measure);
                               return std::move(d);
                             },
                             "dict before/after on the validation arrays, or None.");
}

// The class Calibration: residuals, targets, parameters and their covariance.
void exposeCalibrationArrays(py::class_<Calibration>& calibration) {
  calibration
      .def_property_readonly(
          "residuals",
          [](const Calibration& c) {
            const auto& rows = c.report.result.residuals;
            const auto N = static_cast<py::ssize_t>(rows.size());
            py::array_t<double> position(N), rotation(N), normalized(N), weight(N);
            py::array_t<bool> outlier(N);
            for (py::ssize_t k = 0; k < N; ++k) {
              const MeasurementResidual& x = rows[static_cast<size_t>(k)];
              position.mutable_at(k) = x.position, rotation.mutable_at(k) = x.rotation;
              normalized.mutable_at(k) = x.normalized, weight.mutable_at(k) = x.weight, outlier.mutable_at(k) = x.outlier;
            }
            py::dict d;
            d["position"] = position, d["rotation"] = rotation, d["normalized"] = normalized, d["weight"] = weight;
            d["outlier"] = outlier;
            return d;
          },
          "dict of (N,) arrays, one entry per measurement row (after the fit): position (length_unit), rotation (rad; "
          "NaN for points), normalized (over the noise unit), weight (the robust loss' weight, 1 for squared), "
          "outlier (bool: normalized > outlier_threshold).")
      .def_property_readonly("outliers", [](const Calibration& c) { return c.report.result.outliers; },
                             "Measurements flagged as outliers (int).")
      .def_property_readonly("loss", [](const Calibration& c) { return toPython(c.j["loss"]); },
                             "'squared', 'huber' or 'cauchy'.")
      .def_property_readonly("targets",
                             [](const Calibration& c) {
                               py::dict out;
                               for (size_t t = 0; t < c.report.target_names.size(); ++t) {
                                 out[py::str(c.report.target_names[t])] = vectorArray(c.report.result.target_points[t]);
                               }
                               return out;
                             },
                             "dict name -> (3,) calibrated point in the tool frame (length_unit), for target "
                             "measurements; empty otherwise.")
      .def_property_readonly("cross_validation",
                             [](const Calibration& c) -> py::object {
                               if (!c.j.contains("cross_validation")) return py::none();
                               return toPython(c.j["cross_validation"]);
                             },
                             "dict folds, repeats, candidates (parameters, count, rms_position, rms_rotation, score, failed), "
                             "chosen (select='cv'), or None.")
      .def_property_readonly("dh", [](const Calibration& c) { return toPython(c.j["dh"]); },
                             "dict: the calibrated D-H table with standard deviations (to_dict()['dh']).")
      .def_property_readonly(
          "parameter_names",
          [](const Calibration& c) {
            std::vector<std::string> names;
            for (const Parameter& p : c.report.result.error_model.parameters()) names.push_back(p.name);
            return names;
          },
          "list[str]: the identified parameters ('j2.tilt1', 'j3.scale', 'tool.z', 'smr_a.x', ...), the order of "
          "estimate, standard_deviation and covariance (docs/calibration.md lists their meaning and units).")
      .def_property_readonly("estimate", [](const Calibration& c) { return vectorArray(c.report.result.estimate); },
                             "(p,): every parameter's estimate from the registered nominal, in parameter_names "
                             "order and units (to_dict()['parameters'][k]['value']).")
      .def_property_readonly("standard_deviation",
                             [](const Calibration& c) { return vectorArray(c.report.result.standard_deviation); },
                             "(p,) per parameter, in its unit (inf when undetermined).")
      .def_property_readonly("covariance", [](const Calibration& c) { return matrixArray(c.report.result.covariance); },
                             "(p, p) covariance of the parameters (local coordinates at the calibrated model, "
                             "parameter_names order, their units squared); pseudo-inverse on the determined subspace.")
      .def_property_readonly("measurement_frame",
                             [](const Calibration& c) { return poseArray(c.report.result.registration.T_meas_base); },
                             "(4, 4): the nominal's base in the measurement frame (the registration).")
      .def_property_readonly("warnings", [](const Calibration& c) { return c.report.warnings; },
                             "list[str]: the report's warnings in sentences (rank below the count, no convergence, "
                             "residuals inconsistent with the noise, the D-H conversion's conditioning).")
      .def("__repr__", [](const Calibration& c) {
        // the CLI's words ("rank 33 of 33 (the complete set would be 39)" for a level)
        return "<lowpair.Calibration " + commands::parameterRankText(c.report.result) + ", " +
               (c.report.result.accepted ? "accepted" : "rejected") + ">";
      });
}

}  // namespace

void exposeCalibration(py::module_& m) {
  py::class_<Calibration> calibration = exposeCalibrationSummary(m);
  exposeCalibrationArrays(calibration);
  m.def("calibrate", &calibrateFromArrays, py::arg("robot"), py::arg("q"), py::arg("positions"),
        py::arg("rotations") = py::none(), py::arg("noise_position") = py::none(),
        py::arg("noise_rotation") = py::none(), py::arg("free_pitch") = false, py::arg("loss") = "squared",
        py::arg("outlier_threshold") = 5.0, py::arg("parameters") = py::none(), py::arg("validation_q") = py::none(),
        py::arg("validation_positions") = py::none(), py::arg("validation_rotations") = py::none(),
        py::arg("targets") = py::none(), py::arg("validation_targets") = py::none(), py::arg("select") = py::none(),
        py::arg("folds") = 5, py::arg("repeats") = kCrossValidationRepeats, py::arg("compliance") = py::none(),
        py::arg("backlash") = py::none(), py::arg("prior") = py::none(),
        "calibrate(robot, q, positions, rotations=None, noise_position=None, noise_rotation=None, free_pitch=False,\n"
        "          loss='squared', outlier_threshold=5.0, parameters=None, validation_q=None,\n"
        "          validation_positions=None, validation_rotations=None, targets=None, validation_targets=None,\n"
        "          select=None, folds=5, repeats=10, compliance=None, backlash=None,\n"
        "          prior=None) -> Calibration\n\n"
        "`lowpair calibrate` from arrays (the measurement CSV's columns): q (N, n) joint values (rad / length_unit);\n"
        "positions (N, 3) measured tool positions (length_unit, the robot's; any measurement frame: it is\n"
        "registered); rotations (N, 4) unit quaternions qw, qx, qy, qz (scalar first; norm within 1e-6 of 1) for\n"
        "pose measurements; or targets, N names (the CSV's target column) for laser-tracker target (SMR)\n"
        "measurements, positions then being the targets' points (a point the robot file's `targets:` gives is the\n"
        "start, the others are estimated); neither: position measurements of the tool origin.\n"
        "noise_position (length_unit) and noise_rotation (rad): the measurement noise, standard deviation per\n"
        "coordinate. loss: 'squared', 'huber' or 'cauchy' (robust: blunders weighed down); outlier_threshold:\n"
        "the normalized residual above which a row is flagged. parameters: None (all), 'full', 'lines',\n"
        "'offsets' or names 'j2.offset,base.rz'; select='cv' chooses among full/lines/offsets by `folds`-fold\n"
        "cross-validation over `repeats` partitions of the poses (the first in order, the others shuffled).\n"
        "validation_*: held-out measurements of the same kind (residuals before and after).\n"
        "compliance: 'all' or joints '2,3,5' (1-based indices or names) whose compliance under gravity is fitted\n"
        "(the robot file's masses give the loads); backlash: joints whose backlash is fitted, the approach signs\n"
        "from the order of the rows (`lowpair calibrate --compliance/--backlash`, docs/calibration.md).\n"
        "prior: 'WIDTH' or 'tilt=..,shift=..,scale=..,offset=..': Gaussian priors on the deviations from the\n"
        "nominal (`lowpair calibrate --prior`; to_dict() then has prior and effective_parameters).\n"
        "The GIL is released during the fit. A rejected fit is data (accepted, reason), not an exception.");
}

}  // namespace lowpair::python
