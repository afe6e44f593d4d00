// POE -> D-H on the paper's PUMA 560 (Wu et al. Table I -> Table II), degenerate geometry on purpose,
// canonical output, offsets, the modified export, tool/local forms.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

using namespace lowpair;

namespace {

constexpr double kDeg = M_PI / 180.0;

// Every row standard (the paper's tables): by default a row between nearly parallel axes whose standard d
// would exceed L is a Hayati row (docs/conventions.md), which the paper does not use.
ConvertOptions standardRows() {
  ConvertOptions options;
  options.standard_only = true;
  return options;
}

Vec6 twist(double a, double b, double c, double d, double e, double f) { return (Vec6() << a, b, c, d, e, f).finished(); }

PoeModel pumaNominal() {
  std::vector<JointSpec> j(6);
  j[0].twist = twist(0, 0, 1, 0, 0, 0);
  j[1].twist = twist(0, -1, 0, 0, 0, 0);
  j[2].twist = twist(0, -1, 0, 0, 0, -100);
  j[3].twist = twist(0, 0, -1, -50, 250, 0);
  j[4].twist = twist(0, -1, 0, -20, 0, -250);
  j[5].twist = twist(0, 0, -1, -50, 250, 0);
  return PoeModel::fromToolTwist(j, twist(0, 0, 0, 250, 50, -20), "puma-nominal");
}

PoeModel pumaActual() {
  std::vector<JointSpec> j(6);
  j[0].twist = twist(0.04, -0.02, 0.999, 0.02, 0.04, 0);
  j[1].twist = twist(0, -1.00002, 0, -0.02, 0, 0.05);
  j[2].twist = twist(0.178, -0.984, -0.001, -0.07, 0.009, -101);
  j[3].twist = twist(0.062, 0.013, -0.998, -51, 249, 0.0752);
  j[4].twist = twist(0.001, -1.00004, 0, -20.6, -0.0206, -249);
  j[5].twist = twist(0.095, 0.031, -0.995, -51, 249, 0);
  return PoeModel::fromToolTwist(j, twist(0.02, -0.01, 0.01, 249, 51, -20.6), "puma-actual");
}

// A printed value and the half unit of its last printed digit.
struct Printed {
  double value, half_unit;
};
Printed p4(double v) { return {v, 0.5e-4}; }

struct Table2Row {
  Printed theta, d, alpha, a;
};

void expectPrinted(double actual, const Printed& printed, const std::string& what) {
  EXPECT_LE(std::abs(actual - printed.value), printed.half_unit * (1 + 1e-9) + 1e-12)
      << what << ": got " << actual << ", Table II prints " << printed.value;
}

void expectRow(const DhParams& r, const Table2Row& t, const std::string& what) {
  expectPrinted(r.theta / kDeg, t.theta, what + " theta");
  expectPrinted(r.d, t.d, what + " d");
  expectPrinted(r.alpha / kDeg, t.alpha, what + " alpha");
  expectPrinted(r.a, t.a, what + " a");
}

double fkGap(const PoeModel& poe, const DhModel& dh, const VecX& q) {
  const Pose a = poeForwardKinematics(poe, q), b = dhForwardKinematics(dh, q);
  return std::max(rotationError(a.R, b.R), (a.p - b.p).norm() / poe.lengthScale());
}

}  // namespace

