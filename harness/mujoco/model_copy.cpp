#include "mujoco/model_copy.hpp"

#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>

#include <unistd.h>

#include "io/robot_file.hpp"
#include "mujoco/collision_copy.hpp"
#include "mujoco/messages.hpp"
#include "io/urdf_reader.hpp"

namespace lowpair::mujoco {

using namespace lowpair::io;  // the rooms below

namespace {

using tinyxml2::XMLDocument;
using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

namespace fs = std::filesystem;

// MuJoCo's include nesting is unbounded; ours stops here (a cycle is caught earlier: a file is included once).
constexpr int kMaxIncludeDepth = 16;
// Each pass of the trial load removes one attribute; a file with more unknown attributes than this is not
// a MuJoCo file.
constexpr int kMaxTrialLoads = 1000;

// Mass bounds that let MuJoCo load bodies with no inertial (geometry dropped, URDF links without
// <inertial>); masses never enter kinematics. kBoundMass spells kCopyBoundMass (model_copy.hpp).
constexpr const char* kBoundMass = "1e-6";
constexpr const char* kBoundInertia = "1e-9";

// A file's identity for "included once" (symlinks and ".." resolved where possible).
std::string fileKey(const fs::path& p) {
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(p), ec);
  return ec ? fs::absolute(p).lexically_normal().string() : canonical.string();
}

bool named(const XMLElement* e, const char* name) { return std::string(e->Name()) == name; }

std::string attr(const XMLElement* e, const char* name) {
  const char* v = e->Attribute(name);
  return v ? v : "";
}


// Calls f(a, b) for every pair of elements at the same place in two trees of the same shape.
void forEachPair(const XMLElement* a, const XMLElement* b, const std::function<void(const XMLElement*, const XMLElement*)>& f) {
  f(a, b);
  const XMLElement* ca = a->FirstChildElement();
  const XMLElement* cb = b->FirstChildElement();
  for (; ca && cb; ca = ca->NextSiblingElement(), cb = cb->NextSiblingElement()) forEachPair(ca, cb, f);
}

void forEachElement(XMLElement* e, const std::function<void(XMLElement*)>& f) {
  for (XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) forEachElement(c, f);
  f(e);
}

// Where an element was written: its file and line there.
struct Origin {
  std::string file;
  int line = 0;
};

// Attributes newer than MuJoCo 2.2.2 on elements that shape the kinematics, known to change nothing a
// position depends on (actuator force limits, gravity compensation); anything else 2.2.2 does not know on
// such an element is an error.
const std::map<std::string, std::set<std::string>> kHarmlessNewerAttributes = {
    {"joint", {"actuatorfrcrange", "actuatorfrclimited", "actuatorgravcomp"}},
    {"body", {"gravcomp"}},
    {"compiler", {"assetdir", "saveinertial"}},
};

// Elements whose every attribute only configures dynamics, collision or rendering: physics options and
// the tendons kept for the equality checks (what a tendon couples is its children, not its attributes).
const std::set<std::string> kNonKinematicElements = {"option", "flag", "size", "spatial", "fixed", "tendon"};

class Copier {
 public:
  Copier(const std::string& path, std::vector<std::string>* notes, CopyContent content)
      : path_(path),
        notes_(notes),
        keep_inertials_(content == CopyContent::Inertials),
        collision_(content == CopyContent::Collision) {}

  // the bodies whose mass MuJoCo would take from their (dropped) geoms; only for an inertials copy
  const std::vector<std::string>& massFromGeoms() const { return mass_from_geoms_; }

