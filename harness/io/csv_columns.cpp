// The header rule of lowpair's CSVs (csv_columns.hpp): columns by name, in any order.
#include "io/csv_columns.hpp"

#include <algorithm>
#include <cctype>
#include <unordered_map>
#include <unordered_set>

#include "io/robot_file.hpp"

namespace lowpair::io {

namespace {

// The named columns other than the joints, in CsvColumns order: target, x, y, z, qw, qx, qy, qz.
constexpr std::array<const char*, 8> kNamedColumns{"target", "x", "y", "z", "qw", "qx", "qy", "qz"};

// Notes list at most this many ignored names (then how many more).
constexpr size_t kMaxNotedNames = 10;

std::string lowerCase(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool isQDigits(const std::string& name) {
  return name.size() >= 2 && name[0] == 'q' &&
         std::all_of(name.begin() + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A name the header rule gives a meaning to, in any letter case (csvJointNames refuses these as joint names).
bool isReservedName(const std::string& name) {
  const std::string lower = lowerCase(name);
  return isQDigits(lower) ||
         std::any_of(kNamedColumns.begin(), kNamedColumns.end(), [&](const char* n) { return lower == n; });
}

}  // namespace

std::string CsvColumns::ignoredNote(const std::string& path, long long line) const {
  if (ignored.empty()) return "";
  std::string names;
  for (size_t k = 0; k < std::min(ignored.size(), kMaxNotedNames); ++k) names += (k > 0 ? ", " : "") + quotedFileText(ignored[k]);
  if (ignored.size() > kMaxNotedNames) names += " and " + std::to_string(ignored.size() - kMaxNotedNames) + " more";
  return path + ":" + std::to_string(line) + ": ignored the column" + (ignored.size() > 1 ? "s " : " ") + names +
         " (not a column lowpair reads)";
}

void CsvColumns::requireWholeGroups(const std::string& expected, const std::function<void(const std::string&)>& fail) const {
  if (!incomplete.empty()) fail("missing column '" + incomplete + "' " + expected);
}

std::vector<std::string> csvJointNames(const std::vector<std::string>& joint_names) {
  std::unordered_set<std::string> seen;
  for (const std::string& name : joint_names) {
    if (name.empty() || isReservedName(name) || !seen.insert(name).second) return {};
  }
  return joint_names;
}

std::vector<std::string> csvJointNames(const RobotFile& robot) {
  std::vector<std::string> names;
  if (robot.poe) {
    for (const Joint& j : robot.poe->joints()) names.push_back(j.name);
  } else {
    for (const DhJoint& j : robot.dh->joints()) names.push_back(j.name);
  }
  return csvJointNames(names);
}

CsvColumns findCsvColumns(const std::vector<std::string>& fields, const std::vector<std::string>& joint_names,
                          int max_joints, const std::string& expected, const std::function<void(const std::string&)>& fail) {
  std::unordered_map<std::string, size_t> joint_index, lower_names;  // name -> joint; lower-case name -> joint
  for (size_t i = 0; i < joint_names.size(); ++i) {
    joint_index.emplace(joint_names[i], i);
    lower_names.emplace(lowerCase(joint_names[i]), i);
  }
  std::vector<std::optional<size_t>> by_q, by_name(joint_names.size());  // joint -> column
  std::array<std::optional<size_t>, kNamedColumns.size()> named;        // kNamedColumns -> column
  std::unordered_set<std::string> ignored;
  std::optional<size_t> first_q, first_name;  // a column of each spelling
  CsvColumns columns;
  columns.count = fields.size();
  // the column `c` for slot `slot`, or an error naming both columns of a repeated name
  auto place = [&](std::optional<size_t>& slot, size_t c) {
    if (slot) {
      fail("column " + quotedFileText(fields[c]) + " repeats (columns " + std::to_string(*slot + 1) + " and " +
           std::to_string(c + 1) + ")");
    }
    slot = c;
  };
  for (size_t c = 0; c < fields.size(); ++c) {
    const std::string& name = fields[c];
    if (const auto it = joint_index.find(name); it != joint_index.end()) {
      place(by_name[it->second], c);
      if (!first_name) first_name = c;
      continue;
    }
    if (const auto it = std::find(kNamedColumns.begin(), kNamedColumns.end(), name); it != kNamedColumns.end()) {
      place(named[static_cast<size_t>(it - kNamedColumns.begin())], c);
      continue;
    }
    if (isQDigits(name) && name[1] != '0') {
      if (name.size() > 8 || std::stol(name.substr(1)) > max_joints) {
        fail("more than " + std::to_string(max_joints) + " joint columns");
      }
      const auto k = static_cast<size_t>(std::stol(name.substr(1)));
      if (by_q.size() < k) by_q.resize(k);
      place(by_q[k - 1], c);
      if (!first_q) first_q = c;
      continue;
    }
    if (isReservedName(name) || lower_names.count(lowerCase(name))) {
      fail("unexpected column " + quotedFileText(name) + " " + expected);  // misspelt: never ignored
    }
    if (ignored.insert(name).second) columns.ignored.push_back(name);
  }
  if (first_q && first_name) {
    fail("joint columns " + quotedFileText(fields[std::min(*first_q, *first_name)]) + " and " +
         quotedFileText(fields[std::max(*first_q, *first_name)]) + ": q1..qn or the robot's joint names, not both");
  }
  // every joint of the spelling used, each once
  const bool by_names = first_name.has_value();
  const std::vector<std::optional<size_t>>& joints = by_names ? by_name : by_q;
  for (size_t i = 0; i < joints.size(); ++i) {
    if (!joints[i]) fail("missing column " + quotedFileText(by_names ? joint_names[i] : "q" + std::to_string(i + 1)) + " " + expected);
    columns.joints.push_back(*joints[i]);
  }
  if (columns.dof() > max_joints) fail("more than " + std::to_string(max_joints) + " joint columns");
  columns.joint_names = by_names;
  // x,y,z and qw..qz: each group when it is whole; the first name missing from a partial one
  auto group = [&](size_t first, auto& out) {
    out.emplace();
    const auto size = static_cast<std::ptrdiff_t>(out->size());
    for (size_t k = 0; k < out->size(); ++k) {
      if (named[first + k]) {
        (*out)[k] = *named[first + k];
      } else {
        out.reset();
        const auto begin = named.begin() + static_cast<std::ptrdiff_t>(first);
        if (columns.incomplete.empty() && std::any_of(begin, begin + size, [](const auto& c) { return c.has_value(); })) {
          columns.incomplete = kNamedColumns[first + k];
        }
        return;
      }
    }
  };
  columns.target = named[0];
  group(1, columns.position);
  group(4, columns.quaternion);
  return columns;
}

}  // namespace lowpair::io
