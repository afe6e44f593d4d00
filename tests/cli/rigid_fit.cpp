#include "rigid_fit.hpp"

#include <cmath>

namespace lowpair_test {

RigidFit rigidFit(const Points& a, const Points& b) {
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
