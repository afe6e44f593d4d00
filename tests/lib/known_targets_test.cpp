// Targets whose points are known (a calibrated nest; docs/calibration.md "Known targets"): the tool frame
// joins the parameters, the count follows the known points' geometry (3 for one, 5 for collinear ones, 6
// for three non-collinear ones, plus 3 per unknown point), and a calibration with three known points pins
// the tool (TCP) that unknown points leave at the nominal's.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "calibration_helpers.hpp"
#include "expect_invalid.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

using namespace lowpair;
using namespace calibration_helpers;
using lowpair_test::expectInvalid;

namespace {

// The tracker 2.5 m from the base (mm), turned 120 deg about (1, 1, 1).
Pose trackerFrameMm() { return Pose{expSO3(Vec3(1, 1, 1).normalized() * (2.0 * M_PI / 3.0)), Vec3(2500, -1200, 300)}; }

std::vector<Measurement> measureTargets(const PoeModel& truth, const std::vector<VecX>& qs, const std::vector<Vec3>& points,
                                        const Pose& T_frame_base) {
  std::vector<Measurement> out;
  for (const VecX& q : qs) {
    const Pose T = T_frame_base * poeForwardKinematics(truth, q);
    for (size_t t = 0; t < points.size(); ++t) {
      out.push_back(Measurement{q, Pose{Mat3::Identity(), T.R * points[t] + T.p}, static_cast<int>(t)});
    }
  }
  return out;
}

ErrorModelSpec targetSpec(const std::vector<Vec3>& points, const std::vector<bool>& known) {
  ErrorModelSpec spec;
  for (size_t t = 0; t < points.size(); ++t) spec.targets.push_back(Target{"", points[t], t < known.size() && known[t]});
  return spec;
}

// The tool frame's RMS position (length) and rotation (rad) error of `model` against `truth` over `qs`, both
// predicting in the same frame.
struct ToolError {
  double position = 0.0, rotation = 0.0;
};
ToolError toolError(const PoeModel& model, const PoeModel& truth, const std::vector<VecX>& qs) {
  double p = 0.0, r = 0.0;
  for (const VecX& q : qs) {
    const Pose A = poeForwardKinematics(model, q), B = poeForwardKinematics(truth, q);
    p += (A.p - B.p).squaredNorm();
    r += std::pow(rotationAngle(A.R.transpose() * B.R), 2);
  }
  const double n = static_cast<double>(qs.size());
  return {std::sqrt(p / n), std::sqrt(r / n)};
}

}  // namespace

// The rule on its degenerate geometries: none, one point, coincident points, two points, collinear points
// (exactly, and a hair off the line: 1e-9 L is far above rounding, so the points are not collinear), three
// non-collinear points.
TEST(KnownTargets, ToolRankOfKnownPoints) {
  const double L = 800.0;
  EXPECT_EQ(knownPointsToolRank({}, L), 0);
  EXPECT_EQ(knownPointsToolRank({Vec3(10, 20, 30)}, L), 3);
  EXPECT_EQ(knownPointsToolRank({Vec3(10, 20, 30), Vec3(10, 20, 30)}, L), 3);
  EXPECT_EQ(knownPointsToolRank({Vec3(10, 20, 30), Vec3(-40, 5, 60)}, L), 5);
  const Vec3 a(10, 20, 30), d(-50, -15, 30);
  EXPECT_EQ(knownPointsToolRank({a, a + d, a + 2.5 * d, a - 0.5 * d}, L), 5);
  EXPECT_EQ(knownPointsToolRank({a, a + d, a + 2.0 * d + Vec3(0, 0, 1e-9 * L)}, L), 6);
  EXPECT_EQ(knownPointsToolRank({Vec3(60, 0, 40), Vec3(-30, 55, 25), Vec3(-20, -50, 70)}, L), 6);
}

