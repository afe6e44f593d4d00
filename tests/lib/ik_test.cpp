// Inverse kinematics and compensation (lowpair/ik.hpp): convergence from seeds 0.3 rad per joint away on
// the PUMA 560, the Stanford arm (prismatic), a robot with helical and prismatic joints and a 7-joint arm;
// the minimum-norm step of redundant robots; the statuses (unreachable, singular, out of range, not
// converged); compensation of a calibrated model. Every solution is checked by an FK of its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <Eigen/SVD>

#include "calibration_helpers.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/singularity.hpp"

namespace {

using namespace lowpair;
using Range = std::array<double, 2>;

// ---- robots, built in code ------------------------------------------------------------------------------

DhModel dhRobot(const std::vector<DhParams>& rows, const std::vector<Range>& ranges, const std::string& name,
                double tool_d = 0.0, int prismatic = -1) {
  std::vector<DhJoint> joints(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    joints[i].link = rows[i];
    joints[i].range = ranges[i];
    if (static_cast<int>(i) == prismatic) joints[i].type = JointType::Prismatic;
  }
  return DhModel(DhParams{}, joints, 0.0, tool_d, name);
}

// PUMA 560, Corke mdl_puma560 (models/puma560_corke.yaml), with its joint ranges.
PoeModel puma() {
  return dhToPoe(dhRobot({{0, 0, M_PI / 2, 0}, {0, 0, 0, 0.4318}, {0, 0.15005, -M_PI / 2, 0.0203},
                          {0, 0.4318, M_PI / 2, 0}, {0, 0, -M_PI / 2, 0}, {0, 0, 0, 0}},
                         {{-2.792526803190927, 2.792526803190927}, {-0.7853981633974483, 3.9269908169872414},
                          {-3.9269908169872414, 0.7853981633974483}, {-1.9198621771937625, 2.9670597283903604},
                          {-1.7453292519943295, 1.7453292519943295}, {-4.642575810304916, 4.642575810304916}},
                         "puma560"));
}

// Stanford arm, Corke mdl_stanford (models/stanford_corke.yaml): joint 3 prismatic.
PoeModel stanford() {
  const double r = 2.9670597283903604;
  return dhToPoe(dhRobot({{0, 0.412, -M_PI / 2, 0}, {0, 0.154, M_PI / 2, 0}, {-M_PI / 2, 0, 0, 0},
                          {0, 0, -M_PI / 2, 0}, {0, 0, M_PI / 2, 0}, {0, 0, 0, 0}},
                         {{-r, r}, {-r, r}, {0.3048, 1.27}, {-r, r}, {-M_PI / 2, M_PI / 2}, {-r, r}}, "stanford", 0.263, 2));
}

// The Stanford arm with a helical joint 1 (a screw column: 0.05 m per rad) besides its prismatic joint 3.
PoeModel stanfordHelical() {
  const double r = 2.9670597283903604;
  std::vector<DhJoint> joints(6);
  const std::vector<DhParams> rows{{0, 0.412, -M_PI / 2, 0}, {0, 0.154, M_PI / 2, 0}, {-M_PI / 2, 0, 0, 0},
                                   {0, 0, -M_PI / 2, 0},     {0, 0, M_PI / 2, 0},     {0, 0, 0, 0}};
  const std::vector<Range> ranges{{-r, r}, {-r, r}, {0.3048, 1.27}, {-r, r}, {-M_PI / 2, M_PI / 2}, {-r, r}};
  for (size_t i = 0; i < 6; ++i) {
    joints[i].link = rows[i];
    joints[i].range = ranges[i];
  }
  joints[0].type = JointType::Helical;
  joints[0].pitch = 0.05;
  joints[2].type = JointType::Prismatic;
  return dhToPoe(DhModel(DhParams{}, joints, 0.0, 0.263, "stanford-h"));
}

// PUMA 560, Okamura-Park actual parameters (models/puma560_okamura_actual.yaml, mm): joints 3-6 helical,
// unnormalized twists (joint scales |w| != 1), no ranges.
PoeModel okamuraActual() {
  const double t[6][6] = {{0.04, -0.02, 0.999, 0.02, 0.04, 0},         {0, -1.00002, 0, -0.02, 0, 0.05},
                          {0.178, -0.984, -0.001, -0.07, 0.009, -101}, {0.062, 0.013, -0.998, -51, 249, 0.0752},
                          {0.001, -1.00004, 0, -20.6, -0.0206, -249},  {0.095, 0.031, -0.995, -51, 249, 0}};
  std::vector<JointSpec> joints(6);
  for (int i = 0; i < 6; ++i) joints[i].twist = Eigen::Map<const Vec6>(t[i]);
  Vec6 tool;
  tool << 0.02, -0.01, 0.01, 249, 51, -20.6;
  return PoeModel::fromToolTwist(joints, tool, "okamura");
}

// A 7-joint arm (KUKA iiwa-like D-H), ranges +-170 / +-120 / +-175 deg.
PoeModel sevenJoint() {
  const double a = 170 * M_PI / 180, b = 120 * M_PI / 180, c = 175 * M_PI / 180;
  return dhToPoe(dhRobot({{0, 0.34, -M_PI / 2, 0}, {0, 0, M_PI / 2, 0}, {0, 0.4, M_PI / 2, 0}, {0, 0, -M_PI / 2, 0},
                          {0, 0.4, -M_PI / 2, 0}, {0, 0, M_PI / 2, 0}, {0, 0.126, 0, 0}},
                         {{-a, a}, {-b, b}, {-a, a}, {-b, b}, {-a, a}, {-b, b}, {-c, c}}, "seven", 0.0));
}

// Six joints of every type on generic lines (calibration_helpers jointMix): revolute, helical, prismatic,
// joint scales 0.5-2 and offsets; ranges on the prismatic joints only.
PoeModel mixed() {
  std::mt19937_64 rng(11);
  return calibration_helpers::jointMix("RHPRHR", 1.0, rng);
}

// A planar arm in the xy plane: revolute joints about z through (0,0,0), (1,0,0), ...; the tool at (n,0,0).
PoeModel planar(int n, const std::vector<std::optional<Range>>& ranges = {}) {
  std::vector<JointSpec> joints(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    joints[i].twist << 0, 0, 1, 0, -static_cast<double>(i), 0;  // v = -w x c, c = (i, 0, 0)
    if (static_cast<size_t>(i) < ranges.size()) joints[i].range = ranges[i];
  }
  Pose tool;
  tool.p << n, 0, 0;
  return PoeModel(joints, tool, "planar");
}

// ---- sampling --------------------------------------------------------------------------------------------

// q uniform in each joint's range; [-pi, pi] (revolute, helical) or [-L, L] (prismatic) without one.
VecX sampleQ(const PoeModel& model, std::mt19937_64& rng) {
  VecX q(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double w = j.type == JointType::Prismatic ? model.lengthScale() : M_PI;
    const Range r = j.range ? *j.range : Range{-w, w};
    q[i] = std::uniform_real_distribution<double>(r[0], r[1])(rng);
  }
  return q;
}

// q moved by 0.3 per joint in a random direction (+ or -), in the joint's motion: 0.3 rad for revolute and
// helical joints, 0.3 L for prismatic ones (divided by the joint's scale).
VecX seedNear(const PoeModel& model, const VecX& q, std::mt19937_64& rng) {
  VecX seed = q;
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double unit = (j.type == JointType::Prismatic ? model.lengthScale() : 1.0) / j.scale;
    seed[i] += ((rng() & 1) ? 0.3 : -0.3) * unit;
  }
  return seed;
}

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

