// KDL's position IK solvers on the problems of bench_ik.cpp (same targets, same seeds): ChainIkSolverPos_NR_JL
// (Newton-Raphson, joint limits, ChainIkSolverVel_pinv) and ChainIkSolverPos_LMA. Built into the KDL peer library
// (EIGEN_MAX_ALIGN_BYTES=16, hidden symbols: bench_kdl.cpp's header comment).
#include <benchmark/benchmark.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

#include <cmath>
#include <memory>
#include <string>

#include "kdl_chain.hpp"
#include "kdl_peer.hpp"

namespace lowpair_bench {

namespace {

// Both solvers stop on their own error measure; the tolerance is the acceptance test of lowpair's solvers
// (position error over the size, rotation angle), applied to every result through KDL's FK.
constexpr int kMaxIterations = 100;  // lowpair's kIkMaxIterations; KDL's NR_JL default too

struct KdlIkFixture {
  KdlIkFixture(const RobotCase& robot, const KdlIkProblem& p)
      : r(robot), problem(p), chain(buildChain(robot)), n(chain.getNrOfJoints()), lower(n), upper(n), seed(n), out(n),
        fk(chain), vel(chain), nr(chain, lower, upper, fk, vel, kMaxIterations, p.tolerance * robot.size),
        lma(chain, p.tolerance * robot.size, kMaxIterations) {
    for (unsigned i = 0; i < n; ++i) {
      lower(i) = p.lower[i];
      upper(i) = p.upper[i];
    }
    nr.setJointLimits(lower, upper);
  }
  KDL::Frame target(int k) const {
    const double* e = &r.pose[static_cast<size_t>(k) * 12];
    return KDL::Frame(KDL::Rotation(e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7], e[8]), KDL::Vector(e[9], e[10], e[11]));
  }
  void load(int k) {
    for (unsigned i = 0; i < n; ++i) seed(i) = problem.seed[static_cast<size_t>(k) * n + i];
  }
  bool reached(int k) {
    KDL::Frame F;
    fk.JntToCart(out, F);
    const KDL::Frame t = target(k);
    const KDL::Twist d = KDL::diff(F, t);
    return d.vel.Norm() <= problem.tolerance * r.size * (1.0 + 1e-6) && d.rot.Norm() <= problem.tolerance * (1.0 + 1e-6);
  }
  const RobotCase& r;
  KdlIkProblem problem;
  KDL::Chain chain;
  unsigned n;
  KDL::JntArray lower, upper, seed, out;
  KDL::ChainFkSolverPos_recursive fk;
  KDL::ChainIkSolverVel_pinv vel;
  KDL::ChainIkSolverPos_NR_JL nr;
  KDL::ChainIkSolverPos_LMA lma;
};

template <class Solve>
void run(benchmark::State& state, KdlIkFixture& f, Solve solve) {
  int ok = 0;
  for (int k = 0; k < kPool; ++k) {  // success rate over the pool, before timing
    f.load(k);
    solve(k);
    ok += f.reached(k);
  }
  int k = 0;
  for (auto _ : state) {
    f.load(k);
    solve(k);
    benchmark::DoNotOptimize(f.out.data.data());
    k = (k + 1) & (kPool - 1);
  }
  state.counters["ok"] = static_cast<double>(ok) / kPool;
}

}  // namespace

void registerKdlIkBenchmarks(RobotCaseGetter get, RobotId id, const std::string& name, const KdlIkProblem& problem) {
  auto fixture = std::make_shared<std::unique_ptr<KdlIkFixture>>();
  auto make = [get, id, problem, fixture]() -> KdlIkFixture& {
    if (!*fixture) fixture->reset(new KdlIkFixture(get(id), problem));
    return **fixture;
  };
  benchmark::RegisterBenchmark(("BM_Ik_KdlNrJl_" + name).c_str(), [make](benchmark::State& state) {
    KdlIkFixture& f = make();
    run(state, f, [&f](int k) { f.nr.CartToJnt(f.seed, f.target(k), f.out); });
  });
  benchmark::RegisterBenchmark(("BM_Ik_KdlLma_" + name).c_str(), [make](benchmark::State& state) {
    KdlIkFixture& f = make();
    run(state, f, [&f](int k) { f.lma.CartToJnt(f.seed, f.target(k), f.out); });
  });
}

}  // namespace lowpair_bench
