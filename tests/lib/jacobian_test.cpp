// Jacobians (jacobian.hpp) against references that do not come from the library's Jacobian code:
//
// 1. Central finite differences of forward kinematics on 1,000 seeded random robots x 3 poses
//    (tests/common/random_robot.hpp: 2-7 joints, revolute/prismatic/helical, scales != 1, offsets, parallel,
//    nearly parallel, collinear, intersecting axes), POE and the D-H form poeToDh(model).model, each
//    Jacobian with its own definition:
//      spatial   V_s = vee((dg/dx_i) g^-1)            [w; v], base frame
//      body      V_b = vee(g^-1 (dg/dx_i))            [w; v], tool frame
//      geometric [d p_tool/dx_i; vee((dR/dx_i) R^T)]  [v; w], base frame
//    g(x) is evaluated by this file (product of exponentials / D-H rows, written here from
//    docs/conventions.md) in long double, and checked to equal the library's forward kinematics to
//    double rounding, so the Jacobians are the derivatives of the library's FK.
// 2. Hand-derived columns of small robots (planar RR with offsets and a scale, RP with a scaled
//    prismatic joint, a helical joint, a spatial RR), written from the geometry.
// 3. The conversion functions against the finite-difference references of the Jacobians they convert.
// The compute-then-get contract, the conversions' inverse pairs and aliasing, and the size checks are in
// jacobian_contract_test.cpp.
//
// Step and tolerance of the finite differences. Errors are per unit joint *motion* x = scale (q + offset)
// (column / scale_i), angular rows in rad, linear rows relative to the length scale R of the
// configuration (max of L, |p_tool|, |o_i|; for D-H also the table's max |d|, |a|), prismatic columns
// per slide of R. The step is h in x for revolute/helical joints and h R for prismatic ones.
//   - truncation: (g(x+h) - g(x-h)) / 2h = g' + h^2/6 g''' + O(h^4). For a joint of unit twist xi,
//     g''' g^-1 = hat(xi_s)^3 and g^-1 g''' = hat(xi_b)^3; with |w| = 1, hat(xi)^3 = [-hat(w), hat(w)^2 v]
//     and |hat(w)^2 v| = distance of the axis from the origin of the frame (base or tool) <= 2R (a pitch
//     is along w and drops out); for the tool position, |p'''| = distance of the tool from the axis
//     <= 2R. Prismatic: g is affine in x, no truncation. So truncation <= h^2/6 (rad) and h^2/3 (/R).
//   - rounding of g: n <= 7 factors plus base/tool, each a few eps relative (positions eps R):
//     |dg| <= 36 eps_ld R, hence <= 36 eps_ld / h after the difference (the step itself is exact:
//     the difference is divided by the computed (x+h) - (x-h), Sterbenz).
//   - the library's double rounding (and its double x against the long double one): ~64 eps = 1.4e-14.
//   With long double (x86: eps_ld = 1.08e-19) the step h = 2^-19 = 1.9e-6 (near the minimum of
//   h^2/3 + 36 eps_ld / h) predicts at most 1.2e-12 + 2.1e-12 + 1.4e-14 = 3.3e-12; the bound is three
//   times that, 9.8e-12. Measured: angular 7.0e-13 (h^2/6 = 6.1e-13), linear 1.2e-12 (h^2/3 = 1.2e-12):
//   the truncation term, as predicted. (In double the same formula picks h = 2^-15 and a bound of
//   1.7e-9, the accuracy a double finite difference can reach: eps / h ~ 1e-11 times the chain's factor;
//   long double makes the check two orders of magnitude tighter. Where long double is double, e.g. MSVC,
//   fdStep/fdBound give those double values.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "jacobian_helpers.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"
#include "random_robot.hpp"

using namespace lowpair;

