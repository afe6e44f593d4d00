#pragma once
// computeJacobiansBatch against the single computeJacobians + get at every row of a batch (jacobian_batch_test.cpp,
// tests/harness/jacobian_batch_models_test.cpp): the largest difference, in units of the rounding bound.
//
// Rounding bound. Both forms evaluate the same chain product with the same constants, in a different order of
// operations (vector lanes, contractions): each of the n links adds a few eps of relative error to the rotation
// and a few eps R to the position (R: the configuration's length scale, max of L, |p_tool| and every |o_i|), so
// 64 n eps bounds the difference of any frame entry (kinematics_test.cpp's batch bound). Column i is
// `scale_i [j_i z_i; j_i o_i x z_i + k_i z_i]`: its angular rows inherit the frame's error times |scale_i j_i|,
// its linear rows times `|scale_i| (|j_i| R + |k_i|)`, so each row is divided by that column scale (angular) or
// by it times R (linear). The body and geometric forms add one product with the tool pose: a few eps more,
// inside the same 64 n eps.
#include <algorithm>
#include <cmath>
#include <limits>

#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"

namespace jacobian_batch_check {

using namespace lowpair;

inline double roundingBound(int n) { return 64.0 * std::max(n, 1) * std::numeric_limits<double>::epsilon(); }

// max over the rows of q of |batch - single| / bound, every frame; `L` the model's size (lengthScale). A NaN or
// infinite difference is returned as infinity.
template <class Model>
double batchMismatch(const Model& model, const MatX& q, double L) {
  const int n = model.dof();
  const Eigen::Index count = q.rows();
  MatX jacobians(count, 6 * n), poses(count, 12);
  Data data(model);
  Mat6X J(6, n);
  double worst = 0.0;
  for (const JacobianFrame frame : {JacobianFrame::Spatial, JacobianFrame::Body, JacobianFrame::Geometric}) {
    computeJacobiansBatch(model, q, frame, jacobians, poses);
    for (Eigen::Index k = 0; k < count; ++k) {
      computeJacobians(model, data, q.row(k).transpose());
      if (frame == JacobianFrame::Spatial) getSpatialJacobian(data, J);
      if (frame == JacobianFrame::Body) getBodyJacobian(data, J);
      if (frame == JacobianFrame::Geometric) getGeometricJacobian(data, J);
      double R = std::max(L, data.T_base_tool.p.norm());
      for (const Pose& F : data.T_base_joint) R = std::max(R, F.p.norm());
      const bool linear_first = frame == JacobianFrame::Geometric;
      for (int i = 0; i < n; ++i) {
        const ChainLink& link = model.chain().links[static_cast<size_t>(i)];
        const double column = std::abs(link.motion.scale) * (std::abs(link.turn) * R + std::abs(link.slide));
        const double angular = std::abs(link.motion.scale * link.turn);
        for (int r = 0; r < 6; ++r) {
          const bool linear = (r < 3) == linear_first;
          const double scale = std::max(linear ? column : angular, std::numeric_limits<double>::min());
          const double e = std::abs(jacobians(k, r * n + i) - J(r, i)) / scale / roundingBound(n);
          worst = std::max(worst, std::isfinite(e) ? e : std::numeric_limits<double>::infinity());
        }
      }
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          worst = std::max(worst, std::abs(poses(k, 3 * a + b) - data.T_base_tool.R(a, b)) / roundingBound(n));
        }
        worst = std::max(worst, std::abs(poses(k, 9 + a) - data.T_base_tool.p[a]) / (R * roundingBound(n)));
      }
    }
  }
  return worst;
}

}  // namespace jacobian_batch_check