  // Builds the copy in doc_ and returns the root's name ("mujoco" or "robot").
  std::string build() {
    load(doc_, path_);
    XMLElement* root = doc_.RootElement();
    const std::string kind = root->Name();
    if (kind == "mujoco") {
      folder_ = fs::absolute(path_).parent_path();
      included_.insert(fileKey(path_));
      expandIncludes(root, 0);
      pruneMjcf(root);
      mergeCompiler(root, /*urdf=*/false);
    } else if (kind == "robot") {
      checkUrdf(path_);  // MuJoCo 2.2.2's URDF parser crashes on trees urdfdom rejects
      if (collision_) detail::keepUrdfCollisionGeometry(root, fs::absolute(path_).parent_path(), origin(), *notes_);
      pruneUrdf(root);
    } else {
      fail(path_, "the root element is <" + kind + ">: expected <mujoco> (MJCF) or <robot> (URDF)");
    }
    if (!dropped_.empty() && notes_) {
      std::string s = path_ + ": not needed for kinematics, dropped:";
      bool first = true;
      for (const auto& [name, count] : dropped_) {
        s += std::string(first ? " " : ", ") + std::to_string(count) + " <" + name + ">";
        first = false;
      }
      notes_->push_back(s);
    }
    return kind;
  }

  std::string text() const {
    tinyxml2::XMLPrinter printer;
    doc_.Print(&printer);
    return printer.CStr();
  }

  // Loads the copy (already written to `copy`) with MuJoCo until it loads: each attribute MuJoCo 2.2.2
  // rejects is removed with a note when it cannot change kinematics, else the load is an error naming it.
  void trialLoad(const std::string& copy, bool mjcf) {
    // MuJoCo's warnings belong to the real load (MujocoRobot's), not to each trial
    struct QuietWarnings {
      void (*saved)(const char*) = mju_user_warning;
      QuietWarnings() { mju_user_warning = [](const char*) {}; }
      ~QuietWarnings() { mju_user_warning = saved; }
    } quiet;
    for (int pass = 0; pass < kMaxTrialLoads; ++pass) {
      writeFile(copy, text());
      char error[1000] = "";
      mjModel* m = mj_loadXML(copy.c_str(), nullptr, error, sizeof error);
      if (m) {
        mj_deleteModel(m);
        return;
      }
      const std::string msg = error;
      if (mjcf && dropUnknown(msg)) continue;
      std::string what = "MuJoCo could not load the model: " + remapLines(mujocoLine(msg.c_str()));
      if (msg.find("pos and ipos are both undefined") != std::string::npos) {
        what += " (with compiler coordinate='global' a body without pos takes its frame from its geoms, which "
                "a kinematics-only copy drops: give the body a pos)";
      }
      fail(path_, what);
    }
    fail(path_, "MuJoCo could not load the model: more than " + std::to_string(kMaxTrialLoads) +
                    " attributes MuJoCo 2.2.2 does not know");
  }

  static void writeFile(const std::string& file, const std::string& text) {
    std::FILE* f = std::fopen(file.c_str(), "w");
    bool ok = f != nullptr;
    if (f) {
      ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
      ok = std::fclose(f) == 0 && ok;
    }
    if (!ok) throw RobotFileError(file + ": cannot write the temporary model copy");
  }

 private:
  [[noreturn]] static void fail(const std::string& file, const std::string& what) {
    throw RobotFileError(file + ": " + what);
  }

  detail::ElementOrigin origin() const {
    return [this](const XMLElement* e) { return where(e); };
  }

  std::string where(const XMLElement* e) const {
    auto it = origin_.find(e);
    if (it == origin_.end()) return path_;
    return it->second.file + ": line " + std::to_string(it->second.line);
  }

