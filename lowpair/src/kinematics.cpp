#include "lowpair/kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "chain_eval.hpp"
#include "check.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/se3.hpp"
#include "sincos.hpp"

#if defined(__GNUC__) && !defined(__clang__)
#define LP_ALWAYS_INLINE __attribute__((always_inline))
#else
#define LP_ALWAYS_INLINE
#endif
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(LOWPAIR_NO_DISPATCH)
#define LP_DISPATCH __attribute__((target_clones("arch=x86-64-v3", "default")))
#define LP_HAVE_AVX512_BATCH 1
#else
#define LP_DISPATCH
#endif

namespace lowpair {

namespace {
// the scratch length: dof rounded up to the chain's SIMD lanes (detail::ChainLanes)
int paddedDof(const KinematicChain& chain) { return static_cast<int>(chain.lanes.theta.size()); }
}  // namespace

Data::Data(const KinematicChain& chain)
    : dof(static_cast<int>(chain.links.size())),
      T_base_joint(chain.links.size()),
      J_spatial(6, dof),
      q_padded(VecX::Zero(paddedDof(chain))),
      angle(VecX::Zero(paddedDof(chain))),
      sin_angle(VecX::Zero(paddedDof(chain))),
      cos_angle(VecX::Zero(paddedDof(chain))),
      slide(VecX::Zero(paddedDof(chain))) {
  J_spatial.setZero();
}
Data::Data(const PoeModel& model) : Data(model.chain()) {}
Data::Data(const DhModel& model) : Data(model.chain()) {}

void checkJointVector(const Eigen::Ref<const VecX>& q, int dof) {
  LP_CHECK(q.size() == dof, "expected " << dof << " joint values, got " << q.size());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    LP_CHECK(std::isfinite(q[i]), "joint value " << i + 1 << " is not finite");
  }
}

void jointExp(const Joint& joint, double q, Pose& out) {
  const double x = joint.motion(q);
  if (joint.type == JointType::Prismatic) {
    out.R.setIdentity();
    out.p.noalias() = x * joint.twist.tail<3>();
  } else {
    expUnitTwist(joint.twist.head<3>(), joint.twist.tail<3>(), joint.pitch, x, out);
  }
}

