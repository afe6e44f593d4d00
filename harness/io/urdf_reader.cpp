#include "io/urdf_reader.hpp"

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace lowpair::io {

namespace {

// A prismatic joint that mimics the revolute joint before it forms a helical joint only when both lie on
// one line. `lowpair export` writes both with the same axis and no origin between them, so the lines agree
// to rounding; 1e-9 (rad, and times the chain's length scale) accepts any rounding of a 17-digit file and
// rejects a real offset or tilt.
constexpr double kMimicLine = 1e-9;


// Messages stay on one line whatever the file holds (names with newlines, urdfdom's multi-line errors).
std::string oneLine(const std::string& text) {
  std::string s;
  for (const char ch : text) {
    const bool control = static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f;
    if (control) {
      if (!s.empty() && s.back() != ' ') s += ' ';
    } else {
      s += ch;
    }
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string quoted(const std::string& name) { return "'" + oneLine(name) + "'"; }

std::string streamed(double x) {  // as an ostream prints it (6 significant digits)
  std::ostringstream out;
  out << x;
  return out.str();
}

// Byte offset of the first byte that is not part of well-formed UTF-8 (overlong forms, surrogates and
// code points above U+10FFFF included), or nullopt.
std::optional<size_t> invalidUtf8(const std::string& s) {
  size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    unsigned lo = 0x80, hi = 0xbf;  // allowed range of the second byte
    if (c < 0x80) {
      ++i;
      continue;
    } else if (c >= 0xc2 && c <= 0xdf) {
      extra = 1;
    } else if (c >= 0xe0 && c <= 0xef) {
      extra = 2;
      if (c == 0xe0) lo = 0xa0;
      if (c == 0xed) hi = 0x9f;
    } else if (c >= 0xf0 && c <= 0xf4) {
      extra = 3;
      if (c == 0xf0) lo = 0x90;
      if (c == 0xf4) hi = 0x8f;
    } else {
      return i;
    }
    if (i + static_cast<size_t>(extra) >= s.size()) return i;
    for (int k = 1; k <= extra; ++k) {
      const auto b = static_cast<unsigned char>(s[i + static_cast<size_t>(k)]);
      if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xbf)) return i;
    }
    i += static_cast<size_t>(extra) + 1;
  }
  return std::nullopt;
}

std::string readText(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) failFile(path, "cannot open file: no such file");
  if (fs::is_directory(status)) failFile(path, "is a directory, not a file");
  if (!fs::is_regular_file(status)) failFile(path, "not a regular file");
  requireBoundedModelFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) failFile(path, "cannot open file");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) failFile(path, "cannot read file");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) failFile(path, "not a valid URDF: empty file");
  if (text.find('\0') != std::string::npos) failFile(path, "not a valid URDF: contains NUL bytes (a binary file?)");
  if (const auto at = invalidUtf8(text)) {
    failFile(path, "not a valid URDF: not UTF-8 text (byte " + std::to_string(*at) + ")");
  }
  return text;
}

// urdfdom logs through console_bridge, whose default handler prints to the terminal. While parsing, its
// errors are collected instead (they become the one-line message) and everything below an error is
// dropped; the previous handler and level are restored afterwards. console_bridge's handler is global, so
// parses are serialized.
class CollectErrors : public console_bridge::OutputHandler {
 public:
  CollectErrors() : level_(console_bridge::getLogLevel()) {
    console_bridge::useOutputHandler(this);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
  }
  ~CollectErrors() override {
    console_bridge::restorePreviousOutputHandler();
    console_bridge::setLogLevel(level_);
  }
  CollectErrors(const CollectErrors&) = delete;
  CollectErrors& operator=(const CollectErrors&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    const std::string line = oneLine(text);
    if (line.empty()) return;
    if (!errors_.empty()) errors_ += "; ";
    errors_ += line;
  }
  const std::string& errors() const { return errors_; }

 private:
  console_bridge::LogLevel level_;
  std::string errors_;
};

