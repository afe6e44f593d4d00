#pragma once
/// @file jacobian.hpp
/// Manipulator Jacobians of the base POE model and of the D-H chain (design.md "Geometric Jacobian").
///
/// Three Jacobians, each named by the frame and coordinates it uses:
/// - spatial `J_spatial`: twist coordinates `[w; v]` in the base frame, `V_s = (dg/dt) g^-1`
///   (`v` is the velocity of the point of the moving body at the base origin);
/// - body `J_body`: twist coordinates `[w; v]` in the tool frame, `V_b = g^-1 dg/dt = Ad(g^-1) V_s`;
/// - geometric `J_geometric` (Paden–Sastry eq. 3.13): rows `[v; w]`, `v` = linear velocity of the tool
///   origin and `w` = angular velocity, both in base coordinates.
///
/// Joint variables: joint i moves by `x_i = scale_i (q_i + offset_i)` (POE) or `x_i = scale_i q_i`
/// (D-H, offsets folded into the table), so every column is `d/dq_i` and carries the factor `scale_i`.
/// A helical joint of pitch `h_i` (length/rad) contributes `h_i z_i` to the linear part.
///
/// Every function also runs forward kinematics into `data` (`data.T_base_tool` etc. are valid on
/// return) and allocates nothing: outputs are preallocated `6 x dof` matrices.

#include "lowpair/kinematics.hpp"
#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// Spatial Jacobian: column i = `scale_i Ad(exp(xi_1 x_1) ... exp(xi_{i-1} x_{i-1})) xi_i`
/// (the current joint twist in the base frame, Wu et al. eq. 4 for Ad).
/// @param q joint variables (size dof); @param J_spatial 6 x dof output.
/// @throws std::invalid_argument if `q` or `J_spatial` has the wrong size.
void spatialJacobian(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q,
                     Eigen::Ref<Mat6X> J_spatial);
/// Body Jacobian `Ad(g(q)^-1) J_spatial`.
void bodyJacobian(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q, Eigen::Ref<Mat6X> J_body);
/// Geometric Jacobian (Paden–Sastry eq. 3.13), rows `[v; w]`: column i =
/// `scale_i [z_i x (o_tool - o_i) + h_i z_i; z_i]` (revolute h = 0, helical) or `scale_i [z_i; 0]` (prismatic),
/// with `z_i` the current axis direction and `o_i` a point on it, `o_tool` the tool origin.
void geometricJacobian(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q,
                       Eigen::Ref<Mat6X> J_geometric);

/// The same three for the D-H chain (eq. 10). Joint i's axis is the z axis of `data.T_base_frame[i]`.
void spatialJacobian(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q, Eigen::Ref<Mat6X> J_spatial);
void bodyJacobian(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q, Eigen::Ref<Mat6X> J_body);
void geometricJacobian(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q,
                       Eigen::Ref<Mat6X> J_geometric);

/// `J_body = Ad(T_base_tool^-1) J_spatial`. Column by column, so `J_body` may alias `J_spatial`.
void spatialToBody(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_spatial, Eigen::Ref<Mat6X> J_body);
/// `J_spatial = Ad(T_base_tool) J_body` (inverse of spatialToBody; may alias).
void bodyToSpatial(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_body, Eigen::Ref<Mat6X> J_spatial);
/// Geometric from spatial: `[v + w x p_tool; w]` for each spatial column `[w; v]` (may alias).
void spatialToGeometric(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_spatial,
                        Eigen::Ref<Mat6X> J_geometric);
/// Spatial from geometric: `[w; v - w x p_tool]` (inverse of spatialToGeometric; may alias).
void geometricToSpatial(const Pose& T_base_tool, const Eigen::Ref<const Mat6X>& J_geometric,
                        Eigen::Ref<Mat6X> J_spatial);

}  // namespace lowpair