TEST(PoeToDh, ReproducesTableIINominal) {
  const DhConversion c = poeToDh(pumaNominal());
  const DhModel& m = c.model;
  expectRow(m.base(), {p4(0), p4(0), p4(0), p4(0)}, "base");
  const Table2Row rows[6] = {{p4(0), p4(0), p4(90), p4(0)},    {p4(0), p4(0), p4(0), p4(100)},
                             {p4(0), p4(-50), p4(90), p4(150)}, {p4(180), p4(20), p4(90), p4(0)},
                             {p4(180), p4(0), p4(90), p4(0)},   {p4(0), p4(0), p4(180), p4(0)}};
  for (int i = 0; i < 6; ++i) {
    expectRow(m.joint(i).link, rows[i], "row " + std::to_string(i + 1));
    EXPECT_EQ(m.joint(i).type, JointType::Revolute);
    EXPECT_EQ(m.joint(i).scale, 1.0);
  }
  // Exactly zero where the paper prints 0 (IEEE atan2(+0, -0) would give 180 degrees).
  EXPECT_EQ(m.base().theta, 0.0);
  EXPECT_FALSE(std::signbit(m.base().theta));
  EXPECT_EQ(m.joint(0).link.theta, 0.0);
  EXPECT_FALSE(std::signbit(m.joint(0).link.theta));
  EXPECT_EQ(m.joint(1).link.theta, 0.0);
  expectPrinted(m.toolTheta() / kDeg, p4(0), "tool theta");
  expectPrinted(m.toolD(), p4(0), "tool d");
  // well conditioned: nothing to warn about
  ASSERT_EQ(c.rows.size(), 7u);
  for (const DhRowReport& r : c.rows) EXPECT_FALSE(r.ill_conditioned) << "row " << r.row;
  EXPECT_FALSE(c.tool.ill_conditioned);
  EXPECT_FALSE(c.above_rounding);
  EXPECT_EQ(c.rows[3].abs_a, 150.0);  // row 3: a = 150, d = -50 (Table II)
  EXPECT_EQ(c.rows[3].abs_d, 50.0);
}

TEST(PoeToDh, ReproducesTableIIActual) {
  const DhConversion c = poeToDh(pumaActual(), standardRows());
  const DhModel& m = c.model;
  expectRow(m.base(), {p4(63.4349), p4(1.0000), p4(2.5632), p4(0)}, "base");
  const Table2Row rows[6] = {
      {p4(116.5421), p4(-1.0214), p4(-88.8540), p4(0.0092)}, {p4(-88.0290), p4(-567.6554), p4(10.2538), p4(0.5114)},
      {p4(-86.0527), p4(552.7518), p4(90.0434), p4(153.3035)}, {p4(-169.8271), p4(30.1922), p4(90.7413), p4(1.8365)},
      {p4(-178.0999), p4(-0.7927), p4(91.7710), p4(3.1761)},  {p4(82.8018), p4(-37.0573), p4(175.0748), p4(-0.7202)}};
  // pitch in mm/deg and scale, as printed
  const Printed pitch[6] = {{0, 0}, {0, 0}, {0.0014, 0.5e-4}, {-0.0000009, 0.5e-7}, {0.00000001, 0.5e-8}, {0.0502, 0.5e-4}};
  const Printed scale[6] = {{1.0000005, 0.5e-7}, {1.00002, 0.5e-5}, {0.99997, 0.5e-5},
                            {1.000008, 0.5e-6},  {1.00004, 0.5e-5}, {1.000005, 0.5e-6}};
  const JointType types[6] = {JointType::Revolute, JointType::Revolute, JointType::Helical,
                              JointType::Helical,  JointType::Helical,  JointType::Helical};
  for (int i = 0; i < 6; ++i) {
    const std::string label = "row " + std::to_string(i + 1);
    expectRow(m.joint(i).link, rows[i], label);
    EXPECT_EQ(m.joint(i).type, types[i]) << label;
    expectPrinted(m.joint(i).pitch * kDeg, pitch[i], label + " pitch (mm/deg)");
    expectPrinted(m.joint(i).scale, scale[i], label + " scale");
  }
  expectPrinted(m.toolTheta() / kDeg, p4(83.1872), "tool theta");
  expectPrinted(m.toolD(), p4(-35.4328), "tool d");
  const FkCheck check = checkDhConversion(pumaActual(), m);
  EXPECT_EQ(check.samples, kFkCheckSamples + 1);
  EXPECT_LE(check.max_rotation, 1e-12);
  EXPECT_LE(check.max_translation, 1e-12 * check.scale);
  // the bound's scale is the largest of L and the table's lengths: here |d| of row 2 (567.6554 mm)
  expectPrinted(check.scale, p4(567.6554), "bound scale");
  EXPECT_EQ(check.scale, c.scale);
}