  // Parses `file` into `doc` and records every element's origin.
  void load(XMLDocument& doc, const std::string& file) {
    requireBoundedModelFile(file);  // an include too: a FIFO would hang LoadFile, a 1 GB file cost 3 GB
    // the model and its includes together: each file under the limit, but many of them, cost as much
    std::error_code ec;
    loaded_bytes_ += fs::exists(file, ec) ? fs::file_size(file, ec) : 0;
    if (loaded_bytes_ > kMaxModelFileBytes) {
      fail(file, "the model and the files it includes hold " + std::to_string(loaded_bytes_) + " bytes: over the " +
                     std::to_string(kMaxModelFileBytes >> 20) + " MiB a model file may have");
    }
    const tinyxml2::XMLError status = doc.LoadFile(file.c_str());
    if (status == tinyxml2::XML_ERROR_FILE_NOT_FOUND || status == tinyxml2::XML_ERROR_FILE_COULD_NOT_BE_OPENED) {
      fail(file, "cannot open file");
    }
    if (status == tinyxml2::XML_ERROR_FILE_READ_ERROR) fail(file, "cannot read file");
    if (status == tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED) {
      fail(file, "line " + std::to_string(doc.ErrorLineNum()) + ": not well-formed XML: elements nested deeper than " +
                     std::to_string(TINYXML2_MAX_ELEMENT_DEPTH));
    }
    if (status != tinyxml2::XML_SUCCESS) {
      fail(file, "line " + std::to_string(doc.ErrorLineNum()) + ": not well-formed XML (" + doc.ErrorName() + ")");
    }
    if (!doc.RootElement()) fail(file, "no root element: not an MJCF or URDF file");
    forEachElement(doc.RootElement(), [&](XMLElement* e) { origin_[e] = {file, e->GetLineNum()}; });
  }

  // Replaces every <include file="F"/> below `parent` by the children of F's <mujoco> root. As in MuJoCo
  // 2.2.2, a relative F is relative to the main model's folder (also for an include inside an included
  // file), and a file is included at most once.
  void expandIncludes(XMLElement* parent, int depth) {
    XMLElement* e = parent->FirstChildElement();
    while (e) {
      XMLElement* next = e->NextSiblingElement();
      if (!named(e, "include")) {
        expandIncludes(e, depth);
        e = next;
        continue;
      }
      const std::string file = attr(e, "file");
      if (file.empty()) fail(where(e), "<include> without a file attribute");
      if (depth >= kMaxIncludeDepth) {
        fail(where(e), "<include file='" + file + "'>: includes nested deeper than " + std::to_string(kMaxIncludeDepth));
      }
      const fs::path resolved = fs::path(file).is_absolute() ? fs::path(file) : folder_ / file;
      const std::string key = fileKey(resolved);
      if (!included_.insert(key).second) {
        fail(where(e), "<include file='" + file + "'>: the file is already included (MuJoCo includes a file once)");
      }
      auto included = std::make_unique<XMLDocument>();
      if (!fs::exists(resolved)) fail(where(e), "<include file='" + file + "'>: cannot open " + resolved.string());
      load(*included, resolved.string());
      XMLElement* root = included->RootElement();
      if (!named(root, "mujoco")) {
        fail(resolved.string(), "an included file's root element must be <mujoco>, not <" + std::string(root->Name()) + ">");
      }
      // the included file's own includes first, then its children in place of the <include>
      expandIncludes(root, depth + 1);
      XMLNode* after = e;
      for (const XMLNode* child = root->FirstChild(); child; child = child->NextSibling()) {
        XMLNode* clone = child->DeepClone(&doc_);
        parent->InsertAfterChild(after, clone);
        after = clone;
        if (child->ToElement()) {
          forEachPair(child->ToElement(), clone->ToElement(), [&](const XMLElement* src, const XMLElement* dst) {
            origin_[dst] = origin_[src];
          });
        }
      }
      // the included document goes away: its elements' origins were copied to the clones
      forEachElement(root, [&](XMLElement* src) { origin_.erase(src); });
      parent->DeleteChild(e);
      e = next;
    }
  }

  void drop(XMLElement* e, bool count = true) {
    if (count) ++dropped_[e->Name()];
    e->Parent()->DeleteChild(e);
  }

