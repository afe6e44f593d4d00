// The batched FK of Robot.fk(Q), chunk by chunk (fk_batch.hpp).
#include "fk_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "lowpair/tolerances.hpp"
#include "common.hpp"

namespace lowpair::python {

namespace {

// Batched FK, chunk by chunk: 256 configurations (a multiple of every SIMD block, 4 or 8, so the blocks are
// those of one whole call) keep the chunk's joint values and poses (36 KB for six joints) in the L1 cache.
constexpr Eigen::Index kFkChunk = 256;
// The Jacobians' chunk: 64 configurations (a multiple of 8) keep a chunk's 6 n Jacobian columns (18 KB for six
// joints) in the L1 cache while they are written and copied out (measured: 128 was slower).
constexpr Eigen::Index kJacobianChunk = 64;
// The chunk's Jacobian columns lie this many rows apart beyond the chunk: at a power-of-two stride (64 rows, 512
// bytes) the 6 n columns fall on an eighth of the L1 cache's sets and evict each other (measured: the copy out
// then cost as much as the Jacobians); 4 more rows (544 bytes) spread them over all sets.
constexpr Eigen::Index kJacobianColumnPad = 4;
// Results of at least this many bytes are written with non-temporal stores when their pages are resident: they
// bypass the caches the result would not fit in anyway, and skip reading each line before writing it (12.8 MB for
// N = 100,000). Smaller results stay in the cache for the caller's next read. Into pages not yet faulted in
// (memory new to the process) non-temporal stores cost more than plain ones (docs/python.md, "Speed").
constexpr size_t kStreamBytes = size_t{1} << 20;

// Whether every page of [p, p + bytes) is resident (mincore; one system call, ~3,000 pages for 12.8 MB).
bool resident(const void* p, size_t bytes) {
#if defined(__linux__)
  const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const uintptr_t begin = reinterpret_cast<uintptr_t>(p) & ~(page - 1), end = reinterpret_cast<uintptr_t>(p) + bytes;
  std::vector<unsigned char> pages((end - begin + page - 1) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, pages.data()) != 0) return false;
  return std::all_of(pages.begin(), pages.end(), [](unsigned char c) { return (c & 1) != 0; });
#else
  (void)p, (void)bytes;
  return true;
#endif
}

// Whether a result of `bytes` at `out` is written with non-temporal stores (kStreamBytes).
bool streamable(const double* out, size_t bytes) {
#if defined(__SSE2__)
  return bytes >= kStreamBytes && reinterpret_cast<uintptr_t>(out) % 16 == 0 && resident(out, bytes);
#else
  (void)out, (void)bytes;
  return false;
#endif
}

// The chunk's rows of the row-major (len x dof) q, transposed into the column-major Q the library takes: two
// rows at a time, each 2 x 2 block (row pair, joint pair) transposed in registers (SSE2), the check of the
// joint limits folded in: false when a value is not within its joint's `bound` (|q_i| <= bound[i]; NaN fails).
bool transposeChunk(const double* q, Eigen::Index len, Eigen::Index dof, const double* bound, MatX& Q) {
  double* dst = Q.data();
  const Eigen::Index ld = Q.rows();
  bool finite = true;
  Eigen::Index k = 0;
#if defined(__SSE2__)
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff));
  __m128d bad = _mm_setzero_pd();  // lanes of NaN or beyond the bound: not (|x| <= bound)
  for (; k + 2 <= len; k += 2) {
    const double* a = q + k * dof;  // rows k and k + 1
    const double* b = a + dof;
    Eigen::Index i = 0;
    for (; i + 2 <= dof; i += 2) {
      const __m128d ra = _mm_loadu_pd(a + i), rb = _mm_loadu_pd(b + i), largest = _mm_loadu_pd(bound + i);
      bad = _mm_or_pd(bad, _mm_or_pd(_mm_cmpnle_pd(_mm_and_pd(ra, magnitude), largest),
                                     _mm_cmpnle_pd(_mm_and_pd(rb, magnitude), largest)));
      _mm_storeu_pd(dst + i * ld + k, _mm_unpacklo_pd(ra, rb));
      _mm_storeu_pd(dst + (i + 1) * ld + k, _mm_unpackhi_pd(ra, rb));
    }
    for (; i < dof; ++i) {
      dst[i * ld + k] = a[i], dst[i * ld + k + 1] = b[i];
      finite &= std::abs(a[i]) <= bound[i] && std::abs(b[i]) <= bound[i];
    }
  }
  finite &= _mm_movemask_pd(bad) == 0;
