#pragma once
// Vectorizable sine and cosine for the chain evaluation (not installed; tests include it directly).
// `sinCosLane` is branch-free so that loops over it vectorize: Cody-Waite reduction by pi/2 (3-part
// constant) and the Cephes minimax polynomials on [-pi/4, pi/4]. Accuracy: within 1 ulp (absolute error
// <= 1.2 eps for |x| <= 1e6; tests/lib/kinematics_test.cpp). Precondition: finite |x| <= 1e6 (beyond, the
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

// Four lanes as one GNU vector (GCC and clang): AVX2 registers in the x86-64-v3 clone, SSE2 pairs otherwise.
typedef double Vec4d __attribute__((vector_size(32)));
typedef std::uint64_t Vec4u __attribute__((vector_size(32)));
inline Vec4u bitsOf(Vec4d x) { return (Vec4u)x; }  // vector casts reinterpret the bits
inline Vec4d fromBits(Vec4u b) { return (Vec4d)b; }
// Eight lanes (AVX-512 registers where the batch is compiled for x86-64-v4).
typedef double Vec8d __attribute__((vector_size(64)));
typedef std::uint64_t Vec8u __attribute__((vector_size(64)));
inline Vec8u bitsOf(Vec8d x) { return (Vec8u)x; }
inline Vec8d fromBits(Vec8u b) { return (Vec8d)b; }

// The kernel for one lane (D = double, U = uint64_t) or four (Vec4d, Vec4u); no branches, no calls.
template <class D, class U>
inline void sinCosT(D x, D& s, D& c) {
  const D t = x * kTwoOverPi + kRound;
  const U quadrant = bitsOf(t);  // low bits hold n = round(2x/pi)
  const D n = t - kRound;
  const D r = ((x - n * kPio2A) - n * kPio2B) - n * kPio2C;  // |r| <= pi/4
  const D z = r * r;
  const D ps = ((((( 1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z +
                   2.75573136213857245213e-6) * z - 1.98412698295895385996e-4) * z +
                 8.33333333332211858878e-3) * z - 1.66666666666666307295e-1);
  const D pc = ((((( -1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z -
                    2.75573141792967388112e-7) * z + 2.48015872888517045348e-5) * z -
                  1.38888888888730564116e-3) * z + 4.16666666666665929218e-2);
  const D sr = r + r * (z * ps);
  const D cr = (1.0 - 0.5 * z) + z * z * pc;
  // sin(r + n pi/2) = (sr, cr, -sr, -cr)[n mod 4]; cos(r + n pi/2) = (cr, -sr, -cr, sr)[n mod 4].
  const U odd = 0 - (quadrant & 1);
  const U sb = bitsOf(sr), cb = bitsOf(cr);
  s = fromBits(((cb & odd) | (sb & ~odd)) ^ ((quadrant & 2) << 62));
  c = fromBits(((sb & odd) | (cb & ~odd)) ^ (((quadrant + 1) & 2) << 62));
}

// One lane; inlined into loops that the compiler vectorizes.
inline void sinCosLane(double x, double& s, double& c) { sinCosT<double, std::uint64_t>(x, s, c); }
// Four lanes explicitly.
inline void sinCos4(Vec4d x, Vec4d& s, Vec4d& c) { sinCosT<Vec4d, Vec4u>(x, s, c); }

}  // namespace lowpair::detail
