#include "lowpair/plan.hpp"
#include "linalg.hpp"
#include "rank_rule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "check.hpp"
#include "lowpair/interrupt.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace {

int rowsPerCandidate(const PlanOptions& options) {
  return rowsPerPose(options.measure, static_cast<int>(options.targets.size()));
}

// the candidate's rows of a stacked matrix
template <class M>
auto candidateRows(M& matrix, int m, int rows) {
  return matrix.middleRows(static_cast<Eigen::Index>(m) * rows, rows);
}

// the candidate's column block of PlanCandidates::reduced_t (r x rows)
template <class M>
auto candidateCols(M& matrix, int m, int rows) {
  return matrix.middleCols(static_cast<Eigen::Index>(m) * rows, rows);
}

void checkIndices(const PlanCandidates& c, const std::vector<int>& indices) {
  LP_CHECK(!indices.empty(), "a pose set needs at least one pose");
  std::vector<char> seen(static_cast<size_t>(c.count()), 0);
  for (const int i : indices) {
    LP_CHECK(i >= 0 && i < c.count(), "candidate index " << i << " is outside [0, " << c.count() << ")");
    LP_CHECK(!seen[static_cast<size_t>(i)], "candidate " << i << " appears twice in a pose set");
    seen[static_cast<size_t>(i)] = 1;
  }
}

// The set's identification Jacobian in the calibration's units (ErrorModel::jacobian), recovered from the
// scaled blocks: columns times their RMS, position rows times L.
MatX setJacobian(const PlanCandidates& c, const std::vector<int>& indices) {
  const int rows = c.rows_per_pose;
  MatX J(static_cast<Eigen::Index>(indices.size()) * rows, c.scaled.cols());
  for (size_t k = 0; k < indices.size(); ++k) {
    auto block = candidateRows(J, static_cast<int>(k), rows);
    block.noalias() = candidateRows(c.scaled, indices[k], rows) * c.column_rms.asDiagonal();
    for (int row = 0; row < rows; ++row) {
      if (c.measure != Measure::Pose || row >= 3) block.row(row) *= c.length_scale;
    }
  }
  return J;
}

// --- the search ------------------------------------------------------------------------------------------
//
// State of a greedy or exchange search over one PlanCandidates: the set, its information F (with the ridge
// while the set does not determine every direction), and for the current F: Wt = L^-1 B^T (F = L L^T) for
// every candidate, whose blocks give S_ab = Wt_a^T Wt_b, and per candidate the Cholesky factor of
// I + S_jj and the gain log det(I + S_jj) of adding it. R: the rows per candidate when fixed (3, 6), so the
// per-candidate products are small fixed-size ones (no GEMM packing per candidate).
template <int R>
class Search {
 public:
  using Small = Eigen::Matrix<double, R, R>;
  using Tall = Eigen::Matrix<double, Eigen::Dynamic, R>;  // r x rows

  Search(const PlanCandidates& c, std::vector<int> set)
      : c_(c), rows_(c.rows_per_pose), r_(c.rank), chosen_(static_cast<size_t>(c.count()), 0), set_(std::move(set)) {
    for (const int i : set_) chosen_[static_cast<size_t>(i)] = 1;
    gain_.resize(c.count());
    factors_.resize(rows_, static_cast<Eigen::Index>(c.count()) * rows_);
    ridge_ = kPlanRidge;
    updateRidge();
    refresh();
  }

  const std::vector<int>& set() const { return set_; }

  // Greedy: add the candidate of largest gain.
  void addBest() {
    int best = -1;
    for (int j = 0; j < c_.count(); ++j) {
      if (!chosen_[static_cast<size_t>(j)] && (best < 0 || gain_[j] > gain_[best])) best = j;
    }
    LP_ASSERT(best >= 0);
    set_.push_back(best);
    chosen_[static_cast<size_t>(best)] = 1;
    updateRidge();
    refresh();
  }

