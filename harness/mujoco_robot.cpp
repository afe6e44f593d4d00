#include "mujoco_robot.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <mutex>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

#include "lowpair/se3.hpp"
#include "robot_file.hpp"

namespace lowpair {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw RobotFileError(path + ": " + what); }

Pose poseFrom(const mjtNum* pos, const mjtNum* mat) {
  Pose T;
  for (int r = 0; r < 3; ++r) {
    T.p[r] = pos[r];
    for (int c = 0; c < 3; ++c) T.R(r, c) = mat[3 * r + c];
  }
  return T;
}

// MuJoCo 2.2 reads URDF but fuses links attached by fixed joints and rejects massless links; there is
// no API for either, so load a temporary copy carrying <mujoco><compiler .../></mujoco>.
std::string urdfCopy(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const auto robot = s.find("<robot");
  if (robot == std::string::npos) fail(path, "no <robot> element: not a URDF");
  const auto close = s.find('>', robot);
  // the copy lives in the temp folder: relative mesh paths resolve against the original's folder
  const std::string folder = std::filesystem::absolute(path).parent_path().string();
  s.insert(close + 1, "\n<mujoco><compiler fusestatic=\"false\" discardvisual=\"true\" boundmass=\"1e-6\" "
                      "boundinertia=\"1e-9\" strippath=\"false\" meshdir=\"" + folder + "\"/></mujoco>\n");
  // mkstemps replaces the six Xs with a unique suffix and keeps the 5-character ".urdf" extension
  std::string copy = (std::filesystem::temp_directory_path() / "lowpair_urdf_XXXXXX.urdf").string();
  const int fd = mkstemps(copy.data(), 5);
  if (fd < 0) fail(path, "cannot create a temporary copy");
  ::close(fd);
  std::ofstream(copy) << s;
  return copy;
}

}  // namespace

namespace {

// MuJoCo's messages on one line (its load errors and warnings span several).
std::string oneLine(const char* text) {
  std::string s = text ? text : "";
  for (char& ch : s) {
    if (ch == '\n' || ch == '\r' || ch == '\t') ch = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// The model being loaded, for MuJoCo's error handler (which gets no context).
thread_local std::string g_loading = "MuJoCo";

// MuJoCo's default handlers print to stdout (breaking --json) and append to MUJOCO_LOG.TXT in the
// working directory. Ours: warnings as one "note:" line on stderr; a fatal error (MuJoCo must not
// continue after one) as the CLI's one "error: FILE: what" line and exit status 2.
void installMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_warning = [](const char* msg) { std::fprintf(stderr, "note: MuJoCo: %s\n", oneLine(msg).c_str()); };
    mju_user_error = [](const char* msg) {
      std::fprintf(stderr, "error: %s: MuJoCo: %s\n", g_loading.c_str(), oneLine(msg).c_str());
      std::fflush(stderr);
      std::_Exit(2);
    };
  });
}

}  // namespace

void MujocoRobot::ModelDeleter::operator()(mjModel_* m) const { mj_deleteModel(m); }