// urdfdom parses with TinyXML 1, which recurses once per nesting level and has no limit: a file of 40,000
// nested elements overflows the stack, and 37,000 unclosed ones after a bad declaration took 6 s to fail.
// Every URDF is scanned first, in one linear pass that needs no well-formed XML: the depth of start tags
// not yet closed (comments, CDATA, declarations and processing instructions skipped; quoted attribute
// values may hold '>') may not pass tinyxml2's TINYXML2_MAX_ELEMENT_DEPTH (100; a URDF nests 4 deep).
void requireShallowXml(const std::string& path, const std::string& text) {
  int depth = 0;
  long long line = 1;
  auto skipPast = [&](size_t from, const char* end) {
    const size_t at = text.find(end, from);
    const size_t stop = at == std::string::npos ? text.size() : at + std::char_traits<char>::length(end);
    for (size_t k = from; k < stop; ++k) line += text[k] == '\n';
    return stop;
  };
  size_t k = 0;
  while (k < text.size()) {
    if (text[k] != '<') {
      line += text[k] == '\n';
      ++k;
      continue;
    }
    if (text.compare(k, 4, "<!--") == 0) {
      k = skipPast(k, "-->");
    } else if (text.compare(k, 9, "<![CDATA[") == 0) {
      k = skipPast(k, "]]>");
    } else if (text.compare(k, 2, "<?") == 0) {
      k = skipPast(k, "?>");
    } else if (text.compare(k, 2, "<!") == 0) {
      k = skipPast(k, ">");
    } else {
      const bool closing = text.compare(k, 2, "</") == 0;
      const long long tag_line = line;
      char quote = 0;
      size_t e = k + 1;
      for (; e < text.size(); ++e) {  // the end of the tag, outside quoted attribute values
        line += text[e] == '\n';
        if (quote) {
          if (text[e] == quote) quote = 0;
        } else if (text[e] == '"' || text[e] == '\'') {
          quote = text[e];
        } else if (text[e] == '>') {
          break;
        }
      }
      const bool empty = e < text.size() && text[e - 1] == '/';
      if (closing) {
        depth = std::max(0, depth - 1);
      } else if (!empty && ++depth > TINYXML2_MAX_ELEMENT_DEPTH) {
        failFile(path, "line " + std::to_string(tag_line) + ": not a valid URDF: elements nested deeper than " +
                       std::to_string(TINYXML2_MAX_ELEMENT_DEPTH));
      }
      k = e + 1;
    }
  }
}

// urdfdom keeps the last of two joints that name the same child link and silently drops the other: a
// closed loop (or a typo) opened without a word. MuJoCo rejects such a file; so does lowpair, naming both.
void requireOneParentPerLink(const std::string& path, const std::string& text) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS || !doc.RootElement()) return;  // urdfdom names it
  std::map<std::string, std::string> parent_joint;  // child link -> the joint that names it
  for (const tinyxml2::XMLElement* j = doc.RootElement()->FirstChildElement("joint"); j;
       j = j->NextSiblingElement("joint")) {
    const tinyxml2::XMLElement* child = j->FirstChildElement("child");
    const char* link = child ? child->Attribute("link") : nullptr;
    const char* name = j->Attribute("name");
    if (!link || !name) continue;  // urdfdom names these
    const auto [it, inserted] = parent_joint.emplace(link, name);
    if (!inserted) {
      const std::string& first = it->second;
      failFile(path, "line " + std::to_string(j->GetLineNum()) + ": link " + quoted(link) + " is the child of joints " +
                     quoted(first) + " and " + quoted(name) +
                     ": a closed loop, which a URDF (a tree) cannot describe and lowpair does not open");
    }
  }
}

urdf::ModelInterfaceSharedPtr parse(const std::string& path, const std::string& text) {
  requireShallowXml(path, text);
  requireOneParentPerLink(path, text);
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  std::string errors;
  urdf::ModelInterfaceSharedPtr model;
  {
    CollectErrors collect;
    try {
      model = urdf::parseURDF(text);
    } catch (const std::exception& e) {
      model.reset();
      errors = oneLine(e.what());
    }
    if (errors.empty()) errors = collect.errors();
  }
  if (!model) failFile(path, "not a valid URDF: " + (errors.empty() ? std::string("urdfdom rejected it") : errors));
  return model;
}

