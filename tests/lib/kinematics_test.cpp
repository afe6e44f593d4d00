// Forward kinematics (kinematics.hpp): the compiled chain against the product of exponentials it
// replaces (eq. 5, evaluated independently with expSE3 in long double-free double arithmetic), the
// frame convention of Data::T_base_joint, the batch form against single calls, the sine/cosine kernel
// against long double, and huge joint values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "expect_invalid.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "random_robot.hpp"
#include "sincos.hpp"

using namespace lowpair;
using lowpair_test::expectInvalid;

namespace {

// g(q) = exp(xi_1 x_1) ... exp(xi_n x_n) exp(xi_T) with the twists as the user gave them (eq. 5),
// and the prefix products (the frames' lines) on the way.
Pose productOfExponentials(const PoeModel& model, const VecX& q, std::vector<Pose>* prefix = nullptr) {
  Pose T;
  for (int i = 0; i < model.dof(); ++i) {
    if (prefix) prefix->push_back(T);
    const Joint& j = model.joint(i);
    T = T * expSE3(j.twist * j.motion(q[i]));
  }
  return T * model.toolPose();
}

// Rounding bound of a chain of n links of size up to L: each link adds a few eps of relative error in
// its rotation and a few eps L in its position; 64 n eps covers the constants with margin (measured
// worst below is printed as a property).
double bound(int n) { return 64.0 * std::max(n, 1) * std::numeric_limits<double>::epsilon(); }

}  // namespace

TEST(ForwardKinematics, EqualsProductOfExponentialsOnRandomRobots) {
  std::mt19937_64 rng(81);
  double worst_rotation = 0, worst_translation = 0;
  for (int r = 0; r < 3000; ++r) {
    const lowpair_test::RandomRobot robot = lowpair_test::randomRobot(rng);
    const PoeModel& model = robot.model;
    Data data(model);
    for (int s = 0; s < 5; ++s) {
      const VecX q = lowpair_test::randomConfiguration(model, rng);
      forwardKinematics(model, data, q);
      const Pose ref = productOfExponentials(model, q);
      const double rot = rotationError(data.T_base_tool.R, ref.R);
      const double tr = (data.T_base_tool.p - ref.p).norm() / model.lengthScale();
      worst_rotation = std::max(worst_rotation, rot);
      worst_translation = std::max(worst_translation, tr);
      ASSERT_LE(rot, bound(model.dof())) << lowpair_test::geometryName(robot.geometry) << " robot " << r;
      ASSERT_LE(tr, bound(model.dof())) << lowpair_test::geometryName(robot.geometry) << " robot " << r;
    }
  }
  RecordProperty("worst_rotation", std::to_string(worst_rotation));
  RecordProperty("worst_translation_over_L", std::to_string(worst_translation));
}

// T_base_joint[i]: z along joint i's current line, origin on it, moved by joints 1..i-1 only (the
// line of Ad(exp(xi_1 x_1) ... exp(xi_{i-1} x_{i-1})) xi_i).
TEST(ForwardKinematics, JointFramesLieOnTheCurrentJointLines) {
  std::mt19937_64 rng(82);
  for (int r = 0; r < 1000; ++r) {
    const PoeModel model = lowpair_test::randomRobot(rng).model;
    Data data(model);
    const VecX q = lowpair_test::randomConfiguration(model, rng);
    forwardKinematicsWithFrames(model.chain(), data, q);
    std::vector<Pose> prefix;
    productOfExponentials(model, q, &prefix);
    const double tol = bound(model.dof());
    for (int i = 0; i < model.dof(); ++i) {
      const Joint& j = model.joint(i);
      const Vec6 xi = adjointApply(prefix[static_cast<size_t>(i)], j.twist);
      const Pose& F = data.T_base_joint[static_cast<size_t>(i)];
      const Vec3 z = F.R.col(2);
      if (j.type == JointType::Prismatic) {
        EXPECT_LE((z - xi.tail<3>()).norm(), tol) << "robot " << r << " joint " << i;
        continue;
      }
      EXPECT_LE((z - xi.head<3>()).norm(), tol) << "robot " << r << " joint " << i;
      // the origin is on the line: its moment o x w equals v - h w
      const Vec3 moment = xi.tail<3>() - j.pitch * xi.head<3>();
      EXPECT_LE((F.p.cross(z) - moment).norm(), tol * model.lengthScale()) << "robot " << r << " joint " << i;
      EXPECT_LE((F.R.transpose() * F.R - Mat3::Identity()).norm(), tol);
    }
  }
}

