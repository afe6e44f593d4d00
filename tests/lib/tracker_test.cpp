// Calibration with a laser tracker's data (docs/calibration.md "Tracker data"): any measurement frame,
// several targets (SMRs) per pose at unknown points, blunders and robust losses, the verdict, parameter
// levels and their cross-validated choice. The frame used throughout is the issue's: 120 deg about
// (1, 1, 1) and 2.5 m away (in the robot's length unit: 2500 for a robot in mm).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "calibration_helpers.hpp"
#include "cross_validation_arms.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

using namespace lowpair;
using namespace calibration_helpers;

namespace {

// The tracker's frame relative to the robot's base: 120 deg about (1, 1, 1), moved (2.5, -1.2, 0.3) m.
Pose trackerFrame(double metre) {
  return Pose{expSO3(Vec3(1, 1, 1).normalized() * (2.0 * M_PI / 3.0)), metre * Vec3(2.5, -1.2, 0.3)};
}

std::vector<Measurement> inFrame(std::vector<Measurement> ms, const Pose& T_frame_base) {
  for (Measurement& m : ms) m.T_base_tool = T_frame_base * m.T_base_tool;
  return ms;
}

// Points measured on targets fixed in the tool frame: one row per pose and target.
std::vector<Measurement> measureTargets(const PoeModel& truth, const std::vector<VecX>& qs,
                                        const std::vector<Vec3>& points) {
  std::vector<Measurement> out;
  for (const VecX& q : qs) {
    const Pose T = poeForwardKinematics(truth, q);
    for (size_t t = 0; t < points.size(); ++t) {
      out.push_back(Measurement{q, Pose{Mat3::Identity(), T.R * points[t] + T.p}, static_cast<int>(t)});
    }
  }
  return out;
}

void addPositionNoise(std::vector<Measurement>& ms, double sp, std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  for (Measurement& m : ms) m.T_base_tool.p += sp * lowpair_test::draw3(n, rng);
}


// The D-H numbers that do not depend on where the measurement frame is: rows 2..n (theta, d, alpha, a,
// pitch, scale), alpha and a of row 1 (joint 1 to joint 2), and the tool's theta and d.
std::vector<double> frameFreeDh(const PoeModel& model) {
  const DhModel dh = poeToDh(model).model;
  std::vector<double> out;
  for (int i = 0; i < dh.dof(); ++i) {
    const DhJoint& j = dh.joint(i);
    if (i > 0) {
      out.push_back(j.link.theta);
      out.push_back(j.link.d);
    }
    out.push_back(j.link.alpha);
    out.push_back(j.link.a);
    out.push_back(j.scale);
    out.push_back(j.type == JointType::Helical ? j.pitch : 0.0);
  }
  out.push_back(dh.toolTheta());
  out.push_back(dh.toolD());
  return out;
}

}  // namespace

