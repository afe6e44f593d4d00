#include "lowpair/kinematics.hpp"

#include <algorithm>
#include <cmath>

#include "lowpair/check.hpp"
#include "lowpair/se3.hpp"
#include "sincos.hpp"

namespace lowpair {

Data::Data(const KinematicChain& chain)
    : dof(static_cast<int>(chain.links.size())),
      T_base_joint(chain.links.size()),
      J_spatial(6, dof),
      angle(dof),
      sin_angle(dof),
      cos_angle(dof),
      slide(dof) {
  J_spatial.setZero();
}
Data::Data(const PoeModel& model) : Data(model.chain()) {}
Data::Data(const DhModel& model) : Data(model.chain()) {}

void checkJointVector(const Eigen::Ref<const VecX>& q, int dof) {
  LP_CHECK(q.size() == dof, "expected " << dof << " joint values, got " << q.size());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    LP_CHECK(std::isfinite(q[i]), "joint value " << i + 1 << " is not finite");
  }
}

void jointExp(const Joint& joint, double q, Pose& out) {
  const double x = joint.motion(q);
  if (joint.type == JointType::Prismatic) {
    out.R.setIdentity();
    out.p.noalias() = x * joint.twist.tail<3>();
  } else {
    expUnitTwist(joint.twist.head<3>(), joint.twist.tail<3>(), joint.pitch, x, out);
  }
}

namespace {

using detail::sinCosLane;

// sin and cos of n angles together (the loop vectorizes); angles beyond the kernel's accurate range
// (possible only for huge joint values) are recomputed with libm.
void sinCosAll(const double* angle, int n, double* s, double* c) {
  double largest = 0.0;
  for (int i = 0; i < n; ++i) {
    sinCosLane(angle[i], s[i], c[i]);
    largest = std::max(largest, std::abs(angle[i]));
  }
  if (!(largest <= detail::kSinCosMaxArgument)) {
    for (int i = 0; i < n; ++i) {
      s[i] = std::sin(angle[i]);
      c[i] = std::cos(angle[i]);
    }
  }
}

// The chain product of model.hpp's KinematicChain. Columns X, Y, Z of the rotation and the position P
// are updated in place by T <- T Rz(angle) Trans(p + slide e_z) Rx(alpha); kFrames stores the frame
// before each link (joint i's line) in data.T_base_joint.
template <bool kFrames>
void evaluate(const KinematicChain& chain, Data& data, const double* q) {
  const int n = data.dof;
  double* angle = data.angle.data();
  double* slide = data.slide.data();
  for (int i = 0; i < n; ++i) {
    const ChainLink& link = chain.links[static_cast<size_t>(i)];
    const double x = link.motion.motion(q[i]);
    angle[i] = link.theta + link.motion.turnRate() * x;
    slide[i] = link.p[2] + link.motion.slideRate() * x;
  }
  sinCosAll(angle, n, data.sin_angle.data(), data.cos_angle.data());
  const double* st = data.sin_angle.data();
  const double* ct = data.cos_angle.data();
  double X[3], Y[3], Z[3], P[3];
  const Pose& B = chain.T_base_first;
  for (int k = 0; k < 3; ++k) {
    X[k] = B.R(k, 0);
    Y[k] = B.R(k, 1);
    Z[k] = B.R(k, 2);
    P[k] = B.p[k];
  }
  for (int i = 0; i < n; ++i) {
    const ChainLink& link = chain.links[static_cast<size_t>(i)];
    if (kFrames) {
      Pose& F = data.T_base_joint[static_cast<size_t>(i)];
      for (int k = 0; k < 3; ++k) {
        F.R(k, 0) = X[k];
        F.R(k, 1) = Y[k];
        F.R(k, 2) = Z[k];
        F.p[k] = P[k];
      }
    }
    const double px = link.p[0], py = link.p[1], pz = slide[i];
    const double ca = link.cos_alpha, sa = link.sin_alpha;
    for (int k = 0; k < 3; ++k) {
      const double x = ct[i] * X[k] + st[i] * Y[k];
      const double y = ct[i] * Y[k] - st[i] * X[k];
      const double z = Z[k];
      P[k] += (px * x + py * y) + pz * z;
      X[k] = x;
      Y[k] = ca * y + sa * z;
      Z[k] = ca * z - sa * y;
    }
  }
  const Pose& E = chain.T_last_tool;
  Pose& T = data.T_base_tool;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) T.R(k, m) = (X[k] * E.R(0, m) + Y[k] * E.R(1, m)) + Z[k] * E.R(2, m);
    T.p[k] = ((X[k] * E.p[0] + Y[k] * E.p[1]) + Z[k] * E.p[2]) + P[k];
  }
}

