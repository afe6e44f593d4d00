// What identifiability, calibrate and the D-H table with standard deviations share in their wording
// (calibration_output_parts.hpp).
#include "commands/calibration_output_parts.hpp"

#include <algorithm>
#include <limits>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace lowpair::commands::detail {

using io::RobotFile;
using nlohmann::json;

std::string lengthUnit(const RobotFile& file) { return file.length_unit.empty() ? "length" : file.length_unit; }

std::string pitchUnit(const RobotFile& file) { return lengthUnit(file) + "/" + file.angle_unit; }

namespace {
// x to `digits` significant digits, printf's %g ("0.00802", "1.2e-15")
std::string significant(double x, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}
}  // namespace

// "1.2e-05", or "undetermined" for +inf
std::string deviation(double sd) { return std::isfinite(sd) ? significant(sd, 2) : std::string("undetermined"); }

// A residual statistic to 3 significant digits ("0.00802", "1.2e-15" -> "1.2e-15"): comparable at a glance.
std::string residual(double x) { return significant(x, 3); }

std::vector<std::string> parameterNames(const std::vector<Parameter>& parameters) {
  std::vector<std::string> names;
  for (const Parameter& p : parameters) names.push_back(p.name);
  return names;
}

json undeterminedJson(const RankAnalysis& a, const std::vector<std::string>& names) {
  json out = json::array();
  for (const auto& direction : a.undetermined) {
    json terms = json::array();
    for (const auto& [column, coefficient] : direction) {
      terms.push_back({{"parameter", names[static_cast<size_t>(column)]}, {"coefficient", coefficient}});
    }
    out.push_back(terms);
  }
  return out;
}

json countJson(const ParameterCount& c) {
  return {{"revolute", c.revolute}, {"prismatic", c.prismatic}, {"helical", c.helical}, {"scales", c.scales},
          {"tool", c.tool}};
}

std::string countFormula(const ParameterCount& c) {
  std::ostringstream s;
  s << "5h + 4r + 2t + n + " << c.tool << (c.deflections ? " + d" : "") << " = 5x" << c.helical << " + 4x" << c.revolute
    << " + 2x" << c.prismatic << " + " << c.scales << " + " << c.tool;
  if (c.deflections) s << " + " << c.deflections;
  s << " = " << c.total();
  return s.str();
}

bool knownTarget(const CalibrationResult& c, size_t t) { return c.error_model.spec().knownTarget(t); }

std::string toolFrameText(const CalibrationResult& c) {
  if (c.tool_rank >= 6) {
    return c.measure == Measure::Targets ? "tool frame: determined by the known targets' points"
                                         : "tool frame: determined by the pose measurements";
  }
  if (c.measure == Measure::Position) {
    return "tool frame: its origin calibrated; its orientation is the nominal's (position measurements)";
  }
  return "tool frame: not determined (" +
         std::string(c.tool_rank == 0 ? "the targets' points are unknown and carry it"
                                      : std::to_string(c.tool_rank) + " of its 6 directions fixed by the known points") +
         "): the calibrated file keeps the nominal's, and compensate answers for the flange with it; give three "
         "non-collinear targets as known (targets: known: true, docs/calibration.md) to pin it";
}

// The residual degrees of freedom behind a variance factor: rows (of the measurements not flagged, for a
// robust loss) minus the determined parameters.
double redundancy(const CalibrationResult& c) {
  double rows = 0.0;
  for (const MeasurementResidual& m : c.residuals) {
    if (c.loss == Loss::Squared || !m.outlier) rows += m.rows;
  }
  return rows - c.effective_parameters;  // the rank without a prior
}

