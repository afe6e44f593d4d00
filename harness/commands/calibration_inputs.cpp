// The checks and derivations of calibrate's inputs for the CLI and the Python module (calibration_inputs.hpp).
#include "commands/calibration_inputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <tuple>

#include "io/csv_columns.hpp"
#include "io/joint_table.hpp"
#include "io/output.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::commands {

std::vector<OutsideRange> jointValuesOutsideRanges(const PoeModel& nominal, const std::vector<Measurement>& measurements) {
  std::vector<OutsideRange> out;
  for (size_t k = 0; k < measurements.size(); ++k) {
    for (int i = 0; i < nominal.dof(); ++i) {
      const auto& range = nominal.joint(i).range;
      const double q = measurements[k].q[i];
      if (!range || (q >= (*range)[0] && q <= (*range)[1])) continue;
      const double width = (*range)[1] - (*range)[0];
      const double beyond = q < (*range)[0] ? (*range)[0] - q : q - (*range)[1];
      out.push_back({k, i, q, *range, beyond > kFarOutsideRange * width});
    }
  }
  return out;
}

int checkJointRanges(const PoeModel& nominal, const std::vector<Measurement>& measurements, const std::string& robot_name,
                     const std::function<std::string(const OutsideRange&)>& where,
                     const std::function<void(const std::string&)>& refuse,
                     const std::function<void(const std::string&)>& warn) {
  int outside = 0;
  for (const OutsideRange& x : jointValuesOutsideRanges(nominal, measurements)) {
    const std::string text = where(x) + " = " + io::shortest(x.q) + " is outside joint " + std::to_string(x.joint + 1) +
                             "'s range [" + io::shortest(x.range[0]) + ", " + io::shortest(x.range[1]) + "] of " +
                             robot_name;
    if (x.far) {
      refuse(text + " by more than " + io::shortest(kFarOutsideRange) + " times its width: a wrong column or unit?");
    }
    if (outside++ < kMaxRangeWarnings) warn(text);
  }
  return outside;
}

