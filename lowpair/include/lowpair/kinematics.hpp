#pragma once
/// @file kinematics.hpp
/// Forward kinematics of the base, tool and local POE forms (Wu et al. eqs. 5-7) and of the D-H chain
/// (eq. 10). Free functions writing into a preallocated workspace; no allocation after the workspace
/// is built (tests/alloc_test.cpp proves it).

#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// Workspace for POE forward kinematics, built once per model.
struct PoeData {
  explicit PoeData(const PoeModel& model);
  /// Filled by forwardKinematics:
  std::vector<Pose> T_base_joint;  ///< [i] = exp(xi_1 x_1) ... exp(xi_i x_i), i = 0..n-1 (prefix products)
  Pose T_base_tool;                ///< g(q)
};

/// Workspace for D-H forward kinematics.
struct DhData {
  explicit DhData(const DhModel& model);
  /// Filled by forwardKinematics:
  std::vector<Pose> T_base_frame;  ///< [i] = frame whose z is joint i's axis (before its motion), i = 0..n-1
  Pose T_base_tool;                ///< H(q)
};

/// `g(q)` of the base POE model (eq. 5). @param q joint variables, size dof (unchecked; see checkJointVector).
void forwardKinematics(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q);
/// `H(q)` of the D-H chain (eq. 10).
void forwardKinematics(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q);

/// Convenience forms returning `T_base_tool` (allocate their workspace).
Pose poeForwardKinematics(const PoeModel& model, const Eigen::Ref<const VecX>& q);
Pose dhForwardKinematics(const DhModel& model, const Eigen::Ref<const VecX>& q);

/// `exp(xi_bar x)` of one normalized joint with `x = scale (q + offset)`.
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

Pose forwardKinematics(const ToolPoeModel& model, const Eigen::Ref<const VecX>& q);
Pose forwardKinematics(const LocalPoeModel& model, const Eigen::Ref<const VecX>& q);

/// Geodesic rotation error `atan2(|vee(R - R^T)|/2, (tr R - 1)/2)` of `Ra^T Rb` (rad).
double rotationError(const Mat3& Ra, const Mat3& Rb);
/// The paper's eq. 19 metric: `|| EA_ZYX(Ra^-1 Rb) ||` (rad).
double eulerZyxError(const Mat3& Ra, const Mat3& Rb);

}  // namespace lowpair
