// RobustLoss (robust_loss.hpp): the IRLS weight is rho'(u) / (2u), checked against central differences of
// rho on both sides of the Huber threshold and of the Cauchy scale.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "lowpair/robust_loss.hpp"

namespace lowpair {
namespace {

constexpr double kMachineEps = std::numeric_limits<double>::epsilon();

// The bound on |weight_fd - weight| where weight_fd = (rho(u + h) - rho(u - h)) / (2h) / (2u), u and h binary
// fractions (u +- h exact, the division by 2h exact):
// - rounding: every intermediate of rho (u^2; 2 s u and s^2; s^2 log1p((u/s)^2) <= u^2) is at most
//   M = (u + h + s)^2, and rho takes at most 8 roundings of it, so each evaluation is within 8 eps M; the
//   difference of the two adds eps |difference| <= 2 eps M: 18 eps M / (2h) on rho';
// - truncation: the central difference's remainder h^2 / 6 max |rho'''| on [u - h, u + h] (`third`);
// - the quotient by 2u and weight()'s own rounding (|weight| <= 1): 4 eps.
double finiteDifferenceTolerance(double u, double h, double s, double third) {
  const double M = (u + h + s) * (u + h + s);
  return (18.0 * kMachineEps * M / (2.0 * h) + h * h / 6.0 * third) / (2.0 * u) + 4.0 * kMachineEps;
}

double finiteDifferenceWeight(const RobustLoss& loss, double u, double h) {
  return (loss.rho(u + h) - loss.rho(u - h)) / (2.0 * h) / (2.0 * u);
}

TEST(RobustLoss, OfUsesTheLibraryScales) {
  EXPECT_EQ(RobustLoss::of(Loss::Huber).scale, kHuberThreshold);
  EXPECT_EQ(RobustLoss::of(Loss::Cauchy).scale, kCauchyScale);
  EXPECT_EQ(RobustLoss::of(Loss::Squared).kind, Loss::Squared);
}

TEST(RobustLoss, SquaredWeightIsTheDerivativeOfRho) {
  const RobustLoss loss = RobustLoss::of(Loss::Squared);
  const double h = 1.0 / 16.0;  // rho = u^2: rho''' = 0, no truncation
  for (const double u : {0.5, 1.5, 7.5, 40.0}) {
    EXPECT_NEAR(finiteDifferenceWeight(loss, u, h), loss.weight(u), finiteDifferenceTolerance(u, h, loss.scale, 0.0))
        << "u = " << u;
    EXPECT_EQ(loss.weight(u), 1.0);
  }
}

TEST(RobustLoss, HuberWeightIsTheDerivativeOfRhoOnBothBranches) {
  const RobustLoss loss = RobustLoss::of(Loss::Huber);
  // rho is u^2 inside the threshold and 2 s u - s^2 beyond: rho''' = 0 while [u - h, u + h] stays on one
  // branch, so h can be large (the rounding term shrinks with it)
  const double h = 1.0 / 16.0;
  for (const double u : {0.5, 1.5, 2.875, 3.125, 7.5, 40.0}) {
    ASSERT_TRUE(u + h <= loss.scale || u - h > loss.scale) << "u = " << u << " straddles the threshold";
    EXPECT_NEAR(finiteDifferenceWeight(loss, u, h), loss.weight(u), finiteDifferenceTolerance(u, h, loss.scale, 0.0))
        << "u = " << u;
  }
  EXPECT_EQ(loss.weight(1.5), 1.0);               // inside: least squares
  EXPECT_DOUBLE_EQ(loss.weight(7.5), 3.0 / 7.5);  // beyond: s / u
}

TEST(RobustLoss, CauchyWeightIsTheDerivativeOfRhoInsideAndBeyondItsScale) {
  const RobustLoss loss = RobustLoss::of(Loss::Cauchy);
  const double s = loss.scale;
  // rho''' = -4 u s^2 (3 s^2 - u^2) / (s^2 + u^2)^3, so |rho'''| <= 12 u s^2 / (s^2 + u^2)^2 on [u - h, u + h]
  // is at most 12 (u + h) s^2 / (s^2 + (u - h)^2)^2; h = 2^-15 balances that term (h^2) with rounding (1/h)
  const double h = std::ldexp(1.0, -15);
  for (const double u : {0.5, 1.5, 3.75, 4.25, 12.0, 40.0}) {
    const double third = 12.0 * (u + h) * s * s / std::pow(s * s + (u - h) * (u - h), 2);
    EXPECT_NEAR(finiteDifferenceWeight(loss, u, h), loss.weight(u), finiteDifferenceTolerance(u, h, s, third))
        << "u = " << u;
  }
}

TEST(RobustLoss, NormalizedResidualIsTheRmsOverPointRows) {
  // a point (3 rows): |r|; a pose (6 rows): the root mean square of its two 3-row parts
  EXPECT_DOUBLE_EQ(normalizedResidual(4.0, 3), 2.0);
  EXPECT_DOUBLE_EQ(normalizedResidual(4.0 + 16.0, 6), std::sqrt(10.0));
}

}  // namespace
}  // namespace lowpair
