#pragma once
/// @file fast_fk.hpp
/// Fast forward kinematics of a D-H chain (eq. 10): the joint sines and cosines are computed together
/// by a branch-free, vectorizable polynomial (sinCos below) and the chain product exploits the
/// structure of `A = Rz(theta) Tz(d) Rx(alpha) Tx(a)` with `cos/sin(alpha)` precomputed. The batch form
/// evaluates many configurations at once in structure-of-arrays layout (SIMD across configurations).
/// Results equal `forwardKinematics(DhModel, ...)` to a few ulp of the robot size (bench/fast_fk_test.cpp).
/// No allocation after construction.

#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// `s[i] = sin(x[i])`, `c[i] = cos(x[i])` for `i < n`: Cody-Waite reduction by pi/2 (3-part constant)
/// and the Cephes minimax polynomials on [-pi/4, pi/4]; branch-free so the loop vectorizes.
/// Accuracy: within 1 ulp (absolute error <= 1.2 eps for |x| <= 1e6; tested in bench/fast_fk_test.cpp).
/// Precondition: finite `|x| <= 1e6`.
void sinCos(const double* x, int n, double* s, double* c);

/// Precomputed D-H chain for fast forward kinematics (any mix of revolute, prismatic and helical joints).
class DhKernel {
 public:
  static constexpr int kMaxDof = 16;
  /// Lanes of one batch block (configurations evaluated together).
  static constexpr int kBlock = 8;

  /// @throws std::invalid_argument when the model has more than kMaxDof joints.
  explicit DhKernel(const DhModel& model);

  int dof() const { return dof_; }

  /// `H(q)` (eq. 10). @param q size dof (unchecked).
  void forward(const Eigen::Ref<const VecX>& q, Pose& T_base_tool) const;
  void forward(const double* q, Pose& T_base_tool) const;

  /// FK and the geometric Jacobian (Paden-Sastry eq. 3.13, rows `[v; w]` at the tool origin):
  /// column i = `[j_i z_i x (o_tool - o_i) + k_i z_i; j_i z_i]` times `scale_i` ((j, k) of design.md).
  /// @param J_geometric 6 x dof (unchecked).
  void geometricJacobian(const double* q, Pose& T_base_tool, Eigen::Ref<Mat6X> J_geometric) const;

  /// Batch FK, structure of arrays: joint j of configuration k is `q[j * stride + k]`; pose entry e of
  /// configuration k is written to `out[e * stride + k]`, e = 0..8 the rotation row-major, 9..11 the
  /// position. @param count configurations, `count <= stride`.
  void forwardBatch(const double* q, int count, int stride, double* out) const;

 private:
  struct Row {
    double ca, sa, a, d, theta;  // link_i constants
    double rot, slide;           // theta += rot x, d += slide x, x = scale q
  };
  template <bool kJacobian>
  void chain(const double* q, Pose& T_base_tool, double* z_axes, double* o_axes) const;
  void block(const double* q, int stride, double* out, int out_stride, int lanes) const;
  int dof_ = 0;
  Row rows_[kMaxDof];
  Pose base_, tool_;
};

}  // namespace lowpair
