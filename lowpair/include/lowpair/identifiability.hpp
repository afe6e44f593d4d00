#pragma once
/// @file identifiability.hpp
/// Which parameters of the error model (error_model.hpp) a set of poses determines: the rank rule of the
/// identification Jacobians and the identifiability analysis (Wu, Crawford, Roberts §V; docs/calibration.md).

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "lowpair/error_model.hpp"

namespace lowpair {

/// Rank rule for the identification Jacobians: rows made dimensionless (position rows / L), columns
/// scaled to unit norm (a zero column stays zero), then `rank = #{sigma_i > kRankFactor cols eps sigma_1}`
/// (1000 cols eps, ~8e-12 for 36 columns; the singularity analysis' factor). Measured on 4,000 analyses of
/// random robots (tests/lib/identifiability_test.cpp): exact dependencies leave at most 6.6e-13 sigma_1, genuine
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
/// @param spec `free_pitch`, and for Measure::Targets the targets' points (tool frame; every pose measures
/// each) and their names, the deflections (compliance and backlash joints, values); the parameter set is always
/// the full one
/// @param loads per pose the deflection inputs (deflection.hpp; empty without deflections)
Identifiability analyzeIdentifiability(const PoeModel& model, const std::vector<VecX>& q, Measure measure,
                                       const ErrorModelSpec& spec = {}, const std::vector<PoseLoad>& loads = {});

}  // namespace lowpair