  // The MJCF without what kinematics does not need (README "Validation against MuJoCo").
  void pruneMjcf(XMLElement* root) {
    static const std::set<std::string> kDroppedSections = {"asset",  "actuator", "sensor", "contact",   "keyframe", "visual",
                                                          "statistic", "custom", "size",  "extension", "deformable"};
    for (const XMLElement* c = root->FirstChildElement("compiler"); c; c = c->NextSiblingElement("compiler")) {
      if (c->Attribute("coordinate")) global_coordinates_ = attr(c, "coordinate") == "global";
      if (c->Attribute("inertiafromgeom")) inertia_from_geom_ = attr(c, "inertiafromgeom");
    }
    bool tendon_equality = false;
    for (XMLElement* eq = root->FirstChildElement("equality"); eq; eq = eq->NextSiblingElement("equality")) {
      for (XMLElement* c = eq->FirstChildElement(); c; c = c->NextSiblingElement()) {
        if (named(c, "tendon")) tendon_equality = true;
        if (named(c, "distance")) {
          fail(where(c), "<equality><distance> constrains geoms, which a kinematics-only copy does not keep: "
                         "a closed loop the extraction cannot represent");
        }
      }
    }
    if (collision_) detail::keepMjcfCollisionGeometry(root, folder_, origin(), *notes_);
    for (XMLElement* e = root->FirstChildElement(); e;) {
      XMLElement* next = e->NextSiblingElement();
      const std::string name = e->Name();
      // tendons stay only when a tendon equality needs them (MujocoRobot checks what they couple)
      const bool collision_section = collision_ && (name == "asset" || name == "contact");
      if ((kDroppedSections.count(name) && !collision_section) || (name == "tendon" && !tendon_equality)) {
        drop(e);
      } else if (name == "default") {
        pruneDefaults(e);
      } else if (name == "worldbody") {
        pruneBodies(e);
      } else if (name == "tendon") {
        pruneTendons(e);
      }
      e = next;
    }
  }

  // Defaults of what is kept; geom, mesh, material, camera, light, pair and actuator classes go (a collision
  // copy keeps geom, mesh and pair).
  void pruneDefaults(XMLElement* def) {
    static const std::set<std::string> kKept = {"default", "joint", "site", "equality", "tendon"};
    static const std::set<std::string> kCollision = {"geom", "mesh", "pair"};
    for (XMLElement* c = def->FirstChildElement(); c;) {
      XMLElement* next = c->NextSiblingElement();
      if (!kKept.count(c->Name()) && !(collision_ && kCollision.count(c->Name()))) {
        drop(c, /*count=*/false);
      } else if (named(c, "default")) {
        pruneDefaults(c);
      } else {
        c->DeleteAttribute("material");
      }
      c = next;
    }
  }

  void pruneBodies(XMLElement* e) {
    static const std::set<std::string> kDropped = {"geom", "camera", "light"};
    if (keep_inertials_ && named(e, "body")) noteMassFromGeoms(e);
    for (XMLElement* c = e->FirstChildElement(); c;) {
      XMLElement* next = c->NextSiblingElement();
      if (kDropped.count(c->Name()) && !(collision_ && named(c, "geom"))) {
        drop(c);
      } else if (named(c, "inertial") && !keep_inertials_ && (!global_coordinates_ || e->Attribute("pos"))) {
        // masses never enter kinematics, but MuJoCo's Jacobian is taken about the subtree's centre of
        // mass: a non-finite or huge inertial pos made every Jacobian NaN. (With coordinate='global' a
        // body without pos takes its frame from it: kept there.)
        drop(c, /*count=*/false);
      } else {
        if (named(c, "site")) c->DeleteAttribute("material");
        pruneBodies(c);
      }
      c = next;
    }
  }

