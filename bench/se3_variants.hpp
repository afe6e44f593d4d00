#pragma once
/// @file se3_variants.hpp
/// Alternative implementations of the se(3) exponential `exp(hat6(xi))`, `xi = [w; v]`, kept for the
/// benchmark and accuracy comparison of bench/README.md. The library default is `expSE3` (se3.hpp,
/// the Rodrigues/V closed form); each variant here computes the same map and is allocation-free.
/// Accuracy (worst ulp-equivalent error over the angle sweep 1e-12..pi, bench/exp_variants_test.cpp)
/// is listed in bench/README.md.

#include "lowpair/types.hpp"

namespace lowpair {

/// Wu et al. eq. 2 evaluated literally as a 4x4 matrix polynomial:
/// `exp(Xi) = I + Xi + (1 - cos q)/q^2 Xi^2 + (q - sin q)/q^3 Xi^3`, `q = |w|`, `Xi = hat6(xi)`,
/// with the coefficients in their direct (cancelling) forms; `q = 0` gives the pure translation.
Pose expSE3Paper(const Vec6& xi);

/// Half-angle (unit quaternion) form: `qw = cos(q/2)`, `qv = sin(q/2)/q w`;
/// `R = I + 2 qw hat(qv) + 2 hat(qv)^2`, `p = (I + b W + c W^2) v` with `b = 2 (sin(q/2)/q)^2` and `c`
/// from the series / direct form of expCoefficients. One sin/cos pair (of q/2) instead of two.
Pose expSE3Quaternion(const Vec6& xi);

}  // namespace lowpair
