// The compliant actual robot (harness/mujoco/compliant_actual.hpp): joint springs at rest under gravity.
//
// - A pendulum (hinge about +y, m at r along x, gravity -z): G(theta) = m g r cos(theta), so the rest angle
//   solves k d = m g r cos(q + d), solved here in long double; the tip at rest is (r cos, 0, -r sin).
// - A lift (slide along z carrying m): k d = -m g exactly.
// - An upright pendulum on a spring softer than m g r: an equilibrium (G = 0), unstable.
// - PUMA-like arms (random masses, mass_variants.hpp) with stiffness 1e4 and 1e5 (Corke's, in metres), and
//   100 W and 1000 W (the Okamura actual, in mm, with helical joints):
//   the rest balances MuJoCo's gravity force computed apart (MujocoDynamics::Evaluator, springs by hand),
//   and x_eq - x = G(x)/k to first order: the remainder (G(x_eq) - G(x))/k is at most
//   n max|dG_i/dx_j| |d| / k <= n W |d| / k, W = sum_k m_k |g| (|com_k| + L), and scales as 1/k^2
//   (ten times the stiffness: a hundredth of the remainder).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "mass_variants.hpp"
#include "mujoco/compliant_actual.hpp"
#include "mujoco/mujoco_dynamics.hpp"

using namespace lowpair;
using namespace lowpair::mujoco;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kMass = 2.0, kRadius = 0.5, kG = 9.81;

const char* const kPendulum = R"(<mujoco model="pendulum">
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="arm">
      <joint name="j" type="hinge" axis="0 1 0"/>
      <inertial pos="0.5 0 0" mass="2" diaginertia="0.01 0.01 0.01"/>
      <site name="tool" pos="0.5 0 0"/>
    </body>
  </worldbody>
</mujoco>
)";

// the root of k d = m g r cos(q + d) (increasing in d for k > m g r), Newton in long double
double pendulumRest(double k, double q) {
  const long double mgr = static_cast<long double>(kMass) * kG * kRadius;
  long double d = 0;
  for (int i = 0; i < 100; ++i) d -= (k * d - mgr * std::cos(q + d)) / (k + mgr * std::sin(q + d));
  return static_cast<double>(d);
}

TEST(CompliantActual, PendulumRestsWhereTheSpringHoldsItsWeight) {
  const std::string path = mass_variants::scratch().write("pendulum.xml", kPendulum);
  const MujocoRobot robot(path, "tool");
  const MujocoDynamics dynamics(robot);
  for (double k : {50.0, 1e3, 1e5}) {
    CompliantActual actual(dynamics, VecX::Constant(1, k));
    for (double q : {-1.2, 0.0, 0.4, 2.0}) {
      const Equilibrium eq = actual.settle(VecX::Constant(1, q));
      const double d = pendulumRest(k, q);
      SCOPED_TRACE("k " + std::to_string(k) + " q " + std::to_string(q));
      EXPECT_TRUE(eq.converged) << eq.residual;
      EXPECT_TRUE(eq.stable);
      EXPECT_LE(eq.iterations, 6);
      EXPECT_LE(eq.residual, kSettleTolerance);
      // the solver's tolerance plus the rounding of q + d
      EXPECT_NEAR(eq.x[0] - q, d, kSettleTolerance + 8 * kEps) << "deflection " << d;
      const double theta = q + d;
      EXPECT_LE((eq.T_base_tip.p - Vec3(kRadius * std::cos(theta), 0, -kRadius * std::sin(theta))).norm(),
                kRadius * (kSettleTolerance + 8 * kEps));
      std::printf("pendulum k %g q %g: deflection %.6g, iterations %d, residual %.3g\n", k, q, d, eq.iterations,
                  eq.residual);
    }
  }
}

TEST(CompliantActual, LiftSinksByItsWeightOverTheStiffness) {
  const std::string path = mass_variants::scratch().write("lift.xml", R"(<mujoco><option gravity="0 0 -9.81"/>
    <worldbody><body name="car"><joint name="z" type="slide" axis="0 0 1"/>
    <inertial pos="0.3 0.1 0" mass="3" diaginertia="0.01 0.01 0.01"/><site name="tool"/></body></worldbody></mujoco>)");
  const MujocoRobot robot(path, "tool");
  const MujocoDynamics dynamics(robot);
  CompliantActual actual(dynamics, VecX::Constant(1, 1e4));
  const Equilibrium eq = actual.settle(VecX::Constant(1, 0.2));
  ASSERT_TRUE(eq.converged);
  EXPECT_NEAR(eq.x[0] - 0.2, -3 * kG / 1e4, kSettleTolerance + 4 * kEps);
  EXPECT_NEAR(eq.T_base_tip.p.z(), 0.2 - 3 * kG / 1e4, kSettleTolerance + 4 * kEps);
}

