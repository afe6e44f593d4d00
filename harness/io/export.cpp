#include "io/export.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "io/output.hpp"

namespace lowpair::io {

namespace {

// ---- numbers and text -------------------------------------------------------------------------------

// The shortest of 15, 16 or 17 significant digits that reads back as the same double (17 always does):
// 0.333, not 0.33300000000000002; never "-0".
std::string num(double x) {
  if (x == 0.0) return "0";
  char buffer[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  return buffer;
}

std::string num3(const Vec3& v) { return num(v[0]) + " " + num(v[1]) + " " + num(v[2]); }

// Length of the valid UTF-8 sequence starting at s[i] (shortest form, no surrogates, <= U+10FFFF), or 0.
size_t utf8Length(const std::string& s, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = byte(i);
  if (c < 0x80) return 1;
  size_t n = 0;
  unsigned min = 0, code = 0;
  if ((c & 0xE0) == 0xC0) n = 2, min = 0x80, code = c & 0x1Fu;
  else if ((c & 0xF0) == 0xE0) n = 3, min = 0x800, code = c & 0x0Fu;
  else if ((c & 0xF8) == 0xF0) n = 4, min = 0x10000, code = c & 0x07u;
  else return 0;
  if (i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3Fu);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

// Text XML 1.0 can carry: valid UTF-8 (an invalid byte becomes '?'), control characters as spaces.
std::string xmlText(const std::string& raw) {
  std::string out;
  for (size_t i = 0; i < raw.size();) {
    const size_t n = utf8Length(raw, i);
    if (n == 0) {
      out += '?';
      ++i;
    } else if (n == 1 && (static_cast<unsigned char>(raw[i]) < 0x20 || raw[i] == 0x7F)) {
      out += ' ';
      ++i;
    } else {
      out.append(raw, i, n);
      i += n;
    }
  }
  return out;
}

// One XML comment from lines: XML forbids "--" inside a comment and a '-' before its end.
std::string xmlComment(const std::vector<std::string>& lines) {
  std::string text = "\n";
  for (const std::string& line : lines) text += "  " + xmlText(line) + "\n";
  for (size_t at = text.find("--"); at != std::string::npos; at = text.find("--", at)) text.insert(at + 1, " ");
  return text;
}

// A name for an XML attribute that every URDF/MJCF tool accepts: ASCII letters, digits, '_', '-', '.'.
std::string safeName(const std::string& raw) {
  std::string out;
  for (const char ch : raw) {
    const bool keep = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
                      ch == '_' || ch == '-' || ch == '.';
    out += keep ? ch : '_';
  }
  return out;
}

// Unique names: "base", "tool" and "tool_joint" are reserved; a taken name gets "_2", "_3", ...
class NameTable {
 public:
  NameTable() : used_{"base", "tool", "tool_joint"} {}
  std::string take(const std::string& wanted) {
    std::string name = wanted;
    for (int k = 2; !used_.insert(name).second; ++k) name = wanted + "_" + std::to_string(k);
    return name;
  }

 private:
  std::set<std::string> used_;
};

// Exported names of joint i: the joint (revolute part of a helical joint), the slide of a helical joint,
// the intermediate URDF link between them, and the link (body) the joint moves.
struct ExportNames {
  std::string joint, slide, screw_link, link;
};

std::vector<ExportNames> exportNames(const PoeModel& model) {
  NameTable table;
  std::vector<ExportNames> names(static_cast<size_t>(model.dof()));
  for (int i = 0; i < model.dof(); ++i) {
    const std::string& raw = model.joint(i).name;
    ExportNames& n = names[static_cast<size_t>(i)];
    n.joint = table.take(raw.empty() ? "joint" + std::to_string(i + 1) : safeName(raw));
  }
  for (int i = 0; i < model.dof(); ++i) {
    ExportNames& n = names[static_cast<size_t>(i)];
    if (model.joint(i).type == JointType::Helical) {
      n.slide = table.take(n.joint + "_slide");
      n.screw_link = table.take(n.joint + "_screw");
    }
    n.link = table.take(n.joint + "_link");
  }
  return names;
}

// ---- frames -----------------------------------------------------------------------------------------

// The constant part of a chain link, Rz(theta) Trans(p) Rx(alpha) (model.hpp, KinematicChain).
Pose linkConstant(const ChainLink& link) {
  const double ct = std::cos(link.theta), st = std::sin(link.theta);
  Pose T;
  T.R << ct, -st * link.cos_alpha, st * link.sin_alpha,  //
      st, ct * link.cos_alpha, -ct * link.sin_alpha,     //
      0.0, link.sin_alpha, link.cos_alpha;
  T.p << ct * link.p[0] - st * link.p[1], st * link.p[0] + ct * link.p[1], link.p[2];
  return T;
}

// URDF's rpy of R = Rz(yaw) Ry(pitch) Rx(roll), accurate to rounding at and near gimbal lock: pitch from
// atan2 (never asin), yaw from the first column (any yaw is right when cos(pitch) = 0), and roll from
// what remains, Rx(roll) = Ry(pitch)^T Rz(yaw)^T R, which absorbs the rounding of yaw (relative
// eps / cos(pitch) near the lock) instead of leaving it as an error of the rotation.
Vec3 rollPitchYaw(const Mat3& R) {
  const double c = std::hypot(R(0, 0), R(1, 0));
  const double pitch = std::atan2(-R(2, 0), c);
  const double yaw = c > 0.0 ? std::atan2(R(1, 0), R(0, 0)) : 0.0;
  const Mat3 M = (Eigen::AngleAxisd(pitch, Vec3::UnitY()).toRotationMatrix().transpose() *
                  Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix().transpose()) *
                 R;
  const double roll = std::atan2(M(2, 1), M(1, 1));
  return Vec3(roll, pitch, yaw);
}

// MuJoCo's quat "w x y z" (w >= 0).
std::string quaternion(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() *= -1.0;
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

// ---- XML helpers ------------------------------------------------------------------------------------

tinyxml2::XMLElement* child(tinyxml2::XMLNode* parent, const char* tag) {
  tinyxml2::XMLElement* e = parent->GetDocument()->NewElement(tag);
  parent->InsertEndChild(e);
  return e;
}

std::string printed(tinyxml2::XMLDocument& doc) {
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

void startDocument(tinyxml2::XMLDocument& doc, const std::vector<std::string>& comments) {
  doc.InsertEndChild(doc.NewDeclaration());
  if (!comments.empty()) doc.InsertEndChild(doc.NewComment(xmlComment(comments).c_str()));
}

std::array<double, 2> sorted(double a, double b) { return {std::min(a, b), std::max(a, b)}; }

// ---- URDF -------------------------------------------------------------------------------------------

// The token mass of a link the file gives no mass (kExportMass at the link's origin): simulators refuse a
// massless moving body, and kinematics does not depend on it.
const PointMass kTokenMass{kExportMass, Vec3::Zero()};

// Link i's inertial from the file's masses: the mass at its centre of mass, moved from the base frame at the
// reference configuration into the link's frame there (F_link); a link without a mass gets the token mass.
PointMass linkMass(const std::optional<MassModel>& masses, size_t i, const Pose& F_link) {
  if (!masses || masses->links.empty() || masses->links[i].mass <= 0.0) return kTokenMass;
  return PointMass{masses->links[i].mass, F_link.inverse() * masses->links[i].com};
}

// The tool link's inertial: the token mass without masses (as before), the payload (its centre of mass is given
// in the tool frame) with them, and none when they give no payload.
std::optional<PointMass> payloadMass(const std::optional<MassModel>& masses) {
  if (!masses) return kTokenMass;
  if (masses->payload.mass <= 0.0) return std::nullopt;
  return masses->payload;
}

void urdfLink(tinyxml2::XMLElement* robot, const std::string& name, const std::optional<PointMass>& mass) {
  tinyxml2::XMLElement* link = child(robot, "link");
  link->SetAttribute("name", name.c_str());
  if (!mass) return;
  tinyxml2::XMLElement* inertial = child(link, "inertial");
  tinyxml2::XMLElement* origin = child(inertial, "origin");
  origin->SetAttribute("xyz", num3(mass->com).c_str());
  origin->SetAttribute("rpy", "0 0 0");
  child(inertial, "mass")->SetAttribute("value", num(mass->mass).c_str());
  tinyxml2::XMLElement* inertia = child(inertial, "inertia");
  for (const char* k : {"ixx", "iyy", "izz"}) inertia->SetAttribute(k, num(kExportInertia).c_str());
  for (const char* k : {"ixy", "ixz", "iyz"}) inertia->SetAttribute(k, "0");
}

tinyxml2::XMLElement* urdfJoint(tinyxml2::XMLElement* robot, const std::string& name, const char* type,
                                const std::string& parent, const std::string& child_link, const Pose& origin) {
  tinyxml2::XMLElement* joint = child(robot, "joint");
  joint->SetAttribute("name", name.c_str());
  joint->SetAttribute("type", type);
  child(joint, "parent")->SetAttribute("link", parent.c_str());
  child(joint, "child")->SetAttribute("link", child_link.c_str());
  tinyxml2::XMLElement* o = child(joint, "origin");
  o->SetAttribute("xyz", num3(origin.p).c_str());
  o->SetAttribute("rpy", num3(rollPitchYaw(origin.R)).c_str());
  if (std::string(type) != "fixed") child(joint, "axis")->SetAttribute("xyz", "0 0 1");
  return joint;
}

void urdfLimit(tinyxml2::XMLElement* joint, const std::array<double, 2>& range) {
  tinyxml2::XMLElement* limit = child(joint, "limit");
  limit->SetAttribute("lower", num(range[0]).c_str());
  limit->SetAttribute("upper", num(range[1]).c_str());
  limit->SetAttribute("effort", num(kUrdfEffortVelocity).c_str());
  limit->SetAttribute("velocity", num(kUrdfEffortVelocity).c_str());
}

// ---- MJCF -------------------------------------------------------------------------------------------

void mjcfInertial(tinyxml2::XMLElement* body, const PointMass& mass) {
  tinyxml2::XMLElement* inertial = child(body, "inertial");
  inertial->SetAttribute("pos", num3(mass.com).c_str());
  inertial->SetAttribute("mass", num(mass.mass).c_str());
  const std::string I = num(kExportInertia);
  inertial->SetAttribute("diaginertia", (I + " " + I + " " + I).c_str());
}

void mjcfPlace(tinyxml2::XMLElement* e, const Pose& T) {
  e->SetAttribute("pos", num3(T.p).c_str());
  e->SetAttribute("quat", quaternion(T.R).c_str());
}

tinyxml2::XMLElement* mjcfJoint(tinyxml2::XMLElement* body, const std::string& name, const char* type,
                                const std::optional<std::array<double, 2>>& range) {
  tinyxml2::XMLElement* joint = child(body, "joint");
  joint->SetAttribute("name", name.c_str());
  joint->SetAttribute("type", type);
  joint->SetAttribute("pos", "0 0 0");
  joint->SetAttribute("axis", "0 0 1");
  if (range) {
    joint->SetAttribute("limited", "true");
    joint->SetAttribute("range", (num((*range)[0]) + " " + num((*range)[1])).c_str());
  }
  return joint;
}

std::string robotName(const RobotFile& file) {
  if (!file.name.empty()) return file.name;
  const std::string stem = std::filesystem::path(file.path).stem().string();
  return stem.empty() ? "robot" : stem;
}

}  // namespace

// ---- public -----------------------------------------------------------------------------------------

const char* exportFormatName(ExportFormat format) {
  switch (format) {
    case ExportFormat::Urdf: return "urdf";
    case ExportFormat::Mjcf: return "mjcf";
    case ExportFormat::Poe: return "poe";
    case ExportFormat::Dh: return "dh";
  }
  return "?";
}

ExportFormat parseExportFormat(const std::string& text) {
  for (ExportFormat f : {ExportFormat::Urdf, ExportFormat::Mjcf, ExportFormat::Poe, ExportFormat::Dh}) {
    if (text == exportFormatName(f)) return f;
  }
  throw std::invalid_argument("export format must be urdf, mjcf, poe or dh, got '" + text + "'");
}

PoeModel motionModel(const PoeModel& model) {
  std::vector<Joint> joints = model.joints();
  for (size_t i = 0; i < joints.size(); ++i) {
    Joint& j = joints[i];
    if (j.range) {
      const double lo = j.motion((*j.range)[0]), hi = j.motion((*j.range)[1]);
      if (!std::isfinite(lo) || !std::isfinite(hi)) {
        throw std::invalid_argument(jointLabel(static_cast<int>(i), j.name) +
                                    ": its range in the motion x = scale (q + offset) overflows");
      }
      j.range = std::array<double, 2>{lo, hi};  // scale > 0 keeps the order
    }
    j.scale = 1.0;
    j.offset = 0.0;
  }
  return PoeModel(std::move(joints), model.toolPose(), model.name());
}

bool needsJointVariables(const PoeModel& model) {
  return std::any_of(model.joints().begin(), model.joints().end(),
                     [](const Joint& j) { return j.scale != 1.0 || j.offset != 0.0; });
}

ExportFrames exportFrames(const PoeModel& motion_model) {
  ExportFrames frames;
  // the joint frames of a URDF or MJCF are the standard D-H frames (the header says so): a Hayati row's extra
  // turn has no place in a joint's origin as these writers build it, and a joint frame far out is no defect
  ConvertOptions standard;
  standard.standard_only = true;
  const DhConversion conversion = poeToDh(motion_model, standard);
  frames.size = motion_model.lengthScale();
  frames.dh_scale = conversion.scale;
  const FkCheck check = checkDhConversion(motion_model, conversion.model);
  frames.dh_deviation = std::max(check.max_rotation, check.max_translation / frames.size);
  frames.dh = conversion.scale <= kExportDhScale * frames.size && frames.dh_deviation <= kExportDhDeviation;
  const KinematicChain& chain = frames.dh ? conversion.model.chain() : motion_model.chain();
  frames.T_base_first = chain.T_base_first;
  for (const ChainLink& link : chain.links) frames.T_link.push_back(linkConstant(link));
  frames.T_last_tool = chain.T_last_tool;
  return frames;
}


std::string formatUrdf(const PoeModel& model, const std::string& name, const std::vector<std::string>& comments,
                       const std::optional<MassModel>& masses) {
  const PoeModel motion = motionModel(model);
  const ExportFrames frames = exportFrames(motion);
  const std::vector<ExportNames> names = exportNames(motion);
  const double L = frames.size;
  tinyxml2::XMLDocument doc;
  startDocument(doc, comments);
  tinyxml2::XMLElement* robot = child(&doc, "robot");
  robot->SetAttribute("name", xmlText(name).c_str());
  urdfLink(robot, "base", kTokenMass);
  std::string parent = "base";
  Pose F_link;  // the moved link's frame in the base frame at the reference configuration
  for (int i = 0; i < motion.dof(); ++i) {
    const Joint& j = motion.joint(i);
    const ExportNames& n = names[static_cast<size_t>(i)];
    const Pose& origin = i == 0 ? frames.T_base_first : frames.T_link[static_cast<size_t>(i - 1)];
    F_link = F_link * origin;
    const bool helical = j.type == JointType::Helical;
    const std::string& moved = helical ? n.screw_link : n.link;
    if (j.type == JointType::Prismatic) {
      tinyxml2::XMLElement* e = urdfJoint(robot, n.joint, "prismatic", parent, moved, origin);
      urdfLimit(e, j.range ? *j.range : std::array<double, 2>{-L, L});
    } else {
      tinyxml2::XMLElement* e = urdfJoint(robot, n.joint, j.range ? "revolute" : "continuous", parent, moved, origin);
      if (j.range) urdfLimit(e, *j.range);
    }
    urdfLink(robot, moved, helical ? kTokenMass : linkMass(masses, static_cast<size_t>(i), F_link));
    if (helical) {
      // the screw's slide: on the same axis, slide = pitch * turn (urdf_reader.hpp reads it back as one joint)
      tinyxml2::XMLElement* e = urdfJoint(robot, n.slide, "prismatic", moved, n.link, Pose());
      const double reach = L + 1e4 * std::abs(j.pitch);  // a continuous screw: 1e4 rad of turning beyond L
      urdfLimit(e, j.range ? sorted(j.pitch * (*j.range)[0], j.pitch * (*j.range)[1])
                           : std::array<double, 2>{-reach, reach});
      tinyxml2::XMLElement* mimic = child(e, "mimic");
      mimic->SetAttribute("joint", n.joint.c_str());
      mimic->SetAttribute("multiplier", num(j.pitch).c_str());
      mimic->SetAttribute("offset", "0");
      urdfLink(robot, n.link, linkMass(masses, static_cast<size_t>(i), F_link));
    }
    parent = n.link;
  }
  urdfJoint(robot, "tool_joint", "fixed", parent, "tool", frames.T_link.back() * frames.T_last_tool);
  urdfLink(robot, "tool", payloadMass(masses));
  return printed(doc);
}

std::string formatMjcf(const PoeModel& model, const std::string& name, const std::vector<std::string>& comments,
                       const std::optional<MassModel>& masses) {
  const PoeModel motion = motionModel(model);
  const ExportFrames frames = exportFrames(motion);
  const std::vector<ExportNames> names = exportNames(motion);
  tinyxml2::XMLDocument doc;
  startDocument(doc, comments);
  tinyxml2::XMLElement* mujoco = child(&doc, "mujoco");
  mujoco->SetAttribute("model", xmlText(name).c_str());
  child(mujoco, "compiler")->SetAttribute("angle", "radian");
  child(mujoco, "option")->SetAttribute("gravity", masses ? num3(masses->gravity).c_str() : "0 0 0");
  tinyxml2::XMLElement* body = child(child(mujoco, "worldbody"), "body");
  body->SetAttribute("name", "base");
  mjcfInertial(body, kTokenMass);
  Pose F_link;
  tinyxml2::XMLElement* equality = nullptr;
  for (int i = 0; i < motion.dof(); ++i) {
    const Joint& j = motion.joint(i);
    const ExportNames& n = names[static_cast<size_t>(i)];
    body = child(body, "body");
    body->SetAttribute("name", n.link.c_str());
    const Pose& origin = i == 0 ? frames.T_base_first : frames.T_link[static_cast<size_t>(i - 1)];
    mjcfPlace(body, origin);
    F_link = F_link * origin;
    mjcfInertial(body, linkMass(masses, static_cast<size_t>(i), F_link));
    mjcfJoint(body, n.joint, j.type == JointType::Prismatic ? "slide" : "hinge", j.range);
    if (j.type == JointType::Helical) {
      mjcfJoint(body, n.slide, "slide", std::nullopt);  // driven by the equality below
      if (!equality) equality = child(mujoco, "equality");
      tinyxml2::XMLElement* e = child(equality, "joint");
      e->SetAttribute("joint1", n.slide.c_str());
      e->SetAttribute("joint2", n.joint.c_str());
      e->SetAttribute("polycoef", ("0 " + num(j.pitch) + " 0 0 0").c_str());
    }
  }
  tinyxml2::XMLElement* site = child(body, "site");
  site->SetAttribute("name", "tool");
  const Pose T_last_tool = frames.T_link.back() * frames.T_last_tool;
  mjcfPlace(site, T_last_tool);
  if (masses && masses->payload.mass > 0.0) {  // welded at the tool: MuJoCo counts it with the last link
    tinyxml2::XMLElement* payload = child(body, "body");
    payload->SetAttribute("name", "payload");
    mjcfPlace(payload, T_last_tool);
    mjcfInertial(payload, masses->payload);
  }
  return printed(doc);
}

ExportedRobot exportRobot(const RobotFile& file, ExportFormat format, const std::vector<std::string>& comments) {
  const PoeModel model = file.poeModel();
  const std::string name = robotName(file);
  ExportedRobot result;
  if (format == ExportFormat::Poe) {
    result.text = formatPoeRobotFile(model, file, name, file.description, comments,
                                     RobotFileExtras{file.targets, file.measurement_frame, file.tool_frame, file.masses, file.deflection});
    return result;
  }
  if (format == ExportFormat::Dh) {
    const DhConversion conversion = poeToDh(model);
    result.notes = conversionWarnings(conversion, checkDhConversion(model, conversion.model));
    result.text = formatDhRobotFile(conversion.model, file, name, file.description, comments,
                                    RobotFileExtras{file.targets, file.measurement_frame, file.tool_frame, file.masses, file.deflection});
    return result;
  }
  // URDF lengths are metres (the spec; ROS and every URDF reader assume them): a robot file in another unit
  // is converted, its prismatic joint variables keep their unit (the scales absorb the factor)
  if (format == ExportFormat::Urdf && !file.length_unit.empty() && file.length_unit != "m") {
    const RobotFile metres = inMetres(file);  // throws for a unit lowpair does not convert, naming it
    std::vector<std::string> converted = comments;
    converted.push_back("Lengths converted from " + file.length_unit + " to m (x " + num(*metresPerUnit(file.length_unit)) +
                        "; a prismatic joint variable q keeps " + file.length_unit + ", its scale holds the factor).");
    return exportRobot(metres, format, converted);
  }
  std::vector<std::string> header = comments;
  if (format == ExportFormat::Urdf && file.length_unit.empty()) {
    result.notes.push_back(file.path + " states no length_unit: its lengths are written as they are, and a URDF "
                           "reader takes them as metres");
  }
  const std::string unit = file.length_unit.empty() ? "the robot file's length unit" : file.length_unit;
  header.push_back("Lengths in " + unit + ", angles in rad" +
                   (file.length_unit == "m" ? "." : " (lengths are not converted to metres)."));
  const bool mapped = needsJointVariables(model);
  if (!file.description.empty()) header.push_back("Robot: " + file.description);
  // (a length unit converted to metres puts its factor into the prismatic scales: mapped as well)
  header.push_back(mapped ? "Joint variable: the motion x = scale (q + offset) of the joint variable q of " + file.path +
                                " (a scale is not 1 or an offset not 0; lowpair export writes the robot file of q beside "
                                "its output file as <stem>.joint_variables.yaml)."
                          : "Joint variable: the joint variable q of " + file.path + " (every scale 1, every offset 0).");
  const ExportFrames frames = exportFrames(motionModel(model));
  header.push_back(frames.dh ? "Joint frames: the standard D-H frames of lowpair poe2dh (joint i about/along z of frame i-1)."
                             : "Joint frames: on each joint's line at its point nearest the base origin (the D-H "
                               "table is ill-conditioned: nearly parallel axes); each joint about/along z.");
  if (!frames.dh) {
    char numbers[160];
    std::snprintf(numbers, sizeof numbers, "(its scale %.3g L, FK deviation %.3g)", frames.dh_scale / frames.size,
                  frames.dh_deviation);
    result.notes.push_back(std::string("the D-H table is ill-conditioned ") + numbers +
                           " by nearly parallel axes: the joint frames are put on the joint lines instead");
  }
  const bool helical = std::any_of(model.joints().begin(), model.joints().end(),
                                   [](const Joint& j) { return j.type == JointType::Helical; });
  if (format == ExportFormat::Urdf && helical) {
    result.notes.push_back("MuJoCo 2.2.2 ignores URDF <mimic>, so MuJoCo (lowpair validate) cannot read this URDF's "
                           "helical joints; urdfdom can, and the MJCF export (--format mjcf) has the same frames");
  }
  result.mujoco_readable = !(format == ExportFormat::Urdf && helical);
  if (file.masses) {
    header.push_back(std::string("Masses: each link's <inertial> is its mass (kg) at its centre of mass, the ") +
                     (format == ExportFormat::Urdf ? "tool link's the payload; gravity (a world property, not in URDF): "
                                                   : "payload a body welded at the tool; <option gravity> (m/s^2): ") +
                     num3(file.masses->gravity) + " in the base frame.");
  }
  if (!file.deflection.empty()) {
    header.push_back("Joint compliance and backlash (" + file.path + ") have no " +
                     (format == ExportFormat::Urdf ? "URDF" : "MJCF") +
                     " element: they are in the robot file lowpair export writes beside this one as "
                     "<stem>.joint_variables.yaml.");
  }
  result.text = format == ExportFormat::Urdf ? formatUrdf(model, name, header, file.masses)
                                             : formatMjcf(model, name, header, file.masses);
  if (format == ExportFormat::Mjcf) {
    // one nested body per joint: a long chain nests deeper than the 100 elements tinyxml2 reads (lowpair's
    // readers and its kinematics-only copy for MuJoCo): refuse what could not be read back
    tinyxml2::XMLDocument readback;
    if (readback.Parse(result.text.c_str(), result.text.size()) == tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED) {
      throw RobotFileError(file.path + ": " + std::to_string(model.dof()) + " joints: an MJCF nests one body per "
                           "joint, deeper than the " + std::to_string(TINYXML2_MAX_ELEMENT_DEPTH) +
                           " elements lowpair reads back (about 95 joints at most); export it as a URDF (flat)");
    }
  }
  if (mapped || !file.deflection.empty()) {  // the file of q, and of the deflections the format cannot hold
    std::vector<std::string> jv = comments;
    jv.push_back(std::string("The joint variables q of the exported ") + (format == ExportFormat::Urdf ? "URDF" : "MJCF") +
                 ", whose joint variable is the motion x = scale (q + offset).");
    result.joint_variables =
        file.deflection.empty()
            ? formatPoeRobotFile(model, file, name, file.description, jv)
            : formatPoeRobotFile(model, file, name, file.description, jv,
                                 RobotFileExtras{{}, std::nullopt, ToolFrame::Defined, file.masses, file.deflection});
  }
  return result;
}

std::string jointVariablesPath(const std::string& out) {
  const std::filesystem::path p(out);
  return (p.parent_path() / (p.stem().string() + ".joint_variables.yaml")).string();
}

}  // namespace lowpair::io