MujocoRobot::MujocoRobot(const std::string& path, const std::string& tip, const std::string& base)
{
  {
    std::ifstream probe(path);
    if (!probe) fail(path, "cannot open file");
  }
  const bool urdf = path.size() > 5 && path.substr(path.size() - 5) == ".urdf";
  const std::string load_path = urdf ? urdfCopy(path) : path;
  char error[1000] = "";
  installMujocoHandlers();
  g_loading = path;
  model_.reset(mj_loadXML(load_path.c_str(), nullptr, error, sizeof error));
  if (urdf) std::remove(load_path.c_str());
  if (!model_) fail(path, "MuJoCo could not load the model: " + oneLine(error));
  const mjModel* m = model_.get();

  tip_site_ = mj_name2id(m, mjOBJ_SITE, tip.c_str());
  if (tip_site_ < 0) tip_body_ = mj_name2id(m, mjOBJ_BODY, tip.c_str());
  if (tip_site_ < 0 && tip_body_ < 0) fail(path, "tip '" + tip + "' is neither a site nor a body");
  if (!base.empty()) {
    base_body_ = mj_name2id(m, mjOBJ_BODY, base.c_str());
    if (base_body_ < 0) fail(path, "base '" + base + "' is not a body");
  }
  const int tip_owner = tip_site_ >= 0 ? m->site_bodyid[tip_site_] : tip_body_;

  // the chain: bodies from the tip's up to (excluding) the base
  std::vector<int> bodies;
  for (int b = tip_owner; b != base_body_; b = m->body_parentid[b]) {
    if (b == 0) fail(path, "base '" + base + "' is not an ancestor of the tip '" + tip + "'");
    bodies.push_back(b);
  }
  std::reverse(bodies.begin(), bodies.end());

  // joint equalities: slide (obj1) driven by hinge (obj2)
  std::map<int, std::pair<int, double>> coupled_slide;  // slide joint -> (hinge joint, pitch)
  for (int e = 0; e < m->neq; ++e) {
    if (m->eq_type[e] != mjEQ_JOINT) continue;
    const int j1 = m->eq_obj1id[e], j2 = m->eq_obj2id[e];
    const mjtNum* c = m->eq_data + mjNEQDATA * e;
    const char* n1 = mj_id2name(m, mjOBJ_JOINT, j1);
    const std::string label = "joint equality " + std::string(n1 ? n1 : "?");
    if (j2 < 0) continue;  // a joint fixed to a polynomial of nothing: not a coupling we model
    if (m->jnt_type[j1] != mjJNT_SLIDE || m->jnt_type[j2] != mjJNT_HINGE) {
      fail(path, label + ": only a slide (joint1) driven by a hinge (joint2) is supported (a helical joint)");
    }
    if (c[0] != 0 || c[2] != 0 || c[3] != 0 || c[4] != 0) {
      fail(path, label + ": polycoef must be \"0 h 0 0 0\" (a linear coupling slide = h * hinge)");
    }
    coupled_slide[j1] = {j2, c[1]};
  }

  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m), mj_deleteData);
  mj_kinematics(m, d.get());
  const Pose T_world_base =
      base_body_ == 0 ? Pose() : poseFrom(d->xpos + 3 * base_body_, d->xmat + 9 * base_body_);
  T_base_world_ = T_world_base.inverse();
  const Pose& T_base_world = T_base_world_;

  std::vector<JointSpec> specs;
  std::map<int, size_t> hinge_to_joint;
  for (int b : bodies) {
    for (int k = 0; k < m->body_jntnum[b]; ++k) {
      const int j = m->body_jntadr[b] + k;
      const char* raw = mj_id2name(m, mjOBJ_JOINT, j);
      const std::string name = raw ? raw : "joint" + std::to_string(j);
      const int type = m->jnt_type[j];
      if (type == mjJNT_FREE || type == mjJNT_BALL) {
        fail(path, "joint '" + name + "' is a " + (type == mjJNT_FREE ? "free" : "ball") +
                       " joint: only hinges, slides and coupled hinge+slide pairs form a serial chain of lower pairs");
      }
      const Vec3 axis = T_base_world.R * Vec3(d->xaxis[3 * j], d->xaxis[3 * j + 1], d->xaxis[3 * j + 2]);
      const Vec3 anchor = T_base_world * Vec3(d->xanchor[3 * j], d->xanchor[3 * j + 1], d->xanchor[3 * j + 2]);
      auto coupled = coupled_slide.find(j);
      if (coupled != coupled_slide.end()) {
        const int hinge = coupled->second.first;
        auto it = hinge_to_joint.find(hinge);
        if (it == hinge_to_joint.end()) {
          fail(path, "slide '" + name + "' is coupled to a hinge that does not precede it in the same chain");
        }
        MujocoJoint& mj = joints_[it->second];
        JointSpec& spec = specs[it->second];
        const Vec3 w = spec.twist.head<3>();
        if (w.cross(axis).norm() > 1e-9 || m->jnt_bodyid[hinge] != b) {
          fail(path, "slide '" + name + "' must be on the same body and axis as its hinge to form a helical joint");
        }
        const double h = coupled->second.second * w.dot(axis);  // slide axis may be anti-parallel
        mj.type = JointType::Helical;
        mj.slide_qpos = m->jnt_qposadr[j];
        mj.slide_dof = m->jnt_dofadr[j];
        mj.pitch = coupled->second.second;
        spec.type = JointType::Helical;
        spec.twist.tail<3>() += h * w;
        continue;
      }
      MujocoJoint mj;
      mj.name = name;
      mj.qpos = m->jnt_qposadr[j];
      mj.dof = m->jnt_dofadr[j];
      if (m->jnt_limited[j]) mj.range = std::array<double, 2>{m->jnt_range[2 * j], m->jnt_range[2 * j + 1]};
      JointSpec spec;
      spec.name = name;
      spec.range = mj.range;
      if (type == mjJNT_HINGE) {
        mj.type = JointType::Revolute;
        spec.type = JointType::Revolute;
        spec.twist << axis, anchor.cross(axis);
        // qpos0 (ref) is the zero of the joint variable; the anchor and axis above are at qpos0
        hinge_to_joint[j] = joints_.size();
      } else {
        mj.type = JointType::Prismatic;
        spec.type = JointType::Prismatic;
        spec.twist << Vec3::Zero(), axis;
      }
      joints_.push_back(mj);
      specs.push_back(spec);
    }
  }
  if (joints_.empty()) fail(path, "no joint between the base and the tip '" + tip + "'");
  const Pose T_world_tip = tip_site_ >= 0 ? poseFrom(d->site_xpos + 3 * tip_site_, d->site_xmat + 9 * tip_site_)
                                          : poseFrom(d->xpos + 3 * tip_body_, d->xmat + 9 * tip_body_);
  try {
    poe_ = std::make_unique<PoeModel>(specs, T_base_world * T_world_tip, path);
  } catch (const std::invalid_argument& e) {
    fail(path, e.what());
  }
}

