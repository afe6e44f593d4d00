#include "lowpair/identifiability.hpp"
#include "calibration_internal.hpp"
#include "linalg.hpp"
#include "rank_rule.hpp"

#include <algorithm>
#include <cmath>

#include "check.hpp"
#include "lowpair/singularity.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

using namespace detail;

namespace detail {

// (JacobiSVD, not BDCSVD: Eigen 3.4.0's BDCSVD reads out of bounds in perturbCol0 on some of these
// matrices, AddressSanitizer on the random-robot rank test; Jacobi with QR preconditioning is exact enough
// and fast for <= 60,000 x ~60.)
ScaledRank scaledRank(const MatX& scaled) {
  const Eigen::Index cols = scaled.cols();
  Eigen::JacobiSVD<MatX> svd(scaled, Eigen::ComputeFullV);
  ScaledRank out;
  out.singular_values = VecX::Zero(cols);
  out.singular_values.head(svd.singularValues().size()) = svd.singularValues();
  out.tolerance = numericalRankTolerance(cols > 0 ? out.singular_values[0] : 0.0, static_cast<double>(cols));
  out.rank = numericalRank(out.singular_values, out.tolerance);
  out.V = svd.matrixV();
  for (Eigen::Index k = out.rank; k < cols; ++k) {
    std::vector<std::pair<int, double>> named;
    for (Eigen::Index c = 0; c < cols; ++c) {
      if (std::abs(out.V(c, k)) > kNamedCoefficient) named.emplace_back(static_cast<int>(c), out.V(c, k));
    }
    out.undetermined.push_back(std::move(named));
  }
  return out;
}

// The SVD-based analysis of a matrix whose rows are already dimensionless: columns scaled to unit norm,
// the rank rule (scaledRank), conditioning and observability.
RankAnalysis analyzeDimensionless(const MatX& A, int poses, VecX* column_scale, MatX* V) {
  const Eigen::Index cols = A.cols();
  VecX scale = VecX::Ones(cols);
  for (Eigen::Index c = 0; c < cols; ++c) {
    const double norm = A.col(c).norm();
    if (norm > 0.0 && std::isfinite(norm)) scale[c] = 1.0 / norm;
  }
  ScaledRank rule = scaledRank(A * scale.asDiagonal());
  RankAnalysis out;
  out.columns = static_cast<int>(cols);
  out.singular_values = std::move(rule.singular_values);
  const double s1 = cols > 0 ? out.singular_values[0] : 0.0;
  out.tolerance = rule.tolerance;
  out.rank = rule.rank;
  if (out.rank == cols && cols > 0) {
    const VecX& s = out.singular_values;
    const double s_min = s[cols - 1];
    out.condition = s1 / s_min;
    out.observability[0] = std::exp(s.array().log().mean()) / std::sqrt(static_cast<double>(std::max(poses, 1)));
    out.observability[1] = s_min / s1;
    out.observability[2] = s_min;
    out.observability[3] = s_min * s_min / s1;
    out.observability[4] = 1.0 / s.cwiseInverse().sum();
  } else {
    out.condition = kInf;
  }
  out.undetermined = std::move(rule.undetermined);
  if (column_scale) *column_scale = scale;
  if (V) *V = std::move(rule.V);
  return out;
}

}  // namespace detail

namespace {

// Position rows divided by L (rotation rows are rad already).
MatX dimensionless(const MatX& J, Measure measure, double L) {
  MatX A = J;
  const int per = rowsPerMeasurement(measure);
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    if (measure != Measure::Pose || r % per >= 3) A.row(r) /= L;
  }
  return A;
}

}  // namespace

RankAnalysis analyzeRank(const MatX& jacobian, Measure measure, double L, int poses) {
  LP_CHECK(L > 0.0 && std::isfinite(L), "analyzeRank: the length scale must be positive and finite");
  LP_CHECK(jacobian.rows() % rowsPerMeasurement(measure) == 0, "analyzeRank: rows are not whole measurements");
  LP_CHECK(jacobian.allFinite(), "analyzeRank: the Jacobian has a non-finite entry");
  return analyzeDimensionless(dimensionless(jacobian, measure, L), poses);
}

Identifiability analyzeIdentifiability(const PoeModel& model, const std::vector<VecX>& q, Measure measure,
                                       const ErrorModelSpec& options, const std::vector<PoseLoad>& loads) {
  checkPoses(q, model.dof());
  checkTargets(measure, options);
  Identifiability out;
  out.measure = measure;
  out.free_pitch = options.free_pitch;
  ErrorModelSpec spec;  // the full set
  spec.free_pitch = options.free_pitch;
  spec.targets = options.targets;
  spec.compliance_joints = options.compliance_joints;
  spec.backlash_joints = options.backlash_joints;
  spec.deflection = options.deflection;
  LP_CHECK(loads.empty() || loads.size() == q.size(), "analyzeIdentifiability: " << loads.size() << " loads for " << q.size() << " poses");
  out.expected = identifiableCount(model, measure, spec);
  const ErrorModel em(model, spec);
  out.parameters = em.parameters();
  const int per = rowsPerMeasurement(measure), k = measure == Measure::Targets ? static_cast<int>(spec.targets.size()) : 1;
  const auto poses = static_cast<int>(q.size());
  MatX J(per * static_cast<Eigen::Index>(poses) * k, em.size());
  for (int m = 0; m < poses; ++m) {
    for (int t = 0; t < k; ++t) {
      em.jacobian(q[static_cast<size_t>(m)], loads.empty() ? PoseLoad{} : loads[static_cast<size_t>(m)], measure,
                  J.middleRows(per * (m * k + t), per), measure == Measure::Targets ? t : -1);
    }
  }
  const double L = model.lengthScale();
  out.poe = analyzeRank(J, measure, L, poses);
  const MatX full = fullErrorModelJacobian(model, q, measure, spec, loads);
  out.full_model_rank = analyzeRank(full, measure, L, poses).rank;
  out.full_model_columns = static_cast<int>(full.cols());
  const DhConversion dh = poeToDh(model);
  out.dh = analyzeRank(dhIdentificationJacobian(dh.model, q, measure, spec, &out.dh_parameters, loads), measure,
                       L, poses);
  return out;
}

}  // namespace lowpair
