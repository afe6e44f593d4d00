#pragma once
/// @file se3.hpp
/// SE(3) and se(3) in twist coordinates `[w; v]` (rotation first): hat/vee, exponential, logarithm,
/// adjoint. References are to Wu, Crawford, Roberts (arXiv 1902.00198).

#include "lowpair/types.hpp"

namespace lowpair {

/// Skew matrix `hat(w)` with `hat(w) u = w x u`.
Mat3 hat3(const Vec3& w);
/// Inverse of hat3 for a skew matrix (uses the antisymmetric part).
Vec3 vee3(const Mat3& W);
/// 4x4 se(3) matrix `[hat(w) v; 0 0]` of the twist `xi = [w; v]`.
Mat4 hat6(const Vec6& xi);
/// Inverse of hat6.
Vec6 vee6(const Mat4& Xi);

/// Rotation `exp(hat(w))` for an angle vector `w` (angle |w|).
Mat3 expSO3(const Vec3& w);

/// `exp(hat6(xi))` for a twist `xi = [w; v]` of any magnitude (the angle is `|w|`; `w = 0` is a pure
/// translation by `v`). Closed form `R = I + a W + b W^2`, `p = (I + b W + c W^2) v`. The library default.
Pose expSE3(const Vec6& xi);

/// `exp(hat6(xi) theta)` for a revolute/helical joint: unit axis `w`, `v = p x w + pitch w`, angle
/// `theta` (Wu et al. eq. 2 with `|w| = 1`): `R = I + sin(theta) W + (1 - cos theta) W^2`,
/// `p = (I - R)(w x v) + pitch theta w`. @param pitch length/rad; pass 0 for a revolute joint.
/// Precondition: `|w| = 1` to rounding.
void expUnitTwist(const Vec3& w, const Vec3& v, double pitch, double theta, Pose& out);

/// Logarithm of a pose: the twist `xi` with `expSE3(xi) = T` and rotation angle in `[0, pi]`.
/// Accurate near 0 and near pi (the axis comes from the symmetric part of R there).
Vec6 logSE3(const Pose& T);
/// Logarithm of a rotation: angle vector with angle in `[0, pi]`.
Vec3 logSO3(const Mat3& R);

/// Rotation angle of R in [0, pi] as `atan2(|vee(R - R^T)|/2, (tr R - 1)/2)` (docs/conventions.md; never acos).
double rotationAngle(const Mat3& R);

/// 6x6 adjoint `Ad(T)` acting on `[w; v]` (Wu et al. eq. 4): `[R 0; hat(p) R  R]`.
Mat6 adjoint(const Pose& T);
/// `Ad(T) xi` without forming the matrix: `[R w; R v + p x (R w)]`.
Vec6 adjointApply(const Pose& T, const Vec6& xi);

}  // namespace lowpair
