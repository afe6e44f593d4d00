// The chain kernel as it was before the work of issue 29 (lowpair/src/kinematics.cpp and jacobian.cpp's
// fillSpatial at commit 1cedb69), kept verbatim as the "previous lowpair" of the benchmarks (bench/README.md): the
// same run times both, so the speed-up is measured on the same machine under the same load. Compiled with the
// library's flags and dispatch (x86-64-v3 clone), as the library was.
#include "chain_baseline.hpp"

#include <cmath>
#include <cstring>

#include "chain_eval.hpp"
#include "lowpair/se3.hpp"
#include "sincos.hpp"

#if defined(__GNUC__) && !defined(__clang__)
#define LP_ALWAYS_INLINE __attribute__((always_inline))
#else
#define LP_ALWAYS_INLINE
#endif
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(LOWPAIR_NO_DISPATCH)
#define LP_DISPATCH __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define LP_DISPATCH
#endif

namespace lowpair_bench::baseline {

using namespace lowpair;

namespace {

int paddedDof(const KinematicChain& chain) { return static_cast<int>(chain.lanes.theta.size()); }

using detail::sinCosLane;

// sin and cos of n angles together, n a multiple of detail::kChainLanes (the loop vectorizes); angles beyond the kernel's accurate range
// (possible only for huge joint values) are recomputed with libm.
// (The range test is an integer OR so that the loop still vectorizes; a floating max would not.)
inline bool outOfRange(double angle) { return !(std::abs(angle) <= detail::kSinCosMaxArgument); }

LP_ALWAYS_INLINE inline void sinCosAll(const double* __restrict angle, int n, double* __restrict s,
                                       double* __restrict c) {
  int out_of_range = 0;
  for (int i = 0; i < n; ++i) {
    sinCosLane(angle[i], s[i], c[i]);
    out_of_range |= outOfRange(angle[i]);
  }
  if (out_of_range) {
    for (int i = 0; i < n; ++i) {
      s[i] = std::sin(angle[i]);
      c[i] = std::cos(angle[i]);
    }
  }
}

// The motion rule on a link's constants (JointMotion's (j, k)): joint motion x turns the link by
// theta + j x and slides it by p_z + k x; T is a double or a vector of lanes.
template <class T>
LP_ALWAYS_INLINE inline T linkAngle(double theta, double turn, T x) { return theta + turn * x; }
template <class T>
LP_ALWAYS_INLINE inline T linkSlide(double z, double slide, T x) { return z + slide * x; }

// One row k of T <- T Rz(angle) Trans(p_x, p_y, slide) Rx(alpha) on the rotation columns X, Y, Z and the
// position P, given cos/sin of the angle; T is a double or a vector of lanes (the batch).
template <class T>
LP_ALWAYS_INLINE inline void linkStep(const ChainLink& link, T c, T s, T slide, T& X, T& Y, T& Z, T& P) {
  const T x = c * X + s * Y;
  const T y = c * Y - s * X;
  const T z = Z;
  P += (link.p[0] * x + link.p[1] * y) + slide * z;
  X = x;
  Y = link.cos_alpha * y + link.sin_alpha * z;
  Z = link.cos_alpha * z - link.sin_alpha * y;
}

// Row k of (T * T_last_tool): rotation entry m and the position, from T's row k (X, Y, Z, P).
template <class T>
LP_ALWAYS_INLINE inline T toolRotation(const Pose& E, int m, T X, T Y, T Z) {
  return (X * E.R(0, m) + Y * E.R(1, m)) + Z * E.R(2, m);
}
template <class T>
LP_ALWAYS_INLINE inline T toolPosition(const Pose& E, T X, T Y, T Z, T P) {
  return ((X * E.p[0] + Y * E.p[1]) + Z * E.p[2]) + P;
}

// The chain product of model.hpp's KinematicChain. Columns X, Y, Z of the rotation and the position P
// are updated in place by T <- T Rz(angle) Trans(p + slide e_z) Rx(alpha); kFrames stores the frame
// before each link (joint i's line) in data.T_base_joint.
template <bool kFrames>
LP_ALWAYS_INLINE inline void evaluate(const KinematicChain& chain, Data& data, const double* q) {
  const int n = data.dof;
  const int padded = paddedDof(chain);  // a multiple of kChainLanes: the lane loops below run in full vectors
  const detail::ChainLanes& c = chain.lanes;
  double* __restrict qp = data.q_padded.data();
  double* __restrict angle = data.angle.data();
  double* __restrict slide = data.slide.data();
  const double* __restrict theta = c.theta.data();
  const double* __restrict turn = c.turn.data();
  const double* __restrict slide_rate = c.slide.data();
  const double* __restrict z0 = c.z.data();
  const double* __restrict scale = c.scale.data();
  const double* __restrict offset = c.offset.data();
  std::memcpy(qp, q, sizeof(double) * static_cast<size_t>(n));
  constexpr int L = detail::kChainLanes;
  for (int b = 0; b < padded; b += L) {
    for (int i = b; i < b + L; ++i) {  // fixed trip count: one SIMD vector
      const double x = motionOf(qp[i], scale[i], offset[i]);
      angle[i] = linkAngle(theta[i], turn[i], x);
      slide[i] = linkSlide(z0[i], slide_rate[i], x);
    }
  }
  double* __restrict sin_angle = data.sin_angle.data();
  double* __restrict cos_angle = data.cos_angle.data();
  sinCosAll(angle, padded, sin_angle, cos_angle);
  const double* st = sin_angle;
  const double* ct = cos_angle;
  double X[3], Y[3], Z[3], P[3];
  const Pose& B = chain.T_base_first;
  for (int k = 0; k < 3; ++k) {
    X[k] = B.R(k, 0);
    Y[k] = B.R(k, 1);
    Z[k] = B.R(k, 2);
    P[k] = B.p[k];
  }
  for (int i = 0; i < n; ++i) {
    const ChainLink& link = chain.links[static_cast<size_t>(i)];
    if (kFrames) {
      Pose& F = data.T_base_joint[static_cast<size_t>(i)];
      for (int k = 0; k < 3; ++k) {
        F.R(k, 0) = X[k];
        F.R(k, 1) = Y[k];
        F.R(k, 2) = Z[k];
        F.p[k] = P[k];
      }
    }
    for (int k = 0; k < 3; ++k) linkStep(link, ct[i], st[i], slide[i], X[k], Y[k], Z[k], P[k]);
  }
  const Pose& E = chain.T_last_tool;
  Pose& T = data.T_base_tool;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) T.R(k, m) = toolRotation(E, m, X[k], Y[k], Z[k]);
    T.p[k] = toolPosition(E, X[k], Y[k], Z[k], P[k]);
  }
}

