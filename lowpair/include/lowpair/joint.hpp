#pragma once
/// @file joint.hpp
/// Joint twists: normalization into unit twist, scale and pitch (Wu et al. eq. 1), type inference.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/types.hpp"

namespace lowpair {

/// A joint as the user describes it: a twist of any magnitude in the base frame at the zero
/// configuration, an optional declared type, an offset and an optional range.
struct JointSpec {
  std::string name;                          ///< optional; used in messages and output
  std::optional<JointType> type;             ///< inferred when empty (docs/conventions.md)
  Vec6 twist = Vec6::Zero();                 ///< `[w; v]`, unnormalized allowed: `xi = xi_bar * q_bar`
  double offset = 0.0;                       ///< `dq`, joint-variable units
  std::optional<std::array<double, 2>> range;  ///< joint-variable limits `[lo, hi]`, when known
};

/// How a joint moves: the one definition of the joint-motion rule and of the joint-variable map
/// (docs/conventions.md, Wu et al. eqs. 5 and 10). The joint variable `q` becomes the motion `x = scale (q + offset)`;
/// motion `x` turns by `j x` (rad) about and slides by `k x` (length) along the joint's line, i.e.
/// `Q(x) = Rz(j x) Tz(k x)` in a frame whose z is the line, with `(j, k)` = revolute `(1, 0)`, prismatic
/// `(0, 1)`, helical `(1, pitch)`. Every algorithm (FK, Jacobians, conversions, the harness's sampling)
/// goes through these functions; nothing else states the rule.
/// The joint-variable map on plain numbers, `x = scale (q + offset)` (JointMotion::motion; vectorized
/// loops call it on arrays).
/// (`T` is double, or a SIMD vector of joint values.)
template <class T>
inline T motionOf(T q, double scale, double offset) { return scale * (q + offset); }

struct JointMotion {
  JointType type = JointType::Revolute;
  double pitch = 0.0;   ///< length/rad; 0 unless helical
  double scale = 1.0;   ///< `q_bar > 0`
  double offset = 0.0;  ///< `dq`, joint-variable units

  /// `x = scale (q + offset)`.
  double motion(double q) const { return motionOf(q, scale, offset); }
  /// The inverse map: `q = x / scale - offset`.
  double variable(double x) const { return x / scale - offset; }
  /// `j`: rad turned per unit of motion.
  double turnRate() const { return type == JointType::Prismatic ? 0.0 : 1.0; }
  /// `k`: length slid per unit of motion (the pitch of a helical joint).
  double slideRate() const {
    return type == JointType::Prismatic ? 1.0 : type == JointType::Helical ? pitch : 0.0;
  }
};

/// A joint in normalized form: `xi = twist * scale` with `|w| = 1` (revolute, helical) or `w = 0`,
/// `|v| = 1` (prismatic); `pitch = w.v` (length/rad) for helical joints, 0 otherwise.
struct Joint : JointMotion {
  std::string name;
  Vec6 twist = Vec6::Zero();  ///< unit twist `[w; v]` in the base frame at the zero configuration
  std::optional<std::array<double, 2>> range;  ///< joint-variable limits `[lo, hi]`, when known

  Vec3 axis() const { return twist.head<3>(); }    ///< unit direction (revolute/helical)
  Vec3 moment() const { return twist.tail<3>(); }  ///< `v`
};

/// `|u|` without overflow or underflow (entries up to 1e308, down to subnormal); equal to `u.norm()`
/// wherever that is exact to rounding.
double safeNorm(const Vec3& u);

/// Normalizes a joint twist (Wu et al. eq. 1) and infers or checks its type: prismatic if `w = 0`;
/// revolute if `|w.v| <= kPitchZero eps |w| max(|v|, |w| size)` (then the rounding-level pitch is removed);
/// helical otherwise. @param index 0-based joint index, used in messages. @param size the robot's size (a
/// length, lengthScaleOfSpecs): rounding is judged against it, not only against |v| (0: against |v|).
/// @throws std::invalid_argument for non-finite numbers, a zero twist, or a declared type that
///         contradicts the twist (e.g. a helical twist declared revolute).
Joint normalizeJoint(const JointSpec& spec, int index, double size = 0.0);

/// The robot's size as its unnormalized joint twists and tool position give it before normalization: the
/// largest of |p_tool| and each revolute/helical axis's distance from the origin `|w x v| / |w|^2` (what
/// normalizeJoint judges rounding against).
double lengthScaleOfSpecs(const std::vector<JointSpec>& joints, const Vec3& p_tool);

/// `"joint 3"` or `"joint 3 (elbow)"` for messages (1-based).
std::string jointLabel(int index, const std::string& name);

}  // namespace lowpair
