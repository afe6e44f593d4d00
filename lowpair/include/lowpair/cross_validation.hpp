#pragma once
/// @file cross_validation.hpp
/// Choosing the model by repeated k-fold cross-validation: the parameter level, the prior's width and the joint
/// deflections (docs/calibration.md "Which parameters" and "Selection").

#include <cmath>
#include <limits>
#include <vector>

#include "lowpair/calibrate.hpp"

namespace lowpair {

/// Repeated k-fold cross-validation of candidate fits, folds over poses (a pose's targets stay together): repeat
/// 0 deals pose i to fold i % k, each later repeat deals a fixed shuffle of the poses (seeded by the repeat's
/// number: the same data give the same choice); a partition into the same sets as an earlier one is skipped (as
/// many poses as folds allow one). Every candidate is fitted on k - 1 folds and predicts the held-out one, every
/// pose once per partition, on the same partitions; a candidate whose fit throws or does not converge on any fold
/// is `failed`, not a candidate. `chosen` is the candidate with the least score (ties: fewer parameters, then the
/// earlier in the grid's order). Repeating the partition takes out the luck of one partition: on 390 random
/// 6-joint arms with 15 noisy poses whose errors favour each level in turn, one 5-fold partition chose within
/// 10 % of the best level in hindsight on 380, ten on 387 (docs/calibration.md "Which parameters").
/// Cost: (distinct partitions) x k fits per candidate.
constexpr int kCrossValidationRepeats = 10;
constexpr int kMaxCrossValidationRepeats = 100;
constexpr int kMaxCrossValidationFolds = 20;

/// How the held-out normalized residuals are scored (docs/calibration.md "Selection"). Each held-out measurement
/// k has its weighted residual r_k (position / sigma_position, rotation / sigma_rotation: the fit's weights), of
/// `rows_k` rows (6 for a pose, 3 for a point), and u_k = |r_k| / sqrt(rows_k / 3) (MeasurementResidual::normalized).
/// - Rms: the root of the mean of (rows_k / 3) rho(u_k) under the fit's loss (|r_k|^2 for least squares: the RMS
///   of |r_k|; Huber's or Cauchy's rho with a robust loss), least squares' score: a held-out blunder weighs its
///   square;
/// - Trimmed: the RMS of |r_k| after dropping the kTrimmedFraction of the held-out measurements with the largest
///   u_k (rounded down: fewer than 10 measurements drop none);
/// - Median: the median of |r_k| sqrt(rows_k / median of chi^2 with rows_k dof), which for Gaussian noise is the
///   RMS of |r_k| (sqrt(rows)); half the held-out measurements may be blunders before it moves.
enum class CrossValidationScore { Rms, Trimmed, Median };
/// The fraction of the largest held-out residuals the trimmed score drops: a tenth, room for a blunder among the
/// ten or more measurements a fold of few poses holds out per partition, while Gaussian noise loses only its tail
/// (the trimmed RMS of |r| is then 0.93 of the RMS for 6 rows, 0.89 for 3, measured on 2e6 draws: the same factor for
/// every candidate).
constexpr double kTrimmedFraction = 0.1;
/// The medians of chi^2 with 3 and 6 degrees of freedom (a point's and a pose's |r|^2 under Gaussian noise), to
/// seven digits (chi2.ppf(0.5, k)): the median score's factors sqrt(3 / 2.365974) and sqrt(6 / 5.348121).
constexpr double kChiSquareMedian3 = 2.365974;
constexpr double kChiSquareMedian6 = 5.348121;

/// The candidates crossValidate compares: every level x prior x compliance on/off x backlash on/off, in that
/// order (the level outermost; "off" before "on").
struct CrossValidationGrid {
  std::vector<ParameterSet> levels{ParameterSet::Full, ParameterSet::Lines, ParameterSet::Offsets};
  /// The priors compared (ParameterPrior{}: none); empty: the options' prior alone.
  std::vector<ParameterPrior> priors{};
  /// Also a candidate without the options' compliance_joints (backlash_joints): fitted rigid there (the nominal's
  /// own deflections, CalibrationOptions::deflection, stay applied in every candidate).
  bool compliance_off = false, backlash_off = false;
  CrossValidationScore score = CrossValidationScore::Rms;
};

struct CrossValidation {
  struct Candidate {
    ParameterSet set = ParameterSet::Full;
    int prior = -1;  ///< index into CrossValidationGrid::priors; -1: the options' prior
    bool compliance = false, backlash = false;  ///< the options' compliance (backlash) joints fitted
    int parameters = 0;
    /// the RMS of the held-out position errors (length) and rotation errors (rad) over every partition
    double rms_position = 0.0, rms_rotation = 0.0;
    /// The score (CrossValidationScore) of every held-out measurement of every partition, in the unit of the
    /// weighted residuals (noise units when the noise is stated, else 1/L and 1/rad; without stated noise a robust
    /// loss' rho takes u over the robust scale of the full level fitted to every measurement, one unit for all
    /// candidates).
    double score = 0.0;
    /// The sample standard deviation of the score of each partition alone (how much the score depends on the
    /// partition); NaN with one partition.
    double score_sd = std::numeric_limits<double>::quiet_NaN();
    bool failed = false;  ///< a fold's fit threw or did not converge: not a candidate
  };
  std::vector<Candidate> candidates;
  ParameterSet chosen = ParameterSet::Full;  ///< the chosen candidate's level
  int chosen_index = 0;                      ///< into candidates
  int folds = 0;
  int repeats = 0;  ///< the distinct partitions used (at most the number asked)
  CrossValidationScore score = CrossValidationScore::Rms;
};

/// The poses crossValidate deals to folds: runs of consecutive measurements at the same joint vector (a
/// pose's targets) count once.
int crossValidationPoses(const std::vector<Measurement>& measurements);

/// The options a candidate is fitted with: `options` with the candidate's level, prior (grid.priors[c.prior], or
/// the options' own) and, where it is off, no compliance_joints (backlash_joints).
CalibrationOptions candidateOptions(const CalibrationOptions& options, const CrossValidationGrid& grid,
                                    const CrossValidation::Candidate& c);

/// With joint deflections, each fold's deflection parameters are fitted on its training poses; every measurement
/// keeps the load and the move signs of the whole set (options.move_signs, else moveSigns of all the measurements
/// in order: a held-out pose's sign is the sign of the move that reached it in the file, not re-derived per fold).
/// @throws std::invalid_argument for fewer poses than folds (crossValidationPoses), folds outside [2,
/// kMaxCrossValidationFolds], repeats outside [1, kMaxCrossValidationRepeats], an empty grid, no candidate fitted
/// on every fold, or as calibrate
CrossValidation crossValidate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                              const CalibrationOptions& options, int folds = 5,
                              int repeats = kCrossValidationRepeats, const CrossValidationGrid& grid = {});

}  // namespace lowpair
