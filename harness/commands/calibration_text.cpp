// `lowpair calibrate`'s text (printCalibration, calibration_output.hpp): the set-up, the residual table, the change
// per joint, the D-H table with standard deviations and the warnings.
#include "commands/calibration_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "lowpair/se3.hpp"
#include "commands/calibration_output_parts.hpp"
#include "io/output.hpp"

namespace lowpair::commands {

using namespace lowpair::io;  // the rooms below
using namespace detail;

using nlohmann::json;

namespace {

// The fit's inputs and how it went: measurements, noise, parameters, the cross-validated choice, the measurement
// frame, targets, loss and outliers, convergence.
void printCalibrationSetup(std::ostream& out, const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  const std::string u = lengthUnit(r.nominal);
  out << "calibration of " << robotLabel(r.nominal) << " (" << r.nominal.path << ") from " << r.fit.measurements.size()
      << " " << measurementsText(r.fit.measure) << " ("
      << r.fit.path << ")\n";
  const std::string no_vf_cause = noVarianceFactorCause(c);
  const std::string vf = std::isfinite(c.variance_factor) ? fixed(c.variance_factor, 3)
                         : no_vf_cause.empty()            ? std::string("none (no redundancy)")
                                                          : "none (" + no_vf_cause + ")";
  if (c.noise_stated) {
    out << "noise (stated): position " << deviation(c.sigma_position) << " " << u;
    if (!c.sigma_position_stated) out << " (derived: sigma_rotation L)";
    if (r.fit.measure == Measure::Pose) {
      out << ", rotation " << deviation(c.sigma_rotation) << " rad";
      if (!c.sigma_rotation_stated) out << " (derived: sigma_position / L)";
    }
    out << "; variance factor " << vf << "\n";
  } else {
    out << "noise: not stated (position weighted 1/L, rotation 1/rad; standard deviations from the residuals, "
           "variance factor "
        << vf << ")\n";
  }
  if (c.parameter_set == ParameterSet::Full) {
    out << "parameters: " << parameterRankText(c) << " (" << countFormula(c.expected)
        << (c.error_model.freePitch() ? ", free pitch" : "") << ")\n";
  } else {
    out << "parameters: " << parameterRankText(c) << "\n";
  }
  if (!c.prior.none()) {
    out << priorText(r) << "\n";
    const std::string held = heldByPriorText(c);
    if (!held.empty()) out << "held by the prior (the measurements alone do not determine them): " << held << "\n";
  }
  if (r.cross_validation) {
    const CrossValidation& cv = *r.cross_validation;
    out << "parameter choice (" << cv.folds << "-fold cross-validation, " << cv.repeats
        << (cv.repeats == 1 ? " partition" : " partitions") << "; held-out score"
        << (c.noise_stated ? " in noise units" : " in weighted units, 1/L and 1/rad") << ", RMS position):";
    for (const auto& cand : cv.candidates) {
      out << " " << parameterSetName(cand.set) << " (" << cand.parameters << ") "
          << (cand.failed ? std::string("failed") : residual(cand.score) + ", " + residual(cand.rms_position) + " " + u)
          << ";";
    }
    out << " chosen: " << parameterSetName(r.cross_validation->chosen) << "\n";
  }
  {
    const Pose& F = c.registration.T_meas_base;
    const double angle = rotationAngle(F.R);
    const Vec3 axis = angle > 0.0 ? Vec3(logSO3(F.R) / angle) : Vec3::UnitZ();
    out << "measurement frame: the nominal's base at (" << fixed(F.p.x(), 3) << ", " << fixed(F.p.y(), 3) << ", "
        << fixed(F.p.z(), 3) << ") " << u << ", turned " << fixed(angle * kDeg, 4) << " deg about (" << fixed(axis.x(), 4)
        << ", " << fixed(axis.y(), 4) << ", " << fixed(axis.z(), 4) << ") (closed-form registration"
        << (c.registration.determined ? "" : ": not determined, the predicted points are collinear; identity kept")
        << ")\n";
  }
  if (r.base_frame) {
    const Pose& F = r.base_frame->gauge.T_measurement_base;
    const MeasurementFrameUncertainty& sd = r.base_frame->sd;
    const double angle = rotationAngle(F.R);
    const Vec3 axis = angle > 0.0 ? Vec3(logSO3(F.R) / angle) : Vec3::UnitZ();
    const BaseFrameRule& rule = r.base_frame->gauge.rule;
    out << "base frame: the nominal's (joint 1's line and zero, the foot of the common normal to "
        << (rule.foot_joint >= 0 ? "joint " + std::to_string(rule.foot_joint + 1) : std::string("the tool point"))
        << "); the calibrated base at (" << fixed(F.p.x(), 3) << ", " << fixed(F.p.y(), 3) << ", " << fixed(F.p.z(), 3)
        << ") +- (" << deviation(sd.position.x()) << ", " << deviation(sd.position.y()) << ", " << deviation(sd.position.z())
        << ") " << u << ", turned " << fixed(angle * kDeg, 4) << " deg about (" << fixed(axis.x(), 4) << ", "
        << fixed(axis.y(), 4) << ", " << fixed(axis.z(), 4) << ") +- (" << deviation(sd.rotation.x() * kDeg) << ", "
        << deviation(sd.rotation.y() * kDeg) << ", " << deviation(sd.rotation.z() * kDeg) << ") deg\n";
  }
  if (!c.target_points.empty()) {
    out << "targets:";
    for (size_t t = 0; t < c.target_points.size(); ++t) {
      out << " " << r.target_names[t] << (knownTarget(c, t) ? " (known)" : r.target_from_file[t] ? " (start: nominal file)" : " (start: estimated)");
    }
    out << "\n" << toolFrameText(c) << "\n";
  }
  out << "loss: " << lossName(c.loss);
  if (c.loss != Loss::Squared) {
    out << " (" << (c.loss == Loss::Huber ? "threshold " + shortest(kHuberThreshold) : "scale " + shortest(kCauchyScale))
        << " noise units; noise unit: " << (c.noise_stated ? "the stated noise" : "the median residual, " + residual(c.robust_scale) + " weighted units")
        << "; " << c.reweightings << " reweightings)";
  }
  out << "; outliers (normalized residual > " << shortest(c.outlier_threshold) << "): " << c.outliers << " of "
      << c.residuals.size() << "\n";
  for (const std::string& note : r.notes) out << "note: " << note << "\n";
  out << (c.converged ? "converged" : "NOT converged") << " after " << c.iterations << " iterations ("
      << fixed(r.seconds, 3) << " s)\n\n";
}

// The residual table (measurements and validation, before and after) and the worst measurements.
void printResidualTable(std::ostream& out, const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  const std::string u = lengthUnit(r.nominal);
  char line[256];
  std::snprintf(line, sizeof line, "%-22s %16s %16s %16s %16s\n", "residuals", ("rms pos (" + u + ")").c_str(),
                ("max pos (" + u + ")").c_str(), "rms rot (rad)", "max rot (rad)");
  out << line;
  auto stats = [&](const std::string& label, const ResidualStatistics& s, bool rotation) {
    std::snprintf(line, sizeof line, "%-22s %16s %16s %16s %16s\n", label.c_str(), residual(s.rms_position).c_str(),
                  residual(s.max_position).c_str(), rotation ? residual(s.rms_rotation).c_str() : "-",
                  rotation ? residual(s.max_rotation).c_str() : "-");
    out << line;
  };
  const bool fit_rot = r.fit.measure == Measure::Pose;
  stats("measurements, before", c.before, fit_rot);
  stats("measurements, after", c.after, fit_rot);
  if (r.validation) {
    const ValidationResiduals& v = *r.validation_residuals;
    const bool val_rot = r.validation->measure == Measure::Pose;
    stats("validation, before", v.before, val_rot);
    stats("validation, after", v.after, val_rot);
    if (v.outside_count > 0) {
      stats("  within fitted ranges", v.inside_after, val_rot);
      stats("  outside (" + std::to_string(v.outside_count) + ")", v.outside_after, val_rot);
    }
  }
  out << "(before: the nominal in the measurement frame";
  if (r.validation && r.validation_residuals->outside_count > 0) {
    out << "; outside: validation measurements with a joint value beyond the range the fitting ones cover";
  }
  out << ")\n";

  out << "\nworst measurements (normalized residual: over the "
      << (c.noise_stated ? "stated noise" : "median-based noise scale") << "):\n";
  for (const size_t k : worstMeasurements(c, kWorstMeasurementsShown)) {
    const MeasurementResidual& m = c.residuals[k];
    out << "  " << r.fit.path << ":" << measurementLabel(r, k);
    const int t = r.fit.measurements[k].target;
    if (r.fit.measure == Measure::Targets) out << (t >= 0 ? " target " + r.target_names[static_cast<size_t>(t)] : std::string(" pose"));
    out << ": position " << residual(m.position) << " " << u;
    if (m.rows == 6) out << ", rotation " << residual(m.rotation) << " rad";
    out << ", normalized " << residual(m.normalized) << ", weight " << residual(m.weight) << (m.outlier ? "  OUTLIER" : "")
        << "\n";
  }
}

// The change per joint against the nominal in the measurement frame, and the tool's or the targets'.
void printJointChanges(std::ostream& out, const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  const std::string u = lengthUnit(r.nominal);
  // in the base frame: the nominal itself against the calibrated moved there; else both in the measurement frame
  const PoeModel nominal_base = r.nominal.poeModel();
  const PoeModel& nominal = r.base_frame ? nominal_base : *r.registered_nominal;
  const PoeModel& calibrated = calibratedModel(r, false);
  const Vec3 origin = r.base_frame ? Vec3(Vec3::Zero()) : c.registration.T_meas_base.p;
  char line[256];
  out << "\nchange per joint (calibrated vs the nominal in the " << (r.base_frame ? "base" : "measurement")
      << " frame):\n";
  std::snprintf(line, sizeof line, "%-8s %-10s %14s %16s %18s %14s\n", "joint", "type", "tilt (rad)",
                ("shift (" + u + ")").c_str(), ("pitch (" + pitchUnit(r.nominal) + ")").c_str(), "scale");
  out << line;
  for (int i = 0; i < nominal.dof(); ++i) {
    const Joint& a = nominal.joint(i);
    const Joint& b = calibrated.joint(i);
    const bool prismatic = a.type == JointType::Prismatic;
    const Vec3 da = prismatic ? a.moment() : a.axis(), db = prismatic ? b.moment() : b.axis();
    const double tilt = std::atan2(da.cross(db).norm(), da.dot(db));
    std::string shift = "-";
    if (!prismatic) {  // distance from the nominal line's point nearest the robot's base origin to the calibrated line
      const Vec3& o = origin;
      const Vec3 pa = a.axis().cross(a.moment()), pb = b.axis().cross(b.moment());
      const Vec3 ca = pa + a.axis() * a.axis().dot(o - pa);
      shift = fixed((ca - pb).cross(b.axis()).norm(), 6);
    }
    const double k = r.nominal.angleFactor();
    const std::string pitch = prismatic ? "-" : fixed((b.pitch - a.pitch) * k, 8);
    std::snprintf(line, sizeof line, "%-8s %-10s %14s %16s %18s %14s\n", (b.name.empty() ? std::to_string(i + 1) : b.name).c_str(),
                  jointTypeName(b.type), fixed(tilt, 8).c_str(), shift.c_str(), pitch.c_str(),
                  fixed(b.scale - a.scale, 8).c_str());
    out << line;
  }
  if (c.target_points.empty() || c.error_model.spec().toolParameters()) {
    const Pose& Ta = nominal.toolPose();
    const Pose& Tb = calibrated.toolPose();
    out << "tool: turned " << fixed(rotationAngle(Ta.R.transpose() * Tb.R), 8) << " rad, moved "
        << fixed((Tb.p - Ta.p).norm(), 6) << " " << u << "\n";
  }
  if (!c.target_points.empty()) {
    out << "targets (tool frame, " << u << "):\n";
    for (size_t t = 0; t < c.target_points.size(); ++t) {
      const Vec3& p = c.target_points[t];
      out << "  " << r.target_names[t] << ": " << fixed(p.x(), 6) << " " << fixed(p.y(), 6) << " " << fixed(p.z(), 6)
          << (knownTarget(c, t) ? std::string(" (known)") : " (moved " + fixed((p - c.registration.target_points[t]).norm(), 6) + " from its start)")
          << "\n";
    }
  }
}

// The fitted compliance and backlash, with their inputs (docs/calibration.md "Beyond geometry").
void printDeflections(std::ostream& out, const CalibrationReport& r) {
  auto six = [](double x) {  // 6 significant digits: the JSON has all 17
    std::ostringstream s;
    s.precision(6);
    s << x;
    return s.str();
  };
  const std::vector<DeflectionRow> rows = deflectionRows(r);
  if (rows.empty() && r.deflections.rigid.empty()) return;
  out << "\njoint deflections (the joint stands at q + c tau(q) + b s; tau: the gravity load at the commanded q):\n";
  for (const DeflectionRow& d : rows) {
    const std::string tag = "j" + std::to_string(d.joint + 1);
    if (d.compliance) {
      const std::string load = r.result.model.joint(d.joint).type == JointType::Prismatic ? " N" : " N m";
      out << "  " << tag << ".compliance " << six(d.value) << " +- " << deviation(d.sd) << " " << d.unit << " (load "
          << residual(d.input_min) << " to " << residual(d.input_max) << load << ")\n";
    } else {
      out << "  " << tag << ".backlash " << six(d.value) << " +- " << deviation(d.sd) << " " << d.unit
          << " (s, the sign of the joint's last move, from " << d.sign_source << ")\n";
    }
  }
  for (const int j : r.deflections.rigid) {
    out << "  j" << j + 1 << ": no compliance fitted (--compliance all: its gravity load does not vary over the measurements)\n";
  }
}

}  // namespace

void printCalibration(std::ostream& out, const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  printCalibrationSetup(out, r);
  printResidualTable(out, r);
  printJointChanges(out, r);
  printDeflections(out, r);
  out << "\ncalibrated D-H table (standard D-H, Wu et al. eq. 10; as poe2dh prints it):\n";
  printDhWithDeviations(out, r.nominal, r.dh, "standard deviations of the calibrated D-H table");
  out << "(standard deviations: the parameter covariance "
      << (c.noise_stated ? "from the stated noise" : "scaled by the residuals") << ", propagated through the conversion;\n"
      << " they grow without bound as consecutive axes become parallel, docs/calibration.md)\n";
  if (!r.warnings.empty()) {
    out << "\nwarnings:\n";
    for (const auto& w : r.warnings) out << "  - " << w << "\n";
  }
  out << "\nverdict: " << (c.accepted ? "accepted" : "REJECTED: " + c.reason) << "\n";
}

}  // namespace lowpair::commands
