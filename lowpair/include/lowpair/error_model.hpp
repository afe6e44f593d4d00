#pragma once
/// @file error_model.hpp
/// The error model of a POE model for calibration (Wu, Crawford, Roberts §V; docs/calibration.md).
///
/// Error model (type preserving): joint i's unit twist moves as `xi <- Ad(exp(eta)) xi` (this keeps |w|,
/// w.v and w = 0, i.e. the joint type and pitch), a helical joint (or any revolute/helical joint with
/// free pitch) gets a pitch increment `v <- v + dh w`, every joint a scale increment `scale <- scale + ds`,
/// and the tool `T <- exp(eta_T) T`. Joint offsets are not parameters: they are absorbed (§V).
///
/// The identification parameters are local coordinates of that error model at a model, one per
/// identifiable direction (so the parameter count is the paper's `5h + 4r + 2t + n + 6`):
/// - revolute/helical joint with unit axis `w` through `c` (the line's point nearest the base origin) and
///   unit vectors `u1, u2` perpendicular to `w` (`u1 = w x e`, `e` the base axis least aligned with w):
///   `tilt1, tilt2` (rad) turn the line about `c + s u_k` (`eta = [u_k; c x u_k]`), `shift1, shift2`
///   (length) move it along `u_k` (`eta = [0; u_k]`); `pitch` (length/rad) when helical or freed;
/// - prismatic joint with unit direction `v`: `tilt1, tilt2` (rad) turn it about `u_k` (`eta = [u_k; 0]`);
/// - every joint: `scale` (dimensionless, absolute increment of `scale`);
/// - tool: `rx, ry, rz` (rad) turn it about base-parallel axes through the tool point, `x, y, z` (length)
///   translate it (`eta_T = [r; p_T x r + t]`).
/// - joint deflections (deflection.hpp; docs/calibration.md "Beyond geometry"): `compliance` (joint-variable unit per
///   N m, per N for a prismatic joint) and `backlash` (joint-variable unit) of the joints the spec names: joint i
///   stands at `q_i + c_i tau_i + b_i s_i`, so their columns are joint i's offset column times `tau_i` or `s_i`,
///   the pose's inputs (PoseLoad); the model's rows are evaluated at the deflected joint values.
/// Measurement rows per pose: `[dtheta (3, rad, base frame); dp (3, length)]` for full poses, `dp` for
/// position-only measurements, where a model change moving the tool by the spatial twist `[dw; dv]` gives

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/convert.hpp"
#include "lowpair/deflection.hpp"
#include "lowpair/measure.hpp"
#include "lowpair/model.hpp"

