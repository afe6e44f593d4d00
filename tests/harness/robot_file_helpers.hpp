#pragma once
// Helpers of the robot-file tests (robot_file_targets_test.cpp, robot_file_loads_test.cpp): bit equality of numbers
// read back, and the message of a file the reader refuses.
#include <cstring>
#include <string>

#include "io/robot_file.hpp"

namespace robot_file_helpers {

inline bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The RobotFileError message reading `path`, or "" when it reads.
inline std::string robotFileError(const std::string& path) {
  try {
    lowpair::io::readRobotFile(path);
  } catch (const lowpair::io::RobotFileError& e) {
    return e.what();
  }
  return "";
}

}  // namespace robot_file_helpers
