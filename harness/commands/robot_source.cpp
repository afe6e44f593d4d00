// The one robot loader of the CLI and the Python module (robot_source.hpp).
#include "commands/robot_source.hpp"

#include <filesystem>

#include "mujoco/mujoco_robot.hpp"

namespace lowpair::commands {

io::RobotFile loadRobot(const RobotSource& source, const ArgumentSpelling& spelling) {
  const std::string ext = std::filesystem::path(source.path).extension().string();
  if (ext != ".xml" && ext != ".urdf") {
    if (!source.tip.empty() || !source.base.empty()) {
      throw UsageError(source.path, spelling.name("tip") + "/" + spelling.name("base") +
                                        " go with a model file (.xml or .urdf), not a robot file");
    }
    return io::readRobotFile(source.path);
  }
  if (source.tip.empty()) {
    throw UsageError(source.path, spelling.setting("tip", "NAME") + " is required with a model file; " +
                                      mujoco::tipCandidates(source.path));
  }
  return mujoco::robotFileOfModel(source.path, source.tip, source.base);
}

}  // namespace lowpair::commands