// ---- the error model's new columns ----------------------------------------------------------------------
//
// Offsets, the base (whole-model motion) and targets' points: each column against central differences of
// the measured quantity, as the minimal parameters are in identifiability_test. Step h = cbrt(eps) in the
// parameter's scaled unit; the truncation error is O(h^2) of the second derivative (of order S / unit^2),
// the rounding O(eps S / h): both below 1e-8 S relative to a column of size S, asserted at 1e-7.
TEST(TrackerErrorModel, OffsetBaseAndTargetColumnsMatchCentralDifferences) {
  std::mt19937_64 rng(7);
  Failures failures;
  for (const std::string types : {"RRRRRR", "RPHRRH", "PRRHP"}) {
    const PoeModel model = jointMix(types, 300.0, rng);
    const double L = model.lengthScale();
    const std::vector<Vec3> points = {Vec3(0.1, 0.2, -0.1) * L, Vec3(-0.15, 0.05, 0.2) * L};
    for (const ParameterSet set : {ParameterSet::Full, ParameterSet::Lines, ParameterSet::Offsets}) {
      ErrorModelSpec spec;
      spec.set = set;
      for (const Vec3& p : points) spec.targets.push_back(Target{"", p});
      const ErrorModel em(model, spec);
      const VecX q = uniformJoints(model, rng);
      for (int t = 0; t < 2; ++t) {
        MatX J(3, em.size());
        em.jacobian(q, Measure::Targets, J, t);
        for (int k = 0; k < em.size(); ++k) {
          const Parameter& p = em.parameters()[static_cast<size_t>(k)];
          const double unit = p.unit == "length" || p.unit == "length/rad" ? L : 1.0;
          const double h = std::cbrt(kEpsilon) * unit;
          VecX d = VecX::Zero(em.size());
          d[k] = h;
          auto point = [&](const VecX& delta) {
            const Pose T = poeForwardKinematics(em.apply(delta), q);
            return Vec3(T.R * em.applyTargetPoints(delta)[static_cast<size_t>(t)] + T.p);
          };
          const Vec3 numeric = (point(d) - point(-d)) / (2.0 * h);
          const double S = distanceScale(model, q, poeForwardKinematics(model, q));
          if (!((numeric - J.col(k)).norm() * unit <= 1e-7 * S)) {
            failures.add(types + " " + parameterSetName(set) + " " + p.name +
                         format(": column off by %.3g S", (numeric - J.col(k)).norm() * unit / S));
          }
        }
      }
    }
  }
  EXPECT_EQ(failures.count, 0);
}

// k targets at generic points: the rank is the count 5h + 4r + 2t + n + 3k (the tool frame is not a
// parameter: the targets' points are), on random robots of every joint type with 1-4 targets.
TEST(TrackerIdentifiability, RankWithTargetsEqualsCount) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Failures failures;
  int analyses = 0;
  for (const std::string types : {"RRRRRR", "RRPRRR", "HRPHRR", "PRRRR", "HHHHPP", "RPPR", "RRRRRRR"}) {
    for (int k = 1; k <= 4; ++k) {
      const PoeModel model = jointMix(types, std::pow(10.0, u(rng) * 2.0), rng);
      const double L = model.lengthScale();
      std::vector<Target> targets;
      for (int t = 0; t < k; ++t) targets.push_back(Target{"", Vec3(0.2 * L * lowpair_test::draw3(u, rng))});
      const Identifiability id = analyzeIdentifiability(model, uniformPoses(model, 40, rng), Measure::Targets, ErrorModelSpec{false, ParameterSet::Full, {}, targets});
      ++analyses;
      const int expected = identifiableCount(model, Measure::Pose).total() - 6 + 3 * k;
      if (id.expected.total() != expected) failures.add(types + ": count " + std::to_string(id.expected.total()));
      if (id.poe.rank != expected || id.poe.columns != expected) {
        failures.add(types + " with " + std::to_string(k) + " targets: rank " + std::to_string(id.poe.rank) + " of " +
                     std::to_string(id.poe.columns) + ", count " + std::to_string(expected));
      }
      if (id.full_model_rank != expected) failures.add(types + ": full model rank " + std::to_string(id.full_model_rank));
    }
  }
  std::printf("%d analyses with 1-4 targets\n", analyses);
  EXPECT_EQ(failures.count, 0);
}

// ---- the measurement frame -----------------------------------------------------------------------------

