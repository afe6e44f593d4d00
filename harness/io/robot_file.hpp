#pragma once
/// @file robot_file.hpp
/// Reading robot files (YAML, design.md "Robot file"): a POE or a D-H description. Every error is a
/// RobotFileError whose message reads `FILE: what is wrong` (with the YAML line where there is one).

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/deflection.hpp"
#include "lowpair/gravity.hpp"
#include "lowpair/model.hpp"

namespace lowpair::io {

class RobotFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws RobotFileError("PATH: WHAT"), the line the CLI prints after "error: " (the readers of model files).
[[noreturn]] inline void failFile(const std::string& path, const std::string& what) {
  throw RobotFileError(path + ": " + what);
}

/// Largest model file read, in bytes: a robot file, a URDF, an MJCF, and an MJCF with every file it includes
/// (2 MiB; the published MJCF and URDF files tried by hand (Menagerie, ros-industrial) are at most 11 KB; meshes,
/// which a kinematics-only read never opens, do not count). Checked by size before a byte is read. Why 2 MiB:
/// parsing holds up to about 230 bytes per byte of a file of tiny nodes (measured: a YAML flow list of 2M zeros,
/// 4 MiB, 973 MB and 5.7 s; the same bytes of `<a/>` elements, 240 MB as URDF and 363 MB as MJCF), so 64 MiB
/// could ask for 15 GB.
constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{2} << 20;

/// For an existing `path`: throws unless it is a regular file (after symbolic links) of at most
/// kMaxModelFileBytes. A path that does not exist passes (the reader names it as it always has).
/// @throws RobotFileError `PATH: not a regular file ...` or `PATH: N bytes: over the 2 MiB ...`
void requireBoundedModelFile(const std::string& path);

/// Most joints of a robot (a robot file's list, a URDF's or an MJCF's chain): every command's cost grows with
/// them (singular of 10,000 joints: about 1 s), and the measurement CSVs hold at most kMaxMeasurementJoints.
constexpr int kMaxJoints = 10000;

/// @throws RobotFileError `PATH: N joints, more than the 10000 a robot may have` beyond kMaxJoints
void requireJointCount(const std::string& path, size_t joints);

/// Target names (a robot file's `targets:`, the measurement CSV's `target` column; docs/file_formats.md):
/// 1 to kMaxTargetNameBytes printable ASCII characters, none of them a space, a comma or a quote (`'`, `"`),
/// so that a name is one CSV field as it stands.
constexpr size_t kMaxTargetNameBytes = 64;
/// Most targets a robot file lists, and most distinct target names a measurement file holds.
constexpr int kMaxTargets = 1000;
/// The rule, as error messages state it.
constexpr const char* kTargetNameRule = "a target name is 1-64 printable ASCII characters without spaces, commas or quotes";

/// What makes `name` no target name ("is empty", "holds a space", ...); "" when it is one.
std::string targetNameProblem(const std::string& name);
/// What makes `p` no target point ("is not finite", "has magnitude ..."): non-finite, or beyond the 1e100 a
/// robot's size may reach (kMaxMagnitude, as the tool position); "" when it is one.
std::string targetPointProblem(const Vec3& p);

/// `text` from a file for a message: in single quotes, cut to 40 bytes (then `...`), every byte outside
/// printable ASCII shown as '?'.
std::string quotedFileText(const std::string& text);

/// `tool_frame:` what the calibration that wrote a file determined of its tool frame (docs/file_formats.md).
enum class ToolFrame {
  Defined,  ///< no key: the file's tool frame is what it states (a nominal; a calibration that determined it)
  Origin,   ///< `origin`: the tool origin was calibrated (position measurements); its orientation is the nominal's
  Nominal,  ///< `nominal`: not determined (targets at unknown or too few known points): the nominal's
};

struct RobotFile {
  std::string path;
  std::string name;
  std::string length_unit = "";
  std::string angle_unit = "rad";  ///< "rad" or "deg": offsets, D-H angles, revolute ranges, pitch per angle
  std::string description;
  std::optional<PoeModel> poe;  ///< exactly one of poe / dh is set
  std::optional<DhModel> dh;
  /// `targets:`: points fixed on the tool (a laser tracker's SMRs), in the tool frame and length_unit; names
  /// unique, every point_tool set (at most kMaxTargets).
  std::vector<Target> targets;
  /// Per target (index as `targets`): its `normal:`, the direction its SMR faces in the tool frame, unit length
  /// (normalised on load from a finite nonzero vector); none when the file gives none. `plan --tracker` checks
  /// that the tracker is within `--smr-angle` of it (docs/plan.md "Line of sight"). Not written back by the
  /// robot-file writers (a calibrated file keeps its points only).
  std::vector<std::optional<Vec3>> target_normals;
  /// `measurement_frame:` (4 rows): `T_measurement_base`, the pose of the robot's base frame in the frame its
  /// measurements were taken in (a tracker's), as `calibrate --out` records it; FK in that frame is
  /// `T_measurement_base T_base_tool(q)` (`fk --frame measurement`).
  std::optional<Pose> measurement_frame;
  ToolFrame tool_frame = ToolFrame::Defined;  ///< `tool_frame:`
  /// The masses gravity loads come from (per joint `mass`/`com`, `payload:`, `gravity:`; docs/file_formats.md):
  /// set when any of those keys is given (links empty when no joint states a mass; metres_per_unit from
  /// length_unit).
  std::optional<MassModel> masses;
  /// Per joint `compliance` and `backlash` (radians for turning joints; empty when no joint states one).
  JointDeflection deflection;

