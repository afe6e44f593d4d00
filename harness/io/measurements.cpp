// The measurement CSV (measurements.hpp): a bounded line reader, the header and number rules, the writer.
#include "io/measurements.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "lowpair/tolerances.hpp"
#include "io/csv_columns.hpp"
#include "io/csv_text.hpp"
#include "io/robot_file.hpp"

namespace lowpair::io {

namespace {

const char* const kExpectedColumns = "(expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)";

// Text from the file for a message (robot_file.hpp).
std::string quoted(const std::string& text) { return quotedFileText(text); }

// The header's columns (csv_columns.hpp) and what a measurement file holds: joints, x,y,z, then a target
// name or a quaternion, or both (mixed: a row holds one of them), or neither. @param fail throws "FILE:LINE: what"
CsvColumns measurementColumns(const std::vector<std::string>& fields, const std::vector<std::string>& joint_names,
                              const std::function<void(const std::string&)>& fail) {
  CsvColumns columns = findCsvColumns(fields, joint_names, kMaxMeasurementJoints, kExpectedColumns, fail);
  columns.requireWholeGroups(kExpectedColumns, fail);
  if (columns.joints.empty()) fail(std::string("no joint columns ") + kExpectedColumns);
  if (!columns.position) fail(std::string("missing column 'x' ") + kExpectedColumns);
  return columns;
}

// The sign columns of a header (`s1..sn`, `s_<joint name>`): per joint its field index, taken out of the ignored names.
std::vector<std::optional<size_t>> signColumns(const std::vector<std::string>& fields, const std::vector<std::string>& joint_names,
                                               CsvColumns& columns, const std::function<void(const std::string&)>& fail) {
  const int n = columns.dof();
  std::vector<std::optional<size_t>> signs(static_cast<size_t>(n));
  for (size_t f = 0; f < fields.size(); ++f) {
    const std::string& name = fields[f];
    int joint = -1;
    for (int i = 0; i < n && joint < 0; ++i) {
      const bool by_index = name == "s" + std::to_string(i + 1);
      const bool by_name = static_cast<size_t>(i) < joint_names.size() && name == "s_" + joint_names[static_cast<size_t>(i)];
      if (by_index || by_name) joint = i;
    }
    if (joint < 0) continue;
    if (signs[static_cast<size_t>(joint)]) fail("two sign columns for joint " + std::to_string(joint + 1) + " (" + quotedFileText(name) + ")");
    signs[static_cast<size_t>(joint)] = f;
    columns.ignored.erase(std::remove(columns.ignored.begin(), columns.ignored.end(), name), columns.ignored.end());
  }
  return signs;
}

Measure measureOf(const CsvColumns& columns) {
  return columns.target ? Measure::Targets : columns.quaternion ? Measure::Pose : Measure::Position;
}

// A token as a number (csv_text.hpp). @param fail throws "FILE:LINE: what"
template <class Fail>
double parseNumber(const std::string& token, const Fail& fail) {
  double x = 0.0;
  if (const std::string problem = parseCsvNumber(token, x); !problem.empty()) fail(problem);
  return x;
}

// The names formatMeasurements writes: for Targets, names readMeasurements reads back as they are (valid,
// distinct, at most kMaxTargets); for the other measures, none.
void checkTargetNames(Measure measure, const std::vector<std::string>& target_names) {
  if (measure != Measure::Targets) {
    if (!target_names.empty()) {
      throw std::invalid_argument(std::string("formatMeasurements: target names for ") + measureName(measure) +
                                  " measurements");
    }
    return;
  }
  if (target_names.size() > static_cast<size_t>(kMaxTargets)) {
    throw std::invalid_argument("formatMeasurements: " + std::to_string(target_names.size()) + " target names, at most " +
                                std::to_string(kMaxTargets));
  }
  std::unordered_set<std::string> seen;
  for (const std::string& name : target_names) {
    if (const std::string problem = targetNameProblem(name); !problem.empty()) {
      throw std::invalid_argument("formatMeasurements: target name " + quoted(name) + " " + problem);
    }
    if (!seen.insert(name).second) throw std::invalid_argument("formatMeasurements: target name " + quoted(name) + " repeats");
  }
}

void appendNumber(std::string& out, double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 17);  // %.17g
  out.append(buffer, result.ptr);
}

}  // namespace

std::optional<Mat3> unitQuaternionRotation(double w, double x, double y, double z, double& norm) {
  const Eigen::Quaterniond quaternion(w, x, y, z);
  norm = quaternion.norm();
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) return std::nullopt;
  return quaternion.normalized().toRotationMatrix();
}

Eigen::Vector4d csvQuaternion(const Mat3& R) {
  Eigen::Quaterniond quaternion(R);
  quaternion.normalize();
  if (quaternion.w() < 0) quaternion.coeffs() *= -1.0;
  return {quaternion.w(), quaternion.x(), quaternion.y(), quaternion.z()};
}

