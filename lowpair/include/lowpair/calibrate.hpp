#pragma once
/// @file calibrate.hpp
/// The fit: Levenberg-Marquardt in the error model's coordinates, robust reweighting, covariance and the
/// verdict (Wu, Crawford, Roberts §VI; docs/calibration.md).

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/error_model.hpp"
#include "lowpair/identifiability.hpp"
#include "lowpair/registration.hpp"
#include "lowpair/robust_loss.hpp"

namespace lowpair {

/// One measurement's fit: position (length) and rotation (rad; NaN for points) errors, and the
/// normalized residual `u = sqrt(|r|^2 / (rows / 3))` of its weighted residual r (position / sigma_position,
/// rotation / sigma_rotation; with no stated noise, over the robust scale instead): `|e| / sigma` for a
/// point, the root mean square of the two for a pose.
struct MeasurementResidual {
  double position = 0.0, rotation = 0.0, normalized = 0.0;
  double weight = 1.0;   ///< the robust loss' weight at the result (1 for Squared)
  int rows = 3;          ///< its residual rows: 6 for a pose, 3 for a point (rowsOf)
  bool outlier = false;  ///< normalized > CalibrationOptions::outlier_threshold
};

/// Zero-mean Gaussian priors on the deviations from the nominal (docs/calibration.md "A prior on the nominal"):
/// the standard deviation (width) of each kind of parameter, +inf for none. A parameter with a finite width adds
/// the residual `delta_j / width_j` to the weighted least squares, delta_j its estimate (the sum of the accepted
/// steps from the registered nominal, CalibrationResult::estimate), so the normal equations gain `diag(1/width^2)`
/// (MAP estimation). Which kinds bear one: tilts and the tool's rotations (`tilt`, rad); shifts, the tool's
/// translations and pitches (`shift`, length, length/rad for a pitch); scales (`scale`, dimensionless); joint
/// offsets (`offset`, rad; a prismatic joint's offset takes `shift`). The measurement frame (base.*), the
/// targets' points and the joint deflections stay free. Every width +inf (the default): no prior, the fit of
/// before bit for bit.
struct ParameterPrior {
  static constexpr double kNone = std::numeric_limits<double>::infinity();
  double tilt = kNone, shift = kNone, scale = kNone, offset = kNone;
  bool none() const { return tilt == kNone && shift == kNone && scale == kNone && offset == kNone; }
  /// The width of parameter kind `kind` in unit `unit` (Parameter::unit): +inf where no prior applies.
  double width(ParameterKind kind, const std::string& unit) const;
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
  /// Joint deflections (deflection.hpp; docs/calibration.md "Beyond geometry"): the 0-based joints whose
  /// compliance and backlash are fitted (with any parameter set), the masses their gravity loads come from
  /// (gravityTorques at each measurement's commanded q, with the nominal's geometry in its own base frame), each
  /// measurement's move signs (empty: moveSigns of the measurements' joint vectors in their order), and the
  /// deflections the nominal already has (applied; fitted from there where named). A fitted joint whose load (or
  /// sign) does not vary over the measurements is refused (checkDeflections).
  std::vector<int> compliance_joints{}, backlash_joints{};
  MassModel masses{};
  std::vector<VecX> move_signs{};
  JointDeflection deflection{};
  bool deflects() const { return !compliance_joints.empty() || !backlash_joints.empty() || !deflection.empty(); }
  ParameterPrior prior{};  ///< none by default (every width +inf)

  /// The rules calibrate() applies to its options (the CLI and the Python module call it too).
  /// @throws std::invalid_argument for a noise level not positive and finite, max_iterations < 0, or an
  /// outlier threshold not positive and finite, or a prior width not positive (NaN, 0 or negative)
  void validate() const;
};

/// The rule behind CalibrationResult::accepted (docs/calibration.md "The verdict").
constexpr double kMaxVarianceFactor = 100.0;     ///< stated noise: residuals at most 10x the noise
/// Stated noise: residuals at least a tenth of the noise. Below, the stated noise is not the data's (typically a
/// noise in mm for a robot in m: a variance factor of 1e-6), and the standard deviations, the outlier threshold
/// and every blunder test built on it are off by as much (4 of 4 blunders went unflagged at 2.4e-4).
constexpr double kMinVarianceFactor = 0.01;
constexpr double kMaxRelativeRmsPosition = 0.01;  ///< no stated noise: RMS position at most 1 % of L
constexpr double kMaxRmsRotation = 0.01;          ///< no stated noise: RMS rotation at most 0.01 rad
constexpr double kMaxOutlierFraction = 0.25;      ///< robust losses: at most a quarter flagged

/// Every field but the first two (no default: the calibrated model and its error model) has a default, so
/// that a result is built as `CalibrationResult r{model, error_model}` and filled by field name.
struct CalibrationResult {
  PoeModel model;                    ///< calibrated
  ErrorModel error_model;            ///< the local coordinates at the calibrated model
  ParameterCount expected{};
  RankAnalysis rank{};  ///< of the weighted identification Jacobian at the nominal (fixes the subspace)
  ResidualStatistics before{}, after{};  ///< on the measurements
  int iterations = 0;
  bool converged = false;
  double sigma_position = 0.0, sigma_rotation = 0.0;  ///< the weights used
  bool noise_stated = false;  ///< false: covariance scaled by the a posteriori variance factor
  double variance_factor = 1.0;  ///< `cost / (rows - rank)` (1 expected when the stated noise is right)
  /// Covariance of the parameters (local coordinates at `model`), pseudo-inverse on the determined
  /// subspace; an undetermined parameter has standard deviation +inf.
  MatX covariance{};
  VecX standard_deviation{};
  /// The covariance's principal axes as one-standard-deviation perturbations (columns, parameter units):
  /// `covariance = principal_axes * principal_axes^T`.
  MatX principal_axes{};
  /// Parameter directions the measurements do not determine (columns, parameter units; empty at full rank).
  MatX undetermined_directions{};
  /// Which weight was stated; the other of a stated pair is derived (sigma_rotation = sigma_position / L or
  /// sigma_position = sigma_rotation L).
  bool sigma_position_stated = false, sigma_rotation_stated = false;

