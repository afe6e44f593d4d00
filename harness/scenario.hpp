#pragma once
/// @file scenario.hpp
/// Scenarios (scenarios/*.yaml, README "Scenario format"): what `lowpair validate` compares, over which
/// samples, with which tolerances, and the singular poses it checks.

#include <array>
#include <string>
#include <vector>

namespace lowpair {

struct NamedPose {
  std::string name;
  std::vector<double> q;
};

/// A singular configuration with the Paden–Sastry classes it must show (conventions.md ids, or "other").
struct SingularPose {
  std::string name;
  std::vector<double> q;
  std::vector<std::string> classes;
};

/// Seeds are whole numbers in [0, kMaxSeed] (exact in a double, so YAML and the CLI read the same value).
constexpr long long kMaxSeed = 1LL << 53;

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

}  // namespace lowpair
