#include "lowpair/model.hpp"
#include "linalg.hpp"

#include <algorithm>
#include <cmath>


#include "check.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace {
void packLanes(KinematicChain& chain);
}  // namespace

namespace {

// A rotation given by a user must be orthonormal to kRotationOrthonormal; defects above rounding
// (kRotationExact) are removed by projecting onto the nearest rotation (polar decomposition).
Mat3 checkedRotation(const Mat3& R, const std::string& what) {
  LP_CHECK(R.allFinite(), what << ": rotation has a non-finite entry");
  const double defect = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  LP_CHECK(defect <= kRotationOrthonormal,
           what << ": rotation is not orthonormal (max |R^T R - I| = " << defect << ")");
  LP_CHECK(R.determinant() > 0.0, what << ": rotation has determinant " << R.determinant() << " (a reflection)");
  if (defect <= kRotationExact) return R;
  Eigen::JacobiSVD<Mat3> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

// (theta, alpha) with Rz(theta) Rx(alpha) e_z = u for a unit u (Wu et al. eq. 13 with the roles of the
// frames as in the chain): alpha from atan2 (never acos), theta = 0 when u is along +-z.
void zAngles(const Vec3& u, double& theta, double& alpha) {
  const double h = std::hypot(u[0], u[1]);
  alpha = std::atan2(h, u[2]);
  theta = h > 0.0 ? std::atan2(u[0], -u[1]) : 0.0;
}

Mat3 rzRx(double theta, double cos_alpha, double sin_alpha) {
  const double ct = std::cos(theta), st = std::sin(theta);
  Mat3 R;
  R << ct, -st * cos_alpha, st * sin_alpha,  //
      st, ct * cos_alpha, -ct * sin_alpha,   //
      0.0, sin_alpha, cos_alpha;
  return R;
}

// The constant part of a link as a pose: Rz(theta) Trans(p) Rx(alpha).
Pose linkPose(const ChainLink& link) {
  Pose T;
  T.R = rzRx(link.theta, link.cos_alpha, link.sin_alpha);
  const double ct = std::cos(link.theta), st = std::sin(link.theta);
  T.p << ct * link.p[0] - st * link.p[1], st * link.p[0] + ct * link.p[1], link.p[2];
  return T;
}

// POE -> chain: joint i's frame G_i has z on the joint's line (origin at the line's point nearest the
// base origin; a prismatic joint keeps the previous origin) and x in the previous frame's xy plane, so
// G_i^-1 G_{i+1} = Rz(theta) Trans(p) Rx(alpha) with |p| bounded by the distances of the lines (<= 2 L).
// Each G_{i+1} is composed from the stored constants, so the next link is placed relative to the
// frame the evaluation will actually reach.
KinematicChain poeChain(const std::vector<Joint>& joints, const Pose& tool_pose) {
  KinematicChain chain;
  const size_t n = joints.size();
  auto lineOf = [&](size_t i, const Vec3& previous_origin, Vec3& z, Vec3& o) {
    const Joint& j = joints[i];
    if (j.type == JointType::Prismatic) {
      z = j.moment();
      o = previous_origin;
    } else {
      z = j.axis();
      o = j.axis().cross(j.moment());  // the line's point nearest the base origin
    }
  };
  Pose G;
  if (n > 0) {
    Vec3 z, o;
    lineOf(0, Vec3::Zero(), z, o);
    double theta = 0.0, alpha = 0.0;
    zAngles(z, theta, alpha);
    G.R = rzRx(theta, std::cos(alpha), std::sin(alpha));
    G.p = o;
  }
  chain.T_base_first = G;
  chain.links.resize(n);
  for (size_t i = 0; i < n; ++i) {
    ChainLink& link = chain.links[i];
    link.motion = joints[i];
    link.turn = link.motion.turnRate();
    link.slide = link.motion.slideRate();
    if (i + 1 == n) break;  // the last link's constant part is T_last_tool
    Vec3 z, o;
    lineOf(i + 1, G.p, z, o);
    double alpha = 0.0;
    zAngles(G.R.transpose() * z, link.theta, alpha);
    link.cos_alpha = std::cos(alpha);
    link.sin_alpha = std::sin(alpha);
    const Vec3 p_prev = G.R.transpose() * (o - G.p);  // in G_i coordinates
    const double ct = std::cos(link.theta), st = std::sin(link.theta);
    link.p << ct * p_prev[0] + st * p_prev[1], -st * p_prev[0] + ct * p_prev[1], p_prev[2];  // Rz(-theta) p_prev
    G = G * linkPose(link);
  }
  chain.T_last_tool = G.inverse() * tool_pose;
  packLanes(chain);
  return chain;
}

// D-H -> chain. A standard row maps onto a link directly. A Hayati row ends in `Rx(alpha) Ry(beta)`, which
// is not of the link form `Rx(alpha')`: write it as ZXZ angles `Rz(phi) Rx(alpha') Rz(gamma)`, move
// `Rz(phi)` to the front (`Tz(d) Tx(a) Rz(phi) = Rz(phi) Trans(Rz(-phi) (a, 0, d))`) and hand `Rz(gamma)` to
// the next link as a rotation `c` of its frame about its own z axis (which commutes with that joint's motion
// `Rz(j x) Tz(k x)`): chain frame i = D-H frame i * Rz(c_i), link = Rz(-c_i) Q(x) A Rz(c_{i+1}). With no
// Hayati row every c is 0 and the links are the D-H rows' numbers unchanged.
KinematicChain dhChain(const DhParams& base, const std::vector<DhJoint>& joints, double tool_theta, double tool_d) {
  KinematicChain chain;
  chain.T_base_first = dhTransform(base);
  double c = 0.0;  // rotation of the current chain frame about its z, relative to the D-H frame
  for (const DhJoint& j : joints) {
    ChainLink link;
    link.motion = j;
    link.turn = j.turnRate();
    link.slide = j.slideRate();
    if (!j.link.hayati()) {
      link.theta = c == 0.0 ? j.link.theta : j.link.theta - c;
      link.cos_alpha = std::cos(j.link.alpha);
      link.sin_alpha = std::sin(j.link.alpha);
      link.p << j.link.a, 0.0, j.link.d;  // Rz(theta) Tz(d) Rx(alpha) Tx(a) = Rz(theta) Trans(a, 0, d) Rx(alpha)
      c = 0.0;
    } else {
      const double sa = std::sin(j.link.alpha), ca = std::cos(j.link.alpha);
      const double sb = std::sin(j.link.beta), cb = std::cos(j.link.beta);
      const Vec3 u(sb, -sa * cb, ca * cb);  // Rx(alpha) Ry(beta) e_z
      double phi = 0.0, alpha = 0.0;
      zAngles(u, phi, alpha);
      Mat3 R0;  // Rx(alpha) Ry(beta)
      R0 << cb, 0.0, sb, sa * sb, ca, -sa * cb, -ca * sb, sa, ca * cb;
      const Mat3 M = rzRx(phi, std::cos(alpha), std::sin(alpha)).transpose() * R0;  // Rz(gamma)
      const double gamma = std::atan2(M(1, 0), M(0, 0));
      link.theta = j.link.theta - c + phi;
      link.cos_alpha = std::cos(alpha);
      link.sin_alpha = std::sin(alpha);
      link.p << j.link.a * std::cos(phi), -j.link.a * std::sin(phi), j.link.d;
      c = -gamma;
    }
    chain.links.push_back(link);
  }
  chain.T_last_tool = dhToolTransform(c == 0.0 ? tool_theta : tool_theta - c, tool_d);
  packLanes(chain);
  return chain;
}

// Every constant of a compiled chain is finite, or the model is rejected (never a NaN pose later).
void checkChain(const KinematicChain& chain) {
  bool finite = chain.T_base_first.R.allFinite() && chain.T_base_first.p.allFinite() &&
                chain.T_last_tool.R.allFinite() && chain.T_last_tool.p.allFinite();
  for (const ChainLink& l : chain.links) {
    finite = finite && std::isfinite(l.theta) && std::isfinite(l.cos_alpha) && std::isfinite(l.sin_alpha) &&
             l.p.allFinite() && std::isfinite(l.turn) && std::isfinite(l.slide);
  }
  LP_CHECK(finite, "the model's link frames overflow double precision (lengths near 1e308)");
}

}  // namespace

namespace {

// Fills `chain.lanes` from `chain.links`.
void packLanes(KinematicChain& chain) {
  const size_t n = chain.links.size();
  const size_t padded = (n + detail::kChainLanes - 1) / detail::kChainLanes * detail::kChainLanes;
  detail::ChainLanes& l = chain.lanes;
  l.theta.assign(padded, 0.0);
  l.turn.assign(padded, 0.0);
  l.slide.assign(padded, 0.0);
  l.z.assign(padded, 0.0);
  l.scale.assign(padded, 1.0);
  l.offset.assign(padded, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const ChainLink& link = chain.links[i];
    l.theta[i] = link.theta;
    l.turn[i] = link.turn;
    l.slide[i] = link.slide;
    l.z[i] = link.p[2];
    l.scale[i] = link.motion.scale;
    l.offset[i] = link.motion.offset;
  }
}

}  // namespace

std::vector<Pose> restFrames(const KinematicChain& chain) {
  std::vector<Pose> frames;
  Pose G = chain.T_base_first;
  for (const ChainLink& link : chain.links) {
    frames.push_back(G);
    G = G * linkPose(link);
  }
  return frames;
}

Joint jointOnFrame(const JointMotion& motion, const Pose& T_base_frame) {
  Joint j;
  static_cast<JointMotion&>(j) = motion;
  const Vec3 z = T_base_frame.R.col(2);
  if (motion.type == JointType::Prismatic) {
    j.twist << Vec3::Zero(), z;
  } else {
    j.twist << z, T_base_frame.p.cross(z) + motion.slideRate() * z;  // v = o x w + h w (design.md)
  }
  return j;
}

DhParams movedRow(const DhParams& row, const JointMotion& motion, double x) {
  DhParams out = row;
  out.theta += motion.turnRate() * x;
  out.d += motion.slideRate() * x;
  return out;
}

double lengthScale(const std::vector<Joint>& joints, const Pose& tool_pose) {
  double size = safeNorm(tool_pose.p);
  for (const Joint& j : joints) {
    if (j.type != JointType::Prismatic) size = std::max(size, safeNorm(j.axis().cross(j.moment())));
    // a helical joint's motion covers |pitch| length per radian: a pitch far above every other length
    // must set L, or the lengths it produces would be unbounded relative to L (fuzz regressions numeric/)
    if (j.type == JointType::Helical) size = std::max(size, std::abs(j.pitch));
    // the slide at the range ends, k x with x = scale (q + offset) (prismatic k = 1, helical the pitch): L is
    // a length even when q is in another unit (a URDF export converts cm to m by the scale), and a helical
    // range of 1e98 rad slides far beyond its pitch (fuzz regressions numeric/helical_range_slide)
    if (j.range && j.slideRate() != 0.0) {
      for (const double q : *j.range) size = std::max(size, std::abs(j.slideRate() * j.motion(q)));
    }
  }
  return size > 0.0 ? size : 1.0;
}

namespace {

// The magnitude limits of tolerances.hpp (kMaxMagnitude) for one joint.
void checkJointMagnitudes(const JointMotion& j, const std::optional<std::array<double, 2>>& range,
                          const std::string& label) {
  LP_CHECK(j.scale >= 1.0 / kMaxMagnitude && j.scale <= kMaxMagnitude,
           label << ": scale " << j.scale << " outside [1e-100, 1e100]");
  const double bound = kMaxMagnitude / j.scale;
  LP_CHECK(std::abs(j.offset) <= bound, label << ": |offset| " << std::abs(j.offset) << " above 1e100 / scale");
  if (range) {
    LP_CHECK(std::abs((*range)[0]) <= bound && std::abs((*range)[1]) <= bound,
             label << ": range end above 1e100 / scale in magnitude");
  }
}

void checkSize(double size) {
  LP_CHECK(std::isfinite(size) && size <= kMaxMagnitude,
           "robot size L = " << size << " above 1e100 (a joint axis or the tool that far from the base origin)");
  LP_CHECK(size >= 1.0 / kMaxMagnitude, "robot size L = " << size << " below 1e-100: state the lengths in a smaller unit");
}

}  // namespace

PoeModel::PoeModel(const std::vector<JointSpec>& joints, const Pose& tool_pose, std::string name)
    : name_(std::move(name)) {
  joints_.reserve(joints.size());
  const double size = lengthScaleOfSpecs(joints, tool_pose.p);
  for (size_t i = 0; i < joints.size(); ++i) joints_.push_back(normalizeJoint(joints[i], static_cast<int>(i), size));
  LP_CHECK(tool_pose.p.allFinite(), "tool: position has a non-finite entry");
  tool_pose_.R = checkedRotation(tool_pose.R, "tool");
  tool_pose_.p = tool_pose.p;
  finish();
}

PoeModel::PoeModel(std::vector<Joint> joints, const Pose& tool_pose, std::string name)
    : joints_(std::move(joints)), name_(std::move(name)) {
  for (size_t i = 0; i < joints_.size(); ++i) {
    const Joint& j = joints_[i];
    const std::string label = jointLabel(static_cast<int>(i), j.name);
    LP_CHECK(j.twist.allFinite() && std::isfinite(j.pitch) && std::isfinite(j.scale) && std::isfinite(j.offset),
             label << ": non-finite parameter");
    LP_CHECK(j.scale > 0.0, label << ": scale must be positive, got " << j.scale);
    const double unit = j.type == JointType::Prismatic ? j.twist.tail<3>().norm() : j.twist.head<3>().norm();
    LP_CHECK(std::abs(unit - 1.0) <= kUnitNorm, label << ": twist is not normalized (norm " << unit << ")");
    if (j.type == JointType::Prismatic) {
      LP_CHECK(j.twist.head<3>().isZero(0.0), label << ": prismatic twist has w != 0");
    }
  }
  LP_CHECK(tool_pose.p.allFinite(), "tool: position has a non-finite entry");
  tool_pose_.R = checkedRotation(tool_pose.R, "tool");
  tool_pose_.p = tool_pose.p;
  finish();
}

PoeModel PoeModel::fromToolTwist(const std::vector<JointSpec>& joints, const Vec6& tool_twist, std::string name) {
  LP_CHECK(tool_twist.allFinite(), "tool: twist has a non-finite entry");
  return PoeModel(joints, expSE3(tool_twist), std::move(name));
}

void PoeModel::finish() {
  for (size_t i = 0; i < joints_.size(); ++i) {
    checkJointMagnitudes(joints_[i], joints_[i].range, jointLabel(static_cast<int>(i), joints_[i].name));
  }
  length_scale_ = lowpair::lengthScale(joints_, tool_pose_);
  checkSize(length_scale_);
  chain_ = poeChain(joints_, tool_pose_);
  checkChain(chain_);
}

Pose dhTransform(const DhParams& row) {
  const double ct = std::cos(row.theta), st = std::sin(row.theta);
  const double ca = std::cos(row.alpha), sa = std::sin(row.alpha);
  Pose T;
  T.R << ct, -st * ca, st * sa,  //
      st, ct * ca, -ct * sa,     //
      0.0, sa, ca;
  T.p << row.a * ct, row.a * st, row.d;
  if (row.hayati()) {
    const double cb = std::cos(row.beta), sb = std::sin(row.beta);
    Mat3 Ry;
    Ry << cb, 0.0, sb, 0.0, 1.0, 0.0, -sb, 0.0, cb;
    T.R = T.R * Ry;
  }
  return T;
}

Pose dhToolTransform(double theta, double d) {
  const double ct = std::cos(theta), st = std::sin(theta);
  Pose T;
  T.R << ct, -st, 0.0, st, ct, 0.0, 0.0, 0.0, 1.0;
  T.p << 0.0, 0.0, d;
  return T;
}

DhModel::DhModel(const DhParams& base, std::vector<DhJoint> joints, double tool_theta, double tool_d,
                 std::string name)
    : base_(base), joints_(std::move(joints)), tool_theta_(tool_theta), tool_d_(tool_d), name_(std::move(name)) {
  auto finite = [](const DhParams& r) {
    return std::isfinite(r.theta) && std::isfinite(r.d) && std::isfinite(r.alpha) && std::isfinite(r.a) &&
           std::isfinite(r.beta) && (r.hayati() || r.beta == 0.0);
  };
  LP_CHECK(finite(base_), "base: non-finite D-H parameter");
  LP_CHECK(std::isfinite(tool_theta_) && std::isfinite(tool_d_), "tool: non-finite D-H parameter");
  for (size_t i = 0; i < joints_.size(); ++i) {
    const DhJoint& j = joints_[i];
    const std::string label = jointLabel(static_cast<int>(i), j.name);
    LP_CHECK(finite(j.link), label << ": non-finite D-H parameter");
    LP_CHECK(std::isfinite(j.pitch) && std::isfinite(j.scale) && std::isfinite(j.offset),
             label << ": non-finite pitch, scale or offset");
    LP_CHECK(j.scale > 0.0, label << ": scale must be positive, got " << j.scale);
    LP_CHECK(j.type == JointType::Helical || j.pitch == 0.0,
             label << ": pitch " << j.pitch << " given for a " << jointTypeName(j.type) << " joint");
    if (j.range) {
      LP_CHECK(std::isfinite((*j.range)[0]) && std::isfinite((*j.range)[1]) && (*j.range)[0] <= (*j.range)[1],
               label << ": range must be finite with lo <= hi");
    }
    checkJointMagnitudes(j, j.range, label);
  }
  chain_ = dhChain(base_, joints_, tool_theta_, tool_d_);
  checkChain(chain_);
  // L of the equivalent POE model: its joint lines are the chain's frames at zero motion
  const std::vector<Pose> frames = restFrames(chain_);
  std::vector<Joint> lines;
  for (size_t i = 0; i < joints_.size(); ++i) {
    lines.push_back(jointOnFrame(joints_[i], frames[i]));
    lines.back().range = joints_[i].range;
  }
  Pose T_base_tool = chain_.T_base_first;
  for (const ChainLink& link : chain_.links) T_base_tool = T_base_tool * linkPose(link);
  length_scale_ = lowpair::lengthScale(lines, T_base_tool * chain_.T_last_tool);
  checkSize(length_scale_);
}

bool jointValueWithinLimits(const JointMotion& j, double q) {
  const double x = std::abs(j.motion(q));  // NaN (q NaN or infinite) fails both comparisons
  return x <= kMaxMagnitude && std::abs(j.slideRate()) * x <= kMaxMagnitude;
}

int firstJointBeyondLimits(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  LP_CHECK(q.size() == model.dof(), "firstJointBeyondLimits: q has " << q.size() << " values, the model has "
                                                                     << model.dof() << " joints");
  for (int i = 0; i < model.dof(); ++i) {
    if (!jointValueWithinLimits(model.joint(i), q[i])) return i;
  }
  return -1;
}

}  // namespace lowpair
