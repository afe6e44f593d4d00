#include "mujoco/mujoco_dynamics.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <map>

#include "io/robot_file.hpp"
#include "mujoco/messages.hpp"
#include "mujoco/model_copy.hpp"

namespace lowpair::mujoco {

namespace {

// MuJoCo joint id -> the library joint it belongs to (a helical joint's hinge and slide both map to it).
std::map<int, int> libraryJointOf(const MujocoRobot& robot, const mjModel* m) {
  std::map<int, int> of;
  for (int i = 0; i < robot.dof(); ++i) {
    const MujocoJoint& j = robot.joints()[static_cast<size_t>(i)];
    for (int dof : {j.dof, j.slide_dof}) {
      if (dof >= 0) of[m->dof_jntid[dof]] = i;
    }
  }
  return of;
}

// The copies of one file hold the same joints at the same addresses: checked, as the masses and the
// gravity force read MujocoRobot's addresses in this model.
void requireSameChain(const MujocoRobot& robot, const mjModel* m) {
  for (const MujocoJoint& j : robot.joints()) {
    for (auto [qpos, dof] : {std::pair{j.qpos, j.dof}, std::pair{j.slide_qpos, j.slide_dof}}) {
      if (dof < 0) continue;
      const bool same = dof < m->nv && qpos < m->nq && m->jnt_qposadr[m->dof_jntid[dof]] == qpos;
      if (!same) io::failFile(robot.path(), "joint '" + j.name + "' is not at the same place in the copy with masses");
    }
  }
  if (robot.tipBody() >= m->nbody || robot.baseBody() >= m->nbody) {
    io::failFile(robot.path(), "the copy with masses lacks the tip's or the base's body");
  }
}

// For each body, the library joint whose link it belongs to: that of the nearest body from it towards the
// base that carries chain joints (the last of them), or -1 when no chain joint moves it.
std::vector<int> linkOfBodies(const MujocoRobot& robot, const mjModel* m) {
  const std::map<int, int> joint_of = libraryJointOf(robot, m);
  std::vector<int> link(static_cast<size_t>(m->nbody), -1);
  for (int b = 1; b < m->nbody; ++b) {
    for (int c = b; c != 0 && c != robot.baseBody(); c = m->body_parentid[c]) {
      int last = -1;
      for (int k = m->body_jntadr[c]; k < m->body_jntadr[c] + m->body_jntnum[c]; ++k) {
        auto it = joint_of.find(k);
        if (it != joint_of.end()) last = std::max(last, it->second);
      }
      if (last >= 0) {
        link[static_cast<size_t>(b)] = last;
        break;
      }
    }
  }
  return link;
}

// The body a ModelCopy::massFromGeoms entry names ("'name'"), or -1 (unnamed: "FILE: line N").
int bodyOfEntry(const mjModel* m, const std::string& entry) {
  if (entry.size() < 2 || entry.front() != '\'' || entry.back() != '\'') return -1;
  return mj_name2id(m, mjOBJ_BODY, entry.substr(1, entry.size() - 2).c_str());
}

ModelMasses readMasses(const MujocoRobot& robot, const mjModel* m, const std::vector<std::string>& from_geoms) {
  ModelMasses out;
  const std::vector<int> link = linkOfBodies(robot, m);
  for (const std::string& entry : from_geoms) {
    const int b = bodyOfEntry(m, entry);
    if (b < 0 || link[static_cast<size_t>(b)] >= 0) out.bodies.push_back(entry);  // unnamed: cannot tell
  }
  if (!out.bodies.empty()) {
    out.status = MassStatus::MassFromGeoms;
    return out;
  }
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m), mj_deleteData);
  mj_kinematics(m, d.get());  // at qpos0 (mj_makeData's qpos)
  const size_t n = robot.joints().size();
  std::vector<double> mass(n, 0.0);
  std::vector<Vec3> moment(n, Vec3::Zero());  // sum of m * xipos (world)
  bool weighs = false;
  for (int b = 1; b < m->nbody; ++b) {
    const int i = link[static_cast<size_t>(b)];
    if (i < 0) continue;
    mass[static_cast<size_t>(i)] += m->body_mass[b];
    moment[static_cast<size_t>(i)] += m->body_mass[b] * Eigen::Map<const Vec3>(d->xipos + 3 * b);
    weighs = weighs || m->body_mass[b] > kCopyBoundMass;
  }
  if (!weighs) {
    out.status = MassStatus::NoInertials;
    return out;
  }
  for (size_t i = 0; i < n; ++i) {
    PointMass p;
    p.mass = mass[i];
    if (mass[i] > 0) p.com = robot.T_base_world() * Vec3(moment[i] / mass[i]);
    out.masses.links.push_back(p);
  }
  const Vec3 g_world = Eigen::Map<const Vec3>(m->opt.gravity);
  out.masses.gravity = (m->opt.disableflags & mjDSBL_GRAVITY) ? Vec3::Zero() : Vec3(robot.T_base_world().R * g_world);
  out.masses.metres_per_unit = 1.0;
  return out;
}

}  // namespace