namespace {

using detail::counted;

// Whether an angle is beyond the sine kernel's accurate range (possible only for huge joint values): libm then.
inline bool outOfRange(double angle) { return !(std::abs(angle) <= detail::kSinCosMaxArgument); }

// The motion rule on a link's constants (JointMotion's (j, k)): joint motion x turns the link by
// theta + j x and slides it by p_z + k x; T is a double or a vector of lanes.
template <class T>
LP_ALWAYS_INLINE inline T linkAngle(double theta, double turn, T x) { return theta + turn * x; }
template <class T>
LP_ALWAYS_INLINE inline T linkSlide(double z, double slide, T x) { return z + slide * x; }

// T <- T Rz(angle) Trans(p_x, p_y, slide) Rx(alpha) on the rotation columns X, Y, Z and the position P, given
// cos/sin of the angle: T is one row (a double), the three rows of one configuration (a vector: the single form)
// or one row of a block of configurations (a vector of lanes: the batch).
// (S: the type of c, s and slide: T, or a double broadcast to T's lanes by the arithmetic.)
template <class T, class S>
LP_ALWAYS_INLINE inline void linkStep(const ChainLink& link, S c, S s, S slide, T& X, T& Y, T& Z, T& P) {
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

using detail::Vec4d;
using detail::Vec4u;
using detail::Vec8d;
using detail::Vec8u;

template <class V>
constexpr int lanesOf() { return static_cast<int>(sizeof(V) / sizeof(double)); }

// v in every lane (a loop the compiler turns into one broadcast; `V{} + v` would add 0.0, which it must keep)
template <class V>
LP_ALWAYS_INLINE inline V broadcast(double v) {
  V out;
  for (int l = 0; l < lanesOf<V>(); ++l) out[l] = v;
  return out;
}

// Joint i's motion terms for the lanes b .. b + 3 of the padded arrays (padding lanes: q = 0): the angle's sine
// and cosine and the slide into data's scratch; `bad` gains the lanes whose angle is beyond the sine kernel's
// range (all bits set), tested once for all joints.
LP_ALWAYS_INLINE inline void laneAngles(const detail::ChainLanes& c, Data& data, const double* q, int n, int b,
                                        Vec4u& bad) {
  Vec4d qv;
  if (b + 4 <= n) {
    std::memcpy(&qv, q + b, sizeof qv);
  } else {
    for (int l = 0; l < 4; ++l) qv[l] = b + l < n ? q[b + l] : 0.0;
  }
  auto lanes = [b](const std::vector<double>& v) {
    Vec4d out;
    std::memcpy(&out, v.data() + b, sizeof out);
    return out;
  };
  const Vec4d x = lanes(c.scale) * (qv + lanes(c.offset));   // motionOf
  const Vec4d angle = lanes(c.theta) + lanes(c.turn) * x;    // linkAngle
  const Vec4d slide = lanes(c.z) + lanes(c.slide) * x;       // linkSlide
  Vec4d st, ct;
  detail::sinCos4(angle, st, ct);
  std::memcpy(data.angle.data() + b, &angle, sizeof angle);
  std::memcpy(data.sin_angle.data() + b, &st, sizeof st);
  std::memcpy(data.cos_angle.data() + b, &ct, sizeof ct);
  std::memcpy(data.slide.data() + b, &slide, sizeof slide);
  const Vec4d magnitude = detail::fromBits(detail::bitsOf(angle) & 0x7fffffffffffffffULL);
  bad |= (Vec4u)~(magnitude <= detail::kSinCosMaxArgument);  // NaN too
}

// A column of a rotation (or the position) as lanes 0..2 of a vector: rows 0, 1, 2 (lane 3 zero).
LP_ALWAYS_INLINE inline Vec4d column(const double* v) { return Vec4d{v[0], v[1], v[2], 0.0}; }
LP_ALWAYS_INLINE inline void storeColumn(double* dst, Vec4d v) {
  dst[0] = v[0];
  dst[1] = v[1];
  dst[2] = v[2];
}

// What the single chain evaluation writes besides data.T_base_tool: nothing (forwardKinematics), the joint frames
// (forwardKinematicsWithFrames), or the frames and the spatial Jacobian (computeJacobians).
enum class Fill { Tool, Frames, Jacobian };

// Joint i's spatial Jacobian column `scale_i [j_i z_i; j_i o_i x z_i + k_i z_i]` (jacobian.hpp) from its line:
// z axis Z and origin P as vectors of their three rows (the batch's JacobianBlock writes the same per lane).
LP_ALWAYS_INLINE inline void spatialColumn(const ChainLink& link, Vec4d Z, Vec4d P, double* column) {
  const double j = link.motion.scale * link.turn, k = link.motion.scale * link.slide;
  // o x z by the rows (y, z, x) and (z, x, y) of each vector (__builtin_shufflevector: GCC 12 and clang)
  const Vec4d o_cross_z = __builtin_shufflevector(P, P, 1, 2, 0, 3) * __builtin_shufflevector(Z, Z, 2, 0, 1, 3) -
                          __builtin_shufflevector(P, P, 2, 0, 1, 3) * __builtin_shufflevector(Z, Z, 1, 2, 0, 3);
  storeColumn(column, j * Z);
  storeColumn(column + 3, j * o_cross_z + k * Z);
}

// The chain product of model.hpp's KinematicChain. Columns X, Y, Z of the rotation and the position P, each
// a vector of its three rows, are updated by T <- T Rz(angle) Trans(p + slide e_z) Rx(alpha) (linkStep, the
// coefficients broadcast to the rows); Fill::Frames stores the frame before each link (joint i's line) in
// data.T_base_joint, Fill::Jacobian also joint i's column of data.J_spatial. The sines and cosines of all joints
// come first, a vector of four joints at a time.
template <Fill kFill>
LP_ALWAYS_INLINE inline void evaluate(const KinematicChain& chain, Data& data, const double* q) {
  const int n = data.dof;
  const int padded = paddedDof(chain);  // a multiple of kChainLanes (4): whole vectors
  Vec4u bad{};
  for (int b = 0; b < padded; b += detail::kChainLanes) laneAngles(chain.lanes, data, q, n, b, bad);
  if (LP_UNLIKELY((bad[0] | bad[1] | bad[2] | bad[3]) != 0)) {
    for (int i = 0; i < padded; ++i) {
      data.sin_angle[i] = std::sin(data.angle[i]);
      data.cos_angle[i] = std::cos(data.angle[i]);
    }
  }
  const double* __restrict st = data.sin_angle.data();
  const double* __restrict ct = data.cos_angle.data();
  const double* __restrict slide = data.slide.data();
  const Pose& B = chain.T_base_first;
  Vec4d X = column(B.R.col(0).data()), Y = column(B.R.col(1).data()), Z = column(B.R.col(2).data());
  Vec4d P = column(B.p.data());
  for (int i = 0; i < n; ++i) {
    const ChainLink& link = chain.links[static_cast<size_t>(i)];
    if (kFill != Fill::Tool) {
      Pose& F = data.T_base_joint[static_cast<size_t>(i)];
      storeColumn(F.R.col(0).data(), X);
      storeColumn(F.R.col(1).data(), Y);
      storeColumn(F.R.col(2).data(), Z);
      storeColumn(F.p.data(), P);
    }
    if (kFill == Fill::Jacobian) spatialColumn(link, Z, P, data.J_spatial.col(i).data());
    linkStep(link, ct[i], st[i], slide[i], X, Y, Z, P);
  }
  const Pose& E = chain.T_last_tool;
  Pose& T = data.T_base_tool;
  for (int m = 0; m < 3; ++m) storeColumn(T.R.col(m).data(), toolRotation(E, m, X, Y, Z));
  storeColumn(T.p.data(), toolPosition(E, X, Y, Z, P));
}

// The lanes of one block in a column of an SoA matrix (a configuration per row): rows first .. first + lanes.
// kFull: all lanes are configurations (a whole vector moves); otherwise the last, partial block (unused lanes
// hold q = 0 and are never written).
template <bool kFull, class V>
struct BlockLanes {
  Eigen::Index first;
  int partial_lanes;
  size_t bytes() const { return sizeof(double) * static_cast<size_t>(kFull ? lanesOf<V>() : partial_lanes); }
  LP_ALWAYS_INLINE V load(const double* column) const {
    V v = broadcast<V>(0.0);
    std::memcpy(&v, column + first, bytes());
    return v;
  }
  LP_ALWAYS_INLINE void store(double* column, V v) const { std::memcpy(column + first, &v, bytes()); }
};

// The tool pose of a block: rotation rows R[k][m] and position p[k], lanes = configurations.
template <class V>
struct BlockPose {
  V R[3][3], p[3];
};

// Writes a block's tool poses into the count x 12 `poses` (rotation row-major, then position).
template <bool kFull, class V>
LP_ALWAYS_INLINE inline void storePoses(const BlockLanes<kFull, V>& io, const BlockPose<V>& T, Eigen::Ref<MatX>& poses) {
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) io.store(poses.col(3 * k + m).data(), T.R[k][m]);
    io.store(poses.col(9 + k).data(), T.p[k]);
  }
}