TEST(CheckDhConversion, DetectsAWrongTable) {
  // The check compares two independent forward kinematics, so it must see a table that is off by 1e-6.
  const PoeModel poe = pumaNominal();
  const DhConversion c = poeToDh(poe);
  const FkCheck exact = checkDhConversion(poe, c.model);
  EXPECT_LE(exact.max_translation, 1e-12 * exact.scale);
  std::vector<DhJoint> joints = c.model.joints();
  joints[2].link.a += 1e-6;  // row 3
  const DhModel wrong(c.model.base(), joints, c.model.toolTheta(), c.model.toolD());
  const FkCheck off = checkDhConversion(poe, wrong);
  EXPECT_GT(off.max_translation, 0.5e-6);
  EXPECT_LT(off.max_translation, 1.5e-6);
  joints = c.model.joints();
  joints[4].link.alpha += 1e-6;  // a twist of the wrist turns the tool
  const FkCheck turned = checkDhConversion(poe, DhModel(c.model.base(), joints, c.model.toolTheta(), c.model.toolD()));
  EXPECT_GT(turned.max_rotation, 0.5e-6);
  EXPECT_LT(turned.max_rotation, 1.5e-6);
  // the zero configuration alone, and errors
  EXPECT_EQ(checkDhConversion(poe, wrong, 0).samples, 1);
  EXPECT_THROW(checkDhConversion(poe, wrong, -1), std::invalid_argument);
  std::vector<JointSpec> two(2);
  two[0].twist = twist(0, 0, 1, 0, 0, 0);
  two[1].twist = twist(0, 0, 1, 0, -1, 0);
  EXPECT_THROW(checkDhConversion(PoeModel(two, Pose()), c.model), std::invalid_argument);
}

TEST(PoeToDh, PrismaticJointsConvert) {
  // The authors' MATLAB divides by |w| = 0 here.
  std::vector<JointSpec> j(4);
  j[0].twist = twist(0, 0, 0, 0, 0, 2.5);          // prismatic along z, scale 2.5
  j[1].twist = twist(0, 0, 0, 1, 0, 0);            // prismatic along x, perpendicular
  j[2].twist = twist(1, 0, 0, 0, 0.3, -0.2);       // revolute parallel to the prismatic x
  j[3].twist = twist(0, 0, 0, 3, 0, 0);            // prismatic parallel to the revolute axis
  const PoeModel poe(j, expSE3(twist(0.1, 0.2, 0.3, 1, 2, 3)));
  const DhConversion c = poeToDh(poe);
  EXPECT_EQ(c.model.joint(0).type, JointType::Prismatic);
  EXPECT_DOUBLE_EQ(c.model.joint(0).scale, 2.5);
  for (const auto& jt : c.model.joints()) EXPECT_TRUE(std::isfinite(jt.link.theta + jt.link.d + jt.link.alpha + jt.link.a));
  EXPECT_LE(fkGap(poe, c.model, (VecX(4) << 0.3, -0.7, 1.1, 0.2).finished()), 1e-14);
}

TEST(PoeToDh, ExactlyParallelAndAntiParallelAxes) {
  std::vector<JointSpec> j(4);
  j[0].twist = twist(0, 1, 0, 0, 0, 0);
  j[1].twist = twist(0, 1, 0, -0.5, 0, 0.3);   // parallel
  j[2].twist = twist(0, -1, 0, 0.2, 0, -0.7);  // anti-parallel
  j[3].twist = twist(0, 1, 0, -0.5, 0, 0.3);   // collinear with joint 2
  const PoeModel poe(j, Pose());
  const DhConversion c = poeToDh(poe);
  // rows 1..3 are placed by joints 2..4, all parallel to joint 1; row 4 comes from the tool (Lemma 4)
  EXPECT_TRUE(c.rows[1].parallel);
  EXPECT_TRUE(c.rows[2].parallel);
  EXPECT_TRUE(c.rows[3].parallel);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(c.model.joint(i).link.d, 0.0);  // free choice for parallel axes
    EXPECT_GE(c.model.joint(i).link.a, 0.0);
  }
  EXPECT_LE(fkGap(poe, c.model, (VecX(4) << 0.3, -2.7, 1.1, 3.0).finished()), 1e-14);
}

