// Inverse kinematics (lowpair/ik.hpp): the statuses (unreachable by the reach bound, at a stationary point
// or by orientation; singular; a joint clamped or reported outside its range; not converged; stalled below
// the rounding floor), the solution in Data, the status names, and bad arguments. Convergence and
// compensation are in ik_test.cpp.
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

}  // namespace

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
