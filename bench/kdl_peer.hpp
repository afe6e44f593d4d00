#pragma once
// KDL peer, built as a separate shared library with hidden symbols (bench/CMakeLists.txt): Debian's KDL
// is compiled without -march, so its Eigen code must not be merged with ours. Only std types cross.
#include "robots.hpp"

#define LOWPAIR_BENCH_KDL_API __attribute__((visibility("default")))

namespace lowpair_bench {

using RobotCaseGetter = const RobotCase& (*)(RobotId);

// Registers BM_Fk_Kdl_<Robot> and BM_Jacobian_Kdl_<Robot> for every robot.
LOWPAIR_BENCH_KDL_API void registerKdlBenchmarks(RobotCaseGetter get);

}  // namespace lowpair_bench
