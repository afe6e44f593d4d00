// The base frame as the gauge (base_frame.hpp): the rule recovers a rigid motion of any robot to rounding,
// and its degenerate geometries (parallel, nearly parallel, intersecting axes, prismatic joint 1, axes along z).
#include <gtest/gtest.h>

#include <random>

#include "lowpair/base_frame.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/registration.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "random_robot.hpp"

namespace {

using namespace lowpair;
using lowpair_test::randomRobot;

Pose randomMotion(std::mt19937_64& rng, double distance) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec6 xi;
  xi << 3.0 * lowpair_test::draw3(u, rng), distance * lowpair_test::draw3(u, rng);
  return expSE3(xi);
}

// The rule's conditioning: 1 / the sine of the angle between joint 1 and the joints the rule uses.
double conditioning(const PoeModel& m, const BaseFrameRule& rule) {
  auto dir = [&](int k) { return m.joint(k).type == JointType::Prismatic ? m.joint(k).moment() : m.joint(k).axis(); };
  double c = 1.0;
  for (const int k : {rule.foot_joint, rule.direction_joint}) {
    if (k >= 0) c = std::max(c, 1.0 / dir(0).cross(dir(k)).norm());
  }
  return c;
}

// Moves `m` by T and checks that the rule gives T back: the moved model's frame is T times the model's, and
// toNominalBase puts the moved model back where it was (forward kinematics at a few configurations).
void expectRecovers(const PoeModel& m, const Pose& T, const std::string& what, double* worst = nullptr) {
  const BaseFrameRule rule = baseFrameRule(m);
  const PoeModel moved = movedModel(m, T);
  const BaseFrameGauge g = toNominalBase(moved, m, rule);
  const double L = m.lengthScale(), reach = L + T.p.norm();
  const double cond = conditioning(m, rule);
  const double rotation = rotationAngle(g.T_measurement_base.R.transpose() * T.R);
  const double position = (g.T_measurement_base.p - T.p).norm();
  const double tolerance = 1e3 * kEps * cond * cond;  // relative to the reach (angles: rad)
  EXPECT_LE(rotation, tolerance) << what;
  EXPECT_LE(position, tolerance * reach) << what;
  if (worst) *worst = std::max({*worst, rotation / (kEps * cond * cond), position / (kEps * cond * cond * reach)});
  // the frame of the model put back is the nominal's
  const Pose F = baseFrame(g.model, rule), F0 = baseFrame(m, rule);
  EXPECT_LE(rotationAngle(F.R.transpose() * F0.R), tolerance) << what;
  EXPECT_LE((F.p - F0.p).norm(), tolerance * reach) << what;
  // and the robot too
  std::mt19937_64 rng(7);
  Data a(m), b(g.model);
  for (int s = 0; s < 3; ++s) {
    const VecX q = lowpair_test::randomConfiguration(m, rng);
    forwardKinematics(m, a, q);
    forwardKinematics(g.model, b, q);
    EXPECT_LE((a.T_base_tool.p - b.T_base_tool.p).norm(), 10 * tolerance * reach) << what;
  }
}

TEST(BaseFrame, RandomRobotsMovedByARandomMotionComeBack) {
  std::mt19937_64 rng(20260126);
  double worst = 0.0;
  for (int r = 0; r < lowpair_test::robotCount(500); ++r) {
    const lowpair_test::RandomRobot robot = randomRobot(rng);
    const double L = robot.model.lengthScale();
    expectRecovers(robot.model, randomMotion(rng, 10.0 * L),
                   "robot " + std::to_string(r) + " (" + lowpair_test::geometryName(robot.geometry) + ")", &worst);
  }
  std::printf("worst error over eps cond^2 (times the reach for positions): %.3g\n", worst);
}

// The PUMA of Wu et al.'s Table I: joint 1 along z through the origin, joint 2 along -y through it
// (intersecting): the rule's frame is the base frame itself.
PoeModel puma() {
  std::vector<JointSpec> j(6);
  j[0].twist << 0, 0, 1, 0, 0, 0;
  j[1].twist << 0, -1, 0, 0, 0, 0;
  j[2].twist << 0, -1, 0, 0, 0, -100;
  j[3].twist << 0, 0, -1, -50, 250, 0;
  j[4].twist << 0, -1, 0, -20, 0, -250;
  j[5].twist << 0, 0, -1, -50, 250, 0;
  Vec6 tool;
  tool << 0, 0, 0, 250, 50, -20;
  return PoeModel(j, expSE3(tool));
}