namespace lowpair {

/// The paper's count `5h + 4r + 2t + n + tool` (§V) with its breakdown.
struct ParameterCount {
  int helical = 0, revolute = 0, prismatic = 0;  ///< joints of each type (revolute with free pitch: helical)
  int scales = 0;                                ///< n, one scale per joint
  /// 6 (full pose), 3 (position only), or with targets `3 u + r`: u unknown targets' points, and r the tool
  /// frame's directions the known points fix (knownPointsToolRank: 0 without, 3 for one point, 5 for
  /// collinear points, 6 for three or more non-collinear ones), or 6 with pose measurements among them
  int tool = 6;
  int deflections = 0;  ///< one per compliant joint and one per joint with backlash (deflection.hpp)
  int total() const { return 5 * helical + 4 * revolute + 2 * prismatic + scales + tool + deflections; }
};

enum class ParameterKind {
  Tilt, Shift, Pitch, Scale, ToolRotation, ToolTranslation,
  Offset,                         ///< a joint offset (level `offsets`: not part of the minimal set, §V)
  BaseRotation, BaseTranslation,  ///< the whole model moved in the measurement frame (level `offsets`)
  TargetPoint,                    ///< a target's point on the tool, tool-frame x, y, z
  Compliance, Backlash            ///< a joint's deflection (deflection.hpp), in every set when the spec names the joint
};

/// Which parameters a calibration fits (docs/calibration.md "Which parameters"):
/// - Full: the minimal complete set (the count `5h + 4r + 2t + n + 6`, or `+ 3k` with k targets);
/// - Lines: the joint lines (tilts, shifts, pitches) and the tool (or targets), no scales;
/// - Offsets: the joint offsets, the base (the model moved as a whole: the measurement frame) and the tool
///   (or targets); the base's turn about the first axis and the tool's about the last duplicate those
///   joints' offsets (reported as undetermined, left where the registration put them);
/// - Named: the parameters named in `names`, any of the three levels' (`j2.offset`, `base.rz`, `j3.tilt1`).
enum class ParameterSet { Full, Lines, Offsets, Named };

/// "full" / "lines" / "offsets" / "named".
const char* parameterSetName(ParameterSet set);

/// What an error model parameterizes: the options of ErrorModel, identifiableCount, fullErrorModelJacobian,
/// dhIdentificationJacobian and analyzeIdentifiability (`ErrorModelSpec{true}` frees the pitch; the last
/// three and the count read only `free_pitch` and `targets`).
struct ErrorModelSpec {
  bool free_pitch = false;          ///< revolute joints get a pitch parameter as well (counted as helical)
  ParameterSet set = ParameterSet::Full;
  std::vector<std::string> names{};   ///< ParameterSet::Named
  /// Measure::Targets: the targets (measure.hpp; the type of CalibrationOptions::targets), each with its point
  /// in the tool frame (`point_tool`, required here: the error model is evaluated there). An unknown target gets
  /// 3 parameters (`target.NAME.x`, `.y`, `.z`, tool frame), a known one (`known`) none: its point is fixed.
  /// NAME is the target's name; when one target's name is empty, every target is numbered instead ("1", "2",
  /// ..., so that no number collides with a name). Without known points the tool's 6 parameters are left out
  /// (the points carry the tool frame); with one or more they are kept.
  std::vector<Target> targets{};
  /// Targets: some measurements are of the whole tool frame (mixed data, kPoseMeasurement): the tool's 6
  /// parameters are kept, and the pose measurements determine them.
  bool pose_measurements = false;
  /// Joint deflections (deflection.hpp): the 0-based joints whose compliance (`jK.compliance`) and backlash
  /// (`jK.backlash`) are parameters (in every set, Named included), and the current values of every joint's
  /// (applied whether they are parameters or not; empty: none).
  std::vector<int> compliance_joints{}, backlash_joints{};
  JointDeflection deflection{};
  bool knownTarget(size_t t) const { return t < targets.size() && targets[t].known; }
  std::vector<Vec3> knownPoints() const;  ///< the known targets' points, in order (@throws as validate)
  /// The tool frame has parameters: no targets, at least one known, or pose measurements among them.
  bool toolParameters() const;

