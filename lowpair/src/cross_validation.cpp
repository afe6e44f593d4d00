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

// One held-out measurement's numbers, in the order they were predicted.
struct HeldOut {
  double position = 0.0, rotation = 0.0;  // errors: length, rad
  double u = 0.0;                          // normalized residual (MeasurementResidual::normalized), before the unit
  int rows = 3;
};

// The score (CrossValidationScore) of `held` (non-empty); `unit` and `loss` for Rms.
double scoreOf(const std::vector<HeldOut>& held, CrossValidationScore kind, double unit, const RobustLoss& loss) {
  double sum = 0.0;
  if (kind == CrossValidationScore::Rms) {
    for (const HeldOut& h : held) sum += (h.rows / 3.0) * unit * unit * loss.rho(h.u / unit);
    return std::sqrt(sum / static_cast<double>(held.size()));
  }
  if (kind == CrossValidationScore::Trimmed) {
    std::vector<HeldOut> sorted = held;
    std::sort(sorted.begin(), sorted.end(), [](const HeldOut& a, const HeldOut& b) { return a.u < b.u; });
    const size_t kept = sorted.size() - static_cast<size_t>(kTrimmedFraction * static_cast<double>(sorted.size()));
    for (size_t k = 0; k < kept; ++k) sum += (sorted[k].rows / 3.0) * sorted[k].u * sorted[k].u;
    return std::sqrt(sum / static_cast<double>(kept));
  }
  // |r| sqrt(rows / median chi^2(rows)): the RMS of |r| for Gaussian noise
  std::vector<double> scaled;
  for (const HeldOut& h : held) {
    scaled.push_back(h.u * std::sqrt(h.rows / 3.0) * std::sqrt(h.rows / (h.rows == 6 ? kChiSquareMedian6 : kChiSquareMedian3)));
  }
  std::sort(scaled.begin(), scaled.end());
  const size_t n = scaled.size();
  return n % 2 == 1 ? scaled[n / 2] : 0.5 * (scaled[n / 2 - 1] + scaled[n / 2]);
}

// The partitions' shared inputs: the pose of every measurement, its load (the whole set's), the common unit.
struct Folding {
  const PoeModel* nominal = nullptr;
  const std::vector<Measurement>* measurements = nullptr;
  std::vector<int> pose;
  std::vector<std::vector<int>> partitions;
  int folds = 0;
  double unit = 1.0;
  std::vector<VecX> move_signs;  // of the whole set (empty: no backlash anywhere)
};

// Fits candidate `o` on every fold of every partition and scores the held-out measurements: `c` filled.
void scoreCandidate(const Folding& f, const CalibrationOptions& o, CrossValidationScore kind,
                    CrossValidation::Candidate& c) {
  const std::vector<Measurement>& measurements = *f.measurements;
  CalibrationOptions whole = o;
  whole.move_signs = f.move_signs;
  const std::vector<PoseLoad> loads = measurementLoads(*f.nominal, measurements, whole);
  const RobustLoss loss = RobustLoss::of(o.loss);
  std::vector<HeldOut> all;
  std::vector<double> per_partition;
  for (size_t r = 0; r < f.partitions.size() && !c.failed; ++r) {
    std::vector<HeldOut> held;
    for (int fold = 0; fold < f.folds && !c.failed; ++fold) {
      std::vector<Measurement> train, test;
      std::vector<PoseLoad> test_loads;
      CalibrationOptions fold_options = o;
      fold_options.move_signs.clear();
      for (size_t m = 0; m < measurements.size(); ++m) {
        const bool out = f.partitions[r][static_cast<size_t>(f.pose[m])] == fold;
        (out ? test : train).push_back(measurements[m]);
        if (out && !loads.empty()) test_loads.push_back(loads[m]);
        if (!out && !f.move_signs.empty()) fold_options.move_signs.push_back(f.move_signs[m]);
      }
      try {
        const CalibrationResult fit = calibrate(*f.nominal, train, fold_options);
        c.parameters = fit.error_model.size();
        if (!fit.converged) c.failed = true;
        // each held-out measurement at its deflected joints, its normalized residual with the fit's weights
        const std::vector<Measurement> standing = deflectedMeasurements(test, fit.deflection, test_loads);
        const double wp = fit.sigma_position, wr = fit.sigma_rotation;
        Data data(fit.model);
        for (const Measurement& m : standing) {
          const auto [ep, er] = measurementErrors(predict(fit.model, data, m, o.measure, fit.target_points), m, o.measure);
          const int rows = rowsOf(m, o.measure);  // 6 for a pose, 3 for a point (mixed data mix them)
          held.push_back(HeldOut{ep, er, normalizedResidual(ep * ep / (wp * wp) + er * er / (wr * wr), rows), rows});
        }
      } catch (const std::invalid_argument&) {
        c.failed = true;
      }
    }
    if (!held.empty()) per_partition.push_back(scoreOf(held, kind, f.unit, loss));
    all.insert(all.end(), held.begin(), held.end());
  }
  if (all.empty()) return;
  double sum_p = 0.0, sum_r = 0.0;
  for (const HeldOut& h : all) {
    sum_p += h.position * h.position;
    sum_r += h.rotation * h.rotation;
  }
  c.rms_position = std::sqrt(sum_p / static_cast<double>(all.size()));
  c.rms_rotation = std::sqrt(sum_r / static_cast<double>(all.size()));
  c.score = scoreOf(all, kind, f.unit, loss);
  if (per_partition.size() >= 2) {
    double mean = 0.0, var = 0.0;
    for (const double s : per_partition) mean += s / static_cast<double>(per_partition.size());
    for (const double s : per_partition) var += (s - mean) * (s - mean);
    c.score_sd = std::sqrt(var / static_cast<double>(per_partition.size() - 1));
  }
}