TEST(CompliantActual, UprightPendulumOnASoftSpringIsAnUnstableRest) {
  const std::string path = mass_variants::scratch().write("upright.xml", kPendulum);
  const MujocoRobot robot(path, "tool");
  const MujocoDynamics dynamics(robot);
  // upright: theta = -pi/2 (tip at z = +r), G = 0; dG/dtheta = m g r = 9.81 > k = 5
  CompliantActual soft(dynamics, VecX::Constant(1, 5.0));
  const Equilibrium eq = soft.settle(VecX::Constant(1, -M_PI / 2));
  EXPECT_TRUE(eq.converged);
  EXPECT_FALSE(eq.stable);
  CompliantActual stiff(dynamics, VecX::Constant(1, 20.0));
  EXPECT_TRUE(stiff.settle(VecX::Constant(1, -M_PI / 2)).stable);
}

TEST(CompliantActual, RigidJointsStayAndBadStiffnessIsRejected) {
  std::string puma;
  for (const auto& v : mass_variants::variants(11)) {
    if (v.name == "puma560_corke.xml") puma = v.path;
  }
  const MujocoRobot robot(puma, "tool");
  const MujocoDynamics dynamics(robot);
  VecX k = VecX::Constant(6, 1e4);
  k[1] = 0;
  k[2] = std::numeric_limits<double>::infinity();
  CompliantActual actual(dynamics, k);
  const VecX x = VecX::LinSpaced(6, -1, 1);
  const Equilibrium eq = actual.settle(x);
  ASSERT_TRUE(eq.converged);
  EXPECT_EQ(eq.x[1], x[1]);
  EXPECT_EQ(eq.x[2], x[2]);
  EXPECT_NE(eq.x[0], x[0]);
  EXPECT_THROW(CompliantActual(dynamics, VecX::Constant(5, 1e4)), std::invalid_argument);
  VecX bad = VecX::Constant(6, 1e4);
  bad[3] = -1;
  EXPECT_THROW(CompliantActual(dynamics, bad), std::invalid_argument);
  bad[3] = std::nan("");
  EXPECT_THROW(CompliantActual(dynamics, bad), std::invalid_argument);
  EXPECT_THROW(actual.settle(VecX::Zero(5)), std::invalid_argument);
}

// k_soft 0: a hundred times W (a model in mm, which MuJoCo takes for metres, weighs 1000 times more per kg)
void expectFirstOrder(const std::string& path, double k_soft) {
  SCOPED_TRACE(path);
  const MujocoRobot robot(path, "tool");
  const MujocoDynamics dynamics(robot);
  const MassModel& mm = dynamics.masses().masses;
  const int n = robot.dof();
  const double L = robot.poeModel().lengthScale();
  double W = 0;
  for (const PointMass& p : mm.links) W += p.mass * mm.gravity.norm() * (p.com.norm() + L);
  MujocoDynamics::Evaluator gravity(dynamics);
  if (k_soft == 0) k_soft = 100 * W;
  CompliantActual soft(dynamics, VecX::Constant(n, k_soft)), stiff(dynamics, VecX::Constant(n, 10 * k_soft));
  std::mt19937_64 rng(2727);
  std::uniform_real_distribution<double> angle(-2.5, 2.5);
  int max_iterations = 0;
  double max_residual = 0, min_ratio = 1, max_ratio = 0;
  for (int sample = 0; sample < 20; ++sample) {
    VecX x(n);
    for (int i = 0; i < n; ++i) x[i] = angle(rng);
    const VecX G = gravity.gravityForce(x);
    double remainder[2];
    int which = 0;
    for (CompliantActual* actual : {&soft, &stiff}) {
      const double k = actual->stiffness()[0];
      const Equilibrium eq = actual->settle(x);
      ASSERT_TRUE(eq.converged) << eq.residual;
      EXPECT_TRUE(eq.stable);
      max_iterations = std::max(max_iterations, eq.iterations);
      max_residual = std::max(max_residual, eq.residual);
      const VecX d = eq.x - x;
      // the balance through MuJoCo's gravity force alone and the spring written here
      const VecX balance = (k * d - gravity.gravityForce(eq.x)) / k;
      EXPECT_LE(balance.cwiseAbs().maxCoeff(), kSettleTolerance + 16 * kEps) << balance.transpose();
      const VecX first_order = d - G / k;
      remainder[which++] = first_order.norm();
      EXPECT_LE(first_order.cwiseAbs().maxCoeff(), n * W * d.cwiseAbs().maxCoeff() / k) << first_order.transpose();
    }
    const double ratio = remainder[1] / remainder[0];
    min_ratio = std::min(min_ratio, ratio);
    max_ratio = std::max(max_ratio, ratio);
    EXPECT_GT(ratio, 0.005);
    EXPECT_LT(ratio, 0.02);
  }
  std::printf("%s: k %g and %g: iterations <= %d, residual <= %.3g, remainder ratio in [%.4g, %.4g]\n",
              path.c_str(), k_soft, 10 * k_soft, max_iterations, max_residual, min_ratio, max_ratio);
}

TEST(CompliantActual, PumaDeflectsByGravityOverStiffnessToFirstOrder) {
  const std::vector<mass_variants::Variant> variants = mass_variants::variants(2702);
  for (const auto& v : variants) {
    if (v.name == "puma560_corke.xml") expectFirstOrder(v.path, 1e4);      // metres
    if (v.name == "puma560_okamura_actual.xml") expectFirstOrder(v.path, 0);  // mm; helical joints
  }
}

}  // namespace
