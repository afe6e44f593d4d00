#pragma once
/// @file limits.hpp
/// The size limits of an identification (identifiability, calibrate, --select cv, plan's candidates) and of the
/// inverse kinematics of `ik` and `compensate`, for the CLI and the Python module alike: memory (the numbers held
/// at once) and time (the SVDs' work, the solver's iterations), checked before any work starts (docs/cli.md
/// "Limits").

#include <optional>
#include <string>

#include "lowpair/ik.hpp"
#include "lowpair/measure.hpp"

namespace lowpair::commands {

/// Upper bound on the entries of an identification Jacobian (rows x columns) and the SVD's full V (columns
/// squared): 2e7 doubles, 160 MB, and its SVD about as much again.
constexpr double kMaxJacobianEntries = 2e7;
/// Upper bound on one SVD's work (IdentificationSize::work): about 5 s for `identifiability` (three SVDs) and
/// 25 s for a `calibrate` fit (one SVD per iteration) at the limit on a 2019 x86-64 core (measured: 100 targets
/// on 2 poses, work 2.6e8, 1.5 s; 200 targets, 1.8e9, 11 s).
constexpr double kMaxIdentificationWork = 1e9;
/// Upper bound on the work of `--select cv`: its fits (1 + folds x repeats x candidates; 3 levels, times the prior
/// widths and the deflections on and off compared) times one SVD's work;
/// about 60 s at the limit (measured: 151 fits of 200 PUMA poses, 3.8e8, 9.5 s).
constexpr double kMaxCrossValidationWork = 2.4e9;

/// Upper bound on the work of `ik` and `compensate`: rows x attempts per row (ik's seeds; 1 for a row's own seed
/// and for compensate) x the iteration cap (kIkMaxIterations, 100) x joints (an iteration's cost grows with the
/// joints: the Jacobian, 6 x n, and its QR). 5.6e9 is the default 8 seeds at the row limit (10^6) for a 7-joint
/// robot: no combination of rows and seeds costs more than that. An iteration of a 6-joint robot takes 1.7-2.5
/// us here (about 0.35 us per joint); an unsolved attempt stops at 15-45 iterations on average (measured over
/// 2000 random seeds each of targets out of range or reach), 100 at most: 10-25 min at the limit if no row is
/// solved; rows solved at their first seed take 0.1 ms (10^6 rows of poses in reach: 108 s).
constexpr double kMaxIkWork = 5.6e9;

/// What is over kMaxIkWork for `rows` rows of `attempts` attempts each (ik's seeds; 1 for a row's own seed and
/// for compensate) of a `joints`-joint robot: the text after `SUBJECT: ` (the numbers, the limit, and the most
/// rows at these attempts, or the most seeds for these rows when `seeds_named`), or nothing.
std::optional<std::string> ikWorkProblem(size_t rows, int attempts, int joints, bool seeds_named);

/// Upper bound on the numbers of a plan's candidate blocks (candidates x rows x parameters): the blocks are held
/// about four times (scaled, the SVD's copy, in the determined directions, the search's working copy), so 1e7
/// numbers is about 320 MB.
constexpr double kMaxPlanEntries = 1e7;

/// An identification's Jacobian: rows and columns.
struct IdentificationSize {
  double rows = 0.0, columns = 0.0;
  /// the numbers held at once: the Jacobian and the SVD's full V
  double entries() const { return rows * columns + columns * columns; }
  /// one SVD's work: the QR of the rows (rows columns^2) and the Jacobi sweeps on the square part (about
  /// five times columns^3, measured)
  double work() const { return rows * columns * columns + 5.0 * columns * columns * columns; }
};

/// `measurements` measurements (poses; for targets, one per target and pose) of a `joints`-joint robot with
/// `columns_per_joint` parameters per joint, the tool's 6 and 3 per target: 6 rows per pose measurement, 3 per
/// point.
IdentificationSize identificationSize(double measurements, double joints, double columns_per_joint, Measure measure,
                                      double targets);

/// The numbers an identification of `poses` pose measurements holds at once (IdentificationSize::entries).
inline double identificationEntries(double poses, double joints, double columns_per_joint) {
  return identificationSize(poses, joints, columns_per_joint, Measure::Pose, 0.0).entries();
}

/// What is over a limit, or nothing: `robot` when one pose alone is (the robot or its targets, whatever the
/// pose count).
struct SizeProblem {
  std::string text;
  bool robot = false;
};

/// What of `s` is over the identification limits (kMaxJacobianEntries, kMaxIdentificationWork), as the end of a
/// sentence ("exceed the identification size limit (...)"), or "" when within both.
std::string identificationOverLimit(const IdentificationSize& s);

/// A plan of `poses` poses from `candidates` candidates of `rows` rows and `columns` parameters each: their blocks
/// (kMaxPlanEntries), the SVD of them stacked (kMaxIdentificationWork) and the greedy steps alone
/// (`max_exchange_work`, PlanOptions); `robot` when one candidate alone is over. `targets`: the hint names them.
std::optional<SizeProblem> planSizeProblem(double candidates, double poses, double rows, double columns,
                                           double max_exchange_work, bool targets);

/// identifiability of `poses` random poses (`targets` targets measured at each for Measure::Targets).
std::optional<SizeProblem> identifiabilitySizeProblem(int poses, int joints, Measure measure, int targets);

/// --select cv over `measurements` measurements: 1 + folds x repeats x candidates fits of about their size.
std::optional<std::string> crossValidationSizeProblem(size_t measurements, int joints, Measure measure, int targets,
                                                      int folds, int repeats, int candidates = 3);

}  // namespace lowpair::commands
