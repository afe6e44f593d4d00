#pragma once
// Helpers of the Jacobian tests (jacobian_test.cpp, jacobian_contract_test.cpp): errors made finite, the
// length and rounding scales they are divided by, and the library's three Jacobians at q.
#include <algorithm>
#include <cmath>
#include <limits>

#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"

namespace jacobian_helpers {

using namespace lowpair;

constexpr double kEpsD = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();

inline double finiteOrInf(double e) { return std::isfinite(e) ? e : kInf; }  // NaN never passes a bound

// The length scale of a configuration: the largest distance from the base origin to a joint line's
// frame origin or the tool, at least L.
inline double lengthScale(double L, const Data& data) {
  double R = std::max(L, data.T_base_tool.p.norm());
  for (const Pose& T : data.T_base_joint) R = std::max(R, T.p.norm());
  return R;
}

// The rounding scale of a D-H table (conversion.md, "Accuracy"): max(L, max |d|, max |a|, |d_T|) over the
// base row and the links; its FK and Jacobian are exact to eps times this.
inline double tableScale(const DhModel& dh) {
  double s = std::max({dh.lengthScale(), std::abs(dh.base().d), std::abs(dh.base().a), std::abs(dh.toolD())});
  for (const DhJoint& j : dh.joints()) s = std::max({s, std::abs(j.link.d), std::abs(j.link.a)});
  return s;
}

inline double poseError(const Pose& a, const Pose& b, double R) {
  return finiteOrInf(std::max((a.R - b.R).cwiseAbs().maxCoeff(), (a.p - b.p).cwiseAbs().maxCoeff() / R));
}

struct Jacobians {
  Mat6X spatial, body, geometric;
};
template <class Model>
Jacobians libraryJacobians(const Model& model, Data& data, const VecX& q) {
  const int n = model.dof();
  Jacobians J{Mat6X(6, n), Mat6X(6, n), Mat6X(6, n)};
  computeJacobians(model, data, q);
  getSpatialJacobian(data, J.spatial);
  getBodyJacobian(data, J.body);
  getGeometricJacobian(data, J.geometric);
  return J;
}

}  // namespace jacobian_helpers
