#pragma once
// The per-robot benchmark families, BM_<Area>_<Impl>_<name>: bench_main.cpp registers them for every
// bundled robot and for the user's (--robot=FILE). The robot-independent ones (se(3) exponentials, the
// pose planner, compensation) register themselves at start-up.
#include <string>

#include "robots.hpp"

namespace lowpair_bench {

// bench_lowpair.cpp: FK (POE, D-H) and the Jacobians (spatial, body, geometric), the public functions.
void registerKinematicsBenchmarks(RobotId id, const std::string& name);
// bench_lowpair.cpp: batched FK (a loop of single calls, the SoA batch on POE and D-H, two threads).
void registerBatchBenchmarks(RobotId id, const std::string& name);
// bench_ik.cpp: IK to a pose and to a position.
void registerIkBenchmarks(RobotId id, const std::string& name);
// bench_mujoco.cpp: mj_kinematics and the site Jacobian on robotCase(id).mjcf. The user's MJCF is loaded
// and checked against the robot file here, not when first timed: returns why the robot gets no MuJoCo
// benchmarks ("" when it gets them).
std::string registerMujocoBenchmarks(RobotId id, const std::string& name);

}  // namespace lowpair_bench
