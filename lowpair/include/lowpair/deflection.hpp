#pragma once
/// @file deflection.hpp
/// Joint deflections beyond the geometric model (docs/calibration.md "Beyond geometry"): compliance under the
/// static gravity load (gravity.hpp) and backlash. The controller commands joint value `q_i`; the joint stands at
///
///     q_i + c_i tau_i(q) + b_i s_i
///
/// with `tau_i(q)` the gravity load on joint i at the commanded q (gravityTorques: N m per rad, N for a sliding
/// joint), `c_i` its compliance (joint-variable unit per N m, per N for a prismatic joint: rad/(N m) or length/N),
/// `s_i` in {-1, 0, 1} the sign of joint i's last move (the side of the gear play it rests on) and `b_i` its
/// backlash (half the play, joint-variable unit). The model is first order: tau is evaluated at the commanded
/// configuration with the model's geometry (gravity.hpp).

#include <optional>
#include <vector>

#include "lowpair/gravity.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// The deflection parameters of a robot, per joint (empty: none; otherwise one per joint, 0 for a rigid joint).
struct JointDeflection {
  VecX compliance{};  ///< c_i: joint-variable unit per N m (per N for a prismatic joint)
  VecX backlash{};    ///< b_i: joint-variable unit
  bool empty() const { return compliance.size() == 0 && backlash.size() == 0; }
};

/// The per-pose inputs of a deflection (empty vectors: zero).
struct PoseLoad {
  VecX torque{};  ///< tau(q): gravityTorques at the commanded q
  VecX sign{};    ///< s: the sign of each joint's last move, -1, 0 or 1
};

/// `q + c tau + b s` (element-wise; an empty vector counts as zeros).
/// @throws std::invalid_argument for a non-empty vector whose size is not q's
VecX deflectedJoints(const JointDeflection& deflection, const VecX& q, const PoseLoad& load);

/// The sign of each joint's last move in pose order: `s_j[k] = sign(q_j[k] - q_j[k-1])` when joint j moved
/// between poses k-1 and k; a pose where it did not move keeps the sign of its last move (several targets
/// read at one pose share it); 0 before its first move (the first pose).
std::vector<VecX> moveSigns(const std::vector<VecX>& q);

/// Per pose: `torque` = gravityTorques(model, masses, q[k]) when `with_torque` (else empty), `sign` = signs[k]
/// (signs empty: none). @throws std::invalid_argument as gravityTorques, or for signs of another count or size,
/// or a sign not -1, 0 or 1
std::vector<PoseLoad> poseLoads(const PoeModel& model, const MassModel& masses, const std::vector<VecX>& q,
                                bool with_torque, const std::vector<VecX>& signs);

/// The command whose joints stand at `q_stand`: the q with `q + c tau(q) + b s = q_stand` (tau = gravityTorques(model,
/// masses, q)), by the fixed-point iteration `q <- q_stand - c tau(q) - b s` from `q_stand`. It contracts by the
/// largest `|c_i dtau_i/dq_j|` summed over j, about 1e-3 for real arms (stiffness 1e5-1e6 N m/rad, loads of a
/// few hundred N m), so a few steps reach rounding; nothing when 100 steps leave a change above
/// `16 eps (1 + |q_stand|)` (a compliance so large that the load's change with the deflection matters as much as
/// the deflection).
/// @param sign the approach signs s (empty: no backlash applied)
/// @throws std::invalid_argument as gravityTorques and deflectedJoints
std::optional<VecX> commandFor(const PoeModel& model, const MassModel& masses, const JointDeflection& deflection,
                               const VecX& q_stand, const VecX& sign = VecX());

}  // namespace lowpair