// One batch block: the configurations of one GNU vector V (4 lanes: AVX2 / SSE2 pairs; 8 lanes: AVX-512),
// so the whole state of a block (rotation columns X, Y, Z and position P, three rows each) stays in
// registers. U is the matching unsigned vector (the sine kernel's bit operations).
using detail::Vec4d;
using detail::Vec4u;
using detail::Vec8d;
using detail::Vec8u;

template <class V>
constexpr int lanesOf() { return static_cast<int>(sizeof(V) / sizeof(double)); }

template <class V>
inline V broadcast(double v) { return V{} + v; }

// kFull: all lanes are configurations; otherwise the last, partial block (unused lanes hold q = 0).
template <bool kFull, class V, class U>
LP_ALWAYS_INLINE inline void evaluateBlock(const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                                           Eigen::Ref<MatX> poses, Eigen::Index first, int partial_lanes,
                                           bool use_libm) {
  constexpr int N = lanesOf<V>();
  const int lanes = kFull ? N : partial_lanes;
  const size_t bytes = sizeof(double) * static_cast<size_t>(lanes);
  V X[3], Y[3], Z[3], P[3];
  const Pose& Bs = chain.T_base_first;
  for (int k = 0; k < 3; ++k) {
    X[k] = broadcast<V>(Bs.R(k, 0));
    Y[k] = broadcast<V>(Bs.R(k, 1));
    Z[k] = broadcast<V>(Bs.R(k, 2));
    P[k] = broadcast<V>(Bs.p[k]);
  }
  for (size_t i = 0; i < chain.links.size(); ++i) {
    const ChainLink& link = chain.links[i];
    V qv = broadcast<V>(0.0);
    std::memcpy(&qv, q.col(static_cast<Eigen::Index>(i)).data() + first, bytes);
    const V x = motionOf(qv, link.motion.scale, link.motion.offset);
    const V angle = linkAngle(link.theta, link.turn, x);
    const V slide = linkSlide(link.p[2], link.slide, x);
    V st, ct;
    detail::sinCosT<V, U>(angle, st, ct);
    if (use_libm) {
      for (int l = 0; l < N; ++l) {
        st[l] = std::sin(angle[l]);
        ct[l] = std::cos(angle[l]);
      }
    }
    for (int k = 0; k < 3; ++k) linkStep(link, ct, st, slide, X[k], Y[k], Z[k], P[k]);
  }
  // T * T_last_tool, written to the output columns
  const Pose& E = chain.T_last_tool;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) {
      const V r = toolRotation(E, m, X[k], Y[k], Z[k]);
      std::memcpy(poses.col(3 * k + m).data() + first, &r, bytes);
    }
    const V p = toolPosition(E, X[k], Y[k], Z[k], P[k]);
    std::memcpy(poses.col(9 + k).data() + first, &p, bytes);
  }
}