namespace {

using namespace jacobian_helpers;

using Real = long double;
using Mat4r = Eigen::Matrix<Real, 4, 4>;
using Mat3r = Eigen::Matrix<Real, 3, 3>;
using Vec3r = Eigen::Matrix<Real, 3, 1>;
using VecXr = Eigen::Matrix<Real, Eigen::Dynamic, 1>;

constexpr Real kEpsLd = std::numeric_limits<Real>::epsilon();

// ---- the finite-difference step and bound (see the header) -------------------------------------------
constexpr double kRoundingFactor = 36.0;  // |dg| <= 36 eps R for a chain of <= 9 factors
double fdStep() {
  const double h_opt = std::cbrt(1.5 * kRoundingFactor * static_cast<double>(kEpsLd));
  return std::ldexp(1.0, static_cast<int>(std::lround(std::log2(h_opt))));
}
double fdPredicted() {
  const double h = fdStep();
  return h * h / 3.0 + kRoundingFactor * static_cast<double>(kEpsLd) / h + 64.0 * kEpsD;
}
double fdBound() { return 3.0 * fdPredicted(); }

// ---- forward kinematics of this file, long double ------------------------------------------------------
Mat3r skew(const Vec3r& w) {
  Mat3r W;
  W << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return W;
}
Vec3r veeSkew(const Mat3r& M) {  // w of the antisymmetric part
  return Vec3r(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1)) / 2;
}
Mat4r matrixOf(const Pose& T) {
  Mat4r M = Mat4r::Identity();
  M.topLeftCorner<3, 3>() = T.R.cast<Real>();
  M.topRightCorner<3, 1>() = T.p.cast<Real>();
  return M;
}
Mat4r inverseOf(const Mat4r& G) {
  Mat4r M = Mat4r::Identity();
  M.topLeftCorner<3, 3>() = G.topLeftCorner<3, 3>().transpose();
  M.topRightCorner<3, 1>() = -(G.topLeftCorner<3, 3>().transpose() * G.topRightCorner<3, 1>());
  return M;
}

// exp(xi_bar x) of a normalized joint (conventions.md, Wu eq. 2): R = I + sin x W + (1 - cos x) W^2,
// p = (I - R)(w x v) + h x w; prismatic: translation v x.
Mat4r jointExponential(const Joint& j, Real x) {
  Mat4r E = Mat4r::Identity();
  const Vec3r w = j.twist.head<3>().cast<Real>(), v = j.twist.tail<3>().cast<Real>();
  if (j.type == JointType::Prismatic) {
    E.topRightCorner<3, 1>() = v * x;
    return E;
  }
  const Mat3r W = skew(w);
  const Real s = std::sin(x / 2);
  const Mat3r R = Mat3r::Identity() + std::sin(x) * W + 2 * s * s * W * W;
  E.topLeftCorner<3, 3>() = R;
  E.topRightCorner<3, 1>() = (Mat3r::Identity() - R) * w.cross(v) + static_cast<Real>(j.pitch) * x * w;
  return E;
}

// g(x) = exp(xi_1 x_1) ... exp(xi_n x_n) exp(xi_T) (eq. 5) in the joint motions x.
Mat4r poeFk(const PoeModel& model, const VecXr& x) {
  Mat4r G = Mat4r::Identity();
  for (int i = 0; i < model.dof(); ++i) G = G * jointExponential(model.joint(i), x[i]);
  return G * matrixOf(model.toolPose());
}

// A(theta, d, alpha, a) = Rz(theta) Tz(d) Rx(alpha) Tx(a) (eq. 9).
Mat4r dhRow(Real theta, Real d, Real alpha, Real a) {
  const Real ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha), sa = std::sin(alpha);
  Mat4r A;
  A << ct, -st * ca, st * sa, a * ct,  //
      st, ct * ca, -ct * sa, a * st,   //
      0, sa, ca, d,                    //
      0, 0, 0, 1;
  return A;
}

