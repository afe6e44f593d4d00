// The size limits of an identification (limits.hpp).
#include "commands/limits.hpp"

#include <cmath>
#include <cstdio>

#include "io/output.hpp"

namespace lowpair::commands {

IdentificationSize identificationSize(double measurements, double joints, double columns_per_joint, Measure measure,
                                      double targets) {
  IdentificationSize s;
  // target measurements: a pose of k targets is k measurements of 3 rows (the caller counts them)
  s.rows = measurements * (measure == Measure::Pose ? 6.0 : 3.0);
  s.columns = columns_per_joint * joints + 6.0 + (measure == Measure::Targets ? 3.0 * targets : 0.0);
  return s;
}

namespace {

std::string sizeText(const IdentificationSize& s) {
  return io::shortest(s.rows) + " rows x " + io::shortest(s.columns) + " parameters";
}

std::string whole(double x) { return std::to_string(static_cast<long long>(x)); }

std::string scientific(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

}  // namespace

std::string identificationOverLimit(const IdentificationSize& s) {
  if (s.entries() > kMaxJacobianEntries) {
    return "exceed the identification size limit (" + io::shortest(kMaxJacobianEntries) +
           " numbers: the Jacobian and the SVD's V, columns squared)";
  }
  if (s.work() > kMaxIdentificationWork) {
    return "exceed the identification work limit (" + io::shortest(kMaxIdentificationWork) +
           " for one SVD, rows columns^2 + 5 columns^3: seconds; here " + io::shortest(s.work()) + ")";
  }
  return "";
}

std::optional<SizeProblem> planSizeProblem(double candidates, double poses, double rows, double columns,
                                           double max_exchange_work, bool targets) {
  const std::string blocks = whole(candidates) + " candidates of " + io::shortest(rows) + " rows and " +
                             io::shortest(columns) + " parameters exceed the identification ";
  if (candidates * rows * columns > kMaxPlanEntries) {
    return SizeProblem{blocks + "size limit (" + io::shortest(kMaxPlanEntries) +
                           " numbers, held about four times): fewer candidates",
                       rows * columns > kMaxPlanEntries};
  }
  // the rank rule on every candidate's rows stacked: one SVD
  const IdentificationSize stacked{candidates * rows, columns};
  if (stacked.work() > kMaxIdentificationWork) {
    return SizeProblem{blocks + "work limit (" + io::shortest(kMaxIdentificationWork) +
                           " for the SVD of them stacked, rows columns^2 + 5 columns^3; here " +
                           io::shortest(stacked.work()) + "): fewer candidates" + (targets ? " or targets" : ""),
                       IdentificationSize{rows, columns}.work() > kMaxIdentificationWork};
  }
  // the greedy steps alone (rank <= columns): each pose added after a trial against every candidate (rows x (rank +
  // rows)) and every candidate's factor updated (rows x rank^2); the exchange passes stop at the same budget
  const double greedy = poses * candidates * rows * (columns + rows + columns * columns);
  if (greedy > max_exchange_work) {
    return SizeProblem{whole(poses) + " poses from " + whole(candidates) +
                           " candidates exceed the plan's work limit (" + io::shortest(max_exchange_work) +
                           " operations, about a minute; the greedy choice alone takes " + scientific(greedy) +
                           "): fewer candidates or poses",
                       false};
  }
  return std::nullopt;
}

std::optional<SizeProblem> identifiabilitySizeProblem(int poses, int joints, Measure measure, int targets) {
  // the full error model: 8 columns per joint + pitches; one pose of k targets is k point measurements
  const double per_pose = measure == Measure::Targets ? targets : 1.0;
  const IdentificationSize s = identificationSize(poses * per_pose, joints, 9.0, measure, targets);
  const std::string over = identificationOverLimit(s);
  if (over.empty()) return std::nullopt;
  const bool robot = !identificationOverLimit(identificationSize(per_pose, joints, 9.0, measure, targets)).empty();
  return SizeProblem{std::to_string(poses) + " poses of a " + std::to_string(joints) + "-joint robot" +
                         (measure == Measure::Targets ? " with " + std::to_string(targets) + " targets" : std::string()) +
                         " (" + sizeText(s) + ") " + over,
                     robot};
}

std::optional<std::string> crossValidationSizeProblem(size_t measurements, int joints, Measure measure, int targets,
                                                      int folds, int repeats, int candidates) {
  const IdentificationSize s = identificationSize(static_cast<double>(measurements), joints, 7.0, measure, targets);
  const double fits = 1.0 + static_cast<double>(candidates) * folds * repeats;
  if (fits * s.work() <= kMaxCrossValidationWork) return std::nullopt;
  return io::shortest(fits) + " fits (" + std::to_string(folds) + " folds x " + std::to_string(repeats) +
         " repeats x " + std::to_string(candidates) +
         (candidates == 3 ? " levels" : " candidates") + ", and the full one) of " + sizeText(s) + " exceed the cross-validation work limit (" +
         io::shortest(kMaxCrossValidationWork) + ", about a minute; here " + io::shortest(fits * s.work()) +
         "): fewer repeats or folds, " +
         (candidates > 3 ? std::string("fewer candidates (prior widths, deflections on and off), ") : std::string()) +
         "or fewer measurements";
}

std::optional<std::string> ikWorkProblem(size_t rows, int attempts, int joints, bool seeds_named) {
  const double per_row = static_cast<double>(attempts) * kIkMaxIterations * joints;
  const double work = static_cast<double>(rows) * per_row;
  if (work <= kMaxIkWork) return std::nullopt;
  const auto most = [](double x) { return std::to_string(static_cast<long long>(std::floor(x))); };
  std::string text = (attempts > 1 || seeds_named ? std::to_string(attempts) + " seeds x " : std::string()) +
                     std::to_string(rows) + " rows x " + std::to_string(kIkMaxIterations) + " iterations x " +
                     std::to_string(joints) + " joints = " + io::shortest(work) +
                     " exceed the IK work limit (" + io::shortest(kMaxIkWork) +
                     " joint-iterations: the default 8 seeds at 10^6 rows of a 7-joint robot): at most " +
                     most(kMaxIkWork / per_row) + " rows at " + std::to_string(attempts) +
                     (attempts == 1 ? " attempt" : " seeds");
  if (seeds_named) text += ", or at most " + most(kMaxIkWork / (static_cast<double>(rows) * kIkMaxIterations * joints)) + " seeds for " + std::to_string(rows) + " rows";
  return text;
}

}  // namespace lowpair::commands
