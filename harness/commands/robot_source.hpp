#pragma once
/// @file robot_source.hpp
/// Where a command's robot comes from, read the one way the CLI (ROBOT [--tip --base]) and the Python module
/// (lowpair.load(path, tip, base)) read it.

#include <string>

#include "commands/arguments.hpp"
#include "io/robot_file.hpp"

namespace lowpair::commands {

/// A robot file (.yaml), or an MJCF (.xml) / URDF (.urdf) model whose chain from `base` (default: the world)
/// to `tip` (a site or body) is extracted through MuJoCo.
struct RobotSource {
  std::string path, tip, base;
};

/// Reads the robot: a robot file, or the POE model extracted from a model file (scale 1, no unit).
/// `spelling` names tip and base in the messages as the caller's front end spells them.
/// @throws io::RobotFileError, UsageError (subject: the path; tip/base with a robot file, a model file
/// without tip)
io::RobotFile loadRobot(const RobotSource& source, const ArgumentSpelling& spelling);

}  // namespace lowpair::commands
