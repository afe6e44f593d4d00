#pragma once
/// @file measurements.hpp
/// The measurement CSV: joint variables and the measured tool frame (or a point of it), one measurement per
/// line (written by `lowpair simulate`, read by `lowpair calibrate`).
///
/// Format:
/// - Text, comma separated, lines ending in LF or CRLF; a UTF-8 byte order mark at the start is skipped.
/// - Comments: blank lines, and lines whose first character other than spaces and tabs is `#`, anywhere.
///   One comment may state the length unit of `x,y,z`: `# length_unit: U` (U one token of 1-16 printable
///   ASCII characters, e.g. `mm`; `lowpair simulate` writes it when the unit is known). A second one with
///   another unit is an error. `calibrate` converts measurements in another unit it knows (m, mm, ...) to the nominal's.
/// - Header: the first other line names the columns (names trimmed of spaces and tabs), found by name in any
///   order (csv_columns.hpp): `q1..qn` (or the robot's joint names, when the caller gives them) and `x,y,z`
///   (position measurements), with `qw,qx,qy,qz` (pose measurements) or with `target` (target measurements,
///   Measure::Targets), 1 <= n <= 1000 joints. Any other column is ignored (MeasurementFile::notes says
///   which); a missing, repeated or misspelt (letter case) column is an error. The writer's order is
///   `q1..qn,x,y,z[,qw,qx,qy,qz]` or `q1..qn,target,x,y,z`.
///   - `q1..qn`: the robot's joint variables (rad for revolute and helical joints, length for prismatic);
///   - `x,y,z`: the position of the tool frame in the base frame (`T_base_tool.p`), in the robot's length
///     unit; for target measurements, the measured point of the target named in `target` (the rotation
///     of `T_base_tool` is then the identity);
///   - `target`: a target name (robot_file.hpp targetNameProblem: 1-64 printable ASCII characters, none a
///     space, comma or quote), one row per target measured at a pose (the rows of one pose repeat its q).
///     The names are numbered in order of first appearance (MeasurementFile::target_names, indexed by
///     Measurement::target); at most 1000 distinct names (kMaxTargets);
///   - `qw,qx,qy,qz`: the rotation of `T_base_tool` as a unit quaternion, scalar qw (taken by name: ROS's
///     `qx,qy,qz,qw` is the same rotation). A norm within 1e-6
///     of 1 is accepted (and normalized); q and -q are the same rotation (the writer makes qw >= 0).
/// - Data: every other line is one measurement, exactly one field per column: a number in each column read
///   (the `target` column: a name, trimmed of spaces and tabs), anything in an ignored one. A number is a whole token
///   (trimmed of spaces and tabs) read by strtod in the C locale (e.g. `-1.5`, `2e-3`, `0x1p-3`) and must
///   be finite.
/// - `s1..sn` or `s_<joint name>` (optional, any of the joints): the sign of the joint's last move, -1, 0 or 1
///   (MeasurementFile::signs; calibrate --backlash reads them).
/// - Limits: at least one and at most 1,000,000 measurements, lines of at most 65,536 bytes (without the
///   line end), at most 100,000,000 joint values in all (measurements times joints: 800 MB in memory).
///
/// Errors (RobotFileError) are one line, `FILE:LINE: what` with the 1-based line, or `FILE: what` for the
/// file as a whole (`cannot open file`, `is a directory, not a file`, `no header line ...`,
/// `no measurements`). Text quoted from the file is cut to 40 bytes, with every byte outside printable
/// ASCII shown as '?'.
///
/// The writer prints numbers with 17 significant digits, so joint values and positions read back bit for
/// bit; the rotation reads back to rounding (it passes through a quaternion); target names read back as
/// written (their indices in order of first appearance in the file).

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/csv_text.hpp"
#include "lowpair/calibration.hpp"

