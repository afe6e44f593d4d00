// Instruction counts per call (bench/README.md): runs one operation `calls` times on the PUMA 560's
// configuration pool with callgrind's instrumentation switched on only around the loop, so
//   valgrind --tool=callgrind --instr-atstart=no lowpair_callgrind_calls OP CALLS
// reports the loop's instructions (Ir); divided by CALLS it is the cost of one call. Times vary with the
// machine's load; these counts do not. OP: fk_poe fk_dh jacobian_spatial jacobian_geometric batch_poe
// batch_jacobian fk_mujoco jacobian_mujoco fk_kdl jacobian_kdl, and fk_poe_previous jacobian_spatial_previous
// batch_poe_previous (the kernel before issue 29, chain_baseline.cpp).
#include <valgrind/callgrind.h>

#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "kdl_peer.hpp"
#include "chain_baseline.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "robots_lowpair.hpp"

using namespace lowpair;
using namespace lowpair_bench;

namespace {

void start() { CALLGRIND_START_INSTRUMENTATION; }
void stop() { CALLGRIND_STOP_INSTRUMENTATION; }

Eigen::Map<const VecX> qOf(const RobotCase& r, int c) {
  return {&r.q[static_cast<size_t>((c & (kPool - 1)) * r.dof)], r.dof};
}

volatile double sink;

int runMujoco(const RobotCase& r, bool jacobian, int calls) {
  char error[1000] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(r.mjcf.c_str(), nullptr, error, sizeof error),
                                                 mj_deleteModel);
  if (!m) {
    std::fprintf(stderr, "error: %s: %s\n", r.mjcf.c_str(), error);
    return 2;
  }
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m.get()), mj_deleteData);
  const int site = mj_name2id(m.get(), mjOBJ_SITE, "tool");
  std::vector<double> jacp(static_cast<size_t>(3 * m->nv)), jacr(static_cast<size_t>(3 * m->nv));
  start();
  for (int c = 0; c < calls; ++c) {
    const double* x = &r.x_mujoco[static_cast<size_t>((c & (kPool - 1)) * r.dof)];
    for (int i = 0; i < r.dof; ++i) d->qpos[m->jnt_qposadr[i]] = m->qpos0[m->jnt_qposadr[i]] + x[i];
    mj_kinematics(m.get(), d.get());
    if (jacobian) {
      mj_comPos(m.get(), d.get());
      mj_jacSite(m.get(), d.get(), jacp.data(), jacr.data(), site);
    }
  }
  stop();
  sink = d->site_xpos[3 * site] + jacp[0];
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s OP CALLS\n", argv[0]);
    return 2;
  }
  const std::string op = argv[1];
  const int calls = std::atoi(argv[2]);
  const RobotCase& r = robotCase(RobotId::Puma560);
  const PoeModel& poe = robotModels(RobotId::Puma560).poe;
  const DhModel& dh = robotModels(RobotId::Puma560).dh;
  Data data(poe), dh_data(dh);
  Mat6X J(6, r.dof);
  if (op == "fk_poe") {
    start();
    for (int c = 0; c < calls; ++c) forwardKinematics(poe, data, qOf(r, c));
    stop();
  } else if (op == "fk_dh") {
    start();
    for (int c = 0; c < calls; ++c) forwardKinematics(dh, dh_data, qOf(r, c));
    stop();
  } else if (op == "jacobian_spatial") {
    start();
    for (int c = 0; c < calls; ++c) {
      computeJacobians(poe, data, qOf(r, c));
      getSpatialJacobian(data, J);
    }
    stop();
  } else if (op == "jacobian_geometric") {
    start();
    for (int c = 0; c < calls; ++c) {
      computeJacobians(poe, data, qOf(r, c));
      getGeometricJacobian(data, J);
    }
    stop();
  } else if (op == "batch_poe") {  // calls = configurations, in blocks of kPool
    MatX q(kPool, r.dof), poses(kPool, 12);
    for (int k = 0; k < kPool; ++k) q.row(k) = qOf(r, k).transpose();
    start();
    for (int done = 0; done < calls; done += kPool) forwardKinematicsBatch(poe, q, poses);
    stop();
    sink = poses(0, 0);
  } else if (op == "batch_jacobian") {  // geometric, with the poses; calls = configurations, in blocks of kPool
    MatX q(kPool, r.dof), poses(kPool, 12), jacobians(kPool, 6 * r.dof);
    for (int k = 0; k < kPool; ++k) q.row(k) = qOf(r, k).transpose();
    start();
    for (int done = 0; done < calls; done += kPool) computeJacobiansBatch(poe, q, JacobianFrame::Geometric, jacobians, poses);
    stop();
    sink = jacobians(0, 0);
  } else if (op == "fk_poe_previous") {  // the kernel before issue 29 (chain_baseline.cpp)
    start();
    for (int c = 0; c < calls; ++c) baseline::forwardKinematics(poe.chain(), data, qOf(r, c).data());
    stop();
  } else if (op == "jacobian_spatial_previous") {
    start();
    for (int c = 0; c < calls; ++c) {
      baseline::computeJacobians(poe.chain(), data, qOf(r, c).data());
      getSpatialJacobian(data, J);
    }
    stop();
  } else if (op == "batch_poe_previous") {
    MatX q(kPool, r.dof), poses(kPool, 12);
    for (int k = 0; k < kPool; ++k) q.row(k) = qOf(r, k).transpose();
    start();
    for (int done = 0; done < calls; done += kPool) baseline::forwardKinematicsBatch(poe.chain(), q, poses);
    stop();
    sink = poses(0, 0);
  } else if (op == "fk_mujoco" || op == "jacobian_mujoco") {
    return runMujoco(r, op == "jacobian_mujoco", calls);
  } else if (op == "fk_kdl" || op == "jacobian_kdl") {
    runKdlCalls(&robotCase, RobotId::Puma560, op == "jacobian_kdl", calls, start, stop);
  } else {
    std::fprintf(stderr, "error: unknown OP '%s'\n", op.c_str());
    return 2;
  }
  sink = data.T_base_tool.p[0] + dh_data.T_base_tool.p[0] + J(0, 0);
  return 0;
}
