#include "io/robot_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "lowpair/convert.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "io/robot_file_loads.hpp"
#include "io/yaml_reader.hpp"

namespace lowpair::io {

std::string targetPointProblem(const Vec3& p) {
  if (!p.allFinite()) return "is not finite";
  const double norm = p.norm();  // (inf for coordinates near the double range: refused too)
  if (!(norm <= kMaxMagnitude)) {
    std::ostringstream out;
    out << "has magnitude " << norm << ", above 1e100 (kMaxMagnitude)";
    return out.str();
  }
  return "";
}

std::string targetNameProblem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxTargetNameBytes) {
    return "has " + std::to_string(name.size()) + " characters (at most " + std::to_string(kMaxTargetNameBytes) + ")";
  }
  for (const char ch : name) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == ' ') return "holds a space";
    if (c == ',') return "holds a comma";
    if (c == '"' || c == '\'') return "holds a quote";
    if (c < 0x20 || c >= 0x7f) return "holds a byte outside printable ASCII";
  }
  return "";
}

std::string quotedFileText(const std::string& text) {
  constexpr size_t kMaxQuoted = 40;
  std::string out = "'";
  for (size_t i = 0; i < text.size() && i < kMaxQuoted; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?';
  }
  if (text.size() > kMaxQuoted) out += "...";
  return out + "'";
}

std::optional<double> metresPerUnit(const std::string& length_unit) {
  static const std::pair<const char*, double> kUnits[] = {{"m", 1.0},   {"mm", 1e-3}, {"cm", 1e-2},   {"dm", 1e-1},
                                                          {"um", 1e-6}, {"km", 1e3},  {"in", 0.0254}, {"ft", 0.3048}};
  for (const auto& [name, metres] : kUnits) {
    if (length_unit == name) return metres;
  }
  return std::nullopt;
}

RobotFile inUnit(const RobotFile& file, const std::string& unit) {
  const std::optional<double> f_file = metresPerUnit(file.length_unit);
  if (!f_file) {
    throw RobotFileError(file.path + ": " +
                         (file.length_unit.empty() ? std::string("states no length_unit")
                                                   : "length_unit '" + file.length_unit + "' is not one lowpair converts") +
                         ": give length_unit (m, mm, cm, dm, um, km, in or ft) to write lengths in " + unit);
  }
  const std::optional<double> f_unit = metresPerUnit(unit);
  if (!f_unit) throw RobotFileError("'" + unit + "' is not a length unit lowpair converts (m, mm, cm, dm, um, km, in, ft)");
  const double f = *f_file / *f_unit;
  const PoeModel model = file.poeModel();
  std::vector<Joint> joints = model.joints();
  for (Joint& j : joints) {
    if (j.type == JointType::Prismatic) {
      j.scale *= f;  // x [unit] = f scale (q + offset): q keeps its unit
    } else {
      j.twist.tail<3>() *= f;
      j.pitch *= f;
    }
  }
  Pose tool = model.toolPose();
  tool.p *= f;
  RobotFile out = file;
  for (Target& t : out.targets) {
    if (!t.point_tool) continue;
    *t.point_tool *= f;
    const std::string problem = targetPointProblem(*t.point_tool);
    if (!problem.empty()) {
      throw RobotFileError(file.path + ": target " + quotedFileText(t.name) + ": point in " + unit + " " + problem);
    }
  }
  if (out.measurement_frame) out.measurement_frame->p *= f;
  scaleLoads(out, f);
  out.length_unit = unit;
  out.dh.reset();
  out.poe = PoeModel(std::move(joints), tool, model.name());
  return out;
}

RobotFile inMetres(const RobotFile& file) { return inUnit(file, "m"); }

double RobotFile::angleFactor() const { return angle_unit == "deg" ? M_PI / 180.0 : 1.0; }

PoeModel RobotFile::poeModel() const { return poe ? *poe : dhToPoe(*dh); }

void requireBoundedModelFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status) || fs::is_directory(status)) return;  // the readers name these themselves
  if (!fs::is_regular_file(status)) {
    throw RobotFileError(path + ": not a regular file (a FIFO, device or socket is not read as a model file)");
  }
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (ec) throw RobotFileError(path + ": cannot read file: " + ec.message());
  if (bytes > kMaxModelFileBytes) {
    throw RobotFileError(path + ": " + std::to_string(bytes) + " bytes: over the " +
                         std::to_string(kMaxModelFileBytes >> 20) + " MiB a model file may have");
  }
}