TEST(BaseFrame, IntersectingAxesAlongZ) {
  const PoeModel m = puma();
  const BaseFrameRule rule = baseFrameRule(m);
  EXPECT_EQ(rule.foot_joint, 1);
  EXPECT_EQ(rule.direction_joint, 1);
  const Pose F = baseFrame(m, rule);
  EXPECT_LE((F.matrix() - Mat4::Identity()).norm(), 4 * kEps);
  std::mt19937_64 rng(1);
  for (int k = 0; k < 20; ++k) expectRecovers(m, randomMotion(rng, 3400.0), "puma");
}

TEST(BaseFrame, SkewAxesFootIsTheCommonNormal) {
  // joint 1 along z through (1, 2, 0); joint 2 along x through (0, 0, 5) offset by 3 in y: foot at z = 5
  std::vector<JointSpec> j(2);
  const Vec3 p1(1, 2, 0), w1(0, 0, 1), p2(0, 5, 5), w2(1, 0, 0);
  j[0].twist << w1, p1.cross(w1);
  j[1].twist << w2, p2.cross(w2);
  const PoeModel m(j, Pose{Mat3::Identity(), Vec3(4, 5, 6)});
  const Pose F = baseFrame(m, baseFrameRule(m));
  EXPECT_LE((F.p - Vec3(1, 2, 5)).norm(), 16 * kEps * 10);
  EXPECT_LE((F.R.col(0) - w1.cross(w2)).norm(), 16 * kEps);
}

TEST(BaseFrame, ParallelJoint2UsesTheFirstNonParallelAxis) {
  // SCARA-like: joints 1, 2 parallel (z), joint 3 along x: foot and x from joint 3
  std::vector<JointSpec> j(3);
  const Vec3 z(0, 0, 1), x(1, 0, 0);
  j[0].twist << z, Vec3::Zero();
  j[1].twist << z, Vec3(300, 0, 0).cross(z);
  j[2].twist << x, Vec3(0, 0, 400).cross(x);
  const PoeModel m(j, Pose{Mat3::Identity(), Vec3(500, 0, 400)});
  const BaseFrameRule rule = baseFrameRule(m);
  EXPECT_EQ(rule.foot_joint, 2);
  EXPECT_EQ(rule.direction_joint, 2);
  EXPECT_LE((baseFrame(m, rule).p - Vec3(0, 0, 400)).norm(), 16 * kEps * 400);
  std::mt19937_64 rng(2);
  for (int k = 0; k < 20; ++k) expectRecovers(m, randomMotion(rng, 3000.0), "parallel");
}

TEST(BaseFrame, AllAxesParallelUseTheToolPoint) {
  // a planar arm: every axis along z; origin the tool point's projection, x toward the tool point
  std::vector<JointSpec> j(3);
  const Vec3 z(0, 0, 1);
  j[0].twist << z, Vec3(10, 20, 0).cross(z);
  j[1].twist << z, Vec3(300, 20, 0).cross(z);
  j[2].twist << z, Vec3(600, 20, 0).cross(z);
  const PoeModel m(j, Pose{Mat3::Identity(), Vec3(700, 20, 50)});
  const BaseFrameRule rule = baseFrameRule(m);
  EXPECT_EQ(rule.foot_joint, -1);
  EXPECT_EQ(rule.direction_joint, -1);
  EXPECT_EQ(rule.fallback, BaseFrameRule::XFallback::ToolPoint);
  const Pose F = baseFrame(m, rule);
  EXPECT_LE((F.p - Vec3(10, 20, 50)).norm(), 16 * kEps * 700);  // the tool point's size
  EXPECT_LE((F.R.col(0) - Vec3(1, 0, 0)).norm(), 16 * kEps);
  std::mt19937_64 rng(3);
  for (int k = 0; k < 20; ++k) expectRecovers(m, randomMotion(rng, 3000.0), "planar");
}

