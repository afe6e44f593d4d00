#pragma once
/// @file robust_loss.hpp
/// Robust losses of a calibration (docs/calibration.md "Blunders"), after Ceres's LossFunction and GTSAM's
/// noiseModel::mEstimator: one type carries the loss' kind and scale, its rho and its weight.

#include <cmath>

#include "lowpair/measure.hpp"

namespace lowpair {

/// Robust losses by iteratively reweighted least squares (docs/calibration.md "Blunders"): on a
/// measurement's normalized residual u (below), weight 1 (Squared), min(1, kHuber / u) (Huber), or
/// 1 / (1 + (u / kCauchy)^2) (Cauchy).
enum class Loss { Squared, Huber, Cauchy };
const char* lossName(Loss loss);
constexpr double kHuberThreshold = 3.0;  ///< in normalized residuals (noise units)
constexpr double kCauchyScale = 4.0;     ///< in normalized residuals

/// The normalized residual of one measurement: `u = sqrt(|r|^2 / (rows / 3))` of its weighted residual r
/// (`squared_norm` = |r|^2, `rows` = rowsPerMeasurement): `|e| / sigma` for a point, the root mean square of
/// the position and rotation parts for a pose.
inline double normalizedResidual(double squared_norm, int rows) { return std::sqrt(squared_norm / (rows / 3.0)); }

/// A robust loss on normalized residuals u >= 0 (`scale` in noise units: Huber's threshold, Cauchy's scale;
/// unused by Squared). `rho(u)` is what a fit minimizes (u^2 for least squares) and `weight(u)` the IRLS
/// weight `rho'(u) / (2u)` (1 for least squares), so that a weighted least-squares step with it is a step of
/// the robust problem:
/// - Squared: rho = u^2, weight 1;
/// - Huber:   rho = u^2 for u <= s, 2 s u - s^2 beyond; weight 1, s / u beyond;
/// - Cauchy:  rho = s^2 log(1 + (u / s)^2); weight 1 / (1 + (u / s)^2).
struct RobustLoss {
  Loss kind = Loss::Squared;
  double scale = 1.0;

  /// The library's loss of that kind: Huber at kHuberThreshold, Cauchy at kCauchyScale.
  static constexpr RobustLoss of(Loss kind) {
    return RobustLoss{kind, kind == Loss::Huber ? kHuberThreshold : kind == Loss::Cauchy ? kCauchyScale : 1.0};
  }
  double rho(double u) const;
  double weight(double u) const;
};

}  // namespace lowpair