// One batch block: the chain product for the configurations of one GNU vector V (4 lanes: AVX2 / SSE2 pairs;
// 8 lanes: AVX-512), so the whole state of a block (rotation columns X, Y, Z and position P, three rows each)
// stays in registers. U is the matching unsigned vector (the sine kernel's bit operations). `joint(i, Z, P)`
// sees joint i's line (z axis Z, origin P: rows of the frame before link i); `tool(T)` the block's tool pose.
// Link i's motion terms for a block: the sine and cosine of its angle and its slide, lane by lane.
template <bool kFull, class V, class U>
LP_ALWAYS_INLINE inline void blockTrig(const ChainLink& link, const double* q_column, const BlockLanes<kFull, V>& io,
                                       bool use_libm, V& st, V& ct, V& slide) {
  const V x = motionOf(io.load(q_column), link.motion.scale, link.motion.offset);
  const V angle = linkAngle(link.theta, link.turn, x);
  slide = linkSlide(link.p[2], link.slide, x);
  detail::sinCosT<V, U>(angle, st, ct);
  if (use_libm) {
    for (int l = 0; l < lanesOf<V>(); ++l) {
      st[l] = std::sin(angle[l]);
      ct[l] = std::cos(angle[l]);
    }
  }
}

// Chains of up to this many links get their sines, cosines and slides for the whole block first (on the stack:
// 1.5 KB with 4 lanes), then the product: the sine kernel's temporaries and the product's 12 state vectors are
// then never live together, which with 16 AVX2 registers spilled a third of the block's instructions to the
// stack. Longer chains interleave the two per link.
constexpr size_t kStagedLinks = 16;

