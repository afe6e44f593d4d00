// The prior on the nominal (calibrate.hpp ParameterPrior; docs/calibration.md "A prior on the nominal"): the MAP
// estimate against the closed form of the augmented linear problem, its limits (huge widths: the fit without; tiny
// widths: the nominal), the effective number of parameters against the trace of the hat matrix by finite differences
// of fitted values, and a parameter the data leave undetermined held by the prior.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "calibration_helpers.hpp"

using namespace lowpair;
using namespace calibration_helpers;

namespace {

// A 6R arm of size 1 with generic lines and tool (jointMix), a true robot a = 1e-3 away, noisy poses.
struct Case {
  PoeModel nominal, actual;
  std::vector<Measurement> measurements;
  double sp = 1e-5, sr = 1e-5;
};

Case noisyCase(unsigned seed, int poses, double a, Measure kind = Measure::Pose) {
  std::mt19937_64 rng(seed);
  const PoeModel nominal = jointMix("RRRRRR", 1.0, rng);
  const ErrorModel em(nominal);
  Case c{nominal, em.apply(smallDelta(em, a, false, rng)), {}};
  c.measurements = measure(c.actual, uniformPoses(nominal, poses, rng));
  addNoise(c.measurements, c.sp, kind == Measure::Pose ? c.sr : 0.0, rng);
  return c;
}

CalibrationOptions stated(const Case& c, Measure measure = Measure::Pose) {
  CalibrationOptions o;
  o.measure = measure;
  o.sigma_position = c.sp;
  if (measure == Measure::Pose) o.sigma_rotation = c.sr;
  return o;
}

// The weighted residual of `model` at the measurements ([log(R_m R^T) / sr; (p_m - p) / sp] per pose), as the
// library defines it (calibrate.hpp), written out here from forward kinematics.
VecX weightedResidual(const PoeModel& model, const std::vector<Measurement>& ms, double sp, double sr) {
  VecX r(6 * static_cast<Eigen::Index>(ms.size()));
  for (size_t k = 0; k < ms.size(); ++k) {
    const Pose T = poeForwardKinematics(model, ms[k].q);
    r.segment<3>(6 * static_cast<Eigen::Index>(k)) = logSO3(ms[k].T_base_tool.R * T.R.transpose()) / sr;
    r.segment<3>(6 * static_cast<Eigen::Index>(k) + 3) = (ms[k].T_base_tool.p - T.p) / sp;
  }
  return r;
}

}  // namespace

// Widths of 1e12 (rad, length units, scale) add 1e-24 to normal equations whose diagonal is ~1/sigma^2 = 1e10: the
// fit is the fit without a prior to rounding. What separates the two runs is the iteration: with a prior an iterate is
// the registered nominal moved by the estimate (calibrate.cpp), without one the composition of the steps, so the
// estimates (sums of steps) differ at second order, |x|^2 ~ (a few 1e-3)^2 in these unit-size coordinates, while the
// models agree: their predictions at the measured poses to 1e-6 of the noise (the iteration's convergence), the
// standard deviations and the variance factor to 1e-6 relative; the effective count is the rank to 1e-9.
TEST(CalibrationPrior, HugeWidthsGiveTheFitWithout) {
  const Case c = noisyCase(11, 40, 1e-3);
  const CalibrationResult plain = calibrate(c.nominal, c.measurements, stated(c));
  CalibrationOptions o = stated(c);
  o.prior = ParameterPrior{1e12, 1e12, 1e12, 1e12};
  const CalibrationResult wide = calibrate(c.nominal, c.measurements, o);
  ASSERT_TRUE(plain.accepted) << plain.reason;
  ASSERT_TRUE(wide.accepted) << wide.reason;
  EXPECT_EQ(plain.effective_parameters, plain.rank.rank);  // without a prior: the rank, exactly
  EXPECT_NEAR(wide.effective_parameters, plain.rank.rank, 1e-9);
  EXPECT_EQ(wide.rank.rank, plain.rank.rank);
  EXPECT_TRUE(wide.held_by_prior.empty());
  double worst = 0.0;
  for (const Measurement& m : c.measurements) {
    worst = std::max(worst, (poeForwardKinematics(wide.model, m.q).p - poeForwardKinematics(plain.model, m.q).p).norm() / c.sp);
  }
  const double x = plain.estimate.norm();
  EXPECT_LE((wide.estimate - plain.estimate).norm(), x * x);
  for (Eigen::Index k = 0; k < plain.estimate.size(); ++k) {
    EXPECT_NEAR(wide.standard_deviation[k], plain.standard_deviation[k], 1e-6 * plain.standard_deviation[k]) << k;
  }
  std::printf("huge widths: predictions within %.3g sigma_p of the fit without; estimates %.3g apart (|x|^2 = %.3g); "
              "effective %.12g, rank %d\n", worst, (wide.estimate - plain.estimate).norm(), x * x,
              wide.effective_parameters, plain.rank.rank);
  EXPECT_LE(worst, 1e-6);
  EXPECT_NEAR(wide.variance_factor, plain.variance_factor, 1e-6 * plain.variance_factor);
}