#endif
  for (; k < len; ++k) {
    for (Eigen::Index i = 0; i < dof; ++i) {
      const double x = q[k * dof + i];
      dst[i * ld + k] = x;
      finite &= std::abs(x) <= bound[i];
    }
  }
  return finite;
}

// The library's (len x 12) column-major poses (rotation row-major in columns 0..8, position in 9..11) as len
// row-major 4 x 4 matrices at `out`: two configurations at a time, each 2 x 2 block of (column pair, pose
// pair) transposed in registers (SSE2, the x86-64 baseline); `stream`: non-temporal stores (out 16-aligned).
void repackChunk(const MatX& poses, Eigen::Index len, double* out, bool stream) {
  const double* c = poses.data();
  const Eigen::Index ld = poses.rows();
  Eigen::Index k = 0;
#if defined(__SSE2__)
  const __m128d zero_zero = _mm_setzero_pd(), zero_one = _mm_set_pd(1.0, 0.0);
  auto store = [stream](double* dst, __m128d v) { stream ? _mm_stream_pd(dst, v) : _mm_storeu_pd(dst, v); };
  for (; k + 2 <= len; k += 2, out += 32) {
    for (int a = 0; a < 3; ++a) {
      const __m128d r0 = _mm_loadu_pd(c + (3 * a + 0) * ld + k), r1 = _mm_loadu_pd(c + (3 * a + 1) * ld + k);
      const __m128d r2 = _mm_loadu_pd(c + (3 * a + 2) * ld + k), p = _mm_loadu_pd(c + (9 + a) * ld + k);
      store(out + 4 * a, _mm_unpacklo_pd(r0, r1));
      store(out + 4 * a + 2, _mm_unpacklo_pd(r2, p));
      store(out + 16 + 4 * a, _mm_unpackhi_pd(r0, r1));
      store(out + 16 + 4 * a + 2, _mm_unpackhi_pd(r2, p));
    }
    store(out + 12, zero_zero), store(out + 14, zero_one), store(out + 28, zero_zero), store(out + 30, zero_one);
  }
#endif
  for (; k < len; ++k, out += 16) {
    for (int a = 0; a < 3; ++a) {
      out[4 * a + 0] = c[(3 * a + 0) * ld + k], out[4 * a + 1] = c[(3 * a + 1) * ld + k];
      out[4 * a + 2] = c[(3 * a + 2) * ld + k], out[4 * a + 3] = c[(9 + a) * ld + k];
    }
    out[12] = 0.0, out[13] = 0.0, out[14] = 0.0, out[15] = 1.0;
  }
}

// The library's (len x 6 dof) Jacobians, one row per configuration in numpy's (6, dof) order, column-major, as len
// row-major rows at `out`: two configurations and two columns at a time (6 dof is even), each 2 x 2 block
// transposed in registers (SSE2) as repackChunk does, the two rows written in order.
void repackJacobians(const MatX& J, Eigen::Index len, double* out) {
  const Eigen::Index ld = J.outerStride(), width = J.cols();
  const double* c = J.data();
  Eigen::Index k = 0;
#if defined(__SSE2__)
  for (; k + 2 <= len; k += 2, out += 2 * width) {
    for (Eigen::Index m = 0; m < width; m += 2) {
      const __m128d x = _mm_loadu_pd(c + m * ld + k), y = _mm_loadu_pd(c + (m + 1) * ld + k);
      _mm_storeu_pd(out + m, _mm_unpacklo_pd(x, y));
      _mm_storeu_pd(out + width + m, _mm_unpackhi_pd(x, y));
    }
  }
#endif
  for (; k < len; ++k, out += width) {
    for (Eigen::Index m = 0; m < width; ++m) out[m] = c[m * ld + k];
  }
}

// Each chunk of `count` rows of q (row-major, dof values each) transposed into Q (limits checked on the way, as fk
// checks them), then `evaluate(Q.topRows(len), start, len)`.
template <class Evaluate>
void forEachChunk(const Robot& r, const double* q, Eigen::Index count, Eigen::Index chunk, Evaluate evaluate) {
  const Eigen::Index dof = r.dof();
  MatX Q(std::min(count, chunk), dof);
  const std::vector<double> bound = jointMagnitudeBounds(r.poe);
  for (Eigen::Index start = 0; start < count; start += chunk) {
    const Eigen::Index len = std::min(chunk, count - start);
    if (!transposeChunk(q + start * dof, len, dof, bound.data(), Q)) {
      requireWithinLimits(r.poe, q + start * dof, len, r.subject(), "q", true, start);  // throws, naming the value
    }
    evaluate(Q.topRows(len), start, len);
  }
}

}  // namespace