CalibrationMeasurements readCalibrationMeasurements(const std::string& path, const io::RobotFile& robot,
                                                    const std::string& robot_name, const PoeModel& nominal,
                                                    const std::function<void(const std::string&)>& warn) {
  // the measurements must be of this robot: its joint count, and its length unit when both state one
  // (checked at the header line, before the rest of a large file is read)
  auto check_matches = [&](const io::MeasurementFile& m) {
    if (m.dof != nominal.dof()) {
      throw io::RobotFileError(m.path + ": has " + std::to_string(m.dof) + " joint columns but " + robot_name +
                               " has " + std::to_string(nominal.dof()) + " joints");
    }
    if (!m.length_unit.empty() && !robot.length_unit.empty() && m.length_unit != robot.length_unit &&
        !(io::metresPerUnit(m.length_unit) && io::metresPerUnit(robot.length_unit))) {
      throw io::RobotFileError(m.path + ": lengths in " + m.length_unit + " (its length_unit comment) but " +
                               robot_name + " is in " + robot.length_unit +
                               ", and lowpair converts only m, mm, cm, dm, um, km, in, ft");
    }
  };
  CalibrationMeasurements out;
  out.file = io::readMeasurements(path, check_matches, io::csvJointNames(robot));
  io::MeasurementFile& m = out.file;
  out.notes = m.notes;  // the columns ignored
  check_matches(m);  // a length_unit comment may also follow the header
  // a CSV in another unit lowpair knows: its lengths (positions, and the prismatic joints' values, as a
  // joint-value CSV's: io::convertTableUnit) converted to the nominal's, one note saying so; before the range
  // check, which compares the joint values with the nominal's ranges in its unit
  if (!m.length_unit.empty() && !robot.length_unit.empty() && m.length_unit != robot.length_unit) {
    const double factor = *io::metresPerUnit(m.length_unit) / *io::metresPerUnit(robot.length_unit);
    const std::vector<bool> prismatic = io::prismaticJoints(nominal);
    for (size_t k = 0; k < m.measurements.size(); ++k) {
      Measurement& x = m.measurements[k];
      x.T_base_tool.p *= factor;
      for (Eigen::Index i = 0; i < x.q.size(); ++i) {
        if (!prismatic[static_cast<size_t>(i)]) continue;
        x.q[i] *= factor;
        if (!(std::abs(x.q[i]) <= kMaxMagnitude)) {
          throw io::RobotFileError(m.path + ":" + std::to_string(m.lines[k]) + ": q" + std::to_string(i + 1) +
                                   " is above 1e100 in " + robot.length_unit + " after the unit conversion from " +
                                   m.length_unit);
        }
      }
      if (!(x.T_base_tool.p.cwiseAbs().maxCoeff() <= kMaxMagnitude)) {
        throw io::RobotFileError(m.path + ":" + std::to_string(m.lines[k]) + ": a position is above 1e100 in " +
                                 robot.length_unit + " after the unit conversion from " + m.length_unit);
      }
    }
    out.notes.push_back(m.path + ": lengths converted from " + m.length_unit + " (its length_unit comment) to " +
                        robot.length_unit + " (the nominal's), x " + io::shortest(factor));
    m.converted_from = m.length_unit;
    m.length_unit = robot.length_unit;
  }
  // joint values outside the nominal's ranges: a warning each (the first few), an error beyond
  // kFarOutsideRange range widths (a wrong column or unit, never fitted silently)
  const int outside = checkJointRanges(
      nominal, m.measurements, robot_name,
      [&](const OutsideRange& x) {
        return m.path + ":" + std::to_string(m.lines[x.row]) + ": q" + std::to_string(x.joint + 1);
      },
      [](const std::string& text) { throw io::RobotFileError(text); }, warn);
  if (outside > kMaxRangeWarnings) warn(m.path + ": " + std::to_string(outside) + " joint values outside the ranges in all");
  return out;
}

void checkStatedNoise(const std::optional<double>& noise_position, const std::optional<double>& noise_rotation,
                      const ArgumentSpelling& spelling) {
  for (const auto& [value, name, limit] : {std::tuple{noise_position, "noise_position", kMaxMagnitude},
                                           std::tuple{noise_rotation, "noise_rotation", M_PI}}) {
    if (value && !(*value > 0.0 && *value <= limit)) {
      throw UsageError(spelling.name(name),
                       "must be a positive number up to " + io::shortest(limit) + ", got " + io::shortest(*value));
    }
  }
}

void parseParameters(const std::string& text, CalibrationOptions& options, const ArgumentSpelling& spelling) {
  if (text == "full" || text == "lines" || text == "offsets") {
    options.parameters = text == "full" ? ParameterSet::Full : text == "lines" ? ParameterSet::Lines : ParameterSet::Offsets;
    return;
  }
  options.parameters = ParameterSet::Named;
  std::stringstream in(text);
  for (std::string name; std::getline(in, name, ',');) {
    const auto b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t");
    if (b == std::string::npos) throw UsageError(spelling.name("parameters"), "an empty name in " + io::quotedFileText(text));
    options.parameter_names.push_back(name.substr(b, e - b + 1));
  }
  if (options.parameter_names.empty()) {
    throw UsageError(spelling.name("parameters"), "expected full, lines, offsets or names");
  }
}

std::optional<std::string> mapValidationTargets(io::MeasurementFile& validation, const std::vector<std::string>& fit_names) {
  for (Measurement& m : validation.measurements) {
    if (m.target < 0) continue;
    const std::string& name = validation.target_names[static_cast<size_t>(m.target)];
    const auto it = std::find(fit_names.begin(), fit_names.end(), name);
    if (it == fit_names.end()) return name;
    m.target = static_cast<int>(it - fit_names.begin());
  }
  validation.target_names = fit_names;
  return std::nullopt;
}

