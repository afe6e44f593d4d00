// The joint-vector and target tables (joint_table.hpp).
#include "io/joint_table.hpp"

#include <array>
#include <functional>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/csv_columns.hpp"
#include "io/csv_text.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::io {

namespace {

// A token as a number (csv_text.hpp). @param fail throws "FILE:LINE: what"
template <class Fail>
double number(const std::string& token, const Fail& fail) {
  double x = 0.0;
  if (const std::string problem = parseCsvNumber(token, x); !problem.empty()) fail(problem);
  return x;
}

const char* expectedColumns(TableKind kind) {
  return kind == TableKind::Joints ? "(expected q1..qn or the robot's joint names, and any other columns)"
                                   : "(expected [q1..qn,]x,y,z or [q1..qn,]x,y,z,qw,qx,qy,qz)";
}

// The header's columns (csv_columns.hpp) and what a table holds: joints (Joints), or x,y,z with or without a
// quaternion and optionally joints (Targets). A measurement CSV's columns are not ignored in a joint table
// (it reads a measurement file's joints); anything else is, with a note. @param fail throws "FILE:LINE: what"
CsvColumns tableColumns(const std::vector<std::string>& fields, TableKind kind, const std::vector<std::string>& joint_names,
                        const std::function<void(const std::string&)>& fail) {
  const std::string expected = expectedColumns(kind);
  CsvColumns columns = findCsvColumns(fields, joint_names, kMaxMeasurementJoints, expected, fail);
  if (kind == TableKind::Joints) {
    if (columns.joints.empty()) fail("no joint columns " + expected);
    return columns;
  }
  columns.requireWholeGroups(expected, fail);
  if (columns.target) fail("unexpected column 'target' " + expected);
  if (!columns.position) fail("missing column 'x' " + expected);
  return columns;
}

}  // namespace

JointTable readJointTable(const std::string& path, TableKind kind, int robot_dof, const std::string& robot_path,
                          const std::vector<std::string>& joint_names) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw RobotFileError(path + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RobotFileError(path + ": cannot open file");
  JointTable table;
  table.path = path;
  CsvLineReader lines(in, path);
  auto fail = [&](const std::string& what) { throw RobotFileError(path + ":" + std::to_string(lines.number()) + ": " + what); };
  std::string line;
  std::vector<std::string> fields;
  CsvColumns columns;
  bool have_header = false;
  while (lines.next(line)) {
    if (lines.number() > kMaxMeasurementLines) {
      fail("more than " + std::to_string(kMaxMeasurementLines) + " lines (comments and blank lines count)");
    }
    if (isCsvComment(line)) {
      if (const std::string problem = readLengthUnitComment(line, table.length_unit); !problem.empty()) fail(problem);
      continue;
    }
    splitCsvFields(line, fields);
    if (!have_header) {
      columns = tableColumns(fields, kind, joint_names, fail);
      table.dof = columns.dof();
      table.pose = kind == TableKind::Targets && columns.quaternion.has_value();
      if (table.dof != 0 || kind == TableKind::Joints) {
        if (table.dof != robot_dof) {
          fail("has " + std::to_string(table.dof) + " joint columns but " + robot_path + " has " + std::to_string(robot_dof) +
               " joints");
        }
      }
      if (const std::string note = columns.ignoredNote(path, lines.number()); !note.empty()) table.notes.push_back(note);
      have_header = true;
      continue;
    }
    if (fields.size() != columns.count) {
      fail("expected " + std::to_string(columns.count) + " fields, got " + std::to_string(fields.size()));
    }
    if (table.rows() >= static_cast<size_t>(kMaxMeasurements)) fail("more than " + std::to_string(kMaxMeasurements) + " rows");
    if (static_cast<long long>(table.rows() + 1) * table.dof > kMaxMeasurementJointValues) {
      fail("more than " + std::to_string(kMaxMeasurementJointValues) + " joint values in all (rows x joints)");
    }
    for (const size_t c : columns.joints) table.q.push_back(number(fields[c], fail));
    if (kind == TableKind::Targets) {
      Pose T;
      for (int i = 0; i < 3; ++i) T.p[i] = number(fields[(*columns.position)[static_cast<size_t>(i)]], fail);
      if (table.pose) {
        double w[4];
        for (int i = 0; i < 4; ++i) w[i] = number(fields[(*columns.quaternion)[static_cast<size_t>(i)]], fail);
        double norm = 0.0;
        const std::optional<Mat3> R = unitQuaternionRotation(w[0], w[1], w[2], w[3], norm);
        if (!R) fail("qw..qz is not a unit quaternion (norm " + shortest(norm) + ")");
        T.R = *R;
      }
      table.targets.push_back(T);
    }
    table.lines.push_back(lines.number());
  }
  if (!have_header) throw RobotFileError(path + ": no header line " + expectedColumns(kind));
  if (table.rows() == 0) throw RobotFileError(path + ": no rows");
  return table;
}

std::string convertTableUnit(JointTable& table, const std::string& robot_unit, const std::string& robot_path,
                             const std::vector<bool>& prismatic) {
  if (table.length_unit.empty() || robot_unit.empty() || table.length_unit == robot_unit) return "";
  const std::optional<double> from = metresPerUnit(table.length_unit), to = metresPerUnit(robot_unit);
  if (!from || !to) {
    throw RobotFileError(table.path + ": lengths in " + table.length_unit + " (its length_unit comment) but " + robot_path + " is in " +
                         robot_unit +
                         ", and lowpair converts only m, mm, cm, dm, um, km, in, ft");
  }
  const double factor = *from / *to;
  const bool targets = !table.targets.empty();
  bool any_prismatic = false;
  for (size_t k = 0; k < table.rows(); ++k) {
    const auto beyond = [&](const std::string& what) {
      throw RobotFileError(table.path + ":" + std::to_string(table.lines[k]) + ": " + what + " is above 1e100 in " + robot_unit +
                           " after the unit conversion from " + table.length_unit);
    };
    for (int i = 0; i < table.dof && static_cast<size_t>(i) < prismatic.size(); ++i) {
      if (!prismatic[static_cast<size_t>(i)]) continue;
      any_prismatic = true;
      double& q = table.q[k * static_cast<size_t>(table.dof) + static_cast<size_t>(i)];
      q *= factor;
      if (!(std::abs(q) <= kMaxMagnitude)) beyond("q" + std::to_string(i + 1));
    }
    if (targets) {
      Vec3& p = table.targets[k].p;
      p *= factor;
      if (!(p.cwiseAbs().maxCoeff() <= kMaxMagnitude)) beyond("a position");
    }
  }
  const std::string unit_from = table.length_unit;
  table.length_unit = robot_unit;
  if (!targets && !any_prismatic) return "";  // revolute joints only: q is rad, nothing to convert
  return table.path + ": " + (targets ? "lengths" : "prismatic joint values") + " converted from " + unit_from +
         " (its length_unit comment) to " + robot_unit + " (the robot's), x " + shortest(factor);
}

std::vector<bool> prismaticJoints(const PoeModel& model) {
  std::vector<bool> out;
  for (const Joint& j : model.joints()) out.push_back(j.type == JointType::Prismatic);
  return out;
}

MatX JointTable::matrix() const {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      q.data(), static_cast<Eigen::Index>(rows()), dof);
}

}  // namespace lowpair::io