// A Hayati row's extra turn Ry(beta) (docs/conventions.md "Hayati rows"); the identity in a standard row.
Mat4r hayatiTurn(const DhParams& row) {
  Mat4r Y = Mat4r::Identity();
  if (!row.hayati()) return Y;
  const Real cb = std::cos(Real(row.beta)), sb = std::sin(Real(row.beta));
  Y(0, 0) = cb, Y(0, 2) = sb, Y(2, 0) = -sb, Y(2, 2) = cb;
  return Y;
}

// H(x) = A(base) prod_i [Rz(j x_i) Tz(k x_i) A(link_i)] Rz(theta_T) Tz(d_T) (eq. 10) in the joint motions x,
// each A(row) of a Hayati row followed by Ry(beta).
Mat4r dhFk(const DhModel& model, const VecXr& x) {
  const DhParams& b = model.base();
  Mat4r G = dhRow(b.theta, b.d, b.alpha, b.a) * hayatiTurn(b);
  for (int i = 0; i < model.dof(); ++i) {
    const DhJoint& j = model.joint(i);
    const DhParams& l = j.link;
    G = G * dhRow(l.theta + j.turnRate() * x[i], l.d + j.slideRate() * x[i], l.alpha, l.a) * hayatiTurn(l);
  }
  return G * dhRow(model.toolTheta(), model.toolD(), 0, 0);
}

template <class Model>
VecXr motions(const Model& model, const VecX& q) {
  VecXr x(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    const JointMotion& m = model.joint(i);
    x[i] = static_cast<Real>(m.scale) * (static_cast<Real>(q[i]) + static_cast<Real>(m.offset));
  }
  return x;
}

// ---- finite-difference Jacobians, d/dx (per unit joint motion) -----------------------------------------
struct Reference {
  Mat6X spatial, body, geometric;
  Pose T;  // g(x) rounded to double
};

// step[i]: h for revolute/helical joints (rad), h R for prismatic ones (length), so that both have the
// relative truncation and rounding errors of the header.
template <class Fk>
Reference finiteDifferences(const Fk& fk, const VecXr& x, const VecX& step) {
  const int n = static_cast<int>(x.size());
  Reference ref{Mat6X(6, n), Mat6X(6, n), Mat6X(6, n), Pose{}};
  const Mat4r G = fk(x), Ginv = inverseOf(G);
  ref.T.R = G.topLeftCorner<3, 3>().cast<double>();
  ref.T.p = G.topRightCorner<3, 1>().cast<double>();
  for (int i = 0; i < n; ++i) {
    const Real h = step[i];
    VecXr xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    const Mat4r dG = (fk(xp) - fk(xm)) / (xp[i] - xm[i]);
    const Mat4r S = dG * Ginv;  // hat(V_s)
    const Mat4r B = Ginv * dG;  // hat(V_b)
    ref.spatial.col(i) << veeSkew(S.topLeftCorner<3, 3>()).cast<double>(), S.topRightCorner<3, 1>().cast<double>();
    ref.body.col(i) << veeSkew(B.topLeftCorner<3, 3>()).cast<double>(), B.topRightCorner<3, 1>().cast<double>();
    // geometric: [dp/dx; vee(dR/dx R^T)], and dR R^T is the rotation block of S
    ref.geometric.col(i) << dG.topRightCorner<3, 1>().cast<double>(), ref.spatial.col(i).head<3>();
  }
  return ref;
}

// ---- dimensionless errors -------------------------------------------------------------------------------

// Worst error per unit joint motion: column i of J (d/dq) divided by scale_i against ref (d/dx);
// revolute/helical columns: angular in rad, linear / R; prismatic: angular * R, linear as is. Keeps the
// place of the worst one for the failure message.
struct Worst {
  double angular = 0.0, linear = 0.0;
  std::string where;
  double max() const { return std::max(angular, linear); }
  void add(double a, double l, const std::string& at) {
    a = finiteOrInf(a);
    l = finiteOrInf(l);
    if (std::max(a, l) > max() || (where.empty() && !at.empty())) where = at;
    angular = std::max(angular, a);
    linear = std::max(linear, l);
  }
  void add(const Mat6X& J, const Mat6X& ref, const std::vector<JointMotion>& joints, double R, bool angular_first,
           const std::string& at) {
    for (size_t i = 0; i < joints.size(); ++i) {
      const Eigen::Index c = static_cast<Eigen::Index>(i);
      const bool prismatic = joints[i].type == JointType::Prismatic;
      const Vec6 e = J.col(c) / joints[i].scale - ref.col(c);
      const double ea = (angular_first ? e.head<3>() : e.tail<3>()).norm();
      const double el = (angular_first ? e.tail<3>() : e.head<3>()).norm();
      add(prismatic ? ea * R : ea, prismatic ? el : el / R, at + " column " + std::to_string(i + 1));
    }
  }
};