// ---- statuses -----------------------------------------------------------------------------------------------------

TEST(IkStatus, FarTargetIsUnreachableByTheReachBound) {
  for (const PoeModel& model : {puma(), stanford(), sevenJoint()}) {
    Data data(model);
    IkWorkspace work(model);
    Pose target;
    target.p << 10.0 * model.lengthScale(), 0, 0;
    std::mt19937_64 rng(31);
    const IkResult& r = inverseKinematics(model, data, target, sampleQ(model, rng), IkOptions{}, work);
    EXPECT_EQ(r.status, IkStatus::Unreachable) << model.name();
    EXPECT_EQ(r.iterations, 0);
    EXPECT_FALSE(r.converged);
    EXPECT_NE(r.reason.find("beyond the chain's reach"), std::string::npos) << r.reason;
    EXPECT_TRUE(std::isfinite(r.reach));
    EXPECT_GT(r.position_error, 5.0 * model.lengthScale());
  }
}

TEST(IkStatus, ReachBoundHoldsForEveryConfiguration) {
  // a stretched planar arm reaches its bound exactly: the sum of its link lengths
  const PoeModel arm = planar(3);
  Data data(arm);
  IkWorkspace work(arm);
  IkOptions o;
  o.measure = Measure::Position;
  Pose far;
  far.p << 3.0 + 1e-6, 0, 0;
  EXPECT_EQ(inverseKinematics(arm, data, far, VecX::Zero(3), o, work).status, IkStatus::Unreachable);
  EXPECT_DOUBLE_EQ(work.result.reach, 3.0);
  // no tool position of a random configuration is declared beyond the bound
  for (const PoeModel& model : {puma(), stanford(), mixed(), sevenJoint()}) {
    IkWorkspace w(model);
    Data d(model);
    IkOptions evaluate_only;
    evaluate_only.max_iterations = 0;
    std::mt19937_64 rng(32);
    for (int k = 0; k < 2000; ++k) {
      const Pose target = poeForwardKinematics(model, sampleQ(model, rng));
      const IkResult& r = inverseKinematics(model, d, target, VecX::Zero(model.dof()), evaluate_only, w);
      EXPECT_EQ(r.reason.find("beyond the chain's reach"), std::string::npos) << model.name() << ": " << r.reason;
    }
  }
}

