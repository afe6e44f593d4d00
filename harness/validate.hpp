#pragma once
/// @file validate.hpp
/// Scenarios (scenarios/*.yaml, README "Scenario format") and the MuJoCo validation engine behind
/// `lowpair validate`: for every sample, the MuJoCo tip pose against the library's POE FK of the extracted
/// model, the FK of its converted D-H table and the FK of each cross-checked robot file; and MuJoCo's
/// Jacobian against the library's geometric Jacobian.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/types.hpp"

namespace lowpair {

struct NamedPose {
  std::string name;
  std::vector<double> q;
};

/// A singular configuration with the Paden–Sastry classes it must show (design.md ids, or "other").
struct SingularPose {
  std::string name;
  std::vector<double> q;
  std::vector<std::string> classes;
};

/// Upper bound on `samples` (a scenario or --samples).
constexpr int kMaxSamples = 100000000;

struct Scenario {
  std::string path;  ///< the scenario file ("" for a model given on the command line)
  std::string name;
  std::string model;  ///< MJCF or URDF path
  std::string tip, base;
  std::string joint_variables;           ///< robot file whose scales/offsets define the sampled q ("" = MuJoCo's)
  std::vector<std::string> robot_files;  ///< cross-checked robot files
  int samples = 10000;
  unsigned long long seed = 1;
  std::vector<std::array<double, 2>> ranges;  ///< per joint, in the sampled variable (empty = defaults)
  double tol_rotation = 1e-12;                ///< rad
  double tol_translation = 1e-12;             ///< times the robot size L
  double tol_jacobian_rotation = 1e-12;       ///< rad (per unit joint rate)
  double tol_jacobian_translation = 1e-12;    ///< times L
  std::vector<NamedPose> poses;
  std::vector<SingularPose> singular_poses;
  /// Singularity map: log10(sigma_min) over joints (1-based) map_joints on [-pi, pi]^2 (or their ranges),
  /// the other joints at map_fixed (default: 0.4 rad / mid-range). Empty map_joints: joints 2 and 3.
  std::vector<int> map_joints;
  std::vector<double> map_fixed;
};

/// @throws RobotFileError ("FILE: line N: what")
Scenario readScenario(const std::string& path);

struct RunOptions {
  std::optional<int> samples;
  std::optional<unsigned long long> seed;
  int threads = 0;             ///< 0 = all cores
  int shard = 1, shards = 1;   ///< run the shard-th of `shards` disjoint slices of the random samples
  bool singularity_map = false;  ///< compute the report's singularity map (151 x 151 SVDs)
};

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
  std::vector<float> rotation_errors, translation_errors;  ///< per sample, for the report's pictures
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
  bool pass = true;
  std::vector<ComparisonResult> comparisons;
  std::vector<SingularPoseResult> singular_poses;
  /// log10 sigma_min of the dimensionless Jacobian over the map grid (row-major, map_size^2).
  std::vector<int> map_joints;
  std::array<double, 2> map_range_x{}, map_range_y{};
  int map_size = 0;
  std::vector<double> map_log_sigma;
};

/// @throws RobotFileError for a model or robot file that cannot be used
ScenarioResult runScenario(const Scenario& scenario, const RunOptions& options);

}  // namespace lowpair