template <class Model>
std::vector<JointMotion> motionsOf(const Model& model) {
  std::vector<JointMotion> m;
  for (int i = 0; i < model.dof(); ++i) m.push_back(model.joint(i));
  return m;
}
VecX steps(const std::vector<JointMotion>& joints, double h, double R) {
  VecX step(static_cast<Eigen::Index>(joints.size()));
  for (size_t i = 0; i < joints.size(); ++i) {
    step[static_cast<Eigen::Index>(i)] = joints[i].type == JointType::Prismatic ? h * R : h;
  }
  return step;
}
// scale 1 versions, for comparisons of d/dx with d/dx
std::vector<JointMotion> unitScale(std::vector<JointMotion> m) {
  for (JointMotion& j : m) j.scale = 1.0;
  return m;
}

}  // namespace

TEST(Jacobian, FiniteDifferencesOnThousandRandomRobots) {
  const double h = fdStep(), bound = fdBound();
  std::mt19937_64 rng(19840924);
  Worst poe_s, poe_b, poe_g, dh_s, dh_b, dh_g, conv_sb, conv_bs, conv_sg, conv_gs, dh_vs_poe, fk_poe, fk_dh;
  int configurations = 0, ill_conditioned = 0;
  for (int r = 0; r < 1000; ++r) {
    const lowpair_test::RandomRobot robot = lowpair_test::randomRobot(rng);
    const PoeModel& model = robot.model;
    const DhConversion c = poeToDh(model);
    const double dh_scale = tableScale(c.model);
    const std::vector<JointMotion> poe_joints = motionsOf(model), dh_joints = motionsOf(c.model);
    const std::vector<JointMotion> per_motion = unitScale(poe_joints);
    Data pd(model), dd(c.model);
    Mat6X X(6, model.dof());
    for (int k = 0; k < 3; ++k) {
      ++configurations;
      const VecX q = lowpair_test::randomConfiguration(model, rng);
      const std::string at = std::string(lowpair_test::geometryName(robot.geometry)) + " robot " +
                             std::to_string(r) + " pose " + std::to_string(k);
      const Jacobians P = libraryJacobians(model, pd, q);
      const double R = lengthScale(model.lengthScale(), pd);
      const Reference fd = finiteDifferences([&](const VecXr& x) { return poeFk(model, x); }, motions(model, q),
                                             steps(poe_joints, h, R));
      // the reference FK is the library's FK (to its rounding, 64 n eps as in kinematics_test)
      const double e_fk = poseError(pd.T_base_tool, fd.T, R);
      fk_poe.add(e_fk, e_fk, at);
      poe_s.add(P.spatial, fd.spatial, poe_joints, R, true, at);
      poe_b.add(P.body, fd.body, poe_joints, R, true, at);
      poe_g.add(P.geometric, fd.geometric, poe_joints, R, false, at);

      // the conversion functions map one independent reference onto another (both d/dx: scale 1)
      spatialToBody(fd.T, fd.spatial, X);
      conv_sb.add(X, fd.body, per_motion, R, true, at);
      bodyToSpatial(fd.T, fd.body, X);
      conv_bs.add(X, fd.spatial, per_motion, R, true, at);
      spatialToGeometric(fd.T, fd.spatial, X);
      conv_sg.add(X, fd.geometric, per_motion, R, false, at);
      geometricToSpatial(fd.T, fd.geometric, X);
      conv_gs.add(X, fd.spatial, per_motion, R, true, at);

      // D-H chain of the same robot, same joint variables. Its rounding scale is the table's
      // R_dh = max(R, max |d|, max |a|) (conversion.md): its FK and Jacobian are exact to eps R_dh.
      const Jacobians D = libraryJacobians(c.model, dd, q);
      const double R_dh = std::max({R, dh_scale, lengthScale(model.lengthScale(), dd)});
      dh_vs_poe.add(D.spatial, P.spatial, unitScale(dh_joints), R_dh, true, at);
      // Nearly parallel axes give tables with |d| up to 1e16 L. Evaluated in double, their FK (hence
      // their Jacobian) carries rounding eps R_dh, up to ~L itself, and a finite difference of any
      // precision would be compared against that: a bound relative to R_dh would allow errors larger
      // than the Jacobian. Such tables (over the library's kIllConditioned = 1e3 L warning) are covered
      // by the comparison with the POE Jacobian just above, which is itself checked against FD.
      if (dh_scale > kIllConditioned * model.lengthScale()) {
        ++ill_conditioned;
        continue;
      }
      const Reference fd_dh = finiteDifferences([&](const VecXr& x) { return dhFk(c.model, x); },
                                                motions(c.model, q), steps(dh_joints, h, R_dh));
      const double e_fk_dh = poseError(dd.T_base_tool, fd_dh.T, R_dh);
      fk_dh.add(e_fk_dh, e_fk_dh, at);
      dh_s.add(D.spatial, fd_dh.spatial, dh_joints, R_dh, true, at);
      dh_b.add(D.body, fd_dh.body, dh_joints, R_dh, true, at);
      dh_g.add(D.geometric, fd_dh.geometric, dh_joints, R_dh, false, at);
    }
  }
  std::printf("1000 robots, %d configurations (%d with an ill-conditioned D-H table: D-H checked against POE "
              "only)\nstep h = %.3g, predicted <= %.3g, bound %.3g; worst error per unit joint motion:\n",
              configurations, ill_conditioned, h, fdPredicted(), bound);
  std::printf("%-34s %10s %11s %10s\n", "", "angular", "linear / R", "bound");
  // the D-H and POE Jacobians are both double evaluations of the same lines: rounding, measured ~1e-13;
  // 1e-12 is the validate tolerance. FK: 64 n eps with n <= 9 factors.
  const double fk_bound = 64 * 9 * kEpsD;
  const struct {
    const char* name;
    const Worst& w;
    double bound;
  } rows[] = {{"POE spatial vs FD", poe_s, bound},
              {"POE body vs FD", poe_b, bound},
              {"POE geometric vs FD", poe_g, bound},
              {"D-H spatial vs FD", dh_s, bound},
              {"D-H body vs FD", dh_b, bound},
              {"D-H geometric vs FD", dh_g, bound},
              {"spatialToBody(FD) vs FD", conv_sb, bound},
              {"bodyToSpatial(FD) vs FD", conv_bs, bound},
              {"spatialToGeometric(FD) vs FD", conv_sg, bound},
              {"geometricToSpatial(FD) vs FD", conv_gs, bound},
              {"D-H spatial vs POE (/ R_dh)", dh_vs_poe, 1e-12},
              {"reference FK vs library FK", fk_poe, fk_bound},
              {"reference D-H FK vs library", fk_dh, fk_bound}};
  for (const auto& row : rows) {
    std::printf("%-34s %10.3g %11.3g %10.3g\n", row.name, row.w.angular, row.w.linear, row.bound);
    EXPECT_LE(row.w.max(), row.bound) << row.name << ", worst at " << row.w.where;
  }
  EXPECT_LT(ill_conditioned, configurations / 4);  // most configurations do check the D-H Jacobians by FD
}

