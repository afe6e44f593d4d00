// Inverse kinematics and compensation (lowpair/ik.hpp): convergence from seeds 0.3 rad per joint away on
// the PUMA 560, the Stanford arm (prismatic), a robot with helical and prismatic joints and a 7-joint arm;
// the minimum-norm step of redundant robots; compensation of a calibrated model. Every solution is checked
// by an FK of its own. The statuses (unreachable, singular, out of range, not converged) and bad arguments
// are in ik_status_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <Eigen/SVD>

#include "calibration_helpers.hpp"
#include "ik_helpers.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/singularity.hpp"

namespace {

using namespace lowpair;
using namespace ik_helpers;

Pose pointFrame(const Pose& T, const Vec3& point) {
  Pose F = T;
  F.p = T * point;
  return F;
}

// The errors of q against the target, measured here (not by the solver).
struct Check {
  double position, rotation;
};
Check measured(const PoeModel& model, const VecX& q, const Pose& target, const IkOptions& o) {
  const Pose F = pointFrame(poeForwardKinematics(model, q), o.point_tool);
  return {(F.p - target.p).norm(), o.measure == Measure::Pose ? rotationError(F.R, target.R) : 0.0};
}

struct Stats {
  int runs = 0, ok = 0, max_iterations = 0;
  long iterations = 0;
  int by_status[5] = {};
};

// `count` targets F(q) of random q in the ranges, each solved from a seed 0.3 per joint away from its q.
Stats convergence(const PoeModel& model, Measure measure, int count, unsigned seed, const Vec3& point = Vec3::Zero()) {
  std::mt19937_64 rng(seed);
  Data data(model);
  IkWorkspace work(model);
  IkOptions o;
  o.measure = measure;
  o.point_tool = point;
  const double L = model.lengthScale();
  Stats s;
  for (int k = 0; k < count; ++k) {
    const VecX q = sampleQ(model, rng);
    const Pose target = pointFrame(poeForwardKinematics(model, q), point);
    const IkResult& r = inverseKinematics(model, data, target, seedNear(model, q, rng), o, work);
    ++s.runs;
    ++s.by_status[static_cast<int>(r.status)];
    s.iterations += r.iterations;
    s.max_iterations = std::max(s.max_iterations, r.iterations);
    if (r.status != IkStatus::Ok) continue;
    ++s.ok;
    const Check c = measured(model, r.q, target, o);
    EXPECT_LE(c.position, kIkTolerance * L) << model.name() << " target " << k;
    EXPECT_LE(c.rotation, kIkTolerance) << model.name() << " target " << k;
    EXPECT_TRUE(r.reason.empty()) << r.reason;
    for (int i = 0; i < model.dof(); ++i) {  // Clamp: inside the ranges
      if (model.joint(i).range) {
        EXPECT_GE(r.q[i], (*model.joint(i).range)[0]);
        EXPECT_LE(r.q[i], (*model.joint(i).range)[1]);
      }
    }
  }
  std::printf("[ stats    ] %-10s %-8s %d/%d ok (%.2f %%), iterations mean %.2f max %d; not ok:", model.name().c_str(),
              measureName(measure), s.ok, s.runs, 100.0 * s.ok / s.runs, static_cast<double>(s.iterations) / s.runs,
              s.max_iterations);
  for (int k = 1; k < 5; ++k) {
    if (s.by_status[k] > 0) std::printf(" %d %s", s.by_status[k], ikStatusName(static_cast<IkStatus>(k)));
  }
  std::printf("\n");
  return s;
}

void expectConvergence(const PoeModel& model, Measure measure, unsigned seed, const Vec3& point = Vec3::Zero()) {
  const Stats s = convergence(model, measure, 1000, seed, point);
  EXPECT_GE(s.ok, 990) << model.name() << " " << measureName(measure) << ": " << s.ok << " of " << s.runs;
}

// The dimensionless task Jacobian of ik.hpp at q: rows [v / L; w] of the point, columns per unit of motion.
Mat6X taskJacobian(const PoeModel& model, const VecX& q, const Vec3& point) {
  Data data(model);
  computeJacobians(model, data, q);
  Mat6X J(6, model.dof());
  spatialToGeometric(pointFrame(data.T_base_tool, point), data.J_spatial, J);
  dimensionlessJacobian(model, J);
  return J;
}

}  // namespace

// ---- convergence ---------------------------------------------------------------------------------------------

TEST(IkConvergence, Puma560PoseAndPosition) {
  expectConvergence(puma(), Measure::Pose, 1);
  expectConvergence(puma(), Measure::Position, 2);
}

TEST(IkConvergence, StanfordArmWithItsPrismaticJoint) {
  expectConvergence(stanford(), Measure::Pose, 3);
  expectConvergence(stanford(), Measure::Position, 4);
}

