#include "lowpair/cross_validation.hpp"
#include "calibration_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "check.hpp"
#include "lowpair/kinematics.hpp"

namespace lowpair {

using namespace detail;

namespace {

// Pose p of repeat r goes to fold partition[p]: repeat 0 deals the poses in order (pose i to fold i % k),
// later repeats deal a shuffle of them (Fisher-Yates on mt19937_64 seeded with r, whose output the
// standard fixes: the same data give the same folds everywhere). The folds are numbered in the order of
// their first pose, so two partitions into the same sets compare equal.
std::vector<int> foldsOfRepeat(int poses, int folds, int repeat) {
  std::vector<int> order(static_cast<size_t>(poses));
  for (int p = 0; p < poses; ++p) order[static_cast<size_t>(p)] = p;
  if (repeat > 0) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(repeat));
    for (int i = poses - 1; i > 0; --i) {
      std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(rng() % static_cast<std::uint64_t>(i + 1))]);
    }
  }
  std::vector<int> dealt(static_cast<size_t>(poses)), fold(static_cast<size_t>(poses)), label(static_cast<size_t>(folds), -1);
  for (int i = 0; i < poses; ++i) dealt[static_cast<size_t>(order[static_cast<size_t>(i)])] = i % folds;
  int next = 0;
  for (int p = 0; p < poses; ++p) {
    int& l = label[static_cast<size_t>(dealt[static_cast<size_t>(p)])];
    if (l < 0) l = next++;
    fold[static_cast<size_t>(p)] = l;
  }
  return fold;
}

}  // namespace

int crossValidationPoses(const std::vector<Measurement>& measurements) {
  int poses = measurements.empty() ? 0 : 1;
  for (size_t m = 1; m < measurements.size(); ++m) poses += measurements[m].q == measurements[m - 1].q ? 0 : 1;
  return poses;
}

CrossValidation crossValidate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                              const CalibrationOptions& options, int folds, int repeats) {
  LP_CHECK(folds >= 2 && folds <= kMaxCrossValidationFolds,
           "crossValidate: " << folds << " folds (2 to " << kMaxCrossValidationFolds << ")");
  LP_CHECK(repeats >= 1 && repeats <= kMaxCrossValidationRepeats,
           "crossValidate: " << repeats << " repeats (1 to " << kMaxCrossValidationRepeats << ")");
  // (a held-out prediction would need the fold's deflections and each pose's load and sign: not done)
  LP_CHECK(!options.deflects(), "crossValidate: joint deflections (compliance, backlash) are not cross-validated");
  // folds over poses: consecutive measurements with the same joint vector (a pose's targets) stay together
  std::vector<int> pose(measurements.size(), 0);
  for (size_t m = 1; m < measurements.size(); ++m) {
    pose[m] = pose[m - 1] + (measurements[m].q == measurements[m - 1].q ? 0 : 1);
  }
  const int poses = crossValidationPoses(measurements);
  LP_CHECK(poses >= folds, "crossValidate: " << poses << " poses for " << folds << " folds");
  // distinct partitions only (few poses allow few: as many poses as folds, one)
  std::vector<std::vector<int>> partitions;
  for (int r = 0; r < repeats; ++r) {
    std::vector<int> p = foldsOfRepeat(poses, folds, r);
    if (std::find(partitions.begin(), partitions.end(), p) == partitions.end()) partitions.push_back(std::move(p));
  }
  // The noise unit of the scores, one for every level: 1 with stated noise; without, under a robust loss,
  // the robust scale of the full level fitted to every measurement (each fold fit's own scale would shrink
  // the held-out errors of the levels that fit their training poses tightest)
  double unit = 1.0;
  const bool stated = options.sigma_position.has_value() || options.sigma_rotation.has_value();
  if (!stated && options.loss != Loss::Squared) {
    CalibrationOptions o = options;
    o.parameters = ParameterSet::Full;
    unit = calibrate(nominal, measurements, o).robust_scale;
  }
  const RobustLoss loss = RobustLoss::of(options.loss);
  CrossValidation out;
  out.folds = folds;
  out.repeats = static_cast<int>(partitions.size());
  for (const ParameterSet set : {ParameterSet::Full, ParameterSet::Lines, ParameterSet::Offsets}) {
    CrossValidation::Candidate c;
    c.set = set;
    CalibrationOptions o = options;
    o.parameters = set;
    double sum_p = 0.0, sum_r = 0.0, score = 0.0;
    int held = 0;
    for (size_t r = 0; r < partitions.size() && !c.failed; ++r) {
      for (int f = 0; f < folds && !c.failed; ++f) {
        std::vector<Measurement> train, test;
        for (size_t m = 0; m < measurements.size(); ++m) {
          (partitions[r][static_cast<size_t>(pose[m])] == f ? test : train).push_back(measurements[m]);
        }
        try {
          const CalibrationResult fit = calibrate(nominal, train, o);
          c.parameters = fit.error_model.size();
          if (!fit.converged) c.failed = true;
          // each held-out measurement's normalized residual (the fit's weights, over the common unit) scored
          // by the fit's loss: least squares sums |r|^2, a robust loss does not let a held-out blunder decide
          const double wp = fit.sigma_position, wr = fit.sigma_rotation;
          Data data(fit.model);
          for (const Measurement& m : test) {
            const auto [ep, er] = measurementErrors(predict(fit.model, data, m, o.measure, fit.target_points), m, o.measure);
            sum_p += ep * ep;
            sum_r += er * er;
            const int rows = rowsOf(m, o.measure);  // 6 for a pose, 3 for a point (mixed data mixes them)
            const double u = normalizedResidual(ep * ep / (wp * wp) + er * er / (wr * wr), rows) / unit;
            score += (rows / 3.0) * unit * unit * loss.rho(u);
            ++held;
          }
        } catch (const std::invalid_argument&) {
          c.failed = true;
        }
      }
    }
    if (held > 0) {
      c.rms_position = std::sqrt(sum_p / held);
      c.rms_rotation = std::sqrt(sum_r / held);
      c.score = std::sqrt(score / held);
    }
    out.candidates.push_back(c);
  }
  const CrossValidation::Candidate* best = nullptr;
  for (const auto& c : out.candidates) {
    if (c.failed) continue;
    if (!best || c.score < best->score || (c.score == best->score && c.parameters < best->parameters)) {
      best = &c;
    }
  }
  LP_CHECK(best, "crossValidate: no parameter level could be fitted on every fold");
  out.chosen = best->set;
  return out;
}

}  // namespace lowpair
