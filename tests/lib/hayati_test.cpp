// Hayati rows (docs/conventions.md, "Hayati rows"): a UR-type arm whose three parallel axes are tilted and
// moved as a calibration would leave them converts to a table with every length at most 2 L, exactly both
// ways; exactly parallel axes keep the standard table; random robots with nearly parallel axes likewise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/error_model.hpp"
#include "lowpair/kinematics.hpp"
#include "hayati_helpers.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "random_robot.hpp"

using namespace lowpair;
using hayati_helpers::poeDifference;

namespace {

// UR5's published standard D-H table (exactly parallel axes 2, 3, 4), as a D-H model.
DhModel ur5Dh() {
  const double d[6] = {0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823};
  const double a[6] = {0.0, -0.425, -0.39225, 0.0, 0.0, 0.0};
  const double alpha[6] = {M_PI / 2, 0.0, 0.0, M_PI / 2, -M_PI / 2, 0.0};
  std::vector<DhJoint> joints(6);
  for (int i = 0; i < 6; ++i) {
    joints[static_cast<size_t>(i)].name = "j" + std::to_string(i + 1);
    // the published H = prod A_i with A_i = Rz(theta_i) Tz(d_i) Rx(alpha_i) Tx(a_i) is this chain with an
    // identity base and link_i = A(0, d_i, alpha_i, a_i) after joint i's Rz
    DhParams& link = joints[static_cast<size_t>(i)].link;
    link.alpha = alpha[i];
    link.a = a[i];
    link.d = d[i];
  }
  const DhParams base;
  return DhModel(base, std::move(joints), 0.0, 0.0, "ur5");
}

// The UR5 as a calibration leaves it: every joint twist moved by Ad(exp(eta)) with a rotation of `tilt`
// (rad, random direction) and a translation of 1e-3 L, the tool by exp(eta_T) alike.
PoeModel calibratedUr(double tilt, std::mt19937_64& rng) {
  const PoeModel nominal = dhToPoe(ur5Dh());
  const double L = nominal.lengthScale();
  auto eta = [&]() {
    Vec6 e;
    e << tilt * lowpair_test::unitVector(rng), 1e-3 * L * lowpair_test::unitVector(rng);
    return e;
  };
  std::vector<Joint> joints = nominal.joints();
  for (Joint& j : joints) j.twist = adjointApply(expSE3(eta()), j.twist);
  return PoeModel(std::move(joints), expSE3(eta()) * nominal.toolPose(), "ur5-calibrated");
}

double longestLength(const DhModel& dh) {
  double out = std::max({std::abs(dh.base().d), std::abs(dh.base().a), std::abs(dh.toolD())});
  for (const DhJoint& j : dh.joints()) out = std::max({out, std::abs(j.link.d), std::abs(j.link.a)});
  return out;
}

int hayatiRows(const DhModel& dh) {
  int count = dh.base().hayati() ? 1 : 0;
  for (const DhJoint& j : dh.joints()) count += j.link.hayati() ? 1 : 0;
  return count;
}


}  // namespace

// Every length of the controller's table is at most 2 L for tilts 1e-4 .. 1e-2 (the standard table's d grows
// as L / tilt: 1e2 .. 1e4 L), and the rows between the parallel axes are Hayati rows.
TEST(HayatiUr, EveryLengthAtMostTwoL) {
  std::mt19937_64 rng(26);
  double worst = 0.0;
  for (const double tilt : {1e-4, 3e-4, 1e-3, 3e-3, 1e-2}) {
    for (int trial = 0; trial < 8; ++trial) {
      const PoeModel poe = calibratedUr(tilt, rng);
      const DhConversion c = poeToDh(poe);
      const double ratio = longestLength(c.model) / c.length_scale;
      worst = std::max(worst, ratio);
      EXPECT_LE(ratio, 2.0) << "tilt " << tilt << " trial " << trial;
      if (tilt <= 1e-3) {  // the standard d ~ 0.4 L / tilt: beyond L
        EXPECT_TRUE(c.model.joint(1).link.hayati() && c.model.joint(2).link.hayati()) << "tilt " << tilt;
      }
    }
  }
  std::printf("UR-type arm, tilts 1e-4..1e-2: longest D-H length %.4g L\n", worst);
}

