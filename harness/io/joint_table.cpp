// The joint-vector and target tables (joint_table.hpp).
#include "io/joint_table.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/csv_text.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"

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
  return kind == TableKind::Joints ? "(expected q1..qn, then any columns)"
                                   : "(expected [q1..qn,]x,y,z or [q1..qn,]x,y,z,qw,qx,qy,qz)";
}

}  // namespace

JointTable readJointTable(const std::string& path, TableKind kind, int robot_dof, const std::string& robot_path) {
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
  size_t columns = 0;
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
      size_t k = 0;
      while (k < fields.size() && fields[k] == "q" + std::to_string(table.dof + 1)) {
        if (++table.dof > kMaxMeasurementJoints) fail("more than " + std::to_string(kMaxMeasurementJoints) + " joint columns");
        ++k;
      }
      if (kind == TableKind::Joints) {
        if (table.dof == 0) fail("no joint columns: the first column is " + quotedFileText(fields[0]) + " " + expectedColumns(kind));
      } else {
        static const std::array<const char*, 7> names{"x", "y", "z", "qw", "qx", "qy", "qz"};
        const size_t rest = fields.size() - k;
        if (rest != 3 && rest != 7) {
          fail(std::to_string(rest) + " columns after the joint columns " + expectedColumns(kind));
        }
        for (size_t c = 0; c < rest; ++c) {
          if (fields[k + c] != names[c]) fail("unexpected column " + quotedFileText(fields[k + c]) + " " + expectedColumns(kind));
        }
        table.pose = rest == 7;
      }
      if (table.dof != 0 || kind == TableKind::Joints) {
        if (table.dof != robot_dof) {
          fail("has " + std::to_string(table.dof) + " joint columns but " + robot_path + " has " + std::to_string(robot_dof) +
               " joints");
        }
      }
      columns = fields.size();
      have_header = true;
      continue;
    }
    if (fields.size() != columns) {
      fail("expected " + std::to_string(columns) + " fields, got " + std::to_string(fields.size()));
    }
    if (table.rows() >= static_cast<size_t>(kMaxMeasurements)) fail("more than " + std::to_string(kMaxMeasurements) + " rows");
    if (static_cast<long long>(table.rows() + 1) * table.dof > kMaxMeasurementJointValues) {
      fail("more than " + std::to_string(kMaxMeasurementJointValues) + " joint values in all (rows x joints)");
    }
    for (int i = 0; i < table.dof; ++i) table.q.push_back(number(fields[static_cast<size_t>(i)], fail));
    if (kind == TableKind::Targets) {
      const size_t x = static_cast<size_t>(table.dof);
      Pose T;
      for (int i = 0; i < 3; ++i) T.p[i] = number(fields[x + static_cast<size_t>(i)], fail);
      if (table.pose) {
        double w[4];
        for (int i = 0; i < 4; ++i) w[i] = number(fields[x + 3 + static_cast<size_t>(i)], fail);
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

MatX readJointValues(const std::string& path, int robot_dof, const std::string& robot_path, std::vector<long long>& lines) {
  JointTable table = readJointTable(path, TableKind::Joints, robot_dof, robot_path);
  lines = std::move(table.lines);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      table.q.data(), static_cast<Eigen::Index>(lines.size()), table.dof);
}

}  // namespace lowpair::io