  // A body whose mass MuJoCo computes from its geoms (compiler inertiafromgeom: "true" always, "auto", the
  // default, when the body has no <inertial>): the copy drops the geoms, so that mass is lost.
  void noteMassFromGeoms(const XMLElement* body) {
    if (inertia_from_geom_ == "false" || !body->FirstChildElement("geom")) return;
    if (inertia_from_geom_ != "true" && body->FirstChildElement("inertial")) return;
    const std::string name = attr(body, "name");
    mass_from_geoms_.push_back(name.empty() ? where(body) : "'" + name + "'");
  }

  // Spatial tendons lose their wrapping geoms (dropped with all geometry); sites and joints stay.
  void pruneTendons(XMLElement* tendon) {
    for (XMLElement* t = tendon->FirstChildElement(); t; t = t->NextSiblingElement()) {
      t->DeleteAttribute("material");
      for (XMLElement* c = t->FirstChildElement(); c;) {
        XMLElement* next = c->NextSiblingElement();
        if (named(c, "geom")) drop(c);
        c = next;
      }
    }
  }

  // The URDF without <visual> and <collision> (so no mesh is ever opened).
  void pruneUrdf(XMLElement* robot) {
    if (const XMLElement* block = robot->FirstChildElement("mujoco")) {
      for (const XMLElement* c = block->FirstChildElement("compiler"); c; c = c->NextSiblingElement("compiler")) {
        if (c->Attribute("inertiafromgeom")) inertia_from_geom_ = attr(c, "inertiafromgeom");
      }
    }
    for (XMLElement* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
      // a link's <visual> and <collision> become geoms in MuJoCo: the source of its mass without <inertial>
      const bool has_geoms = link->FirstChildElement("visual") || link->FirstChildElement("collision");
      const bool from_geoms =
          inertia_from_geom_ == "true" || (inertia_from_geom_ != "false" && !link->FirstChildElement("inertial"));
      if (keep_inertials_ && has_geoms && from_geoms) mass_from_geoms_.push_back("'" + attr(link, "name") + "'");
      for (XMLElement* c = link->FirstChildElement(); c;) {
        XMLElement* next = c->NextSiblingElement();
        // masses never enter kinematics, but MuJoCo's Jacobian is taken about the subtree's centre of
        // mass: a non-finite inertial origin (urdfdom accepts one) made every Jacobian NaN
        if (named(c, "visual") || (named(c, "collision") && !collision_)) {
          drop(c);
        } else if (named(c, "inertial") && !keep_inertials_) {
          drop(c, /*count=*/false);
        }
        c = next;
      }
    }
    mergeCompiler(robot, /*urdf=*/true);
  }

  // Compiler settings the copy needs, merged into the file's own: its settings stay (angle, eulerseq,
  // coordinate, ...) except where a kinematics-only copy must differ. MuJoCo reads repeated <compiler>
  // elements in order, the last setting winning, so the added ones go into the last.
  void mergeCompiler(XMLElement* root, bool urdf) {
    std::vector<XMLElement*> compilers;
    XMLElement* block = root;  // where <compiler> elements live: <mujoco>, or a URDF's <mujoco> block
    if (urdf) {
      block = root->FirstChildElement("mujoco");
      if (!block) {
        block = doc_.NewElement("mujoco");
        root->InsertFirstChild(block);
      }
    }
    for (XMLElement* c = block->FirstChildElement("compiler"); c; c = c->NextSiblingElement("compiler")) {
      compilers.push_back(c);
    }
    if (compilers.empty()) {
      XMLElement* c = doc_.NewElement("compiler");
      block->InsertFirstChild(c);
      compilers.push_back(c);
    }
    XMLElement* last = compilers.back();
    auto effective = [&](const char* name) -> const XMLElement* {
      const XMLElement* found = nullptr;
      for (const XMLElement* c : compilers) {
        if (c->Attribute(name)) found = c;
      }
      return found;
    };
    auto setIfAbsent = [&](const char* name, const char* value) {
      if (!effective(name)) last->SetAttribute(name, value);
    };
    // a bound of 0 (or less) bounds nothing: massless bodies would not load
    auto setBound = [&](const char* name, const char* value) {
      const XMLElement* c = effective(name);
      if (!c || !(c->DoubleAttribute(name) > 0)) last->SetAttribute(name, value);
    };
    // fused static bodies would take a tip body's name with them; fusing never changes a pose
    if (const XMLElement* c = effective("fusestatic"); c && attr(c, "fusestatic") != "false") {
      note(c, "compiler fusestatic='" + attr(c, "fusestatic") +
                  "' replaced by 'false': bodies attached without joints stay bodies (no effect on kinematics)");
    }
    last->SetAttribute("fusestatic", "false");
    setBound("boundmass", kBoundMass);
    setBound("boundinertia", kBoundInertia);
    // a collision copy's mesh files are absolute paths, which strippath would cut
    if (collision_) last->SetAttribute("strippath", "false");
    if (urdf) {
      setIfAbsent("discardvisual", "true");
      setIfAbsent("strippath", "false");
    } else {
      // MuJoCo >= 2.3 defaults to autolimits="true" and files written for it rely on it (a range without
      // limited); 2.2.2 knows the attribute but defaults to false, which rejects such a joint
      setIfAbsent("autolimits", "true");
      // the assets are gone: their folders are not needed (and the copy lives elsewhere)
      for (XMLElement* c : compilers) {
        c->DeleteAttribute("meshdir");
        c->DeleteAttribute("texturedir");
        c->DeleteAttribute("assetdir");
      }
    }
  }