std::string priorText(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  if (c.prior.none()) return "";
  auto width = [](double w, double factor, const std::string& unit) {
    return std::isinf(w) ? std::string("free") : significant(w * factor, 6) + " " + unit;
  };
  return "prior (MAP, zero-mean Gaussian on the deviations from the nominal): tilt " + width(c.prior.tilt, 1e3, "mrad") +
         ", shift " + width(c.prior.shift, 1.0, lengthUnit(r.nominal)) +
         (r.prior_unit_assumed ? " (the robot's length unit unknown: 1 mm taken as 1 unit)" : "") + ", scale " +
         width(c.prior.scale, 1e2, "%") + ", offset " + width(c.prior.offset, 1e3, "mrad") +
         "; the measurement frame, targets and deflections free; effective parameters " +
         significant(c.effective_parameters, 6) + " of " + std::to_string(c.error_model.size()) + " parameters";
}

std::string heldByPriorText(const CalibrationResult& c) {
  std::string names;
  for (const int j : c.held_by_prior) {
    names += (names.empty() ? "" : " ") + c.error_model.parameters()[static_cast<size_t>(j)].name;
  }
  return names;
}

// Why a fit has no variance factor (CalibrationResult::variance_factor NaN: residual rows <= rank), in a few
// words: a robust loss that flagged every measurement (or all but a few), else no redundancy in the data.
std::string noVarianceFactorCause(const CalibrationResult& c) {
  if (c.loss != Loss::Squared && c.outliers > 0) {
    const size_t n = c.residuals.size();
    if (static_cast<size_t>(c.outliers) == n) {
      return "all " + std::to_string(n) + " measurements were flagged as outliers, and it is estimated from the others";
    }
    double rows = 0.0, all = 0.0;
    for (const MeasurementResidual& m : c.residuals) {
      all += m.rows;
      if (!m.outlier) rows += m.rows;
    }
    if (all - c.rank.rank > 0) {  // the flags took the redundancy away
      return std::to_string(c.outliers) + " of the " + std::to_string(n) + " measurements were flagged as outliers, " +
             "and the " + std::to_string(static_cast<long long>(rows)) + " residuals of the others do not exceed the " + std::to_string(c.rank.rank) +
             " determined parameters";
    }
  }
  return "";
}

// A measurement's file line; "measurement K" (1-based) for measurements that came from no file (a scenario's).
std::string measurementLabel(const CalibrationReport& r, size_t k) {
  return k < r.fit.lines.size() ? std::to_string(r.fit.lines[k]) : "measurement " + std::to_string(k + 1);
}

std::vector<DeflectionRow> deflectionRows(const CalibrationReport& r) {
  const CalibrationResult& c = r.result;
  std::vector<DeflectionRow> rows;
  const auto& parameters = c.error_model.parameters();
  const std::string u = lengthUnit(r.nominal);
  size_t backlash = 0;
  for (size_t k = 0; k < parameters.size(); ++k) {
    const Parameter& p = parameters[k];
    if (p.kind != ParameterKind::Compliance && p.kind != ParameterKind::Backlash) continue;
    DeflectionRow row;
    row.joint = p.joint;
    row.compliance = p.kind == ParameterKind::Compliance;
    const VecX& values = row.compliance ? c.deflection.compliance : c.deflection.backlash;
    row.value = values[p.joint];
    row.sd = c.standard_deviation[static_cast<Eigen::Index>(k)];
    row.unit = p.unit == "length/N" ? u + "/N" : p.unit == "length" ? u : p.unit;
    row.input_min = std::numeric_limits<double>::infinity();
    row.input_max = -row.input_min;
    for (const PoseLoad& load : c.loads) {
      const double x = (row.compliance ? load.torque : load.sign)[p.joint];
      row.input_min = std::min(row.input_min, x);
      row.input_max = std::max(row.input_max, x);
    }
    if (!row.compliance) {
      const std::vector<bool>& from = r.deflections.sign_from_column;
      const bool column = backlash < from.size() && from[backlash];
      row.sign_source = column ? "its sign column in " + r.fit.path : "the measurements' order";
      ++backlash;
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace lowpair::commands::detail