TEST(ForwardKinematics, DhModelEqualsItsPoeEquivalent) {
  // a D-H chain with every joint type and nonzero offsets, against dhToPoe's product of exponentials
  std::vector<DhJoint> joints(4);
  joints[0].link = {0.1, 0.2, 1.2, 0.3};
  joints[1].type = JointType::Helical;
  joints[1].pitch = 0.05;
  joints[1].offset = 0.4;
  joints[1].link = {-0.3, 0.0, -0.7, 0.5};
  joints[2].type = JointType::Prismatic;
  joints[2].scale = 2.0;
  joints[2].link = {0.0, 0.1, 0.0, 0.2};  // alpha = 0: the next axis is parallel
  joints[3].scale = 0.5;
  joints[3].link = {0.2, 0.3, 0.4, 0.0};
  const DhModel dh({0.3, 0.1, 0.2, 0.4}, joints, 0.5, 0.25, "all-types");
  const PoeModel poe = dhToPoe(dh);
  Data data(dh);
  std::mt19937_64 rng(83);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int s = 0; s < 200; ++s) {
    VecX q(4);
    for (int i = 0; i < 4; ++i) q[i] = u(rng);
    forwardKinematics(dh, data, q);
    const Pose ref = productOfExponentials(poe, q);
    EXPECT_LE(rotationError(data.T_base_tool.R, ref.R), bound(4));
    EXPECT_LE((data.T_base_tool.p - ref.p).norm(), bound(4) * dh.lengthScale());
  }
}

TEST(ForwardKinematics, BatchEqualsSingleCalls) {
  std::mt19937_64 rng(84);
  for (int r = 0; r < 300; ++r) {
    const PoeModel model = lowpair_test::randomRobot(rng).model;
    const DhConversion conversion = poeToDh(model);
    const DhModel& dh = conversion.model;
    const int count = 1 + r % 29;  // full and partial blocks
    MatX q(count, model.dof());
    for (int k = 0; k < count; ++k) q.row(k) = lowpair_test::randomConfiguration(model, rng).transpose();
    MatX poses(count, 12), poses_dh(count, 12);
    forwardKinematicsBatch(model, q, poses);
    forwardKinematicsBatch(dh, q, poses_dh);
    Data data(model), data_dh(dh);
    for (int k = 0; k < count; ++k) {
      const VecX qk = q.row(k).transpose();
      forwardKinematics(model, data, qk);
      forwardKinematics(dh, data_dh, qk);
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          EXPECT_LE(std::abs(poses(k, 3 * a + b) - data.T_base_tool.R(a, b)), bound(model.dof()));
          EXPECT_LE(std::abs(poses_dh(k, 3 * a + b) - data_dh.T_base_tool.R(a, b)), bound(model.dof()));
        }
        EXPECT_LE(std::abs(poses(k, 9 + a) - data.T_base_tool.p[a]), bound(model.dof()) * model.lengthScale());
        // the D-H table's own scale max(L, |d|, |a|) (docs/conversion.md): near parallel axes |d| can be
        // 1e10 L, and single and batch forms round the cancelling terms differently
        EXPECT_LE(std::abs(poses_dh(k, 9 + a) - data_dh.T_base_tool.p[a]), bound(model.dof()) * conversion.scale);
      }
    }
  }
}

TEST(ForwardKinematics, HugeJointValuesStayAccurate) {
  // beyond the sine kernel's range the chain falls back to libm: still the product of exponentials
  std::vector<JointSpec> specs(2);
  specs[0].twist << 0, 0, 1, 0, 0, 0;
  specs[1].twist << 1, 0, 0, 0, 0.5, 0;
  Pose tool;
  tool.p << 0.3, 0.2, 0.1;
  const PoeModel model(specs, tool);
  Data data(model);
  for (const double big : {1e6, 3e7, 1e12, -5e13}) {
    const VecX q = (VecX(2) << big, -big / 3).finished();
    forwardKinematics(model, data, q);
    const Pose ref = productOfExponentials(model, q);
    // a joint angle |x| is itself known to half an ulp (eps |x| / 2), and each form rounds its own sum
    // `theta + x` once: the two may differ by about eps |x| per joint, whatever the algorithm
    const double tol = bound(2) + 2.0 * std::numeric_limits<double>::epsilon() * std::abs(big);
    EXPECT_TRUE(data.T_base_tool.R.allFinite() && data.T_base_tool.p.allFinite()) << big;
    EXPECT_LE(rotationError(data.T_base_tool.R, ref.R), tol) << big;
    EXPECT_LE((data.T_base_tool.p - ref.p).norm(), tol) << big;
  }
}

