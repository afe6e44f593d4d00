#pragma once
/// @file tolerances.hpp
/// Every geometric threshold of lowpair, in one header. Thresholds are relative: a length threshold is
/// multiplied by the robot size `L` (docs/conventions.md), an angle threshold is in radians.

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

/// Hayati rows (docs/conventions.md): a row whose axes are not parallel within the parallel threshold is
/// written as a Hayati row when its standard |d| (or, for the last row, max(|d|, |d_T|)) exceeds
/// `kHayatiLength * L` and the Hayati row's longest length is shorter. Every revolute axis lies within L of
/// the base origin, so a standard row between nearly parallel axes has |d| ~ L / sin(alpha) while the Hayati
/// row's a is the distance of the next axis from this frame's origin in this frame's xy plane: with the
/// factor 1, no length of the table exceeds L by the standard rows and the Hayati rows stay near the
/// distances between the axes (2 L at most for a UR-type arm; tests/lib/hayati_test.cpp).
constexpr double kHayatiLength = 1.0;

/// Conditioning warning: a D-H length beyond `kIllConditioned * L` (Wu et al. §V: nearly parallel axes).
constexpr double kIllConditioned = 1e3;

// --- singularity analysis (singularity.hpp explains each) ---------------------------------------------
/// Rank tolerance factor (see the file comment).
constexpr double kRankFactor = 1e3;
/// The rank rule, the one behind every rank lowpair reports (manipulator Jacobians in singularity.cpp,
/// identification Jacobians in identifiability.cpp, rank_rule.hpp): a singular value counts when it is above
/// kRankFactor * n * eps * sigma_max, n the matrix's larger dimension that rounding grows with (the joints,
/// at least 6, for a manipulator Jacobian; the parameters for an identification Jacobian, whose rows are
/// averaged by the column scaling). A reduced problem keeps the n of the matrix it came from.
constexpr double numericalRankTolerance(double sigma_max, double n) { return kRankFactor * n * kEps * sigma_max; }
/// Angle (rad) and relative distance (times L) tolerance of the line classes.
constexpr double kLineTolerance = 1e-13;
/// The same tolerance once the rank test has found a deficiency. A pose whose sigma_min is at the rank
/// threshold (~1.3e-12 sigma_max) can sit up to ~1e-10 (measured: perturbations of 1e-10 of the listed
/// singular poses stay rank deficient) from the exact singular geometry, so the lines that explain the
/// deficiency are matched within 1e-8; on a regular pose the tight tolerance applies.
constexpr double kLineToleranceSingular = 1e-8;
/// C6: the reciprocal wrench has zero pitch when `|pitch| <= kWrenchPitchTolerance * L`. Applied only to
/// wrenches of a rank-deficient Jacobian, so it cannot make a regular pose singular; it is looser than
/// kLineTolerance because a null vector carries the rounding error divided by the gap sigma_{r} - sigma_{r+1}.
constexpr double kWrenchPitchTolerance = 1e-8;
/// `other`: a joint takes part in a dependency when its coefficient in a unit null vector exceeds this.
constexpr double kNullCoefficient = 1e-8;
/// The classes are searched only for chains of at most this many joints. The search pairs every two axes
/// with every other axis, O(n^4) when many axes share a plane or a point: measured on all-parallel coplanar
/// axes, 0.1 s at 64 joints, 1.4 s at 128, 23 s at 256. 64 covers every arm and the hyper-redundant chains
/// of the literature, and keeps the listing readable (at most 64 * 63 / 2 pairs for C1).
constexpr int kClassSearchMaxJoints = 64;

// --- model input (model.cpp) ----------------------------------------------------------------------------
/// A rotation read from a robot file (`tool_pose`) must be orthonormal to this, `max |R^T R - I|`: a matrix
/// written with 10 decimals (defect below ~3e-10) passes, a scaled or sheared one is an input error.
constexpr double kRotationOrthonormal = 1e-9;
/// Up to this defect the rotation is kept bit for bit (the rounding of a computed rotation); above it, and
/// up to kRotationOrthonormal, it is replaced by the nearest rotation (polar decomposition).
constexpr double kRotationExact = 4.0 * kEps;
/// `PoeModel` from already normalized joints (a conversion result): |w| (prismatic |v|) must be 1 within
/// this, a normalized twist carried through a chain of rigid transforms keeps its norm to rounding.
constexpr double kUnitNorm = 1e3 * kEps;
/// The magnitudes a model may have: the robot size `L` within [1/kMaxMagnitude, kMaxMagnitude] (in the
/// length unit; `L = 1` when every length is 0), every joint scale within the same interval, and every
/// range end and offset at most kMaxMagnitude / scale in magnitude (so the joint value `x = scale (q +
/// offset)` at a range end is at most kMaxMagnitude). Products of three such numbers (a Jacobian entry
/// times L squared, the D-H check's scaled errors) stay far from overflow and underflow; beyond them a
/// model is rejected naming the quantity, never evaluated to inf or NaN (fuzz regressions numeric/*).
constexpr double kMaxMagnitude = 1e100;

}  // namespace lowpair