// The same data, in the base frame and in the tracker's (120 deg, 2.5 m away): the frame-free numbers
// agree and the held-out RMS is within 10 % (here: equal to a small fraction of the noise). Tolerance of
// the agreement (robots of every joint type, predictions compared in one frame): both fits stop when an undamped step gains less than 1e-10 of the cost, so their
// parameters differ by at most ~sqrt(1e-10) of the noise-level spread; predictions are compared at 1e-3
// of the noise, D-H numbers at 1e-3 of their standard deviations' scale (noise / L rad, noise length).
TEST(TrackerFrame, SameDataInAFarFrameCalibratesTheSame) {
  std::mt19937_64 rng(120);
  Failures failures;
  struct Case {
    PoeModel nominal;
    double metre;  // the length unit's metre
    Measure measure;
  };
  // (position only: a tool point off the wrist axes, so that the rank is full; with a rank below the count the
  // undetermined directions stay where the registration put them, in a basis that follows the frame's axes)
  const PoeModel puma = pumaLike(0.0, true);
  const PoeModel puma_off_wrist(puma.joints(), puma.toolPose() * Pose{Mat3::Identity(), Vec3(30, -20, 40)}, "puma-like");
  std::vector<Case> cases = {{puma, 1000.0, Measure::Pose}, {puma_off_wrist, 1000.0, Measure::Position}};
  for (const std::string types : {"RRRRRR", "RPHRRH", "HRPHRR", "PRRRR", "RRPRRR"}) {
    cases.push_back({jointMix(types, 0.5, rng), 1.0, Measure::Pose});
  }
  cases.push_back({jointMix("RHRPRR", 0.5, rng), 1.0, Measure::Position});
  for (const Case& c : cases) {
    const PoeModel& nominal = c.nominal;
    const double L = nominal.lengthScale();
    const ErrorModel em(nominal);
    const PoeModel actual = em.apply(smallDelta(em, 1e-3, false, rng));
    const double sp = 1e-5 * L, sr = 1e-5;
    std::vector<Measurement> base = measure(actual, uniformPoses(nominal, 50, rng));
    addNoise(base, sp, c.measure == Measure::Pose ? sr : 0.0, rng);
    const Pose F = trackerFrame(c.metre);
    const std::vector<Measurement> far = inFrame(base, F);
    CalibrationOptions options;
    options.measure = c.measure;
    options.sigma_position = sp;
    if (c.measure == Measure::Pose) options.sigma_rotation = sr;
    const CalibrationResult a = calibrate(nominal, base, options), b = calibrate(nominal, far, options);
    const std::string where = nominal.name() + " (" + measureName(c.measure) + ")";
    if (!a.accepted || !b.accepted) failures.add(where + ": not accepted: " + a.reason + " / " + b.reason);
    // the registration found the frame (to the size of the robot's errors, 1e-3)
    const Pose found = b.registration.T_meas_base;
    if (!(rotationAngle(found.R.transpose() * F.R) < 1e-2 && (found.p - F.p).norm() < 1e-2 * c.metre + 10 * L * 1e-2)) {
      failures.add(where + ": registration far from the frame");
    }
    const std::vector<VecX> check = uniformPoses(nominal, 100, rng);
    const double rms_a = heldOutRms(a.model, {}, actual, {}, check);
    const double rms_b = heldOutRms(movedModel(b.model, F.inverse()), {}, actual, {}, check);
    const double apart = heldOutRms(movedModel(b.model, F.inverse()), {}, a.model, {}, check);
    std::printf("%s: held-out RMS %.3g (base frame) %.3g (far frame) of L; fits apart %.3g of the noise\n", where.c_str(),
                rms_a / L, rms_b / L, apart / sp);
    if (!(rms_b <= 1.1 * rms_a && rms_a <= 1.1 * rms_b)) failures.add(where + format(": held-out RMS %.3g vs %.3g", rms_a, rms_b));
    if (!(apart <= 1e-3 * sp)) failures.add(where + format(": the two fits are %.3g noise apart", apart / sp));
    // (D-H numbers only without prismatic joints: a prismatic joint's line has a direction but no place, and
    // the conversion places it relative to the frames before it, so its rows depend on the frame)
    const bool prismatic = std::any_of(nominal.joints().begin(), nominal.joints().end(),
                                       [](const Joint& j) { return j.type == JointType::Prismatic; });
    if (c.measure == Measure::Pose && !prismatic) {
      const std::vector<double> x = frameFreeDh(a.model), y = frameFreeDh(b.model);
      for (size_t k = 0; k < x.size(); ++k) {
        const double d = std::abs(std::remainder(x[k] - y[k], 2.0 * M_PI));
        if (!(std::min(d, std::abs(x[k] - y[k])) <= 1e-3 * std::max(sp, sr * L))) {
          failures.add(where + " D-H number " + std::to_string(k) + format(": %.17g vs %.17g", x[k], y[k]));
        }
      }
    }
  }
  EXPECT_EQ(failures.count, 0);
}