TEST(JointLimits, BoundTheSlideAtTheCauseOfNonFinitePoses) {
  // joint 1 revolute (scale 2), joint 2 prismatic (scale 10), joint 3 helical (pitch 1e3): each at the largest value its
  // limit admits gives finite poses; the next double up is refused, and at 1e308 the pose is not finite
  std::vector<JointSpec> specs(3);
  specs[0].twist << 0, 0, 2, 0, 0, 0;  // (an unnormalized twist: its norm is the scale)
  specs[1].twist << 0, 0, 0, 10, 0, 0;
  specs[1].type = JointType::Prismatic;
  specs[2].twist << 0, 0, 1, 0, 0, 1e3;  // v = pitch w: a helical joint through the origin
  specs[2].type = JointType::Helical;
  const PoeModel model(specs, Pose{});
  Data data(model);
  const double limits[3] = {kMaxMagnitude / 2.0, kMaxMagnitude / 10.0, kMaxMagnitude / 1e3};
  for (int i = 0; i < 3; ++i) {
    VecX q = VecX::Zero(3);
    q[i] = limits[i] * (1 - 1e-15);  // (the limit divided by the scale or pitch rounds: stay a few ulps inside)
    EXPECT_EQ(firstJointBeyondLimits(model, q), -1) << i;
    forwardKinematics(model, data, q);
    EXPECT_TRUE(data.T_base_tool.R.allFinite() && data.T_base_tool.p.allFinite()) << i;
    q[i] = limits[i] * (1 + 1e-15);
    EXPECT_EQ(firstJointBeyondLimits(model, q), i) << i;
    q[i] = -q[i];
    EXPECT_EQ(firstJointBeyondLimits(model, q), i) << i;
    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
      q[i] = bad;
      EXPECT_EQ(firstJointBeyondLimits(model, q), i) << i;
    }
  }
  // what the bound prevents: q2 = 1e308 slides 10 x 1e308, an infinite position
  forwardKinematics(model, data, (VecX(3) << 0.0, 1e308, 0.0).finished());
  EXPECT_FALSE(data.T_base_tool.p.allFinite());
  expectInvalid([&] { firstJointBeyondLimits(model, VecX::Zero(2)); }, "firstJointBeyondLimits: q has 2 values, the model has 3 joints");
}

// ---- size checks ---------------------------------------------------------------------------------------
//
// Every function that takes q, a batch or a Data checks their sizes in every build type (this suite runs
// in Release): a wrong size is std::invalid_argument naming the function and both numbers, never a write
// past a buffer. A Data made for a model with fewer joints used to be an out-of-bounds write in Release.

namespace {

// n revolute joints about z through (i, 0, 0), a tool at (n, 0, 0).
PoeModel planarChain(int n) {
  std::vector<JointSpec> specs(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) specs[static_cast<size_t>(i)].twist << 0, 0, 1, 0, -i, 0;
  Pose tool;
  tool.p << n, 0, 0;
  return PoeModel(specs, tool, std::to_string(n) + "R");
}

}  // namespace