TEST(IkStatus, OutOfPlaneTargetIsUnreachableAtAStationaryPoint) {
  // a planar arm cannot leave its plane: the iteration stops where no joint motion reduces the z error
  const PoeModel arm = planar(2);
  Data data(arm);
  IkWorkspace work(arm);
  IkOptions o;
  o.measure = Measure::Position;
  Pose target;
  target.p << 1.0, 0.5, 0.5;
  VecX seed(2);
  seed << 0.2, 0.4;
  const IkResult& r = inverseKinematics(arm, data, target, seed, o, work);
  EXPECT_EQ(r.status, IkStatus::Unreachable) << r.reason;
  EXPECT_NE(r.reason.find("stationary"), std::string::npos) << r.reason;
  EXPECT_NEAR(r.position_error, 0.5, 1e-9);  // the in-plane part is matched
  EXPECT_LT(r.iterations, kIkMaxIterations);
}

TEST(IkStatus, OrientationARobotCannotTakeIsUnreachable) {
  // a planar arm with a pose target turned about x: the rotation error cannot be reduced
  const PoeModel arm = planar(3);
  Data data(arm);
  IkWorkspace work(arm);
  Pose target;
  target.R = expSO3(Vec3(0.5, 0, 0.3));
  target.p << 1.5, 1.0, 0;
  const IkResult& r = inverseKinematics(arm, data, target, VecX::Constant(3, 0.3), IkOptions{}, work);
  EXPECT_EQ(r.status, IkStatus::Unreachable) << r.reason;
  EXPECT_GT(r.rotation_error, 0.4);  // about x: what turns about z cannot remove
  EXPECT_LE(r.position_error, kIkTolerance * arm.lengthScale());
}

TEST(IkStatus, WristSingularTargetIsSingular) {
  // PUMA 560 with q5 = 0: axes 4 and 6 collinear (C1); every solution of that pose has q5 = 0
  const PoeModel model = puma();
  Data data(model);
  IkWorkspace work(model);
  std::mt19937_64 rng(41);
  for (int k = 0; k < 20; ++k) {
    VecX q = sampleQ(model, rng);
    q[4] = 0.0;
    const Pose target = poeForwardKinematics(model, q);
    const IkResult& r = inverseKinematics(model, data, target, seedNear(model, q, rng), IkOptions{}, work);
    EXPECT_EQ(r.status, IkStatus::Singular) << k << ": " << r.reason;
    EXPECT_TRUE(r.converged);
    EXPECT_LE(r.position_error, kIkTolerance * model.lengthScale());
    EXPECT_LE(r.rotation_error, kIkTolerance);
    EXPECT_LE(r.sigma_min, 1e-5);
    EXPECT_NE(r.reason.find("singular"), std::string::npos);
  }
}