// ---- several targets ------------------------------------------------------------------------------------

// 3 SMRs per pose, positions only, the frame unknown (far), the SMRs' points unknown: rank = count, and the
// held-out RMS of the targets at most the noise.
TEST(TrackerTargets, ThreeUnknownSmrsInAFarFrame) {
  std::mt19937_64 rng(3);
  const PoeModel nominal = pumaLike(0.0, true);
  const ErrorModel em(nominal);
  const PoeModel actual = em.apply(smallDelta(em, 1e-3, false, rng));
  const std::vector<Vec3> smr = {Vec3(60, 0, 40), Vec3(-30, 55, 25), Vec3(-20, -50, 70)};  // mm, tool frame
  const double sp = 0.01;
  const Pose F = trackerFrame(1000.0);
  std::vector<Measurement> ms = inFrame(measureTargets(actual, uniformPoses(nominal, 50, rng), smr), F);
  addPositionNoise(ms, sp, rng);
  CalibrationOptions options;
  options.measure = Measure::Targets;
  options.targets = {{"a", std::nullopt}, {"b", std::nullopt}, {"c", std::nullopt}};
  options.sigma_position = sp;
  const CalibrationResult r = calibrate(nominal, ms, options);
  const int count = 4 * 6 + 6 + 3 * 3;
  EXPECT_EQ(r.expected.total(), count);
  EXPECT_EQ(r.rank.rank, count);
  EXPECT_EQ(r.error_model.size(), count);
  EXPECT_TRUE(r.accepted) << r.reason;
  const std::vector<VecX> check = uniformPoses(nominal, 200, rng);
  const double rms = heldOutRms(movedModel(r.model, F.inverse()), r.target_points, actual, smr, check);
  std::printf("3 SMRs, frame and points unknown: %d iterations, registration %d alternations, held-out RMS %.3g mm "
              "(noise %.3g mm), variance factor %.3g\n",
              r.iterations, r.registration.iterations, rms, sp, r.variance_factor);
  EXPECT_LE(rms, sp);
}

// ---- blunders ---------------------------------------------------------------------------------------------

// 100 poses, 5 of them off by 5 mm: Huber and Cauchy reach at most 1.5x the held-out RMS of the same fit
// with the blunders removed by hand and flag exactly the blunders; least squares is rejected.
TEST(TrackerBlunders, RobustLossesFindFiveBlundersInAHundred) {
  std::mt19937_64 rng(5);
  const PoeModel nominal = pumaLike(0.0, true);
  const ErrorModel em(nominal);
  const PoeModel actual = em.apply(smallDelta(em, 1e-3, false, rng));
  const double sp = 0.01, sr = 1e-5;
  std::vector<Measurement> ms = measure(actual, uniformPoses(nominal, 100, rng));
  addNoise(ms, sp, sr, rng);
  const std::vector<size_t> blunders = {7, 23, 41, 66, 90};
  std::vector<Measurement> clean;
  for (size_t m = 0; m < ms.size(); ++m) {
    if (std::find(blunders.begin(), blunders.end(), m) == blunders.end()) clean.push_back(ms[m]);
  }
  for (size_t b : blunders) ms[b].T_base_tool.p += 5.0 * lowpair_test::unitVector(rng);
  CalibrationOptions options;
  options.sigma_position = sp;
  options.sigma_rotation = sr;
  const std::vector<VecX> check = uniformPoses(nominal, 200, rng);
  const CalibrationResult reference = calibrate(nominal, clean, options);
  ASSERT_TRUE(reference.accepted) << reference.reason;
  const double rms_clean = heldOutRms(reference.model, {}, actual, {}, check);
  const CalibrationResult squared = calibrate(nominal, ms, options);
  std::printf("least squares with 5 blunders: %s\n", squared.reason.c_str());
  EXPECT_FALSE(squared.accepted);
  for (const Loss loss : {Loss::Huber, Loss::Cauchy}) {
    options.loss = loss;
    const CalibrationResult r = calibrate(nominal, ms, options);
    const double rms = heldOutRms(r.model, {}, actual, {}, check);
    std::printf("%s: held-out RMS %.3g mm (blunders removed by hand: %.3g), %d outliers, %d reweightings, %d iterations, "
                "variance factor %.3g\n",
                lossName(loss), rms, rms_clean, r.outliers, r.reweightings, r.iterations, r.variance_factor);
    EXPECT_TRUE(r.accepted) << lossName(loss) << ": " << r.reason;
    EXPECT_LE(rms, 1.5 * rms_clean) << lossName(loss);
    for (size_t m = 0; m < ms.size(); ++m) {
      const bool blunder = std::find(blunders.begin(), blunders.end(), m) != blunders.end();
      EXPECT_EQ(r.residuals[m].outlier, blunder) << lossName(loss) << " measurement " << m;
    }
  }
}