// ---- hand-derived columns -------------------------------------------------------------------------------

namespace {

Vec6 col(double a, double b, double c, double d, double e, double f) {
  Vec6 v;
  v << a, b, c, d, e, f;
  return v;
}

Mat6X columns(std::initializer_list<Vec6> cols) {
  Mat6X J(6, static_cast<Eigen::Index>(cols.size()));
  Eigen::Index i = 0;
  for (const Vec6& c : cols) J.col(i++) = c;
  return J;
}

VecX vec(std::initializer_list<double> values) {
  VecX q(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double x : values) q[i++] = x;
  return q;
}

// The expected spatial, body and geometric Jacobians (d/dq) of a small robot, in both the POE model and
// its D-H form. Entries are O(1) (lengths 0.7-3.5, scales <= 3), so the error is the rounding of a few
// operations on them, ~1e-15; the bound 1e-14 leaves a tenfold margin. Returns the worst error.
template <class Model>
double expectJacobians(const Model& model, const VecX& q, const Jacobians& expected, const std::string& what) {
  Data data(model);
  const Jacobians J = libraryJacobians(model, data, q);
  const double tol = 1e-14;
  const double es = finiteOrInf((J.spatial - expected.spatial).cwiseAbs().maxCoeff());
  const double eb = finiteOrInf((J.body - expected.body).cwiseAbs().maxCoeff());
  const double eg = finiteOrInf((J.geometric - expected.geometric).cwiseAbs().maxCoeff());
  EXPECT_LE(es, tol) << what << " spatial\n" << J.spatial << "\nexpected\n" << expected.spatial;
  EXPECT_LE(eb, tol) << what << " body\n" << J.body << "\nexpected\n" << expected.body;
  EXPECT_LE(eg, tol) << what << " geometric\n" << J.geometric << "\nexpected\n" << expected.geometric;
  return std::max({es, eb, eg});
}

double expectPoeAndDh(const PoeModel& model, const VecX& q, const Jacobians& expected, const std::string& what) {
  const double e = expectJacobians(model, q, expected, what + " (POE)");
  return std::max(e, expectJacobians(poeToDh(model).model, q, expected, what + " (poeToDh)"));
}

void printWorst(const char* what, double worst) { std::printf("%s: worst |J - expected| %.3g\n", what, worst); }

}  // namespace

