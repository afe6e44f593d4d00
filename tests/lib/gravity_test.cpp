// gravityTorques (gravity.hpp) against an independent derivation: tau_i = -dU/dq_i, U(q) = -sum m g.com(q)
// (the payload too), the centres of mass moved by forward kinematics of the chain's first i joints (POE
// products of sub-models, not the twists and wrenches gravityTorques sums), differentiated by central
// differences. Random robots of every joint type and geometry (tests/common/random_robot.hpp: revolute,
// prismatic, helical, scales 0.3-3, offsets, axes along z, parallel axes), and exact cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "lowpair/gravity.hpp"
#include "lowpair/kinematics.hpp"
#include "random_robot.hpp"

namespace {

using namespace lowpair;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// The pose of link i (the body joint i moves) at q: the product of the first i joints' exponentials, as
// forward kinematics of the sub-chain with the identity tool.
Pose linkPose(const PoeModel& model, int i, const VecX& q) {
  std::vector<Joint> first(model.joints().begin(), model.joints().begin() + i + 1);
  return poeForwardKinematics(PoeModel(first, Pose{}), q.head(i + 1));
}

// Every mass's centre (length unit) at q, with its mass: the links' then the payload's.
struct Placed {
  double mass;
  Vec3 com;
};
std::vector<Placed> placed(const PoeModel& model, const MassModel& masses, const VecX& q) {
  std::vector<Placed> out;
  for (int i = 0; i < static_cast<int>(masses.links.size()); ++i) {
    out.push_back({masses.links[static_cast<size_t>(i)].mass, linkPose(model, i, q) * masses.links[static_cast<size_t>(i)].com});
  }
  out.push_back({masses.payload.mass, poeForwardKinematics(model, q) * masses.payload.com});
  return out;
}

// U(q) = -sum m g.com(q), J (com in metres)
double potential(const PoeModel& model, const MassModel& masses, const VecX& q) {
  double U = 0.0;
  for (const Placed& p : placed(model, masses, q)) U -= p.mass * masses.gravity.dot(p.com * masses.metres_per_unit);
  return U;
}

// random masses under a random gravity direction, in m or mm
MassModel randomMasses(const PoeModel& model, std::mt19937_64& rng) {
  MassModel m = lowpair_test::randomMasses(model, rng);
  m.gravity = 9.81 * lowpair_test::unitVector(rng);
  m.metres_per_unit = (rng() & 1) ? 1.0 : 1e-3;
  return m;
}

TEST(GravityTorques, EqualMinusTheGradientOfThePotentialOnRandomRobots) {
  std::mt19937_64 rng(27);
  const int robots = lowpair_test::robotCount(500);
  int checked = 0, worst_joint = -1;
  double worst = 0.0;
  for (int r = 0; r < robots; ++r) {
    const lowpair_test::RandomRobot robot = lowpair_test::randomRobot(rng);
    const PoeModel& model = robot.model;
    const MassModel masses = randomMasses(model, rng);
    const VecX q = lowpair_test::randomConfiguration(model, rng);
    const VecX tau = gravityTorques(model, masses, q);
    ASSERT_EQ(tau.size(), model.dof());
    const double L = model.lengthScale(), g = masses.gravity.norm(), mpu = masses.metres_per_unit;
    const int n = model.dof();
    // bounds: the weight times distances (metres) of every centre from the origin, and from joint i's line
    const std::vector<Placed> at_q = placed(model, masses, q);
    double weight_reach = 0.0, weight = 0.0;
    for (const Placed& p : at_q) {
      weight_reach += p.mass * g * (p.com.norm() + L) * mpu;
      weight += p.mass * g;
    }
    for (int i = 0; i < n; ++i) {
      const Joint& j = model.joint(i);
      const bool slides = j.type == JointType::Prismatic;
      // joint i alone: U(x) = A cos x + B sin x + C x + D for a turning joint (|U'''| <= the weight times the
      // distances from its line, at most |com| + |line point|); linear in x for a sliding one
      const Vec3 line_point = i == 0 ? Vec3(j.axis().cross(j.moment())) : Vec3(linkPose(model, i - 1, q) * Vec3(j.axis().cross(j.moment())));
      const double amplitude = slides ? 0.0 : weight_reach + weight * line_point.norm() * mpu;
      const double hx = slides ? 1e-4 * L : 1e-4;  // step of the motion x = scale (q + offset)
      const double h = hx / j.scale;
      VecX qp = q, qm = q;
      qp[i] += h;
      qm[i] -= h;
      const double dU_dq = (potential(model, masses, qp) - potential(model, masses, qm)) / (qp[i] - qm[i]);
      const double expected = -dU_dq / (slides ? mpu : 1.0);
      // truncation h^2/6 |U'''(q)| = scale^3 h^2/6 |U'''(x)|; rounding: U to 32 n eps of weight x reach (FK
      // frames round relative to |com| + L), over the step; per unit of q for sliding joints: over metres
      const double truncation = j.scale * hx * hx / 6.0 * amplitude;
      const double rounding = j.scale * 32.0 * (n + 1) * kEps * weight_reach / hx / (slides ? mpu : 1.0);
      const double tol = 2.0 * (truncation + rounding) + 64.0 * (n + 1) * kEps * std::abs(tau[i]);
      const double error = std::abs(tau[i] - expected);
      EXPECT_LE(error, tol) << "robot " << r << " (" << lowpair_test::geometryName(robot.geometry) << "), joint "
                            << i + 1 << ": tau " << tau[i] << ", -dU/dq " << expected;
      if (tol > 0.0 && error / tol > worst) {
        worst = error / tol;
        worst_joint = i;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, robots);
  std::printf("%d joints checked; worst error %.3g of its tolerance (joint %d)\n", checked, worst, worst_joint + 1);
}

// A single horizontal revolute joint (about x) carrying a point mass r along y: tau = -m g r cos(q).
TEST(GravityTorques, HorizontalRevoluteWithOnePointMass) {
  JointSpec s;
  s.twist << 1, 0, 0, 0, 0, 0;
  const PoeModel model({s}, Pose{});
  MassModel masses;
  const double m = 3.5, r = 400.0, g = 9.81;  // kg, mm, m/s^2
  masses.links = {{m, Vec3(0, r, 0)}};
  masses.metres_per_unit = 1e-3;
  for (const double q : {0.0, 0.3, -1.2, M_PI / 2, 2.5, M_PI}) {
    const VecX tau = gravityTorques(model, masses, VecX::Constant(1, q));
    const double expected = -m * g * r * 1e-3 * std::cos(q);
    EXPECT_NEAR(tau[0], expected, 8.0 * kEps * m * g * r * 1e-3) << "q " << q;
  }
  // the payload instead, on the tool frame turned and moved: the same load from its centre at (0, r, 0)
  Pose tool;
  tool.p = Vec3(0, 0.25 * r, 0);
  const PoeModel with_tool({s}, tool);
  MassModel payload;
  payload.payload = {m, Vec3(0, 0.75 * r, 0)};
  payload.metres_per_unit = 1e-3;
  const VecX tau = gravityTorques(with_tool, payload, VecX::Constant(1, 0.7));
  EXPECT_NEAR(tau[0], -m * g * r * 1e-3 * std::cos(0.7), 8.0 * kEps * m * g * r * 1e-3);
}

// A prismatic joint sliding up along z (scale 2: per unit of q the load moves 2 length units) carries the weight of
// everything after it: tau = -scale m g, in N whatever the length unit.
TEST(GravityTorques, VerticalPrismaticCarriesTheWeight) {
  JointSpec lift, turn;
  lift.twist << 0, 0, 0, 0, 0, 2.0;
  turn.twist << 0, 1, 0, 0, 0, 100;
  const PoeModel model({lift, turn}, Pose{});
  MassModel masses;
  masses.links = {{2.0, Vec3(10, 0, 0)}, {5.0, Vec3(300, 20, 50)}};
  masses.payload = {1.0, Vec3(5, 5, 5)};
  masses.metres_per_unit = 1e-3;
  const VecX tau = gravityTorques(model, masses, Eigen::Vector2d(40.0, 0.4));
  EXPECT_NEAR(tau[0], -2.0 * 8.0 * 9.81, 16.0 * kEps * 8.0 * 9.81 * 2.0);
}

// A vertical first axis (along z through any point) carries no gravity torque: w.M and v.f vanish exactly.
TEST(GravityTorques, VerticalFirstAxisHasNoTorque) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int r = 0; r < 100; ++r) {
    lowpair_test::RandomRobot robot = lowpair_test::randomRobot(rng);
    std::vector<Joint> joints = robot.model.joints();
    const Vec3 p = 500.0 * lowpair_test::draw3(u, rng);
    joints[0].type = JointType::Revolute;
    joints[0].pitch = 0.0;
    joints[0].twist << 0, 0, 1, p.cross(Vec3(0, 0, 1));
    const PoeModel model(joints, robot.model.toolPose());
    MassModel masses = randomMasses(model, rng);
    masses.gravity = Vec3(0, 0, -9.81);
    const VecX tau = gravityTorques(model, masses, lowpair_test::randomConfiguration(model, rng));
    EXPECT_EQ(std::abs(tau[0]), 0.0) << "robot " << r;
  }
}

TEST(GravityTorques, MasslessOrNoMassesGiveZero) {
  std::mt19937_64 rng(3);
  const PoeModel model = lowpair_test::randomRobot(rng).model;
  const VecX q = lowpair_test::randomConfiguration(model, rng);
  EXPECT_TRUE(gravityTorques(model, MassModel{}, q).isZero(0.0));
  MassModel zero;
  zero.links.assign(static_cast<size_t>(model.dof()), PointMass{0.0, Vec3(1, 2, 3)});
  EXPECT_TRUE(gravityTorques(model, zero, q).isZero(0.0));
}

TEST(GravityTorques, RefusesWrongSizesAndBadMasses) {
  std::mt19937_64 rng(4);
  const PoeModel model = lowpair_test::randomRobot(rng).model;
  const VecX q = lowpair_test::randomConfiguration(model, rng);
  MassModel good = randomMasses(model, rng);
  EXPECT_NO_THROW(gravityTorques(model, good, q));
  EXPECT_THROW(gravityTorques(model, good, VecX::Zero(model.dof() + 1)), std::invalid_argument);
  VecX nan_q = q;
  nan_q[0] = std::nan("");
  EXPECT_THROW(gravityTorques(model, good, nan_q), std::invalid_argument);
  MassModel bad = good;
  bad.links.pop_back();
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
  bad = good;
  bad.links[0].mass = -1.0;
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
  bad = good;
  bad.links[0].mass = std::nan("");
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
  bad = good;
  bad.payload.mass = std::numeric_limits<double>::infinity();
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
  bad = good;
  bad.links[0].com.x() = std::nan("");
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
  bad = good;
  bad.gravity.z() = std::nan("");
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
  bad = good;
  bad.metres_per_unit = 0.0;
  EXPECT_THROW(gravityTorques(model, bad, q), std::invalid_argument);
}

}  // namespace
