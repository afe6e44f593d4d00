// SE(3) accuracy: the exponential against a long-double reference over rotation angles 1e-12 .. pi,
// including the branch thresholds; the logarithm near 0 and near pi; the adjoint identity.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "exp_coefficients.hpp"  // lowpair/src (internal)
#include "random_robot.hpp"

using namespace lowpair;

namespace {

using LD = long double;

struct RefExp {
  LD R[3][3];
  LD p[3];
};

// Reference coefficients in long double (64-bit mantissa): Taylor series summed to convergence below
// 2 (no cancellation at all), direct forms above (cancellation there costs < 2 long-double ulp).
void refCoefficients(LD x, LD& a, LD& b, LD& c) {
  if (x < 2.0L) {
    const LD y = x * x;
    a = b = c = 0.0L;
    LD term_a = 1.0L, term_b = 0.5L, term_c = 1.0L / 6.0L;
    for (int k = 0; k < 40; ++k) {
      a += term_a;
      b += term_b;
      c += term_c;
      term_a *= -y / ((2 * k + 2) * (2 * k + 3));
      term_b *= -y / ((2 * k + 3) * (2 * k + 4));
      term_c *= -y / ((2 * k + 4) * (2 * k + 5));
    }
  } else {
    a = sinl(x) / x;
    b = (1.0L - cosl(x)) / (x * x);
    c = (x - sinl(x)) / (x * x * x);
  }
}

RefExp refExp(const Vec6& xi) {
  const LD w[3] = {xi[0], xi[1], xi[2]};
  const LD v[3] = {xi[3], xi[4], xi[5]};
  const LD x = sqrtl(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  LD a, b, c;
  refCoefficients(x, a, b, c);
  const LD W[3][3] = {{0, -w[2], w[1]}, {w[2], 0, -w[0]}, {-w[1], w[0], 0}};
  LD W2[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      W2[i][j] = 0;
      for (int k = 0; k < 3; ++k) W2[i][j] += W[i][k] * W[k][j];
    }
  RefExp out;
  for (int i = 0; i < 3; ++i) {
    out.p[i] = v[i];
    for (int j = 0; j < 3; ++j) {
      out.R[i][j] = (i == j ? 1.0L : 0.0L) + a * W[i][j] + b * W2[i][j];
      out.p[i] += (b * W[i][j] + c * W2[i][j]) * v[j];
    }
  }
  return out;
}

// Worst "ulp-equivalent" entry error |x - x_ref| / (eps max(1, |x_ref|)) of rotation and translation.
struct UlpError {
  double rotation = 0, translation = 0;
};
UlpError ulpError(const Pose& T, const RefExp& ref) {
  UlpError e;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const LD d = fabsl(static_cast<LD>(T.R(i, j)) - ref.R[i][j]) / (kEps * fmaxl(1.0L, fabsl(ref.R[i][j])));
      e.rotation = std::max(e.rotation, static_cast<double>(d));
    }
    const LD d = fabsl(static_cast<LD>(T.p[i]) - ref.p[i]) / (kEps * fmaxl(1.0L, fabsl(ref.p[i])));
    e.translation = std::max(e.translation, static_cast<double>(d));
  }
  return e;
}

std::vector<double> sweepAngles() {
  std::vector<double> angles;
  for (int k = 0; k <= 1200; ++k) angles.push_back(1e-12 * std::pow(M_PI / 1e-12, k / 1200.0));
  for (double t : {1e-4, kSeriesAngle, 0.1, M_PI / 2}) {
    angles.push_back(t);
    angles.push_back(std::nextafter(t, 0.0));
    angles.push_back(std::nextafter(t, 10.0));
  }
  angles.push_back(M_PI - 1e-12);
  return angles;
}

Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return lowpair_test::draw3(n, rng).normalized();
}

}  // namespace

TEST(Se3Hat, VeeInvertsHat) {
  const Vec6 xi = (Vec6() << 0.1, -0.2, 0.3, 1.0, 2.0, -3.0).finished();
  EXPECT_EQ(vee6(hat6(xi)), xi);
  EXPECT_EQ(hat3(xi.head<3>()) * Vec3(1, 2, 3), Vec3(xi.head<3>()).cross(Vec3(1, 2, 3)));
}

TEST(Se3Exp, CoefficientsRelativeErrorAcrossSweep) {
  double worst = 0;
  for (double x : sweepAngles()) {
    const detail::ExpCoefficients k = detail::expCoefficients(x);
    LD a, b, c;
    refCoefficients(x, a, b, c);
    worst = std::max({worst, static_cast<double>(fabsl((k.a - a) / a)), static_cast<double>(fabsl((k.b - b) / b)),
                      static_cast<double>(fabsl((k.c - c) / c))});
  }
  RecordProperty("worst_relative_error_eps", worst / kEps);
  std::printf("exp coefficients: worst relative error %.2f eps\n", worst / kEps);
  EXPECT_LE(worst, 4 * kEps);
}