TEST(IkConvergence, HelicalJoints) {
  const PoeModel okamura = okamuraActual();
  ASSERT_EQ(okamura.joint(3).type, JointType::Helical);
  expectConvergence(okamura, Measure::Pose, 5);
  expectConvergence(okamura, Measure::Position, 6);
  const PoeModel stanford_h = stanfordHelical();
  ASSERT_EQ(stanford_h.joint(0).type, JointType::Helical);
  ASSERT_EQ(stanford_h.joint(2).type, JointType::Prismatic);
  expectConvergence(stanford_h, Measure::Pose, 10);
  expectConvergence(stanford_h, Measure::Position, 11, Vec3(0.1, -0.2, 0.3));  // a point of the tool
}

TEST(IkConvergence, GenericJointMix) {
  // generic lines, scales and offsets: two helical, one prismatic joint
  const PoeModel model = mixed();
  int helical = 0, prismatic = 0;
  for (const Joint& j : model.joints()) {
    helical += j.type == JointType::Helical;
    prismatic += j.type == JointType::Prismatic;
  }
  ASSERT_EQ(helical, 2);
  ASSERT_EQ(prismatic, 1);
  // a random geometry has more singular and ill-conditioned poses than an arm: 99.4 % of 5000 pose targets
  // measured (docs/ik.md); the bound leaves room for another compiler's rounding to change a few outcomes
  const Stats pose = convergence(model, Measure::Pose, 1000, 12);
  EXPECT_GE(pose.ok, 980);
  expectConvergence(model, Measure::Position, 13);
}

TEST(IkConvergence, SevenJointArm) {
  expectConvergence(sevenJoint(), Measure::Pose, 7);
  expectConvergence(sevenJoint(), Measure::Position, 8);
}

TEST(IkConvergence, ToolPointInPoseMode) {
  // the frame at a point of the tool: its origin and the tool's rotation
  expectConvergence(puma(), Measure::Pose, 9, Vec3(0.02, 0.0, 0.15));
}

TEST(IkConvergence, RevoluteJointCrossesPiByAWholeTurn) {
  // joint 1 in [-pi, pi]: the solution at -3.1 is reached from 3.0 through +pi, one turn back into the range
  std::vector<std::optional<Range>> ranges{Range{-M_PI, M_PI}, Range{-M_PI, M_PI}};
  const PoeModel model = planar(2, ranges);
  VecX q(2), seed(2);
  q << -3.1, 0.7;
  seed << 3.0, 0.7;
  Data data(model);
  IkWorkspace work(model);
  IkOptions o;
  o.measure = Measure::Position;
  const IkResult& r = inverseKinematics(model, data, poeForwardKinematics(model, q), seed, o, work);
  ASSERT_EQ(r.status, IkStatus::Ok) << r.reason;
  EXPECT_NEAR(r.q[0], -3.1, 1e-9);
  EXPECT_NEAR(r.q[1], 0.7, 1e-9);
}

// ---- redundancy: the minimum-norm step -----------------------------------------------------------------------

// From a seed near a solution, the change q* - seed is the minimum-norm one of the linearized task: it has no
// component in the task Jacobian's null space (to second order in the distance) and is no longer than the
// displacement that generated the target.
void expectMinimumNorm(const PoeModel& model, Measure measure, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  const int n = model.dof();
  const int m = measure == Measure::Pose ? 6 : 3;
  Data data(model);
  IkWorkspace work(model);
  IkOptions o;
  o.measure = measure;
  for (int k = 0; k < 20; ++k) {
    const VecX q0 = sampleQ(model, rng);
    VecX delta(n);
    for (int i = 0; i < n; ++i) delta[i] = normal(rng);
    delta *= 1e-4 / delta.norm();
    const Pose target = poeForwardKinematics(model, q0 + delta);
    const IkResult& r = inverseKinematics(model, data, target, q0, o, work);
    ASSERT_EQ(r.status, IkStatus::Ok) << r.reason;
    const VecX dq = r.q - q0;  // revolute joints, scale 1: the motion norm is |dq|
    const Mat6X J = taskJacobian(model, q0, Vec3::Zero());
    const Eigen::JacobiSVD<MatX> svd(MatX(J.topRows(m)), Eigen::ComputeFullV);
    const MatX null_space = svd.matrixV().rightCols(n - m);
    // a step with self-motion would have a null-space part of the order of |delta|; the minimum-norm one has
    // none to first order, only the curvature's O(|delta|^2)
    EXPECT_LE((null_space.transpose() * dq).norm(), 10.0 * delta.squaredNorm()) << "self-motion in the step, target " << k;
    EXPECT_LE(dq.norm(), delta.norm() * (1.0 + 1e-6)) << "target " << k;
  }
}

