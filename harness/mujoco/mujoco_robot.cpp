#include "mujoco/mujoco_robot.hpp"

#include <mujoco/mujoco.h>

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>

#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "mujoco/messages.hpp"
#include "mujoco/model_copy.hpp"
#include "io/robot_file.hpp"
#include "io/urdf_reader.hpp"

namespace lowpair::mujoco {

using namespace lowpair::io;  // the rooms below

namespace {

Pose poseFrom(const mjtNum* pos, const mjtNum* mat) {
  Pose T;
  for (int r = 0; r < 3; ++r) {
    T.p[r] = pos[r];
    for (int c = 0; c < 3; ++c) T.R(r, c) = mat[3 * r + c];
  }
  return T;
}

}  // namespace

namespace {

// A hinge's qpos0 (its ref) beyond this, in rad, is no usable zero: qpos = qpos0 + x rounds x to
// ulp(qpos0) / 2 (1.1e-13 rad at 1000), and the acceptance bound is 1e-12. A slide's bound is this many
// model lengths (the farthest joint anchor or the tip from the base at qpos0, at least 1).
constexpr double kMaxRef = 1e3;

bool finite(const Vec3& v) { return v.allFinite(); }

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

// True when body `a` is `b` or one of its ancestors (the world is everyone's).
bool ancestorOrSelf(const mjModel* m, int a, int b) {
  for (; b > 0; b = m->body_parentid[b]) {
    if (b == a) return true;
  }
  return a == 0;
}

std::string nameOf(const mjModel* m, int type, int id, const char* fallback) {
  if (id < 0) return "";
  const char* n = mj_id2name(m, type, id);
  return n ? n : std::string(fallback) + std::to_string(id);
}

// An equality constraint as the element it came from, e.g. <equality><weld body1='a' body2='world'>.
std::string describeEquality(const mjModel* m, int e) {
  const int o1 = m->eq_obj1id[e], o2 = m->eq_obj2id[e];
  std::string s;
  switch (m->eq_type[e]) {
    case mjEQ_CONNECT:
    case mjEQ_WELD:
      s = std::string(m->eq_type[e] == mjEQ_CONNECT ? "connect" : "weld") + " body1='" + nameOf(m, mjOBJ_BODY, o1, "body") +
          "' body2='" + (o2 > 0 ? nameOf(m, mjOBJ_BODY, o2, "body") : "world") + "'";
      break;
    case mjEQ_JOINT:
      s = "joint joint1='" + nameOf(m, mjOBJ_JOINT, o1, "joint") + "'" +
          (o2 >= 0 ? " joint2='" + nameOf(m, mjOBJ_JOINT, o2, "joint") + "'" : "");
      break;
    case mjEQ_TENDON:
      s = "tendon tendon1='" + nameOf(m, mjOBJ_TENDON, o1, "tendon") + "'" +
          (o2 >= 0 ? " tendon2='" + nameOf(m, mjOBJ_TENDON, o2, "tendon") + "'" : "");
      break;
    default:
      s = "distance";
  }
  const char* name = mj_id2name(m, mjOBJ_EQUALITY, e);
  if (name) s += " name='" + std::string(name) + "'";
  return "<equality><" + s + ">";
}

// The names of objects first .. count-1 of a type, for a message: the first 20, unnamed ones skipped.
std::string namesOf(const mjModel* m, int type, int count, int first) {
  std::string s;
  int listed = 0, named = 0;
  for (int id = first; id < count; ++id) {
    const char* name = mj_id2name(m, type, id);
    if (!name || !*name) continue;
    ++named;
    if (listed < 20) s += (listed++ ? ", '" : "'") + mujocoLine(name) + "'";
  }
  if (named > listed) s += ", ... (" + std::to_string(named) + " named)";
  return listed ? s : "none named";
}

// A URDF's <mimic> joints (joint -> the joint it follows): MuJoCo 2.2.2 ignores <mimic>.
std::map<std::string, std::string> urdfMimics(const std::string& path) {
  std::map<std::string, std::string> mimics;
  tinyxml2::XMLDocument doc;
  requireBoundedModelFile(path);
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS || !doc.RootElement()) return mimics;
  const tinyxml2::XMLElement* robot = doc.RootElement();
  if (std::string(robot->Name()) != "robot") return mimics;
  for (const auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const auto* mimic = j->FirstChildElement("mimic");
    const char* name = j->Attribute("name");
    if (mimic && name) mimics[name] = mimic->Attribute("joint") ? mimic->Attribute("joint") : "?";
  }
  return mimics;
}

}  // namespace

