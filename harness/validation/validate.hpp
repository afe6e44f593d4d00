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

#include "validation/calibration_scenario.hpp"
#include "validation/comparison.hpp"
#include "lowpair/model.hpp"
#include "lowpair/types.hpp"
#include "io/robot_file.hpp"
#include "commands/sampling.hpp"
#include "validation/scenario.hpp"

namespace lowpair::validation {

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
  std::vector<double> map_fixed;         ///< q of every joint where the map holds it (the map's two vary)
  std::vector<bool> map_prismatic;       ///< per joint: a length (prismatic), else an angle (rad)
  std::array<double, 2> map_range_x{}, map_range_y{};
  int map_size = 0;
  std::vector<double> map_log_sigma;
  std::vector<CalibrationCaseResult> calibrations;  ///< the scenario's calibration cases (first shard only)
};

/// @throws io::RobotFileError for a model or robot file that cannot be used
ScenarioResult runScenario(const Scenario& scenario, const RunOptions& options);

}  // namespace lowpair::validation
