#include "lowpair/convert.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>

#include "check.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

double wrapAngle(double angle) {
  double out = std::remainder(angle, 2.0 * M_PI);  // [-pi, pi]
  if (out <= -M_PI) out += 2.0 * M_PI;
  return out;
}

namespace {

struct Tolerances {
  double parallel;  // on sin(alpha)
  double length;    // snap lengths below this
};

double snapAngle(double angle) {
  double x = wrapAngle(angle);
  if (std::abs(x) <= kSnapAngle) return 0.0;  // also turns -0 into +0
  if (M_PI - std::abs(x) <= kSnapAngle) return M_PI;
  return x;
}

double snapLength(double x, double tol) { return std::abs(x) <= tol ? 0.0 : x; }

DhParams canonical(const DhParams& row, const Tolerances& tol) {
  DhParams out = row;
  out.theta = snapAngle(row.theta);
  out.d = snapLength(row.d, tol.length);
  out.alpha = snapAngle(row.alpha);
  out.a = snapLength(row.a, tol.length);
  out.beta = row.hayati() ? snapAngle(row.beta) : 0.0;
  return out;
}

// The Hayati row's angles once its origin is placed: with theta fixed by the origin, alpha and beta turn e_z
// onto the unit u (this frame's coordinates): Rz(-theta) u = (sin beta, -sin alpha cos beta, cos alpha cos beta).
// An origin at 0 leaves theta free: it is chosen as a standard row's, so that beta = 0.
void hayatiAngles(const Vec3& u, double px, double py, const Tolerances& tol, DhParams& row) {
  row.kind = DhRowKind::Hayati;
  row.d = 0.0;
  row.a = std::hypot(px, py);
  const double s = std::hypot(u.x(), u.y());
  if (row.a > tol.length) {
    row.theta = std::atan2(py, px);
  } else {
    row.a = 0.0;
    row.theta = s > 0.0 ? std::atan2(u.x(), -u.y()) : 0.0;
  }
  const double ct = std::cos(row.theta), st = std::sin(row.theta);
  const Vec3 w(ct * u.x() + st * u.y(), -st * u.x() + ct * u.y(), u.z());
  row.beta = std::atan2(w.x(), std::hypot(w.y(), w.z()));
  row.alpha = std::atan2(-w.y(), w.z());
}

// Hayati row (docs/conventions.md) for a revolute/helical axis nearly parallel to the current z: the next
// origin is where the axis pierces this frame's xy plane. Precondition: w3 != 0 (not parallel to the plane).
DhParams hayatiRowFromTwist(const Vec6& xi, double pitch, const Tolerances& tol) {
  const Vec3 w = xi.head<3>().normalized();
  const Vec3 m = xi.tail<3>() - pitch * w;
  const Vec3 p0 = w.cross(m);            // the line's point nearest the origin
  const Vec3 P = p0 - (p0.z() / w.z()) * w;  // its point in the xy plane
  DhParams row;
  hayatiAngles(w, P.x(), P.y(), tol, row);
  return row;
}

// Angle between the lines z and Rx(alpha) Ry(beta) z, in [0, pi/2].
double hayatiLineAngle(const DhParams& r) {
  const double ca = std::cos(r.alpha), sa = std::sin(r.alpha), cb = std::cos(r.beta), sb = std::sin(r.beta);
  return std::atan2(std::hypot(sb, sa * cb), std::abs(ca * cb));
}

// Lemmas 1-3: the row A(theta, d, alpha, a) whose z axis is the joint's line, from the joint's unit
// twist expressed in the current frame. For a revolute/helical joint only the line matters (the moment
// m = v - h w); for a prismatic joint only the direction.
DhParams rowFromTwist(JointType type, const Vec6& xi, double pitch, const Tolerances& tol, bool& parallel) {
  DhParams row;
  if (type == JointType::Prismatic) {
    const Vec3 u = xi.tail<3>().normalized();
    const double s = std::hypot(u.x(), u.y());
    parallel = s <= tol.parallel;
    if (parallel) {
      row.alpha = u.z() > 0.0 ? 0.0 : M_PI;
    } else {
      row.alpha = std::atan2(s, u.z());
      row.theta = std::atan2(u.x(), -u.y());
    }
    return row;
  }
  const Vec3 w = xi.head<3>().normalized();
  const Vec3 m = xi.tail<3>() - pitch * w;  // p x w
  const double s = std::hypot(w.x(), w.y());
  parallel = s <= tol.parallel;
  if (parallel) {
    // z is (anti)parallel to the axis: d is free (0); the axis pierces the xy plane at
    // (a cos theta, a sin theta) = sign(w3) (-m2, m1).
    row.alpha = w.z() > 0.0 ? 0.0 : M_PI;
    const double sign = w.z() > 0.0 ? 1.0 : -1.0;
    const double px = -sign * m.y(), py = sign * m.x();
    row.a = std::hypot(px, py);
    row.theta = row.a <= tol.length ? 0.0 : std::atan2(py, px);
    return row;
  }
  // eq. 17: a sin(alpha) = -m3 fixes the sign of alpha so that a >= 0.
  const double a_sin_alpha = -m.z();
  const double abs_alpha = std::atan2(s, w.z());
  const bool intersecting = std::abs(a_sin_alpha) / s <= tol.length;
  const double sign = (intersecting || a_sin_alpha > 0.0) ? 1.0 : -1.0;
  row.alpha = sign * abs_alpha;
  row.a = intersecting ? 0.0 : std::abs(a_sin_alpha) / s;
  row.theta = std::atan2(sign * w.x(), -sign * w.y());
  row.d = (w.x() * m.y() - w.y() * m.x()) / (s * s);
  return row;
}

// The last row as a Hayati row: M = Rz(theta) Tx(a) Rx(alpha) Ry(beta) Rz(theta_T) Tz(d_T): the row's origin
// is where the tool's z line pierces this frame's xy plane. Precondition: the tool z is not in that plane.
void splitToolHayati(const Pose& M, const Tolerances& tol, DhParams& row, double& tool_theta, double& tool_d) {
  const Vec3 u = M.R.col(2);
  tool_d = M.p.z() / u.z();
  const Vec3 P = M.p - tool_d * u;
  hayatiAngles(u, P.x(), P.y(), tol, row);
  const Mat3 N = dhTransform(row).R.transpose() * M.R;  // Rz(theta_T)
  tool_theta = std::atan2(N(1, 0), N(0, 0));
}

// Lemma 4: M = Rz(theta) Tz(d) Rx(alpha) Tx(a) Rz(theta_T) Tz(d_T), alpha in [0, pi].
void splitTool(const Pose& M, const Tolerances& tol, DhParams& row, double& tool_theta, double& tool_d,
               bool& parallel) {
  const Mat3& R = M.R;
  const Vec3& p = M.p;
  const double s = std::hypot(R(0, 2), R(1, 2));
  parallel = s <= tol.parallel;
  if (parallel) {
    row.alpha = R(2, 2) > 0.0 ? 0.0 : M_PI;
    row.a = std::hypot(p.x(), p.y());
    row.theta = row.a <= tol.length ? 0.0 : std::atan2(p.y(), p.x());
    row.d = p.z();
    tool_d = 0.0;
    const double phi = std::atan2(R(1, 0), R(0, 0));  // Rz(phi) = R (alpha 0) or R Rx(pi) (alpha pi)
    tool_theta = row.alpha == 0.0 ? phi - row.theta : row.theta - phi;
    return;
  }
  // theta from the third column; alpha and theta_T from N = Rz(-theta) R = Rx(alpha) Rz(theta_T), so that
  // the rounding in theta (relative eps / sin(alpha) when alpha is small) is absorbed by theta_T instead
  // of rotating the tool.
  row.theta = std::atan2(R(0, 2), -R(1, 2));
  const double ct = std::cos(row.theta), st = std::sin(row.theta);
  Mat3 N;
  N.row(0) = ct * R.row(0) + st * R.row(1);
  N.row(1) = -st * R.row(0) + ct * R.row(1);
  N.row(2) = R.row(2);
  row.alpha = std::atan2(-N(1, 2), N(2, 2));
  const double c_alpha = std::cos(row.alpha), s_alpha = std::sin(row.alpha);
  // Rx(-alpha) N = Rz(theta_T)
  tool_theta = std::atan2(c_alpha * N(1, 0) + s_alpha * N(2, 0), N(0, 0));
  const Vec3 b(ct * p.x() + st * p.y(), -st * p.x() + ct * p.y(), p.z());  // Rz(-theta) p
  row.a = b.x();
  tool_d = -b.y() / s_alpha;
  row.d = b.z() - c_alpha * tool_d;
}

// The seed of checkDhConversion's configurations: fixed so that the check is reproducible (any value would do).
constexpr std::uint64_t kFkCheckSeed = 0x10a7a1;

// max(L, max |d|, max |a|, |d_T|): the scale of the accuracy bound (conversion.md).
double boundScale(const DhModel& dh, double L) {
  double scale = std::max({L, std::abs(dh.base().d), std::abs(dh.base().a), std::abs(dh.toolD())});
  for (const DhJoint& j : dh.joints()) scale = std::max({scale, std::abs(j.link.d), std::abs(j.link.a)});
  return scale;
}

double lineAngle(double alpha) {
  const double x = std::abs(wrapAngle(alpha));
  return std::min(x, M_PI - x);
}

// The longest length of a row (the last row with its tool d).
double longest(const DhParams& r, double tool_d = 0.0) {
  return std::max({std::abs(r.d), std::abs(r.a), std::abs(tool_d)});
}

}  // namespace

