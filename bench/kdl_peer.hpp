#pragma once
// KDL peer, built as a separate shared library with hidden symbols (bench/CMakeLists.txt): Debian's KDL
// is compiled without -march, so its Eigen code must not be merged with ours. Only std types cross.
#include <string>

#include "robots.hpp"

#define LOWPAIR_BENCH_KDL_API __attribute__((visibility("default")))

namespace lowpair_bench {

using RobotCaseGetter = const RobotCase& (*)(RobotId);

// Registers BM_Fk_Kdl_<name> and BM_Jacobian_Kdl_<name> for robot `id` (one without kdl_unsupported).
LOWPAIR_BENCH_KDL_API void registerKdlBenchmarks(RobotCaseGetter get, RobotId id, const std::string& name);

// `calls` KDL FK (or Jacobian) calls cycling through the robot's configurations, between
// `start()` and `stop()` (the instruction counter's toggles: bench/callgrind_calls.cpp).
LOWPAIR_BENCH_KDL_API void runKdlCalls(RobotCaseGetter get, RobotId id, bool jacobian, int calls, void (*start)(),
                                       void (*stop)());

}  // namespace lowpair_bench