// The rank of the identification Jacobian (the error model's and the full, redundant model's) equals the
// count 5h + 4r + 2t + n + 3u + r_known on random robots of every joint type, for mixes of known and unknown
// targets, collinear known points among them.
TEST(KnownTargets, RankEqualsCountForMixesOfKnownAndUnknownPoints) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  struct Mix {
    std::vector<bool> known;
    bool collinear;  // the known points on one line
    int tool;        // 3 u + r_known
  };
  const std::vector<Mix> mixes = {{{true}, false, 3},
                                  {{true, true}, false, 5},
                                  {{true, true, true}, false, 6},
                                  {{true, true, true}, true, 5},
                                  {{true, false, false}, false, 3 + 6},
                                  {{true, true, false}, false, 5 + 3},
                                  {{false, true, true, true}, false, 6 + 3},
                                  {{false, false, false}, false, 9}};
  Failures failures;
  int analyses = 0;
  for (const std::string types : {"RRRRRR", "RRPRRR", "HRPHRR", "PRRRR", "RPPR"}) {
    for (const Mix& mix : mixes) {
      const PoeModel model = jointMix(types, std::pow(10.0, u(rng) * 2.0), rng);
      const double L = model.lengthScale();
      std::vector<Vec3> points;
      const Vec3 base = 0.2 * L * lowpair_test::draw3(u, rng), along = 0.2 * L * lowpair_test::draw3(u, rng);
      for (size_t t = 0; t < mix.known.size(); ++t) {
        points.push_back(mix.collinear && mix.known[t] ? Vec3(base + (0.5 + t) * along) : Vec3(0.2 * L * lowpair_test::draw3(u, rng)));
      }
      const ErrorModelSpec spec = targetSpec(points, mix.known);
      const Identifiability id = analyzeIdentifiability(model, uniformPoses(model, 40, rng), Measure::Targets, spec);
      ++analyses;
      const int expected = identifiableCount(model, Measure::Pose).total() - 6 + mix.tool;
      std::string where = types + " known";
      for (const bool k : mix.known) where += k ? " y" : " n";
      if (id.expected.total() != expected) failures.add(where + ": count " + std::to_string(id.expected.total()));
      if (id.poe.rank != expected) failures.add(where + ": rank " + std::to_string(id.poe.rank) + ", count " + std::to_string(expected));
      if (id.full_model_rank != expected) failures.add(where + ": full model rank " + std::to_string(id.full_model_rank));
      // the error model's columns: the tool's 6 with a known point, 3 per unknown point
      const int unknown = static_cast<int>(std::count(mix.known.begin(), mix.known.end(), false));
      const int columns = identifiableCount(model, Measure::Pose).total() - 6 + 3 * unknown + (unknown < static_cast<int>(mix.known.size()) ? 6 : 0);
      if (id.poe.columns != columns) failures.add(where + ": " + std::to_string(id.poe.columns) + " columns");
    }
  }
  std::printf("%d analyses of known/unknown mixes\n", analyses);
  EXPECT_EQ(failures.count, 0);
}

// With a known point, the tool's columns (and an unknown point's) against central differences of the
// measured point; a known point does not move with any parameter.
TEST(KnownTargets, ToolColumnsMatchCentralDifferences) {
  std::mt19937_64 rng(31);
  Failures failures;
  for (const std::string types : {"RRRRRR", "RPHRRH"}) {
    const PoeModel model = jointMix(types, 300.0, rng);
    const double L = model.lengthScale();
    const std::vector<Vec3> points = {Vec3(0.1, 0.2, -0.1) * L, Vec3(-0.15, 0.05, 0.2) * L};
    const ErrorModel em(model, targetSpec(points, {true, false}));
    const VecX q = uniformJoints(model, rng);
    for (int t = 0; t < 2; ++t) {
      MatX J(3, em.size());
      em.jacobian(q, Measure::Targets, J, t);
      for (int k = 0; k < em.size(); ++k) {
        const Parameter& p = em.parameters()[static_cast<size_t>(k)];
        const double unit = parameterUnit(p, L);
        const double h = std::cbrt(kEpsilon) * unit;
        VecX d = VecX::Zero(em.size());
        d[k] = h;
        if (em.applyTargetPoints(d)[0] != points[0]) failures.add(types + " " + p.name + ": moves the known point");
        auto point = [&](const VecX& delta) {
          const Pose T = poeForwardKinematics(em.apply(delta), q);
          return Vec3(T.R * em.applyTargetPoints(delta)[static_cast<size_t>(t)] + T.p);
        };
        const Vec3 numeric = (point(d) - point(-d)) / (2.0 * h);
        const double S = distanceScale(model, q, poeForwardKinematics(model, q));
        // central differences: h^2 truncation plus eps/h rounding, both eps^(2/3) of the scale
        if (!((numeric - J.col(k)).norm() * unit <= 1e3 * std::pow(kEpsilon, 2.0 / 3.0) * S)) {
          failures.add(types + " target " + std::to_string(t) + " " + p.name +
                       format(": column off by %.3g S", (numeric - J.col(k)).norm() * unit / S));
        }
      }
    }
  }
  EXPECT_EQ(failures.count, 0);
}

