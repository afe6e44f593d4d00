// Inverse kinematics (lowpair/ik.hpp, lowpair/ik_closed_form.hpp) and KDL's position IK solvers on the same
// targets and seeds (bench_kdl_ik.cpp). Numerical solvers: time per solve from a seed 0.3 rad per joint away from a configuration
// of the pool (robots.cpp: seeded, within the joint ranges), to the pose or position of that configuration.
// Counters: `iterations` (steps per solve, averaged) and `ok` (the fraction of solves with status Ok). Before
// timing, every Ok solution of the pool is checked against the library FK; a solution off by more than the
// tolerance skips the benchmark with an error.
#include <benchmark/benchmark.h>

#include <random>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/ik_closed_form.hpp"
#include "kdl_peer.hpp"
#include "lowpair/kinematics.hpp"
#include "registration.hpp"
#include "robots_lowpair.hpp"

namespace lowpair_bench {

using namespace lowpair;

namespace {

// The pool's configurations, their targets and seeds 0.3 per joint away (0.3 rad, or 0.3 L for a prismatic joint,
// over the joint's scale), each joint's direction drawn from a seeded stream.
struct IkPool {
  std::vector<VecX> q, seed;
  std::vector<Pose> target;
};

IkPool ikPool(RobotId id) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  std::mt19937_64 rng(20261123);
  IkPool pool;
  for (int k = 0; k < kPool; ++k) {
    const VecX q = Eigen::Map<const VecX>(&r.q[static_cast<size_t>(k * r.dof)], r.dof);
    VecX seed = q;
    for (int i = 0; i < r.dof; ++i) {
      const Joint& j = model.joint(i);
      seed[i] += ((rng() & 1) ? 0.3 : -0.3) * (j.type == JointType::Prismatic ? model.lengthScale() : 1.0) / j.scale;
    }
    pool.q.push_back(q);
    pool.seed.push_back(seed);
    pool.target.push_back(poeForwardKinematics(model, q));
  }
  return pool;
}

// Solves every target of the pool once: false (and the benchmark skipped) when an Ok solution is not one.
bool checked(benchmark::State& state, const PoeModel& model, const IkPool& pool, const IkOptions& o, double& ok) {
  Data data(model);
  IkWorkspace work(model);
  int count = 0;
  for (int k = 0; k < kPool; ++k) {
    const IkResult& r = inverseKinematics(model, data, pool.target[static_cast<size_t>(k)], pool.seed[static_cast<size_t>(k)], o, work);
    if (r.status != IkStatus::Ok) continue;
    ++count;
    const Pose T = poeForwardKinematics(model, r.q);
    const Pose& t = pool.target[static_cast<size_t>(k)];
    const double dp = (T.p - t.p).norm() / model.lengthScale();
    const double dr = o.measure == Measure::Pose ? rotationError(T.R, t.R) : 0.0;
    if (!(dp <= o.position_tolerance && dr <= o.rotation_tolerance)) {
      state.SkipWithError(("an ok solution misses its target by " + std::to_string(dp) + " L, " + std::to_string(dr) + " rad").c_str());
      return false;
    }
  }
  ok = static_cast<double>(count) / kPool;
  return true;
}

void ikBench(benchmark::State& state, RobotId id, Measure measure, bool check_singularity) {
  const PoeModel& model = robotModels(id).poe;
  static std::vector<IkPool> pools(kRobotIds);
  IkPool& pool = pools[static_cast<size_t>(id)];
  if (pool.q.empty()) pool = ikPool(id);
  IkOptions o;
  o.measure = measure;
  o.check_singularity = check_singularity;
  double ok = 0.0;
  if (!checked(state, model, pool, o, ok)) return;
  Data data(model);
  IkWorkspace work(model);
  long iterations = 0;
  int k = 0;
  for (auto _ : state) {
    const IkResult& r = inverseKinematics(model, data, pool.target[static_cast<size_t>(k)], pool.seed[static_cast<size_t>(k)], o, work);
    iterations += r.iterations;
    benchmark::DoNotOptimize(r.q.data());
    k = (k + 1) & (kPool - 1);
  }
  state.counters["iterations"] = benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
  state.counters["ok"] = ok;
}

// Compensation of the PUMA 560 calibrated by errors of 1e-3 (rad, L, relative scale) in every parameter of the
// error model, seeded at the pool's configurations.
void compensateBench(benchmark::State& state) {
  const PoeModel& nominal = robotModels(RobotId::Puma560).poe;
  const RobotCase& r = robotCase(RobotId::Puma560);
  const ErrorModel em(nominal);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  VecX delta(em.size());
  for (int i = 0; i < em.size(); ++i) delta[i] = 1e-3 * normal(rng) * (em.parameters()[static_cast<size_t>(i)].kind == ParameterKind::Shift ? nominal.lengthScale() : 1.0);
  const PoeModel calibrated = em.apply(delta);
  Data data(nominal);
  IkWorkspace work(nominal);
  IkOptions o;
  int ok = 0;
  for (int k = 0; k < kPool; ++k) {
    ok += compensate(nominal, calibrated, data, Eigen::Map<const VecX>(&r.q[static_cast<size_t>(k * r.dof)], r.dof), o, work).status ==
          IkStatus::Ok;
  }
  long iterations = 0;
  int k = 0;
  for (auto _ : state) {
    const IkResult& res = compensate(nominal, calibrated, data, Eigen::Map<const VecX>(&r.q[static_cast<size_t>(k * r.dof)], r.dof), o, work);
    iterations += res.iterations;
    benchmark::DoNotOptimize(res.q.data());
    k = (k + 1) & (kPool - 1);
  }
  state.counters["iterations"] = benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
  state.counters["ok"] = static_cast<double>(ok) / kPool;
}

// Every solution of each pool target in closed form (ik_closed_form.hpp), default tolerances (refinement when the
// FK check fails). Counters: `solutions` per target (averaged) and `ok`, the fraction of targets whose own
// configuration is among the solutions (jointDistance <= 1e-6), counted over the pool before timing.
void closedFormBench(benchmark::State& state, RobotId id) {
  const PoeModel& model = robotModels(id).poe;
  static std::vector<IkPool> pools(kRobotIds);
  IkPool& pool = pools[static_cast<size_t>(id)];
  if (pool.q.empty()) pool = ikPool(id);
  ClosedFormWorkspace work(model);
  const IkOptions o;
  int ok = 0;
  for (int k = 0; k < kPool; ++k) {
    const ClosedFormResult& r = inverseKinematicsAll(model, pool.target[static_cast<size_t>(k)], o, work);
    bool own = false;
    for (int s = 0; s < r.count; ++s) own |= jointDistance(model, pool.q[static_cast<size_t>(k)], r.solutions[static_cast<size_t>(s)].q) <= 1e-6;
    ok += own;
  }
  long solutions = 0;
  int k = 0;
  for (auto _ : state) {
    const ClosedFormResult& r = inverseKinematicsAll(model, pool.target[static_cast<size_t>(k)], o, work);
    solutions += r.count;
    benchmark::DoNotOptimize(r.solutions.data());
    k = (k + 1) & (kPool - 1);
  }
  state.counters["solutions"] = benchmark::Counter(static_cast<double>(solutions), benchmark::Counter::kAvgIterations);
  state.counters["ok"] = static_cast<double>(ok) / kPool;
}

// The pool's problems in KDL's joint space: lowpair's seeds and ranges mapped through the joint-variable map
// (x = scale (q + offset), linear: x_seed = x_kdl + scale_kdl (seed - q)); no range: +-1e9 (KDL needs one).
KdlIkProblem kdlProblem(RobotId id) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  const IkPool pool = ikPool(id);
  KdlIkProblem p;
  const size_t n = static_cast<size_t>(r.dof);
  for (size_t k = 0; k < static_cast<size_t>(kPool); ++k) {
    for (size_t i = 0; i < n; ++i) {
      const double delta = pool.seed[k][static_cast<Eigen::Index>(i)] - pool.q[k][static_cast<Eigen::Index>(i)];
      p.seed.push_back(r.x_kdl[k * n + i] + r.scale_kdl[i] * delta);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const Joint& j = model.joint(static_cast<int>(i));
    const double q0 = pool.q[0][static_cast<Eigen::Index>(i)], x0 = r.x_kdl[i];
    p.lower.push_back(j.range ? x0 + r.scale_kdl[i] * ((*j.range)[0] - q0) : -1e9);
    p.upper.push_back(j.range ? x0 + r.scale_kdl[i] * ((*j.range)[1] - q0) : 1e9);
  }
  p.tolerance = kIkTolerance;
  return p;
}

const bool registered = [] {
  using benchmark::RegisterBenchmark;
  RegisterBenchmark("BM_Ik_PoseNoSingularityCheck_Puma560", ikBench, RobotId::Puma560, Measure::Pose, false);
  RegisterBenchmark("BM_Compensate_Pose_Puma560", compensateBench);
  return true;
}();

}  // namespace

void registerIkBenchmarks(RobotId id, const std::string& name) {
  benchmark::RegisterBenchmark(("BM_Ik_Pose_" + name).c_str(), ikBench, id, Measure::Pose, true);
  benchmark::RegisterBenchmark(("BM_Ik_Position_" + name).c_str(), ikBench, id, Measure::Position, true);
  if (closedFormStructure(robotModels(id).poe).kind != ClosedFormKind::None) {
    benchmark::RegisterBenchmark(("BM_Ik_ClosedFormAll_" + name).c_str(), closedFormBench, id);
  }
  if (robotCase(id).kdl_unsupported.empty()) registerKdlIkBenchmarks(&robotCase, id, name, kdlProblem(id));
}

}  // namespace lowpair_bench
