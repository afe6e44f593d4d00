// The size limits of an identification (limits.hpp).
#include "commands/limits.hpp"

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

// "" when within both limits, else which is exceeded
std::string overLimit(const IdentificationSize& s) {
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

}  // namespace

std::optional<SizeProblem> identifiabilitySizeProblem(int poses, int joints, Measure measure, int targets) {
  // the full error model: 8 columns per joint + pitches; one pose of k targets is k point measurements
  const double per_pose = measure == Measure::Targets ? targets : 1.0;
  const IdentificationSize s = identificationSize(poses * per_pose, joints, 9.0, measure, targets);
  const std::string over = overLimit(s);
  if (over.empty()) return std::nullopt;
  const bool robot = !overLimit(identificationSize(per_pose, joints, 9.0, measure, targets)).empty();
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

}  // namespace lowpair::commands
