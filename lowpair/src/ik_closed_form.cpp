#include "lowpair/ik_closed_form.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "check.hpp"
#include "ik_ranges.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

namespace {

// A subproblem leaves an angle free when the point (direction) it turns lies within sqrt(eps) L (rad) of the
// axis: the angle is then known to no better than eps / sqrt(eps) = sqrt(eps) rad, and moves the point by at
// most eps L whatever it is, so it is reported as free (motion 0, flag singular); two roots closer than that
// are a double root (singular too).
constexpr double kFree = 1.4901161193847656e-08;  // sqrt(eps) = 2^-26
// A discriminant computed from squared lengths of size S^2 carries a rounding error of a few eps S^2: down to
// -64 eps S^2 it is a double root (the elbow stretched), below it the target is out of reach.
constexpr double kRootRounding = 64.0 * kEps;

// ---- geometry of lines --------------------------------------------------------------------------------------

Vec3 linePoint(const Joint& j) { return j.axis().cross(j.moment()); }  // the foot of the origin (revolute, helical)

double distanceToLine(const Vec3& x, const Vec3& w, const Vec3& p) {
  const Vec3 d = x - p;
  return (d - w * w.dot(d)).norm();
}

// The point nearest to the lines (w_k, p_k) in the least-squares sense: sum_k (I - w_k w_k^T)(x - p_k) = 0.
template <int N>
Vec3 nearestPoint(const std::array<const Joint*, N>& joints) {
  Mat3 A = Mat3::Zero();
  Vec3 b = Vec3::Zero();
  for (const Joint* j : joints) {
    const Mat3 P = Mat3::Identity() - j->axis() * j->axis().transpose();
    A += P;
    b += P * linePoint(*j);
  }
  return A.ldlt().solve(b);
}

bool revoluteLike(const Joint& j, double tolerance, double L) {
  return j.type == JointType::Revolute || (j.type == JointType::Helical && std::abs(j.pitch) <= tolerance * L);
}

double pitchDeviation(const Joint& j, double L) { return j.type == JointType::Helical ? std::abs(j.pitch) / L : 0.0; }

// ---- detection ----------------------------------------------------------------------------------------------

struct Detection {
  double deviation = 0.0;
  char reason[200] = "";
  bool fail(const char* text, double value) {
    std::snprintf(reason, sizeof reason, text, value);
    return false;
  }
  // joint i (0-based) is not revolute, nor helical with a pitch within the tolerance
  bool notRevolute(const Joint& j, int i, double L) {
    if (j.type == JointType::Helical) {
      std::snprintf(reason, sizeof reason, "joint %d is helical (pitch %.3g L)", i + 1, j.pitch / L);
    } else {
      std::snprintf(reason, sizeof reason, "joint %d is prismatic", i + 1);
    }
    return false;
  }
};

// Lines i and j (0-based) meet within the tolerance and are not parallel: their nearest point.
bool meet(const PoeModel& model, int i, int j, double tolerance, Detection& d, Vec3& point) {
  const Joint &a = model.joint(i), &b = model.joint(j);
  const double sine = a.axis().cross(b.axis()).norm();
  char text[120];
  if (sine < kClosedFormSeparation) {
    std::snprintf(text, sizeof text, "axes %d and %d are parallel (sine %%.3g)", i + 1, j + 1);
    return d.fail(text, sine);
  }
  point = nearestPoint<2>({&a, &b});
  const double L = model.lengthScale();
  const double miss = std::max(distanceToLine(point, a.axis(), linePoint(a)), distanceToLine(point, b.axis(), linePoint(b))) / L;
  d.deviation = std::max(d.deviation, 2.0 * miss);
  if (2.0 * miss > tolerance) {
    std::snprintf(text, sizeof text, "axes %d and %d miss each other by %%.3g L", i + 1, j + 1);
    return d.fail(text, 2.0 * miss);
  }
  return true;
}

bool detectSphericalWrist(const PoeModel& model, double tolerance, ClosedFormStructure& s, Detection& d) {
  const double L = model.lengthScale();
  for (int i : {0, 1, 3, 4, 5}) {
    if (!revoluteLike(model.joint(i), tolerance, L)) return d.notRevolute(model.joint(i), i, L);
    d.deviation = std::max(d.deviation, pitchDeviation(model.joint(i), L));
  }
  const Joint& j3 = model.joint(2);
  s.prismatic_elbow = j3.type == JointType::Prismatic;
  if (!s.prismatic_elbow && !revoluteLike(j3, tolerance, L)) return d.notRevolute(j3, 2, L);
  if (!s.prismatic_elbow) d.deviation = std::max(d.deviation, pitchDeviation(j3, L));
  Vec3 unused;
  if (!meet(model, 0, 1, tolerance, d, s.shoulder) || !meet(model, 3, 4, tolerance, d, unused) ||
      !meet(model, 4, 5, tolerance, d, unused)) {
    return false;
  }
  s.wrist = nearestPoint<3>({&model.joint(3), &model.joint(4), &model.joint(5)});
  double miss = 0.0;
  for (int i = 3; i < 6; ++i) miss = std::max(miss, distanceToLine(s.wrist, model.joint(i).axis(), linePoint(model.joint(i))) / L);
  d.deviation = std::max(d.deviation, miss);
  if (miss > tolerance) return d.fail("axes 4, 5, 6 miss a common point by %.3g L", miss);
  if (!s.prismatic_elbow) {
    const double near = std::min(distanceToLine(s.shoulder, j3.axis(), linePoint(j3)), distanceToLine(s.wrist, j3.axis(), linePoint(j3))) / L;
    if (near < kClosedFormSeparation) return d.fail("axis 3 passes %.3g L from the shoulder or wrist point", near);
  }
  if (d.deviation > tolerance) return d.fail("a helical pitch of %.3g L", d.deviation);
  for (int i = 0; i < 6; ++i) {
    const Joint& j = model.joint(i);
    s.w[static_cast<size_t>(i)] = i == 2 && s.prismatic_elbow ? j.moment() : j.axis();
    s.p[static_cast<size_t>(i)] = i < 2 ? s.shoulder : i > 2 ? s.wrist : s.prismatic_elbow ? Vec3::Zero() : linePoint(j);
  }
  return true;
}

bool detectParallelTriple(const PoeModel& model, double tolerance, ClosedFormStructure& s, Detection& d) {
  const double L = model.lengthScale();
  for (int i = 0; i < 6; ++i) {
    if (!revoluteLike(model.joint(i), tolerance, L)) return d.notRevolute(model.joint(i), i, L);
    d.deviation = std::max(d.deviation, pitchDeviation(model.joint(i), L));
  }
  const Vec3 w2 = model.joint(1).axis();
  Vec3 u = w2;
  for (int i : {2, 3}) {
    const Vec3 w = model.joint(i).axis();
    const double sine = w.cross(w2).norm();
    d.deviation = std::max(d.deviation, sine);
    if (sine > tolerance) return d.fail(i == 2 ? "axes 2 and 3 are %.3g rad from parallel" : "axes 2 and 4 are %.3g rad from parallel", sine);
    u += w.dot(w2) > 0.0 ? w : Vec3(-w);
  }
  u.normalize();
  for (int i : {0, 4}) {
    const double sine = model.joint(i).axis().cross(u).norm();
    if (sine < kClosedFormSeparation) return d.fail(i == 0 ? "axis 1 is parallel to axes 2-4 (sine %.3g)" : "axis 5 is parallel to axes 2-4 (sine %.3g)", sine);
  }
  if (!meet(model, 4, 5, tolerance, d, s.wrist)) return false;
  for (int i : {1, 3}) {  // SP3 about axis 3 turns a point of axis 4 to a distance from a point of axis 2
    const double apart = distanceToLine(linePoint(model.joint(i)), u, linePoint(model.joint(2))) / L;
    if (apart < kClosedFormSeparation) return d.fail(i == 1 ? "axes 2 and 3 are %.3g L apart" : "axes 3 and 4 are %.3g L apart", apart);
  }
  if (d.deviation > tolerance) return d.fail("a helical pitch of %.3g L", d.deviation);
  for (int i = 0; i < 6; ++i) {
    const Joint& j = model.joint(i);
    const bool parallel = i >= 1 && i <= 3;
    s.w[static_cast<size_t>(i)] = parallel ? (j.axis().dot(u) > 0.0 ? u : Vec3(-u)) : j.axis();
    s.p[static_cast<size_t>(i)] = i >= 4 ? s.wrist : linePoint(j);
  }
  return true;
}

// ---- the subproblems on the projection ----------------------------------------------------------------------

// The rigid motion of joint i of the projection by motion x: a turn about its line, or a slide.
Pose jointPose(const ClosedFormStructure& s, int i, double x) {
  const Vec3& w = s.w[static_cast<size_t>(i)];
  Pose T;
  if (i == 2 && s.prismatic_elbow) {
    T.p = x * w;
    return T;
  }
  expUnitTwist(w, s.p[static_cast<size_t>(i)].cross(w), 0.0, x, T);
  return T;
}

struct Angle {
  double theta = 0.0;
  bool free = false;
};

// SP1: the turn about the line (w, r) taking u to v (points; directions with r = 0), `scale` their size.
Angle subproblem1(const Vec3& w, const Vec3& r, const Vec3& u, const Vec3& v, double scale) {
  Vec3 a = u - r, b = v - r;
  a -= w * w.dot(a);
  b -= w * w.dot(b);
  if (a.norm() <= kFree * scale || b.norm() <= kFree * scale) return {0.0, true};
  return {std::atan2(w.dot(a.cross(b)), a.dot(b)), false};
}

struct Roots {
  double theta[2] = {0.0, 0.0};
  int count = 0;
  bool singular = false;  // a double root, or both roots free
};

// A discriminant within the rounding of zero is a double root: its square root would be sqrt(rounding), about
// 1e-7 of the scale, and the roots that far from the true double root (the stretched elbow, the wrist with q5 = 0)
// would miss the target by as much; taken as exactly 0 they are exact to rounding.
bool doubleRoot(double disc, double scale) { return disc <= kRootRounding * scale * scale; }

// How negative a discriminant of the projection may be and still give a (double) root: the rounding, plus, for
// a model that is only nearly of the geometry, the projection's error: a discriminant of terms of size S moves
// by about 2 deviation S^2 when the lines move by deviation L (S <= 2 L), so a target the true model reaches
// near a boundary keeps its candidates, which the refinement then moves onto the true solutions (or drops).
double negativeSlack(const ClosedFormStructure& s) { return kRootRounding + 4.0 * s.deviation; }

// `a cos t + b sin t = c`, terms of size `scale`: t = atan2(b, a) -+ atan2(sqrt(a^2 + b^2 - c^2), c).
Roots cosSin(double a, double b, double c, double scale, double slack) {
  Roots out;
  const double r = std::hypot(a, b);
  if (r <= kFree * scale) {  // no dependence on t: every t or none
    out.count = std::abs(c) <= kFree * scale ? 2 : 0;
    out.singular = true;
    return out;
  }
  const double disc = (r - c) * (r + c);
  if (disc < -slack * scale * scale) return out;
  const double root = doubleRoot(disc, scale) ? 0.0 : std::sqrt(disc);
  const double base = std::atan2(b, a), phi = std::atan2(root, c);
  out.theta[0] = base - phi;
  out.theta[1] = base + phi;
  out.count = 2;
  out.singular = root == 0.0;
  return out;
}

// SP3: turns t about the line (w, r) with |exp(t) p - q| = delta.
Roots subproblem3(const Vec3& w, const Vec3& r, const Vec3& p, const Vec3& q, double delta2, double slack) {
  Vec3 u = p - r, v = q - r;
  const double along = w.dot(u - v);
  u -= w * w.dot(u);
  v -= w * w.dot(v);
  // |R u - v|^2 = |u|^2 + |v|^2 - 2 v.R u, v.R u = cos t (u.v) + sin t w.(u x v)
  const double c = 0.5 * (u.squaredNorm() + v.squaredNorm() - (delta2 - along * along));
  return cosSin(u.dot(v), w.dot(u.cross(v)), c, u.norm() * v.norm() + kFree * (delta2 + along * along), slack);
}

// SP2 on intersecting axes w1, w2 through r: exp(t1 w1) exp(t2 w2) p = q; root k in {0, 1} (-, + out of plane).
struct Pair {
  double t1 = 0.0, t2 = 0.0;
  bool ok = false, singular = false;
};

Pair subproblem2(const Vec3& w1, const Vec3& w2, const Vec3& r, const Vec3& p, const Vec3& q, int k, double scale,
                 double slack) {
  const Vec3 u = p - r, v = q - r, n = w1.cross(w2);
  const double c12 = w1.dot(w2), den = c12 * c12 - 1.0;
  const double alpha = (c12 * w2.dot(u) - w1.dot(v)) / den, beta = (c12 * w1.dot(v) - w2.dot(u)) / den;
  const double g2 = u.squaredNorm() - alpha * alpha - beta * beta - 2.0 * alpha * beta * c12;
  Pair out;
  const double scale2 = std::max(u.squaredNorm(), scale * scale);
  if (g2 < -slack * scale2) return out;
  const bool twin = doubleRoot(g2, std::sqrt(scale2));
  const double gamma = twin ? 0.0 : (k == 0 ? -1.0 : 1.0) * std::sqrt(g2) / n.norm();
  const Vec3 c = r + alpha * w1 + beta * w2 + gamma * n;
  const Angle a2 = subproblem1(w2, r, p, c, scale), a1 = subproblem1(w1, r, c, q, scale);
  out.t1 = a1.theta;
  out.t2 = a2.theta;
  out.ok = true;
  out.singular = a1.free || a2.free || twin;
  return out;
}

Vec3 perpendicular(const Vec3& w) {
  const Vec3 e = std::abs(w.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  return w.cross(e).normalized();
}

// Candidates in motion space (x_i), with their flags, collected by the two solvers.
struct Candidates {
  std::array<Vec6, kClosedFormMaxSolutions> x;
  std::array<IkBranch, kClosedFormMaxSolutions> branch;
  std::array<bool, kClosedFormMaxSolutions> singular;
  int count = 0;
  void add(const Vec6& motion, IkBranch b, bool s) {
    x[static_cast<size_t>(count)] = motion;
    branch[static_cast<size_t>(count)] = b;
    singular[static_cast<size_t>(count)] = s;
    ++count;
  }
};

// joints 4, 5, 6 of a spherical wrist, given joints 1-3 (x[0..2]): W = (e1 e2 e3)^-1 G = e4 e5 e6.
void solveWrist(const ClosedFormStructure& s, const Pose& G, double L, Vec6 x, IkBranch b, bool singular, Candidates& out) {
  const Pose W = (jointPose(s, 0, x[0]) * jointPose(s, 1, x[1]) * jointPose(s, 2, x[2])).inverse() * G;
  const Vec3& c = s.wrist;
  const Vec3 p6 = c + L * s.w[5];
  for (int k = 0; k < 2; ++k) {
    const Pair wrist = subproblem2(s.w[3], s.w[4], c, p6, W * p6, k, L, negativeSlack(s));
    if (!wrist.ok) continue;
    x[3] = wrist.t1;
    x[4] = wrist.t2;
    const Pose E45 = jointPose(s, 3, x[3]) * jointPose(s, 4, x[4]);
    const Vec3 pr = c + L * perpendicular(s.w[5]);
    const Angle a6 = subproblem1(s.w[5], c, pr, E45.inverse() * (W * pr), L);
    x[5] = a6.theta;
    b.wrist = k == 1;
    out.add(x, b, singular || wrist.singular || a6.free);
  }
}

void solveSphericalWrist(const ClosedFormStructure& s, const Pose& G, double L, Candidates& out) {
  const Vec3 pd = G * s.wrist;
  const double delta2 = (pd - s.shoulder).squaredNorm();
  Roots elbow;
  if (s.prismatic_elbow) {  // |c + x v - s|^2 = delta^2: x^2 + 2 B x + C = 0
    const Vec3 cs = s.wrist - s.shoulder;
    const double B = s.w[2].dot(cs), disc = B * B - (cs.squaredNorm() - delta2);
    if (disc >= -negativeSlack(s) * L * L) {
      const double root = doubleRoot(disc, L) ? 0.0 : std::sqrt(disc);
      elbow.theta[0] = -B - root;
      elbow.theta[1] = -B + root;
      elbow.count = 2;
      elbow.singular = root == 0.0;
    }
  } else {
    elbow = subproblem3(s.w[2], s.p[2], s.wrist, s.shoulder, delta2, negativeSlack(s));
  }
  for (int e = 0; e < elbow.count; ++e) {
    const Vec3 y = jointPose(s, 2, elbow.theta[e]) * s.wrist;
    for (int k = 0; k < 2; ++k) {
      const Pair shoulder = subproblem2(s.w[0], s.w[1], s.shoulder, y, pd, k, L, negativeSlack(s));
      if (!shoulder.ok) continue;
      Vec6 x = Vec6::Zero();
      x[0] = shoulder.t1;
      x[1] = shoulder.t2;
      x[2] = elbow.theta[e];
      IkBranch b;
      b.shoulder = k == 1;
      b.elbow = e == 1;
      solveWrist(s, G, L, x, b, elbow.singular || shoulder.singular, out);
    }
  }
}

// joints 2, 3, 4 of the parallel triple, given 1, 5, 6: H = e1^-1 G e6^-1 e5^-1 = e2 e3 e4.
void solvePlanar(const ClosedFormStructure& s, const Pose& G, double L, Vec6 x, IkBranch b, bool singular, Candidates& out) {
  const Pose H = jointPose(s, 0, x[0]).inverse() * G * (jointPose(s, 4, x[4]) * jointPose(s, 5, x[5])).inverse();
  const Vec3 &p2 = s.p[1], &p4 = s.p[3];
  const Vec3 h = H * p4;
  const Roots elbow = subproblem3(s.w[2], s.p[2], p4, p2, (h - p2).squaredNorm(), negativeSlack(s));
  const Vec3 n = perpendicular(s.w[1]);
  for (int e = 0; e < elbow.count; ++e) {
    x[2] = elbow.theta[e];
    const Angle a2 = subproblem1(s.w[1], p2, jointPose(s, 2, x[2]) * p4, h, L);
    x[1] = a2.theta;
    const Mat3 R23 = jointPose(s, 1, x[1]).R * jointPose(s, 2, x[2]).R;
    x[3] = subproblem1(s.w[3], Vec3::Zero(), n, R23.transpose() * (H.R * n), 1.0).theta;
    b.elbow = e == 1;
    out.add(x, b, singular || elbow.singular || a2.free);
  }
}

void solveParallelTriple(const ClosedFormStructure& s, const Pose& G, double L, Candidates& out) {
  const Vec3 &u = s.w[1], &w1 = s.w[0], &p1 = s.p[0], &w5 = s.w[4], &w6 = s.w[5];
  // joint 1: (R_1 u).(G c - p1) = u.(c - p1)
  const Vec3 y = G * s.wrist - p1;
  const double c1 = w1.dot(u);
  const Roots shoulder = cosSin(u.dot(y) - c1 * w1.dot(y), w1.cross(u).dot(y), u.dot(s.wrist - p1) - c1 * w1.dot(y), L,
                               negativeSlack(s));
  for (int k = 0; k < shoulder.count; ++k) {
    Vec6 x = Vec6::Zero();
    x[0] = shoulder.theta[k];
    const Vec3 R1u = jointPose(s, 0, x[0]).R * u;
    // joint 5: u.(R_5 w6) = (R_1 u).(R_G w6)
    const double c56 = w5.dot(w6);
    const Roots wrist = cosSin(u.dot(w6) - u.dot(w5) * c56, u.dot(w5.cross(w6)), R1u.dot(G.R * w6) - u.dot(w5) * c56, 1.0,
                              negativeSlack(s));
    for (int m = 0; m < wrist.count; ++m) {
      x[4] = wrist.theta[m];
      // joint 6: R_6 (R_G^T R_1 u) = R_5^T u
      const Angle a6 = subproblem1(w6, Vec3::Zero(), G.R.transpose() * R1u, jointPose(s, 4, x[4]).R.transpose() * u, 1.0);
      x[5] = a6.theta;
      IkBranch b;
      b.shoulder = k == 1;
      b.wrist = m == 1;
      solvePlanar(s, G, L, x, b, shoulder.singular || wrist.singular || a6.free, out);
    }
  }
}

// ---- from motions to checked joint vectors -------------------------------------------------------------------

// x in (-pi, pi]: the subproblems' angles are atan2 values and sums of three of them, within (-5 pi, 5 pi)
// (std::remainder costs ~100 instructions, a third of a subproblem)
double wrapAngle(double x) {
  while (x > M_PI) x -= 2.0 * M_PI;
  while (x <= -M_PI) x += 2.0 * M_PI;
  return x;
}

// q of joint i for motion x: revolute turns in (-pi, pi], then whole turns into the range when possible.
double jointValue(const PoeModel& model, const ClosedFormStructure& s, int i, double x) {
  const Joint& j = model.joint(i);
  const bool turns = !(i == 2 && s.prismatic_elbow);
  double q = j.variable(turns ? wrapAngle(x) : x);
  if (!ik_ranges::inRange(j, q)) ik_ranges::wrapInto(j, q);
  return q;
}

int firstOutOfRange(const PoeModel& model, const Vec6& q) {
  for (int i = 0; i < 6; ++i) {
    if (!ik_ranges::inRange(model.joint(i), q[i])) return i;
  }
  return -1;
}

void residual(const PoeModel& model, Data& data, const Vec6& q, const Pose& T_target, const Vec3& point_tool,
              ClosedFormSolution& out) {
  forwardKinematics(model, data, q);
  const Pose& T = data.T_base_tool;
  out.position_error = (T.R * point_tool + T.p - T_target.p).norm();
  out.rotation_error = rotationError(T.R, T_target.R);
}

void checkTarget(const char* function, const Pose& T) {
  LP_CHECK(T.p.allFinite() && T.R.allFinite(), function << ": the target is not finite");
  const double defect = (T.R.transpose() * T.R - Mat3::Identity()).cwiseAbs().maxCoeff();
  LP_CHECK(defect <= kRotationOrthonormal && T.R.determinant() > 0.0,
           function << ": the target rotation is not a rotation (|R^T R - I| = " << defect << ")");
}

void checkModel(const char* function, const PoeModel& model, const IkOptions& options, const ClosedFormWorkspace& work) {
  LP_CHECK(work.structure.kind != ClosedFormKind::None, function << ": no closed form for this model: " << work.structure.reason);
  bool same = model.dof() == 6;
  for (int i = 0; same && i < 6; ++i) same = model.joint(i).twist == work.twists[static_cast<size_t>(i)];
  LP_CHECK(same, function << ": the workspace was built for another model");
  options.validate(function);
  LP_CHECK(options.measure == Measure::Pose,
           function << ": the closed form solves a pose (a position leaves a 6-joint arm infinitely many solutions)");
}

}  // namespace

const char* closedFormKindName(ClosedFormKind kind) {
  return kind == ClosedFormKind::SphericalWrist ? "spherical_wrist" : kind == ClosedFormKind::ParallelTriple ? "parallel_triple" : "none";
}

ClosedFormStructure closedFormStructure(const PoeModel& model, double tolerance) {
  LP_CHECK(tolerance > 0.0 && tolerance <= 0.1, "closedFormStructure: tolerance must be in (0, 0.1], got " << tolerance);
  ClosedFormStructure s;
  s.tool_pose = model.toolPose();
  if (model.dof() != 6) {
    s.reason = "the closed form needs 6 joints, the model has " + std::to_string(model.dof());
    return s;
  }
  Detection wrist, triple;
  if (detectSphericalWrist(model, tolerance, s, wrist)) {
    s.kind = ClosedFormKind::SphericalWrist;
    s.deviation = wrist.deviation;
    return s;
  }
  ClosedFormStructure t;
  t.tool_pose = s.tool_pose;
  if (detectParallelTriple(model, tolerance, t, triple)) {
    t.kind = ClosedFormKind::ParallelTriple;
    t.deviation = triple.deviation;
    return t;
  }
  s.prismatic_elbow = false;
  s.reason = std::string("no spherical wrist: ") + wrist.reason + "; no parallel axes 2-4: " + triple.reason;
  return s;
}

ClosedFormWorkspace::ClosedFormWorkspace(const PoeModel& model, double tolerance)
    : structure(closedFormStructure(model, tolerance)), data(model), ik(model) {
  for (int i = 0; i < std::min(6, model.dof()); ++i) twists[static_cast<size_t>(i)] = model.joint(i).twist;
}

const ClosedFormResult& inverseKinematicsAll(const PoeModel& model, const Pose& T_target, const IkOptions& options,
                                             ClosedFormWorkspace& work) {
  checkModel("inverseKinematicsAll", model, options, work);
  checkTarget("inverseKinematicsAll", T_target);
  const ClosedFormStructure& s = work.structure;
  const double L = model.lengthScale();
  Pose T_tool = T_target;  // F = T_base_tool Trans(point_tool)
  T_tool.p.noalias() -= T_target.R * options.point_tool;
  const Pose G = T_tool * s.tool_pose.inverse();
  Candidates c;
  if (s.kind == ClosedFormKind::SphericalWrist) {
    solveSphericalWrist(s, G, L, c);
  } else {
    solveParallelTriple(s, G, L, c);
  }
  ClosedFormResult& result = work.result;
  result.kind = s.kind;
  result.count = 0;
  result.dropped = 0;
  IkOptions refine = options;
  refine.ranges = RangePolicy::Report;
  refine.check_singularity = false;
  const double tol_p = options.position_tolerance * L, tol_r = options.rotation_tolerance;
  for (int k = 0; k < c.count; ++k) {
    ClosedFormSolution& sol = result.solutions[static_cast<size_t>(result.count)];
    for (int i = 0; i < 6; ++i) sol.q[i] = jointValue(model, s, i, c.x[static_cast<size_t>(k)][i]);
    sol.branch = c.branch[static_cast<size_t>(k)];
    sol.singular = c.singular[static_cast<size_t>(k)];
    sol.refinement_iterations = 0;
    residual(model, work.data, sol.q, T_target, options.point_tool, sol);
    if (!(sol.position_error <= tol_p && sol.rotation_error <= tol_r)) {
      const IkResult& r = inverseKinematics(model, work.data, T_target, sol.q, refine, work.ik);
      if (!r.converged) {
        ++result.dropped;
        continue;
      }
      sol.q = r.q;
      sol.refinement_iterations = r.iterations;
      sol.position_error = r.position_error;
      sol.rotation_error = r.rotation_error;
    }
    sol.out_of_range = firstOutOfRange(model, sol.q);
    ++result.count;
  }
  // in the order of the branch bits (shoulder, elbow, wrist), whatever order the geometry generated them in
  auto key = [](const ClosedFormSolution& a) { return 4 * a.branch.shoulder + 2 * a.branch.elbow + a.branch.wrist; };
  std::sort(result.solutions.begin(), result.solutions.begin() + result.count,
            [&](const ClosedFormSolution& a, const ClosedFormSolution& b) { return key(a) < key(b); });
  return result;
}

double jointDistance(const PoeModel& model, const Eigen::Ref<const VecX>& a, const Eigen::Ref<const VecX>& b) {
  LP_CHECK(a.size() == model.dof() && b.size() == model.dof(),
           "jointDistance: joint vectors of " << a.size() << " and " << b.size() << " values, the model has " << model.dof() << " joints");
  double d = 0.0;
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double dx = j.scale * (a[i] - b[i]);
    d = std::max(d, j.type == JointType::Revolute    ? std::abs(std::remainder(dx, 2.0 * M_PI))
                    : j.type == JointType::Prismatic ? std::abs(dx) / model.lengthScale()
                                                     : std::abs(dx));
  }
  return d;
}

