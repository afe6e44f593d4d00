#pragma once
/// @file urdf_reader.hpp
/// URDF kinematics through urdfdom (no MuJoCo; meshes are never opened, so `package://` and missing mesh
/// files do not matter). The chain from `base` to `tip` becomes a POE model in the base link's frame:
/// revolute, continuous and prismatic joints (axes of any length, normalized, scale 1), fixed joints folded
/// into the constant transforms, and a prismatic joint that mimics the revolute joint just before it on
/// the same axis (`multiplier` = pitch, length/rad, `offset` 0) read as one helical joint (the convention
/// `lowpair export` writes). Floating, planar and other mimic forms are rejected naming the joint.
/// Units: metres and radians (`length_unit: m`). Joint origins are URDF fixed-axis roll-pitch-yaw,
/// `R = Rz(yaw) Ry(pitch) Rx(roll)`. Only the joints between base and tip are looked at: floating joints or
/// mimics elsewhere in the tree do not matter.
///
/// urdfdom logs through console_bridge; while parsing, its messages are kept off the terminal and its errors
/// become the exception's message (the handler is global: parses are serialized, the previous handler and
/// log level restored).

#include <string>

#include "io/robot_file.hpp"

namespace lowpair::io {

/// @param tip the tip link; @param base the base link ("" = the URDF's root link)
/// @return a RobotFile with `poe` set: joint names and ranges (`<limit lower upper>` as urdfdom reads them,
///         0 where an attribute is missing; none for continuous joints; a helical joint has its revolute's)
///         from the URDF, every scale exactly 1 (the joint value is the turn in rad or the slide in m),
///         `name` the robot's name, `length_unit` "m", `path` the file.
/// @throws RobotFileError (one line, "FILE: what") for a missing file, a directory, an empty, binary or
///         non-UTF-8 file, a file urdfdom cannot parse ("FILE: not a valid URDF: urdfdom's errors"), unknown
///         links, a base that is not an ancestor of the tip, no moving joint between them, unsupported
///         joints, a zero axis, and what PoeModel rejects (e.g. a range with lower > upper).
RobotFile readUrdf(const std::string& path, const std::string& tip, const std::string& base = "");

/// The tips a URDF offers, for the message of a missing or wrong tip: "links: 'base', 'link1', ..." (the first
/// 20, as a wrong tip's message lists them). @throws RobotFileError as readUrdf does for a file urdfdom cannot parse
std::string urdfTipCandidates(const std::string& path);

/// Checks that urdfdom accepts the URDF at `path` (known joint types, every joint's links defined, one tree
/// with one root). ModelCopy calls it before MuJoCo 2.2.2 sees a URDF: MuJoCo's URDF parser crashes on an
/// unknown joint type or a joint whose links are not in the tree (fuzz regressions urdf_mj_loadxml_segv_*).
/// @throws RobotFileError as readUrdf does for a file urdfdom cannot parse
void checkUrdf(const std::string& path);

}  // namespace lowpair::io