void requireJointCount(const std::string& path, size_t joints) {
  if (joints > static_cast<size_t>(kMaxJoints)) {
    throw RobotFileError(path + ": " + std::to_string(joints) + " joints, more than the " + std::to_string(kMaxJoints) +
                         " a robot may have");
  }
}

YAML::Node loadYamlFile(const std::string& path) {
  // a directory opens as a stream on Linux and fails inside yaml-cpp with a raw ios message (and a leak)
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw RobotFileError(path + ": is a directory, not a file");
  requireBoundedModelFile(path);
  if (!std::ifstream(path)) throw RobotFileError(path + ": cannot open file");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw RobotFileError(path + ": line " + std::to_string(e.mark.line + 1) + ", column " +
                         std::to_string(e.mark.column + 1) + ": YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw RobotFileError(path + ": " + e.what());
  }
}

namespace {

// A target's `normal:` (x, y, z in the tool frame): finite, nonzero, returned normalised.
Vec3 readTargetNormal(const YamlReader& in, const YAML::Node& node, const std::string& where) {
  const auto n = in.vector(node, 3, where);
  const Vec3 v(n[0], n[1], n[2]);
  const double norm = v.stableNorm();  // scaled: a subnormal or a huge vector keeps its direction
  if (!v.allFinite() || !(norm > 0.0) || !std::isfinite(norm) || !(v / norm).allFinite()) {
    yamlError(in.path(), node, where + " must be a finite nonzero direction (x, y, z in the tool frame)");
  }
  return v / norm;
}

// `targets:`, a list of {name, point, known, normal} (docs/file_formats.md); the normals in `normals`.
std::vector<Target> readTargets(const YamlReader& in, const YAML::Node& list, std::vector<std::optional<Vec3>>& normals) {
  const std::string& path = in.path();
  if (!list.IsSequence()) yamlError(path, list, "targets must be a list of {name: N, point: [x, y, z]}");
  if (list.size() > static_cast<size_t>(kMaxTargets)) {
    yamlError(path, list, "targets: " + std::to_string(list.size()) + " targets, at most " + std::to_string(kMaxTargets));
  }
  std::vector<Target> targets;
  std::map<std::string, size_t> first;  // name -> index
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node t = list[i];
    const std::string where = "targets[" + std::to_string(i) + "]";
    in.allowOnly(t, where, {"name", "point", "known", "normal"});
    if (!t["name"]) yamlError(path, t, where + ": missing 'name'");
    if (!t["point"]) yamlError(path, t, where + ": missing 'point' (x, y, z in the tool frame)");
    Target target;
    target.name = in.string(t["name"], where + ".name");
    const std::string problem = targetNameProblem(target.name);
    if (!problem.empty()) {
      yamlError(path, t["name"], where + ".name " + quotedFileText(target.name) + " " + problem + " (" + kTargetNameRule + ")");
    }
    if (const auto [it, added] = first.emplace(target.name, i); !added) {
      yamlError(path, t["name"], where + ".name " + quotedFileText(target.name) + " repeats targets[" +
                                     std::to_string(it->second) + "]'s");
    }
    const auto p = in.vector(t["point"], 3, where + ".point");
    target.point_tool = Vec3(p[0], p[1], p[2]);
    const std::string point_problem = targetPointProblem(*target.point_tool);
    if (!point_problem.empty()) yamlError(path, t["point"], where + ".point " + point_problem);
    if (t["known"]) target.known = in.boolean(t["known"], where + ".known");
    normals.push_back(t["normal"] ? std::optional<Vec3>(readTargetNormal(in, t["normal"], where + ".normal")) : std::nullopt);
    targets.push_back(std::move(target));
  }
  return targets;
}

}  // namespace

