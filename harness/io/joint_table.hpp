#pragma once
/// @file joint_table.hpp
/// CSVs of joint vectors and target poses: the input of `fk --q-file`, `simulate --q-file`, `compensate`
/// (joint vectors) and `ik` (targets, optionally with seeds) (docs/ik.md "Input files").
///
/// The measurement CSV's text rules (csv_text.hpp: comments, `# length_unit: U`, bounded lines, decimal
/// numbers) and limits (measurements.hpp), with a header of `q1..qn` (n >= 0) and then
/// - TableKind::Joints: anything (a measurement CSV's x, y, z, quaternion or target columns, a plan's
///   nothing), not read; n >= 1;
/// - TableKind::Targets: exactly `x,y,z` (positions) or `x,y,z,qw,qx,qy,qz` (poses, unit quaternion scalar
///   first, normalized when within 1e-6 of unit norm).

#include <string>
#include <vector>

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
  size_t rows() const { return lines.size(); }
  Eigen::Map<const VecX> row(size_t k) const { return {q.data() + k * static_cast<size_t>(dof), dof}; }
};

/// @param robot_dof the robot's joint count: the q columns must be as many (or none, Targets)
/// @param robot_path for the message of a wrong joint count
/// @throws RobotFileError `FILE:LINE: what` or `FILE: what`
JointTable readJointTable(const std::string& path, TableKind kind, int robot_dof, const std::string& robot_path);

/// The joint values of a TableKind::Joints file as a rows x n matrix, and the file line of each row.
/// @throws RobotFileError as readJointTable
MatX readJointValues(const std::string& path, int robot_dof, const std::string& robot_path, std::vector<long long>& lines);

}  // namespace lowpair::io
