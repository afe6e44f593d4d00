#include "robots_lowpair.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <random>
#include <stdexcept>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "io/robot_file.hpp"
#if __has_include("lowpair/jacobian.hpp")
#include "lowpair/jacobian.hpp"
#define LOWPAIR_BENCH_HAS_JACOBIAN 1
#endif

#ifndef LOWPAIR_MODELS_DIR
#error "LOWPAIR_MODELS_DIR must be defined (bench/CMakeLists.txt)"
#endif

namespace lowpair_bench {

using namespace lowpair;

namespace {

struct Entry {
  RobotModels models;
  RobotCase robot;
};

const char* fileStem(RobotId id) {
  switch (id) {
    case RobotId::Puma560: return "puma560_corke";
    case RobotId::Stanford: return "stanford_corke";
    case RobotId::Panda: return "panda";
    case RobotId::User: break;
  }
  return "";
}

// The range q is drawn from: the joint's, else docs/conventions.md "Sampled joint values" (a turn, or
// [-L, L] for a prismatic joint; harness/commands/sampling.hpp defaultRange).
std::array<double, 2> poolRange(const PoeModel& poe, int i) {
  const Joint& j = poe.joint(i);
  if (j.range) return *j.range;
  const double half = j.type == JointType::Prismatic ? poe.lengthScale() : M_PI;
  return {-half, half};
}

std::unique_ptr<Entry> build(const io::RobotFile& file, const std::string& name, const std::string& mjcf, unsigned seed) {
  PoeModel poe = file.poeModel();
  DhModel dh = file.dh ? *file.dh : poeToDh(poe).model;
  auto e = std::unique_ptr<Entry>(new Entry{RobotModels{poe, dh}, RobotCase{}});
  RobotCase& r = e->robot;
  r.name = name;
  r.mjcf = mjcf;
  r.dof = poe.dof();
  r.size = poe.lengthScale();
  const size_t n = static_cast<size_t>(r.dof);
  for (int i = 0; i < r.dof; ++i) {
    r.prismatic.push_back(poe.joint(i).type == JointType::Prismatic);
    r.scale_mujoco.push_back(poe.joint(i).scale);
    r.scale_kdl.push_back(dh.joint(i).scale);
  }

  std::mt19937_64 rng(seed);
  r.q.resize(kPool * n);
  r.pose.resize(kPool * 12);
  r.jac.resize(kPool * 6 * n);
  r.x_mujoco.resize(kPool * n);
  r.x_kdl.resize(kPool * n);
  Data data(poe);
  for (int k = 0; k < kPool; ++k) {
    for (int i = 0; i < r.dof; ++i) {
      const std::array<double, 2> range = poolRange(poe, i);
      std::uniform_real_distribution<double> u(range[0], range[1]);
      const size_t at = k * n + static_cast<size_t>(i);
      r.q[at] = u(rng);
      r.x_mujoco[at] = poe.joint(i).motion(r.q[at]);
      r.x_kdl[at] = dh.joint(i).motion(r.q[at]);
    }
    const Eigen::Map<const VecX> q(&r.q[k * n], r.dof);
    forwardKinematics(poe, data, q);
    double* out = &r.pose[static_cast<size_t>(k) * 12];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) out[3 * a + b] = data.T_base_tool.R(a, b);
      out[9 + a] = data.T_base_tool.p[a];
    }
    referenceGeometricJacobian(poe, &r.q[k * n], &r.jac[k * 6 * n]);
  }

  // KDL chain description.
  for (int i = 0; i < r.dof && r.kdl_unsupported.empty(); ++i) {
    if (poe.joint(i).type == JointType::Helical) {
      r.kdl_unsupported = "joint " + std::to_string(i + 1) + " is helical (KDL has no screw joint)";
    }
  }
  if (file.dh) {
    r.use_modified = false;
    const DhParams& b = dh.base();
    r.base = {b.theta, b.d, b.alpha, b.a};
    for (const DhJoint& j : dh.joints()) r.rows.push_back({j.link.theta, j.link.d, j.link.alpha, j.link.a});
    r.tool = {dh.toolTheta(), dh.toolD(), 0.0, 0.0};
  } else {
    const ModifiedDh m = toModifiedDh(dh);
    r.use_modified = true;
    r.base_theta = m.base_theta;
    r.base_d = m.base_d;
    for (const ModifiedDhJoint& j : m.joints) r.rows.push_back({j.theta, j.d, j.alpha, j.a});
    r.tool = {m.tool_theta, m.tool_d, m.tool_alpha, m.tool_a};
  }
  return e;
}