template <class V, class U>
LP_ALWAYS_INLINE inline void evaluateBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                                           Eigen::Ref<MatX> poses) {
  constexpr int N = lanesOf<V>();
  // one pass over the input decides whether an angle is beyond the sine kernel's range (then libm is used
  // for the whole call): no per-lane test inside the blocks
  int out_of_range = 0;
  for (size_t i = 0; i < chain.links.size(); ++i) {
    const ChainLink& link = chain.links[i];
    const double* qi = q.col(static_cast<Eigen::Index>(i)).data();
    for (Eigen::Index k = 0; k < q.rows(); ++k) {
      out_of_range |= outOfRange(linkAngle(link.theta, link.turn, motionOf(qi[k], link.motion.scale, link.motion.offset)));
    }
  }
  const bool use_libm = out_of_range != 0;
  Eigen::Index first = 0;
  for (; first + N <= q.rows(); first += N) evaluateBlock<true, V, U>(chain, q, poses, first, N, use_libm);
  if (first < q.rows()) {
    evaluateBlock<false, V, U>(chain, q, poses, first, static_cast<int>(q.rows() - first), use_libm);
  }
}

void fillSpatial(Data& data, const KinematicChain& chain) {
  for (int i = 0; i < data.dof; ++i) {
    const ChainLink& link = chain.links[static_cast<size_t>(i)];
    const Pose& F = data.T_base_joint[static_cast<size_t>(i)];
    const double j = link.motion.scale * link.turn, k = link.motion.scale * link.slide;
    const double z0 = F.R(0, 2), z1 = F.R(1, 2), z2 = F.R(2, 2);
    const double o0 = F.p[0], o1 = F.p[1], o2 = F.p[2];
    double* c = data.J_spatial.col(i).data();  // [j z; j o x z + k z]
    c[0] = j * z0;
    c[1] = j * z1;
    c[2] = j * z2;
    c[3] = j * (o1 * z2 - o2 * z1) + k * z0;
    c[4] = j * (o2 * z0 - o0 * z2) + k * z1;
    c[5] = j * (o0 * z1 - o1 * z0) + k * z2;
  }
}

}  // namespace

LP_DISPATCH void forwardKinematics(const KinematicChain& chain, Data& data, const double* q) {
  evaluate<false>(chain, data, q);
}

LP_DISPATCH void computeJacobians(const KinematicChain& chain, Data& data, const double* q) {
  evaluate<true>(chain, data, q);
  fillSpatial(data, chain);
}

LP_DISPATCH void forwardKinematicsBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                                        Eigen::Ref<MatX> poses) {
  evaluateBatch<Vec4d, Vec4u>(chain, q, poses);
}

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(LOWPAIR_NO_DISPATCH)
__attribute__((target("arch=x86-64-v4"))) void forwardKinematicsBatch8(const KinematicChain& chain,
                                                                       const Eigen::Ref<const MatX>& q,
                                                                       Eigen::Ref<MatX> poses) {
  evaluateBatch<Vec8d, Vec8u>(chain, q, poses);
}
bool hasBatch8() { return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"); }
#else
void forwardKinematicsBatch8(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  forwardKinematicsBatch(chain, q, poses);
}
bool hasBatch8() { return false; }
#endif

void currentBatch4(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  lowpair::detail::chainBatch(chain, q, poses);
}

}  // namespace lowpair_bench::baseline
