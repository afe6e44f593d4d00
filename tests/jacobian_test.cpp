// Jacobians against central finite differences of forward kinematics, on 1,000 seeded random robots
// (2-7 joints: revolute, prismatic, helical; scales != 1; offsets; degenerate axis geometry), POE and
// D-H (via poeToDh), and the consistency of the adjoint conversions.
//
// Step and tolerance from the math: with joint motion x = scale (q + offset), a step of x by
// h_x = 1e-5 (rad, or 1e-5 R for prismatic) gives T(q+h) T(q-h)^-1 = exp(2 h xi_s + O(h^3)) (the h^2
// terms cancel), so the central difference has truncation error ~ h_x^2 ~ 1e-10 relative and rounding
// error ~ eps R / h_x ~ 2e-11 R. Errors are measured per unit joint motion, linear parts relative to the
// length scale R of the configuration; the bound 1e-8 is a hundredfold margin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "random_robot.hpp"

using namespace lowpair;

namespace {

PoeModel randomRobot(std::mt19937_64& rng) { return lowpair_test::randomRobot(rng).model; }
using lowpair_test::randomConfiguration;

// Finite-difference Jacobians (spatial, body, geometric) of any forward-kinematics function.
struct FdJacobians {
  Mat6X spatial, body, geometric;
};

template <class Fk>
FdJacobians finiteDifferences(const Fk& fk, const VecX& q, const VecX& step) {
  const int n = static_cast<int>(q.size());
  FdJacobians fd{Mat6X(6, n), Mat6X(6, n), Mat6X(6, n)};
  for (int i = 0; i < n; ++i) {
    VecX qp = q, qm = q;
    qp[i] += step[i];
    qm[i] -= step[i];
    const Pose Tp = fk(qp), Tm = fk(qm);
    const double h2 = 2.0 * step[i];
    const Vec6 xs = logSE3(Tp * Tm.inverse()) / h2;  // spatial twist
    fd.spatial.col(i) = xs;
    fd.body.col(i) = logSE3(Tm.inverse() * Tp) / h2;
    fd.geometric.col(i) << (Tp.p - Tm.p) / h2, xs.head<3>();
  }
  return fd;
}

// Worst error per unit joint motion: angular rows (rad), linear rows / R.
struct Worst {
  double angular = 0.0, linear = 0.0;
  void add(const Mat6X& J, const Mat6X& ref, const PoeModel& model, double R, bool angular_first) {
    for (int i = 0; i < model.dof(); ++i) {
      const Joint& j = model.joint(i);
      const double unit = j.type == JointType::Prismatic ? j.scale / R : j.scale;  // |dx/dq| in units of R
      const Vec6 e = (J.col(i) - ref.col(i)) / unit;
      const Vec3 ea = angular_first ? e.head<3>() : e.tail<3>();
      const Vec3 el = angular_first ? e.tail<3>() : e.head<3>();
      angular = std::max(angular, ea.norm());
      linear = std::max(linear, el.norm() / R);
    }
  }
};

// The length scale of a configuration: the largest distance from the base origin to a joint axis,
// the tool, or (for D-H) a frame of the table.
double lengthScale(const PoeModel& model, const Data& data) {
  double R = std::max(model.size(), data.T_base_tool.p.norm());
  for (const Pose& T : data.T_base_joint) R = std::max(R, T.p.norm());
  return R;
}

}  // namespace

