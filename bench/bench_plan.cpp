// Calibration pose planning (lowpair/plan.hpp, docs/plan.md): N = 30 poses from M = 5,000 candidates, the
// issue's size. BM_Plan_Candidates_* times the candidates' blocks (identification Jacobians, column scaling,
// the rank rule on all of them), BM_Plan_Poses_* the greedy selection and exchange passes on them, and
// BM_Plan_Total_* both: what `lowpair plan ROBOT --poses 30` spends before its report. Before timing, the plan
// is checked against 100 random sets of 30 from the same candidates (its log det must be the largest).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "lowpair/plan.hpp"
#include "robots_lowpair.hpp"

namespace lowpair_bench {

using namespace lowpair;

namespace {

constexpr int kCandidates = 5000;
constexpr int kPoses = 30;

// The candidates: uniform in each joint's range ([-pi, pi] without one), seeded per robot.
const std::vector<VecX>& candidates(RobotId id) {
  static std::vector<VecX> pools[3];
  std::vector<VecX>& pool = pools[static_cast<int>(id)];
  if (!pool.empty()) return pool;
  const PoeModel& model = robotModels(id).poe;
  std::mt19937_64 rng(20240701u + static_cast<unsigned>(id));
  for (int k = 0; k < kCandidates; ++k) {
    VecX q(model.dof());
    for (int i = 0; i < model.dof(); ++i) {
      const auto& range = model.joint(i).range;
      std::uniform_real_distribution<double> u(range ? (*range)[0] : -M_PI, range ? (*range)[1] : M_PI);
      q[i] = u(rng);
    }
    pool.push_back(q);
  }
  return pool;
}

// The plan must beat the best of 100 random sets of the same size (tests/lib/plan_test.cpp's claim).
bool rejected(benchmark::State& state, const PlanCandidates& c, const PlanResult& plan) {
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& set : randomPoseSets(c.count(), kPoses, 100, 1)) best = std::max(best, evaluatePlan(c, set).log_det);
  if (plan.value.log_det >= best) return false;
  state.SkipWithError(("plan log det " + std::to_string(plan.value.log_det) + " below a random set's " +
                       std::to_string(best)).c_str());
  return true;
}

void planCandidatesBench(benchmark::State& state, RobotId id) {
  const PoeModel& model = robotModels(id).poe;
  const PlanOptions options;
  for (auto _ : state) {
    PlanCandidates c = planCandidates(model, candidates(id), options);
    benchmark::DoNotOptimize(c.reduced_t.data());
  }
}

void planPosesBench(benchmark::State& state, RobotId id) {
  const PlanOptions options;
  const PlanCandidates c = planCandidates(robotModels(id).poe, candidates(id), options);
  if (rejected(state, c, planPoses(c, kPoses, options))) return;
  int swaps = 0;
  for (auto _ : state) {
    PlanResult plan = planPoses(c, kPoses, options);
    swaps = plan.swaps;
    benchmark::DoNotOptimize(plan.indices.data());
  }
  state.counters["swaps"] = swaps;
}

void planTotalBench(benchmark::State& state, RobotId id) {
  const PoeModel& model = robotModels(id).poe;
  const PlanOptions options;
  for (auto _ : state) {
    PlanResult plan = planPoses(model, candidates(id), kPoses, options);
    benchmark::DoNotOptimize(plan.indices.data());
  }
}

const bool registered = [] {
  for (const RobotId id : {RobotId::Puma560, RobotId::Panda}) {
    const std::string n = bundledName(id);
    benchmark::RegisterBenchmark(("BM_Plan_Candidates_" + n).c_str(), planCandidatesBench, id)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Plan_Poses_" + n).c_str(), planPosesBench, id)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_Plan_Total_" + n).c_str(), planTotalBench, id)->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace

}  // namespace lowpair_bench