namespace {

// The `dh:` section: base, joints (a row with `beta` is a Hayati row) and tool; angles times k (deg -> rad).
DhModel readDhSection(YamlReader& in, const std::string& path, const YAML::Node& dh, double k, const std::string& name,
                      std::vector<JointLoadKeys>& load_keys) {
  in.allowOnly(dh, "dh", {"base", "joints", "tool"});
  auto params = [&](const YAML::Node& node, const std::string& where) {
    DhParams r;
    r.theta = in.numberOr(node, "theta", 0.0, where) * k;
    r.d = in.numberOr(node, "d", 0.0, where);
    r.alpha = in.numberOr(node, "alpha", 0.0, where) * k;
    r.a = in.numberOr(node, "a", 0.0, where);
    // beta: a Hayati row Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta) (conventions.md, "Hayati rows")
    if (node["beta"]) {
      r.kind = DhRowKind::Hayati;
      r.beta = in.number(node["beta"], where + ".beta") * k;
    }
    return r;
  };
  DhParams base;
  if (dh["base"]) {
    in.allowOnly(dh["base"], "dh.base", {"theta", "d", "alpha", "a", "beta"});
    base = params(dh["base"], "dh.base");
  }
  const YAML::Node joints = dh["joints"];
  if (!joints.IsDefined() || !joints.IsSequence() || joints.size() == 0) {
    yamlError(path, joints.IsDefined() ? joints : dh, "dh.joints must be a non-empty list");
  }
  requireJointCount(path, joints.size());
  std::vector<DhJoint> list;
  for (size_t i = 0; i < joints.size(); ++i) {
    const YAML::Node j = joints[i];
    const std::string where = "dh.joints[" + std::to_string(i) + "]";
    std::set<std::string> keys = {"name", "type", "theta", "d", "alpha", "a", "beta", "pitch", "scale", "range"};
    keys.insert(kJointLoadKeys.begin(), kJointLoadKeys.end());
    in.allowOnly(j, where, keys);
    DhJoint dj;
    if (j["name"]) dj.name = in.string(j["name"], where + ".name");
    const auto type = in.type(j["type"], where + ".type");
    if (!type) yamlError(path, j, where + ": missing 'type' (revolute, prismatic or helical)");
    dj.type = *type;
    dj.link = params(j, where);
    if (j["pitch"]) {
      if (dj.type != JointType::Helical) {
        yamlError(path, j["pitch"], where + ": 'pitch' is only for helical joints (this one is " +
                                   jointTypeName(dj.type) + ")");
      }
      dj.pitch = in.number(j["pitch"], where + ".pitch") / k;  // length per angle_unit -> per rad
    }
    dj.scale = in.numberOr(j, "scale", 1.0, where);
    if (!(dj.scale > 0.0)) yamlError(path, j["scale"], where + ".scale must be positive");
    dj.range = in.range(j["range"], where + ".range", dj.type == JointType::Prismatic ? 1.0 : k);
    load_keys.push_back(readJointLoadKeys(in, j, where, dj.type == JointType::Prismatic ? 1.0 : k));
    list.push_back(dj);
  }
  double tool_theta = 0.0, tool_d = 0.0;
  if (dh["tool"]) {
    in.allowOnly(dh["tool"], "dh.tool", {"theta", "d"});
    tool_theta = in.numberOr(dh["tool"], "theta", 0.0, "dh.tool") * k;
    tool_d = in.numberOr(dh["tool"], "d", 0.0, "dh.tool");
  }
  return DhModel(base, std::move(list), tool_theta, tool_d, name);
}

}  // namespace

