#pragma once
/// @file convert.hpp
/// POE <-> D-H conversion (Wu, Crawford, Roberts §III: Lemmas 1-4, eq. 18) and the modified (Craig)
/// D-H export of the same chain.

#include <string>
#include <vector>

#include "lowpair/model.hpp"

namespace lowpair {

struct ConvertOptions {
  /// Threshold on `sin(alpha)` below which an axis is treated as parallel to the current z.
  /// 0 selects the rounding-level default `kParallelPerJoint * eps * n`. A larger value snaps nearly
  /// parallel axes (a different, non-equivalent table): the result's fk_check then shows the deviation.
  double parallel_threshold = 0.0;
  /// Configurations sampled by the FK check (plus the zero configuration); 0 disables it.
  int fk_check_samples = 64;
};

/// Conditioning of one D-H row: row 0 is the base, row i is link_i (placed by joint i+1's axis, or by
/// the tool for the last joint).
struct DhRowReport {
  int row = 0;
  double axis_angle = 0.0;   ///< angle between the line before and after this row, in [0, pi/2] (rad)
  bool parallel = false;     ///< the parallel-axis branch was taken (d is a free choice, set to 0)
  bool ill_conditioned = false;  ///< |d| or |a| exceeds kIllConditioned * L
};

/// FK agreement of the converted table with the POE model, measured at the zero configuration and
/// `samples` seeded random configurations (revolute in [-pi, pi], prismatic over its range or [-L, L]).
struct FkCheck {
  int samples = 0;
  double max_rotation = 0.0;     ///< rad
  double max_translation = 0.0;  ///< length
  /// The honest bound scale `max(L, max |d|, max |a|)` of the table (design.md).
  double scale = 1.0;
};

struct DhConversion {
  DhModel model;
  double size = 1.0;  ///< robot size L
  double parallel_threshold = 0.0;  ///< the threshold that was used
  std::vector<DhRowReport> rows;    ///< n + 1 rows (base, link_1 .. link_n)
  std::vector<std::string> warnings;
  FkCheck fk_check;
};

/// POE -> D-H. Exact to rounding for every valid model (prismatic joints, exactly, nearly and
/// anti-parallel axes included); canonical output: angles in (-pi, pi], -0 and sub-tolerance residues
/// snapped to 0, `a >= 0` in every row placed by a joint axis (alpha >= 0 when a = 0), the last row
/// from Lemma 4 with alpha in [0, pi]. Offsets are folded into theta/d with the joint's scale.
DhConversion poeToDh(const PoeModel& model, const ConvertOptions& options = {});

/// D-H -> base POE (exact: twists `Ad(G_i) [0 0 1 0 0 h]`, offsets 0).
PoeModel dhToPoe(const DhModel& model);

/// Modified (Craig) D-H regrouping of a standard D-H chain (design.md):
/// `H = Rz(theta_B) Tz(d_B) prod_i [Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i + j x_i) Tz(d_i + k x_i)]
///  Rx(alpha_n) Tx(a_n) Rz(theta_T) Tz(d_T)`.
struct ModifiedDhJoint : JointMotion {
  std::string name;
  double alpha = 0.0, a = 0.0, theta = 0.0, d = 0.0;
};
struct ModifiedDh {
  double base_theta = 0.0, base_d = 0.0;
  std::vector<ModifiedDhJoint> joints;
  double tool_alpha = 0.0, tool_a = 0.0, tool_theta = 0.0, tool_d = 0.0;
};
ModifiedDh toModifiedDh(const DhModel& model);
/// FK of the modified table (x_i = scale_i q_i).
Pose modifiedDhForwardKinematics(const ModifiedDh& model, const Eigen::Ref<const VecX>& q);

/// Angle wrapped into (-pi, pi].
double wrapAngle(double angle);

}  // namespace lowpair