// ---- the verdict -------------------------------------------------------------------------------------------

// Measurements of another robot, and the right robot's with the joint vectors shuffled across rows: no.
TEST(TrackerVerdict, AnotherRobotOrShuffledRowsAreRejected) {
  std::mt19937_64 rng(9);
  const PoeModel nominal = pumaLike(0.0, true);
  const ErrorModel em(nominal);
  const PoeModel actual = em.apply(smallDelta(em, 1e-3, false, rng));
  const std::vector<VecX> qs = uniformPoses(nominal, 60, rng);
  std::vector<Measurement> shuffled = measure(actual, qs);
  addNoise(shuffled, 0.01, 1e-5, rng);
  for (size_t m = 0; m + 1 < shuffled.size(); m += 2) std::swap(shuffled[m].q, shuffled[m + 1].q);
  const PoeModel other = jointMix("RRRRRR", nominal.lengthScale(), rng);
  std::vector<Measurement> foreign = measure(other, qs);
  for (const bool stated : {true, false}) {
    CalibrationOptions options;
    if (stated) {
      options.sigma_position = 0.01;
      options.sigma_rotation = 1e-5;
    }
    for (const auto* data : {&shuffled, &foreign}) {
      for (const Loss loss : {Loss::Squared, Loss::Huber, Loss::Cauchy}) {
        // (under the sanitizers Huber's code runs as Cauchy's first pass)
        if (loss == Loss::Huber && lowpair_test::sanitized()) continue;
        options.loss = loss;
        const CalibrationResult r = calibrate(nominal, *data, options);
        EXPECT_FALSE(r.accepted) << (data == &shuffled ? "shuffled" : "another robot") << ", " << lossName(loss)
                                 << (stated ? ", noise stated" : "") << ": RMS " << r.after.rms_position;
        EXPECT_FALSE(r.reason.empty());
      }
    }
  }
}

// ---- parameter levels and their choice -----------------------------------------------------------------------

// Offsets only: the parameters are the joint offsets, the base and the tool; a robot whose only errors are
// offsets and a frame is recovered to the noise.
TEST(TrackerParameters, OffsetsFitsOffsetsOnly) {
  std::mt19937_64 rng(11);
  const PoeModel nominal = pumaLike(0.0, true);
  ErrorModelSpec spec;
  spec.set = ParameterSet::Offsets;
  const ErrorModel em(nominal, spec);
  for (const Parameter& p : em.parameters()) {
    EXPECT_TRUE(p.kind == ParameterKind::Offset || p.kind == ParameterKind::BaseRotation ||
                p.kind == ParameterKind::BaseTranslation || p.kind == ParameterKind::ToolRotation ||
                p.kind == ParameterKind::ToolTranslation)
        << p.name;
  }
  EXPECT_EQ(em.size(), 6 + 6 + 6);
  VecX d = VecX::Zero(em.size());
  for (int k = 0; k < em.size(); ++k) d[k] = 1e-3 * (em.parameters()[static_cast<size_t>(k)].unit == "length" ? 100.0 : 1.0) * (k % 3 - 1);
  const PoeModel actual = em.apply(d);
  std::vector<Measurement> ms = measure(actual, uniformPoses(nominal, 40, rng));
  addNoise(ms, 0.01, 1e-5, rng);
  CalibrationOptions options;
  options.sigma_position = 0.01;
  options.sigma_rotation = 1e-5;
  options.parameters = ParameterSet::Offsets;
  const CalibrationResult r = calibrate(nominal, ms, options);
  EXPECT_TRUE(r.accepted) << r.reason;
  EXPECT_EQ(r.error_model.size(), 18);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(r.model.joint(i).scale, nominal.joint(i).scale);
  EXPECT_LE(heldOutRms(r.model, {}, actual, {}, uniformPoses(nominal, 100, rng)), 0.01);
}