TEST(PoeToDh, NearlyParallelAxesAreAccurateAndReported) {
  for (double tilt : {1e-3, 1e-6, 1e-9, 1e-12, 1e-14, 1e-16}) {
    std::vector<JointSpec> j(3);
    j[0].twist = twist(0, 0, 1, 0, 0, 0);
    const Vec3 w = Vec3(std::sin(tilt), 0, std::cos(tilt));
    const Vec3 p(0.3, 0.4, 0);
    j[1].twist << w, p.cross(w);
    j[2].twist = twist(1, 0, 0, 0, 0.1, 0);
    const PoeModel poe(j, expSE3(twist(0, 0, 0, 0.5, 0.5, 0.2)));
    // the default table has a Hayati row there: nothing ill-conditioned, FK as exact
    const DhConversion h = poeToDh(poe);
    EXPECT_FALSE(h.rows[1].ill_conditioned) << "tilt " << tilt;
    EXPECT_EQ(h.model.joint(0).link.hayati(), !h.rows[1].parallel && h.rows[1].standard_d > poe.lengthScale());
    EXPECT_LE(checkDhConversion(poe, h.model).max_translation, 1e-12 * poe.lengthScale()) << "tilt " << tilt;
    const DhConversion c = poeToDh(poe, standardRows());
    const FkCheck check = checkDhConversion(poe, c.model);
    const double bound = 1e-12 * check.scale;
    EXPECT_LE(check.max_translation, bound) << "tilt " << tilt;
    EXPECT_LE(check.max_rotation, 1e-12) << "tilt " << tilt;
    // the lengths the warning quotes are the table's, and |d| ~ |p| / tan(tilt) grows as the axes close
    const DhParams& row1 = c.model.joint(0).link;
    EXPECT_EQ(c.rows[1].abs_d, std::abs(row1.d));
    EXPECT_EQ(c.rows[1].abs_a, std::abs(row1.a));
    EXPECT_EQ(c.tool.abs_d, std::abs(c.model.toolD()));
    const bool ill = std::abs(row1.d) > kIllConditioned * poe.lengthScale();
    EXPECT_EQ(c.rows[1].ill_conditioned, ill);
    if (tilt >= 1e-3) {
      EXPECT_FALSE(ill) << "tilt " << tilt;
    }
    if (tilt <= 1e-6 && !c.rows[1].parallel) {
      EXPECT_TRUE(ill) << "tilt " << tilt;
    }
    if (!c.rows[1].parallel) {
      EXPECT_NEAR(c.rows[1].axis_angle, tilt, 1e-15 + 1e-12 * tilt);
    }
  }
}