// Planar RR arm: joint 1 about z through the origin (offset 0.1), joint 2 about z through (l1, 0, 0)
// (twist scaled by 2, offset -0.2), tool at (l1 + l2, 0, 0) with the base orientation.
// Motions x1 = q1 + 0.1, x2 = 2 (q2 - 0.2); tool p = l1 (c1, s1) + l2 (c12, s12), R = Rz(x1 + x2).
//   geometric: col1 = [z x p; z], col2 = 2 [z x (p - o2); z] = 2 [(-l2 s12, l2 c12, 0); z]
//   spatial:   col1 = [z; 0] (axis through the origin), col2 = 2 [z; o2 x z] = 2 [z; (l1 s1, -l1 c1, 0)]
//   body:      col1 = [z; R^T (z x p)] = [z; (l1 s2, l1 c2 + l2, 0)], col2 = 2 [z; (0, l2, 0)]
TEST(Jacobian, PlanarRRWithOffsetsAndScale) {
  const double l1 = 2.0, l2 = 1.5;
  std::vector<JointSpec> joints(2);
  joints[0].twist << 0, 0, 1, 0, 0, 0;
  joints[0].offset = 0.1;
  joints[1].twist << 0, 0, 2, 2 * Vec3(l1, 0, 0).cross(Vec3(0, 0, 1));  // [w; o x w], scaled by 2
  joints[1].offset = -0.2;
  Pose tool;
  tool.p << l1 + l2, 0, 0;
  const PoeModel model(joints, tool);

  // the same arm as a D-H table written by hand: A(x1, 0, 0, l1) A(x2, 0, 0, l2)
  std::vector<DhJoint> dh(2);
  dh[0].offset = 0.1;
  dh[0].link = {0, 0, 0, l1};
  dh[1].scale = 2.0;
  dh[1].offset = -0.2;
  dh[1].link = {0, 0, 0, l2};
  const DhModel dh_model(DhParams{}, dh, 0.0, 0.0);
  double worst = 0.0;

  for (const VecX& q : {vec({0.3, -0.7}), vec({-2.5, 1.9}), vec({-0.1, 0.2})}) {
    const double x1 = q[0] + 0.1, x2 = 2 * (q[1] - 0.2);
    const double c1 = std::cos(x1), s1 = std::sin(x1), c2 = std::cos(x2), s2 = std::sin(x2);
    const double c12 = std::cos(x1 + x2), s12 = std::sin(x1 + x2);
    const double px = l1 * c1 + l2 * c12, py = l1 * s1 + l2 * s12;
    Jacobians e;
    e.geometric = columns({col(-py, px, 0, 0, 0, 1), 2 * col(-l2 * s12, l2 * c12, 0, 0, 0, 1)});
    e.spatial = columns({col(0, 0, 1, 0, 0, 0), 2 * col(0, 0, 1, l1 * s1, -l1 * c1, 0)});
    e.body = columns({col(0, 0, 1, l1 * s2, l1 * c2 + l2, 0), 2 * col(0, 0, 1, 0, l2, 0)});
    worst = std::max(worst, expectPoeAndDh(model, q, e, "RR"));
    worst = std::max(worst, expectJacobians(dh_model, q, e, "RR (hand-written D-H)"));
  }
  printWorst("planar RR", worst);
}

