#pragma once
/// @file model.hpp
/// Immutable robot models: the base POE model (Wu et al. eq. 5) and the D-H model (eqs. 9-10).
/// Construction validates its input and throws std::invalid_argument naming the joint and the problem.

#include <string>
#include <vector>

#include "lowpair/joint.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// Base POE model `g(q) = exp(xi_1 (q_1 + dq_1)) ... exp(xi_n (q_n + dq_n)) exp(xi_T)` (eq. 5),
/// twists in the base frame. Joint twists are stored normalized (see Joint).
class PoeModel {
 public:
  /// @param tool_pose `exp(xi_T)`: `T_base_tool` when every `q_i = -dq_i`.
  PoeModel(const std::vector<JointSpec>& joints, const Pose& tool_pose, std::string name = "");
  /// From already normalized joints (e.g. a conversion result). Checks unit norms to rounding.
  PoeModel(std::vector<Joint> joints, const Pose& tool_pose, std::string name = "");
  /// With the tool given as a twist `xi_T` (any magnitude): `tool_pose = exp(xi_T)`.
  static PoeModel fromToolTwist(const std::vector<JointSpec>& joints, const Vec6& tool_twist,
                                std::string name = "");

  int dof() const { return static_cast<int>(joints_.size()); }
  const std::vector<Joint>& joints() const { return joints_; }
  const Joint& joint(int i) const { return joints_[static_cast<size_t>(i)]; }
  const Pose& toolPose() const { return tool_pose_; }
  const std::string& name() const { return name_; }
  /// Robot size `L` (design.md): the largest of the tool position, each revolute/helical axis'
  /// distance from the base origin and each prismatic joint's largest `|q|` in its range; 1 if all 0.
  double size() const { return size_; }

 private:
  void finish();
  std::vector<Joint> joints_;
  Pose tool_pose_;
  std::string name_;
  double size_ = 1.0;
};

/// One standard D-H row `A(theta, d, alpha, a) = Rz(theta) Tz(d) Rx(alpha) Tx(a)` (eq. 9).
struct DhParams {
  double theta = 0.0;  ///< rad
  double d = 0.0;      ///< length
  double alpha = 0.0;  ///< rad
  double a = 0.0;      ///< length
};

/// Joint i of a D-H chain: its motion `Q_i(x) = Rz(j x) Tz(k x)`, `x = scale * q`, followed by the
/// constant `link` transform (for the last joint, the tool's first part).
struct DhJoint {
  std::string name;
  JointType type = JointType::Revolute;
  DhParams link;
  double pitch = 0.0;  ///< length/rad, helical only
  double scale = 1.0;  ///< `q_bar`
  std::optional<std::array<double, 2>> range;
};

/// D-H model (eq. 10, Fig. 3):
/// `H(q) = A(base) * prod_i [ Q_i(scale_i q_i) * A(link_i) ] * Rz(tool_theta) Tz(tool_d)`.
class DhModel {
 public:
  DhModel(const DhParams& base, std::vector<DhJoint> joints, double tool_theta, double tool_d,
          std::string name = "");

  int dof() const { return static_cast<int>(joints_.size()); }
  const DhParams& base() const { return base_; }
  const std::vector<DhJoint>& joints() const { return joints_; }
  const DhJoint& joint(int i) const { return joints_[static_cast<size_t>(i)]; }
  double toolTheta() const { return tool_theta_; }
  double toolD() const { return tool_d_; }
  const std::string& name() const { return name_; }
  /// Robot size `L` of the equivalent POE model.
  double size() const { return size_; }

 private:
  DhParams base_;
  std::vector<DhJoint> joints_;
  double tool_theta_ = 0.0;
  double tool_d_ = 0.0;
  std::string name_;
  double size_ = 1.0;
};

/// `A(theta, d, alpha, a)`.
Pose dhTransform(const DhParams& row);
/// `Rz(theta) Tz(d)`.
Pose dhToolTransform(double theta, double d);

/// Robot size `L` from normalized joints and the tool pose (design.md).
double robotSize(const std::vector<Joint>& joints, const Pose& tool_pose);

}  // namespace lowpair