void ConvertOptions::validate() const {
  LP_CHECK(std::isfinite(parallel_threshold) && parallel_threshold >= 0.0 && parallel_threshold < 1.0,
           "poeToDh: parallel_threshold must be in [0, 1), got " << parallel_threshold);
}

DhConversion poeToDh(const PoeModel& model, const ConvertOptions& options) {
  const int n = model.dof();
  LP_CHECK(n >= 1, "poeToDh: the model has no joints");
  options.validate();
  const double L = model.lengthScale();
  Tolerances tol;
  const double rounding_parallel = kParallelPerJoint * kEps * n;
  tol.parallel = options.parallel_threshold > 0.0 ? options.parallel_threshold : rounding_parallel;
  tol.length = kSnapLength * L;

  LP_CHECK(options.row_kinds.empty() || options.row_kinds.size() == static_cast<size_t>(n + 1),
           "poeToDh: row_kinds must be empty or have n + 1 = " << n + 1 << " entries, got " << options.row_kinds.size());
  // Hayati or standard (docs/conventions.md, "Hayati rows"): forced by row_kinds, else the rule
  auto wantHayati = [&](int r, bool parallel, double standard_longest_d, double standard_longest,
                        double hayati_longest) {
    if (parallel) return false;
    if (!options.row_kinds.empty()) return options.row_kinds[static_cast<size_t>(r)] == DhRowKind::Hayati;
    if (options.standard_only) return false;
    return standard_longest_d > kHayatiLength * L && hayati_longest < standard_longest;
  };

  std::vector<DhRowReport> reports(static_cast<size_t>(n + 1));
  std::vector<DhParams> rows(static_cast<size_t>(n + 1));
  Pose G;  // T_base_frame of the rows found so far
  for (int i = 0; i < n; ++i) {
    const Joint& j = model.joint(i);
    const Vec6 xi = adjointApply(G.inverse(), j.twist);
    bool parallel = false;
    DhParams row = canonical(rowFromTwist(j.type, xi, j.pitch, tol, parallel), tol);
    reports[static_cast<size_t>(i)].standard_d = std::abs(row.d);
    if (j.type != JointType::Prismatic && !parallel && xi[2] != 0.0) {
      const DhParams hayati = canonical(hayatiRowFromTwist(xi, j.pitch, tol), tol);
      if (wantHayati(i, parallel, std::abs(row.d), longest(row), longest(hayati)) && std::isfinite(longest(hayati))) {
        row = hayati;
      }
    }
    rows[static_cast<size_t>(i)] = row;
    reports[static_cast<size_t>(i)].parallel = parallel;
    G = G * dhTransform(row);  // snap, then compose
  }
  DhParams last;
  double tool_theta = 0.0, tool_d = 0.0;
  bool parallel = false;
  const Pose M_last = G.inverse() * model.toolPose();
  splitTool(M_last, tol, last, tool_theta, tool_d, parallel);
  last = canonical(last, tol);
  tool_d = snapLength(tool_d, tol.length);
  reports[static_cast<size_t>(n)].standard_d = std::max(std::abs(last.d), std::abs(tool_d));
  if (!parallel && M_last.R(2, 2) != 0.0) {
    DhParams hayati;
    double h_theta = 0.0, h_d = 0.0;
    splitToolHayati(M_last, tol, hayati, h_theta, h_d);
    hayati = canonical(hayati, tol);
    h_d = snapLength(h_d, tol.length);
    if (wantHayati(n, parallel, reports[static_cast<size_t>(n)].standard_d, longest(last, tool_d),
                   longest(hayati, h_d)) &&
        std::isfinite(longest(hayati, h_d))) {
      last = hayati;
      tool_theta = h_theta;
      tool_d = h_d;
    }
  }
  rows[static_cast<size_t>(n)] = last;
  reports[static_cast<size_t>(n)].parallel = parallel;
  tool_theta = snapAngle(tool_theta);

  std::vector<DhJoint> joints(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Joint& j = model.joint(i);
    DhJoint& dj = joints[static_cast<size_t>(i)];
    static_cast<JointMotion&>(dj) = j;
    dj.offset = 0.0;
    dj.name = j.name;
    dj.range = j.range;
    dj.link = rows[static_cast<size_t>(i + 1)];
    // fold the offset: Q_i(x) A(link_i) with x = motion(q) = scale q + motion(0)
    const double x0 = j.motion(0.0);
    if (x0 != 0.0) {
      dj.link = movedRow(dj.link, j, x0);
      dj.link.theta = snapAngle(dj.link.theta);
      dj.link.d = snapLength(dj.link.d, tol.length);
    }
  }

  // folded offsets move the frames: a model near the magnitude limits can have a D-H equivalent beyond them
  // (nearly parallel axes do not: a d of L / sin(alpha) is a number of the table, not a frame of the chain,
  // whose links sit on the joint lines)
  std::optional<DhModel> built;
  try {
    built.emplace(rows[0], std::move(joints), tool_theta, tool_d, model.name());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("poeToDh: the D-H table, its offsets folded, is beyond the magnitude limits: ") +
                                e.what());
  }
  DhModel& dh = *built;
  auto consider = [&](const DhParams& r, int row_index) {
    DhRowReport& rep = reports[static_cast<size_t>(row_index)];
    rep.row = row_index;
    rep.axis_angle = r.hayati() ? hayatiLineAngle(r) : lineAngle(r.alpha);
    rep.hayati = r.hayati();
    rep.abs_d = std::abs(r.d);
    rep.abs_a = std::abs(r.a);
    rep.ill_conditioned = std::max(rep.abs_d, rep.abs_a) > kIllConditioned * L;
  };
  consider(dh.base(), 0);
  for (int i = 0; i < n; ++i) consider(dh.joint(i).link, i + 1);
  DhToolReport tool;
  tool.abs_d = std::abs(dh.toolD());
  tool.ill_conditioned = tool.abs_d > kIllConditioned * L;
  const double scale = boundScale(dh, L);  // before dh is moved from
  return DhConversion{std::move(dh),
                      L,
                      tol.parallel,
                      rounding_parallel,
                      options.parallel_threshold > rounding_parallel,
                      std::move(reports),
                      tool,
                      scale};
}

