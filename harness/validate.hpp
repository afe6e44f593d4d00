#pragma once
/// @file validate.hpp
/// The MuJoCo validation engine behind `lowpair validate` (scenarios: scenario.hpp). runScenario builds a
/// list of comparisons (comparison.hpp): the library's POE FK of the model extracted from MuJoCo
/// (`poe_vs_mujoco`), the FK of its converted D-H table (`dh_vs_mujoco`), the FK of each cross-checked robot
/// file (`robot_file_vs_mujoco:<file>`) and, for a URDF, the urdfdom reading of the same file
/// (`urdfdom_vs_mujoco`) against MuJoCo's tip pose, and the library's geometric Jacobian
/// against MuJoCo's (`jacobian_vs_mujoco`); then it runs every sample through every comparison.
///
/// Samples: the sampled variable q is the `joint_variables` robot file's (or MuJoCo's own); each sample's q
/// depends only on (seed, index) and is generated where it is used; the physical motion is
/// `x_i = joint(i).motion(q_i)` of that model, and every other model gets its own q from x by its own
/// `joint(i).variable(x_i)`. Memory does not grow with the sample count: per comparison, statistics in
/// constant memory (ErrorStatistics) and a subsample of at most 20,000 errors for the report's picture.

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "calibration_scenario.hpp"
#include "comparison.hpp"
#include "lowpair/model.hpp"
#include "lowpair/types.hpp"
#include "robot_file.hpp"
#include "scenario.hpp"

namespace lowpair {

struct RunOptions {
  std::optional<int> samples;
  std::optional<unsigned long long> seed;
  int threads = 0;             ///< 0 = all cores
  int shard = 1, shards = 1;   ///< run the shard-th of `shards` disjoint slices of the random samples
  bool singularity_map = false;  ///< compute the report's singularity map (151 x 151 SVDs)
};

/// The statistics of one comparison over every sample. max, mean, the worst sample and the non-finite count
/// are exact and do not depend on --threads; p99 (the nearest-rank 99th percentile) is read from a
/// log-scale histogram of 100 bins per decade over [1e-20, 1e2) (rad; translation relative to L): its
/// relative error is below 1.2 % (the geometric middle of a 2.3 %-wide bin, never above the max).
struct ComparisonResult {
  std::string name;
  bool pose = true;  ///< pose comparison (false: Jacobian)
  double max_rotation = 0, mean_rotation = 0, p99_rotation = 0;
  double max_rotation_euler = 0;  ///< the paper's ||EA_ZYX(R_a^-1 R_b)|| (eq. 19), pose comparisons only
  double max_translation = 0, mean_translation = 0, p99_translation = 0;
  double tolerance_rotation = 0, tolerance_translation = 0;
  std::vector<double> worst_q;          ///< the worst sample (the first non-finite one, if any)
  long long non_finite = 0;             ///< samples whose error is NaN or inf: the comparison fails
  bool pass = true;
  /// LogHistogram counts (rad; translation / L) of every finite sample, for the report's histogram
  std::vector<long long> rotation_histogram, translation_histogram;
  /// For the report's per-sample picture: the errors of samples 0, plot_stride, 2 plot_stride, ... (at most
  /// PlotSamples::kMaxPoints of them; plot_stride = 1 up to that many samples). rad; translation / L.
  long long plot_stride = 1;
  std::vector<float> rotation_errors, translation_errors;
};

/// At a singular pose: MuJoCo's and the library's Jacobians must agree on the rank, the pose must be
/// rank deficient, and every expected class must be among those reported.
struct SingularPoseResult {
  std::string name;
  std::vector<double> q;
  std::vector<std::string> expected;  ///< class ids
  std::vector<std::string> reported;  ///< "C1(4,6)": class id and joints
  int rank_library = 0, rank_mujoco = 0, dof = 0;
  double sigma_min = 0.0;
  bool pass = true;
};

struct ScenarioResult {
  Scenario scenario;
  double size = 1.0;  ///< L of the extracted model
  int samples = 0;    ///< evaluated (named poses + random samples of this shard)
  double seconds = 0.0;  ///< wall time of the sampled comparisons (all threads)
  int threads_requested = 0, threads = 0;  ///< worker threads asked for and actually started
  bool pass = true;
  std::vector<ComparisonResult> comparisons;
  std::vector<SingularPoseResult> singular_poses;
  /// log10 sigma_min of the dimensionless Jacobian over the map grid (row-major, map_size^2).
  std::vector<int> map_joints;
  std::array<double, 2> map_range_x{}, map_range_y{};
  int map_size = 0;
  std::vector<double> map_log_sigma;
  std::vector<CalibrationCaseResult> calibrations;  ///< the scenario's calibration cases (first shard only)
};

/// @throws RobotFileError for a model or robot file that cannot be used
ScenarioResult runScenario(const Scenario& scenario, const RunOptions& options);

/// Random sample `index` of the stream `seed`: q_i uniform in ranges[i] (q.size() values), from a
/// std::mt19937_64 seeded with splitmix64(seed * 0x100000001B3 + index). It depends only on (seed, index),
/// so results do not depend on threads or shards.
void randomSample(unsigned long long seed, unsigned long long index, const std::vector<std::array<double, 2>>& ranges,
                  Eigen::Ref<VecX> q);

/// Measurement noise of measurement `index` of the stream `seed` (`lowpair simulate`, calibration scenarios):
/// `T.p += N(0, sd_position^2)` per coordinate, then `T.R <- expSO3(n) T.R` with `n ~ N(0, sd_rotation^2 I3)`,
/// from a std::mt19937_64 seeded with splitmix64(splitmix64(seed ^ "noise-st") + index): independent of
/// randomSample's q stream, and a measurement's noise depends only on (seed, index).
void addMeasurementNoise(unsigned long long seed, unsigned long long index, double sd_position, double sd_rotation,
                         Pose& T);

/// The robot file `file` as a POE model, checked to describe the MuJoCo chain of `robot` (joint count and
/// types; `model_path` and `tip` name the chain in messages). @throws RobotFileError
PoeModel matchingModel(const RobotFile& file, const MujocoRobot& robot, const std::string& model_path,
                       const std::string& tip);

/// Sampling ranges of a model's joint variables when none are given: each joint's range when the model has
/// one, else revolute/helical [-pi, pi] and prismatic [-L, L] (L = model.size()).
std::vector<std::array<double, 2>> samplingRanges(const PoeModel& model);

/// Starts one worker thread (replaceable in tests to inject a failure).
using ThreadStarter = std::function<std::thread(std::function<void()>)>;

/// Runs `work(t)` for t = 0 .. threads-1 at once, worker 0 on the calling thread. A thread that cannot be
/// started (std::thread throws, e.g. EAGAIN under `ulimit -u` or when its stack cannot be mapped) ends the
/// starting: the pool runs with the workers it has, so `work` must take its items from a shared queue.
/// Every started thread is joined before this returns or throws; an exception thrown by a worker is
/// rethrown after the join (the first by worker index).
/// @return the number of workers that ran (>= 1)
int runWorkers(int threads, const std::function<void(int)>& work, const ThreadStarter& start = {});

}  // namespace lowpair
