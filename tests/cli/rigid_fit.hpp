#pragma once
// The rigid motion (Kabsch) between two point sets, for the CLI tests that judge a calibrated robot up to one rigid
// motion (its base error): base_frame_cli_test, known_targets_cli_test. Compiled once (rigid_fit.cpp): at the CLI
// tests' -O0 the SVD's templates were most of those two tests' compile time.
#include <Eigen/Dense>
#include <vector>

namespace lowpair_test {

using Points = std::vector<Eigen::Vector3d>;

// The rigid motion (Kabsch) that best maps `a` onto `b`: its translation at the centroid's scale, its angle and
// the RMS left.
struct RigidFit {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double translation = 0.0, angle = 0.0, rms = 0.0;
};
RigidFit rigidFit(const Points& a, const Points& b);

}  // namespace lowpair_test
