// The batched FK of Robot.fk(Q) (docs/python.md, "Speed"): the hot path alone in fk_batch.cpp, as MuJoCo keeps
// its batched rollout in rollout.cc.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lowpair/jacobian.hpp"
#include "robot.hpp"

namespace lowpair::python {

// Whether the byte ranges [a, a + a_bytes) and [b, b + b_bytes) share a byte (the extents test of numpy's
// may_share_memory: strides do not matter here, both arrays are C-contiguous).
inline bool sharesBytes(const void* a, size_t a_bytes, const void* b, size_t b_bytes) {
  const auto x = reinterpret_cast<uintptr_t>(a), y = reinterpret_cast<uintptr_t>(b);
  return a_bytes > 0 && b_bytes > 0 && x < y + b_bytes && y < x + a_bytes;
}

// Batched FK of `count` configurations (row-major count x dof `q`) into `out` (count x 4 x 4, row-major): per
// chunk, transposeChunk (with the finiteness check), forwardKinematicsBatch, repackChunk. Called without the GIL
// (the caller keeps `q` and `out` alive).
// Per joint, a bound on |q_i| within which joint i is within its limits (jointValueWithinLimits: |scale (q +
// offset)| and the slide at most kMaxMagnitude), a little conservative: a value beyond it is checked exactly.
std::vector<double> jointMagnitudeBounds(const PoeModel& model);

// Whether every value of the `count` rows of `dof` values at q is within its joint's bound (NaN is not).
bool withinBounds(const double* q, Eigen::Index count, Eigen::Index dof, const std::vector<double>& bound);

void fkBatchInto(const Robot& r, bool poe, const double* q, Eigen::Index count, double* out);

// Batched Jacobians of the POE model (Robot.jacobian(Q)): `count` configurations (row-major count x dof `q`) into
// `out` (count x 6 x dof, row-major), chunk by chunk as fkBatchInto (computeJacobiansBatch). Called without the GIL.
void jacobianBatchInto(const Robot& r, JacobianFrame frame, const double* q, Eigen::Index count, double* out);

// The rank rule of Robot.singular(q) (jacobianRank) at each of `count` configurations: per row the rank, the
// tolerance and the min(6, dof) singular values (into `rank`, `tolerance` and the row-major count x min(6, dof)
// `sigma`). Called without the GIL.
void singularBatchInto(const Robot& r, const double* q, Eigen::Index count, long long* rank, double* tolerance,
                       double* sigma);

}  // namespace lowpair::python
