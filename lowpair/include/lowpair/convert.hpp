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
  /// parallel axes (a different, non-equivalent table): checkDhConversion then measures the deviation.
  double parallel_threshold = 0.0;
  /// Empty: each row's kind by the rule of docs/conventions.md ("Hayati rows"). Otherwise n + 1 kinds (base,
  /// link_1 .. link_n) that override the rule (dhUncertainty converts perturbed models with the central
  /// table's kinds). A row forced Hayati still takes the parallel branch when its axes are parallel within
  /// the threshold (then it is standard).
  std::vector<DhRowKind> row_kinds;
  /// Standard rows only, as published tables give them (Wu et al.'s Table II): the Hayati rule is not applied,
  /// so a row between nearly parallel axes may have a d far beyond L. Ignored when row_kinds is given.
  bool standard_only = false;

  /// The rule poeToDh applies (the CLI and the Python module call it too).
  /// @throws std::invalid_argument unless parallel_threshold is in [0, 1)
  void validate() const;
};

/// Conditioning of one D-H row: row 0 is the base, row i is link_i (placed by joint i+1's axis, or by
/// the tool for the last joint).
struct DhRowReport {
  int row = 0;
  double axis_angle = 0.0;   ///< angle between the line before and after this row, in [0, pi/2] (rad)
  bool parallel = false;     ///< the parallel-axis branch was taken (d is a free choice, set to 0)
  bool ill_conditioned = false;  ///< |d| or |a| exceeds kIllConditioned * L
  double abs_d = 0.0;        ///< |d| of the row (length)
  double abs_a = 0.0;        ///< |a| of the row (length)
  bool hayati = false;       ///< written as a Hayati row (d = 0, beta about the new y axis)
  double standard_d = 0.0;   ///< |d| the standard row would have had (its d; the last row max(|d|, |d_T|))
};

/// Conditioning of the tool transform `Rz(theta_T) Tz(d_T)` (Lemma 4).
struct DhToolReport {
  double abs_d = 0.0;            ///< |d_T| (length)
  bool ill_conditioned = false;  ///< |d_T| > kIllConditioned * L: the last axis is nearly parallel to the tool z
};

/// The result of poeToDh: the table and, per row, the data that says how well conditioned it is. No FK
/// check (checkDhConversion) and no sentences (the CLI words the conditioning from these fields).
struct DhConversion {
  DhModel model;
  double length_scale = 1.0;                 ///< robot size L
  double parallel_threshold = 0.0;           ///< the threshold on sin(alpha) that was used
  double rounding_parallel_threshold = 0.0;  ///< the rounding-level default `kParallelPerJoint * eps * n`
  /// The requested threshold is above rounding level: nearly parallel axes may have been snapped, so the
  /// table is a different model whose deviation only checkDhConversion measures.
  bool above_rounding = false;
  std::vector<DhRowReport> rows;  ///< n + 1 rows (base, link_1 .. link_n)
  DhToolReport tool;
  /// The accuracy bound's scale `max(L, max |d|, max |a|, |d_T|)` of the table (conversion.md, "Accuracy").
  double scale = 1.0;
};

/// POE -> D-H. Exact to rounding for every valid model (prismatic joints, exactly, nearly and
/// anti-parallel axes included); canonical output: angles in (-pi, pi], -0 and sub-tolerance residues
/// snapped to 0, `a >= 0` in every row placed by a joint axis (alpha >= 0 when a = 0), the last row
/// from Lemma 4 with alpha in [0, pi]. Offsets are folded into theta/d with the joint's scale.
/// Runs no FK check: call checkDhConversion where one is wanted.
/// @throws std::invalid_argument for a model without joints, a threshold outside [0, 1), or a table beyond
/// the magnitude limits (kMaxMagnitude): folded offsets move the D-H frames, so a model within a factor
/// (2n + 1) of the limit on L, or whose offsets slide a joint (|slideRate * scale * offset|) that far, can
/// have a D-H equivalent larger than any accepted model ("poeToDh: ..." names it)
DhConversion poeToDh(const PoeModel& model, const ConvertOptions& options = {});

/// Seeded configurations of the FK check beyond the zero configuration (`poe2dh` prints the check over
/// these 64 + 1).
constexpr int kFkCheckSamples = 64;

/// FK agreement of a D-H table with the POE model it was converted from, measured at `samples + 1`
/// configurations of the POE model's joint variables q: first `q_i = -offset_i` (every joint motion
/// `x_i = 0`), then `samples` configurations drawn from one std::mt19937_64 with a fixed seed, one
/// `u ~ uniform(-1, 1)` per joint in joint order: a joint with a range takes q uniform over its range,
/// whatever its type; without a range a revolute or helical joint takes `q = pi u` and a prismatic one
/// `q = (L / scale) u` (L = the robot size).
struct FkCheck {
  int samples = 0;               ///< configurations compared (samples + 1)
  double max_rotation = 0.0;     ///< rad
  double max_translation = 0.0;  ///< length
  /// The honest bound scale `max(L, max |d|, max |a|, |d_T|)` of the table (conversion.md).
  double scale = 1.0;
};

/// Compares `poe` and `dh` forward kinematics (conversion.md, "Accuracy and conditioning"). Deterministic
/// (fixed seed). @throws std::invalid_argument when the joint counts differ or samples < 0
FkCheck checkDhConversion(const PoeModel& poe, const DhModel& dh, int samples = kFkCheckSamples);

/// D-H -> base POE (exact: twists `Ad(G_i) [0 0 1 0 0 h]`, offsets 0).
PoeModel dhToPoe(const DhModel& model);

/// Modified (Craig) D-H regrouping of a standard D-H chain (docs/conventions.md):
/// `H = Rz(theta_B) Tz(d_B) prod_i [Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i + j x_i) Tz(d_i + k x_i)]
///  Rx(alpha_n) Tx(a_n) Rz(theta_T) Tz(d_T)`.
/// A Hayati row (docs/conventions.md) regroups with its `Ry(beta)` after `Tx(a)`:
/// `Rx(alpha_{i-1}) Tx(a_{i-1}) Ry(beta_{i-1}) Rz(theta_i + j x_i) Tz(d_i + k x_i)` (`beta` 0 otherwise).
struct ModifiedDhJoint : JointMotion {
  std::string name;
  double alpha = 0.0, a = 0.0, theta = 0.0, d = 0.0;
  double beta = 0.0;  ///< of the previous row when it is a Hayati row
};
struct ModifiedDh {
  double base_theta = 0.0, base_d = 0.0;
  std::vector<ModifiedDhJoint> joints;
  double tool_alpha = 0.0, tool_a = 0.0, tool_theta = 0.0, tool_d = 0.0;
  double tool_beta = 0.0;  ///< of the last row when it is a Hayati row
};
ModifiedDh toModifiedDh(const DhModel& model);
/// FK of the modified table (x_i = scale_i q_i). @throws std::invalid_argument unless q has a value per joint
Pose modifiedDhForwardKinematics(const ModifiedDh& model, const Eigen::Ref<const VecX>& q);

/// Angle wrapped into (-pi, pi].
double wrapAngle(double angle);

}  // namespace lowpair