  void note(const XMLElement* e, const std::string& what) {
    if (notes_) notes_->push_back(where(e) + ": " + what);
  }

  // The element at line `line` of the printed copy (MuJoCo's line numbers), as an element of doc_.
  XMLElement* elementAtPrintedLine(int line, const std::string& name) {
    XMLDocument printed;
    const std::string t = text();
    if (printed.Parse(t.c_str(), t.size()) != tinyxml2::XML_SUCCESS || !printed.RootElement()) return nullptr;
    const XMLElement* found = nullptr;
    forEachPair(doc_.RootElement(), printed.RootElement(), [&](const XMLElement* ours, const XMLElement* p) {
      if (!found && p->GetLineNum() == line && (name.empty() || name == p->Name())) found = ours;
    });
    return const_cast<XMLElement*>(found);
  }

  // MuJoCo's "line N" / "line = N" (of the copy) followed by the original file and line.
  std::string remapLines(const std::string& msg) {
    std::string out;
    size_t i = 0;
    while (i < msg.size()) {
      size_t at = msg.find("line", i);
      if (at == std::string::npos) break;
      size_t k = at + 4;
      while (k < msg.size() && (msg[k] == ' ' || msg[k] == '=')) ++k;
      size_t digits = k;
      while (digits < msg.size() && std::isdigit(static_cast<unsigned char>(msg[digits]))) ++digits;
      out += msg.substr(i, at - i);
      if (digits > k) {
        const XMLElement* e = elementAtPrintedLine(std::stoi(msg.substr(k, digits - k)), "");
        out += e ? where(e) : "line ?";
        i = digits;
      } else {
        out += "line";
        i = at + 4;
      }
    }
    return out + msg.substr(std::min(i, msg.size()));
  }

  static std::string quoted(const std::string& msg, const std::string& after) {
    const size_t at = msg.find(after);
    if (at == std::string::npos) return "";
    const size_t begin = at + after.size();
    const size_t end = msg.find('\'', begin);
    return end == std::string::npos ? "" : msg.substr(begin, end - begin);
  }

