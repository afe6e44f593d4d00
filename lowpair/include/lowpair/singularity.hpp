#pragma once
/// @file singularity.hpp
/// Singular configurations (Paden & Sastry 1984): numerical rank of the geometric Jacobian, the
/// geometric classes C1..C7 of docs/conventions.md read off the joint lines, and the wrist/arm decoupling of §5.
///
/// **Dimensionless Jacobian.** The analysis uses `J_n = D_r J_geometric D_c` with
/// `D_r = diag(I/L, I)` (linear rows divided by the robot size L) and `D_c = diag(1/scale_i)` for
/// revolute/helical and `diag(L/scale_i)` for prismatic joints. Each column of `J_n` is then the unit
/// screw of its joint in units of L: `[z x (o_tool - o)/L + (h/L) z; z]` or `[z; 0]`, so every entry is
/// O(1) whatever the robot's unit and joint scales, and the rank (invariant under the invertible row and
/// column scalings) is measured on a well-scaled matrix. sigma_min, manipulability and condition are
/// those of `J_n`.
///
/// **Rank rule.** `rank = #{sigma_k > tol}`, `tol = kRankFactor * max(6, n) * eps * sigma_max(J_n)`
/// (`~1.3e-12 sigma_max` for six joints). Rationale: the computed J_n of a configuration that is exactly
/// singular differs from an exactly singular matrix by the rounding of the forward kinematics and of the
/// closed-form joint values, a few eps per joint times ||J_n||; by Weyl's inequality its smallest singular
/// value is then below `c n eps sigma_max` with c of order 10. kRankFactor = 1000 leaves two orders of
/// margin above that, and stays six orders below the sigma_min ~ 1e-6 of a pose rounded to 1e-3 degrees
/// (docs/robots.md §7), which is therefore regular.
///
/// **Line classes.** Each joint is a line (unit direction z_i, point o_i nearest the base origin) at the
/// configuration. Two directions are parallel when `|z_i x z_j| <= tol` (rad); a point is on a line or
/// plane when its distance is `<= tol * L`. On a regular pose tol = kLineTolerance (1e-13, an order below
/// the rank tolerance: a class that held within it would keep sigma_min below the rank threshold, so for
/// a 6-joint robot a class on a regular pose cannot occur). Once the rank test has found a deficiency,
/// tol = kLineToleranceSingular (1e-8): a pose at the rank threshold can be ~1e-10 away from the exact
/// singular geometry, and the classes must explain the deficiency that was found. Classes use revolute
/// joints only (h = 0; helical joints of
/// different pitch on one line are independent screws), C7 adds a prismatic one.
///
/// **Long chains.** The class search compares every pair of axes with every other axis: O(n^3), O(n^4)
/// when many axes share a plane or a point. It runs only up to kClassSearchMaxJoints joints
/// (tolerances.hpp); a longer chain gets rank, singular values, blocks, the wrist/arm split and the null
/// vectors asked for (SingularityOptions), with `classes_searched = false`.

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/tolerances.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// The joint line at a configuration (base frame).
struct JointLine {
  JointType type = JointType::Revolute;
  Vec3 direction = Vec3::UnitZ();  ///< unit z_i (prismatic: the sliding direction)
  Vec3 point = Vec3::Zero();       ///< o_i: the point of the axis nearest the base origin (0 for prismatic)
  double pitch = 0.0;              ///< length/rad
};

/// One singular class found at a configuration: which, the joints, and the geometry that names it (the
/// CLI words it, e.g. "joint axes 4 and 6 are collinear").
struct SingularClass {
  std::string id;            ///< "C1".."C7" or "other" (conventions.md)
  std::vector<int> joints;   ///< 1-based joint numbers, ascending
  /// C3: the point all the axes pass through; C6 (not at infinity): a point of the line every axis meets
  /// (the one nearest the tool origin). Base frame, length.
  Vec3 point = Vec3::Zero();
  /// C6: the unit direction of the line every axis meets; at infinity, the unit normal every axis is
  /// perpendicular to.
  Vec3 direction = Vec3::Zero();
  bool at_infinity = false;  ///< C6: the common line is at infinity (a pure couple is reciprocal to every axis)
  int prismatic_joint = 0;   ///< C7: the prismatic joint (1-based); the other two in `joints` are the parallel axes
};

/// Paden–Sastry §5: three consecutive revolute axes meeting in one point P (a spherical wrist). With the
/// row operation row1 += (o_tool - P) x row2 (eq. 5.2) the Jacobian becomes block triangular:
/// `[[a_k] 0; * [z_4 z_5 z_6]]` with arm vectors `a_k = z_k x (P - o_k) + h_k z_k` (revolute/helical) or
/// `a_k = z_k` (prismatic) for the other joints. J is singular iff the wrist axes are coplanar (a) or the
/// arm vectors are coplanar (b).
struct DecoupledAnalysis {
  bool applies = false;
  std::array<int, 3> wrist_joints{};  ///< 1-based
  Vec3 wrist_point = Vec3::Zero();    ///< P, base frame
  std::vector<int> arm_joints;        ///< 1-based, the other joints
  bool wrist_singular = false;        ///< (a): rank [z_w1 z_w2 z_w3] < 3
  bool arm_singular = false;          ///< (b): rank [a_k / L or z_k] < min(3, number of arm joints)
  double wrist_sigma_min = 0.0;       ///< of the 3x3 wrist block (dimensionless)
  double arm_sigma_min = 0.0;         ///< of the 3 x (n-3) arm block in units of L
};