// A PUMA-like arm whose actual tool is off the nominal's by 2 mm and 0.02 rad, seen by a tracker 2.5 m away
// through three SMRs. Known points (the actual's, from a calibrated nest) pin the tool: noise-free, the
// calibrated TCP equals the actual's to rounding; with noise, to about the noise. Unknown points (the same
// data) leave the TCP where the nominal has it: off by about the tool's error.
TEST(KnownTargets, ThreeKnownSmrsPinTheTool) {
  std::mt19937_64 rng(5);
  const PoeModel nominal = pumaLike(0.0, true);
  const double L = nominal.lengthScale();
  const ErrorModel em(nominal);
  const PoeModel geometry = em.apply(smallDelta(em, 1e-3, false, rng));
  const Pose tool_error{expSO3(Vec3(0.012, -0.01, 0.013)), Vec3(1.2, -0.9, 1.3)};  // 0.02 rad, 2 mm
  const PoeModel actual(geometry.joints(), geometry.toolPose() * tool_error, "actual");
  const std::vector<Vec3> smr = {Vec3(60, 0, 40), Vec3(-30, 55, 25), Vec3(-20, -50, 70)};  // mm, actual tool frame
  const Pose F = trackerFrameMm();
  const PoeModel actual_in_frame = movedModel(actual, F);
  const std::vector<VecX> fit_q = uniformPoses(nominal, 50, rng), check = uniformPoses(nominal, 200, rng);
  const std::vector<Measurement> exact = measureTargets(actual, fit_q, smr, F);
  const double sp = 0.01;  // mm
  std::vector<Measurement> noisy = exact;
  std::normal_distribution<double> n;
  for (Measurement& m : noisy) m.T_base_tool.p += sp * lowpair_test::draw3(n, rng);

  CalibrationOptions options;
  options.measure = Measure::Targets;
  for (size_t t = 0; t < smr.size(); ++t) options.targets.push_back(Target{"smr" + std::to_string(t), smr[t], true});

  // noise-free: the tool to 1e-9 L (Gauss-Newton converges quadratically on exact data from a start 1e-3 L
  // off; the stop rule ends it within a few steps of rounding)
  const CalibrationResult pinned = calibrate(nominal, exact, options);
  const int count = 4 * 6 + 6 + 6;
  EXPECT_EQ(pinned.expected.total(), count);
  EXPECT_EQ(pinned.rank.rank, count);
  EXPECT_TRUE(pinned.converged);
  const ToolError e0 = toolError(pinned.model, actual_in_frame, check);
  std::printf("known points, noise-free: TCP RMS %.3g mm, %.3g rad\n", e0.position, e0.rotation);
  EXPECT_LE(e0.position, 1e-9 * L);
  EXPECT_LE(e0.rotation, 1e-9);
  for (size_t t = 0; t < smr.size(); ++t) {
    EXPECT_EQ(pinned.target_points[t], smr[t]);
    EXPECT_EQ(pinned.error_model.spec().targets[t].name, options.targets[t].name);
  }

  // noisy: the TCP to the noise (a least-squares fit predicts to about sigma sqrt(p / m): 36 parameters,
  // 450 rows, so 0.3 sigma; the TCP is up to 70 mm off the SMRs, so allow sigma)
  options.sigma_position = sp;
  const CalibrationResult fit = calibrate(nominal, noisy, options);
  EXPECT_TRUE(fit.accepted) << fit.reason;
  const ToolError e1 = toolError(fit.model, actual_in_frame, check);
  std::printf("known points, noise %.3g mm: TCP RMS %.3g mm, %.3g rad\n", sp, e1.position, e1.rotation);
  EXPECT_LE(e1.position, sp);

  // unknown points on the same data: the fit is as good at the SMRs, but the TCP keeps the nominal's tool
  CalibrationOptions unknown = options;
  for (Target& t : unknown.targets) t.known = false;
  const CalibrationResult free_points = calibrate(nominal, noisy, unknown);
  EXPECT_TRUE(free_points.accepted) << free_points.reason;
  EXPECT_EQ(free_points.expected.total(), 4 * 6 + 6 + 9);
  for (size_t t = 0; t < smr.size(); ++t) {  // the fitted points, moved from the given ones
    EXPECT_EQ(*free_points.error_model.spec().targets[t].point_tool, free_points.target_points[t]);
    EXPECT_GT((free_points.target_points[t] - smr[t]).norm(), 0.0);
  }
  const ToolError e2 = toolError(free_points.model, actual_in_frame, check);
  std::printf("unknown points: TCP RMS %.3g mm, %.3g rad (the tool's error: %.3g mm, %.3g rad)\n", e2.position, e2.rotation,
              tool_error.p.norm(), rotationAngle(tool_error.R));
  EXPECT_GE(e2.position, 0.5 * tool_error.p.norm());
}

