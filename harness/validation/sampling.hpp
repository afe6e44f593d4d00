#pragma once
/// @file sampling.hpp
/// The sampling unit: which joint values are drawn (one range rule for every command and scenario,
/// docs/conventions.md "Sampled joint values"), the seeded random streams of joint vectors and measurement
/// noise, the sampled variable of a MuJoCo chain (q <-> x), and the worker pool that runs samples.
/// `lowpair validate`, `simulate`, `identifiability` and a scenario's calibration cases all draw through it,
/// so the same seed gives the same joint vectors everywhere.

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::validation {

using Range = std::array<double, 2>;

/// Seeds are whole numbers in [0, kMaxSeed] (2^53: exact in a double, so YAML and the CLI read the same value).
constexpr long long kMaxSeed = 1LL << 53;

/// The range a joint is sampled over when nothing gives one: a turn [-pi, pi] (revolute, helical) or
/// [-L, L] (prismatic; L the robot size, a length).
Range defaultRange(JointType type, double L);

/// The sampling ranges of a robot file's joint variables: each joint's range when the file gives one, else
/// defaultRange with L = model.lengthScale().
std::vector<Range> samplingRanges(const PoeModel& model);

/// The sampled joint variable q of a MuJoCo chain: a robot file's (`joint_variables`, checked against the
/// chain: x_i = scale (q_i + offset)) or MuJoCo's own (x = q). Its sampling ranges, per joint, the first of:
/// `given` (a scenario's explicit ranges), the joint-variable file's range, the model's (MJCF/URDF) range
/// mapped into q, defaultRange with the chain's L.
struct SampledVariable {
  std::vector<JointMotion> motions;     ///< x_i = motions[i].motion(q_i)
  std::optional<PoeModel> file_model;   ///< the joint-variable robot file's model, when one is given
  std::vector<Range> ranges;            ///< per joint, in q
  /// The unit of the measured lengths: "m" for a URDF (MuJoCo reads it in metres, whatever a joint-variable
  /// file states), else the joint-variable file's, else "" (an MJCF states none)
  std::string length_unit;
};

/// @throws io::RobotFileError for a joint-variable file that does not describe the chain, or a `given` of
/// another length than the chain's joint count (named with `subject`)
SampledVariable sampledVariable(const mujoco::MujocoRobot& robot, const std::string& joint_variables,
                                const std::string& model_path, const std::string& tip,
                                const std::vector<Range>& given = {}, const std::string& subject = "");

/// Random sample `index` of the stream `seed`: q_i uniform in ranges[i] (q.size() values), from a
/// std::mt19937_64 seeded with splitmix64(seed * 0x100000001B3 + index). It depends only on (seed, index),
/// so results do not depend on threads or shards.
void randomSample(unsigned long long seed, unsigned long long index, const std::vector<Range>& ranges,
                  Eigen::Ref<VecX> q);

/// Measurement noise of measurement `index` of the stream `seed` (`lowpair simulate`, calibration scenarios):
/// `T.p += N(0, sd_position^2)` per coordinate, then `T.R <- expSO3(n) T.R` with `n ~ N(0, sd_rotation^2 I3)`,
/// from a std::mt19937_64 seeded with splitmix64(splitmix64(seed ^ "noise-st") + index): independent of
/// randomSample's q stream, and a measurement's noise depends only on (seed, index).
void addMeasurementNoise(unsigned long long seed, unsigned long long index, double sd_position, double sd_rotation,
                         Pose& T);

/// Starts one worker thread (replaceable in tests to inject a failure).
using ThreadStarter = std::function<std::thread(std::function<void()>)>;

/// Runs `work(t)` for t = 0 .. threads-1 at once, worker 0 on the calling thread. A thread that cannot be
/// started (std::thread throws, e.g. EAGAIN under `ulimit -u` or when its stack cannot be mapped) ends the
/// starting: the pool runs with the workers it has, so `work` must take its items from a shared queue.
/// Every started thread is joined before this returns or throws; an exception thrown by a worker is
/// rethrown after the join (the first by worker index).
/// @return the number of workers that ran (>= 1)
int runWorkers(int threads, const std::function<void(int)>& work, const ThreadStarter& start = {});

}  // namespace lowpair::validation
