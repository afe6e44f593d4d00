#include "robots_lowpair.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <random>

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
  }
  return "";
}
const char* caseName(RobotId id) {
  switch (id) {
    case RobotId::Puma560: return "Puma560";
    case RobotId::Stanford: return "Stanford";
    case RobotId::Panda: return "Panda";
  }
  return "";
}

std::unique_ptr<Entry> build(RobotId id) {
  const std::string stem = std::string(LOWPAIR_MODELS_DIR) + "/" + fileStem(id);
  const io::RobotFile file = io::readRobotFile(stem + ".yaml");
  PoeModel poe = file.poeModel();
  DhModel dh = file.dh ? *file.dh : poeToDh(poe).model;
  auto e = std::unique_ptr<Entry>(new Entry{RobotModels{poe, dh}, RobotCase{}});
  RobotCase& r = e->robot;
  r.name = caseName(id);
  r.mjcf = stem + ".xml";
  r.dof = poe.dof();
  r.size = poe.lengthScale();
  const size_t n = static_cast<size_t>(r.dof);
  for (int i = 0; i < r.dof; ++i) r.prismatic.push_back(poe.joint(i).type == JointType::Prismatic);

  std::mt19937_64 rng(20240605u + static_cast<unsigned>(id));
  r.q.resize(kPool * n);
  r.pose.resize(kPool * 12);
  r.jac.resize(kPool * 6 * n);
  Data data(poe);
  for (int k = 0; k < kPool; ++k) {
    for (int i = 0; i < r.dof; ++i) {
      const auto& range = poe.joint(i).range;
      std::uniform_real_distribution<double> u(range ? (*range)[0] : -M_PI, range ? (*range)[1] : M_PI);
      r.q[k * n + static_cast<size_t>(i)] = u(rng);
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

const Entry& entry(RobotId id) {
  static std::mutex mutex;
  static std::map<RobotId, std::unique_ptr<Entry>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[id];
  if (!slot) slot = build(id);
  return *slot;
}

}  // namespace

const RobotCase& robotCase(RobotId id) { return entry(id).robot; }
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