std::unique_ptr<Entry> buildBundled(RobotId id) {
  const std::string stem = std::string(LOWPAIR_MODELS_DIR) + "/" + fileStem(id);
  return build(io::readRobotFile(stem + ".yaml"), bundledName(id), stem + ".xml", 20240605u + static_cast<unsigned>(id));
}

// `text` as one benchmark-name part: its ASCII letters and digits, each word capitalized ("rhino-xr3-slide"
// -> "RhinoXr3Slide"), so that report.py can split BM_<Area>_<Impl>_<Name> at "_". Other ASCII separates
// words; bytes of non-ASCII characters are dropped inside their word.
std::string camelCase(const std::string& text) {
  std::string out;
  bool word_start = true;
  for (const char c : text) {
    if (static_cast<unsigned char>(c) >= 0x80) continue;
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    if (!alnum) {
      word_start = true;
      continue;
    }
    out += word_start && c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
    word_start = false;
  }
  return out;
}

// The user robot's name: its file's name:, else the file stem; never a bundled robot's name (then
// "<Name>User"), never empty ("Robot").
std::string userName(const io::RobotFile& file, const std::filesystem::path& path) {
  std::string name = camelCase(file.name);
  if (name.empty()) name = camelCase(path.stem().string());
  if (name.empty()) name = "Robot";
  for (const RobotId id : kRobots) {
    if (name == bundledName(id)) name += "User";
  }
  return name;
}

std::mutex cache_mutex;
std::unique_ptr<Entry> cache[kRobotIds];

const Entry& entry(RobotId id) {
  std::lock_guard<std::mutex> lock(cache_mutex);
  auto& slot = cache[static_cast<int>(id)];
  if (!slot) {
    if (id == RobotId::User) throw std::logic_error("robotCase(RobotId::User) before loadUserRobot");
    slot = buildBundled(id);
  }
  return *slot;
}

}  // namespace

const RobotCase& robotCase(RobotId id) { return entry(id).robot; }

void loadUserRobot(const std::string& path) {
  const std::filesystem::path file_path(path);
  const std::string ext = file_path.extension().string();
  if (ext == ".xml" || ext == ".urdf") {
    throw io::RobotFileError(path + ": an MJCF or URDF is not benchmarked: write it as a robot file first "
                             "(lowpair export FILE --tip NAME --format poe --out ROBOT.yaml)");
  }
  const io::RobotFile file = io::readRobotFile(path);
  std::filesystem::path mjcf = file_path;
  mjcf.replace_extension(".xml");
  // the library's errors about this model (e.g. "poeToDh: ...") get the path from main, as every other error
  std::unique_ptr<Entry> built =
      build(file, userName(file, file_path), mjcf.string(), 20240605u + static_cast<unsigned>(RobotId::User));
  std::lock_guard<std::mutex> lock(cache_mutex);
  cache[static_cast<int>(RobotId::User)] = std::move(built);
}

const RobotModels& robotModels(RobotId id) { return entry(id).models; }

void referenceGeometricJacobian(const PoeModel& model, const double* q_ptr, double* jac) {
  const int n = model.dof();
  const Eigen::Map<const VecX> q(q_ptr, n);
  Eigen::Map<Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>> J(jac, 6, n);
#ifdef LOWPAIR_BENCH_HAS_JACOBIAN
  Data data(model);
  Mat6X Jg(6, n);
  computeJacobians(model, data, q); getGeometricJacobian(data, Jg);
  J = Jg;
#else
  Data data(model);
  forwardKinematics(model, data, q);
  const Vec3 o_tool = data.T_base_tool.p;
  for (int i = 0; i < n; ++i) {
    const Joint& j = model.joint(i);
    const Pose G = i == 0 ? Pose::identity() : data.T_base_joint[static_cast<size_t>(i - 1)];
    const Vec6 xi = adjointApply(G, j.twist);  // spatial twist [w; v_s], v_s = velocity at the base origin
    const Vec3 w = xi.head<3>();
    const Vec3 v = xi.tail<3>() + w.cross(o_tool);
    J.col(i) << j.scale * v, j.scale * w;
  }
#endif
}

}  // namespace lowpair_bench
