// Jacobians (jacobian.hpp): the compute-then-get contract (the getters do not change data, do not depend on
// call order, and agree with each other through the definitions, derived below, not the library's
// conversions), the conversion functions as inverse pairs that may work in place, and the size checks.
// The Jacobians against finite differences and hand-derived columns are in jacobian_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "expect_invalid.hpp"
#include "jacobian_helpers.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"
#include "random_robot.hpp"

using namespace lowpair;

// ---- the compute-then-get contract ----------------------------------------------------------------------

namespace {

using namespace jacobian_helpers;

bool sameData(const Data& a, const Data& b) {
  if (a.dof != b.dof || a.T_base_joint.size() != b.T_base_joint.size()) return false;
  for (size_t i = 0; i < a.T_base_joint.size(); ++i) {
    if (a.T_base_joint[i].R != b.T_base_joint[i].R || a.T_base_joint[i].p != b.T_base_joint[i].p) return false;
  }
  return a.T_base_tool.R == b.T_base_tool.R && a.T_base_tool.p == b.T_base_tool.p && a.J_spatial == b.J_spatial;
}

// One model: the getters leave data as computeJacobians left it, give the same result in any order and
// on repetition, a reused Data gives what a fresh one gives, and the three Jacobians are related by
// their definitions. From the geometric column [v; w] (v = dp/dq, w = angular velocity, base frame) and
// g = (R, p):
//   spatial: hat(V_s) = (dg/dq) g^-1 = [hat(w)  v - hat(w) p]  ->  [w; v - w x p]
//   body:    hat(V_b) = g^-1 (dg/dq) = [R^T hat(w) R  R^T v]   ->  [R^T w; R^T v]
// (the library builds body and geometric from the spatial Jacobian with an adjoint and v + w x p).
template <class Model>
double checkContract(const Model& model, const VecX& q, const VecX& q_other, double L) {
  const int n = model.dof();
  Data data(model);
  computeJacobians(model, data, q_other);  // stale state that must not leak into the next results
  computeJacobians(model, data, q);
  const Data snapshot = data;
  Mat6X S1(6, n), B1(6, n), G1(6, n), S2(6, n), B2(6, n), G2(6, n);
  getGeometricJacobian(data, G1);
  getBodyJacobian(data, B1);
  getSpatialJacobian(data, S1);
  EXPECT_TRUE(sameData(data, snapshot)) << "a getter changed data";
  getSpatialJacobian(data, S2);
  getGeometricJacobian(data, G2);
  getBodyJacobian(data, B2);
  EXPECT_TRUE(sameData(data, snapshot)) << "a getter changed data";
  EXPECT_TRUE(S1 == S2 && B1 == B2 && G1 == G2) << "getters depend on call order";
  EXPECT_TRUE(S1 == data.J_spatial) << "getSpatialJacobian is not data.J_spatial";

  Data fresh(model);
  const Jacobians F = libraryJacobians(model, fresh, q);
  EXPECT_TRUE(sameData(fresh, data) && F.spatial == S1 && F.body == B1 && F.geometric == G1)
      << "a reused Data gives other results than a fresh one";
  // computeJacobians includes forward kinematics
  Data fk(model);
  forwardKinematics(model, fk, q);
  const double R = lengthScale(L, data);
  EXPECT_LE(poseError(fk.T_base_tool, data.T_base_tool, R), 64 * kEpsD);

  const Mat3& Rt = data.T_base_tool.R;
  const Vec3& p = data.T_base_tool.p;
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const JointMotion& m = model.joint(i);
    const double unit = m.type == JointType::Prismatic ? m.scale / R : m.scale;  // per motion of size R
    const Vec3 v = G1.col(i).head<3>(), w = G1.col(i).tail<3>();
    Vec6 s, b;
    s << w, v - w.cross(p);
    b << Rt.transpose() * w, Rt.transpose() * v;
    const Vec6 es = (S1.col(i) - s) / unit, eb = (B1.col(i) - b) / unit;
    worst = std::max({worst, finiteOrInf(es.head<3>().cwiseAbs().maxCoeff()),
                      finiteOrInf(es.tail<3>().cwiseAbs().maxCoeff() / R),
                      finiteOrInf(eb.head<3>().cwiseAbs().maxCoeff()),
                      finiteOrInf(eb.tail<3>().cwiseAbs().maxCoeff() / R)});
  }
  return worst;
}

}  // namespace

TEST(Jacobian, GettersReadDataAndAgreeWithTheDefinitions) {
  std::mt19937_64 rng(31415);
  double worst_poe = 0.0, worst_dh = 0.0;
  for (int r = 0; r < 200; ++r) {
    const PoeModel model = lowpair_test::randomRobot(rng).model;
    const VecX q = lowpair_test::randomConfiguration(model, rng);
    const VecX q_other = lowpair_test::randomConfiguration(model, rng);
    worst_poe = std::max(worst_poe, checkContract(model, q, q_other, model.lengthScale()));
    const DhConversion c = poeToDh(model);
    if (tableScale(c.model) <= kIllConditioned * model.lengthScale()) {
      worst_dh = std::max(worst_dh, checkContract(c.model, q, q_other, tableScale(c.model)));
    }
  }
  // rounding of one adjoint / cross product on quantities of size R: a few eps
  std::printf("getters vs their definitions (per unit motion, linear / R): POE %.3g, D-H %.3g\n", worst_poe,
              worst_dh);
  EXPECT_LE(worst_poe, 64 * kEpsD);
  EXPECT_LE(worst_dh, 64 * kEpsD);
}