int TargetNumbering::number(const std::string& name, std::string& problem) {
  if (const auto it = indices.find(name); it != indices.end()) return it->second;
  problem = targetNameProblem(name);
  if (!problem.empty() || names.size() >= static_cast<size_t>(kMaxTargets)) return -1;
  const int k = static_cast<int>(names.size());
  names.push_back(name);
  indices.emplace(name, k);
  return k;
}

bool isUnitLabel(const std::string& unit) {
  return !unit.empty() && unit.size() <= 16 && std::all_of(unit.begin(), unit.end(), [](char c) { return c > ' ' && c < 127; });
}

MeasurementFile readMeasurements(const std::string& path, const MeasurementHeaderCheck& check_header,
                                 const std::vector<std::string>& joint_names) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw RobotFileError(path + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw RobotFileError(path + ": cannot open file");

  MeasurementFile file;
  file.path = path;
  CsvLineReader lines(in, path);
  auto fail = [&](const std::string& what) {
    throw RobotFileError(path + ":" + std::to_string(lines.number()) + ": " + what);
  };
  std::string line;
  std::vector<std::string> fields;
  bool have_header = false;
  CsvColumns columns;
  std::vector<std::optional<size_t>> sign_columns;  // per joint
  TargetNumbering targets;  // the target column's names, numbered
  while (lines.next(line)) {
    if (lines.number() > kMaxMeasurementLines) {
      fail("more than " + std::to_string(kMaxMeasurementLines) + " lines (comments and blank lines count)");
    }
    if (isCsvComment(line)) {
      if (const std::string problem = readLengthUnitComment(line, file.length_unit); !problem.empty()) fail(problem);
      continue;
    }
    splitCsvFields(line, fields);
    if (!have_header) {
      columns = measurementColumns(fields, joint_names, fail);
      sign_columns = signColumns(fields, joint_names, columns, fail);
      file.dof = columns.dof();
      for (const auto& c : sign_columns) {
        if (c) file.sign_columns.assign(sign_columns.size(), false);
      }
      for (size_t i = 0; i < file.sign_columns.size(); ++i) file.sign_columns[i] = sign_columns[i].has_value();
      file.measure = measureOf(columns);
      if (const std::string note = columns.ignoredNote(path, lines.number()); !note.empty()) file.notes.push_back(note);
      have_header = true;
      if (check_header) check_header(file);
      continue;
    }
    if (fields.size() != columns.count) {
      fail("expected " + std::to_string(columns.count) +
           (columns.target || !columns.ignored.empty() ? " fields" : " numbers") + ", got " + std::to_string(fields.size()));
    }
    if (file.measurements.size() >= static_cast<size_t>(kMaxMeasurements)) {
      fail("more than " + std::to_string(kMaxMeasurements) + " measurements");
    }
    if (static_cast<long long>(file.measurements.size() + 1) * columns.dof() > kMaxMeasurementJointValues) {
      fail("more than " + std::to_string(kMaxMeasurementJointValues) + " joint values in all (measurements x joints)");
    }
    Measurement m;
    const int n = columns.dof();
    m.q.resize(n);
    for (int i = 0; i < n; ++i) m.q[i] = parseNumber(fields[columns.joints[static_cast<size_t>(i)]], fail);
    // mixed data (both a target and a quaternion column): an empty target is a pose of the tool frame, whose
    // qw..qz are given; a target row leaves them empty
    const bool mixed = columns.target && columns.quaternion;
    bool pose_row = !columns.target && columns.quaternion;
    if (columns.target) {
      const std::string& name = fields[*columns.target];
      pose_row = mixed && name.empty();  // (fields are trimmed)
      if (pose_row) {
        m.target = kPoseMeasurement;
      } else {
        std::string problem;
        m.target = targets.number(name, problem);
        if (m.target < 0) {
          fail(problem.empty() ? "more than " + std::to_string(kMaxTargets) + " distinct target names"
                               : "target " + quoted(name) + " " + problem + " (" + kTargetNameRule + ")");
        }
      }
    }
    if (mixed && !pose_row) {
      for (const size_t c : *columns.quaternion) {
        if (!fields[c].empty()) {
          fail("a target's row leaves qw,qx,qy,qz empty (a row with an empty target is a pose of the tool frame)");
        }
      }
    }
    for (int i = 0; i < 3; ++i) m.T_base_tool.p[i] = parseNumber(fields[(*columns.position)[static_cast<size_t>(i)]], fail);
    if (pose_row) {
      double w[4];
      for (int i = 0; i < 4; ++i) w[i] = parseNumber(fields[(*columns.quaternion)[static_cast<size_t>(i)]], fail);
      double norm = 0.0;
      const std::optional<Mat3> R = unitQuaternionRotation(w[0], w[1], w[2], w[3], norm);
      if (!R) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", norm);
        fail(std::string("qw..qz is not a unit quaternion (norm ") + text + ")");
      }
      m.T_base_tool.R = *R;
    }
    if (!file.sign_columns.empty()) {
      VecX s = VecX::Zero(n);
      for (int i = 0; i < n; ++i) {
        if (!sign_columns[static_cast<size_t>(i)]) continue;
        const std::string& token = fields[*sign_columns[static_cast<size_t>(i)]];
        s[i] = parseNumber(token, fail);
        if (s[i] != -1.0 && s[i] != 0.0 && s[i] != 1.0) {
          fail("joint " + std::to_string(i + 1) + "'s sign " + quoted(token) + " is not -1, 0 or 1 (the sign of its last move)");
        }
      }
      file.signs.push_back(std::move(s));
    }
    file.measurements.push_back(std::move(m));
    file.lines.push_back(lines.number());
  }
  if (!have_header) throw RobotFileError(path + ": no header line " + kExpectedColumns);
  if (file.measurements.empty()) throw RobotFileError(path + ": no measurements");
  file.target_names = std::move(targets.names);
  return file;
}

