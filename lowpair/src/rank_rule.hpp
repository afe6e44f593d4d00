#pragma once
/// @file rank_rule.hpp (internal, not installed)
/// The rank rule of the identification Jacobians (identifiability.hpp, RankAnalysis), one definition for
/// the identifiability analysis, the calibration and the pose planning.

#include <utility>
#include <vector>

#include "lowpair/types.hpp"

namespace lowpair::detail {

/// The rank of a matrix whose rows are dimensionless and whose columns are scaled:
/// `rank = #{sigma_i > kRankFactor cols eps sigma_1}` (numericalRankTolerance, numericalRank).
struct ScaledRank {
  VecX singular_values;  ///< cols of them, descending (zero-padded when rows < cols)
  double tolerance = 0.0;
  int rank = 0;
  MatX V;  ///< the full right singular vectors
  /// per undetermined direction (columns rank..cols-1 of V), the columns whose coefficient exceeds
  /// kNamedCoefficient in magnitude, with their coefficients
  std::vector<std::vector<std::pair<int, double>>> undetermined;
};

/// A null-vector coefficient above this names its parameter in an undetermined direction.
constexpr double kNamedCoefficient = 0.1;

/// (JacobiSVD with full V: see identifiability.cpp.)
ScaledRank scaledRank(const MatX& scaled);

}  // namespace lowpair::detail