  // One exchange pass: each pose of the set in turn swapped for the candidate that raises log det F most,
  // when that is more than kPlanImprovement. Returns the swaps made.
  int exchangePass() {
    int swaps = 0;
    for (size_t k = 0; k < set_.size(); ++k) {
      pollInterrupt();  // one pose of the set against every candidate between polls
      const int i = set_[k];
      const Tall W_i = block(Wt_, i);
      Small I_minus_Sii = -W_i.transpose().lazyProduct(W_i);
      I_minus_Sii.diagonal().array() += 1.0;
      double best_gain = kPlanImprovement;
      int best = -1;
      for (int j = 0; j < c_.count(); ++j) {
        if (chosen_[static_cast<size_t>(j)]) continue;
        // X = L_j^-1 S_ji, L_j the factor of I + S_jj: S_ij (I + S_jj)^-1 S_ji = X^T X
        Small X = block(Wt_, j).transpose().lazyProduct(W_i);
        block(factors_, j).template triangularView<Eigen::Lower>().solveInPlace(X);
        Small T = I_minus_Sii;
        T.noalias() += X.transpose().lazyProduct(X);
        const Eigen::LLT<Small> llt(T);
        if (llt.info() != Eigen::Success) continue;  // F' singular: the swap loses a direction
        const double gain = gain_[j] + 2.0 * llt.matrixLLT().diagonal().array().log().sum();
        if (gain > best_gain) {
          best_gain = gain;
          best = j;
        }
      }
      if (best < 0) continue;
      chosen_[static_cast<size_t>(i)] = 0;
      chosen_[static_cast<size_t>(best)] = 1;
      set_[k] = best;
      ++swaps;
      updateRidge();
      refresh();
    }
    return swaps;
  }

 private:
  // candidate m's column block (rows_ columns), fixed-size when R is
  template <class M>
  auto block(M& matrix, int m) const {
    if constexpr (R == Eigen::Dynamic) {
      return matrix.middleCols(static_cast<Eigen::Index>(m) * rows_, rows_);
    } else {
      return matrix.template middleCols<R>(static_cast<Eigen::Index>(m) * R);
    }
  }

  // The ridge stays until the set determines every direction (then F is exact: the criterion itself).
  void updateRidge() {
    if (ridge_ == 0.0) return;
    if (static_cast<long long>(set_.size()) * rows_ >= r_ && evaluatePlan(c_, set_).rank == r_) ridge_ = 0.0;
  }

  // F, its factor, Wt, and every candidate's factor of I + S_jj and gain.
  void refresh() {
    MatX F = MatX::Identity(r_, r_) * ridge_;
    for (const int i : set_) F.noalias() += block(c_.reduced_t, i) * block(c_.reduced_t, i).transpose();
    Eigen::LLT<MatX> llt(F);
    if (llt.info() != Eigen::Success && ridge_ == 0.0) {  // determined by the rule but not factorable: keep a ridge
      ridge_ = kPlanRidge;
      F.diagonal().array() += ridge_;
      llt.compute(F);
    }
    LP_ASSERT(llt.info() == Eigen::Success);
    Wt_ = c_.reduced_t;
    llt.matrixL().solveInPlace(Wt_);
    for (int j = 0; j < c_.count(); ++j) {
      const auto W = block(Wt_, j);
      Small A = W.transpose().lazyProduct(W);
      A.diagonal().array() += 1.0;
      const Eigen::LLT<Small> f(A);  // I + S_jj is positive definite
      block(factors_, j) = f.matrixL();
      gain_[j] = 2.0 * f.matrixLLT().diagonal().array().log().sum();
    }
  }

  const PlanCandidates& c_;
  int rows_, r_;
  std::vector<char> chosen_;
  std::vector<int> set_;
  double ridge_ = 0.0;
  MatX Wt_;       // r x M rows
  MatX factors_;  // rows x M rows: lower factors of I + S_jj
  VecX gain_;     // log det(I + S_jj)
};