void MujocoRobot::ModelDeleter::operator()(mjModel_* m) const { mj_deleteModel(m); }

namespace {

// The chain from the base to the tip's body: its bodies (base side first) and their joints.
struct Chain {
  const mjModel* m = nullptr;
  std::vector<int> bodies;
  std::set<int> joints;

  std::string jointName(int j) const { return nameOf(m, mjOBJ_JOINT, j, "joint"); }

  // a chain joint whose motion changes the relative pose of the given bodies, or -1
  int jointBetween(const std::vector<int>& touched) const {
    for (int j : joints) {
      size_t below = 0;
      for (int b : touched) below += ancestorOrSelf(m, m->jnt_bodyid[j], b);
      if (below > 0 && below < touched.size()) return j;
    }
    return -1;
  }

  // a chain joint a tendon's length depends on, or -1
  int jointOfTendon(int t) const {
    std::vector<int> touched;
    for (int w = m->tendon_adr[t]; w < m->tendon_adr[t] + m->tendon_num[t]; ++w) {
      const int obj = m->wrap_objid[w];
      if (m->wrap_type[w] == mjWRAP_JOINT && joints.count(obj)) return obj;
      if (m->wrap_type[w] == mjWRAP_SITE) touched.push_back(m->site_bodyid[obj]);
      if (m->wrap_type[w] == mjWRAP_SPHERE || m->wrap_type[w] == mjWRAP_CYLINDER) touched.push_back(m->geom_bodyid[obj]);
    }
    return jointBetween(touched);
  }
};

// The bodies from the tip's up to (excluding) the base, and their joints.
Chain findChain(const mjModel* m, const std::string& path, int tip_owner, int base_body, const std::string& tip,
                const std::string& base) {
  Chain chain;
  chain.m = m;
  for (int b = tip_owner; b != base_body; b = m->body_parentid[b]) {
    if (b == 0) io::failFile(path, "base " + io::quotedFileText(base) + " is not an ancestor of the tip " + io::quotedFileText(tip));
    chain.bodies.push_back(b);
  }
  std::reverse(chain.bodies.begin(), chain.bodies.end());
  for (int b : chain.bodies) {
    for (int k = 0; k < m->body_jntnum[b]; ++k) chain.joints.insert(m->body_jntadr[b] + k);
  }
  io::requireJointCount(path, chain.joints.size());
  return chain;
}

// Equalities (active ones: MuJoCo enforces no other) that constrain the chain's joints. The only one
// modelled: a chain slide (joint1) driven by a chain hinge (joint2) on the same body and axis, linearly
// (a helical joint). A joint outside the chain driven by a chain joint constrains nothing of the chain.
// @return slide joint -> (hinge joint, pitch)
std::map<int, std::pair<int, double>> helicalCouplings(const Chain& chain, const std::string& path) {
  const mjModel* m = chain.m;
  const auto& chain_joints = chain.joints;
  const auto jointName = [&](int j) { return chain.jointName(j); };
  std::map<int, std::pair<int, double>> coupled_slide;  // slide joint -> (hinge joint, pitch)
  std::map<int, int> slide_of_hinge;
  const std::string unmodelled = ": the extraction models an open chain of independent lower pairs only";
  for (int e = 0; e < m->neq; ++e) {
    if (!m->eq_active[e]) continue;
    const std::string label = describeEquality(m, e);
    const int o1 = m->eq_obj1id[e], o2 = m->eq_obj2id[e];
    switch (m->eq_type[e]) {
      case mjEQ_CONNECT:
      case mjEQ_WELD: {
        const int j = chain.jointBetween({o1, o2 > 0 ? o2 : 0});
        if (j >= 0) io::failFile(path, label + " closes a loop through the chain joint '" + jointName(j) + "'" + unmodelled);
        break;
      }
      case mjEQ_TENDON:
        for (int t : {o1, o2}) {
          if (t < 0) continue;
          const int j = chain.jointOfTendon(t);
          if (j >= 0) io::failFile(path, label + " couples the chain joint '" + jointName(j) + "'" + unmodelled);
        }
        break;
      case mjEQ_JOINT: {
        if (!chain_joints.count(o1)) break;
        if (o2 < 0) io::failFile(path, label + " fixes the chain joint '" + jointName(o1) + "'" + unmodelled);
        if (!chain_joints.count(o2)) {
          io::failFile(path, label + " couples the chain joint '" + jointName(o1) + "' to '" + jointName(o2) +
                         "', which is not in the chain" + unmodelled);
        }
        if (m->jnt_type[o1] != mjJNT_SLIDE || m->jnt_type[o2] != mjJNT_HINGE) {
          io::failFile(path, label + ": only a slide (joint1) driven by a hinge (joint2) is supported (a helical joint)");
        }
        const mjtNum* c = m->eq_data + mjNEQDATA * e;
        if (c[0] != 0 || c[2] != 0 || c[3] != 0 || c[4] != 0) {
          io::failFile(path, label + ": polycoef must be \"0 h 0 0 0\" (a linear coupling slide = h * hinge)");
        }
        if (coupled_slide.count(o1)) {
          io::failFile(path, label + ": the slide '" + jointName(o1) + "' is already driven by the hinge '" +
                         jointName(coupled_slide[o1].first) + "'" + unmodelled);
        }
        if (slide_of_hinge.count(o2)) {
          io::failFile(path, label + ": the hinge '" + jointName(o2) + "' already drives the slide '" +
                         jointName(slide_of_hinge[o2]) + "'; one hinge drives at most one slide (a helical joint)");
        }
        coupled_slide[o1] = {o2, c[1]};
        slide_of_hinge[o2] = o1;
        break;
      }
      default:
        io::failFile(path, label + unmodelled);
    }
  }
  return coupled_slide;
}

// MuJoCo 2.2.2 ignores a URDF's <mimic>: a mimicking chain joint would be sampled as independent.
void rejectMimics(const Chain& chain, const std::string& path) {
  const std::map<std::string, std::string> mimics = urdfMimics(path);
  for (int j : chain.joints) {
    auto it = mimics.find(chain.jointName(j));
    if (it != mimics.end()) {
      io::failFile(path, "joint '" + it->first + "' mimics '" + it->second +
                     "' (URDF <mimic>), which MuJoCo 2.2.2 ignores: MuJoCo would move it independently");
    }
  }

}

// MuJoCo 2.2.2 keeps a zero `quat` as a zero quaternion: MuJoCo's own kinematics of the body is then
// meaningless (its joints do not move it), so the model is bad input, not a failed validation.
void requireRotations(const mjModel* m, const mjData* d, const std::vector<int>& framed, const std::string& path) {
  for (int b : framed) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->xmat + 9 * b);
    const double defect = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
    // the compiled body quat, which MuJoCo keeps as given when it cannot normalize it: at qpos0 the frame
    // then looks like the identity, and every joint motion of the body is lost in the product with it
    const Eigen::Map<const Eigen::Vector4d> quat(m->body_quat + 4 * b);
    if (!(defect <= kRotationOrthonormal) || !(std::abs(quat.norm() - 1.0) <= kRotationOrthonormal)) {
      io::failFile(path, "body '" + nameOf(m, mjOBJ_BODY, b, "body") +
                     "': its orientation is not a rotation (a zero quat, or an orientation MuJoCo cannot normalize)");
    }
  }
}

}  // namespace

