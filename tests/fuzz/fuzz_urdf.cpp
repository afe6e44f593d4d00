// Fuzz target: the URDF reader (harness/urdf_reader.hpp) through urdfdom. Input: an optional first line
// `TIP [BASE]` (header_line.hpp), then the URDF. Allowed: RobotFileError. An accepted chain's POE model
// evaluates finitely (FK at fixed joint vectors within the ranges, poeToDh + checkDhConversion).
#include <stdexcept>

#include "fuzz_common.hpp"
#include "header_line.hpp"
#include "io/urdf_reader.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const lowpair_fuzz::TempFile file(".urdf");
  const lowpair_fuzz::HeaderLine in = lowpair_fuzz::splitHeaderLine(data, size);
  try {
    const lowpair::io::RobotFile robot = lowpair::io::readUrdf(file.write(in.data, in.size), in.tip, in.base);
    FUZZ_CHECK(robot.poe.has_value() && !robot.dh.has_value());
    lowpair_fuzz::checkPoeModel(*robot.poe);
    lowpair_fuzz::checkConversion(*robot.poe);
  } catch (const lowpair::io::RobotFileError&) {
  }
  return 0;
}
