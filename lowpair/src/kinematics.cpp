#include "lowpair/kinematics.hpp"

#include <cmath>

#include "lowpair/check.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

PoeData::PoeData(const PoeModel& model) : T_base_joint(static_cast<size_t>(model.dof())) {}
DhData::DhData(const DhModel& model) : T_base_frame(static_cast<size_t>(model.dof())) {}

void checkJointVector(const Eigen::Ref<const VecX>& q, int dof) {
  LP_CHECK(q.size() == dof, "expected " << dof << " joint values, got " << q.size());
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    LP_CHECK(std::isfinite(q[i]), "joint value " << i + 1 << " is not finite");
  }
}

void jointExp(const Joint& joint, double q, Pose& out) {
  const double x = joint.scale * (q + joint.offset);
  if (joint.type == JointType::Prismatic) {
    out.R.setIdentity();
    out.p.noalias() = x * joint.twist.tail<3>();
  } else {
    expUnitTwist(joint.twist.head<3>(), joint.twist.tail<3>(), joint.pitch, x, out);
  }
}

void forwardKinematics(const PoeModel& model, PoeData& data, const Eigen::Ref<const VecX>& q) {
  LP_ASSERT(q.size() == model.dof());
  Pose step;
  Pose T;  // identity
  for (int i = 0; i < model.dof(); ++i) {
    jointExp(model.joint(i), q[i], step);
    T = T * step;
    data.T_base_joint[static_cast<size_t>(i)] = T;
  }
  data.T_base_tool = T * model.toolPose();
}

void forwardKinematics(const DhModel& model, DhData& data, const Eigen::Ref<const VecX>& q) {
  LP_ASSERT(q.size() == model.dof());
  Pose T = dhTransform(model.base());
  for (int i = 0; i < model.dof(); ++i) {
    const DhJoint& j = model.joint(i);
    data.T_base_frame[static_cast<size_t>(i)] = T;
    const double x = j.scale * q[i];
    DhParams row = j.link;
    if (j.type == JointType::Prismatic) {
      row.d += x;
    } else {
      row.theta += x;
      if (j.type == JointType::Helical) row.d += j.pitch * x;
    }
    T = T * dhTransform(row);
  }
  data.T_base_tool = T * dhToolTransform(model.toolTheta(), model.toolD());
}

Pose poeForwardKinematics(const PoeModel& model, const Eigen::Ref<const VecX>& q) {
  PoeData data(model);
  forwardKinematics(model, data, q);
  return data.T_base_tool;
}

Pose dhForwardKinematics(const DhModel& model, const Eigen::Ref<const VecX>& q) {
  DhData data(model);
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
