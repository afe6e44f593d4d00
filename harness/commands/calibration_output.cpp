// `lowpair calibrate`: the report computed once (makeCalibrationReport), its text, JSON, provenance lines and
// rejection line (calibration_output.hpp).
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

// A variance factor below this draws a warning (the noise overstated 2x or more).
constexpr double kVarianceFactorLow = 0.25;
// Above the chi-square bound: the 99.9 % quantile of chi^2_f / f for f residual degrees of freedom, by the
// normal approximation 1 + 3.09 sqrt(2 / f) (a correct noise model exceeds it once in a thousand fits).
double chiSquareBound(double f) { return 1.0 + 3.09 * std::sqrt(2.0 / std::max(f, 1.0)); }




json matrixJson(const Pose& T) {
  json rows = json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({T.R(i, 0), T.R(i, 1), T.R(i, 2), T.p[i]});
  rows.push_back({0.0, 0.0, 0.0, 1.0});
  return rows;
}

// Residual statistics; the rotation ones are null for position measurements (there is no rotation).
json statisticsJson(const ResidualStatistics& s, Measure measure) {
  const bool rotation = measure == Measure::Pose;
  return {{"count", s.count},
          {"rms_position", s.rms_position},
          {"max_position", s.max_position},
          {"rms_rotation", rotation ? json(s.rms_rotation) : json(nullptr)},
          {"max_rotation", rotation ? json(s.max_rotation) : json(nullptr)}};
}

std::vector<std::string> calibrationWarnings(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  std::vector<std::string> w;
  const std::vector<std::string> names = parameterNames(c.error_model.parameters());
  if (c.parameter_set == ParameterSet::Full && c.rank.rank < c.expected.total()) {
    std::ostringstream s;
    // the tool rotation is a column of the error model but not of the count for position measurements
    const int tool_rotation = r.fit.measure == Measure::Position && c.parameter_set == ParameterSet::Full ? 3 : 0;
    s << "rank " << c.rank.rank << " < " << c.expected.total() << ": these measurements do not determine "
      << c.rank.undetermined.size() - static_cast<size_t>(tool_rotation) << " parameter direction(s) of the count"
      << (tool_rotation ? " (and the tool rotation, which position measurements never determine)" : "")
      << (c.prior.none() ? ", left at the nominal:" : ", left at the nominal or held by the prior (listed above):");
    for (const auto& d : c.rank.undetermined) s << " [" << directionText(d, names) << "]";
    s << ". The fit is confined to the directions the nominal determines: an error of the robot along the others "
         "stays in the residuals (after: "
      << fixed(c.after.rms_position, 4) << " " << lengthUnit(r.nominal)
      << " RMS); more varied poses, "
      << (r.fit.measure == Measure::Position ? "pose measurements or a tool point off the wrist axes"
                                             : "or a nominal without the degenerate geometry")
      << " determine them";
    w.push_back(s.str());
  }
  if (!c.converged) w.push_back("did not converge in " + std::to_string(c.iterations) + " iterations");
  if (!std::isfinite(c.variance_factor)) {
    const std::string cause = noVarianceFactorCause(c);
    w.push_back((cause.empty() ? "no redundancy: " + std::to_string(c.rank.rank) +
                                     " determined parameters from as many residuals or fewer, so the fit passes through "
                                     "the noise"
                               : "no variance factor: " + cause + " (look at the worst measurements, the units and "
                                 "the stated noise)") +
                (c.noise_stated ? std::string("; the standard deviations come from the stated noise alone")
                                : std::string("; without stated noise there are no standard deviations")));
  } else if (c.noise_stated && (c.variance_factor > chiSquareBound(redundancy(c)) || c.variance_factor < kVarianceFactorLow)) {
    std::ostringstream s;
    s << "the weighted residuals are " << fixed(std::sqrt(c.variance_factor), 2)
      << " times the stated noise (variance factor " << fixed(c.variance_factor, 3) << "): "
      << (c.variance_factor > 1.0 ? "the noise is understated or the robot has an error the model cannot represent; "
                                    "the standard deviations are too small"
                                  : "the noise is overstated; the standard deviations are too large");
    w.push_back(s.str());
  }
  if (c.outliers > 0) {
    w.push_back(std::to_string(c.outliers) + " measurement(s) flagged as outliers (normalized residual above the "
                "threshold; listed with their lines under \"worst measurements\", JSON \"residuals\"): " +
                (c.loss == Loss::Squared ? std::string("least squares gave them full weight; try --loss huber")
                                         : std::string("the robust loss weighed them down; they are not dropped")));
  }
  if (c.parameter_set != ParameterSet::Full && !c.rank.undetermined.empty()) {
    w.push_back(std::to_string(c.rank.undetermined.size()) + " direction(s) of the " + parameterSetName(c.parameter_set) +
                " parameters are not determined (left where the registration put them): " +
                [&] {
                  std::string t;
                  for (const auto& d : c.rank.undetermined) t += " [" + directionText(d, names) + "]";
                  return t;
                }());
  }
  for (const auto& s : conversionWarnings(r.dh.conversion, checkDhConversion(calibratedModel(r, false), r.dh.conversion.model))) {
    w.push_back("D-H: " + s);
  }
  return w;
}

}  // namespace


