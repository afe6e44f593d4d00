#pragma once
/// @file csv_columns.hpp
/// The header rule every CSV lowpair reads shares (the measurement CSV, measurements.hpp; the joint-vector
/// and target tables, joint_table.hpp): columns are found by their names, in any order
/// (docs/calibration.md "Measurement files (CSV)").
///
/// - Joints: `q1..qn` (n >= 1, each from q1 to qn once), or the robot's own joint names when the reader
///   knows the robot (csvJointNames), every one of them; never both spellings in one header.
/// - `target`, `x,y,z` and `qw,qx,qy,qz` (a rotation's quaternion, scalar qw: its values are taken by name,
///   so ROS's order `qx,qy,qz,qw` reads as the same rotation). A reader of poses takes `x,y,z` all or none,
///   `qw..qz` all or none (CsvColumns::requireWholeGroups); a joint table does not read them.
/// - A name that differs from one of these (or from a `q<digits>`) only in letter case, and `q` with
///   digits that is not q1..q1000 (`q0`, `q01`), are errors (a misspelt column is never dropped silently);
///   any other name is ignored, and the reader says so in one note (CsvColumns::ignoredNote).
/// - A column named twice is an error.
/// Which of the columns a file must or must not hold is the reader's rule (joint_table.hpp, measurements.hpp).

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace lowpair::io {

struct RobotFile;

/// The columns of a header line, by name: each is a 0-based field index.
struct CsvColumns {
  std::vector<size_t> joints;  ///< joint i's column, in joint order (empty: no joint columns)
  bool joint_names = false;    ///< the joints are spelled as the robot's joint names (else q1..qn)
  std::optional<size_t> target;
  std::optional<std::array<size_t, 3>> position;    ///< x, y, z
  std::optional<std::array<size_t, 4>> quaternion;  ///< qw, qx, qy, qz (scalar first, whatever the header's order)
  std::string incomplete;  ///< the first name missing from a partial x,y,z or qw..qz ("" when none is partial)
  std::vector<std::string> ignored;                 ///< the other columns' names, in header order, each once
  size_t count = 0;                                 ///< fields per line

  int dof() const { return static_cast<int>(joints.size()); }
  /// A reader of poses: fails with `missing column 'NAME' EXPECTED` when x,y,z or qw..qz is partial.
  void requireWholeGroups(const std::string& expected, const std::function<void(const std::string&)>& fail) const;
  /// "FILE:LINE: ignored the columns 'a', 'b' (not columns lowpair reads)"; "" when none is ignored.
  std::string ignoredNote(const std::string& path, long long line) const;
};

/// The names of `joint_names` a header may use for the joints: all of them when every joint has a name, they
/// are distinct, and none is (in any letter case) `target`, `x`, `y`, `z`, `qw`..`qz` or `q<digits>`;
/// otherwise none (the header must then say q1..qn).
std::vector<std::string> csvJointNames(const std::vector<std::string>& joint_names);
/// csvJointNames of a robot file's joints (its POE or D-H joints' `name`).
std::vector<std::string> csvJointNames(const RobotFile& robot);

/// Finds the columns of a header line (`fields` split and trimmed, csv_text.hpp).
/// @param joint_names the robot's names (csvJointNames), or none when the reader does not know the robot
/// @param max_joints most joint columns (measurements.hpp kMaxMeasurementJoints)
/// @param expected the reader's expected columns, appended to the messages of a missing or unexpected column
/// @param fail throws `FILE:LINE: what`: a missing joint column (`missing column 'q2'`, `'elbow'`),
/// a repeated one (`column 'x' repeats (columns 2 and 5)`), both joint spellings, a misspelt name, too many
/// joints
CsvColumns findCsvColumns(const std::vector<std::string>& fields, const std::vector<std::string>& joint_names,
                          int max_joints, const std::string& expected, const std::function<void(const std::string&)>& fail);

}  // namespace lowpair::io
