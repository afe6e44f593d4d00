#pragma once
// The chain kernel before issue 29 (chain_baseline.cpp): "previous lowpair" in the benchmarks' tables. No size
// checks (the benchmarks pass matching sizes); the batch is the 4-lane (AVX2) path, as the 29.6 ns.
#include "lowpair/kinematics.hpp"

namespace lowpair_bench::baseline {

// data.T_base_tool (forwardKinematics)
void forwardKinematics(const lowpair::KinematicChain& chain, lowpair::Data& data, const double* q);
// data.T_base_joint, T_base_tool and J_spatial (computeJacobians)
void computeJacobians(const lowpair::KinematicChain& chain, lowpair::Data& data, const double* q);
// forwardKinematicsBatch's 4-lane path
void forwardKinematicsBatch(const lowpair::KinematicChain& chain, const Eigen::Ref<const lowpair::MatX>& q,
                            Eigen::Ref<lowpair::MatX> poses);

// The 8-lane (AVX-512) path, on processors that have it (hasBatch8; otherwise the 4-lane path).
void forwardKinematicsBatch8(const lowpair::KinematicChain& chain, const Eigen::Ref<const lowpair::MatX>& q,
                             Eigen::Ref<lowpair::MatX> poses);
bool hasBatch8();

// Today's forwardKinematicsBatch 4-lane path (lowpair/src/chain_eval.hpp's chainBatch), whatever the processor: the
// counterpart of forwardKinematicsBatch above on AVX-512 machines, which take the 8-lane path.
void currentBatch4(const lowpair::KinematicChain& chain, const Eigen::Ref<const lowpair::MatX>& q,
                   Eigen::Ref<lowpair::MatX> poses);

}  // namespace lowpair_bench::baseline
