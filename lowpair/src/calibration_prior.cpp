// The prior on the nominal (calibrate.hpp ParameterPrior; docs/calibration.md "A prior on the nominal"): its
// widths per parameter, its rows appended to the weighted least squares, and the effective number of parameters.
#include "calibration_prior.hpp"

#include <cmath>

namespace lowpair {

double ParameterPrior::width(ParameterKind kind, const std::string& unit) const {
  switch (kind) {
    case ParameterKind::Tilt:
    case ParameterKind::ToolRotation:
      return tilt;
    case ParameterKind::Shift:
    case ParameterKind::ToolTranslation:
    case ParameterKind::Pitch:
      return shift;
    case ParameterKind::Scale:
      return scale;
    case ParameterKind::Offset:
      return unit == "length" ? shift : offset;
    default:  // the measurement frame, the targets' points, the joint deflections
      return kNone;
  }
}

namespace detail {

VecX priorWeights(const ErrorModel& em, const ParameterPrior& prior) {
  if (prior.none()) return {};
  const std::vector<Parameter>& parameters = em.parameters();
  VecX w(static_cast<Eigen::Index>(parameters.size()));
  for (size_t j = 0; j < parameters.size(); ++j) {
    w[static_cast<Eigen::Index>(j)] = 1.0 / prior.width(parameters[j].kind, parameters[j].unit);  // 1/inf = 0
  }
  return w;
}

MatX withPriorRows(const MatX& J, const VecX& weights) {
  MatX A(J.rows() + J.cols(), J.cols());
  A.topRows(J.rows()) = J;
  A.bottomRows(J.cols()) = weights.asDiagonal();
  return A;
}

VecX withPriorResidual(const VecX& r, const VecX& weights, const VecX& estimate) {
  VecX out(r.size() + weights.size());
  out.head(r.size()) = r;
  out.tail(weights.size()) = -weights.cwiseProduct(estimate);
  return out;
}

double effectiveParameters(const MatX& U, const std::vector<bool>& usable, Eigen::Index data_rows) {
  double trace = 0.0;
  for (Eigen::Index i = 0; i < U.cols(); ++i) {
    if (usable[static_cast<size_t>(i)]) trace += U.col(i).head(data_rows).squaredNorm();
  }
  return trace;
}

std::vector<int> heldByPrior(const MatX& V0, int data_rank, const VecX& sd) {
  std::vector<int> held;
  const Eigen::Index n = V0.rows();
  for (Eigen::Index k = 0; k < n; ++k) {
    bool undetermined = false;  // calibrate's rule for an infinite standard deviation without a prior
    for (Eigen::Index c = data_rank; c < n; ++c) undetermined = undetermined || std::abs(V0(k, c)) > 1e-8;
    if (undetermined && std::isfinite(sd[k])) held.push_back(static_cast<int>(k));
  }
  return held;
}

}  // namespace detail
}  // namespace lowpair
