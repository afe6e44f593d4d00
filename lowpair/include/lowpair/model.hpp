#pragma once
/// @file model.hpp
/// Immutable robot models: the base POE model (Wu et al. eq. 5) and the D-H model (eqs. 9-10).
/// Construction validates its input and throws std::invalid_argument naming the joint and the problem.

#include <string>
#include <vector>

#include "lowpair/joint.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// One link of a KinematicChain: joint i's motion followed by the constant transform to joint i+1's axis.
struct ChainLink {
  JointMotion motion;
  double turn = 1.0, slide = 0.0;           ///< `(j, k)` = motion.turnRate(), motion.slideRate(), cached
  double theta = 0.0;                       ///< rad, added to the joint's turn `j x`
  double cos_alpha = 1.0, sin_alpha = 0.0;  ///< of the twist angle about the new x axis
  Vec3 p = Vec3::Zero();                    ///< translation before `Rx(alpha)` (the joint's slide `k x` adds to p.z)
};

namespace detail {
/// Internal to the evaluation (kinematics.cpp): the links' per-joint numbers again as arrays padded to a
/// multiple of kChainLanes (padding: a joint that does not move), so that the joint angles and their sines
/// and cosines are computed in full SIMD lanes. Filled at model construction; not part of the API.
constexpr int kChainLanes = 4;
struct ChainLanes {
  std::vector<double> theta, turn, slide, z, scale, offset;  // z = p.z of the link
};
}  // namespace detail

/// The form in which both models are evaluated, built once at model construction:
/// `T_base_tool(q) = T_base_first * prod_i [ Rz(theta_i + j_i x_i) Trans(p_i + k_i x_i e_z) Rx(alpha_i) ] * T_last_tool`,
/// `x_i = scale_i (q_i + offset_i)` (JointMotion). The frame before link i has its z axis on joint i's line
/// and its origin on it, so each joint is a rotation about / translation along z and all joint sines and
/// cosines can be computed together. A D-H row maps onto a link directly (`p = (a, 0, d)`, eq. 9); for a
/// POE model the link frames are placed on the joint lines (origin at the point nearest the base origin)
/// with `p` general, which keeps every constant bounded by the robot size even for nearly parallel axes.
struct KinematicChain {
  Pose T_base_first;            ///< frame of joint 1's line at zero motion
  std::vector<ChainLink> links;
  Pose T_last_tool;             ///< from the frame after the last link to the tool
  detail::ChainLanes lanes;     ///< internal: the links as padded arrays (detail::ChainLanes)
};

/// Frames of the joint lines at zero motion (every `x_i = 0`): [i] has z along joint i's line and its
/// origin on it (the `T_base_joint` of kinematics.hpp at `x = 0`).
std::vector<Pose> restFrames(const KinematicChain& chain);

/// The normalized joint whose line is the z axis of `T_base_frame` (through its origin), moving as `motion`:
/// twist `[z; o x z + h z]`, or `[0; z]` for a prismatic joint.
Joint jointOnFrame(const JointMotion& motion, const Pose& T_base_frame);

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
  /// Robot size `L` (docs/conventions.md), a length: the largest of the tool position, each
  /// revolute/helical axis' distance from the base origin, each helical `|pitch|` and each prismatic or
  /// helical joint's largest slide `|k scale (q + offset)|` at its range ends (k = 1 or the pitch); 1 if all 0.
  double lengthScale() const { return length_scale_; }
  /// The compiled chain that forwardKinematics evaluates.
  const KinematicChain& chain() const { return chain_; }

 private:
  void finish();
  std::vector<Joint> joints_;
  Pose tool_pose_;
  std::string name_;
  double length_scale_ = 1.0;
  KinematicChain chain_;
};

/// Whether joint value `q` keeps joint `j` within the magnitude limits an accepted model obeys at its range
/// ends (tolerances.hpp kMaxMagnitude): `q` finite, its motion `|x| = |scale (q + offset)|` and its slide
/// `|slideRate() x|` (a prismatic or helical joint's length) at most kMaxMagnitude. Within them every pose
/// and Jacobian of the model is finite (sums and products of at most three numbers <= 1e100, as for the
/// model itself); beyond them a slide of 1e308 is not (inf, then NaN in the rotation-times-position terms).
bool jointValueWithinLimits(const JointMotion& j, double q);

/// The first joint `i` whose `q[i]` is not within its limits (jointValueWithinLimits); -1 when all are.
/// @throws std::invalid_argument if q.size() != model.dof()
int firstJointBeyondLimits(const PoeModel& model, const Eigen::Ref<const VecX>& q);

/// The kind of a D-H row: standard (eq. 9) or Hayati's modified row for nearly parallel axes
/// (Hayati & Mirmirani 1985; docs/conventions.md, "Hayati rows").
enum class DhRowKind { Standard, Hayati };

/// One D-H row. Standard: `A(theta, d, alpha, a) = Rz(theta) Tz(d) Rx(alpha) Tx(a)` (eq. 9).
/// Hayati: `A(theta, d, alpha, a) Ry(beta) = Rz(theta) Tz(d) Tx(a) Rx(alpha) Ry(beta)`, with `d = 0`
/// (a conversion sets it; only a folded offset of a sliding joint before the row moves it): the next
/// frame's origin lies in this frame's xy plane, so its lengths stay bounded when the next axis is nearly
/// parallel to this frame's z, where the standard row's d grows as 1 / sin(alpha).
struct DhParams {
  double theta = 0.0;  ///< rad
  double d = 0.0;      ///< length
  double alpha = 0.0;  ///< rad
  double a = 0.0;      ///< length
  double beta = 0.0;   ///< rad, about the new y axis; 0 in a standard row
  DhRowKind kind = DhRowKind::Standard;
  bool hayati() const { return kind == DhRowKind::Hayati; }
};

/// Joint i of a D-H chain: its motion `Q_i(x) = Rz(j x) Tz(k x)` (JointMotion; a conversion folds the
/// offset into `link`, so it is 0 there), followed by the constant `link` transform (for the last joint,
/// the tool's first part).
struct DhJoint : JointMotion {
  std::string name;
  DhParams link;
  std::optional<std::array<double, 2>> range;
};

/// `row` after joint motion `x`: `Q(x) A(row) = A(theta + j x, d + k x, alpha, a)` (eqs. 9-10).
DhParams movedRow(const DhParams& row, const JointMotion& motion, double x);

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
  /// Robot size `L` of the equivalent POE model (a length; PoeModel::lengthScale).
  double lengthScale() const { return length_scale_; }
  /// The compiled chain that forwardKinematics evaluates.
  const KinematicChain& chain() const { return chain_; }

 private:
  DhParams base_;
  std::vector<DhJoint> joints_;
  double tool_theta_ = 0.0;
  double tool_d_ = 0.0;
  std::string name_;
  double length_scale_ = 1.0;
  KinematicChain chain_;
};

/// `A(theta, d, alpha, a)`, times `Ry(beta)` for a Hayati row.
Pose dhTransform(const DhParams& row);
/// `Rz(theta) Tz(d)`.
Pose dhToolTransform(double theta, double d);

/// Robot size `L` from normalized joints and the tool pose (docs/conventions.md).
double lengthScale(const std::vector<Joint>& joints, const Pose& tool_pose);

}  // namespace lowpair