MujocoRobot::~MujocoRobot() = default;

MujocoRobot::Evaluator::Evaluator(const MujocoRobot& robot)
    : robot_(&robot), data_(mj_makeData(robot.model_.get()), mj_deleteData) {
  const int nv = robot.model_->nv;
  jacp_.resize(static_cast<size_t>(3 * nv));
  jacr_.resize(static_cast<size_t>(3 * nv));
}

MujocoRobot::Evaluator::~Evaluator() = default;
MujocoRobot::Evaluator::Evaluator(Evaluator&&) noexcept = default;

void MujocoRobot::Evaluator::setConfiguration(const Eigen::Ref<const VecX>& x) {
  const mjModel* m = robot_->model_.get();
  mjData* d = data_.get();
  std::copy(m->qpos0, m->qpos0 + m->nq, d->qpos);
  for (size_t i = 0; i < robot_->joints_.size(); ++i) {
    const MujocoJoint& j = robot_->joints_[i];
    const double xi = x[static_cast<Eigen::Index>(i)];
    d->qpos[j.qpos] = m->qpos0[j.qpos] + xi;
    // mj_kinematics ignores equalities: drive the coupled slide ourselves
    if (j.slide_qpos >= 0) d->qpos[j.slide_qpos] = m->qpos0[j.slide_qpos] + j.pitch * xi;
  }
  mj_kinematics(m, d);
}

Pose MujocoRobot::Evaluator::worldTip() const {
  const mjData* d = data_.get();
  const int s = robot_->tip_site_, b = robot_->tip_body_;
  return s >= 0 ? poseFrom(d->site_xpos + 3 * s, d->site_xmat + 9 * s) : poseFrom(d->xpos + 3 * b, d->xmat + 9 * b);
}

Pose MujocoRobot::Evaluator::tipPose(const Eigen::Ref<const VecX>& x) {
  setConfiguration(x);
  return robot_->T_base_world_ * worldTip();
}

Pose MujocoRobot::Evaluator::tipJacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<Mat6X> J) {
  setConfiguration(x);
  const mjModel* m = robot_->model_.get();
  mjData* d = data_.get();
  mj_comPos(m, d);
  if (robot_->tip_site_ >= 0) {
    mj_jacSite(m, d, jacp_.data(), jacr_.data(), robot_->tip_site_);
  } else {
    mj_jacBody(m, d, jacp_.data(), jacr_.data(), robot_->tip_body_);
  }
  const Mat3& R_base_world = robot_->T_base_world_.R;
  const int nv = m->nv;
  for (size_t i = 0; i < robot_->joints_.size(); ++i) {
    const MujocoJoint& j = robot_->joints_[i];
    Vec3 v, w;
    for (int r = 0; r < 3; ++r) {
      v[r] = jacp_[static_cast<size_t>(r * nv + j.dof)];
      w[r] = jacr_[static_cast<size_t>(r * nv + j.dof)];
      if (j.slide_dof >= 0) {
        v[r] += j.pitch * jacp_[static_cast<size_t>(r * nv + j.slide_dof)];
        w[r] += j.pitch * jacr_[static_cast<size_t>(r * nv + j.slide_dof)];
      }
    }
    // a base body moved by joints outside the chain would need its own velocity; the base is fixed here
    J.col(static_cast<Eigen::Index>(i)) << R_base_world * v, R_base_world * w;
  }
  return robot_->T_base_world_ * worldTip();
}

}  // namespace lowpair