CalibratedBaseFrame calibratedBaseFrame(const CalibrationResult& result, const PoeModel& nominal) {
  return {toNominalBase(result.model, nominal), measurementFrameUncertainty(result, nominal)};
}

const PoeModel& calibratedModel(const CalibrationReport& r, bool measurement_frame) {
  return r.base_frame && !measurement_frame ? r.base_frame->gauge.model : r.result.model;
}

std::optional<MassModel> calibratedMasses(const CalibrationReport& r, bool measurement_frame) {
  if (!r.nominal.masses) return std::nullopt;
  MassModel m = *r.nominal.masses;
  if (!measurement_frame && r.base_frame) return m;
  const Pose& T = r.result.registration.T_meas_base;  // the written model's base frame is the measurement frame
  for (PointMass& link : m.links) link.com = T * link.com;
  m.gravity = T.R * m.gravity;
  return m;
}

std::optional<Pose> recordedMeasurementFrame(const CalibrationReport& r, bool measurement_frame) {
  if (!r.base_frame || measurement_frame) return std::nullopt;
  return r.base_frame->gauge.T_measurement_base;
}

CalibrationReport makeCalibrationReport(RobotFile nominal, MeasurementFile fit, std::optional<MeasurementFile> validation,
                                        CalibrationResult result, DhUncertainty dh, double seconds,
                                        std::optional<CalibratedBaseFrame> base_frame,
                                        const std::vector<PoseLoad>& validation_loads) {
  CalibrationReport r{std::move(nominal), std::move(fit), std::move(validation), std::move(result), std::move(dh),
                      seconds, std::nullopt, false, std::nullopt, {}, {}, std::nullopt, {}, {}, std::move(base_frame)};
  const CalibrationResult& c = r.result;
  r.registered_nominal = movedModel(r.nominal.poeModel(), c.registration.T_meas_base);
  r.target_names = r.fit.target_names;
  for (size_t t = 0; t < c.registration.estimated.size(); ++t) r.target_from_file.push_back(!c.registration.estimated[t]);
  if (r.validation) {
    // at the joints as they stand: deflected by the nominal's deflections (before) and the fit's (after)
    const std::vector<Measurement> ms = deflectedMeasurements(r.validation->measurements, c.deflection, validation_loads);
    const Measure measure = r.validation->measure;
    ValidationResiduals v;
    v.before = residualStatistics(*r.registered_nominal,
                                  deflectedMeasurements(r.validation->measurements, r.nominal.deflection, validation_loads),
                                  measure, c.registration.target_points);
    v.after = residualStatistics(c.model, ms, measure, c.target_points);
    // extrapolation: a joint value outside what the fitting measurements cover
    const int n = c.model.dof();
    VecX lo = VecX::Constant(n, std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Measurement& m : r.fit.measurements) {
      lo = lo.cwiseMin(m.q);
      hi = hi.cwiseMax(m.q);
    }
    std::vector<Measurement> inside, outside;
    for (const Measurement& m : ms) {
      const bool out = (m.q.array() < lo.array()).any() || (m.q.array() > hi.array()).any();
      (out ? outside : inside).push_back(m);
    }
    v.outside_count = static_cast<int>(outside.size());
    v.inside_after = residualStatistics(c.model, inside, measure, c.target_points);
    v.outside_after = residualStatistics(c.model, outside, measure, c.target_points);
    r.validation_residuals = v;
    // a validation set that contradicts the fit by orders of magnitude (kMaxValidationRatio): not accepted
    const double fit_rms = c.after.rms_position, val_rms = v.after.rms_position;
    const double L = c.model.lengthScale();
    if (c.accepted && val_rms > kMaxValidationRatio * fit_rms && val_rms > kMaxValidationRelativeRms * L) {
      const std::string u = lengthUnit(r.nominal);
      std::ostringstream why;
      why << "the validation set contradicts the calibrated model: its RMS position error after is " << residual(val_rms) << " "
          << u << ", ";
      if (fit_rms > 0) why << residual(val_rms / fit_rms) << " times the fit's own (" << residual(fit_rms) << " " << u << ")";
      else why << "the fit's own is 0";
      why << " and " << residual(100.0 * val_rms / L) << " % of the robot's size L = " << residual(L) << " " << u << " (at most "
          << shortest(kMaxValidationRatio) << " times the fit's or " << shortest(100.0 * kMaxValidationRelativeRms) << " % of L)";
      r.result.accepted = false;
      r.result.reason = why.str();
      r.validation_contradicts = true;
    }
  }
  r.warnings = calibrationWarnings(r);
  return r;
}