namespace {

// The candidates' least-squares score from their own RMS fields: sqrt(rms_p^2 / sp^2 + rms_r^2 / sr^2), what
// every held-out measurement's |r|^2 sums to (pose data, stated noise): the score before robust scoring.
ParameterSet squaredScoreChoice(const CrossValidation& cv, double sp, double sr) {
  const CrossValidation::Candidate* best = nullptr;
  auto squared = [&](const CrossValidation::Candidate& c) {
    return c.rms_position * c.rms_position / (sp * sp) + c.rms_rotation * c.rms_rotation / (sr * sr);
  };
  for (const auto& c : cv.candidates) {
    if (!c.failed && (!best || squared(c) < squared(*best))) best = &c;
  }
  return best->set;
}

}  // namespace

// Repeat 0 is the plain k-fold partition, pose i in fold i % k: its score is recomputed here from fits on
// those folds (least squares, stated noise: the RMS weighted residual of every held-out pose). With as many
// poses as folds every shuffle gives the same sets: one partition is used, however many are asked.
TEST(TrackerParameters, CrossValidationPartitions) {
  std::mt19937_64 rng(22);
  const FavouringArm arm = favouringArm("RRPRRR", 0, rng);
  const double sp = 0.5, sr = 5e-4;
  std::vector<Measurement> ms = measure(arm.actual, uniformPoses(arm.nominal, 12, rng));
  addNoise(ms, sp, sr, rng);
  CalibrationOptions options;
  options.sigma_position = sp;
  options.sigma_rotation = sr;
  const CrossValidation cv = crossValidate(arm.nominal, ms, options, 4, 1);
  EXPECT_EQ(cv.repeats, 1);
  for (const auto& c : cv.candidates) {
    ASSERT_FALSE(c.failed) << parameterSetName(c.set);
    double sum = 0.0;
    for (int f = 0; f < 4; ++f) {
      std::vector<Measurement> train, test;
      for (size_t m = 0; m < ms.size(); ++m) (m % 4 == static_cast<size_t>(f) ? test : train).push_back(ms[m]);
      CalibrationOptions o = options;
      o.parameters = c.set;
      const PoeModel fitted = calibrate(arm.nominal, train, o).model;
      for (const Measurement& m : test) {
        const Pose T = predictedMeasurement(fitted, m, Measure::Pose);
        const double er = rotationAngle(T.R.transpose() * m.T_base_tool.R);
        sum += (m.T_base_tool.p - T.p).squaredNorm() / (sp * sp) + er * er / (sr * sr);
      }
    }
    // the same fits and predictions: 12 terms summed, each with a few roundings (16 eps per term)
    EXPECT_NEAR(c.score, std::sqrt(sum / 12.0), 16.0 * 12.0 * kEpsilon * c.score) << parameterSetName(c.set);
  }
  const std::vector<Measurement> four(ms.begin(), ms.begin() + 4);
  EXPECT_EQ(crossValidate(arm.nominal, four, options, 4, 10).repeats, 1);
  EXPECT_GT(crossValidate(arm.nominal, ms, options, 4, 10).repeats, 1);
}

