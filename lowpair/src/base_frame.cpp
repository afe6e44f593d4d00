#include "lowpair/base_frame.hpp"

#include <cmath>

#include "check.hpp"
#include "lowpair/registration.hpp"

namespace lowpair {

namespace {

// A joint's unit direction: the axis (revolute/helical) or the direction (prismatic).
Vec3 direction(const Joint& j) { return j.type == JointType::Prismatic ? j.moment() : j.axis(); }

// The point of a revolute/helical joint's axis nearest the origin: w x v (|w| = 1, v = p x w + h w).
Vec3 axisPoint(const Joint& j) { return j.axis().cross(j.moment()); }

// Joint 1's line: a point on it and its unit direction (a prismatic joint 1: through the tool point).
struct Line {
  Vec3 point, direction;
};
Line firstLine(const PoeModel& m) {
  const Joint& j = m.joint(0);
  return {j.type == JointType::Prismatic ? m.toolPose().p : axisPoint(j), direction(j)};
}

bool parallel(const Vec3& a, const Vec3& b) { return a.cross(b).norm() <= kBaseFrameParallel; }

// `v` made perpendicular to the unit `z`.
Vec3 perpendicular(const Vec3& v, const Vec3& z) { return v - z * z.dot(v); }

}  // namespace

BaseFrameRule baseFrameRule(const PoeModel& nominal) {
  LP_CHECK(nominal.dof() >= 1, "baseFrameRule: the model has no joint");
  const Line line = firstLine(nominal);
  BaseFrameRule rule;
  for (int k = 1; k < nominal.dof(); ++k) {
    const Joint& j = nominal.joint(k);
    if (parallel(line.direction, direction(j))) continue;
    if (rule.direction_joint < 0) rule.direction_joint = k;
    if (rule.foot_joint < 0 && j.type != JointType::Prismatic) rule.foot_joint = k;
  }
  if (rule.direction_joint < 0) {
    const double L = nominal.lengthScale();
    const Vec3& t = nominal.toolPose().p;
    const Mat3& R = nominal.toolPose().R;
    if (perpendicular(t - line.point, line.direction).norm() > kBaseFrameParallel * L) {
      rule.fallback = BaseFrameRule::XFallback::ToolPoint;
    } else if (perpendicular(R.col(0), line.direction).norm() >= perpendicular(R.col(1), line.direction).norm()) {
      rule.fallback = BaseFrameRule::XFallback::ToolX;
    } else {
      rule.fallback = BaseFrameRule::XFallback::ToolY;
    }
  }
  return rule;
}

Pose baseFrame(const PoeModel& model, const BaseFrameRule& rule) {
  LP_CHECK(rule.foot_joint < model.dof() && rule.direction_joint < model.dof(),
           "baseFrame: the rule names joint " << std::max(rule.foot_joint, rule.direction_joint) + 1 << " of a "
                                              << model.dof() << "-joint model");
  const Line line = firstLine(model);
  const Vec3& z = line.direction;
  Vec3 origin;
  if (rule.foot_joint >= 0) {  // foot on line 1 of the common normal to axis k: (c_k - c_1) x d_k . n / |n|^2
    const Joint& j = model.joint(rule.foot_joint);
    const Vec3 n = z.cross(j.axis());
    origin = line.point + z * ((axisPoint(j) - line.point).cross(j.axis()).dot(n) / n.squaredNorm());
  } else {
    origin = line.point + z * z.dot(model.toolPose().p - line.point);
  }
  Vec3 x;
  if (rule.direction_joint >= 0) {
    x = z.cross(direction(model.joint(rule.direction_joint)));
  } else {
    switch (rule.fallback) {
      case BaseFrameRule::XFallback::ToolPoint: x = perpendicular(model.toolPose().p - origin, z); break;
      case BaseFrameRule::XFallback::ToolY: x = perpendicular(model.toolPose().R.col(1), z); break;
      default: x = perpendicular(model.toolPose().R.col(0), z); break;
    }
  }
  x.normalize();
  Pose F;
  F.R.col(0) = x;
  F.R.col(1) = z.cross(x);
  F.R.col(2) = z;
  F.p = origin;
  return F;
}

BaseFrameGauge toNominalBase(const PoeModel& model, const PoeModel& nominal, const BaseFrameRule& rule) {
  LP_CHECK(model.dof() == nominal.dof(), "toNominalBase: " << model.dof() << " joints against the nominal's "
                                                            << nominal.dof());
  const Pose T_measurement_base = baseFrame(model, rule) * baseFrame(nominal, rule).inverse();
  return {rule, T_measurement_base, movedModel(model, T_measurement_base.inverse())};
}

BaseFrameGauge toNominalBase(const PoeModel& model, const PoeModel& nominal) {
  return toNominalBase(model, nominal, baseFrameRule(nominal));
}

}  // namespace lowpair