std::vector<Target> nominalTargets(const io::RobotFile& nominal, const std::vector<std::string>& names) {
  std::vector<Target> targets;
  for (const std::string& name : names) {
    const auto it = std::find_if(nominal.targets.begin(), nominal.targets.end(), [&](const Target& t) { return t.name == name; });
    targets.push_back(it != nominal.targets.end() ? *it : Target{name, std::nullopt});
  }
  return targets;
}

namespace {

// A positive width (inf allowed) in the whole of `text`, else nothing.
std::optional<double> positiveNumber(const std::string& text) {
  if (text.empty() || text.find_first_of(" \t") != std::string::npos) return std::nullopt;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !(x > 0.0)) return std::nullopt;
  return x;
}

}  // namespace

ParameterPrior priorOfWidth(double width, std::optional<double> metres_per_unit) {
  const double mm = 1e-3 / metres_per_unit.value_or(1e-3);  // one millimetre in the robot's unit
  ParameterPrior prior;
  prior.tilt = 1e-3 * width;
  prior.shift = mm * width;
  prior.scale = 1e-3 * width;
  prior.offset = 1e-2 * width;
  return prior;
}

std::vector<double> parsePriorGrid(const std::string& text, const ArgumentSpelling& spelling) {
  if (text == "default") return std::vector<double>(kDefaultPriorGrid.begin(), kDefaultPriorGrid.end());
  auto refuse = [&](const std::string& why) -> UsageError {
    return UsageError(spelling.name("prior_grid"), why + " in " + io::quotedFileText(text) +
                                                        " (expected 'default' or a comma list of prior widths, positive "
                                                        "finite numbers, each once, at most " +
                                                        std::to_string(kMaxPriorGrid) + ")");
  };
  std::vector<double> widths;
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    const std::optional<double> width = positiveNumber(item);
    if (!width || std::isinf(*width)) throw refuse("'" + item + "' is not a positive finite width");
    if (std::find(widths.begin(), widths.end(), *width) != widths.end()) throw refuse("'" + item + "' given twice");
    widths.push_back(*width);
  }
  if (widths.empty() || text.back() == ',') throw refuse("no width");
  if (widths.size() > static_cast<size_t>(kMaxPriorGrid)) throw refuse(std::to_string(widths.size()) + " widths");
  return widths;
}

ParameterPrior parsePrior(const std::string& text, std::optional<double> metres_per_unit, const ArgumentSpelling& spelling) {
  const double mm = 1e-3 / metres_per_unit.value_or(1e-3);  // one millimetre in the robot's unit
  auto refuse = [&](const std::string& why) -> UsageError {
    return UsageError(spelling.name("prior"), why + " in " + io::quotedFileText(text) +
                                                   " (expected WIDTH or tilt=..,shift=..,scale=..,offset=.., positive numbers)");
  };
  ParameterPrior prior;
  if (text.find('=') == std::string::npos) {
    const std::optional<double> width = positiveNumber(text);
    if (!width || std::isinf(*width)) throw refuse("not a positive finite width");
    return priorOfWidth(*width, metres_per_unit);
  }
  std::vector<std::string> seen;
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    if (eq == std::string::npos) throw refuse("no '=' in '" + item + "'");
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) throw refuse("'" + key + "' given twice");
    seen.push_back(key);
    const std::optional<double> value = positiveNumber(item.substr(eq + 1));
    if (!value) throw refuse("'" + key + "' is not a positive width");
    if (key == "tilt") prior.tilt = 1e-3 * *value;
    else if (key == "shift") prior.shift = mm * *value;
    else if (key == "scale") prior.scale = 1e-2 * *value;
    else if (key == "offset") prior.offset = 1e-3 * *value;
    else throw refuse("unknown kind '" + key + "' (tilt, shift, scale or offset)");
  }
  if (prior.none()) throw refuse("every width is inf (no prior: leave --prior out)");
  return prior;
}

}  // namespace lowpair::commands
