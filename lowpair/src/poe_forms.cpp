// The POE model's other forms (kinematics.hpp): the tool and local POE models, their conversions and forward
// kinematics, and the rotation error measures. Not the hot path (kinematics.cpp's chain kernel).
#include <cmath>
#include <string>
#include <vector>

#include "check.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

using detail::counted;

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

namespace {
void checkFormSizes(Eigen::Index q_size, size_t joints) {
  const auto n = static_cast<Eigen::Index>(joints);
  LP_CHECK(q_size == n, "forwardKinematics: q has " << counted(q_size, "value") << ", the model has " << counted(n, "joint"));
}
}  // namespace

Pose forwardKinematics(const ToolPoeModel& model, const Eigen::Ref<const VecX>& q) {
  checkFormSizes(q.size(), model.joints.size());
  Pose T = model.tool_pose;
  Pose step;
  for (size_t i = 0; i < model.joints.size(); ++i) {
    jointExp(model.joints[i], q[static_cast<Eigen::Index>(i)], step);
    T = T * step;
  }
  return T;
}

Pose forwardKinematics(const LocalPoeModel& model, const Eigen::Ref<const VecX>& q) {
  checkFormSizes(q.size(), model.joints.size());
  LP_CHECK(model.frames.size() == model.joints.size() + 1, "forwardKinematics: the local POE model has "
                                                               << model.frames.size() << " frames for "
                                                               << model.joints.size() << " joints (n + 1 needed)");
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