// A held-out blunder is scored as the fit's loss scores it: with a robust loss, one reading 5000 sigma off
// does not decide the choice. One arm favouring each level, 20 poses, the blunder in pose 7: the choice with
// the blunder is the choice on the clean data; the least-squares score of the same held-out errors (what the
// choice was made by before) chooses otherwise at least once. (Under the sanitizers Huber only.)
TEST(TrackerParameters, CrossValidationScoresAHeldOutBlunderByTheLoss) {
  std::mt19937_64 rng(21);
  const double sp = 0.5, sr = 5e-4;
  int squared_differs = 0;
  for (int favours = 0; favours < 3; ++favours) {
    const FavouringArm arm = favouringArm("RRPRRR", favours, rng);
    std::vector<Measurement> clean = measure(arm.actual, uniformPoses(arm.nominal, 20, rng));
    addNoise(clean, sp, sr, rng);
    std::vector<Measurement> blundered = clean;
    blundered[7].T_base_tool.p += 5000.0 * sp * Vec3(0.6, -0.8, 0.0);
    for (const Loss loss : {Loss::Huber, Loss::Cauchy}) {
      if (loss == Loss::Cauchy && lowpair_test::sanitized()) continue;
      CalibrationOptions options;
      options.sigma_position = sp;
      options.sigma_rotation = sr;
      options.loss = loss;
      const CrossValidation a = crossValidate(arm.nominal, clean, options, 5, 2);
      const CrossValidation b = crossValidate(arm.nominal, blundered, options, 5, 2);
      std::string line;
      for (size_t c = 0; c < 3; ++c) {
        line += std::string(" ") + parameterSetName(a.candidates[c].set) +
                format(" %.4g -> %.4g", a.candidates[c].score, b.candidates[c].score);
      }
      std::printf("favours %d, %s:%s\n", favours, lossName(loss), line.c_str());
      EXPECT_EQ(parameterSetName(a.chosen), std::string(parameterSetName(b.chosen)))
          << "favours " << favours << ", " << lossName(loss) << ":" << line;
      if (squaredScoreChoice(b, sp, sr) != a.chosen) ++squared_differs;
    }
  }
  EXPECT_GE(squared_differs, 1);
}


// --select cv: on random 6-joint arms with few noisy poses (15, pose data, noise 0.5 on a robot of about
// 1000 and 5e-4 rad), the level chosen by repeated 5-fold cross-validation has a held-out RMS within 10 % of
// the best of the three levels in hindsight, and the choice matters: the robots' errors favour each level in
// turn (favouringArm), so that always fitting `full` is within 10 % on only 13 of the 30. Beyond this seed (the
// former test's): CrossValidationStudy. Under the sanitizers the first 9 robots (always `full` is within 10 %
// on 4 of them; the statistics are this test's in the Release build).
TEST(TrackerParameters, CrossValidationPicksANearBestLevel) {
  std::mt19937_64 rng(15);
  Failures failures;
  const int robots = lowpair_test::sanitized() ? 9 : 30;
  int near_best = 0, full_near_best = 0;
  for (int robot = 0; robot < robots; ++robot) {
    const FavouringArm arm = favouringArm(robot % 2 ? "RRRRRR" : "RRPRRR", robot % 3, rng);
    const LevelOutcome o = levelOutcome(arm, Measure::Pose, {kCrossValidationRepeats}, rng);
    EXPECT_EQ(o.cv[0].repeats, kCrossValidationRepeats);
    std::string line;
    for (const auto& c : o.cv[0].candidates) {
      line += std::string(" ") + parameterSetName(c.set) +
              format(" score %.3g held-out %.3g", c.score, o.held_out[LevelOutcome::level(c.set)]);
    }
    std::printf("robot %d:%s; chose %s\n", robot, line.c_str(), parameterSetName(o.cv[0].chosen));
    if (o.chosen(0) <= 1.1 * o.best) ++near_best;
    if (o.held_out[0] <= 1.1 * o.best) ++full_near_best;
    if (!(o.chosen(0) <= 1.1 * o.best)) {
      failures.add("robot " + std::to_string(robot) + format(": chosen %.3g, best %.3g", o.chosen(0), o.best));
    }
  }
  std::printf("the chosen level within 10 %% of the best in hindsight on %d of %d robots (always full: %d)\n",
              near_best, robots, full_near_best);
  EXPECT_EQ(failures.count, 0);
  // the choice matters: fitting every parameter is not within 10 % on most of these robots
  EXPECT_LE(full_near_best, robots / 2);
}
