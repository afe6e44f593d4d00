#pragma once
/// @file robot_file.hpp
/// Reading robot files (YAML, design.md "Robot file"): a POE or a D-H description. Every error is a
/// RobotFileError whose message reads `FILE: what is wrong` (with the YAML line where there is one).

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lowpair/model.hpp"

namespace lowpair::io {

class RobotFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Largest model file read, in bytes: a robot file, a URDF, an MJCF and each file it includes (64 MiB;
/// the published MJCF and URDF files tried by hand (Menagerie, ros-industrial) are at most 11 KB; meshes, which a
/// kinematics-only read never opens, do not count). Checked by size before a byte is read.
constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{64} << 20;

/// For an existing `path`: throws unless it is a regular file (after symbolic links) of at most
/// kMaxModelFileBytes. A path that does not exist passes (the reader names it as it always has).
/// @throws RobotFileError `PATH: not a regular file ...` or `PATH: N bytes: over the 64 MiB ...`
void requireBoundedModelFile(const std::string& path);

struct RobotFile {
  std::string path;
  std::string name;
  std::string length_unit = "";
  std::string angle_unit = "rad";  ///< "rad" or "deg": offsets, D-H angles, revolute ranges, pitch per angle
  std::string description;
  std::optional<PoeModel> poe;  ///< exactly one of poe / dh is set
  std::optional<DhModel> dh;

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
/// moments, pitches and tool position are multiplied by metresPerUnit(length_unit), whose prismatic scales
/// absorb the factor (q, its offset and range keep the file's unit), and whose length_unit is "m".
/// @throws RobotFileError when the file states no length unit or one lowpair does not convert
RobotFile inMetres(const RobotFile& file);

/// `file` with every length in `unit` (one metresPerUnit knows), as inMetres does for metres.
/// @throws RobotFileError when the file states no length unit, or either unit is not one lowpair converts
RobotFile inUnit(const RobotFile& file, const std::string& unit);

/// A POE robot file holding `model` (readRobotFile reads it back to rounding: twists `scale * unit twist`
/// with 17 significant digits, the tool as `tool_pose`), with `like`'s length and angle units (offsets and
/// revolute ranges converted to its angle_unit), `name`, `description` and `comments` as leading `#` lines.
/// Strings are emitted by yaml-cpp (quoted and escaped as needed).
std::string formatPoeRobotFile(const PoeModel& model, const RobotFile& like, const std::string& name,
                               const std::string& description, const std::vector<std::string>& comments);

/// A D-H robot file of `model` (docs/file_formats.md; readRobotFile reads it back to rounding: numbers with
/// 17 significant digits, strings quoted and escaped by yaml-cpp) with `like`'s units (angles, pitch and
/// revolute ranges in its angle_unit), `name`, `description` and `comments` as leading `#` lines.
/// A joint offset (0 in every table poeToDh makes) is folded into its row (movedRow).
std::string formatDhRobotFile(const DhModel& model, const RobotFile& like, const std::string& name,
                              const std::string& description, const std::vector<std::string>& comments);

}  // namespace lowpair::io
