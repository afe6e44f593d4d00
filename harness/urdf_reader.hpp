#pragma once
/// @file urdf_reader.hpp
/// URDF kinematics through urdfdom (no MuJoCo; meshes are never opened, so `package://` and missing mesh
/// files do not matter). The chain from `base` to `tip` becomes a POE model in the base link's frame:
/// revolute, continuous and prismatic joints (axes of any length, normalized, scale 1), fixed joints folded
/// into the constant transforms, and a prismatic joint that mimics the revolute joint just before it on
/// the same axis (`multiplier` = pitch, length/rad, `offset` 0) read as one helical joint (the convention
/// `lowpair export` writes). Floating, planar and other mimic forms are rejected naming the joint.
/// Units: metres and radians (`length_unit: m`).

#include <string>

#include "robot_file.hpp"

namespace lowpair {

/// @param tip the tip link; @param base the base link ("" = the URDF's root link)
/// @return a RobotFile with `poe` set: joint names and ranges (limits; none for continuous joints) from
///         the URDF, `name` the robot's name, `length_unit` "m", `path` the file.
/// @throws RobotFileError ("FILE: what") for a file urdfdom cannot parse, unknown links, a tip that is
///         not below the base, unsupported joints.
RobotFile readUrdf(const std::string& path, const std::string& tip, const std::string& base = "");

}  // namespace lowpair
