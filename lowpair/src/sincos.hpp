#pragma once
// Vectorizable sine and cosine for the chain evaluation (not installed; tests include it directly).
// `sinCosLane` is branch-free so that loops over it vectorize: Cody-Waite reduction by pi/2 (3-part
// constant) and the Cephes minimax polynomials on [-pi/4, pi/4]. Accuracy: within 1 ulp (absolute error
// <= 1.2 eps for |x| <= 1e6; tests/sincos_test.cpp). Precondition: finite |x| <= 1e6 (beyond, the
// reduction loses accuracy: n * kPio2A is exact only for |n| < 2^29); callers fall back to std::sin/cos.
// Hand-written rather than SLEEF: bench/README.md compares the two.

#include <cstdint>
#include <cstring>

namespace lowpair::detail {

/// Largest |x| for which sinCosLane keeps its accuracy.
constexpr double kSinCosMaxArgument = 1e6;

// Cody-Waite split of pi/2 (Cephes DP1..DP3 times 2): n * kPio2A is exact for |n| < 2^29.
constexpr double kPio2A = 1.57079625129699707031e0;
constexpr double kPio2B = 7.54978941586159635335e-8;
constexpr double kPio2C = 5.39030285815811905290e-15;
constexpr double kTwoOverPi = 0.63661977236758134308;
constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer in the low bits

inline std::uint64_t bitsOf(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
inline double fromBits(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// One lane; inlined into loops that the compiler vectorizes (no branches, no calls).
inline void sinCosLane(double x, double& s, double& c) {
  const double t = x * kTwoOverPi + kRound;
  const std::uint64_t quadrant = bitsOf(t);  // low bits hold n = round(2x/pi)
  const double n = t - kRound;
  const double r = ((x - n * kPio2A) - n * kPio2B) - n * kPio2C;  // |r| <= pi/4
  const double z = r * r;
  const double ps = ((((( 1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z +
                        2.75573136213857245213e-6) * z - 1.98412698295895385996e-4) * z +
                      8.33333333332211858878e-3) * z - 1.66666666666666307295e-1);
  const double pc = ((((( -1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z -
                         2.75573141792967388112e-7) * z + 2.48015872888517045348e-5) * z -
                       1.38888888888730564116e-3) * z + 4.16666666666665929218e-2);
  const double sr = r + r * (z * ps);
  const double cr = (1.0 - 0.5 * z) + z * z * pc;
  // sin(r + n pi/2) = (sr, cr, -sr, -cr)[n mod 4]; cos(r + n pi/2) = (cr, -sr, -cr, sr)[n mod 4].
  const std::uint64_t odd = 0 - (quadrant & 1);
  const std::uint64_t sb = bitsOf(sr), cb = bitsOf(cr);
  s = fromBits(((cb & odd) | (sb & ~odd)) ^ ((quadrant & 2) << 62));
  c = fromBits(((sb & odd) | (cb & ~odd)) ^ (((quadrant + 1) & 2) << 62));
}


}  // namespace lowpair::detail