std::string parameterRankText(const CalibrationResult& c) {
  if (c.parameter_set == ParameterSet::Full) {
    return "rank " + std::to_string(c.rank.rank) + " of " + std::to_string(c.expected.total());
  }
  return std::string(parameterSetName(c.parameter_set)) + ", rank " + std::to_string(c.rank.rank) + " of " +
         std::to_string(c.error_model.size()) + " (the complete set would be " + std::to_string(c.expected.total()) + ")";
}

std::vector<std::string> calibrationProvenance(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  const std::string u = lengthUnit(r.nominal);
  std::vector<std::string> lines;
  lines.push_back("calibrated by lowpair calibrate from " + r.nominal.path + " and " + r.fit.path + " (" +
                  std::to_string(r.fit.measurements.size()) + " " + measurementsText(r.fit.measure) + ")");
  lines.push_back("rank " + std::to_string(c.rank.rank) + " of " + std::to_string(c.expected.total()) +
                  (r.result.error_model.freePitch() ? ", free pitch" : "") + ", " + std::to_string(c.iterations) +
                  " iterations" + (c.converged ? "" : " (not converged)"));
  lines.push_back("RMS position error on the measurements: before " + fixed(c.before.rms_position, 6) + " " + u +
                  ", after " + fixed(c.after.rms_position, 6) + " " + u);
  if (r.base_frame) {
    lines.push_back("in the nominal's base frame (joint 1's line, its zero and the foot of the common normal: "
                    "docs/calibration.md); measurement_frame: the base in the frame of " + r.fit.path + ", " +
                    fixed(r.base_frame->gauge.T_measurement_base.p.norm(), 3) + " " + u + " from its origin; loss " +
                    lossName(c.loss) + ", parameters " + parameterSetName(c.parameter_set));
  } else {
    lines.push_back("in the measurement frame of " + r.fit.path + " (the nominal's base registered at " +
                    fixed(c.registration.T_meas_base.p.norm(), 3) + " " + u + " from its origin); loss " + lossName(c.loss) +
                    ", parameters " + parameterSetName(c.parameter_set));
  }
  return lines;
}

std::vector<Target> calibratedTargets(const CalibrationReport& r) {
  std::vector<Target> out;
  for (size_t t = 0; t < r.result.target_points.size() && t < r.target_names.size(); ++t) {
    out.push_back(Target{r.target_names[t], r.result.target_points[t], r.result.error_model.spec().knownTarget(t)});
  }
  return out;
}