// dhToPoe(poeToDh(M)) = M: twists and tool to 1e-12 (rad, L). The error is rounding in the n + 1 compositions
// of the conversion and of dhToPoe, each eps times lengths that are now at most 2 L: about 4 n eps ~ 5e-15;
// 1e-12 leaves a factor 200.
TEST(HayatiUr, DhToPoeRoundTripIsExact) {
  std::mt19937_64 rng(1985);
  double worst = 0.0;
  for (const double tilt : {1e-4, 1e-3, 1e-2}) {
    for (int trial = 0; trial < 8; ++trial) {
      const PoeModel poe = calibratedUr(tilt, rng);
      const double e = poeDifference(poe, dhToPoe(poeToDh(poe).model));
      worst = std::max(worst, e);
      EXPECT_LE(e, 1e-12) << "tilt " << tilt;
    }
  }
  std::printf("UR-type arm: round trip error %.3g (rad, L)\n", worst);
}

// FK of the Hayati table equals the POE FK over random q to 64 eps L (the chain's rounding: n + 2 poses
// composed, each with lengths <= 2 L).
TEST(HayatiUr, ForwardKinematicsAgree) {
  std::mt19937_64 rng(7);
  for (const double tilt : {1e-4, 1e-2}) {
    const PoeModel poe = calibratedUr(tilt, rng);
    const DhConversion c = poeToDh(poe);
    const FkCheck check = checkDhConversion(poe, c.model, 200);
    EXPECT_LE(check.max_translation, 64 * kEps * c.length_scale) << "tilt " << tilt;
    EXPECT_LE(check.max_rotation, 64 * kEps) << "tilt " << tilt;
    // the modified (Craig) regrouping carries the Hayati rows' beta
    const ModifiedDh m = toModifiedDh(c.model);
    std::uniform_real_distribution<double> u(-M_PI, M_PI);
    for (int s = 0; s < 20; ++s) {
      VecX q(6);
      for (int i = 0; i < 6; ++i) q[i] = u(rng);
      const Pose A = poeForwardKinematics(poe, q), B = modifiedDhForwardKinematics(m, q);
      EXPECT_LE((A.p - B.p).norm(), 64 * kEps * c.length_scale);
      EXPECT_LE(rotationError(A.R, B.R), 64 * kEps);
    }
  }
}

// Exactly parallel axes keep today's standard table: the UR5's published numbers, no Hayati row.
TEST(HayatiUr, ExactlyParallelAxesStayStandard) {
  const DhConversion c = poeToDh(dhToPoe(ur5Dh()));
  EXPECT_EQ(hayatiRows(c.model), 0);
  EXPECT_TRUE(c.rows[0].parallel && c.rows[2].parallel && c.rows[3].parallel);
  EXPECT_NEAR(c.model.joint(0).link.d, 0.089159, 1e-15);
  EXPECT_NEAR(c.model.joint(1).link.a, 0.425, 1e-15);
  EXPECT_EQ(c.model.joint(1).link.d, 0.0);
  EXPECT_NEAR(c.model.joint(2).link.a, 0.39225, 1e-15);
  EXPECT_EQ(c.model.joint(2).link.d, 0.0);
  EXPECT_NEAR(c.model.joint(3).link.d, 0.10915, 1e-15);
}

// A standard table forced by row_kinds has the huge d Hayati rows avoid: the rule is what bounds the lengths.
TEST(HayatiUr, ForcedStandardRowsBlowUp) {
  std::mt19937_64 rng(5);
  const PoeModel poe = calibratedUr(1e-4, rng);
  ConvertOptions options;
  options.row_kinds.assign(7, DhRowKind::Standard);
  const DhConversion c = poeToDh(poe, options);
  EXPECT_EQ(hayatiRows(c.model), 0);
  EXPECT_GT(longestLength(c.model) / c.length_scale, 100.0);
  EXPECT_THROW(poeToDh(poe, [] { ConvertOptions o; o.row_kinds.assign(3, DhRowKind::Standard); return o; }()),
               std::invalid_argument);
}

