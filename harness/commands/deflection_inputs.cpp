// --compliance and --backlash of calibrate and identifiability (deflection_inputs.hpp).
#include "commands/deflection_inputs.hpp"

#include <algorithm>
#include <stdexcept>

#include "io/output.hpp"

namespace lowpair::commands {

namespace {

std::string trimmed(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t") - begin + 1);
}

// The joint a list item names: a 1-based index or a joint name; -1 for none.
int namedJoint(const std::string& item, const PoeModel& model) {
  for (int i = 0; i < model.dof(); ++i) {
    if (!model.joint(i).name.empty() && item == model.joint(i).name) return i;
  }
  if (item.empty() || item.size() > 9 || !std::all_of(item.begin(), item.end(), [](char c) { return c >= '0' && c <= '9'; })) return -1;
  const int k = std::stoi(item);
  return k >= 1 && k <= model.dof() ? k - 1 : -1;
}

}  // namespace

std::vector<int> parseJointList(const std::string& text, const PoeModel& model, const std::string& option,
                                const ArgumentSpelling& spelling, bool* all) {
  const std::string name = spelling.name(option);
  if (trimmed(text) == "all" && all) {
    *all = true;
    std::vector<int> every(static_cast<size_t>(model.dof()));
    for (int i = 0; i < model.dof(); ++i) every[static_cast<size_t>(i)] = i;
    return every;
  }
  std::vector<int> joints;
  size_t begin = 0;
  while (true) {
    const size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = trimmed(text.substr(begin, end - begin));
    const int j = namedJoint(item, model);
    if (j < 0) {
      throw UsageError(name, io::quotedFileText(item) + " is no joint of the robot (1-based indices 1.." + std::to_string(model.dof()) +
                                 " or joint names" + (all ? ", or all" : "") + ")");
    }
    if (std::find(joints.begin(), joints.end(), j) != joints.end()) {
      throw UsageError(name, "joint " + std::to_string(j + 1) + " is named twice");
    }
    joints.push_back(j);
    if (end == text.size()) break;
    begin = end + 1;
  }
  std::sort(joints.begin(), joints.end());
  return joints;
}

DeflectionChoice chooseDeflections(const io::RobotFile& nominal_file, const PoeModel& nominal,
                                   const std::optional<std::string>& compliance, const std::optional<std::string>& backlash,
                                   const std::vector<Measurement>& measurements, const std::vector<bool>& sign_columns,
                                   const std::vector<VecX>& signs, const std::string& data, CalibrationOptions& options,
                                   const ArgumentSpelling& spelling) {
  DeflectionChoice choice;
  bool all = false;
  if (compliance) choice.compliance = parseJointList(*compliance, nominal, "compliance", spelling, &all);
  if (backlash) choice.backlash = parseJointList(*backlash, nominal, "backlash", spelling);
  if (!choice.compliance.empty() && !nominal_file.masses) {
    throw UsageError(spelling.name("compliance"),
                     nominal_file.path + " states no masses (per joint mass and com, payload:, gravity:; "
                                         "docs/file_formats.md): there is no gravity load to be compliant under");
  }
  options.masses = nominal_file.masses.value_or(MassModel{});
  options.deflection = nominal_file.deflection;
  options.compliance_joints = choice.compliance;
  options.backlash_joints = choice.backlash;
  if (!options.deflects()) return choice;
  options.move_signs = measurementMoveSigns(measurements, choice.backlash, sign_columns, signs);
  for (const int j : choice.backlash) {
    choice.sign_from_column.push_back(static_cast<size_t>(j) < sign_columns.size() && sign_columns[static_cast<size_t>(j)]);
  }
  const std::vector<PoseLoad> loads = measurementLoads(nominal, measurements, options);
  // each kind's joints against the inputs; `all` keeps the joints whose load varies
  auto check = [&](const std::vector<int>& joints, bool is_compliance) {
    ErrorModelSpec spec;
    (is_compliance ? spec.compliance_joints : spec.backlash_joints) = joints;
    checkDeflections(nominal, spec, loads);
  };
  if (all) {
    std::vector<int> varying;
    for (const int j : choice.compliance) {
      try {
        check({j}, true);
        varying.push_back(j);
      } catch (const std::invalid_argument&) {
        choice.rigid.push_back(j);
      }
    }
    choice.compliance = varying;
    options.compliance_joints = varying;
  }
  try {
    check(choice.compliance, true);
  } catch (const std::invalid_argument& e) {
    throw UsageError(spelling.name("compliance"), data + ": " + e.what());
  }
  try {
    check(choice.backlash, false);
  } catch (const std::invalid_argument& e) {
    throw UsageError(spelling.name("backlash"), data + ": " + e.what());
  }
  return choice;
}

std::vector<VecX> measurementMoveSigns(const std::vector<Measurement>& measurements, const std::vector<int>& backlash,
                                       const std::vector<bool>& sign_columns, const std::vector<VecX>& signs) {
  std::vector<VecX> q;
  for (const Measurement& m : measurements) q.push_back(m.q);
  std::vector<VecX> out = moveSigns(q);
  for (const int j : backlash) {
    if (static_cast<size_t>(j) >= sign_columns.size() || !sign_columns[static_cast<size_t>(j)]) continue;
    for (size_t k = 0; k < q.size(); ++k) out[k][j] = signs[k][j];
  }
  return out;
}

bool appliesCompliance(const io::RobotFile& file) {
  return file.masses.has_value() && file.deflection.compliance.size() > 0 && file.deflection.compliance.any();
}

namespace {

bool holdsBacklash(const io::RobotFile& file) { return file.deflection.backlash.size() > 0 && file.deflection.backlash.any(); }

}  // namespace

JointDeflection appliedDeflection(const io::RobotFile& file, bool with_backlash) {
  JointDeflection d;
  if (appliesCompliance(file)) d.compliance = file.deflection.compliance;
  if (with_backlash && holdsBacklash(file)) d.backlash = file.deflection.backlash;
  return d;
}

VecX standingJoints(const io::RobotFile& file, const PoeModel& model, const VecX& q, const VecX& sign) {
  const JointDeflection d = appliedDeflection(file, sign.size() > 0);
  if (d.empty()) return q;
  PoseLoad load;
  if (d.compliance.size() > 0) load.torque = gravityTorques(model, *file.masses, q);
  load.sign = sign;
  return deflectedJoints(d, q, load);
}

std::vector<VecX> approachSigns(const std::string& text, const std::vector<VecX>& rows, int dof, bool one_row,
                                const ArgumentSpelling& spelling) {
  const std::string option = spelling.name("approach");
  if (text.empty()) return {};
  if (trimmed(text) == "order") {
    if (one_row) throw UsageError(option, "'order' needs rows of joint values (--q-file): one q has no move before it");
    return moveSigns(rows);
  }
  VecX s(dof);
  size_t begin = 0;
  for (int i = 0; i < dof; ++i) {
    const size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = trimmed(text.substr(begin, end - begin));
    if (item != "-1" && item != "0" && item != "1" && item != "+1") {
      throw UsageError(option, "expected 'order' or " + std::to_string(dof) + " signs -1, 0 or 1 (one per joint), got " +
                                   io::quotedFileText(text));
    }
    s[i] = std::stod(item);
    if (end == text.size() && i + 1 < dof) {
      throw UsageError(option, std::to_string(i + 1) + " signs for " + std::to_string(dof) + " joints");
    }
    begin = end + 1;
  }
  if (begin <= text.size()) throw UsageError(option, "more than " + std::to_string(dof) + " signs for " + std::to_string(dof) + " joints");
  return std::vector<VecX>(rows.size(), s);
}

std::string deflectionNote(const io::RobotFile& file, bool approach) {
  std::string note;
  if (appliesCompliance(file)) note = file.path + ": compliance applied (the joints stand at q + c tau(q) under the file's masses)";
  if (file.deflection.compliance.size() > 0 && file.deflection.compliance.any() && !file.masses) {
    note = file.path + ": compliance not applied: the file states no masses";
  }
  if (holdsBacklash(file)) {
    note += std::string(note.empty() ? file.path + ": " : "; ") +
            (approach ? "backlash applied (b s, s from --approach)" : "backlash not applied (it needs the approach direction of each joint: --approach)");
  }
  return note;
}

ErrorModelSpec deflectionSpec(const CalibrationOptions& options) {
  ErrorModelSpec spec;
  spec.compliance_joints = options.compliance_joints;
  spec.backlash_joints = options.backlash_joints;
  spec.deflection = options.deflection;
  return spec;
}

}  // namespace lowpair::commands
