#pragma once
/// @file kinematics.hpp
/// Forward kinematics of the base, tool and local POE forms (Wu et al. eqs. 5-7) and of the D-H chain
/// (eq. 10). Free functions writing into a preallocated workspace; no allocation after the workspace
/// is built (tests/lib/alloc_test.cpp proves it).

#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// Everything the algorithms compute for one model, preallocated once (`Data data(model)`); fields are
/// grouped by the function that fills them. One index convention for both models: `T_base_joint[i]` is
/// the frame of joint i's line (z along the line, origin on it) carried by the link *before* joint i,
/// i.e. moved by joints 1..i-1 only. For a D-H model it is the standard D-H frame i-1.
/// A Data fits every model with its number of joints (a copy of the model, its D-H form, another robot of
/// the same dof): every function that takes one checks `dof` against the model and throws
/// std::invalid_argument otherwise. Every buffer's size is a function of dof (the scratch is dof rounded
/// up to the chain's SIMD lanes), so equal dof means buffers of the right size. Do not resize them.
struct Data {
  explicit Data(const PoeModel& model);
  explicit Data(const DhModel& model);
  explicit Data(const KinematicChain& chain);

  int dof = 0;  ///< joints of the model this Data was made for
  // forwardKinematics, forwardKinematicsWithFrames and computeJacobians:
  Pose T_base_tool;                ///< `g(q)` (POE) / `H(q)` (D-H)
  // forwardKinematicsWithFrames and computeJacobians (not forwardKinematics):
  std::vector<Pose> T_base_joint;  ///< n frames, see above
  Mat6X J_spatial;                 ///< 6 x n, twist coordinates `[w; v]` in the base frame (jacobian.hpp)
  // scratch of the chain evaluation, padded to the chain's SIMD lanes (joint values, angles, their
  // sines and cosines, slides):
  VecX q_padded, angle, sin_angle, cos_angle, slide;
};

/// Forward kinematics: fills `data.T_base_tool` (`g(q)` of eq. 5 for POE, `H(q)` of eq. 10 for D-H) and
/// nothing else. Allocates nothing; all joint sines and cosines are computed together. (The joint frames
/// `data.T_base_joint` are filled by forwardKinematicsWithFrames and by computeJacobians, which needs them.)
/// @param data made for a model with `model.dof()` joints (Data)
/// @param q joint variables, `model.dof()` of them (not checked for finiteness: see checkJointVector)
/// @throws std::invalid_argument, in every build type, when q or data has another size, e.g.
/// "forwardKinematics: q has 5 values, the model has 6 joints" or
/// "forwardKinematics: data was made for a model with 7 joints, this model has 6".
void forwardKinematics(const PoeModel& model, Data& data, const Eigen::Ref<const VecX>& q);
void forwardKinematics(const DhModel& model, Data& data, const Eigen::Ref<const VecX>& q);

/// Forward kinematics that also fills `data.T_base_joint` (the frame of every joint's line).
/// @throws std::invalid_argument as forwardKinematics ("forwardKinematicsWithFrames: ...").
void forwardKinematicsWithFrames(const KinematicChain& chain, Data& data, const Eigen::Ref<const VecX>& q);

/// Batch forward kinematics, structure of arrays (SIMD across configurations), same results as
/// forwardKinematics to rounding. @param q `count x dof`: column j holds joint j of every configuration.
/// @param poses `count x 12` output: columns 0..8 the rotation of `T_base_tool` row-major, 9..11 its
/// position. Allocates nothing.
/// @throws std::invalid_argument, in every build type, when q does not have dof columns
/// ("forwardKinematicsBatch: q has 5 columns, the model has 6 joints") or poses is not `count x 12`.
void forwardKinematicsBatch(const PoeModel& model, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses);
void forwardKinematicsBatch(const DhModel& model, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses);

/// Convenience forms returning `T_base_tool` (they allocate a Data; use forwardKinematics in loops).
/// @throws std::invalid_argument when q does not have dof values ("poeForwardKinematics: q has ...").
Pose poeForwardKinematics(const PoeModel& model, const Eigen::Ref<const VecX>& q);
Pose dhForwardKinematics(const DhModel& model, const Eigen::Ref<const VecX>& q);

/// `exp(xi_bar x)` of one normalized joint with `x = joint.motion(q)`: the exponential form of the same
/// motion (used by the tool and local POE forms, eqs. 6-7).
void jointExp(const Joint& joint, double q, Pose& out);

/// @throws std::invalid_argument unless `q` has `dof` finite entries.
void checkJointVector(const Eigen::Ref<const VecX>& q, int dof);

/// Tool POE form (eq. 6): `g(q) = exp(xi_T) exp(xi'_1 (q_1 + dq_1)) ... exp(xi'_n (q_n + dq_n))`,
/// twists `xi'_i = Ad(exp(xi_T)^-1) xi_i` in the tool frame at the zero configuration.
struct ToolPoeModel {
  Pose tool_pose;             ///< exp(xi_T)
  std::vector<Joint> joints;  ///< unit twists in the tool frame
};

/// Local POE form (eq. 7): `g(q) = H_1 exp(xi^1_1 x_1) H_2 exp(xi^2_2 x_2) ... H_n exp(xi^n_n x_n) H_{n+1}`,
/// twist i in link frame i; `frames[i-1] = H_i = T_{i-1,i}` at the zero configuration, `frames[n] = H_{n+1}`.
struct LocalPoeModel {
  std::vector<Pose> frames;   ///< n + 1 constant transforms
  std::vector<Joint> joints;  ///< unit twists in their link frames
};

/// Eq. 8 conversions. toLocalPoe places link frame i on joint i's axis (origin at the axis point
/// nearest the base origin, z along the axis), so each local twist is `[0 0 1 0 0 h]` or `[0 0 0 0 0 1]`.
ToolPoeModel toToolPoe(const PoeModel& model);
PoeModel fromToolPoe(const ToolPoeModel& model, const std::string& name = "");
LocalPoeModel toLocalPoe(const PoeModel& model);
/// With user-chosen link frames `T_base_link_i` at the zero configuration (n of them).
LocalPoeModel toLocalPoe(const PoeModel& model, const std::vector<Pose>& T_base_link);
PoeModel fromLocalPoe(const LocalPoeModel& model, const std::string& name = "");

/// FK of the tool and local forms (eqs. 6 and 7), as products of joint exponentials.
/// @throws std::invalid_argument when q does not have one value per joint (or, local form, the model
/// does not have n + 1 frames)
Pose forwardKinematics(const ToolPoeModel& model, const Eigen::Ref<const VecX>& q);
Pose forwardKinematics(const LocalPoeModel& model, const Eigen::Ref<const VecX>& q);

/// Geodesic rotation error `atan2(|vee(R - R^T)|/2, (tr R - 1)/2)` of `Ra^T Rb` (rad).
double rotationError(const Mat3& Ra, const Mat3& Rb);
/// The paper's eq. 19 metric: `|| EA_ZYX(Ra^-1 Rb) ||` (rad).
double eulerZyxError(const Mat3& Ra, const Mat3& Rb);

}  // namespace lowpair
