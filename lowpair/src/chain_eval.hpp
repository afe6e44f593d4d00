#pragma once
// The chain evaluation of kinematics.cpp for the library's own callers (kinematics.cpp, jacobian.cpp); not
// installed. The evaluators trust their sizes: every public function checks them first with
// checkChainCall, in every build type.

#include "check.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"

namespace lowpair::detail {

// data.T_base_tool of `chain` at q (forwardKinematics); chainFrames also fills data.T_base_joint.
void chainTool(const KinematicChain& chain, Data& data, const double* q);
void chainFrames(const KinematicChain& chain, Data& data, const double* q);
// computeJacobians: data.T_base_tool, T_base_joint and J_spatial in one pass.
void chainJacobian(const KinematicChain& chain, Data& data, const double* q);

// forwardKinematicsBatch's 4-lane path (AVX2 in its x86-64-v3 clone), whatever the processor; no size checks (the
// benchmarks time it beside the 8-lane path that AVX-512 processors take).
void chainBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses);

// computeJacobiansBatch of `chain` (sizes checked here).
void jacobianBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, JacobianFrame frame,
                   Eigen::Ref<MatX> jacobians, Eigen::Ref<MatX> poses);

// The message of a failed checkChainCall, e.g. "forwardKinematics: q has 5 values, the model has 6 joints"
// or "computeJacobians: data was made for a model with 7 joints, this model has 6".
[[noreturn]] LP_COLD void throwChainMismatch(const char* function, const KinematicChain& chain, const Data& data,
                                             Eigen::Index q_size);

// `function` evaluates `chain` into `data` at a q of `q_size` values: q has one value per joint, and data
// was made for a chain of as many joints (the evaluation indexes the links, data's frames and Jacobian
// columns up to data.dof, and the lanes and data's scratch up to paddedDof, which is a function of the
// joint count). Two integer compares; nothing is built unless one fails.
inline void checkChainCall(const char* function, const KinematicChain& chain, const Data& data, Eigen::Index q_size) {
  const auto dof = static_cast<Eigen::Index>(chain.links.size());
  if (LP_UNLIKELY(q_size != dof || data.dof != dof)) throwChainMismatch(function, chain, data, q_size);
}

}  // namespace lowpair::detail