  double angleFactor() const;  ///< radians per angle_unit
  int dof() const { return poe ? poe->dof() : dh->dof(); }
  /// The POE model, converting the D-H description when that is what the file holds.
  PoeModel poeModel() const;
};

/// @throws RobotFileError
RobotFile readRobotFile(const std::string& path);

/// Metres per length unit for the units lowpair converts: m, mm, cm, dm, um, km, in, ft; nullopt for
/// any other label (and for none).
std::optional<double> metresPerUnit(const std::string& length_unit);

/// `file` with every length in metres (what a URDF holds): a POE file (a D-H file converted) whose twist
/// moments, pitches, tool position and target points are multiplied by metresPerUnit(length_unit), whose
/// prismatic scales absorb the factor (q, its offset and range keep the file's unit), and whose length_unit
/// is "m".
/// @throws RobotFileError when the file states no length unit or one lowpair does not convert, or a target
/// point would be above 1e100 (kMaxMagnitude) in the new unit
RobotFile inMetres(const RobotFile& file);

/// `file` with every length in `unit` (one metresPerUnit knows), as inMetres does for metres.
/// @throws RobotFileError when the file states no length unit, or either unit is not one lowpair converts, or
/// a target point would be above 1e100 (kMaxMagnitude) in `unit`
RobotFile inUnit(const RobotFile& file, const std::string& unit);

/// What a written robot file records beside its model (every part optional).
struct RobotFileExtras {
  /// The file's `targets:` (points with 17 significant digits: they read back bit for bit; `known: true` for
  /// known ones; none: no key).
  std::vector<Target> targets{};
  std::optional<Pose> measurement_frame{};  ///< `measurement_frame:` (4 rows, 17 significant digits)
  ToolFrame tool_frame = ToolFrame::Defined;  ///< `tool_frame:` (Defined: no key)
  /// Per joint `mass`/`com` (when links are given) and `payload:`/`gravity:` (17 significant digits).
  std::optional<MassModel> masses{};
  /// Per joint `compliance` and `backlash` where non-zero (17 significant digits, in the file's angle unit).
  JointDeflection deflection{};
};

/// A POE robot file holding `model` (readRobotFile reads it back to rounding: twists `scale * unit twist`
/// with 17 significant digits, the tool as `tool_pose`), with `like`'s length and angle units (offsets and
/// revolute ranges converted to its angle_unit), `name`, `description` and `comments` as leading `#` lines.
/// Strings are emitted by yaml-cpp (quoted and escaped as needed).
/// @throws std::invalid_argument for targets readRobotFile would refuse (a name that is not a target name or
/// repeats, a target without point_tool, a point not finite or above 1e100, more than kMaxTargets)
std::string formatPoeRobotFile(const PoeModel& model, const RobotFile& like, const std::string& name,
                               const std::string& description, const std::vector<std::string>& comments,
                               const RobotFileExtras& extras = {});

/// A D-H robot file of `model` (docs/file_formats.md; readRobotFile reads it back to rounding: numbers with
/// 17 significant digits, strings quoted and escaped by yaml-cpp) with `like`'s units (angles, pitch and
/// revolute ranges in its angle_unit), `name`, `description` and `comments` as leading `#` lines.
/// A joint offset (0 in every table poeToDh makes) is folded into its row (movedRow). `extras` as for
/// formatPoeRobotFile (targets in the D-H tool frame; the D-H base frame is the POE model's, so a measurement
/// frame carries over as it is).
/// @throws std::invalid_argument as formatPoeRobotFile for targets
std::string formatDhRobotFile(const DhModel& model, const RobotFile& like, const std::string& name,
                              const std::string& description, const std::vector<std::string>& comments,
                              const RobotFileExtras& extras = {});

}  // namespace lowpair::io