// Widths of 1e-12 on every kind with the offsets level: the base (the measurement frame, 6 parameters) stays free and
// everything else is held at the nominal. The fit only decreases the MAP cost from the registered nominal (estimate 0),
// so |delta_j / width_j|^2 <= cost at the start: |delta_j| <= width_j sqrt(cost_0). The effective count is the base's
// 6 plus sum over held parameters of s^2 / (s^2 + 1/width^2) ~ (1e-12 * 1e5)^2 each: 6 to 1e-9.
TEST(CalibrationPrior, TinyWidthsKeepTheNominal) {
  const Case c = noisyCase(12, 30, 1e-3);
  CalibrationOptions o = stated(c);
  o.parameters = ParameterSet::Offsets;
  o.prior = ParameterPrior{1e-12, 1e-12, 1e-12, 1e-12};
  const CalibrationResult r = calibrate(c.nominal, c.measurements, o);
  const double cost0 = static_cast<double>(6 * c.measurements.size()) * (r.before.rms_position * r.before.rms_position) /
                       (c.sp * c.sp);  // |r_0|^2 >= this: the position rows alone
  int free = 0;
  const auto& parameters = r.error_model.parameters();
  for (size_t j = 0; j < parameters.size(); ++j) {
    const bool base = parameters[j].kind == ParameterKind::BaseRotation || parameters[j].kind == ParameterKind::BaseTranslation;
    free += base ? 1 : 0;
    if (!base) {
      // the bound with the whole start cost (position and rotation rows): 1e-12 sqrt(cost0 + rotation rows)
      EXPECT_LE(std::abs(r.estimate[static_cast<Eigen::Index>(j)]), 1e-12 * std::sqrt(4.0 * cost0)) << parameters[j].name;
    }
  }
  ASSERT_EQ(free, 6);
  std::printf("tiny widths: effective %.12g (free %d of %d); RMS before %.3g after %.3g\n", r.effective_parameters, free,
              r.error_model.size(), r.before.rms_position, r.after.rms_position);
  EXPECT_NEAR(r.effective_parameters, free, 1e-9);
  // the same data without the prior move the offsets: the test can fail
  CalibrationOptions without = o;
  without.prior = {};
  const CalibrationResult plain = calibrate(c.nominal, c.measurements, without);
  EXPECT_GT(plain.estimate.cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_LT(plain.after.rms_position, 0.95 * r.after.rms_position);
}

// On a nearly linear case (an error of 1e-7 with noise 1e-8: the second-order terms are ~1e-7 of the first), the MAP
// estimate is the closed form x = (J^T J + P)^-1 J^T r0 of the augmented linear problem, J here by central differences
// of the weighted residual written out from forward kinematics (h = 1e-6: error ~h^2), r0 at the nominal, no
// registration (the measurements in the model's base frame). Widths are set near the data's own precision, so the
// prior moves the estimate by a large fraction of it (checked: the unregularized closed form differs).
TEST(CalibrationPrior, MapEstimateIsTheAugmentedClosedForm) {
  std::mt19937_64 rng(13);
  const PoeModel nominal = jointMix("RRRRRR", 1.0, rng);
  const ErrorModel em(nominal);
  const PoeModel actual = em.apply(smallDelta(em, 1e-7, false, rng));
  std::vector<Measurement> ms = measure(actual, uniformPoses(nominal, 12, rng));
  const double sp = 1e-8, sr = 1e-8;
  addNoise(ms, sp, sr, rng);
  CalibrationOptions o;
  o.sigma_position = sp;
  o.sigma_rotation = sr;
  o.register_frame = false;
  o.prior = ParameterPrior{3e-8, 2e-8, 5e-8, 1e-7};
  const CalibrationResult r = calibrate(nominal, ms, o);
  ASSERT_TRUE(r.converged);
  const Eigen::Index n = em.size();
  const VecX r0 = weightedResidual(nominal, ms, sp, sr);
  MatX J(r0.size(), n);
  VecX P(n);
  const double h = 1e-6;
  for (Eigen::Index k = 0; k < n; ++k) {
    VecX d = VecX::Zero(n);
    d[k] = h;
    // r = measured - predicted: J = d(predicted)/dx = -(dr/dx)
    J.col(k) = -(weightedResidual(em.apply(d), ms, sp, sr) - weightedResidual(em.apply(-d), ms, sp, sr)) / (2 * h);
    const Parameter& p = em.parameters()[static_cast<size_t>(k)];
    P[k] = 1.0 / std::pow(o.prior.width(p.kind, p.unit), 2);
  }
  const MatX N = J.transpose() * J;
  const VecX map = (N + MatX(P.asDiagonal())).ldlt().solve(J.transpose() * r0);
  const VecX least_squares = N.ldlt().solve(J.transpose() * r0);
  const double diff = (r.estimate - map).norm() / map.norm();
  std::printf("closed form: |MAP - closed form| / |closed form| = %.3g; |least squares - MAP| / |MAP| = %.3g\n", diff,
              (least_squares - map).norm() / map.norm());
  EXPECT_LE(diff, 1e-4);
  EXPECT_GE((least_squares - map).norm(), 0.1 * map.norm());  // the prior matters here
  // the covariance is (J^T J + P)^-1
  const MatX cov = (N + MatX(P.asDiagonal())).inverse();
  for (Eigen::Index k = 0; k < n; ++k) EXPECT_NEAR(r.standard_deviation[k], std::sqrt(cov(k, k)), 1e-4 * std::sqrt(cov(k, k)));
}

// The effective number of parameters is the trace of the hat matrix, d(fitted)/d(measured) summed over the residual
// rows: each measured coordinate moved by +-e noise units (central differences: the quadratic terms cancel), the fit
// redone, the fitted value's change over 2e. Position rows: the predicted position; rotation rows: the predicted
// rotation's change in the base frame. The fits converge to ~1e-8 noise units; over e = 0.1 and 60 rows the sum is
// good to ~1e-4: tolerance 1e-3. Widths near the data's precision put the count strictly between 0 and the rank.
TEST(CalibrationPrior, EffectiveCountIsTheTraceOfTheHatMatrix) {
  std::mt19937_64 rng(14);
  const PoeModel nominal = jointMix("RRRRRR", 1.0, rng);
  const ErrorModel em(nominal);
  const PoeModel actual = em.apply(smallDelta(em, 1e-4, false, rng));
  std::vector<Measurement> ms = measure(actual, uniformPoses(nominal, 10, rng));
  const double sp = 1e-5, sr = 1e-5;
  addNoise(ms, sp, sr, rng);
  CalibrationOptions o;
  o.sigma_position = sp;
  o.sigma_rotation = sr;
  o.register_frame = false;
  o.prior = ParameterPrior{2e-5, 2e-5, 2e-5, 2e-5};
  const CalibrationResult r = calibrate(nominal, ms, o);
  ASSERT_TRUE(r.converged) << r.iterations << " iterations, variance factor " << r.variance_factor;
  const double e = 0.1;
  double trace = 0.0;
  for (size_t k = 0; k < ms.size(); ++k) {
    for (int row = 0; row < 6; ++row) {
      Pose fitted[2];
      for (int side = 0; side < 2; ++side) {
        std::vector<Measurement> moved = ms;
        const double s = side == 0 ? e : -e;
        Vec3 unit = Vec3::Zero();
        unit[row % 3] = 1.0;
        if (row < 3) {
          moved[k].T_base_tool.R = expSO3(s * sr * unit) * moved[k].T_base_tool.R;
        } else {
          moved[k].T_base_tool.p += s * sp * unit;
        }
        fitted[side] = poeForwardKinematics(calibrate(nominal, moved, o).model, ms[k].q);
      }
      const double change = row < 3 ? logSO3(fitted[0].R * fitted[1].R.transpose())[row] / sr
                                    : (fitted[0].p - fitted[1].p)[row - 3] / sp;
      trace += change / (2 * e);
    }
  }
  std::printf("effective parameters %.9g, trace of the hat matrix by differences %.9g (rank %d)\n",
              r.effective_parameters, trace, r.rank.rank);
  EXPECT_NEAR(r.effective_parameters, trace, 1e-3);
  EXPECT_LT(r.effective_parameters, r.rank.rank - 1.0);
  EXPECT_GT(r.effective_parameters, 1.0);
}

// Position measurements do not determine the tool's rotation (its columns are 0 in position rows: calibration_test's
// PositionOnlyLeavesOnlyTheToolRotationUndetermined). A tilt prior holds it: the data's rank still says 3 directions
// are undetermined, held_by_prior names tool.rx, ry, rz, their estimate stays 0 (the prior's mean: the data do not
// move them) and their standard deviation is the prior's width (the data add nothing), to rounding.
TEST(CalibrationPrior, HoldsWhatTheDataLeaveUndetermined) {
  const Case c = noisyCase(15, 40, 1e-3, Measure::Position);
  ASSERT_EQ(positionOnlyLoss(c.nominal), 0);
  CalibrationOptions o = stated(c, Measure::Position);
  const CalibrationResult plain = calibrate(c.nominal, c.measurements, o);
  o.prior = ParameterPrior{1e-3, 1e-3, 1e-3, 1e-2};
  const CalibrationResult r = calibrate(c.nominal, c.measurements, o);
  ASSERT_EQ(plain.rank.rank, r.error_model.size() - 3);
  EXPECT_EQ(r.rank.rank, plain.rank.rank);  // the data's rank, as without the prior
  EXPECT_EQ(plain.undetermined_directions.cols(), 3);
  EXPECT_EQ(r.undetermined_directions.cols(), 0);  // neither data nor prior: none left
  std::vector<std::string> held;
  for (const int j : r.held_by_prior) held.push_back(r.error_model.parameters()[static_cast<size_t>(j)].name);
  EXPECT_EQ(held, (std::vector<std::string>{"tool.rx", "tool.ry", "tool.rz"}));
  for (const int j : r.held_by_prior) {
    EXPECT_FALSE(std::isfinite(plain.standard_deviation[j]));
    EXPECT_NEAR(r.standard_deviation[j], 1e-3, 1e-9);
    EXPECT_LE(std::abs(r.estimate[j]), 1e-12);
  }
  EXPECT_TRUE(r.accepted) << r.reason;
}

TEST(CalibrationPrior, RefusesWidthsNotPositive) {
  const Case c = noisyCase(16, 20, 1e-3);
  for (const double bad : {0.0, -1.0, std::nan("")}) {
    CalibrationOptions o = stated(c);
    o.prior.shift = bad;
    EXPECT_THROW(calibrate(c.nominal, c.measurements, o), std::invalid_argument) << bad;
  }
}
