// Files written and read by the Python module (files.cpp): Robot.save and lowpair.export write through exportTo.
#pragma once

#include <string>

#include "robot.hpp"

namespace lowpair::python {

// `lowpair export --out path`: the robot as 'urdf', 'mjcf', 'poe' or 'dh' (Robot.save: its own kind).
void exportTo(const Robot& r, const std::string& path, const std::string& format_text);

}  // namespace lowpair::python