std::string massProblem(const ModelMasses& masses, const std::string& path) {
  switch (masses.status) {
    case MassStatus::Ok:
      return "";
    case MassStatus::NoInertials:
      return path + ": no masses: no body the chain moves has a mass above the bound " +
             "(1e-6 kg) a model copy gives a body without <inertial>";
    case MassStatus::MassFromGeoms: {
      std::string names;
      for (const std::string& b : masses.bodies) names += (names.empty() ? "" : ", ") + b;
      return path + ": no masses: the mass of " + names + " comes from geometry (no <inertial>, or compiler " +
             "inertiafromgeom='true'), which lowpair does not read: give the bodies an <inertial>";
    }
  }
  return "";
}

void MujocoDynamics::ModelDeleter::operator()(mjModel_* m) const { mj_deleteModel(m); }

MujocoDynamics::MujocoDynamics(const MujocoRobot& robot) : robot_(&robot) {
  installMujocoHandlers();
  setLoadingModel(robot.path());
  const ModelCopy copy(robot.path(), nullptr, CopyContent::Inertials);  // MujocoRobot printed the notes
  char error[1000] = "";
  model_.reset(mj_loadXML(copy.path().c_str(), nullptr, error, sizeof error));
  if (!model_) io::failFile(robot.path(), "MuJoCo could not load the model with its masses: " + mujocoLine(error));
  requireSameChain(robot, model_.get());
  masses_ = readMasses(robot, model_.get(), copy.massFromGeoms());
}

MujocoDynamics::~MujocoDynamics() = default;

void setChainConfiguration(const MujocoRobot& robot, const mjModel* m, mjData* d, const Eigen::Ref<const VecX>& x) {
  std::copy(m->qpos0, m->qpos0 + m->nq, d->qpos);
  std::fill(d->qvel, d->qvel + m->nv, 0.0);
  for (size_t i = 0; i < robot.joints().size(); ++i) {
    const MujocoJoint& j = robot.joints()[i];
    const double xi = x[static_cast<Eigen::Index>(i)];
    d->qpos[j.qpos] = m->qpos0[j.qpos] + xi;
    if (j.slide_qpos >= 0) d->qpos[j.slide_qpos] = m->qpos0[j.slide_qpos] + j.pitch * xi;
  }
}

VecX chainForce(const MujocoRobot& robot, const double* f) {
  VecX out(robot.dof());
  for (size_t i = 0; i < robot.joints().size(); ++i) {
    const MujocoJoint& j = robot.joints()[i];
    out[static_cast<Eigen::Index>(i)] = f[j.dof] + (j.slide_dof >= 0 ? j.pitch * f[j.slide_dof] : 0.0);
  }
  return out;
}

MujocoDynamics::Evaluator::Evaluator(const MujocoDynamics& dynamics)
    : dynamics_(&dynamics), data_(mj_makeData(dynamics.model_.get()), mj_deleteData) {}

MujocoDynamics::Evaluator::~Evaluator() = default;
MujocoDynamics::Evaluator::Evaluator(Evaluator&&) noexcept = default;

VecX MujocoDynamics::Evaluator::gravityForce(const Eigen::Ref<const VecX>& x) {
  const mjModel* m = dynamics_->model_.get();
  mjData* d = data_.get();
  if (x.size() != dynamics_->robot().dof()) {
    throw std::invalid_argument("gravityForce: expected " + std::to_string(dynamics_->robot().dof()) +
                                " joint values, got " + std::to_string(x.size()));
  }
  setChainConfiguration(dynamics_->robot(), m, d, x);
  mj_fwdPosition(m, d);
  mj_fwdVelocity(m, d);  // qfrc_bias: at zero velocity, the force that holds the robot against gravity
  return -chainForce(dynamics_->robot(), d->qfrc_bias);
}

}  // namespace lowpair::mujoco