FkCheck checkDhConversion(const PoeModel& poe, const DhModel& dh, int samples) {
  const int n = poe.dof();
  LP_CHECK(dh.dof() == n, "checkDhConversion: the D-H model has " << dh.dof() << " joints, the POE model " << n);
  LP_CHECK(samples >= 0, "checkDhConversion: samples must be >= 0, got " << samples);
  const double L = poe.lengthScale();
  FkCheck check;
  check.scale = boundScale(dh, L);
  std::mt19937_64 rng(kFkCheckSeed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Data poe_data(poe);
  Data dh_data(dh);
  VecX q = VecX::Zero(n);
  for (int s = 0; s <= samples; ++s) {
    if (s > 0) {
      for (int i = 0; i < n; ++i) {
        const Joint& j = poe.joint(i);
        if (j.range) {
          const auto& r = *j.range;
          q[i] = r[0] + 0.5 * (unit(rng) + 1.0) * (r[1] - r[0]);
        } else {
          q[i] = unit(rng) * (j.type == JointType::Prismatic ? L / j.scale : M_PI);
        }
      }
    } else {
      for (int i = 0; i < n; ++i) q[i] = -poe.joint(i).offset;
    }
    forwardKinematics(poe, poe_data, q);
    forwardKinematics(dh, dh_data, q);
    check.max_rotation = std::max(check.max_rotation, rotationError(poe_data.T_base_tool.R, dh_data.T_base_tool.R));
    check.max_translation = std::max(check.max_translation, (poe_data.T_base_tool.p - dh_data.T_base_tool.p).norm());
  }
  check.samples = samples + 1;
  return check;
}

PoeModel dhToPoe(const DhModel& model) {
  std::vector<Joint> joints;
  const std::vector<Pose> frames = restFrames(model.chain());
  for (int i = 0; i < model.dof(); ++i) {
    const DhJoint& dj = model.joint(i);
    Joint j = jointOnFrame(dj, frames[static_cast<size_t>(i)]);
    j.name = dj.name;
    j.range = dj.range;
    joints.push_back(j);
  }
  VecX q_rest(model.dof());  // zero motion: q = -offset, where exp(xi_T) is the tool pose (eq. 5)
  for (int i = 0; i < model.dof(); ++i) q_rest[i] = model.joint(i).variable(0.0);
  return PoeModel(std::move(joints), dhForwardKinematics(model, q_rest), model.name());
}

ModifiedDh toModifiedDh(const DhModel& model) {
  ModifiedDh out;
  out.base_theta = model.base().theta;
  out.base_d = model.base().d;
  double alpha = model.base().alpha, a = model.base().a, beta = model.base().beta;
  for (const DhJoint& dj : model.joints()) {
    ModifiedDhJoint mj;
    static_cast<JointMotion&>(mj) = dj;
    mj.name = dj.name;
    mj.alpha = alpha;
    mj.a = a;
    mj.beta = beta;
    mj.theta = dj.link.theta;
    mj.d = dj.link.d;
    out.joints.push_back(mj);
    alpha = dj.link.alpha;
    a = dj.link.a;
    beta = dj.link.beta;
  }
  out.tool_alpha = alpha;
  out.tool_a = a;
  out.tool_beta = beta;
  out.tool_theta = model.toolTheta();
  out.tool_d = model.toolD();
  return out;
}

namespace {
// Rx(alpha) Tx(a) Ry(beta)
Pose rxTx(double alpha, double a, double beta) {
  const double c = std::cos(alpha), s = std::sin(alpha);
  Pose T;
  T.R << 1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c;
  T.p << a, 0.0, 0.0;
  if (beta != 0.0) {
    const double cb = std::cos(beta), sb = std::sin(beta);
    Mat3 Ry;
    Ry << cb, 0.0, sb, 0.0, 1.0, 0.0, -sb, 0.0, cb;
    T.R = T.R * Ry;
  }
  return T;
}
}  // namespace

Pose modifiedDhForwardKinematics(const ModifiedDh& model, const Eigen::Ref<const VecX>& q) {
  LP_CHECK(q.size() == static_cast<Eigen::Index>(model.joints.size()),
           "modifiedDhForwardKinematics: q has " << q.size() << " values, the model has " << model.joints.size() << " joints");
  Pose T = dhToolTransform(model.base_theta, model.base_d);
  for (size_t i = 0; i < model.joints.size(); ++i) {
    const ModifiedDhJoint& j = model.joints[i];
    const DhParams moved = movedRow({j.theta, j.d, 0.0, 0.0}, j, j.motion(q[static_cast<Eigen::Index>(i)]));
    T = T * rxTx(j.alpha, j.a, j.beta) * dhToolTransform(moved.theta, moved.d);
  }
  return T * rxTx(model.tool_alpha, model.tool_a, model.tool_beta) * dhToolTransform(model.tool_theta, model.tool_d);
}

}  // namespace lowpair