namespace {

// The chain's joints at qpos0 in the base frame: `joints_` (MuJoCo's addresses, appended) and the
// library's joint specs (returned); a coupled slide makes its hinge helical.
std::vector<JointSpec> extractJoints(const Chain& chain, const mjData* d,
                                     const std::map<int, std::pair<int, double>>& coupled_slide,
                                     const Pose& T_base_world, const Pose& T_base_tip, const std::string& path,
                                     std::vector<MujocoJoint>& joints) {
  const mjModel* m = chain.m;
  const auto jointName = [&](int j) { return chain.jointName(j); };
  std::vector<JointSpec> specs;
  std::vector<std::pair<std::string, double>> slide_refs;  // checked once the model's length is known
  std::map<int, size_t> hinge_to_joint;
  double length = T_base_tip.p.norm();
  for (int b : chain.bodies) {
    for (int k = 0; k < m->body_jntnum[b]; ++k) {
      const int j = m->body_jntadr[b] + k;
      const std::string name = jointName(j);
      const int type = m->jnt_type[j];
      if (type == mjJNT_FREE || type == mjJNT_BALL) {
        io::failFile(path, "joint '" + name + "' is a " + (type == mjJNT_FREE ? "free" : "ball") +
                       " joint: only hinges, slides and coupled hinge+slide pairs form a serial chain of lower pairs");
      }
      const double ref = m->qpos0[m->jnt_qposadr[j]];
      if (!std::isfinite(ref) || (type == mjJNT_HINGE && std::abs(ref) > kMaxRef)) {
        io::failFile(path, "joint '" + name + "': qpos0 (its ref) " + number(ref) +
                       " is no usable zero (qpos = qpos0 + x must resolve x; |qpos0| <= 1000 rad)");
      }
      if (type == mjJNT_SLIDE) slide_refs.emplace_back(name, ref);
      const Vec3 axis = T_base_world.R * Vec3(d->xaxis[3 * j], d->xaxis[3 * j + 1], d->xaxis[3 * j + 2]);
      const Vec3 anchor = T_base_world * Vec3(d->xanchor[3 * j], d->xanchor[3 * j + 1], d->xanchor[3 * j + 2]);
      if (!finite(axis) || !finite(anchor)) io::failFile(path, "joint '" + name + "': its axis or anchor at qpos0 is not finite");
      length = std::max(length, anchor.norm());
      auto coupled = coupled_slide.find(j);
      if (coupled != coupled_slide.end()) {
        const int hinge = coupled->second.first;
        auto it = hinge_to_joint.find(hinge);
        if (it == hinge_to_joint.end()) {
          io::failFile(path, "slide '" + name + "' is coupled to a hinge that does not precede it in the same chain");
        }
        MujocoJoint& mj = joints[it->second];
        JointSpec& spec = specs[it->second];
        const Vec3 w = spec.twist.head<3>();
        if (w.cross(axis).norm() > 1e-9 || m->jnt_bodyid[hinge] != b) {
          io::failFile(path, "slide '" + name + "' must be on the same body and axis as its hinge to form a helical joint");
        }
        const double h = coupled->second.second * w.dot(axis);  // slide axis may be anti-parallel
        if (!std::isfinite(h)) io::failFile(path, "slide '" + name + "': its pitch is not finite");
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
      if (m->jnt_limited[j]) {
        mj.range = std::array<double, 2>{m->jnt_range[2 * j], m->jnt_range[2 * j + 1]};
        if (!std::isfinite((*mj.range)[0]) || !std::isfinite((*mj.range)[1])) {
          io::failFile(path, "joint '" + name + "': its range is not finite");
        }
      }
      JointSpec spec;
      spec.name = name;
      spec.range = mj.range;
      if (type == mjJNT_HINGE) {
        mj.type = JointType::Revolute;
        spec.type = JointType::Revolute;
        spec.twist << axis, anchor.cross(axis);
        // qpos0 (ref) is the zero of the joint variable; the anchor and axis above are at qpos0
        hinge_to_joint[j] = joints.size();
      } else {
        mj.type = JointType::Prismatic;
        spec.type = JointType::Prismatic;
        spec.twist << Vec3::Zero(), axis;
      }
      joints.push_back(mj);
      specs.push_back(spec);
    }
  }
  for (const auto& [name, ref] : slide_refs) {
    if (std::abs(ref) > kMaxRef * std::max(1.0, length)) {
      io::failFile(path, "joint '" + name + "': qpos0 (its ref) " + number(ref) + " is no usable zero (qpos = qpos0 + x must " +
                     "resolve x; |qpos0| <= 1000 model lengths, here " + number(kMaxRef * std::max(1.0, length)) + ")");
    }
  }
  return specs;
}

}  // namespace

MujocoRobot::MujocoRobot(const std::string& path, const std::string& tip, const std::string& base)
    : path_(path), tip_(tip) {
  installMujocoHandlers();
  setLoadingModel(path);
  std::vector<std::string> notes;
  {
    const ModelCopy copy(path, &notes);  // kinematics only; it loaded once already
    char error[1000] = "";
    model_.reset(mj_loadXML(copy.path().c_str(), nullptr, error, sizeof error));
    if (!model_) io::failFile(path, "MuJoCo could not load the model: " + mujocoLine(error));
    if (error[0]) notes.push_back(path + ": MuJoCo: " + mujocoLine(error));  // a warning
  }
  const mjModel* m = model_.get();

  tip_site_ = mj_name2id(m, mjOBJ_SITE, tip.c_str());
  if (tip_site_ < 0) tip_body_ = mj_name2id(m, mjOBJ_BODY, tip.c_str());
  if (tip_site_ < 0 && tip_body_ < 0) {
    io::failFile(path, "tip " + io::quotedFileText(tip) + " is neither a site nor a body; sites: " + namesOf(m, mjOBJ_SITE, m->nsite, 0) +
                   "; bodies: " + namesOf(m, mjOBJ_BODY, m->nbody, 1));
  }
  if (!base.empty()) {
    base_body_ = mj_name2id(m, mjOBJ_BODY, base.c_str());
    if (base_body_ < 0) io::failFile(path, "base " + io::quotedFileText(base) + " is not a body; bodies: " + namesOf(m, mjOBJ_BODY, m->nbody, 1));
  }
  const int tip_owner = tip_site_ >= 0 ? m->site_bodyid[tip_site_] : tip_body_;
  const Chain chain = findChain(m, path, tip_owner, base_body_, tip, base);
  // MuJoCo's Jacobian is taken about its tree's centre of mass: a body off the path from the world to the
  // tip (a finger beyond the tip, a second arm) far away or at inf would make it imprecise or NaN. Masses
  // never enter kinematics: only the path's bodies weigh anything in this copy. (The compiled subtree masses
  // keep the old weights: the reference point moves, and the Jacobian does not depend on it.)
  for (int b = 1; b < m->nbody; ++b) {
    if (!ancestorOrSelf(m, b, tip_owner)) model_->body_mass[b] = 0.0;
  }

  const std::map<int, std::pair<int, double>> coupled_slide = helicalCouplings(chain, path);
  rejectMimics(chain, path);

  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m), mj_deleteData);
  mj_kinematics(m, d.get());
  std::vector<int> framed = chain.bodies;
  if (base_body_ != 0) framed.push_back(base_body_);
  requireRotations(m, d.get(), framed, path);
  // every body (off the chain too: it enters MuJoCo's centre of mass) within the magnitude limit that
  // keeps the library's numbers finite (kMaxMagnitude, as for robot files)
  for (int b = 1; b < m->nbody; ++b) {
    const double coordinate = Eigen::Map<const Vec3>(d->xpos + 3 * b).cwiseAbs().maxCoeff();
    if (!(coordinate <= kMaxMagnitude)) {
      io::failFile(path, "body '" + nameOf(m, mjOBJ_BODY, b, "body") + "' has a coordinate of magnitude " + number(coordinate) +
                     " at qpos0: beyond the 1e100 lowpair evaluates (kMaxMagnitude)");
    }
  }
  const Pose T_world_base =
      base_body_ == 0 ? Pose() : poseFrom(d->xpos + 3 * base_body_, d->xmat + 9 * base_body_);
  T_base_world_ = T_world_base.inverse();
  const Pose& T_base_world = T_base_world_;
  const Pose T_world_tip = tip_site_ >= 0 ? poseFrom(d->site_xpos + 3 * tip_site_, d->site_xmat + 9 * tip_site_)
                                          : poseFrom(d->xpos + 3 * tip_body_, d->xmat + 9 * tip_body_);
  const Pose T_base_tip = T_base_world * T_world_tip;

  const std::vector<JointSpec> specs =
      extractJoints(chain, d.get(), coupled_slide, T_base_world, T_base_tip, path, joints_);
  if (joints_.empty()) io::failFile(path, "no joint between the base and the tip " + io::quotedFileText(tip));
  if (!finite(T_base_tip.p) || !T_base_tip.R.allFinite()) io::failFile(path, "the tip pose at qpos0 is not finite");
  try {
    poe_ = std::make_unique<PoeModel>(specs, T_base_tip, path);
  } catch (const std::invalid_argument& e) {
    io::failFile(path, e.what());
  }
  // notes once the model is accepted: a rejected file gets its one error line
  for (const std::string& n : notes) emitNote(n);
}

