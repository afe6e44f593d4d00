#pragma once
/// @file joint.hpp
/// Joint twists: normalization into unit twist, scale and pitch (Wu et al. eq. 1), type inference.

#include <array>
#include <optional>
#include <string>

#include "lowpair/types.hpp"

namespace lowpair {

/// A joint as the user describes it: a twist of any magnitude in the base frame at the zero
/// configuration, an optional declared type, an offset and an optional range.
struct JointSpec {
  std::string name;                          ///< optional; used in messages and output
  std::optional<JointType> type;             ///< inferred when empty (design.md)
  Vec6 twist = Vec6::Zero();                 ///< `[w; v]`, unnormalized allowed: `xi = xi_bar * q_bar`
  double offset = 0.0;                       ///< `dq`, joint-variable units
  std::optional<std::array<double, 2>> range;  ///< joint-variable limits `[lo, hi]`, when known
};

/// A joint in normalized form: `xi = twist * scale` with `|w| = 1` (revolute, helical) or `w = 0`,
/// `|v| = 1` (prismatic); `pitch = w.v` (length/rad) for helical joints, 0 otherwise.
struct Joint {
  std::string name;
  JointType type = JointType::Revolute;
  Vec6 twist = Vec6::Zero();  ///< unit twist `[w; v]`
  double pitch = 0.0;         ///< length/rad; 0 unless helical
  double scale = 1.0;         ///< `q_bar`: the D-H joint variable is `scale * q`
  double offset = 0.0;        ///< `dq`, joint-variable units
  std::optional<std::array<double, 2>> range;

  Vec3 axis() const { return twist.head<3>(); }    ///< unit direction (revolute/helical)
  Vec3 moment() const { return twist.tail<3>(); }  ///< `v`
};

/// Normalizes a joint twist (Wu et al. eq. 1) and infers or checks its type: prismatic if `w = 0`;
/// revolute if `|w.v| <= kPitchZero eps |w| |v|` (then the rounding-level pitch is removed); helical
/// otherwise. @param index 0-based joint index, used in messages.
/// @throws std::invalid_argument for non-finite numbers, a zero twist, or a declared type that
///         contradicts the twist (e.g. a helical twist declared revolute).
Joint normalizeJoint(const JointSpec& spec, int index);

/// `"joint 3"` or `"joint 3 (elbow)"` for messages (1-based).
std::string jointLabel(int index, const std::string& name);

}  // namespace lowpair
