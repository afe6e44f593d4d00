// KDL peers: ChainFkSolverPos_recursive and ChainJntToJacSolver on chains built from the robots' D-H
// tables (standard for a D-H robot file: PUMA, Stanford; modified for a POE one: Panda). Compiled with
// EIGEN_MAX_ALIGN_BYTES=16 into a shared library with hidden visibility: no Eigen code is shared with the
// rest of the benchmark.
#include <benchmark/benchmark.h>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include <cmath>
#include <memory>
#include <string>

#include "kdl_chain.hpp"
#include "kdl_peer.hpp"

namespace lowpair_bench {

KDL::Chain buildChain(const RobotCase& r) {
  KDL::Chain chain;
  const size_t n = r.rows.size();
  auto joint = [&](size_t i) {
    return KDL::Joint(r.prismatic[i] ? KDL::Joint::TransZ : KDL::Joint::RotZ);
  };
  if (!r.use_modified) {
    // A_base, then per joint: Q_i(x) * A(link_i) = Rz/Tz(x) * DH(a, alpha, d, theta); tool Rz Tz.
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None),
                                  KDL::Frame::DH(r.base.a, r.base.alpha, r.base.d, r.base.theta)));
    for (size_t i = 0; i < n; ++i) {
      const DhRow& row = r.rows[i];
      chain.addSegment(KDL::Segment(joint(i), KDL::Frame::DH(row.a, row.alpha, row.d, row.theta)));
    }
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None),
                                  KDL::Frame(KDL::Rotation::RotZ(r.tool.theta), KDL::Vector(0, 0, r.tool.d))));
  } else {
    // Rz(theta_B) Tz(d_B) Craig(row 0); joint i moves after Rz(theta_i) Tz(d_i) (they commute), then
    // Craig(alpha_i, a_i, theta_{i+1}, d_{i+1}); the last joint ends with the tool row.
    const KDL::Frame base(KDL::Rotation::RotZ(r.base_theta), KDL::Vector(0, 0, r.base_d));
    const DhRow& r0 = r.rows[0];
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None),
                                  base * KDL::Frame::DH_Craig1989(r0.a, r0.alpha, r0.d, r0.theta)));
    for (size_t i = 0; i < n; ++i) {
      const DhRow next = i + 1 < n ? r.rows[i + 1] : r.tool;
      chain.addSegment(KDL::Segment(joint(i), KDL::Frame::DH_Craig1989(next.a, next.alpha, next.d, next.theta)));
    }
  }
  return chain;
}

namespace {

struct KdlFixture {
  explicit KdlFixture(const RobotCase& robot)
      : r(robot), chain(buildChain(robot)), fk(chain), jac_solver(chain), q(chain.getNrOfJoints()),
        jac(chain.getNrOfJoints()) {
    // agreement with the library over the whole pool, before anything is timed
    const int n = r.dof;
    for (int k = 0; k < kPool; ++k) {
      load(k);
      KDL::Frame F;
      fk.JntToCart(q, F);
      double pose[12];
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) pose[3 * a + b] = F.M(a, b);
        pose[9 + a] = F.p(a);
      }
      fk_error = std::max(fk_error, poseMismatch(r, k, pose));
      jac_solver.JntToJac(q, jac);
      std::unique_ptr<double[]> J(new double[6 * static_cast<size_t>(n)]);
      for (int a = 0; a < 6; ++a) {
        for (int b = 0; b < n; ++b) {  // d/dx -> d/dq
          const double dx = jac(static_cast<unsigned>(a), static_cast<unsigned>(b));
          J[static_cast<size_t>(a * n + b)] = dx * r.scale_kdl[static_cast<size_t>(b)];
        }
      }
      jac_error = std::max(jac_error, jacobianMismatch(r, k, J.get()));
    }
  }
  void load(int k) {
    const double* src = &r.x_kdl[static_cast<size_t>(k * r.dof)];
    for (int i = 0; i < r.dof; ++i) q(static_cast<unsigned>(i)) = src[i];
  }
  const RobotCase& r;
  KDL::Chain chain;
  KDL::ChainFkSolverPos_recursive fk;
  KDL::ChainJntToJacSolver jac_solver;
  KDL::JntArray q;
  KDL::Jacobian jac;
  double fk_error = 0.0, jac_error = 0.0;
};

KdlFixture& fixture(RobotCaseGetter get, RobotId id) {
  static std::unique_ptr<KdlFixture> cache[kRobotIds];
  auto& slot = cache[static_cast<int>(id)];
  if (!slot) slot.reset(new KdlFixture(get(id)));
  return *slot;
}

bool rejected(benchmark::State& state, double error, const char* what) {
  if (error <= kAgree) return false;
  state.SkipWithError((std::string(what) + " disagrees with lowpair: " + std::to_string(error) + " x size").c_str());
  return true;
}

}  // namespace

void registerKdlBenchmarks(RobotCaseGetter get, RobotId id, const std::string& name) {
  benchmark::RegisterBenchmark(("BM_Fk_Kdl_" + name).c_str(), [get, id](benchmark::State& state) {
    KdlFixture& f = fixture(get, id);
    if (rejected(state, f.fk_error, "KDL FK")) return;
    KDL::Frame F;
    int k = 0;
    for (auto _ : state) {
      f.load(k);
      f.fk.JntToCart(f.q, F);
      benchmark::DoNotOptimize(F);
      k = (k + 1) & (kPool - 1);
    }
  });
  benchmark::RegisterBenchmark(("BM_Jacobian_Kdl_" + name).c_str(), [get, id](benchmark::State& state) {
    KdlFixture& f = fixture(get, id);
    if (rejected(state, f.jac_error, "KDL Jacobian")) return;
    int k = 0;
    for (auto _ : state) {
      f.load(k);
      f.jac_solver.JntToJac(f.q, f.jac);
      benchmark::DoNotOptimize(f.jac.data.data());
      benchmark::ClobberMemory();
      k = (k + 1) & (kPool - 1);
    }
  });
}

void runKdlCalls(RobotCaseGetter get, RobotId id, bool jacobian, int calls, void (*start)(), void (*stop)()) {
  KdlFixture& f = fixture(get, id);
  KDL::Frame F;
  start();
  for (int c = 0; c < calls; ++c) {
    f.load(c & (kPool - 1));
    if (jacobian) {
      f.jac_solver.JntToJac(f.q, f.jac);
    } else {
      f.fk.JntToCart(f.q, F);
    }
  }
  stop();
  benchmark::DoNotOptimize(F);
  benchmark::DoNotOptimize(f.jac.data.data());
}

}  // namespace lowpair_bench