MujocoRobot::~MujocoRobot() = default;

int MujocoRobot::tipBody() const { return tip_site_ >= 0 ? model_->site_bodyid[tip_site_] : tip_body_; }

Vec3 MujocoRobot::siteInTip(const std::string& site) const {
  const mjModel* m = model_.get();
  const int tip_owner = tip_site_ >= 0 ? m->site_bodyid[tip_site_] : tip_body_;
  // fixed to the tip: the tip's body or one below it reached through bodies without joints
  auto fixedBelowTip = [&](int body) {
    for (int b = body; b != tip_owner; b = m->body_parentid[b]) {
      if (b == 0 || m->body_jntnum[b] > 0 || m->body_mocapid[b] >= 0) return false;
    }
    return true;
  };
  std::string usable;  // the sites a target may name, for the message
  int listed = 0;
  for (int s = 0; s < m->nsite; ++s) {
    const char* name = mj_id2name(m, mjOBJ_SITE, s);
    if (s == tip_site_ || !name || !*name || !fixedBelowTip(m->site_bodyid[s])) continue;
    if (listed++ < 20) usable += (usable.empty() ? "'" : ", '") + mujocoLine(name) + "'";
  }
  if (listed > 20) usable += ", ... (" + std::to_string(listed) + ")";
  if (usable.empty()) usable = "none";
  const int id = mj_name2id(m, mjOBJ_SITE, site.c_str());
  if (id < 0) {
    io::failFile(path_, "target '" + mujocoLine(site.c_str()) + "' is not a site; sites fixed to the tip '" + tip_ + "': " + usable);
  }
  const int body = m->site_bodyid[id];
  if (!fixedBelowTip(body)) {
    io::failFile(path_, "site '" + mujocoLine(site.c_str()) + "' is on body '" + nameOf(m, mjOBJ_BODY, body, "body") +
                    "', which is not fixed to the tip '" + tip_ + "' (body '" + nameOf(m, mjOBJ_BODY, tip_owner, "body") +
                    "'): a target must move with the tool; sites fixed to the tip: " + usable);
  }
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m), mj_deleteData);
  mj_kinematics(m, d.get());
  const Pose T_world_tip = tip_site_ >= 0 ? poseFrom(d->site_xpos + 3 * tip_site_, d->site_xmat + 9 * tip_site_)
                                          : poseFrom(d->xpos + 3 * tip_body_, d->xmat + 9 * tip_body_);
  const Vec3 p_world_site = Eigen::Map<const Vec3>(d->site_xpos + 3 * id);
  const Vec3 p_tip_site = T_world_tip.R.transpose() * (p_world_site - T_world_tip.p);
  if (!(p_tip_site.cwiseAbs().maxCoeff() <= kMaxMagnitude)) {
    io::failFile(path_, "site '" + mujocoLine(site.c_str()) + "' is not at a finite point of magnitude at most 1e100 from the tip");
  }
  return p_tip_site;
}

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

