#pragma once
/// @file export.hpp
/// `lowpair export`: a robot as a URDF, an MJCF, a POE robot file or a D-H robot file (README, "The
/// `lowpair` command line"; docs/file_formats.md, "export").
///
/// URDF and MJCF are kinematic twins of the model: one link (body) per joint frame, every joint about or
/// along the z axis of its frame, the base link/body `base` and the tool frame `tool` (a URDF link on a
/// fixed joint, an MJCF site). Their joint variable is the physical motion `x = scale (q + offset)`
/// (docs/conventions.md, the joint-variable map), in radians and the robot's length unit; when a joint's
/// scale is not 1 or its offset not 0 the robot file of `q` has to travel with them (`joint_variables`).
/// Helical joints: URDF, a revolute joint and, on an intermediate link, a prismatic joint on the same
/// axis that mimics it (`multiplier` = pitch, length/rad; MuJoCo 2.2.2 ignores `<mimic>`, so only urdfdom
/// reads such a URDF as lowpair does); MJCF, a hinge and a slide in one body coupled
/// by `<equality><joint joint1=slide joint2=hinge polycoef="0 pitch 0 0 0"/>` (mujoco_robot.hpp).
/// Limits (in x): a range becomes `<limit>` / `range`; a revolute joint without one is `continuous` (MJCF:
/// an unlimited hinge), a prismatic one gets `+-L` in URDF (below) and stays unlimited in MJCF; a screw's
/// URDF slide gets pitch times the revolute's limits, or `+-(L + 1e4 |pitch|)` for a continuous screw.
/// Numbers in URDF/MJCF: the shortest of 15, 16, 17 significant digits that reads back as the same double;
/// in the robot files (yaml-cpp) 17 digits. Names are made XML-safe (`[A-Za-z0-9_.-]`, anything else `_`)
/// and unique (`_2`, `_3`, ...; `base`, `tool`, `tool_joint` reserved); the robot name and comments keep
/// their text (control characters as spaces, invalid UTF-8 as `?`, `--` split in comments), and the
/// documents are built and printed by tinyxml2 (attribute values escaped), so no name can break the file.

#include <optional>
#include <string>
#include <vector>

#include "lowpair/model.hpp"
#include "io/robot_file.hpp"

namespace lowpair::io {

enum class ExportFormat { Urdf, Mjcf, Poe, Dh };

/// "urdf", "mjcf", "poe", "dh".
const char* exportFormatName(ExportFormat format);
/// @throws std::invalid_argument for any other text
ExportFormat parseExportFormat(const std::string& text);

/// Prismatic joints without a range get the URDF limit `+-L` (L = the robot size, the project's default
/// sampling range of such joints: a limit that leaves L, and so every tolerance, unchanged on read-back).
/// MJCF slides without a range stay unlimited. Effort and velocity limits (required by URDF, unused by
/// kinematics) are this placeholder.
constexpr double kUrdfEffortVelocity = 1e6;
/// Mass and principal moments of inertia of every exported link/body (simulators refuse massless moving
/// links; kinematics does not depend on them). In the robot's units (kg and kg length^2 if in metres).
constexpr double kExportMass = 1e-3, kExportInertia = 1e-6;
/// URDF and MJCF use the D-H frames of poeToDh when the table is well conditioned: its accuracy scale
/// (DhConversion::scale, the largest of L, |d|, |a|, |d_T|) at most kExportDhScale L and its FK deviation
/// from the POE model (checkDhConversion, 65 configurations) at most kExportDhDeviation (rad, and times L).
/// Otherwise (nearly parallel consecutive axes) each joint frame is put on the joint's line at its point
/// nearest the base origin (the frames the library evaluates, KinematicChain), whose constants stay bounded
/// by 2 L. On 3,000 random robots read back by urdfdom, frames on the lines gave <= 2.2e-14 L for every
/// robot; D-H frames <= 4e-14 L up to a scale of 128 L, 4e-13 L at 1e3 L, and 1.3e-12 L for a row whose
/// axes meet at 1.4e-4 rad although its scale was only 26 L (the table's own deviation): hence both tests.
constexpr double kExportDhScale = 100.0;
constexpr double kExportDhDeviation = 1e-13;

/// The model with the physical motion as its joint variable: every joint's scale 1 and offset 0, ranges
/// mapped by `x = scale (q + offset)`; same unit twists, pitches, names and tool pose, so its FK at `x`
/// is the model's FK at `q`. @throws std::invalid_argument when a mapped range overflows.
PoeModel motionModel(const PoeModel& model);

/// True when some joint's scale is not 1 or its offset not 0 (the URDF/MJCF variable x differs from q).
bool needsJointVariables(const PoeModel& model);

/// The frames URDF and MJCF are written from, for a model whose joint variable is the motion
/// (motionModel): `T_base_tool(x) = T_base_first * prod_i [Rz(j_i x_i) Tz(k_i x_i) T_link[i]] * T_last_tool`,
/// joint i about/along the z axis of the frame it follows.
struct ExportFrames {
  Pose T_base_first;         ///< frame of joint 1's line in the base frame
  std::vector<Pose> T_link;  ///< [i]: joint i's moved frame to joint i+1's frame (the last: identity or D-H link_n)
  Pose T_last_tool;          ///< after the last link to the tool
  bool dh = true;            ///< D-H frames (false: frames on the joint lines, see kExportDhScale)
  double dh_scale = 1.0;     ///< DhConversion::scale of the D-H table
  double dh_deviation = 0.0; ///< its FK deviation from the model: max(rotation, translation / L)
  double size = 1.0;         ///< L
};
ExportFrames exportFrames(const PoeModel& motion_model);


/// URDF of `model` (file comment above); lengths in the model's unit. `comments` become one XML comment.
/// With `masses` (the robot file's, in the model's length unit): each link's <inertial> holds its mass at its
/// centre of mass (a massless moving link keeps kExportMass), the tool link the payload (none without one).
std::string formatUrdf(const PoeModel& model, const std::string& name, const std::vector<std::string>& comments,
                       const std::optional<MassModel>& masses = std::nullopt);
/// MJCF of `model` (file comment above), `<compiler angle="radian"/>`, zero gravity. With `masses`: the
/// links' inertials as formatUrdf's, the payload a body welded at the tool, and the file's gravity.
std::string formatMjcf(const PoeModel& model, const std::string& name, const std::vector<std::string>& comments,
                       const std::optional<MassModel>& masses = std::nullopt);

/// What `lowpair export` writes.
struct ExportedRobot {
  std::string text;  ///< the file in the requested format
  /// URDF/MJCF of a model with a scale != 1 or offset != 0: the POE robot file whose joint variable q maps
  /// onto the exported one by `x = scale (q + offset)` (validate / simulate `--joint-variables`, scenarios'
  /// `joint_variables:`).
  std::optional<std::string> joint_variables;
  std::vector<std::string> notes;  ///< sentences for stderr (ill-conditioned D-H rows, frames chosen)
  /// MuJoCo (lowpair validate) can load the file: false for a URDF with helical joints (MuJoCo 2.2.2 has no
  /// `<mimic>`; MujocoRobot refuses a mimicking joint) and for robot files.
  bool mujoco_readable = false;
};

/// `file` in `format`; `comments` (provenance) head the file.
ExportedRobot exportRobot(const RobotFile& file, ExportFormat format, const std::vector<std::string>& comments);

/// `<dir>/<stem of out>.joint_variables.yaml`.
std::string jointVariablesPath(const std::string& out);

}  // namespace lowpair::io
