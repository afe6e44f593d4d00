// Forward kinematics of many configurations at once: the PUMA 560 (Corke's standard D-H table,
// models/puma560_corke.yaml, metres) built in code, 10,000 random configurations through
// forwardKinematicsBatch, checked against the single-configuration FK and against Corke's known pose at
// q = 0. Built and run by ctest (example.fk_batch); exits 1 on a wrong result.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <lowpair/kinematics.hpp>

int main() {
  const double h = std::acos(0.0);  // pi / 2
  // Corke's rows (theta, d, alpha, a): A_i = Rz(q_i + theta) Tz(d) Rx(alpha) Tx(a)
  const lowpair::DhParams rows[6] = {{0, 0, h, 0},      {0, 0, 0, 0.4318}, {0, 0.15005, -h, 0.0203},
                                     {0, 0.4318, h, 0}, {0, 0, -h, 0},     {0, 0, 0, 0}};
  std::vector<lowpair::DhJoint> joints(6);
  for (int i = 0; i < 6; ++i) joints[static_cast<size_t>(i)].link = rows[i];  // revolute, scale 1, offset 0
  const lowpair::DhModel puma(lowpair::DhParams{}, joints, 0.0, 0.0, "puma560");

  // 10,000 configurations, one per row (seeded: the same numbers every run)
  const int count = 10000;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  lowpair::MatX Q(count, 6);
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 6; ++i) Q(k, i) = angle(rng);

  lowpair::MatX poses(count, 12);  // per row: R row-major (9), then p (3)
  lowpair::forwardKinematicsBatch(puma, Q, poses);

  // the batch against one configuration at a time (the same chain in SIMD lanes, another operation order);
  // 1e-14 m ~ 50 eps of a 0.9 m reach: rounding, where a wrong joint or product order is O(0.1)
  lowpair::Data data(puma);
  double worst = 0.0;
  for (int k = 0; k < count; ++k) {
    lowpair::forwardKinematics(puma, data, Q.row(k).transpose());
    const lowpair::Pose& T = data.T_base_tool;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(poses(k, 3 * r + c) - T.R(r, c)));
      worst = std::max(worst, std::abs(poses(k, 9 + r) - T.p(r)));
    }
  }

  // Corke's fkine(qz): identity rotation, tool at (a2 + a3, -d3, d4) = (0.4521, -0.15005, 0.4318) m
  const lowpair::Pose T0 = lowpair::dhForwardKinematics(puma, lowpair::VecX::Zero(6));
  const double zero_err = std::max((T0.p - lowpair::Vec3(0.4521, -0.15005, 0.4318)).cwiseAbs().maxCoeff(),
                                   (T0.R - lowpair::Mat3::Identity()).cwiseAbs().maxCoeff());
  std::printf("%d poses; |batch - single| = %.3g; at q = 0: p = (%.6g, %.6g, %.6g), |T - T_corke| = %.3g\n", count,
              worst, T0.p.x(), T0.p.y(), T0.p.z(), zero_err);
  return worst <= 1e-14 && zero_err <= 1e-15 ? 0 : 1;
}
