#pragma once
/// @file jacobian.hpp
/// Manipulator Jacobians of the base POE model and of the D-H chain (docs/conventions.md, Jacobians).
///
/// Three Jacobians, each named by the frame and coordinates it uses:
/// - spatial `J_spatial`: twist coordinates `[w; v]` in the base frame, `V_s = (dg/dt) g^-1`
///   (`v` is the velocity of the point of the moving body at the base origin);
/// - body `J_body`: twist coordinates `[w; v]` in the tool frame, `V_b = g^-1 dg/dt = Ad(g^-1) V_s`;
/// - geometric `J_geometric` (Paden–Sastry eq. 3.13): rows `[v; w]`, `v` = linear velocity of the tool
///   origin and `w` = angular velocity, both in base coordinates.
///
/// Joint variables: joint i moves by `x_i = scale_i (q_i + offset_i)` (JointMotion), so every column is
/// `d/dq_i` and carries the factor `scale_i`.
/// A helical joint of pitch `h_i` (length/rad) contributes `h_i z_i` to the linear part.
///
/// Compute, then get (as Pinocchio's computeJointJacobians / getJointJacobian): computeJacobians runs
/// forward kinematics once, filling the joint frames as forwardKinematicsWithFrames does (they are what the
/// columns are made of) and `data.J_spatial` in the same pass; the three getters read `data` and never recompute.
/// Nothing allocates: outputs are preallocated `6 x dof` matrices.
///
/// | function | fills / reads | cost (PUMA 560, bench/README.md) |
/// |---|---|---|
/// | forwardKinematics (kinematics.hpp) | `T_base_tool` only | one chain product |
/// | forwardKinematicsWithFrames (kinematics.hpp) | `T_base_joint`, `T_base_tool` | one chain product |
/// | computeJacobians | `T_base_joint`, `T_base_tool` and `J_spatial` | FK with frames + one column per joint |
/// | getSpatialJacobian | reads `J_spatial` | a copy |
/// | getGeometricJacobian | reads `J_spatial`, `T_base_tool` | one cross product per column |
/// | getBodyJacobian | reads `J_spatial`, `T_base_tool` | one adjoint per column |
/// | computeJacobiansBatch | many configurations: poses and one Jacobian each | SIMD across configurations |

#include "lowpair/kinematics.hpp"
#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// Forward kinematics and the spatial Jacobian: column i = `scale_i [j_i z_i; j_i o_i x z_i + k_i z_i]`
/// (the current joint twist in the base frame, `Ad(exp(xi_1 x_1) ... exp(xi_{i-1} x_{i-1})) xi_i` of Wu et
/// al. eq. 4), from joint i's line `(z_i, o_i)` = z axis and origin of `data.T_base_joint[i]`.
/// @throws std::invalid_argument, in every build type, when q does not have dof values or data was made
/// for a model with another number of joints, e.g. "computeJacobians: q has 5 values, the model has 6
/// joints" or "computeJacobians: data was made for a model with 7 joints, this model has 6".
void computeJacobians(const PoeModel& model, Data& data, const Eigen::Ref<const VecX>& q);
void computeJacobians(const DhModel& model, Data& data, const Eigen::Ref<const VecX>& q);

/// Reads the spatial Jacobian (`[w; v]`, base frame). Precondition: computeJacobians on this data.
/// @throws std::invalid_argument unless J_spatial is 6 x dof.
void getSpatialJacobian(const Data& data, Eigen::Ref<Mat6X> J_spatial);
/// Body Jacobian `Ad(g(q)^-1) J_spatial` (`[w; v]`, tool frame).
void getBodyJacobian(const Data& data, Eigen::Ref<Mat6X> J_body);
/// Geometric Jacobian (Paden-Sastry eq. 3.13), rows `[v; w]`: column i =
/// `scale_i [j_i z_i x (o_tool - o_i) + k_i z_i; j_i z_i]` (`(j, k)` of JointMotion).
void getGeometricJacobian(const Data& data, Eigen::Ref<Mat6X> J_geometric);

/// The frame and coordinates of a Jacobian (file comment): spatial `[w; v]` base frame, body `[w; v]` tool frame,
/// geometric `[v; w]` (the tool origin's velocity), base frame.
enum class JacobianFrame { Spatial, Body, Geometric };

/// Batched computeJacobians + get, structure of arrays as forwardKinematicsBatch (kinematics.hpp): SIMD across
/// configurations (4 lanes with AVX2, 8 with AVX-512), the same results as the single form to rounding.
/// Allocates nothing.
/// @param q `count x dof`: column i holds joint i of every configuration.
/// @param frame which Jacobian (getSpatialJacobian, getBodyJacobian, getGeometricJacobian).
/// @param jacobians `count x 6 dof` output: row k is configuration k's `6 x dof` Jacobian, row-major (entry
/// `(r, i)` in column `r dof + i`), the order of numpy's `(count, 6, dof)`.
/// @param poses `count x 12` output: `T_base_tool` as forwardKinematicsBatch writes it.
/// @throws std::invalid_argument, in every build type, when q does not have dof columns
/// ("computeJacobiansBatch: q has 5 columns, the model has 6 joints"), poses is not `count x 12` or jacobians
/// not `count x 6 dof`.
void computeJacobiansBatch(const PoeModel& model, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                           Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses);
void computeJacobiansBatch(const DhModel& model, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                           Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses);

/// `J_body = Ad(T_base_tool^-1) J_spatial`. Column by column, so `J_body` may alias `J_spatial`.
/// The four conversions throw std::invalid_argument when input and output differ in column count.
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
