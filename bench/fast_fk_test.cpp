// The fast D-H kernel (single call and batch, lowpair/fast_fk.hpp) equals the library FK within
// 1e-12 x robot size on every benchmark robot, and its sinCos is accurate to about 1 ulp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "lowpair/fast_fk.hpp"
#include "robots_lowpair.hpp"

using namespace lowpair;
using namespace lowpair_bench;

namespace {

double pose12Error(const RobotCase& r, int k, const Pose& T) {
  double pose[12];
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) pose[3 * a + b] = T.R(a, b);
    pose[9 + a] = T.p[a];
  }
  return poseMismatch(r, k, pose);
}

}  // namespace

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
  std::vector<double> s(x.size()), c(x.size());
  sinCos(x.data(), static_cast<int>(x.size()), s.data(), c.data());
  double abs_err = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    const long double xs = std::sin(static_cast<long double>(x[i])), xc = std::cos(static_cast<long double>(x[i]));
    abs_err = std::max(abs_err, static_cast<double>(std::max(std::abs(s[i] - xs), std::abs(c[i] - xc))) / eps);
  }
  RecordProperty("max_abs_error_eps", std::to_string(abs_err));
  EXPECT_LE(abs_err, 1.2);
}

TEST(DhKernel, SingleAndBatchEqualLibraryFk) {
  for (RobotId id : kRobots) {
    const RobotCase& r = robotCase(id);
    const DhKernel kernel(robotModels(id).dh);
    // single call
    double single = 0.0;
    Pose T;
    for (int k = 0; k < kPool; ++k) {
      kernel.forward(&r.q[static_cast<size_t>(k * r.dof)], T);
      single = std::max(single, pose12Error(r, k, T));
    }
    EXPECT_LE(single, kAgree) << r.name;
    // batch, a count that is not a multiple of the block
    const int count = kPool - 3;
    std::vector<double> q(static_cast<size_t>(r.dof * kPool)), out(12 * kPool);
    for (int k = 0; k < kPool; ++k) {
      for (int i = 0; i < r.dof; ++i) q[static_cast<size_t>(i * kPool + k)] = r.q[static_cast<size_t>(k * r.dof + i)];
    }
    kernel.forwardBatch(q.data(), count, kPool, out.data());
    double batch = 0.0, batch_vs_single = 0.0;
    for (int k = 0; k < count; ++k) {
      double pose[12];
      for (int e = 0; e < 12; ++e) pose[e] = out[static_cast<size_t>(e * kPool + k)];
      batch = std::max(batch, poseMismatch(r, k, pose));
      kernel.forward(&r.q[static_cast<size_t>(k * r.dof)], T);
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) batch_vs_single = std::max(batch_vs_single, std::abs(pose[3 * a + b] - T.R(a, b)));
        batch_vs_single = std::max(batch_vs_single, std::abs(pose[9 + a] - T.p[a]) / r.size);
      }
    }
    EXPECT_LE(batch, kAgree) << r.name;
    EXPECT_LE(batch_vs_single, kAgree) << r.name;
  }
}

TEST(DhKernel, GeometricJacobianEqualsLibrary) {
  for (RobotId id : kRobots) {
    const RobotCase& r = robotCase(id);
    const DhKernel kernel(robotModels(id).dh);
    Pose T;
    Mat6X J(6, r.dof);
    Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> Jr(6, r.dof);
    double err = 0.0;
    for (int k = 0; k < kPool; ++k) {
      kernel.geometricJacobian(&r.q[static_cast<size_t>(k * r.dof)], T, J);
      Jr = J;
      err = std::max({err, pose12Error(r, k, T), jacobianMismatch(r, k, Jr.data())});
    }
    EXPECT_LE(err, kAgree) << r.name;
  }
}