TEST(IkRedundancy, SevenJointPoseStepIsMinimumNorm) { expectMinimumNorm(sevenJoint(), Measure::Pose, 21); }

TEST(IkRedundancy, SixJointPositionStepIsMinimumNorm) { expectMinimumNorm(puma(), Measure::Position, 22); }

// ---- compensation ----------------------------------------------------------------------------------------------------

// The calibrated model: the nominal moved by errors of 1e-3 (rad, L, relative scale) in every parameter of the
// error model (calibration.hpp).
PoeModel perturbed(const PoeModel& nominal, unsigned seed) {
  std::mt19937_64 rng(seed);
  const ErrorModel em(nominal);
  return em.apply(calibration_helpers::smallDelta(em, 1e-3, false, rng));
}

// The smallest singular value of the dimensionless task Jacobian at q.
double sigmaMin(const PoeModel& model, const VecX& q, Measure measure, const Vec3& point) {
  const int m = measure == Measure::Pose ? 6 : 3;
  const Mat6X J = taskJacobian(model, q, point);
  const VecX s = Eigen::JacobiSVD<MatX>(MatX(J.topRows(m))).singularValues();
  return s[s.size() - 1];
}

// Joint values at least `margin` (of the joint's motion: rad, or L) inside every range.
bool insideRanges(const PoeModel& model, const VecX& q, double margin) {
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double unit = (j.type == JointType::Prismatic ? model.lengthScale() : 1.0) / j.scale;
    if (j.range && (q[i] < (*j.range)[0] + margin * unit || q[i] > (*j.range)[1] - margin * unit)) return false;
  }
  return true;
}

// 200 nominal joint vectors at which the task Jacobian's sigma_min is at least 0.1 and every joint 0.1 inside
// its range: a 1e-3 model error then moves the solution by ~1e-2, so it exists inside the ranges (nearer a
// workspace boundary a calibrated arm 1e-3 L shorter cannot reach the nominal pose: unreachable, correctly).
void expectCompensation(const PoeModel& nominal, Measure measure, unsigned seed, const Vec3& point = Vec3::Zero()) {
  const PoeModel calibrated = perturbed(nominal, seed);
  Data data(nominal);
  IkWorkspace work(nominal);
  IkOptions o;
  o.measure = measure;
  o.point_tool = point;
  std::mt19937_64 rng(seed + 100);
  const double L = nominal.lengthScale();
  int ok = 0, runs = 0, max_iterations = 0;
  double max_dq = 0.0;
  while (runs < 200) {
    const VecX q = sampleQ(nominal, rng);
    if (sigmaMin(nominal, q, measure, point) < 0.1 || !insideRanges(nominal, q, 0.1)) continue;
    ++runs;
    const IkResult& r = compensate(nominal, calibrated, data, q, o, work);
    EXPECT_EQ(r.status, IkStatus::Ok) << r.reason;
    if (r.status != IkStatus::Ok) continue;
    ++ok;
    const Pose wanted = pointFrame(poeForwardKinematics(nominal, q), point);
    const Pose got = pointFrame(poeForwardKinematics(calibrated, r.q), point);
    EXPECT_LE((got.p - wanted.p).norm(), kIkTolerance * L);
    if (measure == Measure::Pose) {
      EXPECT_LE(rotationError(got.R, wanted.R), kIkTolerance);
    }
    EXPECT_LE((r.q - q).norm(), 0.1) << "the compensation continues q";
    max_dq = std::max(max_dq, (r.q - q).norm());
    max_iterations = std::max(max_iterations, r.iterations);
  }
  std::printf("[ stats    ] compensate %-10s %-8s %d/%d ok, max |q' - q| %.3g, max iterations %d\n", nominal.name().c_str(),
              measureName(measure), ok, runs, max_dq, max_iterations);
}

TEST(Compensate, CalibratedPumaReproducesTheNominalPose) { expectCompensation(puma(), Measure::Pose, 61); }

TEST(Compensate, PositionOfAToolPoint) {
  expectCompensation(puma(), Measure::Position, 62, Vec3(0.0, 0.05, 0.1));
  expectCompensation(sevenJoint(), Measure::Position, 63);
}

TEST(Compensate, HelicalPrismaticAndRedundantArms) {
  expectCompensation(okamuraActual(), Measure::Pose, 64);
  expectCompensation(stanfordHelical(), Measure::Pose, 67);
  expectCompensation(sevenJoint(), Measure::Pose, 65);
  expectCompensation(stanford(), Measure::Pose, 66);
}

TEST(Compensate, JointCountsMustAgree) {
  const PoeModel nominal = puma();
  Data data(nominal);
  IkWorkspace work(nominal);
  EXPECT_THROW(compensate(nominal, sevenJoint(), data, VecX::Zero(6), IkOptions{}, work), std::invalid_argument);
}
