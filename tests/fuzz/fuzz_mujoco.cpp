// Fuzz target: MujocoRobot (harness/mujoco_robot.hpp): the kinematics-only copy (ModelCopy, tinyxml2), MuJoCo's
// loader and the chain extraction, for MJCF and URDF. Input: an optional first line `TIP [BASE]`
// (header_line.hpp), then the model. Allowed: RobotFileError. An accepted model's POE model evaluates
// finitely, and so do MuJoCo's tip pose and Jacobian at q = 0.
//
// MuJoCo's fatal errors: the harness's handler (installMujocoHandlers) prints one line and calls _Exit(2),
// the CLI's documented exit for a bad model. Under libFuzzer that would end the run without a report, so
// LLVMFuzzerInitialize lets the harness install its handlers and then replaces the error handler with one
// that throws MujocoFatal, counted here as a rejected input (MuJoCo's own compiler throws through its C code
// the same way). MuJoCo's loader installs its own handler while compiling, so this handler only sees fatal
// errors outside mj_loadXML (mj_makeData, the kinematics calls). Set LOWPAIR_FUZZ_MUJOCO_EXIT=1 to keep
// the harness's _Exit(2) instead (e.g. to check that an input ends as exit 2).
#include <mujoco/mujoco.h>

#include <cstdlib>
#include <stdexcept>

#include "fuzz_common.hpp"
#include "header_line.hpp"
#include "lowpair/kinematics.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::mujoco;

namespace {
struct MujocoFatal : std::runtime_error {
  using std::runtime_error::runtime_error;
};
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  try {
    const lowpair::mujoco::MujocoRobot robot("/nonexistent/lowpair_fuzz.xml", "tool");  // installs the handlers
  } catch (const lowpair::io::RobotFileError&) {
  }
  const char* keep = std::getenv("LOWPAIR_FUZZ_MUJOCO_EXIT");
  if (!(keep && *keep == '1')) mju_user_error = [](const char* msg) { throw MujocoFatal(msg); };
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // the root element decides MJCF or URDF, not the suffix
  static const lowpair_fuzz::TempFile file(".xml");
  const lowpair_fuzz::HeaderLine in = lowpair_fuzz::splitHeaderLine(data, size);
  try {
    const lowpair::mujoco::MujocoRobot robot(file.write(in.data, in.size), in.tip, in.base);
    const lowpair::PoeModel& model = robot.poeModel();
    FUZZ_CHECK(model.dof() == robot.dof());
    lowpair_fuzz::checkPoeModel(model);
    lowpair::mujoco::MujocoRobot::Evaluator eval(robot);
    const lowpair::VecX zero = lowpair::VecX::Zero(robot.dof());
    FUZZ_CHECK(lowpair_fuzz::finite(eval.tipPose(zero)));
    lowpair::Mat6X J(6, robot.dof());
    FUZZ_CHECK(lowpair_fuzz::finite(eval.tipJacobian(zero, J)));
    FUZZ_CHECK(J.allFinite());
  } catch (const lowpair::io::RobotFileError&) {
  } catch (const MujocoFatal& e) {
    std::fprintf(stderr, "MuJoCo fatal error (the CLI exits 2): %s\n", e.what());
  }
  return 0;
}
