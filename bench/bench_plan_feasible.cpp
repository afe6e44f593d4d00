// plan's feasible candidates (docs/plan.md "Feasible plans", "Line of sight"): 5,000 candidates of a 6-joint
// arm on a table with a fixture (tests/data/collision/menagerie_arm_cell.xml, capsules and boxes), each checked
// for contacts (mj_kinematics + mj_collision) and, when free, for the tracker's rays to its three SMRs (mj_ray)
// and their angles: what `lowpair plan ... --model --tracker` spends before planning. The model is loaded once
// per iteration, as plan loads it. A separate executable: it links the harness rooms, which the library copy of
// lowpair_bench (LOWPAIR_BENCH_LIBRARY_COPY) would define twice.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "commands/plan_feasibility.hpp"
#include "commands/sampling.hpp"
#include "io/robot_file.hpp"

namespace {

using namespace lowpair;

constexpr int kCandidates = 5000;
const std::string kCell = std::string(LOWPAIR_TEST_DATA_DIR) + "/collision/menagerie_arm_cell";

void feasibleBench(benchmark::State& state, bool tracker) {
  const io::RobotFile file = io::readRobotFile(kCell + ".yaml");
  const std::vector<commands::Range> ranges = commands::samplingRanges(file.poeModel());
  std::vector<VecX> candidates(kCandidates, VecX(file.poeModel().dof()));
  for (int i = 0; i < kCandidates; ++i) commands::randomSample(1, static_cast<unsigned long long>(i), ranges, candidates[static_cast<size_t>(i)]);
  commands::FeasibilityRequest request;
  request.model = kCell + ".xml";
  request.tip = "tool";
  if (tracker) request.tracker = Vec3(1.2, -0.6, 0.8);
  const commands::ArgumentSpelling spelling{[](const std::string& n) { return n; },
                                            [](const std::string& n, const std::string& v) { return n + "=" + v; }};
  commands::FeasibilityReport report;
  for (auto _ : state) {
    report = {};
    std::vector<int> kept = commands::feasibleCandidates(file, candidates, request, spelling, report);
    benchmark::DoNotOptimize(kept.data());
  }
  state.counters["kept"] = report.kept;
  state.counters["collisions"] = report.self_collision + report.world + report.floor_contact;
  state.counters["occluded"] = report.occluded;
  state.counters["angle"] = report.angle;
}

const bool registered = [] {
  benchmark::RegisterBenchmark("BM_Plan_Feasible_Collisions_MenagerieCell", feasibleBench, false)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_Plan_Feasible_CollisionsAndRays_MenagerieCell", feasibleBench, true)->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
