// The complete program of docs/api.md: a planar 2R arm, its forward kinematics, geometric Jacobian and a
// batch of configurations. Built and run by ctest (example.planar_2r); exits 1 when a result is not the
// one worked out by hand.

#include <cmath>
#include <cstdio>
#include <iostream>

#include <lowpair/jacobian.hpp>  // Data, forwardKinematics, computeJacobians, the getters
#include <lowpair/version.hpp>   // LOWPAIR_VERSION_STRING

int main() {
  // A planar 2R arm: joint twists [w; v] in the base frame at q = 0 (v = p x w), tool at (2, 0, 0).
  lowpair::JointSpec j1, j2;
  j1.twist << 0, 0, 1, 0, 0, 0;                                // revolute about z through the origin
  j2.twist << 0, 0, 1, 0, -1, 0;                               // revolute about z through (1, 0, 0)
  lowpair::Pose tool;
  tool.p << 2, 0, 0;
  const lowpair::PoeModel model({j1, j2}, tool, "planar-2r");  // or a DhModel; validated at construction
  lowpair::Data data(model);                                   // every buffer, allocated once

  Eigen::VectorXd q(2);
  q << 0.3, -0.7;
  lowpair::forwardKinematics(model, data, q);                  // data.T_base_tool
  lowpair::computeJacobians(model, data, q);                   // FK once + data.J_spatial
  lowpair::Mat6X J(6, model.dof());
  lowpair::getGeometricJacobian(data, J);                      // or getSpatialJacobian / getBodyJacobian

  Eigen::MatrixXd Q = Eigen::MatrixXd::Random(1000, 2);        // 1000 configurations, one per row
  Eigen::MatrixXd poses(1000, 12);                             // row-major rotation, then position
  lowpair::forwardKinematicsBatch(model, Q, poses);            // many configurations at once (SIMD)

  std::cout << "lowpair " << LOWPAIR_VERSION_STRING << "\n"
            << data.T_base_tool.p.transpose() << "\n" << J << "\n" << poses.row(0) << "\n";

  // The checks: by hand, links of length 1 at absolute angles a = q1 and b = q1 + q2.
  const double a = q(0), b = q(0) + q(1);
  const Eigen::Vector3d p(std::cos(a) + std::cos(b), std::sin(a) + std::sin(b), 0.0);
  const Eigen::Vector3d elbow(std::cos(a), std::sin(a), 0.0);
  lowpair::Mat6X J_hand = lowpair::Mat6X::Zero(6, 2);  // [v; w]: v_i = z x (p - point on axis i), w_i = z
  J_hand.col(0) << -p.y(), p.x(), 0, 0, 0, 1;
  J_hand.col(1) << -(p.y() - elbow.y()), p.x() - elbow.x(), 0, 0, 0, 1;
  // two exponentials and a product of numbers of size <= 2: a few eps; 1e-14 leaves room for libm's last bit
  const double tol = 1e-14;
  const double p_err = (data.T_base_tool.p - p).cwiseAbs().maxCoeff();
  const double J_err = (J - J_hand).cwiseAbs().maxCoeff();
  // the batch evaluates the same chain in SIMD lanes with another operation order: rounding apart
  double batch_err = 0.0;
  for (Eigen::Index k = 0; k < Q.rows(); ++k) {
    const lowpair::Pose T = lowpair::poeForwardKinematics(model, Q.row(k).transpose());
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) batch_err = std::max(batch_err, std::abs(poses(k, 3 * r + c) - T.R(r, c)));
      batch_err = std::max(batch_err, std::abs(poses(k, 9 + r) - T.p(r)));
    }
  }
  std::printf("|p - p_hand| = %.3g, |J - J_hand| = %.3g, |batch - single| = %.3g (tolerance %.3g)\n", p_err, J_err,
              batch_err, tol);
  return p_err <= tol && J_err <= tol && batch_err <= tol ? 0 : 1;
}
