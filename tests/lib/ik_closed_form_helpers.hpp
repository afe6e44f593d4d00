#pragma once
// Helpers of the closed-form IK tests (ik_closed_form_test.cpp, ik_closed_form_study.cpp): robots built in code,
// a calibrated-like perturbation, and the check that every solution is found.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "ik_helpers.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/ik_closed_form.hpp"
#include "lowpair/se3.hpp"

namespace ik_closed_form_helpers {

using namespace lowpair;
using namespace ik_helpers;

// UR5e, UR's published D-H table (tests/data/ur5e.yaml cites it), ranges +-2 pi.
inline PoeModel ur5e() {
  const double r = 2.0 * M_PI;
  return dhToPoe(dhRobot({{0, 0.1625, M_PI / 2, 0}, {0, 0, 0, -0.425}, {0, 0, 0, -0.3922}, {0, 0.1333, M_PI / 2, 0},
                          {0, 0.0997, -M_PI / 2, 0}, {0, 0.0996, 0, 0}},
                         {{-r, r}, {-r, r}, {-r, r}, {-r, r}, {-r, r}, {-r, r}}, "ur5e"));
}

// The PUMA 560 without its shoulder offset (d3 = 0): the wrist centre can reach axis 1.
inline PoeModel pumaNoOffset() {
  const double r = M_PI;
  return dhToPoe(dhRobot({{0, 0, M_PI / 2, 0}, {0, 0, 0, 0.4318}, {0, 0, -M_PI / 2, 0.0203}, {0, 0.4318, M_PI / 2, 0},
                          {0, 0, -M_PI / 2, 0}, {0, 0, 0, 0}},
                         {{-r, r}, {-r, r}, {-r, r}, {-r, r}, {-r, r}, {-r, r}}, "puma-no-offset"));
}

// Every joint line moved by a rigid motion of size `size` (rad, and L for the translation): the twist type is
// kept (Ad preserves w.v), the wrist centre and the shoulder point are missed by about `size` L.
inline PoeModel perturbed(const PoeModel& model, double size, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  const double L = model.lengthScale();
  std::vector<Joint> joints = model.joints();
  for (Joint& j : joints) {
    Vec6 eta;
    for (int k = 0; k < 6; ++k) eta[k] = size * normal(rng) * (k < 3 ? 1.0 : L);
    j.twist = adjointApply(expSE3(eta), j.twist);
  }
  return PoeModel(joints, model.toolPose(), model.name() + "-perturbed");
}

// The target of q: the tool frame (point_tool = 0).
inline Pose targetOf(const PoeModel& model, const VecX& q) { return poeForwardKinematics(model, q); }

// FK's rounding floor is 16 (n + 1) eps S (S a few L) ~ 1e-13 L; the subproblems divide by sines >= 1e-2 and by
// distances >= 1e-2 L between the lines they use, so 1e-12 L and rad hold away from singular targets. Near one (a
// double root: the error of a square root of a discriminant near 0 grows as eps / sqrt(discriminant)) a candidate
// can miss it: then the Newton refinement brings it there, and the tests count how often that happens.
constexpr double kClosedFormAccuracy = 1e-12;

inline IkOptions exactOptions() {
  IkOptions o;
  o.position_tolerance = kClosedFormAccuracy;
  o.rotation_tolerance = kClosedFormAccuracy;
  return o;
}

// How far (jointDistance) a joint vector whose FK misses the target by `residual` (in L and rad) may lie from the
// exact solution: residual / sigma_min to first order (sigma_min of the dimensionless task Jacobian, which maps rad
// to L), times 100 for the second-order terms, plus 1e-6 (the rounding of the comparison). Capped at 0.05 rad: next
// to a singularity the branches meet, and distinct solutions elsewhere differ by O(1) rad.
inline double sameSolution(double residual, double sigma_min) { return std::min(0.05, 1e-6 + 100.0 * residual / sigma_min); }

// Every solution the numerical solver finds from many seeds is one of the closed form's, and every closed-form
// solution is exact through FK (refined by Newton steps for at most 1 % of them: the near-singular targets); the
// configuration the target came from is among them.
inline void everySolutionFound(const PoeModel& model, int targets, int seeds, int expected_max) {
  std::mt19937_64 rng(2026);
  ClosedFormWorkspace work(model);
  Data data(model);
  IkWorkspace ik(model);
  IkOptions numeric, at_q;
  numeric.ranges = at_q.ranges = RangePolicy::Report;
  at_q.max_iterations = 0;
  const IkOptions exact = exactOptions();
  const double L = model.lengthScale();
  int most = 0, numeric_found = 0, solutions = 0, refined = 0;
  for (int t = 0; t < targets; ++t) {
    const VecX q = sampleQ(model, rng);
    const Pose target = targetOf(model, q);
    const double sigma_q = inverseKinematics(model, data, target, q, at_q, ik).sigma_min;
    const ClosedFormResult& r = inverseKinematicsAll(model, target, exact, work);
    ASSERT_EQ(r.dropped, 0) << model.name() << " target " << t;
    most = std::max(most, r.count);
    auto member = [&](const VecX& x, double within) {
      for (int k = 0; k < r.count; ++k) {
        if (jointDistance(model, x, r.solutions[static_cast<size_t>(k)].q) <= within) return true;
      }
      return false;
    };
    for (int k = 0; k < r.count; ++k) {
      const ClosedFormSolution& s = r.solutions[static_cast<size_t>(k)];
      const Pose T = poeForwardKinematics(model, s.q);
      EXPECT_LE((T.p - target.p).norm(), kClosedFormAccuracy * L);
      EXPECT_LE(rotationError(T.R, target.R), kClosedFormAccuracy);
      ++solutions;
      refined += s.refinement_iterations > 0;
    }
    EXPECT_TRUE(member(q, sameSolution(kClosedFormAccuracy, sigma_q)))
        << model.name() << " target " << t << ": its own configuration is missing (sigma_min " << sigma_q << ")";
    for (int k = 0; k < seeds; ++k) {
      const VecX seed = sampleQ(model, rng);
      const IkResult& n = inverseKinematics(model, data, target, seed, numeric, ik);
      if (!n.converged) continue;
      ++numeric_found;
      EXPECT_TRUE(member(n.q, sameSolution(kIkTolerance, n.sigma_min)))
          << model.name() << " target " << t << ": numerical solution " << n.q.transpose() << " (sigma_min "
          << n.sigma_min << ") is not among the " << r.count << " closed-form ones";
    }
  }
  EXPECT_EQ(most, expected_max) << model.name();
  EXPECT_GT(numeric_found, targets * seeds / 4) << model.name();  // the comparison did happen
  EXPECT_LE(refined, solutions / 100) << model.name();
  std::printf("%s: %d targets, %d solutions (%d refined), %d numerical solutions from %d seeds each compared\n",
              model.name().c_str(), targets, solutions, refined, numeric_found, seeds);
}

}  // namespace ik_closed_form_helpers