// The identification Jacobian's Hayati columns (theta, alpha, a, beta) against central differences of the FK.
TEST(HayatiUr, IdentificationJacobianBetaColumns) {
  std::mt19937_64 rng(11);
  const DhModel dh = poeToDh(calibratedUr(1e-3, rng)).model;
  ASSERT_TRUE(dh.joint(1).link.hayati());
  std::vector<VecX> qs;
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  for (int s = 0; s < 3; ++s) {
    VecX q(6);
    for (int i = 0; i < 6; ++i) q[i] = u(rng);
    qs.push_back(q);
  }
  std::vector<std::string> names;
  const MatX J = dhIdentificationJacobian(dh, qs, Measure::Position, ErrorModelSpec{}, &names);
  const auto column = std::find(names.begin(), names.end(), "j2.beta") - names.begin();
  ASSERT_LT(column, static_cast<long>(names.size()));
  EXPECT_EQ(std::count(names.begin(), names.end(), "j2.d"), 0);
  const double h = 1e-6;
  auto moved = [&](double step) {
    std::vector<DhJoint> joints = dh.joints();
    joints[1].link.beta += step;
    return DhModel(dh.base(), joints, dh.toolTheta(), dh.toolD());
  };
  const DhModel plus = moved(h), minus = moved(-h);
  for (size_t m = 0; m < qs.size(); ++m) {
    const Vec3 fd = (dhForwardKinematics(plus, qs[m]).p - dhForwardKinematics(minus, qs[m]).p) / (2 * h);
    const Vec3 col = J.block<3, 1>(3 * static_cast<Eigen::Index>(m), column);
    EXPECT_LE((fd - col).norm(), 1e-7) << "pose " << m;
  }
}

// The standard deviation of beta of a calibrated UR-type arm is finite, and d of a Hayati row is fixed.
TEST(HayatiUr, BetaStandardDeviationIsFinite) {
  std::mt19937_64 rng(3);
  const PoeModel actual = calibratedUr(1e-3, rng);
  std::vector<Measurement> ms;
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  for (int s = 0; s < 40; ++s) {
    Measurement m;
    m.q = VecX(6);
    for (int i = 0; i < 6; ++i) m.q[i] = u(rng);
    m.T_base_tool = poeForwardKinematics(actual, m.q);
    ms.push_back(m);
  }
  CalibrationOptions options;
  options.sigma_position = 1e-5;
  options.sigma_rotation = 1e-5;
  const CalibrationResult result = calibrate(actual, ms, options);
  const DhUncertainty sd = dhUncertainty(result);
  ASSERT_TRUE(sd.conversion.model.joint(1).link.hayati());
  for (int r : {1, 2}) {
    EXPECT_TRUE(sd.links[static_cast<size_t>(r)].hayati());
    EXPECT_TRUE(std::isfinite(sd.links[static_cast<size_t>(r)].beta)) << r;
    EXPECT_GT(sd.links[static_cast<size_t>(r)].beta, 0.0) << r;
    EXPECT_LT(sd.links[static_cast<size_t>(r)].beta, 1e-3) << r;
    EXPECT_TRUE(sd.links_fixed[static_cast<size_t>(r)].d);
  }
}

// Random robots with nearly parallel consecutive axes: every conversion is exact both ways, and a row whose
// standard d would exceed L is a Hayati row no longer than the standard one.
TEST(HayatiProperty, NearlyParallelRobotsRoundTrip) {
  std::mt19937_64 rng(2026);
  int hayati = 0, robots = 0;
  for (int k = 0; robots < lowpair_test::robotCount(300) && k < 20000; ++k) {
    const lowpair_test::RandomRobot r = lowpair_test::randomRobot(rng);
    if (r.geometry != lowpair_test::Geometry::NearlyParallel) continue;
    ++robots;
    const DhConversion c = poeToDh(r.model);
    hayati += hayatiRows(c.model);
    const double L = c.length_scale;
    for (const DhRowReport& rep : c.rows) {
      if (!rep.hayati) continue;
      EXPECT_GT(rep.standard_d, kHayatiLength * L);
      EXPECT_LT(std::max(rep.abs_a, rep.abs_d), std::max(rep.standard_d, rep.abs_a));
    }
    // tolerance: rounding of the compositions, eps times the bound scale times a factor for n + 2 poses
    const FkCheck check = checkDhConversion(r.model, c.model, 16);
    const double tol = 256 * kEps * c.scale * (r.model.dof() + 2);
    EXPECT_LE(check.max_translation, tol) << "robot " << robots;
    const PoeModel back = dhToPoe(c.model);
    const FkCheck again = checkDhConversion(back, c.model, 16);
    EXPECT_LE(again.max_translation, tol) << "robot " << robots;
  }
  std::printf("%d nearly-parallel robots, %d Hayati rows\n", robots, hayati);
  EXPECT_GT(robots, 10);
  EXPECT_GT(hayati, 0);
}