  // One attribute or keyword MuJoCo 2.2.2 rejected (its schema's first violation, or a keyword it does
  // not know): removed with a note when it cannot change kinematics; false when `msg` is another error.
  bool dropUnknown(const std::string& msg) {
    const std::string element = quoted(msg, "Element '");
    const size_t line_at = msg.find("', line ");
    if (element.empty() || line_at == std::string::npos) return false;
    const int line = std::atoi(msg.c_str() + line_at + 8);
    XMLElement* e = elementAtPrintedLine(line, element);
    if (!e) return false;
    std::string attribute = quoted(msg, "unrecognized attribute: '");
    const std::string keyword = quoted(msg, "invalid keyword: '");
    if (attribute.empty() && !keyword.empty()) {
      for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
        if (keyword == a->Value()) attribute = a->Name();
      }
    }
    const bool unknown_element = msg.find("unrecognized element") != std::string::npos;
    if (attribute.empty() && !unknown_element) return false;
    const std::string what = unknown_element ? "element <" + element + ">"
                             : keyword.empty() ? "unrecognized attribute: '" + attribute + "' on <" + element + ">"
                                               : "invalid keyword: '" + keyword + "' in <" + element + " " + attribute + ">";
    if (unknown_element) {
      fail(path_, "MuJoCo could not load the model: " + what + " (" + where(e) +
                      ") is not known to MuJoCo 2.2.2 and may shape the kinematics");
    }
    auto harmless = kHarmlessNewerAttributes.find(element);
    const bool droppable = kNonKinematicElements.count(element) ||
                           (keyword.empty() && harmless != kHarmlessNewerAttributes.end() && harmless->second.count(attribute));
    if (!droppable) {
      fail(path_, "MuJoCo could not load the model: " + what + " (" + where(e) +
                      "): not known to MuJoCo 2.2.2, and <" + element + "> shapes the kinematics");
    }
    note(e, "dropped <" + element + " " + attribute + "='" + attr(e, attribute.c_str()) +
                "'>: not known to MuJoCo 2.2.2, no effect on kinematics");
    e->DeleteAttribute(attribute.c_str());
    return true;
  }

  std::string path_;
  bool global_coordinates_ = false;  // <compiler coordinate="global"> (MuJoCo 2.2.2 still reads it)
  std::vector<std::string>* notes_;
  bool keep_inertials_ = false;       // CopyContent::Inertials
  bool collision_ = false;            // CopyContent::Collision
  std::string inertia_from_geom_ = "auto";  // <compiler inertiafromgeom>, MuJoCo's default "auto"
  std::vector<std::string> mass_from_geoms_;
  XMLDocument doc_;
  fs::path folder_;
  std::set<std::string> included_;
  std::uintmax_t loaded_bytes_ = 0;  // of the model and the files it includes, so far
  std::unordered_map<const XMLElement*, Origin> origin_;
  std::map<std::string, int> dropped_;
};

}  // namespace

std::string createTemporaryFile(const std::string& model, const std::string& stem, const std::string& ext) {
  // mkstemps replaces the six Xs with a unique suffix and keeps the extension
  std::string path = (fs::temp_directory_path() / (stem + "_XXXXXX" + ext)).string();
  const int fd = mkstemps(path.data(), static_cast<int>(ext.size()));
  if (fd < 0) throw RobotFileError(model + ": cannot create a temporary copy in " + fs::temp_directory_path().string());
  ::close(fd);
  return path;
}

ModelCopy::ModelCopy(const std::string& path, std::vector<std::string>* notes, CopyContent content) {
  std::vector<std::string> local;
  Copier copier(path, &local, content);
  const bool mjcf = copier.build() == "mujoco";
  const std::string copy = createTemporaryFile(path, "lowpair_model", mjcf ? ".xml" : ".urdf");
  try {
    copier.trialLoad(copy, mjcf);
  } catch (...) {
    std::remove(copy.c_str());
    throw;
  }
  copy_ = copy;
  mass_from_geoms_ = copier.massFromGeoms();
  if (notes) notes->insert(notes->end(), local.begin(), local.end());
}

ModelCopy::~ModelCopy() {
  if (!copy_.empty()) std::remove(copy_.c_str());
}

}  // namespace lowpair::mujoco