// The conversion functions: inverse pairs, and each may work in place (documented aliasing).
TEST(Jacobian, ConversionsInvertAndMayAlias) {
  std::mt19937_64 rng(2718);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int r = 0; r < 200; ++r) {
    const double size = std::pow(10.0, 3.0 * u(rng));
    Vec6 xi;
    xi << 3.0 * lowpair_test::draw3(u, rng), size * lowpair_test::draw3(u, rng);
    const Pose T = expSE3(xi);
    const int n = 1 + static_cast<int>(rng() % 7);
    Mat6X J(6, n);
    for (int i = 0; i < n; ++i) J.col(i) << lowpair_test::draw3(u, rng), size * lowpair_test::draw3(u, rng);
    Mat6X X(6, n), Y(6, n), A(6, n);
    auto relative = [&](const Mat6X& a, const Mat6X& b) {
      // spatial [w; v], |w| <= 1 rad and |v| <= size: angular rows as they are, linear rows / size
      return finiteOrInf(std::max((a.topRows<3>() - b.topRows<3>()).cwiseAbs().maxCoeff(),
                                  (a.bottomRows<3>() - b.bottomRows<3>()).cwiseAbs().maxCoeff() / size));
    };
    spatialToBody(T, J, X);
    bodyToSpatial(T, X, Y);
    worst = std::max(worst, relative(Y, J));
    A = J;
    spatialToBody(T, A, A);
    EXPECT_TRUE(A == X) << "spatialToBody in place";
    A = X;
    bodyToSpatial(T, A, A);
    EXPECT_TRUE(A == Y) << "bodyToSpatial in place";
    spatialToGeometric(T, J, X);
    geometricToSpatial(T, X, Y);
    worst = std::max(worst, relative(Y, J));
    A = J;
    spatialToGeometric(T, A, A);
    EXPECT_TRUE(A == X) << "spatialToGeometric in place";
    A = X;
    geometricToSpatial(T, A, A);
    EXPECT_TRUE(A == Y) << "geometricToSpatial in place";
  }
  std::printf("round trips (relative to the twist size): %.3g\n", worst);
  EXPECT_LE(worst, 64 * kEpsD);
}

using lowpair_test::expectInvalid;


// Sizes are checked in every build type (this suite runs in Release): q, the Data (a Data made for a model
// with fewer joints was an out-of-bounds write in Release) and the output columns.
TEST(Jacobian, RejectsWrongSizes) {
  std::vector<JointSpec> joints(2);
  joints[0].twist << 0, 0, 1, 0, 0, 0;
  joints[1].twist << 0, 1, 0, 0, 0, 1;
  const PoeModel model(joints, Pose{});
  const DhModel dh = poeToDh(model).model;
  std::vector<JointSpec> three = joints;
  three.push_back(joints[0]);
  const PoeModel model3(three, Pose{});
  Data data(model), data3(model3), data1(PoeModel({joints[0]}, Pose{}));
  Mat6X J(6, 2), K(6, 3);
  expectInvalid([&] { computeJacobians(model, data, VecX::Zero(3)); }, "computeJacobians: q has 3 values, the model has 2 joints");
  expectInvalid([&] { computeJacobians(dh, data, VecX::Zero(1)); }, "computeJacobians: q has 1 value, the model has 2 joints");
  expectInvalid([&] { computeJacobians(model, data3, VecX::Zero(2)); },
                "computeJacobians: data was made for a model with 3 joints, this model has 2");
  expectInvalid([&] { computeJacobians(dh, data1, VecX::Zero(2)); },
                "computeJacobians: data was made for a model with 1 joint, this model has 2");
  EXPECT_NO_THROW(computeJacobians(dh, data, VecX::Zero(2)));  // a Data fits every model of its joint count
  computeJacobians(model, data, VecX::Zero(2));
  expectInvalid([&] { getSpatialJacobian(data, K); }, "getSpatialJacobian: the output has 3 columns, data has 2 joints");
  expectInvalid([&] { getBodyJacobian(data, K); }, "getBodyJacobian: the output has 3 columns, data has 2 joints");
  expectInvalid([&] { getGeometricJacobian(data, K); }, "getGeometricJacobian: the output has 3 columns, data has 2 joints");
  EXPECT_NO_THROW(getGeometricJacobian(data, J));
  // the conversions write a column per input column
  expectInvalid([&] { spatialToBody(Pose{}, J, K); }, "spatialToBody: the input has 2 columns, the output 3");
  expectInvalid([&] { bodyToSpatial(Pose{}, K, J); }, "bodyToSpatial: the input has 3 columns, the output 2");
  expectInvalid([&] { spatialToGeometric(Pose{}, J, K); }, "spatialToGeometric: the input has 2 columns, the output 3");
  expectInvalid([&] { geometricToSpatial(Pose{}, K, J); }, "geometricToSpatial: the input has 3 columns, the output 2");
}
