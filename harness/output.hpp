#pragma once
/// @file output.hpp
/// JSON and human-readable renderings of models, conversions and poses (the CLI's contract, README).

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "lowpair/convert.hpp"
#include "robot_file.hpp"

namespace lowpair {

nlohmann::json poseJson(const Pose& T);
nlohmann::json dhJson(const RobotFile& file, const DhConversion& conversion);
nlohmann::json modifiedDhJson(const RobotFile& file, const DhConversion& conversion);
nlohmann::json poeJson(const RobotFile& file, const PoeModel& model);

void printDh(std::ostream& out, const RobotFile& file, const DhConversion& conversion);
void printModifiedDh(std::ostream& out, const RobotFile& file, const DhConversion& conversion);
void printPoe(std::ostream& out, const RobotFile& file, const PoeModel& model);
void printPose(std::ostream& out, const Pose& T, const std::string& length_unit);

/// The robot's name, or its file when it has none.
std::string robotLabel(const RobotFile& file);
/// A vector as a JSON-ready std::vector.
std::vector<double> toVector(const Eigen::Ref<const VecX>& x);

/// "12.3456" for moderate magnitudes, "1.2346e+07" beyond; never "-0.0000".
std::string fixed(double x, int decimals = 4);

}  // namespace lowpair