bool branchOf(const PoeModel& model, const Eigen::Ref<const VecX>& q, const IkOptions& options, ClosedFormWorkspace& work,
              IkBranch& branch) {
  checkModel("branchOf", model, options, work);
  checkJointVector(q, model.dof());
  forwardKinematics(model, work.data, q);
  Pose target = work.data.T_base_tool;
  target.p.noalias() += target.R * options.point_tool;
  const ClosedFormResult& r = inverseKinematicsAll(model, target, options, work);
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int k = 0; k < r.count; ++k) {
    const double d = jointDistance(model, q, r.solutions[static_cast<size_t>(k)].q);
    if (d < best_distance) {
      best_distance = d;
      best = k;
    }
  }
  if (best < 0) return false;
  branch = r.solutions[static_cast<size_t>(best)].branch;
  return true;
}

const ClosedFormSolution* compensateOnBranch(const PoeModel& nominal, const PoeModel& calibrated,
                                             const Eigen::Ref<const VecX>& q, const IkOptions& options,
                                             ClosedFormWorkspace& nominal_work, ClosedFormWorkspace& calibrated_work) {
  IkBranch branch;
  if (!branchOf(nominal, q, options, nominal_work, branch)) return nullptr;
  forwardKinematics(nominal, nominal_work.data, q);
  Pose target = nominal_work.data.T_base_tool;
  target.p.noalias() += target.R * options.point_tool;
  ClosedFormResult& r = calibrated_work.result;
  inverseKinematicsAll(calibrated, target, options, calibrated_work);
  ClosedFormSolution* best = nullptr;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int k = 0; k < r.count; ++k) {
    ClosedFormSolution& s = r.solutions[static_cast<size_t>(k)];
    if (s.branch != branch) continue;
    const double d = jointDistance(calibrated, q, s.q);
    if (d < best_distance) {
      best_distance = d;
      best = &s;
    }
  }
  // each revolute joint by whole turns to the nominal row's value, where the range allows (the same pose)
  for (int i = 0; best != nullptr && i < calibrated.dof(); ++i) {
    const Joint& j = calibrated.joint(i);
    if (!ik_ranges::periodic(j)) continue;
    const double P = ik_ranges::period(j);
    const double moved = best->q[i] - P * std::round((best->q[i] - q[i]) / P);
    if (ik_ranges::inRange(j, moved)) best->q[i] = moved;
  }
  return best;
}

}  // namespace lowpair