// Each variant of the exponential, over the angle sweep with random unit axes and |v| = 1 (so every
// entry is O(1) and the ulp-equivalent measure is a relative one).
TEST(Se3Exp, SweepAgainstLongDoubleReference) {
  std::mt19937_64 rng(7);
  UlpError worst_general, worst_joint;
  for (double angle : sweepAngles()) {
    for (int rep = 0; rep < 4; ++rep) {
      const Vec3 w = randomUnit(rng);
      const Vec3 v = randomUnit(rng);
      const double pitch = rep % 2 ? 0.0 : 0.3;
      const Vec3 v_joint = v - w.dot(v) * w + pitch * w;
      Vec6 xi;
      xi << angle * w, angle * v;
      const RefExp ref = refExp(xi);
      const UlpError e = ulpError(expSE3(xi), ref);
      worst_general.rotation = std::max(worst_general.rotation, e.rotation);
      worst_general.translation = std::max(worst_general.translation, e.translation);
      Vec6 xj;
      xj << angle * w, angle * v_joint;
      Pose T;
      expUnitTwist(w, v_joint, pitch, angle, T);
      const UlpError ej = ulpError(T, refExp(xj));
      worst_joint.rotation = std::max(worst_joint.rotation, ej.rotation);
      worst_joint.translation = std::max(worst_joint.translation, ej.translation);
    }
  }
  std::printf("expSE3: worst %.2f ulp (rotation), %.2f ulp (translation)\n", worst_general.rotation,
              worst_general.translation);
  std::printf("expUnitTwist: worst %.2f ulp (rotation), %.2f ulp (translation)\n", worst_joint.rotation,
              worst_joint.translation);
  // The reference's own input is the double twist, so the error is the rounding of the closed forms: the
  // coefficients' relative error (at most 4 eps, the test above; sin and cos of the joint form within 1 ulp)
  // plus the roundings along an entry's path (an entry of w x (w x v) or of b w w^T + a W passes through at
  // most 8 operations of u = eps / 2 each: 4 eps), on entries of size at most max(1, |x_ref|) for these unit
  // inputs (|v| = 1, |w| <= pi, coefficients <= 1): 8 eps. (GCC measures 4, clang 4.9: FMA contraction.)
  constexpr double kBound = 8.0;
  EXPECT_LE(worst_general.rotation, kBound);
  EXPECT_LE(worst_general.translation, kBound);
  EXPECT_LE(worst_joint.rotation, kBound);
  EXPECT_LE(worst_joint.translation, kBound);
}

TEST(Se3Exp, ZeroAndPureTranslation) {
  Vec6 xi = Vec6::Zero();
  EXPECT_TRUE(expSE3(xi).matrix().isIdentity(0.0));
  xi << 0, 0, 0, 1, -2, 3;
  const Pose T = expSE3(xi);
  EXPECT_TRUE(T.R.isIdentity(0.0));
  EXPECT_EQ(T.p, Vec3(1, -2, 3));
}

TEST(Se3Log, RoundTripAcrossSweepAndNearPi) {
  std::mt19937_64 rng(11);
  std::vector<double> angles = sweepAngles();
  for (int k = 1; k <= 15; ++k) angles.push_back(M_PI - std::pow(10.0, -k));
  angles.push_back(M_PI);
  double worst_R = 0, worst_p = 0, worst_xi = 0;
  for (double angle : angles) {
    for (int rep = 0; rep < 4; ++rep) {
      const Vec3 w = randomUnit(rng);
      const Vec3 v = randomUnit(rng);
      Vec6 xi;
      xi << angle * w, angle * v;
      const Pose T = expSE3(xi);
      const Vec6 back = logSE3(T);
      const Pose T2 = expSE3(back);
      worst_R = std::max(worst_R, (T2.R - T.R).cwiseAbs().maxCoeff());
      worst_p = std::max(worst_p, (T2.p - T.p).cwiseAbs().maxCoeff());
      // the twist itself is recoverable away from pi (at pi, w and -w give the same rotation)
      if (angle < M_PI - 1e-6) worst_xi = std::max(worst_xi, (back - xi).cwiseAbs().maxCoeff() / std::max(1.0, angle));
    }
  }
  std::printf("log: worst exp(log T) - T: %.2g (R), %.2g (p); worst log(exp xi) - xi: %.2g\n", worst_R, worst_p,
              worst_xi);
  EXPECT_LE(worst_R, 8 * kEps);
  EXPECT_LE(worst_p, 8 * kEps);
  // Away from pi the axis is conditioned by 1/sin(angle): 1e-6 from pi costs up to 1e6 eps.
  EXPECT_LE(worst_xi, 1e-9);
}

TEST(Se3Log, ExactlyPiAboutCoordinateAxes) {
  for (int k = 0; k < 3; ++k) {
    Vec3 w = Vec3::Zero();
    w[k] = M_PI;
    const Mat3 R = expSO3(w);
    const Vec3 back = logSO3(R);
    EXPECT_NEAR(back.norm(), M_PI, 4 * kEps);
    EXPECT_LE((expSO3(back) - R).cwiseAbs().maxCoeff(), 4 * kEps);
  }
}

TEST(Se3Adjoint, ConjugationIdentity) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 100; ++i) {
    Vec6 a, b;
    a << randomUnit(rng) * 2.0, randomUnit(rng) * 5.0;
    b << randomUnit(rng) * 1.3, randomUnit(rng);
    const Pose T = expSE3(a);
    const Pose lhs = expSE3(adjointApply(T, b));
    const Pose rhs = T * expSE3(b) * T.inverse();
    EXPECT_LE((lhs.matrix() - rhs.matrix()).cwiseAbs().maxCoeff(), 64 * kEps);
    EXPECT_LE((adjoint(T) * b - adjointApply(T, b)).cwiseAbs().maxCoeff(), 16 * kEps);
  }
}

TEST(Se3RotationAngle, ResolvesTinyAngles) {
  // acos((tr R - 1)/2) cannot resolve below ~1e-8 rad; the atan2 form can.
  const Mat3 R = expSO3(Vec3(1e-12, 0, 0));
  EXPECT_NEAR(rotationAngle(R), 1e-12, 1e-24);
}
