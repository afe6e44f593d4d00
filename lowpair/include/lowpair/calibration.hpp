#pragma once
/// @file calibration.hpp
/// Identifiability and calibration of POE models (Wu, Crawford, Roberts §V-VI; docs/calibration.md).
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
/// Measurement rows per pose: `[dtheta (3, rad, base frame); dp (3, length)]` for full poses, `dp` for
/// position-only measurements, where a model change moving the tool by the spatial twist `[dw; dv]` gives
/// `dtheta = dw` and `dp = dv + dw x p_tool`.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/convert.hpp"
#include "lowpair/model.hpp"

namespace lowpair {

/// What a measurement observes of the tool: its frame, its origin, or points fixed on it (targets: a laser
/// tracker's SMRs, several per pose, each at an unknown or known point of the tool).
enum class Measure { Pose, Position, Targets };

/// "pose" / "position" / "targets".
const char* measureName(Measure measure);

/// Rows per measurement: 6 for Pose (`[dtheta; dp]`), 3 otherwise.
int rowsPerMeasurement(Measure measure);

/// One measurement: joint variables of the model and what was measured in the measurement frame (the base
/// frame of the model being calibrated): the tool frame (Pose), its origin (Position: `T_base_tool.p`), or
/// one target's point (Targets: `T_base_tool.p`, `target` its index).
struct Measurement {
  VecX q;
  Pose T_base_tool;
  int target = -1;  ///< Targets: index into the targets (CalibrationOptions::targets); -1 otherwise
};

/// A point fixed on the tool (an SMR): its name and, when known, its position in the tool frame (length).
struct Target {
  std::string name;
  std::optional<Vec3> point_tool;
};

/// The paper's count `5h + 4r + 2t + n + tool` (§V) with its breakdown.
struct ParameterCount {
  int helical = 0, revolute = 0, prismatic = 0;  ///< joints of each type (revolute with free pitch: helical)
  int scales = 0;                                ///< n, one scale per joint
  int tool = 6;  ///< 6 (full pose), 3 (position only) or 3k (k targets: their points; the tool frame is theirs)
  int total() const { return 5 * helical + 4 * revolute + 2 * prismatic + scales + tool; }
};

/// @param free_pitch revolute joints get a pitch parameter (counted as helical)
/// @param targets k, for Measure::Targets (tool: 3k)
ParameterCount identifiableCount(const PoeModel& model, Measure measure, bool free_pitch = false, int targets = 1);

enum class ParameterKind {
  Tilt, Shift, Pitch, Scale, ToolRotation, ToolTranslation,
  Offset,                         ///< a joint offset (level `offsets`: not part of the minimal set, §V)
  BaseRotation, BaseTranslation,  ///< the whole model moved in the measurement frame (level `offsets`)
  TargetPoint                     ///< a target's point on the tool, tool-frame x, y, z
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

/// What an error model parameterizes.
struct ErrorModelSpec {
  bool free_pitch = false;          ///< revolute joints get a pitch parameter as well
  ParameterSet set = ParameterSet::Full;
  std::vector<std::string> names;   ///< ParameterSet::Named
  /// Targets' points in the tool frame: with at least one, the tool's 6 parameters are replaced by 3 per
  /// target (`target.NAME.x`, `.y`, `.z`, tool frame); names from `target_names` ("1", "2", ... when empty).
  std::vector<Vec3> targets;
  std::vector<std::string> target_names;
};

/// One identification parameter (a column of the identification Jacobian).
struct Parameter {
  ParameterKind kind = ParameterKind::Tilt;
  int joint = -1;      ///< 0-based joint, -1 for the tool
  int component = 0;   ///< 0/1 for tilt and shift, 0..2 (x, y, z) for the tool
  std::string name;    ///< "j3.tilt1", "j3.shift2", "j3.pitch", "j3.scale", "j3.offset", "tool.rx", "tool.z",
                       ///< "base.rx", "base.z", "target.smr_a.x" (1-based joints)
  std::string unit;    ///< "rad", "length", "length/rad", "1"
};

/// The error model's local coordinates at one model (see the file comment).
class ErrorModel {
 public:
  /// @param free_pitch give revolute joints a pitch parameter as well
  explicit ErrorModel(const PoeModel& model, bool free_pitch = false);
  /// @throws std::invalid_argument for a Named set naming a parameter the model does not have (or none)
  ErrorModel(const PoeModel& model, const ErrorModelSpec& spec);