// RP arm: joint 1 about z through the origin, joint 2 prismatic along x (twist [0; 3 x]: scale 3,
// offset 0.5), tool at (l, 0, 0). Motion x2 = 3 (q2 + 0.5); the tool is at r (c1, s1, 0), r = l + x2,
// with R = Rz(q1).
//   geometric: col1 = [(-r s1, r c1, 0); z], col2 = 3 [(c1, s1, 0); 0]
//   spatial:   col1 = [z; 0],                col2 = 3 [0; (c1, s1, 0)]
//   body:      col1 = [z; (0, r, 0)],        col2 = 3 [0; (1, 0, 0)]
TEST(Jacobian, RevolutePrismaticWithScale) {
  const double l = 1.2;
  std::vector<JointSpec> joints(2);
  joints[0].twist << 0, 0, 1, 0, 0, 0;
  joints[1].twist << 0, 0, 0, 3, 0, 0;
  joints[1].offset = 0.5;
  Pose tool;
  tool.p << l, 0, 0;
  const PoeModel model(joints, tool);
  double worst = 0.0;
  for (const VecX& q : {vec({0.4, 0.25}), vec({2.8, -1.1}), vec({-1.3, 0.0})}) {
    const double c1 = std::cos(q[0]), s1 = std::sin(q[0]), r = l + 3 * (q[1] + 0.5);
    Jacobians e;
    e.geometric = columns({col(-r * s1, r * c1, 0, 0, 0, 1), 3 * col(c1, s1, 0, 0, 0, 0)});
    e.spatial = columns({col(0, 0, 1, 0, 0, 0), 3 * col(0, 0, 0, c1, s1, 0)});
    e.body = columns({col(0, 0, 1, 0, r, 0), 3 * col(0, 0, 0, 1, 0, 0)});
    worst = std::max(worst, expectPoeAndDh(model, q, e, "RP"));
  }
  printWorst("RP", worst);
}