TEST(IkStatus, StretchedArmTargetIsSingular) {
  // the planar arm's tool at distance 2 (the elbow straight): a boundary of the workspace
  const PoeModel arm = planar(2);
  Data data(arm);
  IkWorkspace work(arm);
  IkOptions o;
  o.measure = Measure::Position;
  Pose target;
  target.p << 2.0 * std::cos(0.4), 2.0 * std::sin(0.4), 0;
  VecX seed(2);
  seed << 0.1, 0.3;
  const IkResult& r = inverseKinematics(arm, data, target, seed, o, work);
  EXPECT_EQ(r.status, IkStatus::Singular) << r.reason;
  EXPECT_LE(r.position_error, kIkTolerance * arm.lengthScale());
  EXPECT_NEAR(r.q[1], 0.0, 1e-4);
}

TEST(IkStatus, RegularTargetsAreNotSingular) {
  // the threshold sqrt(tolerance) sigma_max flags nothing on random targets (covered by the convergence tests);
  // here a pose 1e-3 rad from the wrist singularity: regular, condition ~1e3
  const PoeModel model = puma();
  Data data(model);
  IkWorkspace work(model);
  VecX q(6);
  q << 0.3, 0.5, -1.2, 0.4, 1e-3, 0.2;
  const IkResult& r = inverseKinematics(model, data, poeForwardKinematics(model, q), q + VecX::Constant(6, 0.1),
                                        IkOptions{}, work);
  EXPECT_EQ(r.status, IkStatus::Ok) << r.reason;
  EXPECT_EQ(r.rank, 6);
  EXPECT_GT(r.sigma_min, 1e-5);
}

TEST(IkStatus, ClampedJointOutOfRangeIsReported) {
  // both solutions of the target have q1 > 0.5 (1.0 and 1.3): joint 1 stops at its limit
  const PoeModel arm = planar(2, {Range{-0.5, 0.5}, Range{-M_PI, M_PI}});
  Data data(arm);
  IkWorkspace work(arm);
  IkOptions o;
  o.measure = Measure::Position;
  VecX q(2), seed(2);
  q << 1.0, 0.3;
  seed << 0.2, 0.2;
  const IkResult& r = inverseKinematics(arm, data, poeForwardKinematics(arm, q), seed, o, work);
  EXPECT_EQ(r.status, IkStatus::OutOfRange) << r.reason;
  EXPECT_EQ(r.joint, 0);
  EXPECT_EQ(r.q[0], 0.5);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.reason.find("joint 1"), std::string::npos) << r.reason;
}

TEST(IkStatus, ReportPolicySolvesAndNamesTheJointOutsideItsRange) {
  const PoeModel arm = planar(2, {Range{-0.5, 0.5}, Range{-M_PI, M_PI}});
  Data data(arm);
  IkWorkspace work(arm);
  IkOptions o;
  o.measure = Measure::Position;
  o.ranges = RangePolicy::Report;
  VecX q(2), seed(2);
  q << 1.0, 0.3;
  seed << 0.9, 0.2;
  const IkResult& r = inverseKinematics(arm, data, poeForwardKinematics(arm, q), seed, o, work);
  EXPECT_EQ(r.status, IkStatus::OutOfRange) << r.reason;
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.joint, 0);
  EXPECT_NEAR(r.q[0], 1.0, 1e-9);
}

TEST(IkStatus, IterationLimitIsNotConverged) {
  const PoeModel model = puma();
  Data data(model);
  IkWorkspace work(model);
  IkOptions o;
  o.max_iterations = 1;
  VecX q(6);
  q << 0.3, 0.5, -1.2, 0.4, 0.8, 0.2;
  const IkResult& r = inverseKinematics(model, data, poeForwardKinematics(model, q), q + VecX::Constant(6, 0.3), o, work);
  EXPECT_EQ(r.status, IkStatus::NotConverged);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_NE(r.reason.find("1 iterations"), std::string::npos) << r.reason;
  // the same workspace then solves it, and the reason is cleared
  const IkResult& again = inverseKinematics(model, data, poeForwardKinematics(model, q), q + VecX::Constant(6, 0.3),
                                            IkOptions{}, work);
  EXPECT_EQ(again.status, IkStatus::Ok);
  EXPECT_TRUE(again.reason.empty());
}