  const PoeModel& model() const { return model_; }
  bool freePitch() const { return spec_.free_pitch; }
  const ErrorModelSpec& spec() const { return spec_; }
  /// The targets' points (tool frame) at this model; empty without targets.
  const std::vector<Vec3>& targets() const { return spec_.targets; }
  const std::vector<Parameter>& parameters() const { return parameters_; }
  int size() const { return static_cast<int>(parameters_.size()); }
  /// The model moved by `delta` (one entry per parameter): `Ad(exp(eta))` per joint, pitch and scale
  /// increments, `exp(eta_T)` on the tool. Joint names, offsets and ranges are kept; with free pitch a
  /// joint's type follows its new pitch (revolute when |pitch| <= kPitchZero eps L, the pitch then 0).
  /// @throws std::invalid_argument when a scale would become <= 0 or a number non-finite
  PoeModel apply(const Eigen::Ref<const VecX>& delta) const;
  /// The targets' points moved by `delta` (tool frame).
  std::vector<Vec3> applyTargets(const Eigen::Ref<const VecX>& delta) const;
  /// The same parameters, their directions (the eta twists) kept from this model, at another model of the
  /// same robot (a calibration iterate): the coordinates of every iterate then mean the same thing.
  ErrorModel rebased(const PoeModel& model) const;
  ErrorModel rebased(const PoeModel& model, const std::vector<Vec3>& targets) const;
  /// Identification Jacobian at `q`: d(measured quantity)/d(parameters), 6 rows `[dtheta; dp]` (Pose) or
  /// 3 rows `dp` (Position; Targets: of target `target`'s point), `size()` columns; units: rad and length
  /// per parameter unit. Also returns the model's `T_base_tool(q)`.
  Pose jacobian(const Eigen::Ref<const VecX>& q, Measure measure, Eigen::Ref<MatX> rows, int target = -1) const;