// Lanes of one batch block: configurations evaluated together, every inner loop over the lanes.
constexpr int kBlock = 8;

void evaluateBlock(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses,
                   Eigen::Index first, int lanes) {
  constexpr int B = kBlock;
  alignas(64) double X[3][B], Y[3][B], Z[3][B], P[3][B];
  alignas(64) double angle[B], st[B], ct[B], slide[B];
  const Pose& Bs = chain.T_base_first;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < B; ++l) {
      X[k][l] = Bs.R(k, 0);
      Y[k][l] = Bs.R(k, 1);
      Z[k][l] = Bs.R(k, 2);
      P[k][l] = Bs.p[k];
    }
  }
  for (size_t i = 0; i < chain.links.size(); ++i) {
    const ChainLink& link = chain.links[i];
    const double* qi = q.col(static_cast<Eigen::Index>(i)).data() + first;
    const double turn = link.motion.turnRate(), slide_rate = link.motion.slideRate();
    double largest = 0.0;
    for (int l = 0; l < B; ++l) {
      const double x = link.motion.motion(l < lanes ? qi[l] : 0.0);
      angle[l] = link.theta + turn * x;
      slide[l] = link.p[2] + slide_rate * x;
      largest = std::max(largest, std::abs(angle[l]));
    }
    for (int l = 0; l < B; ++l) sinCosLane(angle[l], st[l], ct[l]);
    if (!(largest <= detail::kSinCosMaxArgument)) {
      for (int l = 0; l < B; ++l) {
        st[l] = std::sin(angle[l]);
        ct[l] = std::cos(angle[l]);
      }
    }
    const double px = link.p[0], py = link.p[1], ca = link.cos_alpha, sa = link.sin_alpha;
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < B; ++l) {
        const double x = ct[l] * X[k][l] + st[l] * Y[k][l];
        const double y = ct[l] * Y[k][l] - st[l] * X[k][l];
        const double z = Z[k][l];
        P[k][l] += (px * x + py * y) + slide[l] * z;
        X[k][l] = x;
        Y[k][l] = ca * y + sa * z;
        Z[k][l] = ca * z - sa * y;
      }
    }
  }
  const Pose& E = chain.T_last_tool;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) {
      double* out = poses.col(3 * k + m).data() + first;
      for (int l = 0; l < lanes; ++l) out[l] = (X[k][l] * E.R(0, m) + Y[k][l] * E.R(1, m)) + Z[k][l] * E.R(2, m);
    }
    double* out = poses.col(9 + k).data() + first;
    for (int l = 0; l < lanes; ++l) out[l] = ((X[k][l] * E.p[0] + Y[k][l] * E.p[1]) + Z[k][l] * E.p[2]) + P[k][l];
  }
}

void evaluateBatch(const KinematicChain& chain, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  LP_CHECK(q.cols() == static_cast<Eigen::Index>(chain.links.size()),
           "forwardKinematicsBatch: q has " << q.cols() << " columns for " << chain.links.size() << " joints");
  LP_CHECK(poses.rows() == q.rows() && poses.cols() == 12,
           "forwardKinematicsBatch: poses must be " << q.rows() << " x 12, got " << poses.rows() << " x " << poses.cols());
  for (Eigen::Index first = 0; first < q.rows(); first += kBlock) {
    const int lanes = static_cast<int>(std::min<Eigen::Index>(kBlock, q.rows() - first));
    evaluateBlock(chain, q, poses, first, lanes);
  }
}

}  // namespace

void forwardKinematics(const PoeModel& model, Data& data, const Eigen::Ref<const VecX>& q) {
  LP_ASSERT(q.size() == model.dof() && data.dof == model.dof());
  evaluate<true>(model.chain(), data, q.data());
}

void forwardKinematics(const DhModel& model, Data& data, const Eigen::Ref<const VecX>& q) {
  LP_ASSERT(q.size() == model.dof() && data.dof == model.dof());
  evaluate<true>(model.chain(), data, q.data());
}

void forwardKinematicsBatch(const PoeModel& model, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  evaluateBatch(model.chain(), q, poses);
}

void forwardKinematicsBatch(const DhModel& model, const Eigen::Ref<const MatX>& q, Eigen::Ref<MatX> poses) {
  evaluateBatch(model.chain(), q, poses);
}

Pose poeForwardKinematics(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  Data data(model);
  forwardKinematics(model, data, q);
  return data.T_base_tool;
}