  /// The rules on the spec alone (ErrorModel, fullErrorModelJacobian, dhIdentificationJacobian,
  /// analyzeIdentifiability and knownPoints, so identifiableCount with targets, call it; the deflections are
  /// checked against the model there).
  /// @throws std::invalid_argument naming the target for a target without a point or with one not finite
  void validate() const;
};

/// The tool-frame directions that known points (tool frame, at least `L`-sized robot) fix: 0 for none, 3 for
/// one point (or coincident ones: the turns about it are free), 5 for collinear ones (the turn about their
/// line is free), 6 otherwise. Coincident: every difference at most `kRankFactor eps L`; collinear: the
/// differences' second singular value at most numericalRankTolerance of the first.
int knownPointsToolRank(const std::vector<Vec3>& known_points, double L);

/// The count for `spec.free_pitch` and, for Measure::Targets, the targets (tool: `3 u + r`, ParameterCount::tool).
ParameterCount identifiableCount(const PoeModel& model, Measure measure, const ErrorModelSpec& spec = {});

/// One identification parameter (a column of the identification Jacobian).
struct Parameter {
  ParameterKind kind = ParameterKind::Tilt;
  int joint = -1;      ///< 0-based joint, -1 for the tool
  int component = 0;   ///< 0/1 for tilt and shift, 0..2 (x, y, z) for the tool
  std::string name;    ///< "j3.tilt1", "j3.shift2", "j3.pitch", "j3.scale", "j3.offset", "tool.rx", "tool.z",
                       ///< "base.rx", "base.z", "target.smr_a.x", "j2.compliance", "j5.backlash" (1-based joints)
  std::string unit;    ///< "rad", "length", "length/rad", "1", "rad/(N m)", "length/N"
};

/// The error model's local coordinates at one model (see the file comment).
class ErrorModel {
 public:
  /// @throws std::invalid_argument for a Named set naming a parameter the model does not have (or none), and as
  /// ErrorModelSpec::validate (a target without a point)
  explicit ErrorModel(const PoeModel& model, const ErrorModelSpec& spec = {});

  const PoeModel& model() const { return model_; }
  bool freePitch() const { return spec_.free_pitch; }
  const ErrorModelSpec& spec() const { return spec_; }
  /// The targets' points (tool frame) at this model, index = Measurement::target (the points of
  /// `spec().targets`); empty without targets.
  const std::vector<Vec3>& targetPoints() const { return target_points_; }
  const std::vector<Parameter>& parameters() const { return parameters_; }
  int size() const { return static_cast<int>(parameters_.size()); }
  /// The model moved by `delta` (one entry per parameter): `Ad(exp(eta))` per joint, pitch and scale
  /// increments, `exp(eta_T)` on the tool. Joint names, offsets and ranges are kept; with free pitch a
  /// joint's type follows its new pitch (revolute when |pitch| <= kPitchZero eps L, the pitch then 0).
  /// @throws std::invalid_argument when a scale would become <= 0 or a number non-finite
  PoeModel apply(const Eigen::Ref<const VecX>& delta) const;
  /// apply() as data: the moved model, or nothing where apply throws (a scale through 0, a model beyond
  /// the magnitude limits): a fit's trial step or a probe that leaves the valid models.
  std::optional<PoeModel> tryApply(const Eigen::Ref<const VecX>& delta) const;
  /// The targets' points moved by `delta` (tool frame; a known target's stays).
  std::vector<Vec3> applyTargetPoints(const Eigen::Ref<const VecX>& delta) const;
  /// The joint deflections moved by `delta` (every joint's; entries sized to the model's joints when a
  /// deflection parameter exists).
  JointDeflection applyDeflection(const Eigen::Ref<const VecX>& delta) const;
  /// The current joint deflections (ErrorModelSpec::deflection).
  const JointDeflection& deflection() const { return spec_.deflection; }
  /// The same parameters, their directions (the eta twists) kept from this model, at another model of the
  /// same robot (a calibration iterate): the coordinates of every iterate then mean the same thing.
  /// `target_points`: the targets' points there (as targetPoints(); applyTargetPoints of a step), one per target.
  ErrorModel rebased(const PoeModel& model) const;
  ErrorModel rebased(const PoeModel& model, const std::vector<Vec3>& target_points) const;
  ErrorModel rebased(const PoeModel& model, const std::vector<Vec3>& target_points,
                     const JointDeflection& deflection) const;
  /// Identification Jacobian at `q`: d(measured quantity)/d(parameters), 6 rows `[dtheta; dp]` (Pose) or
  /// 3 rows `dp` (Position; Targets: of target `target`'s point), `size()` columns; units: rad and length
  /// per parameter unit. Also returns the model's `T_base_tool(q)`.
  Pose jacobian(const Eigen::Ref<const VecX>& q, Measure measure, Eigen::Ref<MatX> rows, int target = -1) const;
  /// The same at the commanded `q` with the pose's deflection inputs: rows and pose at the deflected joint values
  /// `deflectedJoints(deflection(), q, load)`, a compliance column times `load.torque`, a backlash column times
  /// `load.sign` (empty: 0).
  Pose jacobian(const Eigen::Ref<const VecX>& q, const PoseLoad& load, Measure measure, Eigen::Ref<MatX> rows,
                int target = -1) const;