TEST(BaseFrame, NearlyParallelIsDecidedOnTheNominal) {
  // the nominal's joint 2 is parallel to joint 1; a calibrated one tilted by 1e-3 (inside the band) and by
  // 0.02 (outside it) is placed by the nominal's choice (joint 3), not switched to joint 2
  std::vector<JointSpec> j(3);
  const Vec3 z(0, 0, 1), x(1, 0, 0);
  j[0].twist << z, Vec3::Zero();
  j[1].twist << z, Vec3(300, 0, 0).cross(z);
  j[2].twist << x, Vec3(0, 0, 400).cross(x);
  const PoeModel nominal(j, Pose{Mat3::Identity(), Vec3(500, 0, 400)});
  const BaseFrameRule rule = baseFrameRule(nominal);
  ASSERT_EQ(rule.foot_joint, 2);
  std::mt19937_64 rng(4);
  for (const double tilt : {1e-9, 1e-3, 2e-2}) {
    std::vector<JointSpec> k = j;
    const Vec3 w = expSO3(Vec3(tilt, 0, 0)) * z;
    k[1].twist << w, Vec3(300, 0, 0).cross(w);
    const PoeModel calibrated(k, nominal.toolPose());
    const BaseFrameGauge g = toNominalBase(movedModel(calibrated, randomMotion(rng, 2000.0)), nominal);
    EXPECT_EQ(g.rule.foot_joint, 2);
    // joint 1's line and the foot are the nominal's: the moved-back joint 1 is the nominal's
    // rounding of a motion of 2000 and its inverse on a robot of reach 700: 64 eps times their sum
    const double moved = 64 * kEps * (2000 + 700);
    EXPECT_LE((g.model.joint(0).twist - nominal.joint(0).twist).norm(), moved) << tilt;
    EXPECT_LE((baseFrame(g.model, rule).p - baseFrame(nominal, rule).p).norm(), moved) << tilt;
  }
}

TEST(BaseFrame, PrismaticJoint1TakesItsLineThroughTheToolPoint) {
  // a gantry-like robot: joint 1 prismatic along x, joint 2 revolute along z, joint 3 prismatic along z
  std::vector<JointSpec> j(3);
  j[0].twist << Vec3::Zero(), Vec3(1, 0, 0);
  j[0].range = std::array<double, 2>{-500, 500};
  j[1].twist << Vec3(0, 0, 1), Vec3(0, 200, 0).cross(Vec3(0, 0, 1));
  j[2].twist << Vec3::Zero(), Vec3(0, 0, 1);
  j[2].range = std::array<double, 2>{-100, 100};
  const PoeModel m(j, Pose{Mat3::Identity(), Vec3(50, 300, 100)});
  const BaseFrameRule rule = baseFrameRule(m);
  EXPECT_EQ(rule.foot_joint, 1);
  EXPECT_EQ(rule.direction_joint, 1);
  // line 1: along x through (50, 300, 100); joint 2's axis: along z through (0, 200): the foot is (0, 300, 100)
  const Pose F = baseFrame(m, rule);
  EXPECT_LE((F.p - Vec3(0, 300, 100)).norm(), 16 * kEps * 400);
  EXPECT_LE((F.R.col(2) - Vec3(1, 0, 0)).norm(), 16 * kEps);
  std::mt19937_64 rng(5);
  for (int k = 0; k < 20; ++k) expectRecovers(m, randomMotion(rng, 3000.0), "prismatic joint 1");
}

TEST(BaseFrame, CartesianRobotUsesTheToolPoint) {
  // PPP: directions only; x from joint 2's direction, the origin the tool point
  std::vector<JointSpec> j(3);
  for (int i = 0; i < 3; ++i) {
    j[static_cast<size_t>(i)].twist << Vec3::Zero(), Vec3::Unit(i);
    j[static_cast<size_t>(i)].range = std::array<double, 2>{-1, 1};
  }
  const PoeModel m(j, Pose{Mat3::Identity(), Vec3(0.1, 0.2, 0.3)});
  const BaseFrameRule rule = baseFrameRule(m);
  EXPECT_EQ(rule.foot_joint, -1);
  EXPECT_EQ(rule.direction_joint, 1);
  std::mt19937_64 rng(6);
  for (int k = 0; k < 20; ++k) expectRecovers(m, randomMotion(rng, 3.0), "cartesian");
}

}  // namespace