ToolFrame calibratedToolFrame(const CalibrationResult& c) {
  if (c.tool_rank >= 6) return ToolFrame::Defined;
  return c.measure == Measure::Position ? ToolFrame::Origin : ToolFrame::Nominal;
}

std::vector<size_t> worstMeasurements(const CalibrationResult& c, size_t count) {
  std::vector<size_t> order(c.residuals.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  count = std::min(count, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count), order.end(), [&](size_t a, size_t b) {
    return c.residuals[a].normalized > c.residuals[b].normalized;
  });
  order.resize(count);
  return order;
}

namespace {

// What a file's lengths were read in: "its length_unit comment says m (converted x 1000 to mm)", "its
// length_unit comment says mm", "no length_unit comment (taken as mm)".
std::string statedUnitText(const MeasurementFile& m, const std::string& robot_unit) {
  if (!m.converted_from.empty()) {
    const std::optional<double> from = metresPerUnit(m.converted_from), to = metresPerUnit(m.length_unit);
    return "its length_unit comment says " + m.converted_from + " (converted" +
           (from && to ? " x " + shortest(*from / *to) : std::string()) + " to " + m.length_unit + ")";
  }
  if (!m.length_unit.empty()) return "its length_unit comment says " + m.length_unit;
  return "no length_unit comment (taken as " + robot_unit + ")";
}

}  // namespace

std::string rejectionText(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  std::ostringstream s;
  if (r.validation_contradicts && r.validation) {
    const std::string u = lengthUnit(r.nominal);
    s << r.validation->path << ": calibration rejected, nothing written: " << c.reason << "; look at, in order: units ("
      << r.validation->path << ": " << statedUnitText(*r.validation, u) << "; " << r.fit.path << ": "
      << statedUnitText(r.fit, u) << "), whether it measures this robot in the same measurement frame and tool as "
      << r.fit.path << ", its joint columns (order, q in rad)";
    if (r.validation_residuals && r.validation_residuals->outside_count > 0) {
      s << ", extrapolation (" << r.validation_residuals->outside_count
        << " of its measurements have a joint value beyond the fit's range)";
    }
    return s.str();
  }
  s << r.fit.path << ": calibration rejected, nothing written: " << c.reason << "; worst lines";
  const std::vector<size_t> worst = worstMeasurements(c, kWorstMeasurementsShown);
  for (size_t k = 0; k < worst.size(); ++k) {
    s << (k ? ", " : " ") << measurementLabel(r, worst[k]) << " (" << residual(c.residuals[worst[k]].normalized) << ")";
  }
  s << " (normalized residual: over the " << (c.noise_stated ? "stated noise" : "median-based noise scale")
    << "); look at, in order: units (the CSV's length_unit, q in rad), blunders ("
    << (c.loss == Loss::Squared ? "--loss huber, " : "") << "the worst lines), the measurement frame, a wrong nominal "
    << "(another robot, joint order or type), the stated noise";
  return s.str();
}

namespace {

// calibrationJson's "parameters" (value and standard deviation of each) and "correlation" (of the determined ones)
void parameterJson(const CalibrationResult& c, json& o) {
  json params = json::array();
  const auto& ps = c.error_model.parameters();
  for (size_t k = 0; k < ps.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    params.push_back({{"name", ps[k].name}, {"unit", ps[k].unit}, {"value", c.estimate[i]},
                      {"standard_deviation", finiteOrNull(c.standard_deviation[i])}});
  }
  o["parameters"] = params;
  // correlations of the determined parameters (finite, nonzero standard deviation), by index into
  // "parameters": what a near-singular fit trades against what
  std::vector<Eigen::Index> determined;
  for (Eigen::Index k = 0; k < c.standard_deviation.size(); ++k) {
    if (std::isfinite(c.standard_deviation[k]) && c.standard_deviation[k] > 0 && k < c.covariance.rows()) {
      determined.push_back(k);
    }
  }
  json correlation = json::array();
  for (const Eigen::Index a : determined) {
    json row = json::array();
    for (const Eigen::Index b : determined) {
      row.push_back(finiteOrNull(c.covariance(a, b) / (c.standard_deviation[a] * c.standard_deviation[b])));
    }
    correlation.push_back(row);
  }
  o["correlation"] = {{"parameters", determined}, {"matrix", correlation}};
}

// calibrationJson's "residuals": one per measurement, with its file line (and target)
json residualsJson(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  json residuals = json::array();
  for (size_t k = 0; k < c.residuals.size(); ++k) {
    const MeasurementResidual& m = c.residuals[k];
    json e = {{"line", k < r.fit.lines.size() ? json(r.fit.lines[k]) : json(nullptr)},
              {"position", m.position},
              {"rotation", finiteOrNull(m.rotation)},
              {"normalized", m.normalized},
              {"weight", m.weight},
              {"outlier", m.outlier}};
    if (r.fit.measure == Measure::Targets) {
      const int t = r.fit.measurements[k].target;  // a pose among target measurements: null
      e["target"] = t >= 0 ? json(r.target_names[static_cast<size_t>(t)]) : json(nullptr);
    }
    residuals.push_back(e);
  }
  return residuals;
}

}  // namespace

