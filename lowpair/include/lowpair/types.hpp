#pragma once
/// @file types.hpp
/// The one place for lowpair's conventions.
///
/// - Twist coordinates are `[w; v]`, rotation first (Wu et al. eq. 1).
/// - A `Pose` is a rigid transform `T_a_b` (frame b seen from frame a): `p_a = R * p_b + p`.
/// - Angles are radians; pitch is length per radian; lengths are in the robot file's unit.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lowpair {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
using Mat6X = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// Rigid transform `T_a_b = [R p; 0 1]`. Plain value type; `R` is assumed orthonormal.
struct Pose {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();

  static Pose identity() { return Pose{}; }
  static Pose fromMatrix(const Mat4& T) { return Pose{T.topLeftCorner<3, 3>(), T.topRightCorner<3, 1>()}; }

  Mat4 matrix() const {
    Mat4 T = Mat4::Identity();
    T.topLeftCorner<3, 3>() = R;
    T.topRightCorner<3, 1>() = p;
    return T;
  }
  /// `T_b_a` from `T_a_b`.
  Pose inverse() const {
    Pose out;
    out.R.noalias() = R.transpose();
    out.p.noalias() = -(out.R * p);
    return out;
  }
  /// `T_a_c = T_a_b * T_b_c`.
  Pose operator*(const Pose& T_b_c) const {
    Pose out;
    out.R.noalias() = R * T_b_c.R;
    out.p.noalias() = R * T_b_c.p;
    out.p += p;
    return out;
  }
  Vec3 operator*(const Vec3& p_b) const { return R * p_b + p; }
};

/// Joint kinds of lower pairs. Helical joints carry a pitch (length/rad).
enum class JointType { Revolute, Prismatic, Helical };

/// "revolute", "prismatic", "helical".
const char* jointTypeName(JointType type);

}  // namespace lowpair
