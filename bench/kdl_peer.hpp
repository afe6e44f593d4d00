#pragma once
// KDL peer, built as a separate shared library with hidden symbols (bench/CMakeLists.txt): Debian's KDL
// is compiled without -march, so its Eigen code must not be merged with ours. Only std types cross.
#include <string>
#include <vector>

#include "robots.hpp"

#define LOWPAIR_BENCH_KDL_API __attribute__((visibility("default")))

namespace lowpair_bench {

using RobotCaseGetter = const RobotCase& (*)(RobotId);

// Registers BM_Fk_Kdl_<name> and BM_Jacobian_Kdl_<name> for robot `id` (one without kdl_unsupported).
LOWPAIR_BENCH_KDL_API void registerKdlBenchmarks(RobotCaseGetter get, RobotId id, const std::string& name);

// The inverse-kinematics problems of bench_ik.cpp in KDL's joint space: per pool configuration a seed (kPool x
// dof, the motions of lowpair's seeds), the joint ranges (dof each, the motions of the range ends) and the
// acceptance tolerance (of lowpair's solvers: position over the size, rotation in rad).
struct KdlIkProblem {
  std::vector<double> seed, lower, upper;
  double tolerance = 1e-10;
};

// Registers BM_Ik_KdlNrJl_<name> (ChainIkSolverPos_NR_JL: Newton-Raphson with joint limits, pseudo-inverse
// velocity solver) and BM_Ik_KdlLma_<name> (ChainIkSolverPos_LMA, unit weights) on the pool's poses from the
// problem's seeds; counter `ok` the fraction of solves within the tolerance through KDL's FK.
LOWPAIR_BENCH_KDL_API void registerKdlIkBenchmarks(RobotCaseGetter get, RobotId id, const std::string& name,
                                                   const KdlIkProblem& problem);

// `calls` KDL FK (or Jacobian) calls cycling through the robot's configurations, between
// `start()` and `stop()` (the instruction counter's toggles: bench/callgrind_calls.cpp).
LOWPAIR_BENCH_KDL_API void runKdlCalls(RobotCaseGetter get, RobotId id, bool jacobian, int calls, void (*start)(),
                                       void (*stop)());

}  // namespace lowpair_bench
