#pragma once
// Helpers of the inverse kinematics tests (ik_test.cpp, ik_status_test.cpp): the robots, built in code, and
// the joint vectors they are solved at and from.
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "calibration_helpers.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"

namespace ik_helpers {

using namespace lowpair;
using Range = std::array<double, 2>;

// ---- robots, built in code ------------------------------------------------------------------------------

inline DhModel dhRobot(const std::vector<DhParams>& rows, const std::vector<Range>& ranges, const std::string& name,
                       double tool_d = 0.0, int prismatic = -1) {
  std::vector<DhJoint> joints(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    joints[i].link = rows[i];
    joints[i].range = ranges[i];
    if (static_cast<int>(i) == prismatic) joints[i].type = JointType::Prismatic;
  }
  return DhModel(DhParams{}, joints, 0.0, tool_d, name);
}

// PUMA 560, Corke mdl_puma560 (models/puma560_corke.yaml), with its joint ranges.
inline PoeModel puma() {
  return dhToPoe(dhRobot({{0, 0, M_PI / 2, 0}, {0, 0, 0, 0.4318}, {0, 0.15005, -M_PI / 2, 0.0203},
                          {0, 0.4318, M_PI / 2, 0}, {0, 0, -M_PI / 2, 0}, {0, 0, 0, 0}},
                         {{-2.792526803190927, 2.792526803190927}, {-0.7853981633974483, 3.9269908169872414},
                          {-3.9269908169872414, 0.7853981633974483}, {-1.9198621771937625, 2.9670597283903604},
                          {-1.7453292519943295, 1.7453292519943295}, {-4.642575810304916, 4.642575810304916}},
                         "puma560"));
}

// Stanford arm, Corke mdl_stanford (models/stanford_corke.yaml): joint 3 prismatic.
inline PoeModel stanford() {
  const double r = 2.9670597283903604;
  return dhToPoe(dhRobot({{0, 0.412, -M_PI / 2, 0}, {0, 0.154, M_PI / 2, 0}, {-M_PI / 2, 0, 0, 0},
                          {0, 0, -M_PI / 2, 0}, {0, 0, M_PI / 2, 0}, {0, 0, 0, 0}},
                         {{-r, r}, {-r, r}, {0.3048, 1.27}, {-r, r}, {-M_PI / 2, M_PI / 2}, {-r, r}}, "stanford", 0.263, 2));
}

// The Stanford arm with a helical joint 1 (a screw column: 0.05 m per rad) besides its prismatic joint 3.
inline PoeModel stanfordHelical() {
  const double r = 2.9670597283903604;
  std::vector<DhJoint> joints(6);
  const std::vector<DhParams> rows{{0, 0.412, -M_PI / 2, 0}, {0, 0.154, M_PI / 2, 0}, {-M_PI / 2, 0, 0, 0},
                                   {0, 0, -M_PI / 2, 0},     {0, 0, M_PI / 2, 0},     {0, 0, 0, 0}};
  const std::vector<Range> ranges{{-r, r}, {-r, r}, {0.3048, 1.27}, {-r, r}, {-M_PI / 2, M_PI / 2}, {-r, r}};
  for (size_t i = 0; i < 6; ++i) {
    joints[i].link = rows[i];
    joints[i].range = ranges[i];
  }
  joints[0].type = JointType::Helical;
  joints[0].pitch = 0.05;
  joints[2].type = JointType::Prismatic;
  return dhToPoe(DhModel(DhParams{}, joints, 0.0, 0.263, "stanford-h"));
}

// PUMA 560, Okamura-Park actual parameters (models/puma560_okamura_actual.yaml, mm): joints 3-6 helical,
// unnormalized twists (joint scales |w| != 1), no ranges.
inline PoeModel okamuraActual() {
  const double t[6][6] = {{0.04, -0.02, 0.999, 0.02, 0.04, 0},         {0, -1.00002, 0, -0.02, 0, 0.05},
                          {0.178, -0.984, -0.001, -0.07, 0.009, -101}, {0.062, 0.013, -0.998, -51, 249, 0.0752},
                          {0.001, -1.00004, 0, -20.6, -0.0206, -249},  {0.095, 0.031, -0.995, -51, 249, 0}};
  std::vector<JointSpec> joints(6);
  for (int i = 0; i < 6; ++i) joints[i].twist = Eigen::Map<const Vec6>(t[i]);
  Vec6 tool;
  tool << 0.02, -0.01, 0.01, 249, 51, -20.6;
  return PoeModel::fromToolTwist(joints, tool, "okamura");
}

// A 7-joint arm (KUKA iiwa-like D-H), ranges +-170 / +-120 / +-175 deg.
inline PoeModel sevenJoint() {
  const double a = 170 * M_PI / 180, b = 120 * M_PI / 180, c = 175 * M_PI / 180;
  return dhToPoe(dhRobot({{0, 0.34, -M_PI / 2, 0}, {0, 0, M_PI / 2, 0}, {0, 0.4, M_PI / 2, 0}, {0, 0, -M_PI / 2, 0},
                          {0, 0.4, -M_PI / 2, 0}, {0, 0, M_PI / 2, 0}, {0, 0.126, 0, 0}},
                         {{-a, a}, {-b, b}, {-a, a}, {-b, b}, {-a, a}, {-b, b}, {-c, c}}, "seven", 0.0));
}

// Six joints of every type on generic lines (calibration_helpers jointMix): revolute, helical, prismatic,
// joint scales 0.5-2 and offsets; ranges on the prismatic joints only.
inline PoeModel mixed() {
  std::mt19937_64 rng(11);
  return calibration_helpers::jointMix("RHPRHR", 1.0, rng);
}

// A planar arm in the xy plane: revolute joints about z through (0,0,0), (1,0,0), ...; the tool at (n,0,0).
inline PoeModel planar(int n, const std::vector<std::optional<Range>>& ranges = {}) {
  std::vector<JointSpec> joints(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    joints[i].twist << 0, 0, 1, 0, -static_cast<double>(i), 0;  // v = -w x c, c = (i, 0, 0)
    if (static_cast<size_t>(i) < ranges.size()) joints[i].range = ranges[i];
  }
  Pose tool;
  tool.p << n, 0, 0;
  return PoeModel(joints, tool, "planar");
}

// ---- sampling --------------------------------------------------------------------------------------------

// q uniform in each joint's range; [-pi, pi] (revolute, helical) or [-L, L] (prismatic) without one.
inline VecX sampleQ(const PoeModel& model, std::mt19937_64& rng) {
  VecX q(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double w = j.type == JointType::Prismatic ? model.lengthScale() : M_PI;
    const Range r = j.range ? *j.range : Range{-w, w};
    q[i] = std::uniform_real_distribution<double>(r[0], r[1])(rng);
  }
  return q;
}

// q moved by 0.3 per joint in a random direction (+ or -), in the joint's motion: 0.3 rad for revolute and
// helical joints, 0.3 L for prismatic ones (divided by the joint's scale).
inline VecX seedNear(const PoeModel& model, const VecX& q, std::mt19937_64& rng) {
  VecX seed = q;
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double unit = (j.type == JointType::Prismatic ? model.lengthScale() : 1.0) / j.scale;
    seed[i] += ((rng() & 1) ? 0.3 : -0.3) * unit;
  }
  return seed;
}

}  // namespace ik_helpers