struct SingularityReport {
  int dof = 0;
  int rank = 0;                 ///< numerical rank of J_n (see the file comment)
  bool singular = false;        ///< rank < min(6, dof)
  double length_scale = 1.0;    ///< L
  double tolerance = 0.0;       ///< the rank threshold on the singular values of J_n
  VecX singular_values;         ///< of J_n, descending, min(6, dof) of them
  double sigma_min = 0.0;       ///< smallest of singular_values
  /// Yoshikawa manipulability `sqrt(det(J_n J_n^T))` for dof >= 6; for dof < 6 (where that is 0) the
  /// product of the singular values `sqrt(det(J_n^T J_n))`.
  double manipulability = 0.0;
  double condition = 0.0;       ///< sigma_max / sigma_min (+inf when sigma_min = 0)
  int rank_linear = 0;          ///< rank of the 3 x n linear block (tool-origin velocities)
  int rank_angular = 0;         ///< rank of the 3 x n angular block
  std::vector<JointLine> lines; ///< the joint lines used by the classification
  /// The classes were searched: dof <= kClassSearchMaxJoints. Otherwise `classes` is empty because the
  /// search was skipped, not because no class holds.
  bool classes_searched = true;
  std::vector<SingularClass> classes;
  DecoupledAnalysis decoupled;
  int nullity = 0;  ///< dof - rank: the dimension of the null space of J_n
  /// The first min(nullity, SingularityOptions::max_null_vectors) vectors of an orthonormal basis of the x
  /// with J_n x ~ 0: the dependent unit joint screws (the joint velocity is `qdot_i = x_i / scale_i`, times
  /// L for prismatic joints). The basis starts with the right singular vectors of the deficient singular
  /// values; for n > 6 it continues with the self-motion (the complement of J_n's row space).
  std::vector<VecX> null_space;
};

/// What analyzeSingularity returns beyond the rank, the singular values and the classes.
struct SingularityOptions {
  /// At most this many null-space vectors (`SingularityReport::nullity` counts them all). A chain of n
  /// joints has up to n of them, n^2 numbers: bound it for long chains.
  int max_null_vectors = std::numeric_limits<int>::max();

  /// The rule analyzeSingularity applies (the CLI and the Python module call it too).
  /// @throws std::invalid_argument for max_null_vectors < 0
  void validate() const;
};

/// In place: the geometric Jacobian (rows [v; w]) of `model` made dimensionless, `J_n = D_r J D_c`
/// (file comment): linear rows over L, columns over the joint scale, prismatic columns times L.
/// @throws std::invalid_argument unless J_geometric has dof columns
void dimensionlessJacobian(const PoeModel& model, Eigen::Ref<Mat6X> J_geometric);

/// The rank threshold `kRankFactor * max(6, dof) * eps * sigma_max` on the singular values of J_n.
double rankTolerance(double sigma_max, int dof);

/// Number of singular values above `tolerance`.
int numericalRank(const Eigen::Ref<const VecX>& singular_values, double tolerance);

/// The rank rule applied to a geometric Jacobian of `model` (from the library or from elsewhere, e.g.
/// MuJoCo): J_n, its singular values (descending, min(6, dof)) and the count above rankTolerance.
struct JacobianRank {
  int rank = 0;
  double tolerance = 0.0;
  VecX singular_values;
};
JacobianRank jacobianRank(const PoeModel& model, const Eigen::Ref<const Mat6X>& J_geometric);

/// Joint lines of a POE model at q (from the forward-kinematics prefix frames).
std::vector<JointLine> jointLines(const PoeModel& model, const Eigen::Ref<const VecX>& q);

/// Rank, singular values, classes C1..C7 / `other`, the decoupled wrist/arm analysis and the null space at q.
/// For a 6-joint robot a class is reported exactly when the rank is deficient (`other` when no listed
/// class explains the dependency). For other joint counts `singular` means rank < min(6, dof), the line
/// classes are still listed as degenerate axis sets, and `other` is added when singular without a class.
/// Chains of more than kClassSearchMaxJoints joints are not searched for classes (`classes_searched`
/// false); everything else is computed in O(dof) time and memory plus the null vectors asked for.
/// @throws std::invalid_argument unless q has dof finite entries and max_null_vectors >= 0.
SingularityReport analyzeSingularity(const PoeModel& model, const Eigen::Ref<const VecX>& q,
                                     const SingularityOptions& options = {});

}  // namespace lowpair
