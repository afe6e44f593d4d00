#pragma once
// The rigid motion (Kabsch) between two point sets, for the CLI tests that judge a calibrated robot up to one rigid
// motion (its base error): base_frame_cli_test, known_targets_cli_test.
#include <Eigen/Dense>
#include <cmath>
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
inline RigidFit rigidFit(const Points& a, const Points& b) {
  Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < a.size(); ++k) {
    ca += a[k];
    cb += b[k];
  }
  ca /= static_cast<double>(a.size());
  cb /= static_cast<double>(b.size());
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < a.size(); ++k) M += (b[k] - cb) * (a[k] - ca).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  const Eigen::Vector3d t = cb - R * ca;
  RigidFit f;
  f.R = R;
  f.t = t;
  f.translation = t.norm();
  f.angle = Eigen::AngleAxisd(R).angle();
  double s = 0.0;
  for (size_t k = 0; k < a.size(); ++k) s += (R * a[k] + t - b[k]).squaredNorm();
  f.rms = std::sqrt(s / static_cast<double>(a.size()));
  return f;
}

}  // namespace lowpair_test