TEST(Jacobian, FiniteDifferencesOnThousandRandomRobots) {
  std::mt19937_64 rng(19840924);
  Worst poe_s, poe_b, poe_g, dh_s, dh_b, dh_g, dh_vs_poe;
  int robots = 0, configurations = 0, ill_conditioned = 0;
  for (int r = 0; r < 1000; ++r) {
    const PoeModel model = randomRobot(rng);
    const DhConversion c = poeToDh(model);
    const int n = model.dof();
    Data pd(model);
    Data dd(c.model);
    Mat6X Js(6, n), Jb(6, n), Jg(6, n), Ds(6, n), Db(6, n), Dg(6, n);
    for (int k = 0; k < 3; ++k) {
      const VecX q = randomConfiguration(model, rng);
      computeJacobians(model, pd, q); getSpatialJacobian(pd, Js);
      computeJacobians(model, pd, q); getBodyJacobian(pd, Jb);
      computeJacobians(model, pd, q); getGeometricJacobian(pd, Jg);
      const double R = lengthScale(model, pd);
      VecX step(n);
      for (int i = 0; i < n; ++i) {
        const Joint& j = model.joint(i);
        step[i] = (j.type == JointType::Prismatic ? 1e-5 * R : 1e-5) / j.scale;
      }
      const FdJacobians fd = finiteDifferences([&](const VecX& x) { return poeForwardKinematics(model, x); }, q, step);
      poe_s.add(Js, fd.spatial, model, R, true);
      poe_b.add(Jb, fd.body, model, R, true);
      poe_g.add(Jg, fd.geometric, model, R, false);

      // D-H chain of the same robot; its rounding scale includes the table's |d|, |a| (design.md)
      computeJacobians(c.model, dd, q); getSpatialJacobian(dd, Ds);
      computeJacobians(c.model, dd, q); getBodyJacobian(dd, Db);
      computeJacobians(c.model, dd, q); getGeometricJacobian(dd, Dg);
      const double R_dh = std::max(R, c.fk_check.scale);
      dh_vs_poe.add(Ds, Js, model, R_dh, true);
      // Finite differences of the D-H FK carry its rounding eps R_dh / h: with nearly parallel axes
      // (|d| up to 1e16 L) that swamps the derivative, so they are taken only on well-conditioned tables;
      // the ill-conditioned ones are covered by the analytic D-H vs POE comparison above.
      if (c.fk_check.scale > kIllConditioned * model.size()) {
        ++ill_conditioned;
        continue;
      }
      const FdJacobians fd_dh =
          finiteDifferences([&](const VecX& x) { return dhForwardKinematics(c.model, x); }, q, step);
      dh_s.add(Ds, fd_dh.spatial, model, R_dh, true);
      dh_b.add(Db, fd_dh.body, model, R_dh, true);
      dh_g.add(Dg, fd_dh.geometric, model, R_dh, false);
    }
    configurations += 3;
    ++robots;
  }
  std::printf("%d robots, %d configurations (%d with an ill-conditioned D-H table: no D-H finite differences); "
              "worst error per unit joint motion\n", robots, configurations, ill_conditioned);
  EXPECT_LT(ill_conditioned, configurations / 4);  // most configurations do check the D-H Jacobians
  std::printf("%-28s %12s %14s\n", "", "angular", "linear / R");
  const std::pair<const char*, Worst*> rows[] = {{"POE spatial vs FD", &poe_s}, {"POE body vs FD", &poe_b},
                                                 {"POE geometric vs FD", &poe_g}, {"D-H spatial vs FD", &dh_s},
                                                 {"D-H body vs FD", &dh_b},       {"D-H geometric vs FD", &dh_g},
                                                 {"D-H spatial vs POE spatial", &dh_vs_poe}};
  for (const auto& [name, w] : rows) {
    std::printf("%-28s %12.3g %14.3g\n", name, w->angular, w->linear);
    EXPECT_LE(w->angular, 1e-8) << name;
    EXPECT_LE(w->linear, 1e-8) << name;
  }
  // the two analytic forms agree to rounding
  EXPECT_LE(dh_vs_poe.angular, 1e-12);
  EXPECT_LE(dh_vs_poe.linear, 1e-12);
}

