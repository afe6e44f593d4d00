#pragma once
/// @file joint_table.hpp
/// CSVs of joint vectors and target poses: the input of `fk --q-file`, `simulate --q-file`, `compensate`
/// (joint vectors) and `ik` (targets, optionally with seeds) (docs/ik.md "Input files").
///
/// The measurement CSV's text rules (csv_text.hpp: comments, `# length_unit: U`, bounded lines, decimal
/// numbers), header rule (csv_columns.hpp: columns by name in any order, `q1..qn` or the robot's joint names,
/// other columns ignored with a note) and limits (measurements.hpp), with
/// - TableKind::Joints: the joints (n >= 1); a measurement CSV's x, y, z, quaternion and target columns are
///   not read (and not noted);
/// - TableKind::Targets: `x,y,z` (positions), with `qw,qx,qy,qz` (poses, unit quaternion taken by name,
///   normalized when within 1e-6 of unit norm), optionally with the joints (a seed per row); no `target`.

#include <string>
#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair::io {

enum class TableKind { Joints, Targets };

struct JointTable {
  std::string path;
  int dof = 0;                   ///< the q columns (0: none, Targets only)
  bool pose = false;             ///< Targets: quaternion columns present
  std::vector<double> q;         ///< rows x dof, row-major
  std::vector<Pose> targets;     ///< Targets: one per row (rotation identity for positions)
  std::vector<long long> lines;  ///< the file line of each row
  std::string length_unit;       ///< from `# length_unit: U`; "" when none
  std::vector<std::string> notes;  ///< one line each without "note: ": the ignored columns
  size_t rows() const { return lines.size(); }
  /// The joint values as a rows x dof matrix.
  MatX matrix() const;
  Eigen::Map<const VecX> row(size_t k) const { return {q.data() + k * static_cast<size_t>(dof), dof}; }
};

/// @param robot_dof the robot's joint count: the joint columns must be as many (or none, Targets)
/// @param robot_path for the message of a wrong joint count
/// @param joint_names the robot's joint names a header may use instead of q1..qn (csvJointNames); none: q1..qn
/// @throws RobotFileError `FILE:LINE: what` or `FILE: what`
JointTable readJointTable(const std::string& path, TableKind kind, int robot_dof, const std::string& robot_path,
                          const std::vector<std::string>& joint_names = {});

/// The table's lengths in the robot's unit: when its `# length_unit` and `robot_unit` are both stated and
/// differ, the prismatic joints' values (`prismatic[i]`: joint i's q is a length; revolute and helical q are
/// rad) and the Targets' positions are multiplied by metresPerUnit(table) / metresPerUnit(robot), and
/// table.length_unit becomes robot_unit. One of them unstated, or both the same: nothing changes (as
/// calibrate reads a measurement CSV).
/// @return the note saying what was converted ("" when nothing was): "FILE: lengths converted from mm (its
///   length_unit comment) to m (the robot's), x 0.001" (Targets), "FILE: prismatic joint values converted ..."
///   (Joints)
/// @throws RobotFileError naming the file and the unit when one of the two is not a unit lowpair converts, or
///   `FILE:LINE: ...` when a converted value exceeds kMaxMagnitude
std::string convertTableUnit(JointTable& table, const std::string& robot_unit, const std::string& robot_path,
                             const std::vector<bool>& prismatic);

/// The joint types as convertTableUnit takes them: true where q is a length (a prismatic joint).
std::vector<bool> prismaticJoints(const PoeModel& model);

}  // namespace lowpair::io