// A known target needs its point in calibrate's options; every target of an error model needs one (finite): the
// error model and every function taking a spec refuse a target without, naming it (numbered when one is unnamed).
TEST(KnownTargets, TargetsWithoutPointsAreRefusedByName) {
  CalibrationOptions options;
  options.measure = Measure::Targets;
  options.targets = {Target{"a", std::nullopt, true}};
  EXPECT_THROW(options.validate(), std::invalid_argument);
  const PoeModel nominal = pumaLike(0.0, true);
  const std::vector<VecX> q(1, VecX::Zero(nominal.dof()));
  ErrorModelSpec spec;
  spec.targets = {Target{"smr_a", Vec3(1, 2, 3)}, Target{"smr_b", std::nullopt}};
  const std::string message = "error model: target smr_b has no point (an error model needs every target's point)";
  expectInvalid([&] { (void)ErrorModel(nominal, spec); }, message);
  expectInvalid([&] { identifiableCount(nominal, Measure::Targets, spec); }, message);
  expectInvalid([&] { fullErrorModelJacobian(nominal, q, Measure::Targets, spec); }, message);
  expectInvalid([&] { dhIdentificationJacobian(poeToDh(nominal).model, q, Measure::Targets, spec); }, message);
  expectInvalid([&] { analyzeIdentifiability(nominal, q, Measure::Targets, spec); }, message);
  spec.targets[1].point_tool = Vec3(1, std::nan(""), 3);
  expectInvalid([&] { (void)ErrorModel(nominal, spec); }, "error model: target smr_b has a non-finite point");
  spec.targets[0].name.clear();
  expectInvalid([&] { spec.validate(); }, "error model: target 2 has a non-finite point");
}

// The targets' parameters carry the targets' names, every target numbered when one name is empty, in the error
// model and the D-H parameterization alike; a known target has none. rebased moves the spec's points with
// targetPoints() and keeps names and known flags.
TEST(KnownTargets, TargetParameterNamesAndRebasedPoints) {
  const PoeModel nominal = pumaLike(0.0, true);
  const std::vector<VecX> q(1, VecX::Zero(nominal.dof()));
  ErrorModelSpec spec;
  spec.targets = {Target{"smr_a", Vec3(60, 0, 40)}, Target{"nest", Vec3(-30, 55, 25), true},
                  Target{"smr_c", Vec3(-20, -50, 70)}};
  auto targetParameters = [&](const ErrorModelSpec& s) {
    std::vector<std::string> poe, dh, columns;
    const ErrorModel em(nominal, s);
    for (const Parameter& p : em.parameters()) {
      if (p.kind == ParameterKind::TargetPoint) poe.push_back(p.name);
    }
    dhIdentificationJacobian(poeToDh(nominal).model, q, Measure::Targets, s, &columns);
    for (const std::string& c : columns) {
      if (c.rfind("target.", 0) == 0) dh.push_back(c);
    }
    EXPECT_EQ(dh, poe);
    return poe;
  };
  EXPECT_EQ(targetParameters(spec), (std::vector<std::string>{"target.smr_a.x", "target.smr_a.y", "target.smr_a.z",
                                                              "target.smr_c.x", "target.smr_c.y", "target.smr_c.z"}));
  spec.targets[2].name.clear();
  EXPECT_EQ(targetParameters(spec), (std::vector<std::string>{"target.1.x", "target.1.y", "target.1.z", "target.3.x",
                                                              "target.3.y", "target.3.z"}));
  const ErrorModel em(nominal, spec);
  const std::vector<Vec3> moved = {Vec3(61, 1, 41), Vec3(-30, 55, 25), Vec3(-21, -49, 71)};
  const ErrorModel at = em.rebased(nominal, moved);
  EXPECT_EQ(at.targetPoints(), moved);
  for (size_t t = 0; t < moved.size(); ++t) {
    EXPECT_EQ(*at.spec().targets[t].point_tool, moved[t]);
    EXPECT_EQ(at.spec().targets[t].name, spec.targets[t].name);
    EXPECT_EQ(at.spec().targets[t].known, t == 1);
  }
}