TEST(Jacobian, ConversionsAreConsistent) {
  std::mt19937_64 rng(31415);
  double worst = 0.0;
  for (int r = 0; r < 200; ++r) {
    const PoeModel model = randomRobot(rng);
    const int n = model.dof();
    Data data(model);
    const VecX q = randomConfiguration(model, rng);
    Mat6X Js(6, n), Jb(6, n), Jg(6, n), X(6, n), Y(6, n);
    computeJacobians(model, data, q); getSpatialJacobian(data, Js);
    computeJacobians(model, data, q); getBodyJacobian(data, Jb);
    computeJacobians(model, data, q); getGeometricJacobian(data, Jg);
    const Pose& T = data.T_base_tool;
    const double scale = std::max(Js.cwiseAbs().maxCoeff(), 1.0);
    spatialToBody(T, Js, X);
    worst = std::max(worst, (X - Jb).cwiseAbs().maxCoeff() / scale);
    bodyToSpatial(T, Jb, Y);
    worst = std::max(worst, (Y - Js).cwiseAbs().maxCoeff() / scale);
    spatialToGeometric(T, Js, X);
    worst = std::max(worst, (X - Jg).cwiseAbs().maxCoeff() / scale);
    geometricToSpatial(T, Jg, Y);
    worst = std::max(worst, (Y - Js).cwiseAbs().maxCoeff() / scale);
    // the matrix form of the adjoint (Wu et al. eq. 4)
    const Mat6X Jb_matrix = adjoint(T.inverse()) * Js;
    worst = std::max(worst, (Jb_matrix - Jb).cwiseAbs().maxCoeff() / scale);
    // in place (aliasing) gives the same
    X = Js;
    spatialToBody(T, X, X);
    worst = std::max(worst, (X - Jb).cwiseAbs().maxCoeff() / scale);
  }
  std::printf("worst conversion mismatch (relative to max |J|): %.3g\n", worst);
  EXPECT_LE(worst, 1e-12);
}

TEST(Jacobian, GeometricColumnsFollowEq313) {
  // a helical joint about z through (1, 0, 0) with pitch 0.2 and scale 2, then a prismatic one along x
  std::vector<JointSpec> joints(2);
  joints[0].type = JointType::Helical;
  joints[0].twist << 0, 0, 2, 2 * (Vec3(1, 0, 0).cross(Vec3(0, 0, 1)) + 0.2 * Vec3(0, 0, 1));
  joints[1].twist << 0, 0, 0, 3, 0, 0;
  Pose tool;
  tool.p << 0, 1, 0;
  const PoeModel model(joints, tool);
  Data data(model);
  Mat6X J(6, 2);
  VecX q = VecX::Zero(2);
  computeJacobians(model, data, q); getGeometricJacobian(data, J);
  // column 1: 2 [z x (o_tool - o) + h z; z] = 2 [(0,0,1) x (-1,1,0) + (0,0,0.2); (0,0,1)]
  Vec6 c1;
  c1 << 2 * Vec3(-1, -1, 0.2), 2 * Vec3(0, 0, 1);
  Vec6 c2;
  c2 << 3, 0, 0, 0, 0, 0;
  EXPECT_LE((J.col(0) - c1).norm(), 1e-15);
  EXPECT_LE((J.col(1) - c2).norm(), 1e-15);
}

TEST(Jacobian, RejectsWrongSizes) {
  std::vector<JointSpec> joints(2);
  joints[0].twist << 0, 0, 1, 0, 0, 0;
  joints[1].twist << 0, 1, 0, 0, 0, 1;
  const PoeModel model(joints, Pose{});
  Data data(model);
  Mat6X J(6, 2), K(6, 3);
  EXPECT_THROW(computeJacobians(model, data, VecX::Zero(3)), std::invalid_argument);
  computeJacobians(model, data, VecX::Zero(2));
  EXPECT_THROW(getSpatialJacobian(data, K), std::invalid_argument);
  EXPECT_THROW(getBodyJacobian(data, K), std::invalid_argument);
  EXPECT_THROW(getGeometricJacobian(data, K), std::invalid_argument);
  EXPECT_NO_THROW(getGeometricJacobian(data, J));
}
