#include "lowpair/model.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/SVD>

#include "lowpair/check.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace {

// A rotation given by a user must be orthonormal to 1e-9; rounding-level defects are removed by
// projecting onto the nearest rotation (polar decomposition), larger ones are an input error.
Mat3 checkedRotation(const Mat3& R, const std::string& what) {
  LP_CHECK(R.allFinite(), what << ": rotation has a non-finite entry");
  const double defect = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  LP_CHECK(defect <= 1e-9, what << ": rotation is not orthonormal (max |R^T R - I| = " << defect << ")");
  LP_CHECK(R.determinant() > 0.0, what << ": rotation has determinant " << R.determinant() << " (a reflection)");
  if (defect <= 4.0 * kEps) return R;
  Eigen::JacobiSVD<Mat3> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace

double robotSize(const std::vector<Joint>& joints, const Pose& tool_pose) {
  double size = tool_pose.p.norm();
  for (const Joint& j : joints) {
    if (j.type == JointType::Prismatic) {
      if (j.range) size = std::max({size, std::abs((*j.range)[0]), std::abs((*j.range)[1])});
    } else {
      size = std::max(size, j.axis().cross(j.moment()).norm());
    }
  }
  return size > 0.0 ? size : 1.0;
}

PoeModel::PoeModel(const std::vector<JointSpec>& joints, const Pose& tool_pose, std::string name)
    : name_(std::move(name)) {
  joints_.reserve(joints.size());
  for (size_t i = 0; i < joints.size(); ++i) joints_.push_back(normalizeJoint(joints[i], static_cast<int>(i)));
  LP_CHECK(tool_pose.p.allFinite(), "tool: position has a non-finite entry");
  tool_pose_.R = checkedRotation(tool_pose.R, "tool");
  tool_pose_.p = tool_pose.p;
  finish();
}

PoeModel::PoeModel(std::vector<Joint> joints, const Pose& tool_pose, std::string name)
    : joints_(std::move(joints)), name_(std::move(name)) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    const Joint& j = joints_[i];
    const std::string label = jointLabel(static_cast<int>(i), j.name);
    LP_CHECK(j.twist.allFinite() && std::isfinite(j.pitch) && std::isfinite(j.scale) && std::isfinite(j.offset),
             label << ": non-finite parameter");
    LP_CHECK(j.scale > 0.0, label << ": scale must be positive, got " << j.scale);
    const double unit = j.type == JointType::Prismatic ? j.twist.tail<3>().norm() : j.twist.head<3>().norm();
    LP_CHECK(std::abs(unit - 1.0) <= 1e3 * kEps, label << ": twist is not normalized (norm " << unit << ")");
    if (j.type == JointType::Prismatic) {
      LP_CHECK(j.twist.head<3>().isZero(0.0), label << ": prismatic twist has w != 0");
    }
  }
  LP_CHECK(tool_pose.p.allFinite(), "tool: position has a non-finite entry");
  tool_pose_.R = checkedRotation(tool_pose.R, "tool");
  tool_pose_.p = tool_pose.p;
  finish();
}

PoeModel PoeModel::fromToolTwist(const std::vector<JointSpec>& joints, const Vec6& tool_twist, std::string name) {
  LP_CHECK(tool_twist.allFinite(), "tool: twist has a non-finite entry");
  return PoeModel(joints, expSE3(tool_twist), std::move(name));
}

void PoeModel::finish() { size_ = robotSize(joints_, tool_pose_); }

Pose dhTransform(const DhParams& row) {
  const double ct = std::cos(row.theta), st = std::sin(row.theta);
  const double ca = std::cos(row.alpha), sa = std::sin(row.alpha);
  Pose T;
  T.R << ct, -st * ca, st * sa,  //
      st, ct * ca, -ct * sa,     //
      0.0, sa, ca;
  T.p << row.a * ct, row.a * st, row.d;
  return T;
}

Pose dhToolTransform(double theta, double d) {
  const double ct = std::cos(theta), st = std::sin(theta);
  Pose T;
  T.R << ct, -st, 0.0, st, ct, 0.0, 0.0, 0.0, 1.0;
  T.p << 0.0, 0.0, d;
  return T;
}

DhModel::DhModel(const DhParams& base, std::vector<DhJoint> joints, double tool_theta, double tool_d,
                 std::string name)
    : base_(base), joints_(std::move(joints)), tool_theta_(tool_theta), tool_d_(tool_d), name_(std::move(name)) {
  auto finite = [](const DhParams& r) {
    return std::isfinite(r.theta) && std::isfinite(r.d) && std::isfinite(r.alpha) && std::isfinite(r.a);
  };
  LP_CHECK(finite(base_), "base: non-finite D-H parameter");
  LP_CHECK(std::isfinite(tool_theta_) && std::isfinite(tool_d_), "tool: non-finite D-H parameter");
  std::vector<Joint> axes;
  Pose G = dhTransform(base_);
  for (size_t i = 0; i < joints_.size(); ++i) {
    const DhJoint& j = joints_[i];
    const std::string label = jointLabel(static_cast<int>(i), j.name);
    LP_CHECK(finite(j.link), label << ": non-finite D-H parameter");
    LP_CHECK(std::isfinite(j.pitch) && std::isfinite(j.scale), label << ": non-finite pitch or scale");
    LP_CHECK(j.scale > 0.0, label << ": scale must be positive, got " << j.scale);
    LP_CHECK(j.type == JointType::Helical || j.pitch == 0.0,
             label << ": pitch " << j.pitch << " given for a " << jointTypeName(j.type) << " joint");
    if (j.range) {
      LP_CHECK(std::isfinite((*j.range)[0]) && std::isfinite((*j.range)[1]) && (*j.range)[0] <= (*j.range)[1],
               label << ": range must be finite with lo <= hi");
    }
    Joint axis;
    axis.type = j.type;
    axis.range = j.range;
    const Vec3 z = G.R.col(2);
    if (j.type == JointType::Prismatic) {
      axis.twist << Vec3::Zero(), z;
    } else {
      axis.twist << z, G.p.cross(z);
    }
    axes.push_back(axis);
    G = G * dhTransform(j.link);
  }
  size_ = robotSize(axes, G * dhToolTransform(tool_theta_, tool_d_));
}

}  // namespace lowpair
