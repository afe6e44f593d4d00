#pragma once
// Accuracy of an se(3) exponential against a long-double reference over a rotation-angle sweep
// 1e-12 .. pi (log-spaced, plus the neighbourhoods of the branch thresholds 1e-4 and 1.5 and of pi).
// Error per entry: |x - x_ref| / (eps max(1, |x_ref|)) ("ulp-equivalent"), rotation and translation
// separately. Used by bench/exp_accuracy.cpp (README table) and bench/exp_variants_test.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "lowpair/types.hpp"

namespace lowpair_bench {

struct ExpError {
  double rotation = 0.0, translation = 0.0;            // worst ulp-equivalent error
  double rotation_angle = 0.0, translation_angle = 0.0;  // where it occurred
};

// exp(hat6(xi)) in long double for a double twist: R = I + a W + b W^2, p = (I + b W + c W^2) v,
// coefficients by their Taylor series below 2 (no cancellation) and directly above.
inline void referenceExp(const lowpair::Vec6& xi, long double R[3][3], long double p[3]) {
  using LD = long double;
  const LD w[3] = {xi[0], xi[1], xi[2]}, v[3] = {xi[3], xi[4], xi[5]};
  const LD y = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  const LD x = std::sqrt(y);
  LD a = 0, b = 0, c = 0;
  if (x < 2.0L) {
    LD ta = 1.0L, tb = 0.5L, tc = 1.0L / 6.0L;
    for (int k = 0; k < 40; ++k) {
      a += ta;
      b += tb;
      c += tc;
      ta *= -y / ((2 * k + 2) * (2 * k + 3));
      tb *= -y / ((2 * k + 3) * (2 * k + 4));
      tc *= -y / ((2 * k + 4) * (2 * k + 5));
    }
  } else {
    a = std::sin(x) / x;
    b = (1.0L - std::cos(x)) / y;
    c = (x - std::sin(x)) / (x * y);
  }
  const LD W[3][3] = {{0, -w[2], w[1]}, {w[2], 0, -w[0]}, {-w[1], w[0], 0}};
  LD W2[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      W2[i][j] = 0;
      for (int k = 0; k < 3; ++k) W2[i][j] += W[i][k] * W[k][j];
    }
  }
  for (int i = 0; i < 3; ++i) {
    p[i] = v[i];
    for (int j = 0; j < 3; ++j) {
      R[i][j] = (i == j ? 1.0L : 0.0L) + a * W[i][j] + b * W2[i][j];
      p[i] += (b * W[i][j] + c * W2[i][j]) * v[j];
    }
  }
}

inline std::vector<double> sweepAngles() {
  std::vector<double> angles;
  for (int i = 0; i <= 600; ++i) angles.push_back(std::pow(10.0, -12.0 + i * (12.0 + std::log10(M_PI)) / 600.0));
  for (double t : {1e-4, 1.5, M_PI}) {
    for (int i = -20; i <= 20; ++i) angles.push_back(std::min(M_PI, t * (1.0 + i * 1e-3)));
  }
  for (int i = 1; i <= 20; ++i) angles.push_back(M_PI - i * 1e-9);
  return angles;
}

// Worst error of `exp` (Vec6 -> Pose) over the sweep, `axes` random unit axes and translations per angle.
template <class Exp>
ExpError expSweepError(Exp exp, int axes = 16) {
  const double eps = std::numeric_limits<double>::epsilon();
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  ExpError out;
  for (double angle : sweepAngles()) {
    for (int s = 0; s < axes; ++s) {
      lowpair::Vec3 axis(u(rng), u(rng), u(rng));
      axis.normalize();
      lowpair::Vec6 xi;
      xi << angle * axis, lowpair::Vec3(u(rng), u(rng), u(rng));
      long double R[3][3], p[3];
      referenceExp(xi, R, p);
      const lowpair::Pose T = exp(xi);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const double e = static_cast<double>(std::abs(T.R(i, j) - R[i][j]) / std::max(1.0L, std::abs(R[i][j]))) / eps;
          if (!(e <= out.rotation)) out.rotation = std::isnan(e) ? INFINITY : e, out.rotation_angle = angle;
        }
        const double e = static_cast<double>(std::abs(T.p[i] - p[i]) / std::max(1.0L, std::abs(p[i]))) / eps;
        if (!(e <= out.translation)) out.translation = std::isnan(e) ? INFINITY : e, out.translation_angle = angle;
      }
    }
  }
  return out;
}

}  // namespace lowpair_bench
