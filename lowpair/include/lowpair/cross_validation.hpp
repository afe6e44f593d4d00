#pragma once
/// @file cross_validation.hpp
/// Choosing the parameter level by repeated k-fold cross-validation (docs/calibration.md "Which parameters").

#include <vector>

#include "lowpair/calibrate.hpp"

namespace lowpair {

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

/// The poses crossValidate deals to folds: runs of consecutive measurements at the same joint vector (a
/// pose's targets) count once.
int crossValidationPoses(const std::vector<Measurement>& measurements);

/// @throws std::invalid_argument for fewer poses than folds (crossValidationPoses), folds outside [2, kMaxCrossValidationFolds],
/// repeats outside [1, kMaxCrossValidationRepeats], options with joint deflections (CalibrationOptions::deflects), or as
/// calibrate
CrossValidation crossValidate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                              const CalibrationOptions& options, int folds = 5,
                              int repeats = kCrossValidationRepeats);

}  // namespace lowpair
