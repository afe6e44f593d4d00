// The checks and derivations of calibrate's inputs for the CLI and the Python module (calibration_inputs.hpp).
#include "validation/calibration_inputs.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "io/output.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::validation {

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
    if (b == std::string::npos) throw UsageError(spelling.name("parameters"), "an empty name in '" + text + "'");
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

}  // namespace lowpair::validation