// The candidates of `grid` in its order: level, prior, compliance off/on, backlash off/on.
std::vector<CrossValidation::Candidate> gridCandidates(const CalibrationOptions& options, const CrossValidationGrid& grid) {
  std::vector<CrossValidation::Candidate> out;
  const int priors = grid.priors.empty() ? 1 : static_cast<int>(grid.priors.size());
  const bool compliance = !options.compliance_joints.empty(), backlash = !options.backlash_joints.empty();
  for (const ParameterSet set : grid.levels) {
    for (int p = 0; p < priors; ++p) {
      for (const bool c_on : {false, true}) {
        if (c_on ? !compliance : (compliance && !grid.compliance_off)) continue;
        for (const bool b_on : {false, true}) {
          if (b_on ? !backlash : (backlash && !grid.backlash_off)) continue;
          CrossValidation::Candidate c;
          c.set = set;
          c.prior = grid.priors.empty() ? -1 : p;
          c.compliance = c_on;
          c.backlash = b_on;
          out.push_back(c);
        }
      }
    }
  }
  return out;
}

}  // namespace

int crossValidationPoses(const std::vector<Measurement>& measurements) {
  int poses = measurements.empty() ? 0 : 1;
  for (size_t m = 1; m < measurements.size(); ++m) poses += measurements[m].q == measurements[m - 1].q ? 0 : 1;
  return poses;
}

CalibrationOptions candidateOptions(const CalibrationOptions& options, const CrossValidationGrid& grid,
                                    const CrossValidation::Candidate& c) {
  CalibrationOptions o = options;
  o.parameters = c.set;
  if (c.prior >= 0) o.prior = grid.priors.at(static_cast<size_t>(c.prior));
  if (!c.compliance) o.compliance_joints.clear();
  if (!c.backlash) o.backlash_joints.clear();
  return o;
}

CrossValidation crossValidate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                              const CalibrationOptions& options, int folds, int repeats, const CrossValidationGrid& grid) {
  LP_CHECK(folds >= 2 && folds <= kMaxCrossValidationFolds,
           "crossValidate: " << folds << " folds (2 to " << kMaxCrossValidationFolds << ")");
  LP_CHECK(repeats >= 1 && repeats <= kMaxCrossValidationRepeats,
           "crossValidate: " << repeats << " repeats (1 to " << kMaxCrossValidationRepeats << ")");
  LP_CHECK(!grid.levels.empty(), "crossValidate: no parameter level to compare");
  Folding f;
  f.nominal = &nominal;
  f.measurements = &measurements;
  f.folds = folds;
  // folds over poses: consecutive measurements with the same joint vector (a pose's targets) stay together
  f.pose.assign(measurements.size(), 0);
  for (size_t m = 1; m < measurements.size(); ++m) {
    f.pose[m] = f.pose[m - 1] + (measurements[m].q == measurements[m - 1].q ? 0 : 1);
  }
  const int poses = crossValidationPoses(measurements);
  LP_CHECK(poses >= folds, "crossValidate: " << poses << " poses for " << folds << " folds");
  // distinct partitions only (few poses allow few: as many poses as folds, one)
  for (int r = 0; r < repeats; ++r) {
    std::vector<int> p = foldsOfRepeat(poses, folds, r);
    if (std::find(f.partitions.begin(), f.partitions.end(), p) == f.partitions.end()) f.partitions.push_back(std::move(p));
  }
  // the move signs of the whole set, in its order: a fold's poses keep the sign of the move that reached them
  const std::vector<PoseLoad> loads = measurementLoads(nominal, measurements, options);
  if (!loads.empty() && loads.front().sign.size() > 0) {
    for (const PoseLoad& l : loads) f.move_signs.push_back(l.sign);
  }
  // The noise unit of the scores, one for every candidate: 1 with stated noise; without, under a robust loss,
  // the robust scale of the full level fitted to every measurement (each fold fit's own scale would shrink
  // the held-out errors of the candidates that fit their training poses tightest)
  const bool stated = options.sigma_position.has_value() || options.sigma_rotation.has_value();
  if (!stated && options.loss != Loss::Squared) {
    CalibrationOptions o = options;
    o.parameters = ParameterSet::Full;
    f.unit = calibrate(nominal, measurements, o).robust_scale;
  }
  CrossValidation out;
  out.folds = folds;
  out.repeats = static_cast<int>(f.partitions.size());
  out.score = grid.score;
  out.candidates = gridCandidates(options, grid);
  for (CrossValidation::Candidate& c : out.candidates) scoreCandidate(f, candidateOptions(options, grid, c), grid.score, c);
  int best = -1;
  for (size_t i = 0; i < out.candidates.size(); ++i) {
    const CrossValidation::Candidate& c = out.candidates[i];
    if (c.failed) continue;
    const CrossValidation::Candidate* b = best < 0 ? nullptr : &out.candidates[static_cast<size_t>(best)];
    if (!b || c.score < b->score || (c.score == b->score && c.parameters < b->parameters)) best = static_cast<int>(i);
  }
  LP_CHECK(best >= 0, "crossValidate: no candidate could be fitted on every fold");
  out.chosen_index = best;
  out.chosen = out.candidates[static_cast<size_t>(best)].set;
  return out;
}

}  // namespace lowpair
