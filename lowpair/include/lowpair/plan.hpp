#pragma once
/// @file plan.hpp
/// Planning the poses of a calibration (docs/plan.md): choose N of M candidate joint vectors so that the
/// identification Jacobian of the minimal parameters (calibration.hpp, ErrorModel) is as well conditioned
/// as possible, and predict the standard deviation of every D-H number a calibration on them would give.
///
/// Scaling (the rank rule's, analyzeRank): position rows are divided by the robot size L (rotation rows
/// are rad), and every column c is divided by `s_c = |column c over the M candidates| / sqrt(M)`, its
/// root mean square per candidate pose. The scale is fixed by the candidates, not by the set, so the
/// criterion of two sets drawn from the same candidates compares their information and nothing else (a
/// set whose own column norms were made 1 would hide how much it sees of each parameter). A column no
/// candidate moves stays zero.
///
/// The criterion is taken over the directions the candidates determine (the rank rule on all M
/// candidates stacked): with an orthonormal basis Q of them (right singular vectors), a pose's block is
/// `B_m = A_m Q` (A_m its scaled rows), a set's information `F = sum B_m^T B_m` (r x r, r the candidates'
/// rank), and
/// - D-optimality: `log det F` (-inf when the set does not determine all r directions);
/// - O1 (Sun & Hollerbach 1997): `(prod sigma_i)^(1/r) / sqrt(N) = exp(log det F / (2 r)) / sqrt(N)`,
///   sigma_i the singular values of the stacked `B`. For a fixed N it is a monotone function of
///   `log det F`: both criteria choose the same set; they differ in the number reported.
///
/// Algorithm: greedy selection (Wynn / Dykstra) by the matrix determinant lemma, each step adding the
/// candidate of largest gain `log det(I + B_c F^-1 B_c^T)` (F with a small ridge `kPlanRidge I` while the
/// set does not yet determine every direction), then exchange passes (Fedorov 1972, in the sequential form
/// of Cook & Nachtsheim 1980): each pose of the set in turn is swapped for the candidate that raises
/// `log det F` most, `log det(I + S_jj) + log det(I - S_ii + S_ij (I + S_jj)^-1 S_ji)` with
/// `S_ab = B_a F^-1 B_b^T`, when that gain exceeds kPlanImprovement; passes repeat until none swaps.

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/model.hpp"

namespace lowpair {

/// What a plan maximizes (see the file comment).
enum class PlanCriterion { D, O1 };

/// "D" / "O1".
const char* planCriterionName(PlanCriterion criterion);

/// Ridge added to the information, relative to the candidates' mean information per pose and direction
/// (1 in the scaled units), while a set does not determine every direction: small enough that the greedy
/// step's gain is dominated by the directions a candidate adds, large enough to keep the factorization of
/// a singular information matrix far from rounding.
constexpr double kPlanRidge = 1e-6;
/// An exchange is made only when it raises `log det F` by more than this (the determinant by a factor
/// 1 + 1e-9): a strict increase, so the passes end.
constexpr double kPlanImprovement = 1e-9;

struct PlanOptions {
  Measure measure = Measure::Pose;
  bool free_pitch = false;
  /// Measure::Targets: the targets (as CalibrationOptions::targets), each with its point (tool frame); every pose
  /// measures each (3 rows per target). Their names name the targets' parameters ("1", "2", ... when one is empty).
  std::vector<Target> targets;
  /// Measure::Targets, optional: per candidate (planCandidates' order), per target, whether the pose measures it
  /// (a tracker's line of sight, docs/plan.md); empty: every pose measures every target. A target not measured
  /// contributes no rows: its three rows of the candidate's block are zero.
  std::vector<std::vector<bool>> measured;
  PlanCriterion criterion = PlanCriterion::D;
  int max_exchange_passes = 100;  ///< each pass tries every pose of the set once
  /// The search's work budget: a trial (a pose against a candidate) costs about rows x (rank + rows)
  /// operations, a pose added or swapped in about candidates x rows x rank^2; the greedy steps add N - start
  /// poses after trying each against every candidate, an exchange pass tries N x candidates; no pass starts
  /// that would take the total beyond the budget. 2e11 is about a minute here (1000 PUMA poses of 5000
  /// candidates: 5.4e10, 22 s; of 46,296: 4.9e11 for the greedy steps alone, 153 s). PlanResult::work_limit
  /// says when it ended the exchange.
  double max_exchange_work = 2e11;