template <bool kFull, class V, class U, class Joint, class Tool>
LP_ALWAYS_INLINE inline void evaluateBlock(const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                                           const BlockLanes<kFull, V>& io, bool use_libm, Joint& joint, Tool& tool) {
  V X[3], Y[3], Z[3], P[3];
  const Pose& Bs = chain.T_base_first;
  for (int k = 0; k < 3; ++k) {
    X[k] = broadcast<V>(Bs.R(k, 0));
    Y[k] = broadcast<V>(Bs.R(k, 1));
    Z[k] = broadcast<V>(Bs.R(k, 2));
    P[k] = broadcast<V>(Bs.p[k]);
  }
  const size_t n = chain.links.size();
  auto column = [&q](size_t i) { return q.col(static_cast<Eigen::Index>(i)).data(); };
  if (n <= kStagedLinks) {
    V st[kStagedLinks], ct[kStagedLinks], slide[kStagedLinks];
    for (size_t i = 0; i < n; ++i) blockTrig<kFull, V, U>(chain.links[i], column(i), io, use_libm, st[i], ct[i], slide[i]);
    for (size_t i = 0; i < n; ++i) {
      joint(i, Z, P);
      for (int k = 0; k < 3; ++k) linkStep(chain.links[i], ct[i], st[i], slide[i], X[k], Y[k], Z[k], P[k]);
    }
  } else {
    for (size_t i = 0; i < n; ++i) {
      V st, ct, slide;
      blockTrig<kFull, V, U>(chain.links[i], column(i), io, use_libm, st, ct, slide);
      joint(i, Z, P);
      for (int k = 0; k < 3; ++k) linkStep(chain.links[i], ct, st, slide, X[k], Y[k], Z[k], P[k]);
    }
  }
  // T * T_last_tool
  const Pose& E = chain.T_last_tool;
  BlockPose<V> T;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) T.R[k][m] = toolRotation(E, m, X[k], Y[k], Z[k]);
    T.p[k] = toolPosition(E, X[k], Y[k], Z[k], P[k]);
  }
  tool(T);
}

// The batched FK's hooks: no joint output, the tool pose written to `poses`.
template <bool kFull, class V>
struct FkBlock {
  const BlockLanes<kFull, V>& io;
  Eigen::Ref<MatX>& poses;
  LP_ALWAYS_INLINE void operator()(size_t, const V*, const V*) {}
  LP_ALWAYS_INLINE void operator()(const BlockPose<V>& T) { storePoses(io, T, poses); }
};

// The batched Jacobians' hooks: joint i's spatial column `scale_i [j_i z_i; j_i o_i x z_i + k_i z_i]` (the
// arithmetic of the single form's spatialColumn, per lane) into columns i, dof + i, .. 5 dof + i of `jacobians`;
// at the tool, the poses, and the columns turned into the requested frame: `u = v + w x p_tool` gives the geometric column `[u; w]`
// and the body column `[R^T w; R^T u]` (`Ad(T^-1) [w; v]`, jacobian.hpp).
template <bool kFull, class V>
struct JacobianBlock {
  const BlockLanes<kFull, V>& io;
  const KinematicChain& chain;
  JacobianFrame frame;
  Eigen::Ref<MatX>& jacobians;
  Eigen::Ref<MatX>& poses;
  // entry (r, i) of a configuration's Jacobian is column r dof + i: Jacobian row r starts this far after row 0
  Eigen::Index rowStep() const { return (jacobians.cols() / 6) * jacobians.outerStride(); }
  LP_ALWAYS_INLINE void operator()(size_t i, const V* z, const V* o) {
    const ChainLink& link = chain.links[i];
    const double j = link.motion.scale * link.turn, k = link.motion.scale * link.slide;
    const Eigen::Index step = rowStep();
    double* c = jacobians.data() + static_cast<Eigen::Index>(i) * jacobians.outerStride();
    io.store(c, j * z[0]);
    io.store(c + step, j * z[1]);
    io.store(c + 2 * step, j * z[2]);
    io.store(c + 3 * step, j * (o[1] * z[2] - o[2] * z[1]) + k * z[0]);
    io.store(c + 4 * step, j * (o[2] * z[0] - o[0] * z[2]) + k * z[1]);
    io.store(c + 5 * step, j * (o[0] * z[1] - o[1] * z[0]) + k * z[2]);
  }
  LP_ALWAYS_INLINE void operator()(const BlockPose<V>& T) {
    storePoses(io, T, poses);
    if (frame == JacobianFrame::Spatial) return;
    const Eigen::Index step = rowStep();
    for (Eigen::Index i = 0; i < jacobians.cols() / 6; ++i) {
      double* c = jacobians.data() + i * jacobians.outerStride();
      V w[3], u[3];
      for (int r = 0; r < 3; ++r) w[r] = io.load(c + r * step);
      u[0] = io.load(c + 3 * step) + (w[1] * T.p[2] - w[2] * T.p[1]);
      u[1] = io.load(c + 4 * step) + (w[2] * T.p[0] - w[0] * T.p[2]);
      u[2] = io.load(c + 5 * step) + (w[0] * T.p[1] - w[1] * T.p[0]);
      for (int r = 0; r < 3; ++r) {
        if (frame == JacobianFrame::Geometric) {
          io.store(c + r * step, u[r]);
          io.store(c + (3 + r) * step, w[r]);
        } else {
          io.store(c + r * step, (T.R[0][r] * w[0] + T.R[1][r] * w[1]) + T.R[2][r] * w[2]);
          io.store(c + (3 + r) * step, (T.R[0][r] * u[0] + T.R[1][r] * u[1]) + T.R[2][r] * u[2]);
        }
      }
    }
  }
};