 private:
  PoeModel model_;
  ErrorModelSpec spec_;
  std::vector<Vec3> target_points_;  // the points of spec_.targets (the Jacobian's and the fit's)
  std::vector<Parameter> all_;       // every candidate parameter, in column order of the full computation
  std::vector<int> selected_;        // indices into all_ of the parameters
  std::vector<int> target_columns_;  // per target: index into all_ of its x parameter, -1 when known
  std::vector<int> offset_columns_;  // per joint: index into all_ of its offset parameter
  struct DeflectionColumn {
    int column = 0, joint = 0;  // index into all_ (after the targets'), 0-based joint
    bool compliance = true;     // else backlash
  };
  std::vector<DeflectionColumn> deflection_columns_;
  std::vector<Parameter> parameters_;
  std::vector<std::array<Vec6, 4>> basis_;  // per joint: eta of tilt1, tilt2, shift1, shift2 (prismatic: 2)
  Vec3 center_ = Vec3::Zero();              // the base parameters turn the model about this point
  VecX expanded(const Eigen::Ref<const VecX>& delta) const;  // delta over all_ (0 where not selected)
};

/// The error model without local reduction: per joint the 6 coordinates of `eta` (base frame), the pitch
/// (helical or freed), the scale and the offset; the tool's 6 coordinates of `eta_T`. Its columns are
/// redundant by construction (2 per revolute/helical joint, 4 per prismatic joint, every offset); its rank
/// is the number of identifiable parameters (what identifiability compares with the count).
/// @return `6n + pitches + 2n + 6` columns, rows as ErrorModel::jacobian
/// Measure::Targets: rows per pose and target (3 each), and 3 more columns per target (its point, tool frame).
/// @param spec its `free_pitch`, `targets` and deflections (one more column per deflection parameter, after the
/// tool's; rows at the deflected joint values)
/// @param loads per pose the deflection inputs (empty: none)
MatX fullErrorModelJacobian(const PoeModel& model, const std::vector<VecX>& q, Measure measure,
                            const ErrorModelSpec& spec = {}, const std::vector<PoseLoad>& loads = {});

/// The D-H parameterization of the same robot (poeToDh of the model): base `theta, d, alpha, a`, per
/// joint `theta, d, alpha, a` (+ `pitch` when helical or freed) + `scale`, tool `theta, d`; analytic
/// columns. @param spec its `free_pitch`, `targets` and deflections (as fullErrorModelJacobian; D-H joint i's
/// motion column times its input)
/// @param names receives the column names ("base.theta", "j2.a", "tool.d", "j2.compliance", ...)
MatX dhIdentificationJacobian(const DhModel& model, const std::vector<VecX>& q, Measure measure,
                              const ErrorModelSpec& spec = {}, std::vector<std::string>* names = nullptr,
                              const std::vector<PoseLoad>& loads = {});

/// The spec's deflections against the poses' inputs: joint indices in range and unrepeated, value vectors empty or
/// one per joint, one load per pose; and every deflection parameter's input varies over the poses (a torque
/// whose spread over the poses is at most kRankFactor n eps of the largest torque, a sign the same at every pose,
/// cannot be told from the joint's offset: a vertical first axis carries no gravity torque).
/// @throws std::invalid_argument naming the joint and what does not vary
void checkDeflections(const PoeModel& model, const ErrorModelSpec& spec, const std::vector<PoseLoad>& loads);


}  // namespace lowpair
