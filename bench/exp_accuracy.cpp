// Prints the accuracy of every se(3) exponential variant (bench/README.md table).
#include <cstdio>

#include <unsupported/Eigen/MatrixFunctions>

#include "exp_accuracy.hpp"
#include "lowpair/se3.hpp"
#include "se3_variants.hpp"

int main() {
  using namespace lowpair;
  struct Variant {
    const char* name;
    Pose (*exp)(const Vec6&);
  };
  const Variant variants[] = {
      {"Rodrigues (expSE3)", [](const Vec6& xi) { return expSE3(xi); }},
      {"Paper (eq. 2, 4x4)", [](const Vec6& xi) { return expSE3Paper(xi); }},
      {"Quaternion", [](const Vec6& xi) { return expSE3Quaternion(xi); }},
      {"EigenMatrixExp", [](const Vec6& xi) { return Pose::fromMatrix(hat6(xi).exp()); }},
  };
  std::printf("| variant | rotation ulp-eq (at angle) | translation ulp-eq (at angle) |\n|---|---|---|\n");
  for (const Variant& v : variants) {
    const lowpair_bench::ExpError e = lowpair_bench::expSweepError(v.exp);
    std::printf("| %s | %.2f (%.3g) | %.2f (%.3g) |\n", v.name, e.rotation, e.rotation_angle, e.translation,
                e.translation_angle);
  }
  return 0;
}
