#pragma once
/// @file calibration_output_parts.hpp
/// Wording the text and JSON of identifiability, calibrate and the D-H table with standard deviations share
/// (calibration_output.cpp, identifiability_output.cpp, dh_output.cpp); internal to the commands room.

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "io/robot_file.hpp"
#include "commands/calibration_output.hpp"

namespace lowpair::commands::detail {

constexpr double kDeg = 180.0 / M_PI;

/// The robot file's length unit, or "length" when it states none.
std::string lengthUnit(const io::RobotFile& file);
/// "mm/deg": the unit of a pitch in the robot file.
std::string pitchUnit(const io::RobotFile& file);
/// "1.2e-05", or "undetermined" for +inf
std::string deviation(double sd);
/// A residual statistic to 3 significant digits ("0.00802", "1.2e-15"): comparable at a glance.
std::string residual(double x);
std::vector<std::string> parameterNames(const std::vector<Parameter>& parameters);
/// The undetermined directions, each a list of {parameter, coefficient}.
nlohmann::json undeterminedJson(const RankAnalysis& a, const std::vector<std::string>& names);
nlohmann::json countJson(const ParameterCount& c);
/// "5h + 4r + 2t + n + 6 = 5x0 + 4x6 + 2x0 + 6 + 6 = 36"
std::string countFormula(const ParameterCount& c);
/// Target t of the fit is known (its point fixed).
bool knownTarget(const CalibrationResult& c, size_t t);
/// "tool frame: determined by ..." / "tool frame: not determined (...)": CalibrationResult::tool_rank in words.
std::string toolFrameText(const CalibrationResult& c);
/// The residual degrees of freedom behind a variance factor (rows of the measurements not flagged, for a robust
/// loss, minus the determined parameters).
double redundancy(const CalibrationResult& c);

/// With a prior (CalibrationResult::prior): the line saying its widths (6 significant digits, the shift in the robot's
/// unit) and the effective number of parameters; the parameters it holds (names), empty when none. Without: both empty.
std::string priorText(const CalibrationReport& r);
std::string heldByPriorText(const CalibrationResult& c);
/// Why a calibration has no variance factor, in words.
std::string noVarianceFactorCause(const CalibrationResult& c);
/// One fitted joint deflection of a calibration, as the text and JSON give it.
struct DeflectionRow {
  int joint = 0;             ///< 0-based
  bool compliance = true;    ///< else backlash
  double value = 0.0, sd = 0.0;  ///< the calibrated total (rad or length units) and the parameter's sd
  std::string unit;          ///< "rad/(N m)", "mm/N", "rad", "mm"
  double input_min = 0.0, input_max = 0.0;  ///< the load (N m or N) or sign range over the measurements
  std::string sign_source;   ///< backlash: "column s3" / "the measurements' order"; "" for a compliance
};
/// The fitted deflections of `r`, in parameter order.
std::vector<DeflectionRow> deflectionRows(const CalibrationReport& r);

/// A measurement's file line; "measurement K" (1-based) for measurements that came from no file.
std::string measurementLabel(const CalibrationReport& r, size_t k);

}  // namespace lowpair::commands::detail
