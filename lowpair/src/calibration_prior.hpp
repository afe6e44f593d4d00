#pragma once
/// @file calibration_prior.hpp (internal, not installed)
/// The prior on the nominal as rows of the weighted least squares (calibrate.hpp ParameterPrior).

#include <vector>

#include "lowpair/calibrate.hpp"

namespace lowpair::detail {

/// Per parameter of `em` the prior's weight 1/width (0 for a free parameter); empty when `prior.none()`.
VecX priorWeights(const ErrorModel& em, const ParameterPrior& prior);

/// The Jacobian with the prior's rows below: `[J; diag(weights)]` (the prior residual's derivative).
MatX withPriorRows(const MatX& J, const VecX& weights);

/// The residual with the prior's rows below: `[r; -weights .* estimate]`, in the sign of r (measured - predicted:
/// a step dx changes it by `-[J; diag(weights)] dx`).
VecX withPriorResidual(const VecX& r, const VecX& weights, const VecX& estimate);

/// The trace of the hat matrix of the data rows: with `[J; P^(1/2)] = U S V^T` (thin, the usable singular values
/// marked), `J (J^T J + P)^-1 J^T = U_d U_d^T` on them, U_d the first `data_rows` rows of U: the trace is |U_d|_F^2.
double effectiveParameters(const MatX& U, const std::vector<bool>& usable, Eigen::Index data_rows);

/// The parameters that move along a direction the data leave undetermined (the right singular vectors `V0` of the
/// data's scaled Jacobian beyond `data_rank`) and whose standard deviation `sd` (with the prior) is finite.
std::vector<int> heldByPrior(const MatX& V0, int data_rank, const VecX& sd);

}  // namespace lowpair::detail