MeasurementWriter::MeasurementWriter(std::ostream& out, Measure measure, Eigen::Index dof,
                                     const std::vector<std::string>& target_names, bool mixed)
    : out_(out), measure_(measure), dof_(dof), target_names_(target_names), mixed_(mixed && measure == Measure::Targets) {
  checkTargetNames(measure, target_names);
}

void MeasurementWriter::writeHeader(const std::vector<std::string>& comments) {
  std::string text;
  for (const std::string& comment : comments) {
    size_t begin = 0;
    while (true) {  // one "# " line per line of the comment
      const size_t end = std::min(comment.find('\n', begin), comment.size());
      std::string line = comment.substr(begin, end - begin);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      text += line.empty() ? "#\n" : "# " + line + "\n";
      if (end == comment.size()) break;
      begin = end + 1;
    }
  }
  for (Eigen::Index i = 0; i < dof_; ++i) text += "q" + std::to_string(i + 1) + ",";
  text += measure_ == Measure::Pose        ? "x,y,z,qw,qx,qy,qz\n"
          : mixed_                         ? "target,x,y,z,qw,qx,qy,qz\n"
          : measure_ == Measure::Targets   ? "target,x,y,z\n"
                                           : "x,y,z\n";
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
}

bool MeasurementWriter::poseRow(int target) const {
  return measure_ == Measure::Pose || (measure_ == Measure::Targets && target == kPoseMeasurement);
}

void MeasurementWriter::checkRow(Eigen::Index dof, int target) const {
  if (dof != dof_) {
    throw std::invalid_argument("formatMeasurements: joint vectors of " + std::to_string(dof_) + " and " +
                                std::to_string(dof) + " values");
  }
  if (measure_ == Measure::Targets && !poseRow(target) && (target < 0 || static_cast<size_t>(target) >= target_names_.size())) {
    throw std::invalid_argument("formatMeasurements: target " + std::to_string(target) + " of " +
                                std::to_string(target_names_.size()) + " target names");
  }
}

void MeasurementWriter::write(const Eigen::Ref<const VecX>& q, const Pose& T, int target) {
  checkRow(q.size(), target);
  row_.clear();
  for (Eigen::Index i = 0; i < dof_; ++i) {
    appendNumber(row_, q[i]);
    row_ += ',';
  }
  const bool pose_row = poseRow(target);
  if (measure_ == Measure::Targets && pose_row) {
    row_ += ',';
  } else if (measure_ == Measure::Targets) {
    row_ += target_names_[static_cast<size_t>(target)] + ',';
  }
  for (int i = 0; i < 3; ++i) {
    if (i > 0) row_ += ',';
    appendNumber(row_, T.p[i]);
  }
  if (pose_row) {
    const Eigen::Vector4d quaternion = csvQuaternion(T.R);
    for (int i = 0; i < 4; ++i) {
      row_ += ',';
      appendNumber(row_, quaternion[i]);
    }
  } else if (mixed_) {
    row_ += ",,,";  // a target's row: qw..qz empty
    row_ += ',';
  }
  row_ += '\n';
  out_.write(row_.data(), static_cast<std::streamsize>(row_.size()));
}

std::string formatMeasurements(Measure measure, const std::vector<Measurement>& measurements,
                               const std::vector<std::string>& comments, const std::vector<std::string>& target_names) {
  std::ostringstream out;
  writeMeasurements(out, measure, measurements, comments, target_names);
  return std::move(out).str();
}

void writeMeasurements(std::ostream& out, Measure measure, const std::vector<Measurement>& measurements,
                       const std::vector<std::string>& comments, const std::vector<std::string>& target_names) {
  if (measurements.empty()) throw std::invalid_argument("formatMeasurements: no measurements");
  // target measurements with poses of the tool frame among them (mixed): both columns, each row one of them
  const bool mixed = measure == Measure::Targets &&
                     std::any_of(measurements.begin(), measurements.end(),
                                 [](const Measurement& m) { return m.target == kPoseMeasurement; });
  MeasurementWriter writer(out, measure, measurements.front().q.size(), target_names, mixed);
  for (const Measurement& m : measurements) writer.checkRow(m.q.size(), m.target);  // every row, before a byte
  writer.writeHeader(comments);
  for (const Measurement& m : measurements) writer.write(m);
}

}  // namespace lowpair::io