void checkBatchSizes(const char* function, const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                     const Eigen::Ref<MatX>& poses) {
  LP_CHECK(q.cols() == static_cast<Eigen::Index>(chain.links.size()),
           function << ": q has " << counted(q.cols(), "column") << ", the model has "
                    << counted(static_cast<Eigen::Index>(chain.links.size()), "joint"));
  LP_CHECK(poses.rows() == q.rows() && poses.cols() == 12,
           function << ": poses is " << poses.rows() << " x " << poses.cols() << ", expected " << q.rows()
                    << " x 12 (a row per configuration of q)");
}

void checkJacobianBatchSizes(const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                             const Eigen::Ref<MatX>& jacobians, const Eigen::Ref<MatX>& poses) {
  checkBatchSizes("computeJacobiansBatch", chain, q, poses);
  const Eigen::Index columns = 6 * q.cols();
  LP_CHECK(jacobians.rows() == q.rows() && jacobians.cols() == columns,
           "computeJacobiansBatch: jacobians is " << jacobians.rows() << " x " << jacobians.cols() << ", expected "
                                                  << q.rows() << " x " << columns
                                                  << " (a row per configuration of q, 6 columns per joint)");
}

// Whether an angle of the batch is beyond the sine kernel's range (then libm is used for the whole call): one
// pass over the input, no per-lane test inside the blocks.
bool batchNeedsLibm(const KinematicChain& chain, const Eigen::Ref<const MatX>& q) {
  int out_of_range = 0;
  for (size_t i = 0; i < chain.links.size(); ++i) {
    const ChainLink& link = chain.links[i];
    const double* qi = q.col(static_cast<Eigen::Index>(i)).data();
    for (Eigen::Index k = 0; k < q.rows(); ++k) {
      out_of_range |= outOfRange(linkAngle(link.theta, link.turn, motionOf(qi[k], link.motion.scale, link.motion.offset)));
    }
  }
  return out_of_range != 0;
}

// The blocks of a batch: full vectors, then the partial one. Hooks<kFull, V> is FkBlock or JacobianBlock, made
// from the block's lanes and `args`.
template <class V, class U, template <bool, class> class Hooks, class... Args>
LP_ALWAYS_INLINE inline void evaluateBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q,
                                           Args&... args) {
  constexpr int N = lanesOf<V>();
  const bool use_libm = batchNeedsLibm(chain, q);
  Eigen::Index first = 0;
  for (; first + N <= q.rows(); first += N) {
    const BlockLanes<true, V> io{first, N};
    Hooks<true, V> hooks{io, args...};
    evaluateBlock<true, V, U>(chain, q, io, use_libm, hooks, hooks);
  }
  if (first < q.rows()) {
    const BlockLanes<false, V> io{first, static_cast<int>(q.rows() - first)};
    Hooks<false, V> hooks{io, args...};
    evaluateBlock<false, V, U>(chain, q, io, use_libm, hooks, hooks);
  }
}

}  // namespace