PlanResult finish(const PlanCandidates& c, std::vector<int> set, const PlanValue& start, int swaps, int passes,
                  PlanCriterion criterion) {
  PlanResult out;
  std::sort(set.begin(), set.end());
  out.indices = std::move(set);
  out.criterion = criterion;
  out.value = evaluatePlan(c, out.indices);
  out.start = start;
  out.swaps = swaps;
  out.passes = passes;
  out.rank = analyzeRank(setJacobian(c, out.indices), c.measure, c.length_scale, static_cast<int>(out.indices.size()));
  out.expected = c.expected;
  out.candidate_rank = c.rank;
  return out;
}

template <int R>
PlanResult runPlan(const PlanCandidates& c, std::vector<int> start, int N, const PlanOptions& options) {
  // the search's work (PlanOptions::max_exchange_work): a trial of a pose against a candidate costs about
  // rows x (rank + rows) operations, a pose added or swapped in candidates x rows x rank^2 (every candidate's
  // factor updated)
  const double M = c.count(), rows = c.rows_per_pose, rank = c.rank;
  const double trial = rows * (rank + rows), update = M * rows * rank * rank;
  double work = static_cast<double>(N - static_cast<int>(start.size())) * (M * trial + update);
  Search<R> search(c, std::move(start));
  while (static_cast<int>(search.set().size()) < N) {
    pollInterrupt();
    search.addBest();
  }
  const PlanValue before = evaluatePlan(c, search.set());
  int swaps = 0, passes = 0;
  const double pass_trials = static_cast<double>(N) * M * trial;
  bool work_limit = false;
  while (passes < options.max_exchange_passes) {
    if (work + pass_trials > options.max_exchange_work) {  // the greedy steps and the passes so far count
      work_limit = true;
      break;
    }
    ++passes;
    const int made = search.exchangePass();
    work += pass_trials + made * update;
    swaps += made;
    if (made == 0) break;
  }
  PlanResult out = finish(c, search.set(), before, swaps, passes, options.criterion);
  out.work_limit = work_limit;
  return out;
}

PlanResult dispatch(const PlanCandidates& c, std::vector<int> start, int N, const PlanOptions& options) {
  options.validate();
  if (c.rank == 0) {  // nothing to determine: any set is as good (the first N)
    std::vector<int> set = start;
    for (int j = 0; static_cast<int>(set.size()) < N; ++j) {
      if (std::find(set.begin(), set.end(), j) == set.end()) set.push_back(j);
    }
    const PlanValue v = evaluatePlan(c, set);
    return finish(c, std::move(set), v, 0, 0, options.criterion);
  }
  switch (c.rows_per_pose) {  // fixed sizes: a position, a pose, three SMRs (a tracker's usual nest)
    case 3: return runPlan<3>(c, std::move(start), N, options);
    case 6: return runPlan<6>(c, std::move(start), N, options);
    case 9: return runPlan<9>(c, std::move(start), N, options);
    default: return runPlan<Eigen::Dynamic>(c, std::move(start), N, options);
  }
}

}  // namespace

void PlanOptions::validate() const {
  LP_CHECK((measure == Measure::Targets) == !targets.empty(), "Measure::Targets needs targets' points, and only it");
  for (const Target& t : targets) {
    LP_CHECK(t.point_tool, "target " << t.name << " has no point: planning needs every target's point");
    LP_CHECK(t.point_tool->allFinite(), "a target's point is not finite");
  }
  LP_CHECK(measured.empty() || measure == Measure::Targets, "PlanOptions::measured goes with Measure::Targets only");
  for (const std::vector<bool>& m : measured) {
    LP_CHECK(m.size() == targets.size(), "PlanOptions::measured: a candidate has " << m.size() << " flags for "
                                                                                 << targets.size() << " targets");
  }
  LP_CHECK(max_exchange_passes >= 0, "max_exchange_passes must be >= 0, got " << max_exchange_passes);
  LP_CHECK(max_exchange_work > 0.0, "max_exchange_work must be positive, got " << max_exchange_work);
}

const char* planCriterionName(PlanCriterion criterion) { return criterion == PlanCriterion::D ? "D" : "O1"; }