TEST(PoeToDh, ParallelThresholdOptionReportsDeviation) {
  std::vector<JointSpec> j(2);
  j[0].twist = twist(0, 0, 1, 0, 0, 0);
  const Vec3 w = Vec3(std::sin(1e-7), 0, std::cos(1e-7));
  j[1].twist << w, Vec3(0.3, 0.4, 0).cross(w);
  const PoeModel poe(j, expSE3(twist(0, 0, 0, 0.5, 0.5, 0.2)));
  ConvertOptions snap;
  snap.parallel_threshold = 1e-6;
  const DhConversion c = poeToDh(poe, snap);
  EXPECT_TRUE(c.rows[1].parallel);
  EXPECT_TRUE(c.above_rounding);
  EXPECT_EQ(c.parallel_threshold, 1e-6);
  EXPECT_EQ(c.rounding_parallel_threshold, 16 * 2 * kEps);  // 16 eps per joint, 2 joints
  const FkCheck check = checkDhConversion(poe, c.model);
  EXPECT_GT(check.max_translation, 1e-9);  // snapping a 1e-7 rad tilt moves the tool
  EXPECT_LT(check.max_translation, 1e-5);
  // at the default threshold the same robot converts exactly and nothing is flagged
  const DhConversion exact = poeToDh(poe);
  EXPECT_FALSE(exact.above_rounding);
  EXPECT_FALSE(exact.rows[1].parallel);
  EXPECT_EQ(exact.parallel_threshold, exact.rounding_parallel_threshold);
  EXPECT_LE(checkDhConversion(poe, exact.model).max_translation, 1e-12 * exact.scale);
}

TEST(PoeToDh, OffsetsFoldIntoThetaAndD) {
  std::vector<JointSpec> j(3);
  j[0].twist = twist(0, 0, 2, 0, 0, 0);  // revolute, scale 2
  j[0].offset = 0.25;
  j[1].twist = twist(1, 0, 0, 0.4, 0, 0.3);  // helical, pitch 0.4
  j[1].offset = -0.5;
  j[2].twist = twist(0, 0, 0, 0, 0, 0.5);  // prismatic, scale 0.5
  j[2].offset = 0.2;
  const PoeModel poe(j, expSE3(twist(0.3, 0, 0, 1, 1, 1)));
  const DhConversion c = poeToDh(poe);
  std::vector<JointSpec> j0 = j;
  for (auto& s : j0) s.offset = 0;
  const DhConversion c0 = poeToDh(PoeModel(j0, poe.toolPose()));
  EXPECT_NEAR(c.model.joint(0).link.theta, wrapAngle(c0.model.joint(0).link.theta + 2 * 0.25), 1e-15);
  EXPECT_NEAR(c.model.joint(1).link.theta, wrapAngle(c0.model.joint(1).link.theta - 0.5), 1e-15);
  EXPECT_NEAR(c.model.joint(1).link.d, c0.model.joint(1).link.d - 0.4 * 0.5, 1e-15);
  EXPECT_NEAR(c.model.joint(2).link.d, c0.model.joint(2).link.d + 0.5 * 0.2, 1e-15);
  EXPECT_LE(fkGap(poe, c.model, (VecX(3) << 0.1, 0.2, 0.3).finished()), 1e-14);
}

TEST(PoeToDh, CanonicalOutput) {
  // Intersecting axes (a = 0) take alpha >= 0; rows placed by joint axes have a >= 0; no -0.
  const DhConversion c = poeToDh(pumaNominal());
  auto check = [](const DhParams& r, bool axis_row) {
    EXPECT_GT(r.theta, -M_PI);
    EXPECT_LE(r.theta, M_PI);
    EXPECT_GT(r.alpha, -M_PI);
    EXPECT_LE(r.alpha, M_PI);
    for (double x : {r.theta, r.d, r.alpha, r.a}) EXPECT_FALSE(x == 0.0 && std::signbit(x));
    if (axis_row) {
      EXPECT_GE(r.a, 0.0);
      if (r.a == 0.0) {
        EXPECT_GE(r.alpha, 0.0);
      }
    }
  };
  check(c.model.base(), true);
  for (int i = 0; i < 5; ++i) check(c.model.joint(i).link, true);
  check(c.model.joint(5).link, false);
}

