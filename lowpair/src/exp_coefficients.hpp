#pragma once
// The coefficients of the exponential (se3.cpp), internal to the library: expSO3 and expSE3 use them, and
// the exp accuracy study (tests/lib/se3_test.cpp) and the benchmark's exp variants (bench/se3_variants.cpp)
// include this header through the source directory. Not installed.

namespace lowpair::detail {

/// Coefficients of the exponential for a rotation angle `x >= 0`:
/// `a = sin(x)/x`, `b = (1 - cos x)/x^2`, `c = (x - sin x)/x^3`, each accurate to a few ulp for every x
/// (Taylor series below kSeriesAngle where the direct forms cancel).
struct ExpCoefficients {
  double cos_x, a, b, c;
};
ExpCoefficients expCoefficients(double x);
/// `(x - sin x)/x^3` alone (the c of ExpCoefficients), for exponential variants that need only it.
double expCoefficientC(double x);

}  // namespace lowpair::detail