// Mixed data: 30 poses measured through three SMRs at unknown points and 10 more with a 6-DOF probe (the tool
// frame, kPoseMeasurement), fitted together in one frame 2.5 m away: the pose measurements determine the tool
// frame (count: the tool's 6 plus 3 per unknown point), so the TCP is the actual's (noise-free to 1e-9 L;
// with noise to the noise), and the SMRs' points to the noise.
TEST(KnownTargets, MixedPoseAndTargetMeasurementsFitTogether) {
  std::mt19937_64 rng(8);
  const PoeModel nominal = pumaLike(0.0, true);
  const double L = nominal.lengthScale();
  const ErrorModel em(nominal);
  const PoeModel geometry = em.apply(smallDelta(em, 1e-3, false, rng));
  const PoeModel actual(geometry.joints(), geometry.toolPose() * Pose{expSO3(Vec3(0.01, 0.012, -0.008)), Vec3(-1.1, 1.4, 0.9)},
                        "actual");
  const std::vector<Vec3> smr = {Vec3(60, 0, 40), Vec3(-30, 55, 25), Vec3(-20, -50, 70)};
  const Pose F = trackerFrameMm();
  const PoeModel actual_in_frame = movedModel(actual, F);
  std::vector<Measurement> exact = measureTargets(actual, uniformPoses(nominal, 30, rng), smr, F);
  for (const VecX& q : uniformPoses(nominal, 10, rng)) {
    exact.push_back(Measurement{q, F * poeForwardKinematics(actual, q), kPoseMeasurement});
  }
  CalibrationOptions options;
  options.measure = Measure::Targets;
  options.targets = {{"a", std::nullopt}, {"b", std::nullopt}, {"c", std::nullopt}};
  const std::vector<VecX> check = uniformPoses(nominal, 200, rng);

  const CalibrationResult r0 = calibrate(nominal, exact, options);
  const int count = 4 * 6 + 6 + 6 + 3 * 3;
  EXPECT_EQ(r0.expected.total(), count);
  EXPECT_EQ(r0.rank.rank, count);
  EXPECT_EQ(r0.tool_rank, 6);
  EXPECT_TRUE(r0.converged);
  const ToolError e0 = toolError(r0.model, actual_in_frame, check);
  std::printf("mixed data, noise-free: TCP RMS %.3g mm, %.3g rad\n", e0.position, e0.rotation);
  EXPECT_LE(e0.position, 1e-9 * L);
  EXPECT_LE(e0.rotation, 1e-9);
  // the residuals: 6 rows for each pose measurement (its rotation measured), 3 for each point
  EXPECT_EQ(r0.residuals.back().rows, 6);
  EXPECT_TRUE(std::isfinite(r0.residuals.back().rotation));
  EXPECT_EQ(r0.residuals.front().rows, 3);
  EXPECT_TRUE(std::isnan(r0.residuals.front().rotation));

  // noise 0.01 mm per coordinate on every point and position, 1e-5 rad on the probe's rotations: accepted,
  // the TCP and the SMRs to the noise (a least-squares fit predicts to about sigma sqrt(p / rows): 45
  // parameters, 330 rows, 0.37 sigma)
  const double sp = 0.01, sr = 1e-5;
  std::vector<Measurement> noisy = exact;
  std::normal_distribution<double> n;
  for (Measurement& m : noisy) {
    m.T_base_tool.p += sp * lowpair_test::draw3(n, rng);
    if (m.target == kPoseMeasurement) m.T_base_tool.R = expSO3(sr * lowpair_test::draw3(n, rng)) * m.T_base_tool.R;
  }
  options.sigma_position = sp;
  options.sigma_rotation = sr;
  const CalibrationResult r1 = calibrate(nominal, noisy, options);
  EXPECT_TRUE(r1.accepted) << r1.reason;
  const ToolError e1 = toolError(r1.model, actual_in_frame, check);
  std::vector<Measurement> held_out = measureTargets(actual, check, smr, F);
  const ResidualStatistics points = residualStatistics(r1.model, held_out, Measure::Targets, r1.target_points);
  std::printf("mixed data, noise %.3g mm: TCP RMS %.3g mm, %.3g rad; SMRs held out %.3g mm; variance factor %.3g\n", sp,
              e1.position, e1.rotation, points.rms_position, r1.variance_factor);
  EXPECT_LE(e1.position, sp);
  EXPECT_LE(points.rms_position, sp);
  EXPECT_GT(r1.after.rms_rotation, 0.0);  // over the pose measurements only
  EXPECT_LE(r1.after.rms_rotation, 3 * sr);
}