TEST(PoeToDh, AxisAlongMinusZAndToolAlongLastAxis) {
  std::vector<JointSpec> j(2);
  j[0].twist = twist(0, 0, -1, 0, 0, 0);  // along -z through the origin
  j[1].twist = twist(0, 0, -1, 0.5, 0, 0);
  Pose tool;
  tool.R = expSO3(Vec3(M_PI, 0, 0));  // tool z = -z, parallel to the last axis
  tool.p = Vec3(0, 0.5, -1);
  const PoeModel poe(j, tool);
  const DhConversion c = poeToDh(poe);
  EXPECT_EQ(c.model.base().alpha, M_PI);
  EXPECT_EQ(c.model.base().theta, 0.0);
  EXPECT_TRUE(c.rows[2].parallel);
  EXPECT_LE(fkGap(poe, c.model, (VecX(2) << 0.7, -2.0).finished()), 1e-14);
}

TEST(DhToPoe, RoundTripOnTheActualPuma) {
  const PoeModel poe = pumaActual();
  const DhConversion c = poeToDh(poe);
  const PoeModel back = dhToPoe(c.model);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(back.joint(i).type, poe.joint(i).type);
    EXPECT_NEAR(back.joint(i).pitch, poe.joint(i).pitch, 1e-15 * poe.lengthScale());
    EXPECT_EQ(back.joint(i).scale, poe.joint(i).scale);
    // the same line: same direction, same moment
    EXPECT_LE((back.joint(i).twist - poe.joint(i).twist).cwiseAbs().maxCoeff(), 1e-12 * poe.lengthScale());
  }
  const VecX q = (VecX(6) << 0.1, -0.4, 2.0, -3.0, 0.5, 1.5).finished();
  const Pose a = poeForwardKinematics(poe, q), b = poeForwardKinematics(back, q);
  EXPECT_LE(rotationError(a.R, b.R), 1e-14);
  EXPECT_LE((a.p - b.p).norm(), 1e-13 * poe.lengthScale());
}

TEST(ModifiedDh, NominalPumaCraigTable) {
  // Craig's table of the nominal PUMA, regrouped by hand from Table II (standard rows
  // (theta, d, alpha, a) = (0,0,90,0) (0,0,0,100) (0,-50,90,150) (180,20,90,0) (180,0,90,0) (0,0,180,0)):
  // joint i gets (alpha_{i-1}, a_{i-1}) of the row before and (theta_i, d_i) of its own row.
  const PoeModel poe = pumaNominal();
  const ModifiedDh m = toModifiedDh(poeToDh(poe).model);
  struct Row {
    double alpha, a, theta, d;  // deg, mm
  };
  const Row expected[6] = {{0, 0, 0, 0}, {90, 0, 0, 0}, {0, 100, 0, -50}, {90, 150, 180, 20}, {90, 0, 180, 0}, {90, 0, 0, 0}};
  ASSERT_EQ(m.joints.size(), 6u);
  EXPECT_NEAR(m.base_theta, 0.0, 1e-12);
  EXPECT_NEAR(m.base_d, 0.0, 1e-12);
  for (int i = 0; i < 6; ++i) {
    const ModifiedDhJoint& j = m.joints[static_cast<size_t>(i)];
    EXPECT_NEAR(j.alpha / kDeg, expected[i].alpha, 1e-10) << "joint " << i + 1;
    EXPECT_NEAR(j.a, expected[i].a, 1e-10) << "joint " << i + 1;
    EXPECT_NEAR(std::abs(wrapAngle(j.theta - expected[i].theta * kDeg)), 0.0, 1e-12) << "joint " << i + 1;
    EXPECT_NEAR(j.d, expected[i].d, 1e-10) << "joint " << i + 1;
  }
  EXPECT_NEAR(m.tool_alpha / kDeg, 180.0, 1e-10);
  EXPECT_NEAR(m.tool_a, 0.0, 1e-10);
  EXPECT_NEAR(m.tool_theta, 0.0, 1e-12);
  EXPECT_NEAR(m.tool_d, 0.0, 1e-10);
}