// The joint's origin: the joint frame in its parent link's frame (URDF rpy is fixed-axis roll, pitch, yaw,
// R = Rz(yaw) Ry(pitch) Rx(roll); urdfdom keeps it as a unit quaternion).
Pose originOf(const urdf::Joint& joint) {
  const urdf::Pose& o = joint.parent_to_joint_origin_transform;
  Pose T;
  T.R = Eigen::Quaterniond(o.rotation.w, o.rotation.x, o.rotation.y, o.rotation.z).toRotationMatrix();
  T.p = Vec3(o.position.x, o.position.y, o.position.z);
  return T;
}

const char* urdfTypeName(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE: return "revolute";
    case urdf::Joint::CONTINUOUS: return "continuous";
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::FLOATING: return "floating";
    case urdf::Joint::PLANAR: return "planar";
    case urdf::Joint::FIXED: return "fixed";
    default: return "unknown";
  }
}

// The links that exist, so the user sees the file's spelling (the first 20).
std::string linkNames(const urdf::ModelInterface& model) {
  std::string s;
  int count = 0;
  for (const auto& [name, link] : model.links_) {
    if (count == 20) {
      s += ", ... (" + std::to_string(model.links_.size()) + " in all)";
      break;
    }
    s += (count++ ? ", " : "") + quoted(name);
  }
  return s;
}

// The joints from `base` down to `tip`, base first.
std::vector<urdf::JointConstSharedPtr> chainJoints(const std::string& path, const urdf::ModelInterface& model,
                                                   const std::string& tip, const std::string& base) {
  // a name not found: the links that exist
  auto links = [&model]() { return linkNames(model); };
  if (!model.getLink(tip)) failFile(path, "tip " + quotedFileText(tip) + " is not a link; links: " + links());
  if (!model.getLink(base)) failFile(path, "base " + quotedFileText(base) + " is not a link; links: " + links());
  std::vector<urdf::JointConstSharedPtr> joints;
  std::string link = tip;
  while (link != base) {
    const urdf::LinkConstSharedPtr l = model.getLink(link);
    if (!l || !l->parent_joint || joints.size() > model.joints_.size()) {
      failFile(path, "base " + quoted(base) + " is not an ancestor of tip " + quoted(tip));
    }
    joints.push_back(l->parent_joint);
    link = l->parent_joint->parent_link_name;
  }
  return {joints.rbegin(), joints.rend()};
}

struct Line {
  Vec3 point, direction;  // unit direction
};

bool sameLine(const Line& a, const Line& b) {
  const double scale = std::max({1.0, a.point.norm(), b.point.norm()});
  return a.direction.cross(b.direction).norm() <= kMimicLine &&
         (b.point - a.point).cross(a.direction).norm() <= kMimicLine * scale;
}

}  // namespace

void checkUrdf(const std::string& path) { parse(path, readText(path)); }

std::string urdfTipCandidates(const std::string& path) { return "links: " + linkNames(*parse(path, readText(path))); }