void jacobianBatchInto(const Robot& r, JacobianFrame frame, const double* q, Eigen::Index count, double* out) {
  const Eigen::Index dof = r.dof(), rows = std::min(count, kJacobianChunk);
  MatX J(rows + kJacobianColumnPad, 6 * dof), poses(rows, 12);
  forEachChunk(r, q, count, kJacobianChunk, [&](const Eigen::Ref<const MatX>& Q, Eigen::Index start, Eigen::Index len) {
    computeJacobiansBatch(r.poe, Q, frame, J.topRows(len), poses.topRows(len));
    repackJacobians(J, len, out + start * 6 * dof);
  });
}

void singularBatchInto(const Robot& r, const double* q, Eigen::Index count, long long* rank, double* tolerance,
                       double* sigma) {
  const Eigen::Index dof = r.dof(), rows = std::min(count, kJacobianChunk), m = std::min<Eigen::Index>(6, dof);
  MatX J(rows + kJacobianColumnPad, 6 * dof), poses(rows, 12);
  Mat6X Jk(6, dof);
  forEachChunk(r, q, count, kJacobianChunk, [&](const Eigen::Ref<const MatX>& Q, Eigen::Index start, Eigen::Index len) {
    computeJacobiansBatch(r.poe, Q, JacobianFrame::Geometric, J.topRows(len), poses.topRows(len));
    for (Eigen::Index k = 0; k < len; ++k) {
      for (Eigen::Index i = 0; i < dof; ++i) {
        for (int row = 0; row < 6; ++row) Jk(row, i) = J(k, row * dof + i);
      }
      const JacobianRank rule = jacobianRank(r.poe, Jk);
      rank[start + k] = rule.rank;
      tolerance[start + k] = rule.tolerance;
      for (Eigen::Index j = 0; j < m; ++j) sigma[(start + k) * m + j] = rule.singular_values(j);
    }
  });
}

std::vector<double> jointMagnitudeBounds(const PoeModel& model) {
  std::vector<double> bound(static_cast<size_t>(model.dof()));
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double b = kMaxMagnitude / std::max(1.0, std::abs(j.slideRate())) / j.scale - std::abs(j.offset);
    bound[static_cast<size_t>(i)] = std::max(0.0, b * (1.0 - 1e-15));
  }
  return bound;
}

bool withinBounds(const double* q, Eigen::Index count, Eigen::Index dof, const std::vector<double>& bound) {
  // the bounds repeated over 8 rows: one contiguous, branch-free pass the compiler vectorizes
  constexpr Eigen::Index kRows = 8;
  const auto tile_size = static_cast<size_t>(kRows * dof);
  std::vector<double> tile(tile_size);
  for (size_t t = 0; t < tile_size; ++t) tile[t] = bound[t % static_cast<size_t>(dof)];
  bool ok = true;
  Eigen::Index k = 0;
  for (; k + kRows <= count; k += kRows, q += kRows * dof) {
    bool tile_ok = true;
    for (size_t t = 0; t < tile_size; ++t) tile_ok &= std::abs(q[t]) <= tile[t];
    ok &= tile_ok;
  }
  for (; k < count; ++k, q += dof) {
    for (Eigen::Index i = 0; i < dof; ++i) ok &= std::abs(q[i]) <= bound[static_cast<size_t>(i)];
  }
  return ok;
}

void fkBatchInto(const Robot& r, bool poe, const double* q, Eigen::Index count, double* out) {
  MatX poses(std::min(count, kFkChunk), 12);
  const bool stream = streamable(out, static_cast<size_t>(count) * 16 * sizeof(double));
  forEachChunk(r, q, count, kFkChunk, [&](const Eigen::Ref<const MatX>& Q, Eigen::Index start, Eigen::Index len) {
    if (poe) {
      forwardKinematicsBatch(r.poe, Q, poses.topRows(len));
    } else {
      forwardKinematicsBatch(r.dhModel(), Q, poses.topRows(len));
    }
    repackChunk(poses, len, out + 16 * start, stream);
  });
#if defined(__SSE2__)
  if (stream) _mm_sfence();  // the non-temporal stores are visible before the GIL is taken back
#endif
}

}  // namespace lowpair::python