namespace detail {

// The entry points into the chain evaluation, compiled twice on x86-64 with GCC: for the baseline
// and for x86-64-v3 (AVX2 + FMA), chosen once at load time (target_clones), so users of the default
// build get the vectorized kernel without -march flags.
LP_DISPATCH void chainTool(const KinematicChain& chain, Data& data, const double* q) { evaluate<Fill::Tool>(chain, data, q); }
LP_DISPATCH void chainFrames(const KinematicChain& chain, Data& data, const double* q) {
  evaluate<Fill::Frames>(chain, data, q);
}
LP_DISPATCH void chainJacobian(const KinematicChain& chain, Data& data, const double* q) {
  evaluate<Fill::Jacobian>(chain, data, q);
}
LP_DISPATCH void chainBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  evaluateBatch<Vec4d, Vec4u, FkBlock>(chain, q, poses);
}
LP_DISPATCH void chainJacobianBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                                    Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses) {
  evaluateBatch<Vec4d, Vec4u, JacobianBlock>(chain, q, chain, frame, jacobians, poses);
}

#if defined(LP_HAVE_AVX512_BATCH)
// Eight lanes per block with AVX-512 (32 registers hold a block's state): chosen at run time when the
// processor has it (valgrind's emulated CPU does not, so instruction counts measure the AVX2 path).
__attribute__((target("arch=x86-64-v4"))) void chainBatch8(const KinematicChain& chain,
                                                           const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  evaluateBatch<Vec8d, Vec8u, FkBlock>(chain, q, poses);
}
__attribute__((target("arch=x86-64-v4"))) void chainJacobianBatch8(const KinematicChain& chain,
                                                                   const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                                                                   Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses) {
  evaluateBatch<Vec8d, Vec8u, JacobianBlock>(chain, q, chain, frame, jacobians, poses);
}
bool hasAvx512() {
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
                          __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw");
  return has;
}
#endif

void batch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  checkBatchSizes("forwardKinematicsBatch", chain, q, poses);
#if defined(LP_HAVE_AVX512_BATCH)
  if (hasAvx512()) {
    chainBatch8(chain, q, poses);
    return;
  }
#endif
  chainBatch(chain, q, poses);
}

void jacobianBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                   Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses) {
  checkJacobianBatchSizes(chain, q, jacobians, poses);
#if defined(LP_HAVE_AVX512_BATCH)
  if (hasAvx512()) {
    chainJacobianBatch8(chain, q, frame, jacobians, poses);
    return;
  }
#endif
  chainJacobianBatch(chain, q, frame, jacobians, poses);
}

}  // namespace detail

void detail::throwChainMismatch(const char* function, const KinematicChain& chain, const Data& data,
                                Eigen::Index q_size) {
  const auto dof = static_cast<Eigen::Index>(chain.links.size());
  std::string what = std::string(function) + ": ";
  if (q_size != dof) {
    what += "q has " + counted(q_size, "value") + ", the model has " + counted(dof, "joint");
  } else {
    what += "data was made for a model with " + counted(data.dof, "joint") + ", this model has " + std::to_string(dof);
  }
  throw std::invalid_argument(what);
}

void forwardKinematics(const PoeModel& model, Data& data, const Eigen::Ref<const VecX>& q) {
  detail::checkChainCall("forwardKinematics", model.chain(), data, q.size());
  detail::chainTool(model.chain(), data, q.data());
}

void forwardKinematics(const DhModel& model, Data& data, const Eigen::Ref<const VecX>& q) {
  detail::checkChainCall("forwardKinematics", model.chain(), data, q.size());
  detail::chainTool(model.chain(), data, q.data());
}

void forwardKinematicsWithFrames(const KinematicChain& chain, Data& data, const Eigen::Ref<const VecX>& q) {
  detail::checkChainCall("forwardKinematicsWithFrames", chain, data, q.size());
  detail::chainFrames(chain, data, q.data());
}

void forwardKinematicsBatch(const PoeModel& model, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  detail::batch(model.chain(), q, poses);
}

void forwardKinematicsBatch(const DhModel& model, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  detail::batch(model.chain(), q, poses);
}

Pose poeForwardKinematics(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  Data data(model);
  detail::checkChainCall("poeForwardKinematics", model.chain(), data, q.size());
  detail::chainTool(model.chain(), data, q.data());
  return data.T_base_tool;
}

Pose dhForwardKinematics(const DhModel& model, const Eigen::Ref<const VecX>& q) {
  Data data(model);
  detail::checkChainCall("dhForwardKinematics", model.chain(), data, q.size());
  detail::chainTool(model.chain(), data, q.data());
  return data.T_base_tool;
}

}  // namespace lowpair