RobotFile readRobotFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path);
  YamlReader in(path);
  if (!root.IsMap()) yamlError(path, root, "a robot file must be a mapping with 'poe:' or 'dh:'");
  // 4 rows of 4 numbers, the last [0, 0, 0, 1] (poe.tool_pose, measurement_frame)
  auto readPoseRows = [&](const YAML::Node& node, const std::string& key) {
    if (!node.IsSequence() || node.size() != 4) yamlError(path, node, key + " must be 4 rows of 4 numbers");
    Mat4 T;
    for (int r = 0; r < 4; ++r) {
      const auto row = in.vector(node[r], 4, key + "[" + std::to_string(r) + "]");
      for (int c = 0; c < 4; ++c) T(r, c) = row[static_cast<size_t>(c)];
    }
    if (T(3, 0) != 0.0 || T(3, 1) != 0.0 || T(3, 2) != 0.0 || T(3, 3) != 1.0) {
      yamlError(path, node, key + ": the last row must be [0, 0, 0, 1]");
    }
    return Pose::fromMatrix(T);
  };
  in.allowOnly(root, "the robot file", {"name", "length_unit", "angle_unit", "description", "poe", "dh", "targets",
                                       "measurement_frame", "tool_frame", "payload", "gravity"});

  RobotFile file;
  file.path = path;
  if (root["name"]) file.name = in.string(root["name"], "name");
  if (root["length_unit"]) file.length_unit = in.string(root["length_unit"], "length_unit");
  if (root["description"]) file.description = in.string(root["description"], "description");
  if (root["angle_unit"]) {
    file.angle_unit = in.string(root["angle_unit"], "angle_unit");
    if (file.angle_unit != "rad" && file.angle_unit != "deg") {
      yamlError(path, root["angle_unit"], "angle_unit must be rad or deg, got '" + file.angle_unit + "'");
    }
  }
  const double k = file.angleFactor();
  const bool has_poe = root["poe"].IsDefined(), has_dh = root["dh"].IsDefined();
  if (has_poe == has_dh) yamlError(path, root, "a robot file needs exactly one of 'poe:' and 'dh:'");

  std::vector<JointLoadKeys> load_keys;
  try {
    if (has_poe) {
      const YAML::Node poe = root["poe"];
      in.allowOnly(poe, "poe", {"joints", "tool", "tool_pose"});
      const YAML::Node joints = poe["joints"];
      if (!joints.IsDefined() || !joints.IsSequence() || joints.size() == 0) {
        yamlError(path, joints.IsDefined() ? joints : poe, "poe.joints must be a non-empty list");
      }
      requireJointCount(path, joints.size());
      std::vector<JointSpec> specs;
      for (size_t i = 0; i < joints.size(); ++i) {  // (load_keys: the masses' and deflections' keys, per joint)
        const YAML::Node j = joints[i];
        const std::string where = "poe.joints[" + std::to_string(i) + "]";
        std::set<std::string> keys = {"name", "type", "twist", "offset", "range"};
        keys.insert(kJointLoadKeys.begin(), kJointLoadKeys.end());
        in.allowOnly(j, where, keys);
        if (!j["twist"]) yamlError(path, j, where + ": missing 'twist'");
        JointSpec spec;
        if (j["name"]) spec.name = in.string(j["name"], where + ".name");
        spec.type = in.type(j["type"], where + ".type");
        const auto t = in.vector(j["twist"], 6, where + ".twist");
        spec.twist = Eigen::Map<const Vec6>(t.data());
        const bool prismatic = spec.twist.head<3>().isZero(0.0);
        const double unit = prismatic ? 1.0 : k;
        spec.offset = in.numberOr(j, "offset", 0.0, where) * unit;
        spec.range = in.range(j["range"], where + ".range", unit);
        load_keys.push_back(readJointLoadKeys(in, j, where, unit));
        specs.push_back(spec);
      }
      if (poe["tool"] && poe["tool_pose"]) yamlError(path, poe, "give either poe.tool (a twist) or poe.tool_pose, not both");
      Pose tool;
      if (poe["tool"]) {
        const auto t = in.vector(poe["tool"], 6, "poe.tool");
        tool = expSE3(Eigen::Map<const Vec6>(t.data()));
      } else if (poe["tool_pose"]) {
        const YAML::Node tp = poe["tool_pose"];
        tool = readPoseRows(tp, "poe.tool_pose");
      }
      file.poe.emplace(specs, tool, file.name);
    } else {
      file.dh = readDhSection(in, path, root["dh"], k, file.name, load_keys);
    }
    readLoads(in, root, load_keys, file);
    if (root["targets"]) file.targets = readTargets(in, root["targets"], file.target_normals);
    if (root["measurement_frame"]) {
      const Pose T = readPoseRows(root["measurement_frame"], "measurement_frame");
      if (!T.R.allFinite() || !T.p.allFinite() || !(T.p.norm() <= kMaxMagnitude)) {
        yamlError(path, root["measurement_frame"], "measurement_frame: a number is not finite or above 1e100");
      }
      if (!((T.R.transpose() * T.R - Mat3::Identity()).norm() <= kRotationOrthonormal) || T.R.determinant() <= 0.0) {
        yamlError(path, root["measurement_frame"], "measurement_frame: the first three columns are not a rotation");
      }
      file.measurement_frame = T;
    }
    if (root["tool_frame"]) {
      const std::string tool_frame = in.string(root["tool_frame"], "tool_frame");
      if (tool_frame != "origin" && tool_frame != "nominal") {
        yamlError(path, root["tool_frame"], "tool_frame: " + quotedFileText(tool_frame) +
                                                " is not 'origin' or 'nominal' (what a calibration left of the nominal's tool frame)");
      }
      file.tool_frame = tool_frame == "origin" ? ToolFrame::Origin : ToolFrame::Nominal;
    }
  } catch (const std::invalid_argument& e) {
    throw RobotFileError(path + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw RobotFileError(path + ": " + e.what());
  }
  return file;
}