TEST(SizeChecks, ForwardKinematicsRejectsWrongQAndForeignData) {
  const PoeModel poe5 = planarChain(5), poe6 = planarChain(6), poe7 = planarChain(7);
  const DhModel dh6 = poeToDh(poe6).model;
  Data data5(poe5), data6(poe6), data7(poe7), data_dh6(dh6);
  const VecX q5 = VecX::Constant(5, 0.1), q6 = VecX::Constant(6, 0.1), q7 = VecX::Constant(7, 0.1);

  expectInvalid([&] { forwardKinematics(poe6, data6, q5); }, "forwardKinematics: q has 5 values, the model has 6 joints");
  expectInvalid([&] { forwardKinematics(poe6, data6, q7); }, "forwardKinematics: q has 7 values, the model has 6 joints");
  expectInvalid([&] { forwardKinematics(poe6, data7, q6); },
                "forwardKinematics: data was made for a model with 7 joints, this model has 6");
  expectInvalid([&] { forwardKinematics(poe6, data5, q6); },
                "forwardKinematics: data was made for a model with 5 joints, this model has 6");
  expectInvalid([&] { forwardKinematics(dh6, data_dh6, q5); }, "forwardKinematics: q has 5 values, the model has 6 joints");
  expectInvalid([&] { forwardKinematics(dh6, data7, q6); },
                "forwardKinematics: data was made for a model with 7 joints, this model has 6");
  expectInvalid([&] { forwardKinematics(poe7, data7, VecX(0)); }, "forwardKinematics: q has 0 values, the model has 7 joints");

  expectInvalid([&] { forwardKinematicsWithFrames(poe6.chain(), data6, q7); },
                "forwardKinematicsWithFrames: q has 7 values, the model has 6 joints");
  expectInvalid([&] { forwardKinematicsWithFrames(poe6.chain(), data5, q6); },
                "forwardKinematicsWithFrames: data was made for a model with 5 joints, this model has 6");

  expectInvalid([&] { poeForwardKinematics(poe6, q5); }, "poeForwardKinematics: q has 5 values, the model has 6 joints");
  expectInvalid([&] { dhForwardKinematics(dh6, q7); }, "dhForwardKinematics: q has 7 values, the model has 6 joints");
  expectInvalid([&] { forwardKinematics(toToolPoe(poe6), q5); }, "forwardKinematics: q has 5 values, the model has 6 joints");
  expectInvalid([&] { forwardKinematics(toLocalPoe(poe6), q7); }, "forwardKinematics: q has 7 values, the model has 6 joints");
  const PoeModel poe1 = planarChain(1), poe2 = planarChain(2);
  Data data1(poe1), data2(poe2);
  expectInvalid([&] { forwardKinematics(poe2, data2, VecX::Zero(1)); }, "forwardKinematics: q has 1 value, the model has 2 joints");
  expectInvalid([&] { forwardKinematics(poe2, data1, VecX::Zero(2)); },
                "forwardKinematics: data was made for a model with 1 joint, this model has 2");

  // what fits: a Data fits every model with its number of joints (a copy, the D-H form, another robot)
  const PoeModel copy = poe6;
  EXPECT_NO_THROW(forwardKinematics(copy, data6, q6));
  EXPECT_NO_THROW(forwardKinematics(dh6, data6, q6));
  EXPECT_NO_THROW(forwardKinematicsWithFrames(dh6.chain(), data6, q6));
  // the rejected calls wrote nothing: data6 still holds the FK of q6
  forwardKinematics(poe6, data6, q6);
  const Pose before = data6.T_base_tool;
  EXPECT_THROW(forwardKinematics(poe6, data6, q5), std::invalid_argument);
  EXPECT_EQ(data6.T_base_tool.matrix(), before.matrix());
}

TEST(SizeChecks, BatchRejectsWrongColumnsAndPoses) {
  const PoeModel poe6 = planarChain(6);
  const DhModel dh6 = poeToDh(poe6).model;
  MatX poses(10, 12);
  expectInvalid([&] { forwardKinematicsBatch(poe6, MatX::Zero(10, 5), poses); },
                "forwardKinematicsBatch: q has 5 columns, the model has 6 joints");
  expectInvalid([&] { forwardKinematicsBatch(dh6, MatX::Zero(10, 7), poses); },
                "forwardKinematicsBatch: q has 7 columns, the model has 6 joints");
  expectInvalid([&] { forwardKinematicsBatch(poe6, MatX::Zero(11, 6), poses); },
                "forwardKinematicsBatch: poses is 10 x 12, expected 11 x 12 (a row per configuration of q)");
  MatX narrow(10, 9);
  expectInvalid([&] { forwardKinematicsBatch(dh6, MatX::Zero(10, 6), narrow); },
                "forwardKinematicsBatch: poses is 10 x 9, expected 10 x 12 (a row per configuration of q)");
  EXPECT_NO_THROW(forwardKinematicsBatch(poe6, MatX::Zero(10, 6), poses));
}

TEST(SinCos, WithinOneUlpOverJointRanges) {
  const double eps = std::numeric_limits<double>::epsilon();
  std::mt19937_64 rng(3);
  std::vector<double> x;
  std::uniform_real_distribution<double> small(-4 * M_PI, 4 * M_PI), large(-1e6, 1e6);
  for (int i = 0; i < 200000; ++i) x.push_back(small(rng));
  for (int i = 0; i < 20000; ++i) x.push_back(large(rng));
  for (int k = -8; k <= 8; ++k) {  // around the quadrant boundaries and the zeros
    for (int j = -50; j <= 50; ++j) x.push_back(k * M_PI / 4 + j * 1e-9);
  }
  double abs_err = 0.0;
  for (const double xi : x) {
    double s = 0, c = 0;
    detail::sinCosLane(xi, s, c);
    const long double xs = std::sin(static_cast<long double>(xi)), xc = std::cos(static_cast<long double>(xi));
    abs_err = std::max(abs_err, static_cast<double>(std::max(std::abs(s - xs), std::abs(c - xc))) / eps);
  }
  RecordProperty("max_abs_error_eps", std::to_string(abs_err));
  EXPECT_LE(abs_err, 1.2);
}