 private:
  PoeModel model_;
  ErrorModelSpec spec_;
  std::vector<Parameter> all_;       // every candidate parameter, in column order of the full computation
  std::vector<int> selected_;        // indices into all_ of the parameters
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
MatX fullErrorModelJacobian(const PoeModel& model, const std::vector<VecX>& q, Measure measure, bool free_pitch,
                            const std::vector<Vec3>& targets = {});

/// The D-H parameterization of the same robot (poeToDh of the model): base `theta, d, alpha, a`, per
/// joint `theta, d, alpha, a` (+ `pitch` when helical or freed) + `scale`, tool `theta, d`; analytic
/// columns. @param names receives the column names ("base.theta", "j2.a", "tool.d", ...)
MatX dhIdentificationJacobian(const DhModel& model, const std::vector<VecX>& q, Measure measure, bool free_pitch,
                              std::vector<std::string>* names = nullptr, const std::vector<Vec3>& targets = {});

/// Rank rule for the identification Jacobians: rows made dimensionless (position rows / L), columns
/// scaled to unit norm (a zero column stays zero), then `rank = #{sigma_i > kRankFactor cols eps sigma_1}`
/// (1000 cols eps, ~8e-12 for 36 columns; the singularity analysis' factor). Measured on 4,000 analyses of
/// random robots (tests/calibration_test.cpp): exact dependencies leave at most 6.6e-13 sigma_1, genuine
/// singular values are at least 5.7e-4 sigma_1.
struct RankAnalysis {
  int rank = 0;
  int columns = 0;
  VecX singular_values;  ///< of the scaled matrix, descending
  double tolerance = 0.0;  ///< on the singular values, as above
  double condition = 0.0;  ///< sigma_1 / sigma_min over all columns; +inf when rank < columns
  /// Sun & Hollerbach's observability indices of the scaled matrix (m = columns, P poses):
  /// O1 = (prod sigma)^(1/m) / sqrt(P), O2 = sigma_min / sigma_1, O3 = sigma_min, O4 = sigma_min^2 / sigma_1,
  /// O5 = 1 / sum(1 / sigma_i); all 0 when rank < columns.
  std::array<double, 5> observability{};
  /// The undetermined directions (right null vectors in scaled coordinates, unit norm): per direction the
  /// columns whose coefficient exceeds 0.1 in magnitude, with their coefficients.
  std::vector<std::vector<std::pair<int, double>>> undetermined;
};

/// @param L the length scale dividing position rows; @param poses P (for O1)
RankAnalysis analyzeRank(const MatX& jacobian, Measure measure, double L, int poses);

/// Identifiability of a model over a set of poses (docs/calibration.md): the count, the rank of the
/// identification Jacobian (minimal parameters) and of the full error model (the "at most"), and the
/// same for the D-H parameterization.
struct Identifiability {
  Measure measure = Measure::Pose;
  bool free_pitch = false;
  ParameterCount expected;
  std::vector<Parameter> parameters;
  RankAnalysis poe;                 ///< minimal parameters (ErrorModel)
  int full_model_rank = 0, full_model_columns = 0;  ///< fullErrorModelJacobian
  std::vector<std::string> dh_parameters;
  RankAnalysis dh;                  ///< dhIdentificationJacobian of poeToDh(model)
};

/// @throws std::invalid_argument for poses of the wrong size or non-finite, and as poeToDh when the model's
/// D-H table is beyond the magnitude limits (its `dh` rank cannot be computed)
/// @param targets Measure::Targets: the targets' points (tool frame); every pose measures each
Identifiability analyzeIdentifiability(const PoeModel& model, const std::vector<VecX>& q, Measure measure,
                                       bool free_pitch = false, const std::vector<Vec3>& targets = {});

/// Residual statistics of a model against measurements: position error `|p_meas - p_model|` (length) and
/// rotation error `rotationAngle(R_model^T R_meas)` (rad; 0 for position measurements).
struct ResidualStatistics {
  int count = 0;
  double rms_position = 0.0, max_position = 0.0;
  double rms_rotation = 0.0, max_rotation = 0.0;
};

/// @param targets the targets' points (tool frame), for Measure::Targets
ResidualStatistics residualStatistics(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Vec3>& targets = {});

/// The measured point or pose a model predicts for one measurement (Targets: `T(q) point`).
Pose predictedMeasurement(const PoeModel& model, const Measurement& m, Measure measure,
                          const std::vector<Vec3>& targets = {});

/// `model` moved as a whole by `T_frame_base`: every twist `Ad(T) xi`, the tool `T T_tool`. Its forward
/// kinematics is `T_frame_base T_base_tool(q)`: the same robot seen from another frame.
PoeModel movedModel(const PoeModel& model, const Pose& T_frame_base);

/// The closed-form rigid registration (Horn; Kabsch-Umeyama without scale) of the measurement frame:
/// the pose `T_meas_base` of the model's base frame in the measurement frame that best maps the model's
/// predicted points (tool origins or targets' points; for Pose data the rotations as well, weighted by L^2)
/// onto the measured ones. Targets without a point are estimated in turn (each the mean of its measured
/// points expressed in the predicted tool frame), alternating with the registration until both settle.
struct Registration {
  Pose T_meas_base;
  std::vector<Vec3> targets;  ///< every target's point (tool frame): given or estimated
  std::vector<bool> estimated;
  int iterations = 0;
  bool determined = true;  ///< false: the predicted points are collinear (and no rotations): identity kept
};

/// @throws std::invalid_argument as calibrate for bad measurements
Registration registerMeasurementFrame(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Target>& targets = {});

/// Robust losses by iteratively reweighted least squares (docs/calibration.md "Blunders"): on a
/// measurement's normalized residual u (below), weight 1 (Squared), min(1, kHuber / u) (Huber), or
/// 1 / (1 + (u / kCauchy)^2) (Cauchy).
enum class Loss { Squared, Huber, Cauchy };
const char* lossName(Loss loss);
constexpr double kHuberThreshold = 3.0;  ///< in normalized residuals (noise units)
constexpr double kCauchyScale = 4.0;     ///< in normalized residuals

/// One measurement's fit: position (length) and rotation (rad; NaN for points) errors, and the
/// normalized residual `u = sqrt(|r|^2 / (rows / 3))` of its weighted residual r (position / sigma_position,
/// rotation / sigma_rotation; with no stated noise, over the robust scale instead): `|e| / sigma` for a
/// point, the root mean square of the two for a pose.
struct MeasurementResidual {
  double position = 0.0, rotation = 0.0, normalized = 0.0;
  double weight = 1.0;   ///< the robust loss' weight at the result (1 for Squared)
  bool outlier = false;  ///< normalized > CalibrationOptions::outlier_threshold
};

struct CalibrationOptions {
  Measure measure = Measure::Pose;
  bool free_pitch = false;
  /// Measurement noise (standard deviation per coordinate): weights the residuals (position / sigma_position,
  /// rotation / sigma_rotation). Unset: sigma_rotation = sigma_position / L when one is given; when neither
  /// is, the ratio L and an a posteriori noise level (variance factor) are used for the covariance.
  std::optional<double> sigma_position;  ///< length
  std::optional<double> sigma_rotation;  ///< rad
  int max_iterations = 100;
  /// Measure::Targets: the targets (index = Measurement::target); unknown points are estimated.
  std::vector<Target> targets;
  /// Register the measurement frame in closed form before the fit (registerMeasurementFrame).
  bool register_frame = true;
  Loss loss = Loss::Squared;
  double outlier_threshold = 5.0;  ///< normalized residual above which a measurement is flagged
  ParameterSet parameters = ParameterSet::Full;
  std::vector<std::string> parameter_names;  ///< ParameterSet::Named
};

/// The rule behind CalibrationResult::accepted (docs/calibration.md "The verdict").
constexpr double kMaxVarianceFactor = 100.0;     ///< stated noise: residuals at most 10x the noise
constexpr double kMaxRelativeRmsPosition = 0.01;  ///< no stated noise: RMS position at most 1 % of L
constexpr double kMaxRmsRotation = 0.01;          ///< no stated noise: RMS rotation at most 0.01 rad
constexpr double kMaxOutlierFraction = 0.25;      ///< robust losses: at most a quarter flagged

struct CalibrationResult {
  PoeModel model;                    ///< calibrated
  ErrorModel error_model;            ///< the local coordinates at the calibrated model
  ParameterCount expected;
  RankAnalysis rank;                 ///< of the weighted identification Jacobian at the nominal (fixes the subspace)
  ResidualStatistics before, after;  ///< on the measurements
  int iterations = 0;
  bool converged = false;
  double sigma_position = 0.0, sigma_rotation = 0.0;  ///< the weights used
  bool noise_stated = false;  ///< false: covariance scaled by the a posteriori variance factor
  double variance_factor = 1.0;  ///< `cost / (rows - rank)` (1 expected when the stated noise is right)
  /// Covariance of the parameters (local coordinates at `model`), pseudo-inverse on the determined
  /// subspace; an undetermined parameter has standard deviation +inf.
  MatX covariance;
  VecX standard_deviation;
  /// The covariance's principal axes as one-standard-deviation perturbations (columns, parameter units):
  /// `covariance = principal_axes * principal_axes^T`.
  MatX principal_axes;
  /// Parameter directions the measurements do not determine (columns, parameter units; empty at full rank).
  MatX undetermined_directions;
  /// Which weight was stated; the other of a stated pair is derived (sigma_rotation = sigma_position / L or
  /// sigma_position = sigma_rotation L).
  bool sigma_position_stated = false, sigma_rotation_stated = false;

