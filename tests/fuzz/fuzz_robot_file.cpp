// Fuzz target: the robot-file reader (harness/robot_file.hpp). The input is a robot file (YAML). Allowed:
// RobotFileError, std::invalid_argument. An accepted file must evaluate finitely: its POE model (converted
// from D-H when the file holds D-H) and its D-H model at fixed joint vectors within the ranges, and poeToDh
// with checkDhConversion.
#include <stdexcept>

#include "fuzz_common.hpp"
#include "lowpair/kinematics.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const lowpair_fuzz::TempFile file(".yaml");
  try {
    const lowpair::io::RobotFile robot = lowpair::io::readRobotFile(file.write(data, size));
    FUZZ_CHECK(robot.poe.has_value() != robot.dh.has_value());
    FUZZ_CHECK(std::isfinite(robot.angleFactor()));
    if (robot.dh) {
      for (const lowpair::VecX& q : lowpair_fuzz::fixedConfigurations(lowpair_fuzz::rangesOf(robot.dh->joints())))
        FUZZ_CHECK(lowpair_fuzz::finite(lowpair::dhForwardKinematics(*robot.dh, q)));
    }
    const lowpair::PoeModel model = robot.poeModel();
    lowpair_fuzz::checkPoeModel(model);
    lowpair_fuzz::checkConversion(model);
  } catch (const lowpair::io::RobotFileError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