PlanCandidates planCandidates(const PoeModel& model, const std::vector<VecX>& candidates, const PlanOptions& options) {
  LP_CHECK(!candidates.empty(), "planning needs at least one candidate pose");
  options.validate();
  for (const VecX& q : candidates) checkJointVector(q, model.dof());
  LP_CHECK(options.measured.empty() || options.measured.size() == candidates.size(),
           "PlanOptions::measured has " << options.measured.size() << " candidates' flags for " << candidates.size());
  ErrorModelSpec spec;
  spec.free_pitch = options.free_pitch;
  spec.targets = options.targets;
  const ErrorModel em(model, spec);

  PlanCandidates c;
  c.measure = options.measure;
  c.free_pitch = options.free_pitch;
  c.targets = options.targets;
  c.q = candidates;
  c.parameters = em.parameters();
  c.expected = identifiableCount(model, options.measure, spec);
  c.length_scale = model.lengthScale();
  c.rows_per_pose = rowsPerCandidate(options);
  const int M = c.count(), rows = c.rows_per_pose, p = em.size();

  // the blocks, dimensionless (position rows / L)
  c.scaled.resize(static_cast<Eigen::Index>(M) * rows, p);
  for (int m = 0; m < M; ++m) {
    auto block = candidateRows(c.scaled, m, rows);
    if (options.measure == Measure::Targets) {
      for (int t = 0; t * 3 < rows; ++t) {
        const bool seen = options.measured.empty() || options.measured[static_cast<size_t>(m)][static_cast<size_t>(t)];
        if (seen) {
          em.jacobian(candidates[static_cast<size_t>(m)], Measure::Targets, block.middleRows(3 * t, 3), t);
        } else {
          block.middleRows(3 * t, 3).setZero();  // a target the pose does not measure: no rows
        }
      }
    } else {
      em.jacobian(candidates[static_cast<size_t>(m)], options.measure, block);
    }
    for (int row = 0; row < rows; ++row) {
      if (options.measure != Measure::Pose || row >= 3) block.row(row) /= c.length_scale;
    }
  }
  LP_CHECK(c.scaled.allFinite(), "the identification Jacobian of a candidate is not finite");
  // columns over their RMS per candidate (a zero column stays zero)
  c.column_rms = VecX::Ones(p);
  for (int k = 0; k < p; ++k) {
    const double rms = c.scaled.col(k).norm() / std::sqrt(static_cast<double>(M));
    if (rms > 0.0 && std::isfinite(rms)) {
      c.column_rms[k] = rms;
      c.scaled.col(k) /= rms;
    }
  }
  // the directions the candidates determine: the rank rule on all of them stacked
  detail::ScaledRank rule = detail::scaledRank(c.scaled);
  c.rank = rule.rank;
  c.basis = rule.V.leftCols(c.rank);
  c.undetermined = std::move(rule.undetermined);
  c.reduced_t.noalias() = c.basis.transpose() * c.scaled.transpose();
  return c;
}

PlanValue evaluatePlan(const PlanCandidates& c, const std::vector<int>& indices) {
  checkIndices(c, indices);
  const int rows = c.rows_per_pose, r = c.rank;
  PlanValue v;
  const auto N = static_cast<double>(indices.size());
  if (r == 0) {  // no direction: the empty determinant
    v.log_det = 0.0;
    v.o1 = 1.0 / std::sqrt(N);
    return v;
  }
  MatX B(static_cast<Eigen::Index>(indices.size()) * rows, r);
  for (size_t k = 0; k < indices.size(); ++k) {
    candidateRows(B, static_cast<int>(k), rows) = candidateCols(c.reduced_t, indices[k], rows).transpose();
  }
  const Eigen::JacobiSVD<MatX> svd(B);
  VecX s = VecX::Zero(r);
  s.head(svd.singularValues().size()) = svd.singularValues();
  // the rule's n is the parameter count, as for the whole identification Jacobian
  v.rank = numericalRank(s, numericalRankTolerance(s[0], static_cast<double>(c.scaled.cols())));
  if (v.rank == r) {
    const double sum_log = s.array().log().sum();
    v.log_det = 2.0 * sum_log;
    v.o1 = std::exp(sum_log / r) / std::sqrt(N);
  }
  return v;
}

