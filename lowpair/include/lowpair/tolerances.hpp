#pragma once
/// @file tolerances.hpp
/// Every geometric threshold of lowpair, in one header. Thresholds are relative: a length threshold is
/// multiplied by the robot size `L` (design.md), an angle threshold is in radians.

#include <limits>

namespace lowpair {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Revolute vs helical: a twist `[w; v]` is revolute when `|w.v| <= kPitchZero * eps * |w| |v|`.
constexpr double kPitchZero = 64.0;

/// Below this rotation angle (rad) the exponential and logarithm use Taylor series for
/// sin(x)/x, (1 - cos x)/x^2 and (x - sin x)/x^3 (see se3.cpp for the error analysis).
constexpr double kSeriesAngle = 1.5;

/// Parallel-axis threshold of the D-H conversion on sin(alpha), per joint of the chain: the
/// default is `kParallelPerJoint * eps * n` (rounding level, Wu et al. §III-B).
constexpr double kParallelPerJoint = 16.0;

/// Canonicalization of a D-H table: angles within `kSnapAngle` (rad) of 0 or pi and lengths within
/// `kSnapLength * L` of 0 are snapped.
constexpr double kSnapAngle = 64.0 * kEps;
constexpr double kSnapLength = 64.0 * kEps;

/// Conditioning warning: a D-H length beyond `kIllConditioned * L` (Wu et al. §V: nearly parallel axes).
constexpr double kIllConditioned = 1e3;

}  // namespace lowpair