TEST(ModifiedDh, ForwardKinematicsMatchesPoe) {
  // against the POE model the table came from (product of exponentials), not the standard table
  const PoeModel poe = pumaActual();
  const ModifiedDh m = toModifiedDh(poeToDh(poe).model);
  for (const VecX& q : {VecX((VecX(6) << 0.1, -0.4, 2.0, -3.0, 0.5, 1.5).finished()), VecX(VecX::Zero(6)),
                        VecX((VecX(6) << -2.5, 1.0, -0.3, 0.8, -1.9, 3.0).finished())}) {
    const Pose a = poeForwardKinematics(poe, q), b = modifiedDhForwardKinematics(m, q);
    EXPECT_LE(rotationError(a.R, b.R), 1e-14);
    EXPECT_LE((a.p - b.p).norm(), 1e-13 * poe.lengthScale());
  }
  // q must have a value per joint, in every build type
  try {
    modifiedDhForwardKinematics(m, VecX::Zero(5));
    ADD_FAILURE() << "a q of 5 values for 6 joints was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "modifiedDhForwardKinematics: q has 5 values, the model has 6 joints");
  }
}

TEST(PoeForms, ToolAndLocalRoundTrips) {
  const PoeModel poe = pumaActual();
  const VecX q = (VecX(6) << 0.1, -0.4, 2.0, -3.0, 0.5, 1.5).finished();
  const Pose ref = poeForwardKinematics(poe, q);
  const ToolPoeModel tool = toToolPoe(poe);
  const LocalPoeModel local = toLocalPoe(poe);
  for (const Pose& T : {forwardKinematics(tool, q), forwardKinematics(local, q),
                        poeForwardKinematics(fromToolPoe(tool), q), poeForwardKinematics(fromLocalPoe(local), q)}) {
    EXPECT_LE(rotationError(ref.R, T.R), 1e-14);
    EXPECT_LE((ref.p - T.p).norm(), 1e-13 * poe.lengthScale());
  }
  // local twists are [0 0 1 0 0 h]
  for (size_t i = 0; i < local.joints.size(); ++i) {
    Vec6 expect;
    expect << 0, 0, 1, 0, 0, local.joints[i].pitch;
    EXPECT_LE((local.joints[i].twist - expect).cwiseAbs().maxCoeff(), 1e-13);
  }
}

TEST(JointNormalization, TypesAndErrors) {
  JointSpec s;
  s.twist = twist(0, 0, 2, 1, 0, 0);
  Joint j = normalizeJoint(s, 0);
  EXPECT_EQ(j.type, JointType::Revolute);
  EXPECT_EQ(j.scale, 2.0);
  s.twist = twist(0, 0, 2, 1, 0, 0.1);
  EXPECT_EQ(normalizeJoint(s, 0).type, JointType::Helical);
  EXPECT_DOUBLE_EQ(normalizeJoint(s, 0).pitch, 0.05);  // w.v / |w|^2 = 0.2 / 4
  s.type = JointType::Revolute;
  EXPECT_THROW(normalizeJoint(s, 0), std::invalid_argument);  // helical twist declared revolute
  s.type = JointType::Prismatic;
  EXPECT_THROW(normalizeJoint(s, 0), std::invalid_argument);
  s.type.reset();
  s.twist = Vec6::Zero();
  EXPECT_THROW(normalizeJoint(s, 0), std::invalid_argument);
  s.twist = twist(0, 0, 1, NAN, 0, 0);
  EXPECT_THROW(normalizeJoint(s, 0), std::invalid_argument);
  s.twist = twist(0, 0, 0, 0, 3, 4);
  s.type = JointType::Revolute;
  EXPECT_THROW(normalizeJoint(s, 0), std::invalid_argument);
  // the actual PUMA's tiny pitch survives (8e-7 mm/rad on a 250 mm arm)
  s.type.reset();
  s.twist = twist(0.001, -1.00004, 0, -20.6, -0.0206, -249);
  const Joint tiny = normalizeJoint(s, 4);
  EXPECT_EQ(tiny.type, JointType::Helical);
  EXPECT_NEAR(tiny.pitch, 8.24e-7 / (1.00004 * 1.00004 + 1e-6), 1e-10);
}
