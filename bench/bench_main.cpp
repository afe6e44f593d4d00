// Entry point. Registers the per-robot benchmarks (registration.hpp; the KDL peers live in a separate
// shared library and register from here too) for the bundled robots and, with --robot=FILE, for the user's
// robot file. With a user robot and no --benchmark_filter, only that robot's benchmarks run. A file that
// cannot be benchmarked is one line `error: FILE: what` on stderr and exit 2, before anything runs.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include "io/one_line.hpp"
#include "kdl_peer.hpp"
#include "registration.hpp"

namespace {

using namespace lowpair_bench;
using lowpair::io::oneLine;


void registerBundled(RobotId id) {
  const std::string name = bundledName(id);
  registerKinematicsBenchmarks(id, name);
  registerMujocoBenchmarks(id, name);
  registerKdlBenchmarks(&robotCase, id, name);
  if (id == RobotId::Puma560) registerBatchBenchmarks(id, name);
  registerIkBenchmarks(id, name);
}

// Everything a bundled robot gets; a peer that cannot take the robot is one `note:` line saying why.
void registerUser(const std::string& path) {
  const RobotCase& r = robotCase(RobotId::User);
  registerKinematicsBenchmarks(RobotId::User, r.name);
  const std::string mujoco = registerMujocoBenchmarks(RobotId::User, r.name);
  if (!mujoco.empty()) std::cerr << oneLine("note: " + r.name + ": MuJoCo skipped: " + mujoco) << "\n";
  if (r.kdl_unsupported.empty()) {
    registerKdlBenchmarks(&robotCase, RobotId::User, r.name);
  } else {
    std::cerr << oneLine("note: " + r.name + ": KDL skipped: " + r.kdl_unsupported) << "\n";
  }
  registerBatchBenchmarks(RobotId::User, r.name);
  registerIkBenchmarks(RobotId::User, r.name);
  benchmark::AddCustomContext("lowpair_robot", oneLine(r.name + " from " + path));
}

}  // namespace

int main(int argc, char** argv) {
  // --robot=FILE is ours: taken out of argv before Google Benchmark reads the rest
  std::string robot_path;
  bool has_robot = false, has_filter = std::getenv("BENCHMARK_FILTER") != nullptr;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--robot=", 0) == 0) {
      robot_path = arg.substr(8);
      has_robot = true;
      continue;
    }
    if (arg.rfind("--benchmark_filter=", 0) == 0) has_filter = true;
    argv[kept++] = argv[i];
  }
  argc = kept;
  if (has_robot && robot_path.empty()) {
    std::cerr << "error: --robot=: no robot file given\n";
    return 2;
  }
  if (has_robot) {
    try {
      loadUserRobot(robot_path);
    } catch (const std::exception& e) {
      const std::string what = e.what();
      const bool names_file = what.rfind(robot_path + ":", 0) == 0;
      std::cerr << oneLine("error: " + (names_file ? what : robot_path + ": " + what)) << "\n";
      return 2;
    }
  }

  for (const RobotId id : kRobots) registerBundled(id);
  if (has_robot) registerUser(robot_path);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // BM_<Area>_<Impl>_<Name>: four parts, so no BM_Exp_<Variant> can match a robot's name
  if (has_robot && !has_filter) {
    benchmark::SetBenchmarkFilter("^BM_[^_]+_[^_]+_" + robotCase(RobotId::User).name + "(/|$)");
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