namespace {

// The part every written robot file shares: `#` comments (one line each), then name, description and units,
// leaving the top-level map open. 17 significant digits: every number reads back to the same double.
void beginRobotFile(YAML::Emitter& out, const RobotFile& like, const std::string& name, const std::string& description,
                    const std::vector<std::string>& comments) {
  out.SetDoublePrecision(17);
  for (std::string c : comments) {
    std::replace_if(c.begin(), c.end(), [](char ch) { return ch == '\n' || ch == '\r'; }, ' ');
    out << YAML::Comment(c) << YAML::Newline;
  }
  out << YAML::BeginMap;
  out << YAML::Key << "name" << YAML::Value << name;
  if (!description.empty()) out << YAML::Key << "description" << YAML::Value << description;
  if (!like.length_unit.empty()) out << YAML::Key << "length_unit" << YAML::Value << like.length_unit;
  out << YAML::Key << "angle_unit" << YAML::Value << like.angle_unit;
}

// `targets:` (none: no key), checked as readRobotFile checks them so that the file reads back.
void writeTargets(YAML::Emitter& out, const std::vector<Target>& targets) {
  if (targets.empty()) return;
  if (targets.size() > static_cast<size_t>(kMaxTargets)) {
    throw std::invalid_argument("robot file: " + std::to_string(targets.size()) + " targets, at most " +
                                std::to_string(kMaxTargets));
  }
  std::set<std::string> names;
  for (const Target& t : targets) {
    const std::string name = quotedFileText(t.name);
    if (const std::string problem = targetNameProblem(t.name); !problem.empty()) {
      throw std::invalid_argument("robot file: target name " + name + " " + problem);
    }
    if (!names.insert(t.name).second) throw std::invalid_argument("robot file: target name " + name + " repeats");
    if (!t.point_tool) throw std::invalid_argument("robot file: target " + name + " has no point");
    if (const std::string problem = targetPointProblem(*t.point_tool); !problem.empty()) {
      throw std::invalid_argument("robot file: target " + name + ": point " + problem);
    }
  }
  out << YAML::Key << "targets" << YAML::Value << YAML::BeginSeq;
  for (const Target& t : targets) {
    const Vec3& p = *t.point_tool;
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << t.name;
    out << YAML::Key << "point" << YAML::Value << YAML::Flow << std::vector<double>{p[0], p[1], p[2]};
    if (t.known) out << YAML::Key << "known" << YAML::Value << true;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

// targets:, measurement_frame: and tool_frame: (RobotFileExtras), each only when there is one
void writeExtras(YAML::Emitter& out, const RobotFileExtras& extras) {
  writeTargets(out, extras.targets);
  writeLoads(out, extras);
  if (extras.measurement_frame) {
    out << YAML::Key << "measurement_frame" << YAML::Value << YAML::BeginSeq;
    const Mat4 F = extras.measurement_frame->matrix();
    for (int r = 0; r < 4; ++r) out << YAML::Flow << std::vector<double>{F(r, 0), F(r, 1), F(r, 2), F(r, 3)};
    out << YAML::EndSeq;
  }
  if (extras.tool_frame != ToolFrame::Defined) {
    out << YAML::Key << "tool_frame" << YAML::Value << (extras.tool_frame == ToolFrame::Origin ? "origin" : "nominal");
  }
}

}  // namespace

std::string formatPoeRobotFile(const PoeModel& model, const RobotFile& like, const std::string& name,
                               const std::string& description, const std::vector<std::string>& comments,
                               const RobotFileExtras& extras) {
  const double k = like.angleFactor();
  checkLoadExtras(extras, model.dof());
  YAML::Emitter out;
  beginRobotFile(out, like, name, description, comments);
  out << YAML::Key << "poe" << YAML::Value << YAML::BeginMap << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (const Joint& j : model.joints()) {
    const double unit = j.type == JointType::Prismatic ? 1.0 : k;  // joint-variable unit of offset and range
    const Vec6 xi = j.twist * j.scale;
    out << YAML::Flow << YAML::BeginMap;
    if (!j.name.empty()) out << YAML::Key << "name" << YAML::Value << j.name;
    out << YAML::Key << "type" << YAML::Value << jointTypeName(j.type);
    out << YAML::Key << "twist" << YAML::Value << YAML::Flow
        << std::vector<double>(xi.data(), xi.data() + 6);
    if (j.offset != 0.0) out << YAML::Key << "offset" << YAML::Value << j.offset / unit;
    if (j.range) {
      out << YAML::Key << "range" << YAML::Value << YAML::Flow
          << std::vector<double>{(*j.range)[0] / unit, (*j.range)[1] / unit};
    }
    writeJointLoadKeys(out, extras, static_cast<int>(&j - model.joints().data()), unit);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "tool_pose" << YAML::Value << YAML::BeginSeq;
  const Mat4 T = model.toolPose().matrix();
  for (int r = 0; r < 4; ++r) out << YAML::Flow << std::vector<double>{T(r, 0), T(r, 1), T(r, 2), T(r, 3)};
  out << YAML::EndSeq << YAML::EndMap;
  writeExtras(out, extras);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::string formatDhRobotFile(const DhModel& model, const RobotFile& like, const std::string& name,
                              const std::string& description, const std::vector<std::string>& comments,
                              const RobotFileExtras& extras) {
  const double k = like.angleFactor();
  checkLoadExtras(extras, model.dof());
  YAML::Emitter out;
  beginRobotFile(out, like, name, description, comments);
  auto row = [&](const DhParams& r) {
    out << YAML::Key << "theta" << YAML::Value << r.theta / k;
    // a Hayati row's d is 0 (written only when a folded offset of a sliding joint moved it)
    if (!r.hayati() || r.d != 0.0) out << YAML::Key << "d" << YAML::Value << r.d;
    out << YAML::Key << "alpha" << YAML::Value << r.alpha / k << YAML::Key << "a" << YAML::Value << r.a;
    if (r.hayati()) out << YAML::Key << "beta" << YAML::Value << r.beta / k;
  };
  out << YAML::Key << "dh" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "base" << YAML::Value << YAML::Flow << YAML::BeginMap;
  row(model.base());
  out << YAML::EndMap;
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (const DhJoint& j : model.joints()) {
    const double unit = j.type == JointType::Prismatic ? 1.0 : k;  // joint-variable unit of the range
    out << YAML::Flow << YAML::BeginMap;
    if (!j.name.empty()) out << YAML::Key << "name" << YAML::Value << j.name;
    out << YAML::Key << "type" << YAML::Value << jointTypeName(j.type);
    row(movedRow(j.link, j, j.motion(0.0)));  // the offset folded (conventions.md, D-H model)
    if (j.type == JointType::Helical) out << YAML::Key << "pitch" << YAML::Value << j.pitch * k;  // per angle_unit
    out << YAML::Key << "scale" << YAML::Value << j.scale;
    if (j.range) {
      out << YAML::Key << "range" << YAML::Value << YAML::Flow
          << std::vector<double>{(*j.range)[0] / unit, (*j.range)[1] / unit};
    }
    writeJointLoadKeys(out, extras, static_cast<int>(&j - model.joints().data()), unit);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "tool" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "theta" << YAML::Value << model.toolTheta() / k << YAML::Key << "d" << YAML::Value << model.toolD();
  out << YAML::EndMap << YAML::EndMap;
  writeExtras(out, extras);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace lowpair::io