json calibrationJson(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  json o;
  o["name"] = robotLabel(r.nominal);
  o["nominal"] = r.nominal.path;
  o["length_unit"] = r.nominal.length_unit.empty() ? json(nullptr) : json(r.nominal.length_unit);
  o["measurements"] = {{"path", r.fit.path}, {"count", r.fit.measurements.size()}, {"measure", measureName(r.fit.measure)}};
  o["free_pitch"] = c.error_model.freePitch();
  // the weights are noise only when stated; otherwise they are relative weights (1/L, 1/rad)
  o["noise"] = {{"position", c.noise_stated ? json(c.sigma_position) : json(nullptr)},
                {"rotation", c.noise_stated ? json(c.sigma_rotation) : json(nullptr)},
                {"stated", c.noise_stated},
                // the weight of a stated pair that was not given itself: sigma_position / L or sigma_rotation L
                {"derived", !c.noise_stated                                      ? json(nullptr)
                            : !c.sigma_rotation_stated && r.fit.measure == Measure::Pose ? json("rotation")
                            : !c.sigma_position_stated                            ? json("position")
                                                                                  : json(nullptr)}};
  o["variance_factor"] = finiteOrNull(c.variance_factor);  // null: no redundancy (rows <= rank)
  if (!c.prior.none()) {  // (only with --prior: other outputs unchanged)
    auto width = [](double w) { return std::isinf(w) ? json(nullptr) : json(w); };
    json held = json::array();
    for (const int j : c.held_by_prior) held.push_back(c.error_model.parameters()[static_cast<size_t>(j)].name);
    o["prior"] = {{"tilt", width(c.prior.tilt)},   {"shift", width(c.prior.shift)},
                  {"scale", width(c.prior.scale)}, {"offset", width(c.prior.offset)},
                  {"length_unit_assumed", r.prior_unit_assumed}, {"held", held}};
    o["effective_parameters"] = c.effective_parameters;
  }
  o["before"] = statisticsJson(c.before, r.fit.measure);
  o["after"] = statisticsJson(c.after, r.fit.measure);
  if (r.validation) {
    const ValidationResiduals& v = *r.validation_residuals;
    o["validation"] = {{"path", r.validation->path}, {"measure", measureName(r.validation->measure)},
                       {"before", statisticsJson(v.before, r.validation->measure)},
                       {"after", statisticsJson(v.after, r.validation->measure)}};
  }
  if (r.validation) {
    const ValidationResiduals& v = *r.validation_residuals;
    o["validation"]["extrapolation"] = {{"outside", v.outside_count},
                                        {"inside_after", statisticsJson(v.inside_after, r.validation->measure)},
                                        {"outside_after", statisticsJson(v.outside_after, r.validation->measure)}};
  }
  o["accepted"] = c.accepted;
  o["verdict"] = c.accepted ? json("accepted") : json(c.reason);
  o["measurement_frame"] = matrixJson(c.registration.T_meas_base);
  o["registration"] = {{"iterations", c.registration.iterations}, {"determined", c.registration.determined}};
  if (r.base_frame) {
    // the gauge: the calibrated robot in the nominal's base frame; T_measurement_base its pose in the
    // measurement frame, standard deviations: rotation about the measurement frame's axes (rad), position
    const CalibratedBaseFrame& b = *r.base_frame;
    const BaseFrameRule& rule = b.gauge.rule;
    auto v3 = [](const Vec3& x) { return json{finiteOrNull(x.x()), finiteOrNull(x.y()), finiteOrNull(x.z())}; };
    o["base_frame"] = {{"T_measurement_base", matrixJson(b.gauge.T_measurement_base)},
                       {"sd", {{"rotation", v3(b.sd.rotation)}, {"position", v3(b.sd.position)}}},
                       {"rule", {{"foot_joint", rule.foot_joint >= 0 ? json(rule.foot_joint + 1) : json(nullptr)},
                                 {"direction_joint", rule.direction_joint >= 0 ? json(rule.direction_joint + 1) : json(nullptr)}}}};
  }
  o["loss"] = lossName(c.loss);
  o["robust_scale"] = {{"value", c.robust_scale}, {"source", c.noise_stated ? "stated noise" : "median residual"}};
  o["outlier_threshold"] = c.outlier_threshold;
  o["outliers"] = c.outliers;
  o["reweightings"] = c.reweightings;
  o["parameter_set"] = parameterSetName(c.parameter_set);
  o["residuals"] = residualsJson(r);
  json targets = json::array();
  for (size_t t = 0; t < c.target_points.size(); ++t) {
    targets.push_back({{"name", r.target_names[t]},
                       {"point", {c.target_points[t].x(), c.target_points[t].y(), c.target_points[t].z()}},
                       {"start", r.target_from_file[t] ? "nominal file" : "estimated"},
                       {"known", knownTarget(c, t)}});
  }
  o["targets"] = targets;
  o["tool_frame"] = {{"determined", c.tool_rank >= 6}, {"rank", c.tool_rank}, {"text", toolFrameText(c)}};
  if (r.cross_validation) {
    json candidates = json::array();
    for (const auto& cand : r.cross_validation->candidates) {
      candidates.push_back({{"parameters", parameterSetName(cand.set)},
                            {"count", cand.parameters},
                            {"rms_position", cand.failed ? json(nullptr) : json(cand.rms_position)},
                            {"rms_rotation", cand.failed || r.fit.measure != Measure::Pose ? json(nullptr) : json(cand.rms_rotation)},
                            {"score", cand.failed ? json(nullptr) : json(cand.score)},
                            {"failed", cand.failed}});
    }
    o["cross_validation"] = {{"folds", r.cross_validation->folds},
                             {"repeats", r.cross_validation->repeats},
                             {"candidates", candidates},
                             {"chosen", parameterSetName(r.cross_validation->chosen)}};
  }
  json deflections = json::array();
  for (const DeflectionRow& d : deflectionRows(r)) {
    json row = {{"joint", d.joint + 1}, {"kind", d.compliance ? "compliance" : "backlash"}, {"value", d.value},
                {"sd", finiteOrNull(d.sd)}, {"unit", d.unit}};
    if (d.compliance) {
      row["load"] = {{"min", d.input_min}, {"max", d.input_max}};
    } else {
      row["signs"] = d.sign_source;
    }
    deflections.push_back(row);
  }
  if (!deflections.empty() || !r.deflections.rigid.empty()) {  // (only with deflections: other outputs unchanged)
    o["deflections"] = deflections;
    o["rigid"] = json::array();
    for (const int j : r.deflections.rigid) o["rigid"].push_back(j + 1);
  }
  o["notes"] = r.notes;
  o["iterations"] = c.iterations;
  o["converged"] = c.converged;
  o["rank"] = c.rank.rank;
  o["expected"] = c.expected.total();
  o["joints"] = countJson(c.expected);
  parameterJson(c, o);
  o["undetermined"] = undeterminedJson(c.rank, parameterNames(c.error_model.parameters()));
  // the calibrated D-H table with standard deviations (angles rad, pitch length/rad; null = undetermined)
  o["dh"] = dhUncertaintyJson(r.dh);
  o["warnings"] = r.warnings;
  o["seconds"] = r.seconds;
  return o;
}

}  // namespace lowpair::commands