RobotFile readUrdf(const std::string& path, const std::string& tip, const std::string& base) {
  const urdf::ModelInterfaceSharedPtr model = parse(path, readText(path));
  if (!model->getRoot()) failFile(path, "not a valid URDF: no root link");
  const std::string base_link = base.empty() ? model->getRoot()->name : base;
  const std::vector<urdf::JointConstSharedPtr> chain = chainJoints(path, *model, tip, base_link);
  requireJointCount(path, chain.size());

  std::vector<JointSpec> specs;
  std::vector<Line> lines;             // of specs
  std::vector<int> urdf_types;         // of specs
  std::vector<bool> merged;            // of specs: already a helical pair
  Pose T_base_frame;                   // the current joint (then child link) frame at zero
  for (const urdf::JointConstSharedPtr& joint : chain) {
    const std::string label = "joint " + quoted(joint->name);
    const Pose origin = originOf(*joint);
    if (!origin.R.allFinite() || !origin.p.allFinite()) failFile(path, label + ": origin is not finite");
    T_base_frame = T_base_frame * origin;
    const int type = joint->type;
    if (type == urdf::Joint::FIXED) continue;
    if (type != urdf::Joint::REVOLUTE && type != urdf::Joint::CONTINUOUS && type != urdf::Joint::PRISMATIC) {
      failFile(path, label + ": a " + urdfTypeName(type) +
                     " joint is not supported (revolute, continuous, prismatic and fixed joints only)");
    }
    const Vec3 axis(joint->axis.x, joint->axis.y, joint->axis.z);
    const double norm = safeNorm(axis);
    if (!std::isfinite(norm)) failFile(path, label + ": axis is not finite");
    if (norm == 0.0) failFile(path, label + ": zero axis");
    const Line line{T_base_frame.p, T_base_frame.R * (axis / norm)};

    if (joint->mimic) {
      const urdf::JointMimic& mimic = *joint->mimic;
      const std::string what = label + ": mimic of " + quoted(mimic.joint_name);
      const std::string helical = " (supported: a prismatic joint mimicking the revolute joint just before it "
                                  "on its axis line with offset 0, read as one helical joint)";
      if (type != urdf::Joint::PRISMATIC) {
        failFile(path, what + ": a " + urdfTypeName(type) + " joint cannot mimic" + helical);
      }
      if (specs.empty() || specs.back().name != mimic.joint_name) {
        failFile(path, what + ": that is not the moving joint just before it in the chain" + helical);
      }
      if (urdf_types.back() == urdf::Joint::PRISMATIC) failFile(path, what + ": that is a prismatic joint" + helical);
      if (merged.back()) failFile(path, what + ": that is already mimicked by another prismatic joint" + helical);
      if (mimic.offset != 0.0) failFile(path, what + ": offset " + streamed(mimic.offset) + " is not 0" + helical);
      if (!std::isfinite(mimic.multiplier)) failFile(path, what + ": multiplier is not finite");
      if (!sameLine(lines.back(), line)) failFile(path, what + ": not on the same axis line" + helical);
      // the slide runs along +w or -w of the revolute axis: pitch = multiplier * (u . w)
      const Vec3& w = lines.back().direction;
      const double pitch = line.direction.dot(w) > 0.0 ? mimic.multiplier : -mimic.multiplier;
      JointSpec& screw = specs.back();
      if (pitch != 0.0) {
        screw.type = JointType::Helical;
        screw.twist.tail<3>() += pitch * w;
      }
      merged.back() = true;
      continue;
    }

    JointSpec spec;
    spec.name = joint->name;
    if (type == urdf::Joint::PRISMATIC) {
      spec.type = JointType::Prismatic;
      spec.twist << Vec3::Zero(), line.direction;
    } else {
      spec.type = JointType::Revolute;
      spec.twist << line.direction, line.point.cross(line.direction);
    }
    if (type != urdf::Joint::CONTINUOUS && joint->limits) {
      spec.range = std::array<double, 2>{joint->limits->lower, joint->limits->upper};
    }
    specs.push_back(std::move(spec));
    lines.push_back(line);
    urdf_types.push_back(type);
    merged.push_back(false);
  }
  if (specs.empty()) {
    failFile(path, "no moving joint between base " + quoted(base_link) + " and tip " + quoted(tip));
  }

  RobotFile file;
  file.path = path;
  file.name = model->getName();
  file.length_unit = "m";
  file.angle_unit = "rad";
  file.description = "URDF chain from " + quoted(base_link) + " to " + quoted(tip);
  try {
    // the twists were built from unit axes: the URDF joint value is the motion itself, so the scale is 1
    // exactly (normalizeJoint would return |w| = 1 to rounding)
    std::vector<Joint> joints;
    for (size_t i = 0; i < specs.size(); ++i) {
      joints.push_back(normalizeJoint(specs[i], static_cast<int>(i)));
      joints.back().scale = 1.0;
    }
    file.poe.emplace(std::move(joints), T_base_frame, model->getName());
  } catch (const std::invalid_argument& e) {
    failFile(path, oneLine(e.what()));
  }
  return file;
}

}  // namespace lowpair::io
