#pragma once
// The KDL chain of a benchmark robot (bench_kdl.cpp), for the KDL translation units only (they include KDL).
#include <kdl/chain.hpp>

#include "robots.hpp"

namespace lowpair_bench {

// Standard D-H rows for a D-H robot file (PUMA, Stanford), the modified export for a POE one (Panda).
KDL::Chain buildChain(const RobotCase& r);

}  // namespace lowpair_bench