namespace lowpair::io {

struct MeasurementFile {
  std::string path;
  Measure measure = Measure::Pose;  ///< Position when the file has no quaternion columns
  int dof = 0;                      ///< n, the number of joint columns
  std::vector<Measurement> measurements;  ///< rotation = identity for position measurements
  std::vector<long long> lines;           ///< the file line of each measurement (for messages)
  std::string length_unit;  ///< from a `# length_unit: U` comment; "" when the file states none
  /// The unit its `# length_unit` comment stated when a reader converted its lengths to the robot's (and set
  /// length_unit to the robot's): "" when nothing was converted.
  std::string converted_from;
  /// Measure::Targets: the target names in order of first appearance (Measurement::target indexes them);
  /// empty otherwise.
  std::vector<std::string> target_names;
  /// What the reader did that the user should know, one line each without "note: ": the ignored columns.
  std::vector<std::string> notes;
  /// Columns `s1..sn` or `s_<joint name>`: the sign of each joint's last move (-1, 0 or 1; deflection.hpp), read
  /// for backlash. Per joint whether the file has its column (empty: none), and per measurement the values (0 for
  /// a joint without a column; empty when the file has no sign column).
  std::vector<bool> sign_columns;
  std::vector<VecX> signs;
};

/// Limits of the reader (see the file comment).
constexpr int kMaxMeasurements = 1000000;
constexpr int kMaxMeasurementJoints = 1000;
constexpr size_t kMaxMeasurementLineBytes = kMaxCsvLineBytes;  ///< 65,536 (csv_text.hpp)
constexpr long long kMaxMeasurementJointValues = 100000000;

/// A quaternion qw..qz is a unit quaternion when its norm is within this of 1 (it is then normalized): the rule
/// of every reader of quaternion columns (measurement, target and pose CSVs) and of the Python module's arrays.
constexpr double kUnitQuaternionTolerance = 1e-6;

/// The rotation of the quaternion (w, x, y, z), scalar first, normalized, when its norm is within
/// kUnitQuaternionTolerance of 1; else nothing. `norm` is set to its norm (for the caller's message).
std::optional<Mat3> unitQuaternionRotation(double w, double x, double y, double z, double& norm);

/// The quaternion qw, qx, qy, qz the writer prints for the rotation R: normalized, qw >= 0.
Eigen::Vector4d csvQuaternion(const Mat3& R);

/// Target names numbered in order of first appearance, as the reader numbers the `target` column.
struct TargetNumbering {
  std::vector<std::string> names;                ///< in order of first appearance
  std::unordered_map<std::string, int> indices;  ///< name -> index into names
  /// The index of `name`, a new name numbered next; -1 when the name is new and not a target name
  /// (`problem`: its targetNameProblem) or kMaxTargets names are numbered already (`problem` empty).
  int number(const std::string& name, std::string& problem);
};

/// A unit label a `# length_unit: U` comment can hold: one token of 1-16 printable ASCII characters.
bool isUnitLabel(const std::string& unit);

/// Every line counts, comments and blank lines too: a stream of `#` lines ends here.
constexpr long long kMaxMeasurementLines = kMaxMeasurements + 100000LL;

/// Called once the header line is read (dof, measure and a length_unit comment before it are set, no
/// measurement yet): a caller that knows what the file must hold rejects a wrong one before the rest of a
/// large file is read. It throws to reject.
using MeasurementHeaderCheck = std::function<void(const MeasurementFile& header)>;

/// Reads a measurement CSV. @throws RobotFileError (see the file comment)
/// @param joint_names the robot's joint names a header may use instead of q1..qn (csvJointNames); none: q1..qn
MeasurementFile readMeasurements(const std::string& path, const MeasurementHeaderCheck& check_header = {},
                                 const std::vector<std::string>& joint_names = {});

/// The CSV text of `measurements`: `comments` as `# ...` lines (a comment holding line breaks becomes
/// several), the header, then one line per measurement (17 significant digits; quaternion with qw >= 0
/// for Pose; for Targets the name `target_names[m.target]` in the `target` column).
/// @param target_names Measure::Targets only (empty for the other measures): distinct target names, at
/// most kMaxTargets
/// @throws std::invalid_argument for no measurement, joint vectors of different sizes, target names for
/// another measure, a name that is not a target name or repeats, or a Targets measurement whose `target`
/// is not an index into `target_names`
std::string formatMeasurements(Measure measure, const std::vector<Measurement>& measurements,
                               const std::vector<std::string>& comments,
                               const std::vector<std::string>& target_names = {});

/// formatMeasurements onto a stream, row by row (the text of 10^6 rows is never held whole); every row is
/// checked before the first byte is written. @throws std::invalid_argument as formatMeasurements
void writeMeasurements(std::ostream& out, Measure measure, const std::vector<Measurement>& measurements,
                       const std::vector<std::string>& comments, const std::vector<std::string>& target_names = {});

/// The measurement CSV written one row at a time, from rows kept elsewhere (`fk --q-file` writes the table it
/// read and the poses it computed, without a Measurement per row): the same bytes as formatMeasurements.
class MeasurementWriter {
 public:
  /// @param mixed Measure::Targets with poses of the tool frame among the rows (both sets of columns)
  /// @throws std::invalid_argument for target names as formatMeasurements
  MeasurementWriter(std::ostream& out, Measure measure, Eigen::Index dof, const std::vector<std::string>& target_names,
                    bool mixed = false);
  /// The comments and the header line.
  void writeHeader(const std::vector<std::string>& comments);
  /// @throws std::invalid_argument for a row formatMeasurements refuses (checkRow)
  void write(const Eigen::Ref<const VecX>& q, const Pose& T_base_tool, int target = -1);
  void write(const Measurement& m) { write(m.q, m.T_base_tool, m.target); }
  /// @throws std::invalid_argument when a row of `dof` joint values measuring `target` cannot be written
  void checkRow(Eigen::Index dof, int target) const;

 private:
  bool poseRow(int target) const;
  std::ostream& out_;
  Measure measure_;
  Eigen::Index dof_;
  std::vector<std::string> target_names_;
  bool mixed_;
  std::string row_;  // one row's text, reused
};

}  // namespace lowpair::io
