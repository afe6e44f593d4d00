// The held-out scores of crossValidate (cross_validation.hpp, docs/calibration.md "Selection by cross-validation"):
// on Gaussian noise the median score equals the RMS score and the trimmed one is the RMS of the kept 90 %; a planted
// held-out blunder moves the RMS score and not the robust ones; a prior grid is scored candidate by candidate.
//
// The numbers: 300 pose measurements of an exact nominal (no geometric error) with 0.1 (length, L 1000) and 1e-4 rad
// of stated noise: |r|^2 of a held-out pose is chi^2 with 6 dof (plus the fold fit's small prediction error, the
// same for every score). Sampled 5000 times (numpy), median/RMS is 1.000 +- 0.014 and trimmed/RMS 0.930 +- 0.005 for
// 300 such values: the tolerances 0.07 and 0.025 are 5 of those sd. A wrong factor (the median without
// sqrt(rows / median chi^2): 0.94x; of u instead of |r|: 0.71x) or a trimmed score dropping nothing (1.0x) fails;
// measured here 0.995 and 0.928.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "calibration_helpers.hpp"
#include "lowpair/calibration.hpp"

namespace {

using namespace lowpair;
using namespace calibration_helpers;

struct NoisyArm {
  PoeModel nominal;
  std::vector<Measurement> measurements;
  CalibrationOptions options;
};

NoisyArm noisyArm(std::mt19937_64& rng) {
  NoisyArm a{jointMix("RRRRRR", 1000.0, rng), {}, {}};
  a.measurements = measure(a.nominal, uniformPoses(a.nominal, 300, rng));
  addNoise(a.measurements, 0.1, 1e-4, rng);
  a.options.sigma_position = 0.1;
  a.options.sigma_rotation = 1e-4;
  return a;
}

double scoreOf(const NoisyArm& a, const std::vector<Measurement>& ms, CrossValidationScore score) {
  CrossValidationGrid grid;
  grid.levels = {ParameterSet::Offsets};
  grid.score = score;
  const CrossValidation cv = crossValidate(a.nominal, ms, a.options, 5, 1, grid);
  EXPECT_EQ(cv.candidates.size(), 1u);
  EXPECT_FALSE(cv.candidates[0].failed);
  return cv.candidates[0].score;
}

TEST(CrossValidationScore, MedianEqualsRmsAndTrimmedDropsTheTailOnGaussianNoise) {
  std::mt19937_64 rng(31);
  const NoisyArm a = noisyArm(rng);
  const double rms = scoreOf(a, a.measurements, CrossValidationScore::Rms);
  const double trimmed = scoreOf(a, a.measurements, CrossValidationScore::Trimmed);
  const double median = scoreOf(a, a.measurements, CrossValidationScore::Median);
  std::printf("rms %.4f, trimmed %.4f (%.4f), median %.4f (%.4f)\n", rms, trimmed, trimmed / rms, median, median / rms);
  // sqrt(6) for chi^2 with 6 dof, a few % more for the fold fits' prediction error (20 parameters on 240 poses)
  EXPECT_GT(rms, std::sqrt(6.0));
  EXPECT_LT(rms, 1.1 * std::sqrt(6.0));
  EXPECT_NEAR(median / rms, 1.0, 0.07);
  EXPECT_NEAR(trimmed / rms, 0.930, 0.025);
}

// One measurement moved by 1000 sigma: held out once, it adds 1000^2 x 3 / 300 to the mean of |r|^2 (RMS x 40); the
// trimmed score drops it and the median does not see it (each moves by at most the weight of one value of 300, far
// inside the tolerance of 5 %; the fold fits it trains under least squares move too, and that is not the score's).
TEST(CrossValidationScore, AHeldOutBlunderMovesRmsNotTheRobustScores) {
  std::mt19937_64 rng(32);
  const NoisyArm a = noisyArm(rng);
  std::vector<Measurement> blundered = a.measurements;
  blundered[150].T_base_tool.p.x() += 1000.0 * 0.1;
  CalibrationOptions huber = a.options;  // the fits weigh the blunder down where it is trained on
  huber.loss = Loss::Huber;
  NoisyArm b{a.nominal, blundered, huber};
  NoisyArm c{a.nominal, a.measurements, huber};
  const double rms_ratio = scoreOf(b, blundered, CrossValidationScore::Rms) / scoreOf(c, a.measurements, CrossValidationScore::Rms);
  const double trimmed_ratio =
      scoreOf(b, blundered, CrossValidationScore::Trimmed) / scoreOf(c, a.measurements, CrossValidationScore::Trimmed);
  const double median_ratio =
      scoreOf(b, blundered, CrossValidationScore::Median) / scoreOf(c, a.measurements, CrossValidationScore::Median);
  std::printf("blunder / clean: rms %.3f, trimmed %.3f, median %.3f\n", rms_ratio, trimmed_ratio, median_ratio);
  EXPECT_GT(rms_ratio, 1.5);  // Huber's rho, linear beyond its threshold: 2 s u / 300 with u = 1000
  EXPECT_NEAR(trimmed_ratio, 1.0, 0.05);
  EXPECT_NEAR(median_ratio, 1.0, 0.05);
}

}  // namespace