  /// The rules the planning functions apply to their options (the CLI and the Python module call it too).
  /// @throws std::invalid_argument for targets with another measure (or none with Measure::Targets), a
  /// target without a point or with one not finite, max_exchange_passes < 0, or max_exchange_work not positive
  void validate() const;
};

/// The candidates' scaled identification blocks, computed once (compute, then get): every plan, exchange
/// and evaluation of subsets of the same candidates reads them.
struct PlanCandidates {
  Measure measure = Measure::Pose;
  bool free_pitch = false;
  std::vector<Target> targets;          ///< PlanOptions::targets
  std::vector<VecX> q;                  ///< the candidates (joint vectors)
  std::vector<Parameter> parameters;    ///< the columns: ErrorModel(model, {free_pitch, targets})
  ParameterCount expected;              ///< identifiableCount
  double length_scale = 1.0;            ///< L, dividing the position rows
  int rows_per_pose = 6;                ///< 6 (Pose), 3 (Position), 3k (k targets)
  /// Per parameter: the candidates' RMS per pose of its dimensionless column (1 for a column no candidate moves).
  VecX column_rms;
  /// Every candidate's block, dimensionless and column-scaled (A_m: rows m*rows_per_pose ...).
  MatX scaled;
  /// The rank rule on all candidates stacked: the number r of directions any set can determine, and those
  /// no set determines (named as RankAnalysis::undetermined: columns with coefficients above 0.1).
  int rank = 0;
  std::vector<std::vector<std::pair<int, double>>> undetermined;
  MatX basis;  ///< p x r, orthonormal: the determined directions (right singular vectors, scaled columns)
  /// The blocks in the determined directions, transposed: column block m (`rows_per_pose` columns) is
  /// `B_m^T = (A_m Q)^T` (r x rows), each candidate contiguous.
  MatX reduced_t;
  int count() const { return static_cast<int>(q.size()); }
};

/// @throws std::invalid_argument for no candidate, a candidate of the wrong size or not finite, targets
/// with another measure (or none with Measure::Targets), or a Named parameter set
PlanCandidates planCandidates(const PoeModel& model, const std::vector<VecX>& candidates, const PlanOptions& options);

/// A set's criterion values (see the file comment).
struct PlanValue {
  double log_det = -std::numeric_limits<double>::infinity();  ///< D; -inf when rank < r
  double o1 = 0.0;  ///< O1; 0 when rank < r
  int rank = 0;     ///< of the set's stacked B, by the rank rule (at most the candidates' r)
  double criterion(PlanCriterion c) const { return c == PlanCriterion::D ? log_det : o1; }
};

/// The criterion of the candidates `indices` (each at most once; any order).
/// @throws std::invalid_argument for an index out of range, a repeated one, or none
PlanValue evaluatePlan(const PlanCandidates& candidates, const std::vector<int>& indices);

struct PlanResult {
  std::vector<int> indices;  ///< the chosen candidates, increasing
  PlanCriterion criterion = PlanCriterion::D;
  PlanValue value;           ///< of the chosen set
  PlanValue start;           ///< of the set the exchange started from (planPoses: the greedy set)
  int swaps = 0;             ///< exchanges made
  int passes = 0;            ///< exchange passes run (the last one made none, unless max_exchange_passes ended it)
  bool work_limit = false;   ///< the exchange ended at PlanOptions::max_exchange_work (the set is the last pass's)
  /// The rank rule (analyzeRank) on the chosen set's identification Jacobian, with its undetermined directions
  /// (the count cannot be reached when N poses have fewer rows than parameters, or when the candidates do not
  /// determine everything: `candidate_rank`).
  RankAnalysis rank;
  ParameterCount expected;
  int candidate_rank = 0;    ///< PlanCandidates::rank
};

/// Chooses `N` of the candidates: greedy, then exchange passes (file comment).
/// @throws std::invalid_argument for N < 1 or N > candidates.count()
PlanResult planPoses(const PlanCandidates& candidates, int N, const PlanOptions& options = {});

/// planPoses on candidates computed from `model` (planCandidates).
PlanResult planPoses(const PoeModel& model, const std::vector<VecX>& candidates, int N, const PlanOptions& options);

/// Exchange passes from the set `start` (the second half of planPoses): the result's `log_det` is never
/// below `start`'s.
/// @throws std::invalid_argument as evaluatePlan for `start`
PlanResult exchangePoses(const PlanCandidates& candidates, const std::vector<int>& start, const PlanOptions& options = {});

/// `sets` random sets of N distinct candidates (the baseline a plan is compared with): set k is drawn by
/// Floyd's algorithm from a std::mt19937_64 seeded with `seed + k` (raw engine outputs reduced modulo the
/// range, a bias below 2^-40 for at most 2^24 candidates), indices increasing.
/// @throws std::invalid_argument for N < 1, N > M or sets < 0
std::vector<std::vector<int>> randomPoseSets(int M, int N, int sets, unsigned long long seed);

/// The expected result of calibrating on `q` (docs/plan.md): calibrate() on noise-free measurements of
/// `model` itself at `q` (frame not registered: it is the base frame), with the stated noise, so the fit
/// converges at once and its covariance is the stated noise carried through the weighted identification
/// Jacobian at the model; `dh` propagates it through the D-H conversion (dhUncertainty).
struct ExpectedUncertainty {
  CalibrationResult calibration;  ///< standard_deviation per parameter; rank and undetermined directions
  DhUncertainty dh;
};

/// @param sigma_position, sigma_rotation the measurement noise as CalibrationOptions states it (one may be
/// derived from the other with L); at least one must be given
/// @param measured Measure::Targets, optional: per pose of `q`, per target, whether it is measured (as
/// PlanOptions::measured, whose own value, per candidate, is not read here); empty: every target of every pose
/// @throws std::invalid_argument without stated noise, for no pose, a `measured` of the wrong shape, or as calibrate
ExpectedUncertainty expectedUncertainty(const PoeModel& model, const std::vector<VecX>& q, const PlanOptions& options,
                                        std::optional<double> sigma_position, std::optional<double> sigma_rotation,
                                        const std::vector<std::vector<bool>>& measured = {});

}  // namespace lowpair