// One helical joint about z through c = (1, 0, 0), pitch 0.2 length/rad, scale 2 (twist
// 2 [z; c x z + 0.2 z] = [0 0 2; 0 -2 0.4]), offset 0.3; tool at (0, 1, 0). Motion x = 2 (q + 0.3):
// the tool turns by x about the axis and rises by 0.2 x, p = c + Rz(x) (-1, 1, 0) + 0.2 x z, R = Rz(x).
//   geometric: 2 [z x (p - c) + 0.2 z; z] = 2 [(-cos x + sin x, -sin x - cos x, 0.2); z]
//   spatial:   2 [z; c x z + 0.2 z] = 2 [z; (0, -1, 0.2)]   (constant: the first joint)
//   body:      2 [R^T z; R^T (geometric linear)] = 2 [z; (-1, -1, 0.2)]
TEST(Jacobian, HelicalPitchEntersTheLinearPart) {
  std::vector<JointSpec> joints(1);
  joints[0].type = JointType::Helical;
  joints[0].twist << 0, 0, 2, 0, -2, 0.4;
  joints[0].offset = 0.3;
  Pose tool;
  tool.p << 0, 1, 0;
  const PoeModel model(joints, tool);
  ASSERT_EQ(model.joint(0).type, JointType::Helical);
  double worst = 0.0;
  for (const VecX& q : {vec({0.0}), vec({1.7}), vec({-2.9})}) {
    const double x = 2 * (q[0] + 0.3), c = std::cos(x), s = std::sin(x);
    Jacobians e;
    e.geometric = columns({2 * col(-c + s, -s - c, 0.2, 0, 0, 1)});
    e.spatial = columns({2 * col(0, 0, 1, 0, -1, 0.2)});
    e.body = columns({2 * col(0, 0, 1, -1, -1, 0.2)});
    worst = std::max(worst, expectPoeAndDh(model, q, e, "helical"));
  }
  printWorst("helical", worst);
}

// Spatial RR: joint 1 about z through the origin, joint 2 about y through o2 = (0, 0, a), tool at
// (b, 0, a). At q: z2 = (-s1, c1, 0), p = o2 + Rz(q1) Ry(q2) (b, 0, 0) = (b c2 c1, b c2 s1, a - b s2),
// R = Rz(q1) Ry(q2).
//   geometric: col1 = [z x p; z] = [(-b c2 s1, b c2 c1, 0); z]
//              col2 = [z2 x (p - o2); z2] = [(-b s2 c1, -b s2 s1, -b c2); (-s1, c1, 0)]
//   spatial:   col1 = [z; 0], col2 = [z2; o2 x z2] = [(-s1, c1, 0); (-a c1, -a s1, 0)]
//   body:      col1 = [R^T z; R^T (z x p)] = [(-s2, 0, c2); (0, b c2, 0)]
//              col2 = [R^T z2; R^T (z2 x (p - o2))] = [(0, 1, 0); (0, 0, -b)]
TEST(Jacobian, SpatialRRWithPerpendicularAxes) {
  const double a = 0.7, b = 1.3;
  std::vector<JointSpec> joints(2);
  joints[0].twist << 0, 0, 1, 0, 0, 0;
  joints[1].twist << 0, 1, 0, -a, 0, 0;  // o2 x y = (0, 0, a) x (0, 1, 0) = (-a, 0, 0)
  Pose tool;
  tool.p << b, 0, a;
  const PoeModel model(joints, tool);
  double worst = 0.0;
  for (const VecX& q : {vec({0.4, -1.1}), vec({-2.2, 2.6}), vec({3.0, 0.05})}) {
    const double c1 = std::cos(q[0]), s1 = std::sin(q[0]), c2 = std::cos(q[1]), s2 = std::sin(q[1]);
    Jacobians e;
    e.geometric = columns({col(-b * c2 * s1, b * c2 * c1, 0, 0, 0, 1),
                           col(-b * s2 * c1, -b * s2 * s1, -b * c2, -s1, c1, 0)});
    e.spatial = columns({col(0, 0, 1, 0, 0, 0), col(-s1, c1, 0, -a * c1, -a * s1, 0)});
    e.body = columns({col(-s2, 0, c2, 0, b * c2, 0), col(0, 1, 0, 0, 0, -b)});
    worst = std::max(worst, expectPoeAndDh(model, q, e, "spatial RR"));
  }
  printWorst("spatial RR", worst);
}
