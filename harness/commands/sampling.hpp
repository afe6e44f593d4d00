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

#include "lowpair/calibration.hpp"
#include "lowpair/model.hpp"
#include "lowpair/types.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::commands {

using Range = std::array<double, 2>;

/// Seeds are whole numbers in [0, kMaxSeed] (2^53: exact in a double, so YAML and the CLI read the same value).
constexpr long long kMaxSeed = 1LL << 53;

/// The range a joint is sampled over when nothing gives one: a turn [-pi, pi] (revolute, helical) or
/// [-L, L] (prismatic; L the robot size, a length).
Range defaultRange(JointType type, double L);

/// The sampling ranges of a robot file's joint variables: each joint's range when the file gives one, else
/// defaultRange with L = model.lengthScale().
std::vector<Range> samplingRanges(const PoeModel& model);

/// What is wrong with evaluating `model` at value `q` of joint `i` (jointValueWithinLimits, model.hpp): ""
/// when nothing; "'nan' is not finite"; or "'1e+308' is beyond joint 3's limit (j3, prismatic: |scale (q +
/// offset)| at most 1e100, kMaxMagnitude): its pose would not be finite". The one check the CLI (--q,
/// --q-file rows, ik seeds) and the Python module (fk, jacobian, singular, ik, compensate, simulate,
/// calibrate) make before evaluating, so that no result they print or return is inf or NaN.
std::string jointValueProblem(const PoeModel& model, int i, double q);

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

/// Samples first .. first+count-1 of the stream `seed` (randomSample), in order.
std::vector<VecX> randomSamples(unsigned long long seed, unsigned long long first, int count,
                                const std::vector<Range>& ranges);

/// Measurement noise of measurement `index` of the stream `seed` (`lowpair simulate`, calibration scenarios):
/// `T.p += N(0, sd_position^2)` per coordinate, then `T.R <- expSO3(n) T.R` with `n ~ N(0, sd_rotation^2 I3)`,
/// from a std::mt19937_64 seeded with splitmix64(splitmix64(seed ^ "noise-st") + index): independent of
/// randomSample's q stream, and a measurement's noise depends only on (seed, index).
void addMeasurementNoise(unsigned long long seed, unsigned long long index, double sd_position, double sd_rotation,
                         Pose& T);

/// The pose `T_base_frame` of a measurement frame (a laser tracker's) relative to the robot base: rotation
/// `expSO3(rotation)` (a rotation vector, rad) and `translation` (the robot's length unit). A simulated
/// measurement is expressed in it: `T_frame_base * (the tool frame, origin or target point in the base frame)`.
Pose measurementFrame(const Vec3& rotation, const Vec3& translation);

/// How a simulated measurement is taken (`lowpair simulate`, a scenario's calibration cases; the two share it,
/// docs/calibration.md "Measurement files"): what is measured, in which frame, with which noise.
struct MeasurementSetup {
  Measure measure = Measure::Pose;
  /// Measure::Targets: the targets' points in the tool frame; every pose measures each, in this order.
  std::vector<Vec3> targets;
  Pose T_frame_base;  ///< the measurement frame (identity: the base frame); measurementFrame(...).inverse()
  double sd_position = 0.0;  ///< noise per coordinate, length, in the measurement frame
  double sd_rotation = 0.0;  ///< noise per axis of `exp(n)`, rad, about the measurement frame's axes (Pose)
};

/// Rows (measurements) per pose: the number of targets for Measure::Targets, else 1.
int rowsPerPose(const MeasurementSetup& setup);

/// Appends the measurements of pose `pose` (joint values `q`, tool frame `T_base_tool`): rows
/// `pose * R .. pose * R + R - 1` (R = rowsPerPose) of the stream. Row r holds `T_frame_base * T_base_tool`
/// (Pose, Position) or the point `T_frame_base * T_base_tool * targets[t]` (Targets, one row per target,
/// `target = t`, rotation identity), then its noise addMeasurementNoise(seed, r, sd_position, sd_rotation)
/// in the measurement frame: a row's noise depends only on (seed, r), and with one row per pose r is the
/// pose's index (what simulate and the calibration cases always did).
void appendMeasurements(const MeasurementSetup& setup, unsigned long long seed, unsigned long long pose,
                        const Eigen::Ref<const VecX>& q, const Pose& T_base_tool, std::vector<Measurement>& out);

/// Blunders (gross errors, docs/calibration.md "Blunders"): `count` distinct rows of `measurements`, drawn
/// from the stream (seed, "blunders") by Floyd's algorithm (uniform over the subsets, independent of the q
/// and noise streams), each moved by exactly `size` (length) along a direction uniform on the unit sphere
/// drawn from the stream (seed, "blunders", row): `p += size u` in the measurement frame (a pose's rotation is
/// kept). Uses only the engine's raw 64-bit outputs (no distribution object): the same rows and directions
/// with every standard library.
/// @return the rows moved (0-based), increasing
/// @throws std::invalid_argument for count < 0 or above the number of measurements, or size not finite or < 0
std::vector<size_t> addBlunders(unsigned long long seed, long long count, double size,
                                std::vector<Measurement>& measurements);

/// Most worker threads (`validate --threads`): each holds its own statistics (about 35 KB per comparison) and
/// MuJoCo data; 20,000 threads once asked for more than 8 GB. 256 is more than the cores of any machine this runs
/// on (results do not depend on the count).
constexpr int kMaxThreads = 256;

/// Starts one worker thread (replaceable in tests to inject a failure).
using ThreadStarter = std::function<std::thread(std::function<void()>)>;

/// Runs `work(t)` for t = 0 .. threads-1 at once, worker 0 on the calling thread. A thread that cannot be
/// started (std::thread throws, e.g. EAGAIN under `ulimit -u` or when its stack cannot be mapped) ends the
/// starting: the pool runs with the workers it has, so `work` must take its items from a shared queue.
/// Every started thread is joined before this returns or throws; an exception thrown by a worker is
/// rethrown after the join (the first by worker index).
/// @return the number of workers that ran (>= 1)
int runWorkers(int threads, const std::function<void(int)>& work, const ThreadStarter& start = {});

}  // namespace lowpair::commands