PoeModel matchingModel(const RobotFile& file, const MujocoRobot& robot, const std::string& model_path,
                       const std::string& tip) {
  const PoeModel m = file.poeModel();
  if (m.dof() != robot.dof()) {
    throw RobotFileError(file.path + ": has " + std::to_string(m.dof()) + " joints but the chain to '" + tip + "' in " +
                         model_path + " has " + std::to_string(robot.dof()));
  }
  for (int i = 0; i < m.dof(); ++i) {
    const MujocoJoint& j = robot.joints()[static_cast<size_t>(i)];
    if (m.joint(i).type != j.type) {
      throw RobotFileError(file.path + ": joint " + std::to_string(i + 1) + " is " + jointTypeName(m.joint(i).type) +
                           " but MuJoCo joint '" + j.name + "' is " + jointTypeName(j.type));
    }
  }
  return m;
}

std::string tipCandidates(const std::string& path) {
  if (std::filesystem::path(path).extension() == ".urdf") return io::urdfTipCandidates(path);
  installMujocoHandlers();
  setLoadingModel(path);
  const ModelCopy copy(path, nullptr);  // kinematics only (its notes are the load's, printed by a real load)
  char error[1000] = "";
  const std::unique_ptr<mjModel, void (*)(mjModel*)> model(mj_loadXML(copy.path().c_str(), nullptr, error, sizeof error),
                                                           mj_deleteModel);
  if (!model) io::failFile(path, "MuJoCo could not load the model: " + mujocoLine(error));
  const mjModel* m = model.get();
  return "sites: " + namesOf(m, mjOBJ_SITE, m->nsite, 0) + "; bodies: " + namesOf(m, mjOBJ_BODY, m->nbody, 1);
}

io::RobotFile robotFileOfModel(const std::string& path, const std::string& tip, const std::string& base) {
  if (std::filesystem::path(path).extension() == ".urdf") return io::readUrdf(path, tip, base);  // urdfdom, not MuJoCo
  const MujocoRobot robot(path, tip, base);
  io::RobotFile file;
  file.path = path;
  file.name = std::filesystem::path(path).stem().string();
  file.description = "extracted by MuJoCo: chain to '" + tip + "'";
  file.poe = robot.poeModel();
  return file;
}

}  // namespace lowpair::mujoco
