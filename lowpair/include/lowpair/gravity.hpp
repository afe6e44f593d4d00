#pragma once
/// @file gravity.hpp
/// Link masses and the static gravity load on each joint (docs/calibration.md "Beyond geometry").
///
/// Link i is the rigid body joint i moves and joint i+1 does not (the last link carries the tool). Its centre
/// of mass is given in the base frame at the reference configuration (every joint motion `x = scale (q +
/// offset)` zero, where the POE product is the identity) and moves rigidly with the link by the model's POE
/// at the commanded q: `com_i(q) = exp(xi_1 x_1) ... exp(xi_i x_i) com_i`. The payload's centre of mass is
/// given in the tool frame. The load is first order: evaluated at the commanded configuration, not at the
/// deflected one (the deflection changes the moment arms by `|dq| |r|`, a relative error of `|dq|`, about
/// 1e-3 for a 1 mrad deflection).

#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// A point mass standing for a rigid body's gravity load.
struct PointMass {
  double mass = 0.0;           ///< kg, >= 0
  Vec3 com = Vec3::Zero();     ///< centre of mass, model length unit (frame: see MassModel)
};

/// The masses a model's gravity loads come from.
struct MassModel {
  std::vector<PointMass> links{};  ///< one per joint (link i: what joint i moves), com in the base frame
                                   ///< at the reference configuration
  PointMass payload{};             ///< com in the tool frame
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< m/s^2, base frame
  double metres_per_unit = 1.0;    ///< the model's length unit in metres (mm: 1e-3)
  bool empty() const { return links.empty() && payload.mass == 0.0; }
};

/// The static generalized gravity force on each joint variable at the commanded `q`: the work gravity does
/// per unit of `q_i` when joint i alone moves, `tau_i = scale_i xi_i(q)^T F_i`, with `xi_i(q)` joint i's unit
/// twist moved by the joints before it and `F_i` the wrench (about the base origin) of the gravity forces
/// `m g` on every link from i on and the payload. Units: N m per rad of motion for revolute and helical joints,
/// N for prismatic joints (times `scale`: per unit of the joint variable).
/// @throws std::invalid_argument if q.size() != model.dof(), masses.links.size() is neither 0 nor dof(),
///         or a mass is negative or not finite
VecX gravityTorques(const PoeModel& model, const MassModel& masses, const Eigen::Ref<const VecX>& q);

/// The checks of gravityTorques on `masses` for a `dof`-joint model (link count, masses finite and >= 0, centres
/// of mass and gravity finite, metres_per_unit positive and finite). @throws std::invalid_argument naming the part
void checkMassModel(const MassModel& masses, int dof);

}  // namespace lowpair