TEST(IkStatus, ToleranceBelowTheRoundingFloorStalls) {
  const PoeModel model = puma();
  Data data(model);
  IkWorkspace work(model);
  IkOptions o;
  o.position_tolerance = 1e-30;
  o.rotation_tolerance = 1e-30;
  VecX q(6);
  q << 0.3, 0.5, -1.2, 0.4, 0.8, 0.2;
  const IkResult& r = inverseKinematics(model, data, poeForwardKinematics(model, q), q + VecX::Constant(6, 0.3), o, work);
  EXPECT_EQ(r.status, IkStatus::NotConverged) << r.reason;
  EXPECT_LT(r.iterations, kIkMaxIterations);
  EXPECT_LE(r.position_error, 1e-14);
}

TEST(IkStatus, DataHoldsTheSolution) {
  const PoeModel model = sevenJoint();
  Data data(model);
  IkWorkspace work(model);
  std::mt19937_64 rng(51);
  const VecX q = sampleQ(model, rng);
  const IkResult& r = inverseKinematics(model, data, poeForwardKinematics(model, q), seedNear(model, q, rng), IkOptions{}, work);
  ASSERT_EQ(r.status, IkStatus::Ok);
  Data fresh(model);  // computeJacobians' FK (with the joint frames), bit for bit
  computeJacobians(model, fresh, r.q);
  EXPECT_EQ(data.T_base_tool.p, fresh.T_base_tool.p);
  EXPECT_EQ(data.T_base_tool.R, fresh.T_base_tool.R);
  EXPECT_EQ(data.J_spatial, fresh.J_spatial);
}

TEST(IkStatus, NamesAreTheCsvWords) {
  EXPECT_STREQ(ikStatusName(IkStatus::Ok), "ok");
  EXPECT_STREQ(ikStatusName(IkStatus::OutOfRange), "out_of_range");
  EXPECT_STREQ(ikStatusName(IkStatus::Singular), "singular");
  EXPECT_STREQ(ikStatusName(IkStatus::Unreachable), "unreachable");
  EXPECT_STREQ(ikStatusName(IkStatus::NotConverged), "not_converged");
}

TEST(IkInput, BadArgumentsThrowNamingThem) {
  const PoeModel model = puma();
  Data data(model);
  IkWorkspace work(model);
  const VecX q = VecX::Zero(6);
  const Pose target = poeForwardKinematics(model, q);
  auto expectThrow = [&](const IkOptions& o, const std::string& what, const Eigen::Ref<const VecX>& seed, const Pose& t) {
    try {
      inverseKinematics(model, data, t, seed, o, work);
      ADD_FAILURE() << "no throw for " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  IkOptions o;
  expectThrow(o, "q has 5 values", VecX::Zero(5), target);
  VecX nan = q;
  nan[2] = NAN;
  expectThrow(o, "joint value 3 is not finite", nan, target);
  o.measure = Measure::Targets;
  expectThrow(o, "pose or a position", q, target);
  o = IkOptions{};
  o.position_tolerance = 0.0;
  expectThrow(o, "position_tolerance", q, target);
  o = IkOptions{};
  o.damping = -1.0;
  expectThrow(o, "damping", q, target);
  o = IkOptions{};
  o.max_iterations = -1;
  expectThrow(o, "max_iterations", q, target);
  Pose sheared = target;
  sheared.R(0, 1) += 1e-3;
  expectThrow(IkOptions{}, "not a rotation", q, sheared);
  Pose infinite = target;
  infinite.p[0] = INFINITY;
  expectThrow(IkOptions{}, "not finite", q, infinite);
  IkWorkspace small(5);
  EXPECT_THROW(inverseKinematics(model, data, target, q, IkOptions{}, small), std::invalid_argument);
  Data other(planar(2));
  EXPECT_THROW(inverseKinematics(model, other, target, q, IkOptions{}, work), std::invalid_argument);
}

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
