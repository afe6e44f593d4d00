// Closed-form inverse kinematics (lowpair/ik_closed_form.hpp): the geometry detected from the POE lines, every
// solution of random targets against the numerical solver from many seeds, degenerate targets on purpose, a
// calibrated (nearly Pieper) model refined, and compensation that keeps the nominal row's branch.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "ik_closed_form_helpers.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/ik_closed_form.hpp"
#include "lowpair/se3.hpp"

namespace {

using namespace lowpair;
using namespace ik_helpers;
using namespace ik_closed_form_helpers;

TEST(ClosedFormStructure, DetectsTheGeometryFromTheLines) {
  const ClosedFormStructure p = closedFormStructure(puma());
  EXPECT_EQ(p.kind, ClosedFormKind::SphericalWrist) << p.reason;
  EXPECT_FALSE(p.prismatic_elbow);
  EXPECT_LE(p.deviation, 1e-14);  // a D-H model is exact to rounding
  EXPECT_LE((p.shoulder).norm(), 1e-14);  // axes 1 and 2 of Corke's PUMA meet at the base origin
  const ClosedFormStructure s = closedFormStructure(stanford());
  EXPECT_EQ(s.kind, ClosedFormKind::SphericalWrist) << s.reason;
  EXPECT_TRUE(s.prismatic_elbow);
  const ClosedFormStructure u = closedFormStructure(ur5e());
  EXPECT_EQ(u.kind, ClosedFormKind::ParallelTriple) << u.reason;
  EXPECT_LE(u.deviation, 1e-14);
  for (const PoeModel& m : {sevenJoint(), mixed(), okamuraActual(), stanfordHelical()}) {
    const ClosedFormStructure n = closedFormStructure(m);
    EXPECT_EQ(n.kind, ClosedFormKind::None) << m.name();
    EXPECT_FALSE(n.reason.empty()) << m.name();
  }
}

TEST(ClosedFormStructure, NearlyWithinTheToleranceOnly) {
  std::mt19937_64 rng(5);
  const PoeModel near = perturbed(puma(), 1e-4, rng), far = perturbed(puma(), 1e-2, rng);
  const ClosedFormStructure a = closedFormStructure(near), b = closedFormStructure(far);
  EXPECT_EQ(a.kind, ClosedFormKind::SphericalWrist) << a.reason;
  EXPECT_GT(a.deviation, 1e-6);   // the lines do miss
  EXPECT_LE(a.deviation, kClosedFormNearly);
  EXPECT_EQ(b.kind, ClosedFormKind::None);
  EXPECT_NE(b.reason.find("miss"), std::string::npos) << b.reason;
  // the same model is of the geometry for a looser tolerance
  EXPECT_EQ(closedFormStructure(far, 0.1).kind, ClosedFormKind::SphericalWrist);
}

TEST(InverseKinematicsAll, EverySolutionOfThePuma) { everySolutionFound(puma(), 150, 16, 8); }
TEST(InverseKinematicsAll, EverySolutionOfTheStanfordArm) { everySolutionFound(stanford(), 150, 16, 8); }
TEST(InverseKinematicsAll, EverySolutionOfTheUr5e) { everySolutionFound(ur5e(), 150, 16, 8); }

// Joint scales (unnormalized twists) and offsets: the subproblems' motions x become q = x / scale - offset
// (JointMotion::variable), the slide of the Stanford arm's prismatic joint included.
TEST(InverseKinematicsAll, JointScalesAndOffsetsApply) {
  const double scales[6] = {2.0, 0.5, 1.5, 1.0, 3.0, 0.8}, offsets[6] = {0.3, -0.2, 0.1, 0.5, -0.4, 0.25};
  for (const PoeModel& base : {puma(), stanford(), ur5e()}) {
    std::vector<JointSpec> specs(6);
    for (int i = 0; i < 6; ++i) {
      specs[static_cast<size_t>(i)].type = base.joint(i).type;
      specs[static_cast<size_t>(i)].twist = base.joint(i).twist * scales[i];
      specs[static_cast<size_t>(i)].offset = offsets[i];
    }
    const PoeModel model(specs, base.toolPose(), base.name() + "-scaled");
    ClosedFormWorkspace work(model);
    ASSERT_NE(work.structure.kind, ClosedFormKind::None) << work.structure.reason;
    std::mt19937_64 rng(9);
    for (int t = 0; t < 20; ++t) {
      VecX q = sampleQ(base, rng);  // in the base robot's ranges, as motions; q of the scaled model:
      for (int i = 0; i < 6; ++i) q[i] = q[i] / scales[i] - offsets[i];
      const Pose target = targetOf(model, q);
      const ClosedFormResult& r = inverseKinematicsAll(model, target, exactOptions(), work);
      ASSERT_GT(r.count, 0) << model.name();
      bool own = false;
      for (int k = 0; k < r.count; ++k) {
        const ClosedFormSolution& sol = r.solutions[static_cast<size_t>(k)];
        EXPECT_EQ(sol.refinement_iterations, 0) << model.name();
        own |= jointDistance(model, q, sol.q) <= 1e-6;
      }
      EXPECT_TRUE(own) << model.name() << " target " << t;
    }
  }
}

TEST(InverseKinematicsAll, BranchFlagsAreDistinct) {
  std::mt19937_64 rng(3);
  for (const PoeModel& model : {puma(), ur5e()}) {
    ClosedFormWorkspace work(model);
    const VecX q = sampleQ(model, rng);
    const ClosedFormResult& r = inverseKinematicsAll(model, targetOf(model, q), exactOptions(), work);
    ASSERT_EQ(r.count, 8) << model.name();
    int seen = 0;
    for (int k = 0; k < r.count; ++k) {
      const IkBranch& b = r.solutions[static_cast<size_t>(k)].branch;
      seen |= 1 << (4 * b.shoulder + 2 * b.elbow + b.wrist);
    }
    EXPECT_EQ(seen, 255) << model.name();
  }
}

// Degenerate targets: every solution returned is finite and reaches the target; the singular ones say so.
void expectReached(const PoeModel& model, const ClosedFormResult& r, const Pose& target, double tolerance) {
  for (int k = 0; k < r.count; ++k) {
    const ClosedFormSolution& s = r.solutions[static_cast<size_t>(k)];
    ASSERT_TRUE(s.q.allFinite());
    const Pose T = poeForwardKinematics(model, s.q);
    EXPECT_LE((T.p - target.p).norm(), tolerance * model.lengthScale());
    EXPECT_LE(rotationError(T.R, target.R), tolerance);
  }
}

TEST(InverseKinematicsAll, WristSingularQ5Zero) {
  const PoeModel model = puma();
  ClosedFormWorkspace work(model);
  VecX q(6);
  q << 0.4, 0.7, -1.1, 0.5, 0.0, -0.3;
  const Pose target = targetOf(model, q);
  const ClosedFormResult& r = inverseKinematicsAll(model, target, exactOptions(), work);
  ASSERT_GT(r.count, 0);
  EXPECT_EQ(r.dropped, 0);
  expectReached(model, r, target, kClosedFormAccuracy);
  int singular = 0;
  for (int k = 0; k < r.count; ++k) singular += r.solutions[static_cast<size_t>(k)].singular;
  EXPECT_GT(singular, 0);  // axes 4 and 6 aligned: joint 4 is free
}

TEST(InverseKinematicsAll, ShoulderSingularTargetOnAxis1) {
  const PoeModel model = pumaNoOffset();
  ASSERT_EQ(closedFormStructure(model).kind, ClosedFormKind::SphericalWrist);
  ClosedFormWorkspace work(model);
  Pose target;  // the tool is at the wrist centre: a tool origin on axis 1 puts the wrist centre there
  target.p << 0.0, 0.0, 0.5;
  target.R = expSO3(Vec3(0.3, -0.2, 0.5));
  const ClosedFormResult& r = inverseKinematicsAll(model, target, exactOptions(), work);
  ASSERT_GT(r.count, 0);
  expectReached(model, r, target, kClosedFormAccuracy);
  for (int k = 0; k < r.count; ++k) EXPECT_TRUE(r.solutions[static_cast<size_t>(k)].singular);
}

TEST(InverseKinematicsAll, ElbowStretched) {
  const PoeModel model = ur5e();  // q3 = 0: the upper arm and the forearm in line
  ClosedFormWorkspace work(model);
  VecX q(6);
  q << 0.3, -0.8, 0.0, 0.4, 1.1, -0.6;
  const Pose target = targetOf(model, q);
  IkOptions o = exactOptions();
  o.max_iterations = kIkMaxIterations;  // at a double root the rounding of the square root is sqrt(eps): refine
  o.position_tolerance = o.rotation_tolerance = 1e-10;
  const ClosedFormResult& r = inverseKinematicsAll(model, target, o, work);
  ASSERT_GT(r.count, 0);
  expectReached(model, r, target, 1e-10);
  bool own = false;
  for (int k = 0; k < r.count; ++k) own |= jointDistance(model, q, r.solutions[static_cast<size_t>(k)].q) <= 1e-4;
  EXPECT_TRUE(own);  // sqrt of the 1e-10 residual's rounding: the stretched elbow is known to ~1e-5
}

TEST(InverseKinematicsAll, OutOfReachHasNoSolutionAndNoNan) {
  for (const PoeModel& model : {puma(), stanford(), ur5e()}) {
    ClosedFormWorkspace work(model);
    Pose target;
    target.p << 3.0 * model.lengthScale(), 0.5, 0.2;
    const ClosedFormResult& r = inverseKinematicsAll(model, target, IkOptions{}, work);
    if (model.name() == "stanford") {  // the slide has a range: it reaches anything, beyond the range
      EXPECT_EQ(r.count, 8);
      for (int k = 0; k < r.count; ++k) {
        const ClosedFormSolution& sol = r.solutions[static_cast<size_t>(k)];
        EXPECT_GE(sol.out_of_range, 0);
        EXPECT_TRUE(sol.q[2] > 1.27 || sol.q[2] < 0.3048) << sol.q[2];  // the slide beyond its range (either way)
        EXPECT_TRUE(r.solutions[static_cast<size_t>(k)].q.allFinite());
      }
      continue;
    }
    EXPECT_EQ(r.count, 0) << model.name();
  }
}

TEST(InverseKinematicsAll, NearlyPieperReachesTheToleranceAfterRefinement) {
  std::mt19937_64 rng(17);
  for (const PoeModel& nominal : {puma(), ur5e()}) {
    const PoeModel model = perturbed(nominal, 2e-4, rng);
    ClosedFormWorkspace work(model);
    ASSERT_NE(work.structure.kind, ClosedFormKind::None) << work.structure.reason;
    IkOptions o;  // tolerance 1e-10 L and rad
    int refined = 0, checked = 0;
    Data data(model);
    IkWorkspace ik(model);
    IkOptions at_q;
    at_q.max_iterations = 0;
    at_q.ranges = RangePolicy::Report;
    for (int t = 0; t < 40; ++t) {
      const VecX q = sampleQ(model, rng);
      // away from singular targets (dimensionless sigma_min >= 0.05): near one, the projection's candidate of
      // a branch may lie in another branch's basin of the true model, or its root may vanish
      if (inverseKinematics(model, data, targetOf(model, q), q, at_q, ik).sigma_min < 0.05) continue;
      ++checked;
      const Pose target = targetOf(model, q);
      const ClosedFormResult& r = inverseKinematicsAll(model, target, o, work);
      expectReached(model, r, target, 1e-10);
      bool own = false;
      for (int k = 0; k < r.count; ++k) {
        own |= jointDistance(model, q, r.solutions[static_cast<size_t>(k)].q) <= 1e-6;
        refined += r.solutions[static_cast<size_t>(k)].refinement_iterations > 0;
      }
      EXPECT_TRUE(own) << model.name() << " target " << t;

    }
    EXPECT_GT(refined, 0) << model.name();
    EXPECT_GT(checked, 20) << model.name();  // the projection is not the model: refinement did work
  }
}

// A program of rows crossing no singularity (q5, the elbow and the wrist centre's distance from axis 1 stay
// away from their singular values): each compensated row is on its nominal row's branch, the same for all.
TEST(CompensateOnBranch, KeepsTheBranchOnEveryRow) {
  std::mt19937_64 rng(23);
  const PoeModel nominal = puma();
  const PoeModel calibrated = perturbed(nominal, 2e-4, rng);
  ClosedFormWorkspace nominal_work(nominal), calibrated_work(calibrated), check_work(calibrated);
  VecX a(6), b(6);
  // the wrist centre stays in front of axis 1 (the shoulder singularity: its reach in the arm plane 0), q3 far
  // from the stretched elbow (-1.52), q5 from 0; checked below through sigma_min on every row
  a << 0.2, 0.2, -0.9, 0.3, 0.8, 0.1;
  b << 1.0, 0.5, -0.3, 1.0, 1.2, 1.0;
  Data data(nominal);
  IkWorkspace ik(nominal);
  IkOptions at_q;
  at_q.max_iterations = 0;
  const IkOptions o;
  IkBranch first;
  for (int row = 0; row <= 50; ++row) {
    const VecX q = a + (b - a) * (row / 50.0);
    ASSERT_GE(inverseKinematics(nominal, data, poeForwardKinematics(nominal, q), q, at_q, ik).sigma_min, 0.05) << "row " << row;
    IkBranch nominal_branch, compensated_branch;
    ASSERT_TRUE(branchOf(nominal, q, o, nominal_work, nominal_branch));
    if (row == 0) first = nominal_branch;
    EXPECT_EQ(nominal_branch, first) << "row " << row;
    const ClosedFormSolution* s = compensateOnBranch(nominal, calibrated, q, o, nominal_work, calibrated_work);
    ASSERT_NE(s, nullptr) << "row " << row;
    ASSERT_TRUE(branchOf(calibrated, VecX(s->q), o, check_work, compensated_branch));
    EXPECT_EQ(compensated_branch, nominal_branch) << "row " << row;
    EXPECT_LE(jointDistance(calibrated, q, VecX(s->q)), 0.05);  // a calibration moves joints by ~1e-3, not a branch
    const Pose want = poeForwardKinematics(nominal, q), got = poeForwardKinematics(calibrated, s->q);
    EXPECT_LE((want.p - got.p).norm(), 1e-10 * nominal.lengthScale());
  }
}

TEST(InverseKinematicsAll, BadArguments) {
  const PoeModel model = puma();
  ClosedFormWorkspace work(model);
  IkOptions position;
  position.measure = Measure::Position;
  EXPECT_THROW(inverseKinematicsAll(model, Pose{}, position, work), std::invalid_argument);
  EXPECT_THROW(inverseKinematicsAll(ur5e(), Pose{}, IkOptions{}, work), std::invalid_argument);  // another model
  Pose bad;
  bad.p[0] = std::nan("");
  EXPECT_THROW(inverseKinematicsAll(model, bad, IkOptions{}, work), std::invalid_argument);
  const PoeModel seven = sevenJoint();
  ClosedFormWorkspace none(seven);
  EXPECT_THROW(inverseKinematicsAll(seven, Pose{}, IkOptions{}, none), std::invalid_argument);
  EXPECT_THROW(closedFormStructure(model, 0.0), std::invalid_argument);
}

}  // namespace