Pose dhForwardKinematics(const DhModel& model, const Eigen::Ref<const VecX>& q) {
  Data data(model);
  forwardKinematics(model, data, q);
  return data.T_base_tool;
}

namespace {
Joint transformed(const Joint& j, const Pose& T_new_old) {
  Joint out = j;
  out.twist = adjointApply(T_new_old, j.twist);
  return out;
}
}  // namespace

ToolPoeModel toToolPoe(const PoeModel& model) {
  ToolPoeModel out;
  out.tool_pose = model.toolPose();
  const Pose T_tool_base = model.toolPose().inverse();
  for (const Joint& j : model.joints()) out.joints.push_back(transformed(j, T_tool_base));
  return out;
}

PoeModel fromToolPoe(const ToolPoeModel& model, const std::string& name) {
  std::vector<Joint> joints;
  for (const Joint& j : model.joints) joints.push_back(transformed(j, model.tool_pose));
  return PoeModel(std::move(joints), model.tool_pose, name);
}

LocalPoeModel toLocalPoe(const PoeModel& model) {
  std::vector<Pose> frames;
  for (const Joint& j : model.joints()) {
    const bool prismatic = j.type == JointType::Prismatic;
    const Vec3 z = prismatic ? j.moment() : j.axis();
    Pose G;
    G.p = prismatic ? Vec3::Zero() : Vec3(j.axis().cross(j.moment()));
    // x: perpendicular to z, built from the base axis least aligned with z (deterministic).
    Eigen::Index k = 0;
    z.cwiseAbs().minCoeff(&k);
    const Vec3 x = z.cross(Vec3::Unit(k)).normalized();
    G.R.col(0) = x;
    G.R.col(1) = z.cross(x);
    G.R.col(2) = z;
    frames.push_back(G);
  }
  return toLocalPoe(model, frames);
}

LocalPoeModel toLocalPoe(const PoeModel& model, const std::vector<Pose>& T_base_link) {
  LP_CHECK(static_cast<int>(T_base_link.size()) == model.dof(),
           "toLocalPoe: expected " << model.dof() << " link frames, got " << T_base_link.size());
  LocalPoeModel out;
  Pose prev;  // identity
  for (int i = 0; i < model.dof(); ++i) {
    const Pose& G = T_base_link[static_cast<size_t>(i)];
    out.frames.push_back(prev.inverse() * G);
    out.joints.push_back(transformed(model.joint(i), G.inverse()));
    prev = G;
  }
  out.frames.push_back(prev.inverse() * model.toolPose());
  return out;
}

PoeModel fromLocalPoe(const LocalPoeModel& model, const std::string& name) {
  LP_CHECK(model.frames.size() == model.joints.size() + 1, "fromLocalPoe: need n + 1 frames for n joints");
  std::vector<Joint> joints;
  Pose G;
  for (size_t i = 0; i < model.joints.size(); ++i) {
    G = G * model.frames[i];
    joints.push_back(transformed(model.joints[i], G));
  }
  return PoeModel(std::move(joints), G * model.frames.back(), name);
}

Pose forwardKinematics(const ToolPoeModel& model, const Eigen::Ref<const VecX>& q) {
  Pose T = model.tool_pose;
  Pose step;
  for (size_t i = 0; i < model.joints.size(); ++i) {
    jointExp(model.joints[i], q[static_cast<Eigen::Index>(i)], step);
    T = T * step;
  }
  return T;
}

Pose forwardKinematics(const LocalPoeModel& model, const Eigen::Ref<const VecX>& q) {
  Pose T;
  Pose step;
  for (size_t i = 0; i < model.joints.size(); ++i) {
    jointExp(model.joints[i], q[static_cast<Eigen::Index>(i)], step);
    T = T * model.frames[i] * step;
  }
  return T * model.frames.back();
}

double rotationError(const Mat3& Ra, const Mat3& Rb) {
  const Mat3 E = Ra.transpose() * Rb;
  return rotationAngle(E);
}

double eulerZyxError(const Mat3& Ra, const Mat3& Rb) {
  const Mat3 E = Ra.transpose() * Rb;
  // E = Rz(a) Ry(b) Rx(c)
  const double b = std::atan2(-E(2, 0), std::hypot(E(0, 0), E(1, 0)));
  const double a = std::atan2(E(1, 0), E(0, 0));
  const double c = std::atan2(E(2, 1), E(2, 2));
  return std::sqrt(a * a + b * b + c * c);
}

}  // namespace lowpair