PlanResult planPoses(const PlanCandidates& candidates, int N, const PlanOptions& options) {
  LP_CHECK(N >= 1 && N <= candidates.count(),
           "planPoses: N must be in [1, " << candidates.count() << "] (the candidates), got " << N);
  return dispatch(candidates, {}, N, options);
}

PlanResult planPoses(const PoeModel& model, const std::vector<VecX>& candidates, int N, const PlanOptions& options) {
  return planPoses(planCandidates(model, candidates, options), N, options);
}

PlanResult exchangePoses(const PlanCandidates& candidates, const std::vector<int>& start, const PlanOptions& options) {
  checkIndices(candidates, start);
  return dispatch(candidates, start, static_cast<int>(start.size()), options);
}

std::vector<std::vector<int>> randomPoseSets(int M, int N, int sets, unsigned long long seed) {
  LP_CHECK(N >= 1 && N <= M, "randomPoseSets: N must be in [1, " << M << "], got " << N);
  LP_CHECK(sets >= 0, "randomPoseSets: sets must be >= 0, got " << sets);
  std::vector<std::vector<int>> out;
  std::vector<char> in(static_cast<size_t>(M), 0);
  for (int k = 0; k < sets; ++k) {
    std::mt19937_64 rng(seed + static_cast<unsigned long long>(k));
    std::vector<int> set;
    for (int j = M - N; j < M; ++j) {  // Floyd: a uniform N-subset of [0, M)
      const auto t = static_cast<int>(rng() % static_cast<unsigned long long>(j + 1));
      const int pick = in[static_cast<size_t>(t)] ? j : t;
      in[static_cast<size_t>(pick)] = 1;
      set.push_back(pick);
    }
    for (const int i : set) in[static_cast<size_t>(i)] = 0;
    std::sort(set.begin(), set.end());
    out.push_back(std::move(set));
  }
  return out;
}

ExpectedUncertainty expectedUncertainty(const PoeModel& model, const std::vector<VecX>& q, const PlanOptions& options,
                                        std::optional<double> sigma_position, std::optional<double> sigma_rotation,
                                        const std::vector<std::vector<bool>>& measured) {
  LP_CHECK(sigma_position || sigma_rotation, "expectedUncertainty: state the measurement noise (position, rotation or both)");
  LP_CHECK(!q.empty(), "expectedUncertainty: needs at least one pose");
  LP_CHECK(measured.empty() || (options.measure == Measure::Targets && measured.size() == q.size()),
           "expectedUncertainty: measured needs Measure::Targets and one entry per pose (" << q.size() << "), got "
                                                                                          << measured.size());
  for (const std::vector<bool>& m : measured) {
    LP_CHECK(m.size() == options.targets.size(), "expectedUncertainty: measured has " << m.size() << " flags for "
                                                                                     << options.targets.size() << " targets");
  }
  options.validate();
  CalibrationOptions co;
  co.measure = options.measure;
  co.free_pitch = options.free_pitch;
  co.sigma_position = sigma_position;
  co.sigma_rotation = sigma_rotation;
  co.register_frame = false;  // the measurements are in the base frame
  co.targets = options.targets;  // each with its point (validate)
  std::vector<Measurement> measurements;
  Data data(model);
  for (size_t k = 0; k < q.size(); ++k) {
    const VecX& qi = q[k];
    checkJointVector(qi, model.dof());
    forwardKinematics(model, data, qi);
    const Pose& T = data.T_base_tool;
    if (options.measure != Measure::Targets) {
      measurements.push_back(Measurement{qi, T});
      continue;
    }
    for (size_t t = 0; t < options.targets.size(); ++t) {
      if (!measured.empty() && !measured[k][t]) continue;
      measurements.push_back(Measurement{qi, Pose{Mat3::Identity(), T.R * *options.targets[t].point_tool + T.p}, static_cast<int>(t)});
    }
  }
  CalibrationResult calibration = calibrate(model, measurements, co);
  DhUncertainty dh = dhUncertainty(calibration);
  return ExpectedUncertainty{std::move(calibration), std::move(dh)};
}

}  // namespace lowpair