  Measure measure = Measure::Pose;
  ParameterSet parameter_set = ParameterSet::Full;
  /// The registration: the pose of the nominal's base frame in the measurement frame (identity when not
  /// registered). `before` is the nominal placed there (with its targets as registered/estimated).
  Registration registration{};
  /// The calibrated targets' points (tool frame of `model`; index = Measurement::target; names and known flags:
  /// `error_model.spec().targets`, which hold the same points).
  std::vector<Vec3> target_points{};
  /// The tool frame's directions the measurements can determine: 6 (pose measurements; targets with three
  /// non-collinear known points), 3 (position measurements: the tool origin), or with targets
  /// knownPointsToolRank of the known ones (0 with unknown points only: they carry the tool frame, which
  /// stays the nominal's). Below 6, a compensated tool pose is the flange's with the nominal's tool.
  int tool_rank = 6;
  Loss loss = Loss::Squared;
  /// Robust losses: the noise unit of the normalized residuals: 1 (stated noise) or the a posteriori scale
  /// from the median residual (`median u / median of chi with rows dof`), in weighted-residual units.
  double robust_scale = 1.0;
  bool robust_scale_from_median = false;
  int reweightings = 0;  ///< IRLS passes
  std::vector<MeasurementResidual> residuals{};  ///< one per measurement, in order
  int outliers = 0;
  /// The verdict: converged, and the residuals consistent with the stated noise (variance factor, over
  /// the measurements not flagged for robust losses, in [kMinVarianceFactor, kMaxVarianceFactor]; at most a quarter
  /// flagged),
  /// or without stated noise the RMS below 1 % of L and 0.01 rad. `reason` says why not (empty if accepted).
  bool accepted = false;
  std::string reason{};
  double outlier_threshold = 5.0;  ///< CalibrationOptions::outlier_threshold
  /// The estimate of every parameter (`error_model.parameters()` order and units): the sum of the accepted
  /// steps from the registered nominal (`before`): exact for offsets, scales, pitches and targets' points;
  /// to first order for the twists and the tool (the model moves by one `exp` per step, and composed
  /// exponentials add only to first order). With `standard_deviation` it is the parameter table of a fit.
  VecX estimate{};
  /// The calibrated joint deflections (CalibrationOptions::deflection moved by the fitted compliance and backlash
  /// parameters), and per measurement the inputs they were fitted with (empty without deflections).
  JointDeflection deflection{};
  std::vector<PoseLoad> loads{};
  /// The prior (CalibrationOptions::prior), and the effective number of parameters: the trace of the hat matrix
  /// `J (J^T W J + P)^-1 J^T W` on the fit's determined subspace (P = diag(1/width^2), 0 for free parameters), between
  /// the free parameters' count and the determined count; exactly `rank.rank` without a prior. The variance factor's
  /// redundancy is `rows - effective_parameters`. With a prior, `rank` stays the data's (the measurements alone), the
  /// covariance is `(J^T W J + P)^-1` (scaled as without), and `undetermined_directions` are those neither the data nor
  /// the prior determine.
  ParameterPrior prior{};
  double effective_parameters = 0.0;
  /// The parameters (indices into `error_model.parameters()`) that move along a direction the data leave undetermined
  /// and that the prior determines (finite standard deviation from the prior alone); empty without a prior.
  std::vector<int> held_by_prior{};
};

/// The deflection inputs of `measurements` for `options` (calibrate's): empty when options.deflects() is false;
/// else per measurement its gravity load (when a compliance is fitted or given) at the nominal and its move signs
/// (options.move_signs, else moveSigns of the joint vectors in order, when a backlash is fitted or given).
/// @throws std::invalid_argument as poseLoads
std::vector<PoseLoad> measurementLoads(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                                       const CalibrationOptions& options);

/// `measurements` with each joint vector deflected: `deflectedJoints(deflection, q, loads[k])` (loads empty: a copy).
std::vector<Measurement> deflectedMeasurements(const std::vector<Measurement>& measurements,
                                               const JointDeflection& deflection, const std::vector<PoseLoad>& loads);

/// Levenberg–Marquardt in the error model's coordinates (directions fixed at the nominal, re-centred at
/// every iterate) on the determined subspace of the nominal: the weighted, column-scaled Jacobian at the
/// nominal and the rank rule of analyzeRank fix the subspace once; every step lies in it, so undetermined
/// directions are left at the nominal (a direction undetermined at the nominal can look determined a hair
/// away from it, and fitting noise along it would be fitting nothing). @throws std::invalid_argument for measurements whose
/// joint count differs from the model's or with non-finite numbers, or for no measurement.
CalibrationResult calibrate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                            const CalibrationOptions& options = {});

}  // namespace lowpair
