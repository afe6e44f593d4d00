// Contacts of a MuJoCo chain at a configuration (collision_check.hpp).
#include "mujoco/collision_check.hpp"

#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>


#include "io/robot_file.hpp"
#include "mujoco/messages.hpp"
#include "mujoco/model_copy.hpp"

namespace lowpair::mujoco {

namespace {

namespace fs = std::filesystem;
using tinyxml2::XMLElement;

constexpr const char* kFloorName = "lowpair-floor";

// A temporary .xml file (createTemporaryFile), removed with the object.
struct TempXml {
  std::string path;
  explicit TempXml(const std::string& model) : path(createTemporaryFile(model, "lowpair_floor", ".xml")) {}
  ~TempXml() { std::remove(path.c_str()); }
};

XMLElement* findBody(XMLElement* e, const std::string& name) {
  for (XMLElement* c = e->FirstChildElement("body"); c; c = c->NextSiblingElement("body")) {
    const char* n = c->Attribute("name");
    if (n && name == n) return c;
    if (XMLElement* found = findBody(c, name)) return found;
  }
  return nullptr;
}

// The collision copy as an MJCF with the floor plane in the base body (the world body for the world): a URDF
// copy is first written out as MJCF by MuJoCo (mj_saveLastXML after loading it).
void writeWithFloor(const std::string& copy, const std::string& model, const std::string& base, double z,
                    const std::string& out) {
  std::string source = copy;
  if (fs::path(copy).extension() == ".urdf") {
    char error[1000] = "";
    std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(copy.c_str(), nullptr, error, sizeof error),
                                                   mj_deleteModel);
    if (!m || !mj_saveLastXML(out.c_str(), m.get(), error, sizeof error)) {
      io::failFile(model, "MuJoCo could not write the model with a floor: " + mujocoLine(error));
    }
    source = out;
  }
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(source.c_str()) != tinyxml2::XML_SUCCESS || !doc.RootElement()) {
    io::failFile(model, "cannot read the collision copy to add the floor");
  }
  XMLElement* world = doc.RootElement()->FirstChildElement("worldbody");
  XMLElement* body = world && !base.empty() ? findBody(world, base) : world;
  if (!body) io::failFile(model, "no body " + io::quotedFileText(base) + " to put the floor in");
  XMLElement* floor = doc.NewElement("geom");
  floor->SetAttribute("name", kFloorName);
  floor->SetAttribute("type", "plane");
  floor->SetAttribute("size", "0 0 1");
  char exact[40];
  std::snprintf(exact, sizeof exact, "0 0 %.17g", z);
  floor->SetAttribute("pos", exact);
  floor->SetAttribute("contype", "2147483647");
  floor->SetAttribute("conaffinity", "2147483647");
  body->InsertFirstChild(floor);
  if (doc.SaveFile(out.c_str()) != tinyxml2::XML_SUCCESS) io::failFile(model, "cannot write the floor copy");
}

}  // namespace

void CollisionChecker::ModelDeleter::operator()(mjModel_* m) const { mj_deleteModel(m); }

CollisionChecker::CollisionChecker(const MujocoRobot& robot, std::optional<double> floor_z)
    : robot_(robot), data_(nullptr, mj_deleteData) {
  const std::string& path = robot.path();
  installMujocoHandlers();
  setLoadingModel(path);
  std::vector<std::string> notes;
  {
    const ModelCopy copy(path, &notes, CopyContent::Collision);
    std::string load = copy.path();
    std::optional<TempXml> floor_copy;
    if (floor_z) {
      floor_copy.emplace(path);
      // the base body's name, from the kinematics model's ids (the same in every copy)
      std::string base;
      if (robot.baseBody() > 0) {
        char error[1000] = "";
        std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(load.c_str(), nullptr, error, sizeof error),
                                                       mj_deleteModel);
        if (!m) io::failFile(path, "MuJoCo could not load the model with its geometry: " + mujocoLine(error));
        const char* name = mj_id2name(m.get(), mjOBJ_BODY, robot.baseBody());
        base = name ? name : "";
      }
      writeWithFloor(load, path, base, *floor_z, floor_copy->path);
      load = floor_copy->path;
    }
    char error[1000] = "";
    model_.reset(mj_loadXML(load.c_str(), nullptr, error, sizeof error));
    if (!model_) io::failFile(path, "MuJoCo could not load the model with its geometry: " + mujocoLine(error));
  }
  mjModel* m = model_.get();
  // collisions are what is asked: a model that disables contacts is checked all the same
  m->opt.disableflags &= ~(mjDSBL_CONTACT | mjDSBL_CONSTRAINT);
  data_.reset(mj_makeData(m));
  if (!data_) io::failFile(path, "MuJoCo could not allocate the collision data");
  floor_geom_ = floor_z ? mj_name2id(m, mjOBJ_GEOM, kFloorName) : -1;
  for (int g = 0; g < m->ngeom; ++g) {
    if (g != floor_geom_ && (m->geom_contype[g] || m->geom_conaffinity[g])) ++collision_geoms_;
  }
  // the summary of what a kinematics copy drops does not describe this copy
  for (const std::string& n : notes) {
    if (n.find(": not needed for kinematics, dropped:") == std::string::npos) notes_.push_back(n);
  }
}

CollisionChecker::~CollisionChecker() = default;

ContactReport CollisionChecker::contactsAt(const Eigen::Ref<const VecX>& x) {
  const mjModel* m = model_.get();
  mjData* d = data_.get();
  mju_copy(d->qpos, m->qpos0, m->nq);
  const std::vector<MujocoJoint>& joints = robot_.joints();
  for (size_t i = 0; i < joints.size(); ++i) {
    const MujocoJoint& j = joints[i];
    const double xi = x[static_cast<Eigen::Index>(i)];
    d->qpos[j.qpos] = m->qpos0[j.qpos] + xi;
    if (j.slide_qpos >= 0) d->qpos[j.slide_qpos] = m->qpos0[j.slide_qpos] + j.pitch * xi;
  }
  mj_kinematics(m, d);
  mj_collision(m, d);
  ContactReport r;
  r.contacts = d->ncon;
  int rank = 3;  // Self 0, World 1, Floor 2: the first met wins
  for (int c = 0; c < d->ncon; ++c) {
    const int g1 = d->contact[c].geom1, g2 = d->contact[c].geom2;
    int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
    ContactKind kind = ContactKind::Self;
    if (g1 == floor_geom_ || g2 == floor_geom_) {
      kind = ContactKind::Floor;
      (g1 == floor_geom_ ? b1 : b2) = -1;
    } else if (m->body_weldid[b1] == 0 || m->body_weldid[b2] == 0) {
      kind = ContactKind::World;
    }
    rank = std::min(rank, static_cast<int>(kind));
    const std::array<int, 2> pair{std::min(b1, b2), std::max(b1, b2)};
    if (std::find(r.bodies.begin(), r.bodies.end(), pair) == r.bodies.end()) r.bodies.push_back(pair);
  }
  if (rank < 3) r.kind = static_cast<ContactKind>(rank);
  return r;
}

std::string CollisionChecker::bodyName(int body) const {
  if (body < 0) return "floor";
  const char* name = mj_id2name(model_.get(), mjOBJ_BODY, body);
  return name && *name ? name : "body " + std::to_string(body);
}

}  // namespace lowpair::mujoco