  Measure measure = Measure::Pose;
  ParameterSet parameter_set = ParameterSet::Full;
  /// The registration: the pose of the nominal's base frame in the measurement frame (identity when not
  /// registered). `before` is the nominal placed there (with its targets as registered/estimated).
  Registration registration;
  std::vector<Vec3> targets;  ///< calibrated targets' points (tool frame of `model`)
  Loss loss = Loss::Squared;
  /// Robust losses: the noise unit of the normalized residuals: 1 (stated noise) or the a posteriori scale
  /// from the median residual (`median u / median of chi with rows dof`), in weighted-residual units.
  double robust_scale = 1.0;
  bool robust_scale_from_median = false;
  int reweightings = 0;  ///< IRLS passes
  std::vector<MeasurementResidual> residuals;  ///< one per measurement, in order
  int outliers = 0;
  /// The verdict: converged, and the residuals consistent with the stated noise (variance factor, over
  /// the measurements not flagged for robust losses, at most kMaxVarianceFactor; at most a quarter flagged),
  /// or without stated noise the RMS below 1 % of L and 0.01 rad. `reason` says why not (empty if accepted).
  bool accepted = false;
  std::string reason;
  double outlier_threshold = 5.0;  ///< CalibrationOptions::outlier_threshold
  /// The estimate of every parameter (`error_model.parameters()` order and units): the sum of the accepted
  /// steps from the registered nominal (`before`): exact for offsets, scales, pitches and targets' points;
  /// to first order for the twists and the tool (the model moves by one `exp` per step, and composed
  /// exponentials add only to first order). With `standard_deviation` it is the parameter table of a fit.
  VecX estimate;
};

/// Levenberg–Marquardt in the error model's coordinates (directions fixed at the nominal, re-centred at
/// every iterate) on the determined subspace of the nominal: the weighted, column-scaled Jacobian at the
/// nominal and the rank rule of analyzeRank fix the subspace once; every step lies in it, so undetermined
/// directions are left at the nominal (a direction undetermined at the nominal can look determined a hair
/// away from it, and fitting noise along it would be fitting nothing). @throws std::invalid_argument for measurements whose
/// joint count differs from the model's or with non-finite numbers, or for no measurement.
CalibrationResult calibrate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                            const CalibrationOptions& options = {});

/// Repeated k-fold cross-validation of the parameter levels (Full, Lines, Offsets), folds over poses (a
/// pose's targets stay together): repeat 0 deals pose i to fold i % k, each later repeat deals a fixed
/// shuffle of the poses (seeded by the repeat's number: the same data give the same choice); a partition
/// into the same sets as an earlier one is skipped (as many poses as folds allow one). Each level is fitted
/// on k - 1 folds and predicts the held-out one, every pose once per partition; a level whose fit throws or
/// does not converge on any fold is `failed`, not a candidate. `chosen` is the level with the least score
/// (ties: fewer parameters). Repeating the partition takes out the luck of one partition: on 390 random
/// 6-joint arms with 15 noisy poses whose errors favour each level in turn, one 5-fold partition chose
/// within 10 % of the best level in hindsight on 380, ten on 387 (docs/calibration.md "Which parameters").
/// Cost: (distinct partitions) x k fits per level.
constexpr int kCrossValidationRepeats = 10;
constexpr int kMaxCrossValidationRepeats = 100;
constexpr int kMaxCrossValidationFolds = 20;

struct CrossValidation {
  struct Candidate {
    ParameterSet set = ParameterSet::Full;
    int parameters = 0;
    /// the RMS of the held-out position errors (length) and rotation errors (rad) over every partition
    double rms_position = 0.0, rms_rotation = 0.0;
    /// What is compared: per held-out measurement its normalized residual u (position over sigma_position,
    /// rotation over sigma_rotation: the fit's weights, so noise units when the noise is stated, else
    /// 1/L and 1/rad; without stated noise a robust loss divides by the robust scale of the full level
    /// fitted to every measurement, one unit for all levels), scored by the fit's loss (u^2 for least
    /// squares, Huber's or Cauchy's rho: a held-out blunder counts as the fit counts it), and the root of
    /// the mean (for least squares the RMS weighted residual).
    double score = 0.0;
    bool failed = false;  ///< a fold's fit threw or did not converge: not a candidate
  };
  std::vector<Candidate> candidates;
  ParameterSet chosen = ParameterSet::Full;
  int folds = 0;
  int repeats = 0;  ///< the distinct partitions used (at most the number asked)
};

/// @throws std::invalid_argument for fewer poses than folds, folds outside [2, kMaxCrossValidationFolds],
/// repeats outside [1, kMaxCrossValidationRepeats], or as calibrate
CrossValidation crossValidate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                              const CalibrationOptions& options, int folds = 5,
                              int repeats = kCrossValidationRepeats);

/// Standard deviations of the calibrated D-H table: the parameter covariance propagated through poeToDh by
/// central differences of one standard deviation along the covariance's principal axes (angle differences
/// wrapped; a row whose `a` changes sign is compared on the central table's branch, `(theta - pi, d, -alpha,
/// -a)` with pi moved to the next theta). A D-H number that moves along an undetermined direction is +inf.
/// No standard deviation is below the number's rounding, `eps max(|value|, unit)` (unit: L for lengths and
/// pitches, 1 for angles and scales): a noise-free fit gives that floor, never an exact 0. An entry the
/// conversion fixes by convention has standard deviation 0 and its flag set: a row placed by a prismatic
/// joint's axis has `a = 0` and `d = 0` (docs/conversion.md; `d` only while no offset of the joint before
/// it moves it: one that slides, prismatic, helical or revolute with a fitted pitch, with a nonzero or fitted
/// offset).
struct DhUncertainty {
  DhConversion conversion;              ///< of the calibrated model
  DhParams base;                        ///< standard deviations
  std::vector<DhParams> links;          ///< per joint
  std::vector<double> pitch, scale;     ///< per joint (pitch 0 for non-helical)
  double tool_theta = 0.0, tool_d = 0.0;
  struct Fixed {
    bool d = false, a = false;
  };
  Fixed base_fixed;                 ///< set by the D-H convention, not measured (standard deviation 0)
  std::vector<Fixed> links_fixed;   ///< per joint's row
};

DhUncertainty dhUncertainty(const CalibrationResult& result);

}  // namespace lowpair
