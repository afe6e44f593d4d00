// Singularity analysis (Paden & Sastry 1984) on the project's robot files: every singular pose of
// robots.md §1.4, §2, §3, §4, solved exactly from the closed forms (robots.md §7), is rank deficient and
// reported with its listed classes; the poses printed in rounded degrees are regular; on 10,000 random
// poses per 6-joint robot a class is reported exactly when the rank is deficient, and the wrist/arm split
// of §5 agrees with the rank.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <string>

#include <Eigen/Eigenvalues>

#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "random_robot.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

using namespace lowpair;

namespace {

constexpr double kDeg = M_PI / 180.0;

RobotFile robot(const std::string& file) { return readRobotFile(std::string(LOWPAIR_MODELS) + "/" + file); }

VecX vec(std::initializer_list<double> values) {
  VecX q(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double x : values) q[i++] = x;
  return q;
}

struct Expected {
  std::string id;
  std::vector<int> joints;  // 1-based; empty: any
};

struct Pose6 {
  std::string file, label;
  VecX q;
  std::vector<Expected> expected;  // empty: regular
  enum class Split { None, Wrist, Arm } split = Split::None;
};

std::string classesText(const SingularityReport& r) {
  std::string s;
  for (const SingularClass& c : r.classes) {
    s += (s.empty() ? "" : " ") + c.id + "(";
    for (size_t k = 0; k < c.joints.size(); ++k) s += (k ? "," : "") + std::to_string(c.joints[k]);
    s += ")";
  }
  return s.empty() ? "-" : s;
}

std::string expectedText(const std::vector<Expected>& e) {
  std::string s;
  for (const Expected& x : e) {
    s += (s.empty() ? "" : " ") + x.id;
    if (!x.joints.empty()) {
      s += "(";
      for (size_t k = 0; k < x.joints.size(); ++k) s += (k ? "," : "") + std::to_string(x.joints[k]);
      s += ")";
    }
  }
  return s.empty() ? "regular" : s;
}

bool reported(const SingularityReport& r, const Expected& e) {
  for (const SingularClass& c : r.classes) {
    if (c.id == e.id && (e.joints.empty() || c.joints == e.joints)) return true;
  }
  return false;
}

// PUMA 560 (Corke standard D-H, robots.md §1.4): det J = -a2 (a3 s3 + d4 c3)(a2 c2 + a3 c23 - d4 s23) s5.
std::vector<Pose6> pumaCorkePoses(const std::string& file) {
  const RobotFile dh = robot("puma560_corke.yaml");  // the D-H numbers, also for the POE file
  const double a2 = dh.dh->joint(1).link.a, a3 = dh.dh->joint(2).link.a, d4 = dh.dh->joint(3).link.d;
  // shoulder: c2 (a2 + a3 c3 - d4 s3) - s2 (a3 s3 + d4 c3) = 0
  auto shoulder = [&](double q3, bool other_root) {
    const double A = a2 + a3 * std::cos(q3) - d4 * std::sin(q3), B = a3 * std::sin(q3) + d4 * std::cos(q3);
    return other_root ? std::atan2(-A, -B) : std::atan2(A, B);
  };
  const double elbow_stretched = std::atan2(-d4, a3), elbow_folded = std::atan2(d4, -a3);
  using S = Pose6::Split;
  return {
      {file, "qz = 0 (wrist)", vec({0, 0, 0, 0, 0, 0}), {{"C1", {4, 6}}}, S::Wrist},
      {file, "qr (wrist)", vec({0, M_PI / 2, -M_PI / 2, 0, 0, 0}), {{"C1", {4, 6}}}, S::Wrist},
      {file, "qs (wrist)", vec({0, 0, -M_PI / 2, 0, 0, 0}), {{"C1", {4, 6}}}, S::Wrist},
      {file, "wrist q5 = 0", vec({0.3, 0.5, -0.4, 0.7, 0, 0.2}), {{"C1", {4, 6}}}, S::Wrist},
      {file, "elbow stretched", vec({0.3, 0.5, elbow_stretched, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {file, "elbow folded", vec({0.3, 0.5, elbow_folded, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {file, "elbow, q4 = 0", vec({0.3, 0.5, elbow_stretched, 0, 0.6, 0.2}), {{"C2", {2, 3, 5}}}, S::Arm},
      {file, "shoulder q3 = 0", vec({0.3, shoulder(0, false), 0, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {file, "shoulder q3 = 0 (2nd)", vec({0.3, shoulder(0, true), 0, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {file, "shoulder q3 = -90", vec({0.3, shoulder(-M_PI / 2, false), -M_PI / 2, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {file, "shoulder q3 = -90 (2nd)", vec({0.3, shoulder(-M_PI / 2, true), -M_PI / 2, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {file, "qn (regular)", vec({0, M_PI / 4, M_PI, 0, M_PI / 4, 0}), {}, S::None},
      {file, "elbow -87.308 deg printed", vec({0.3, 0.5, -87.308 * kDeg, 0.7, 0.6, 0.2}), {}, S::None},
      {file, "shoulder 46.316 deg printed", vec({0.3, 46.316 * kDeg, 0, 0.7, 0.6, 0.2}), {}, S::None},
  };
}

std::vector<Pose6> listedPoses() {
  using S = Pose6::Split;
  std::vector<Pose6> poses = pumaCorkePoses("puma560_corke.yaml");
  for (Pose6& p : pumaCorkePoses("puma560_corke_poe.yaml")) poses.push_back(p);

  // Okamura-Park nominal (§1.4): det J = -100 (150 s3 - 20 c3)(100 c2 + 150 c23 + 20 s23) s5.
  const std::string ok = "puma560_okamura_nominal.yaml";
  auto ok_shoulder = [](double q3, bool other_root) {  // c2 A + s2 B = 0
    const double A = 100 + 150 * std::cos(q3) + 20 * std::sin(q3), B = 20 * std::cos(q3) - 150 * std::sin(q3);
    return other_root ? std::atan2(A, -B) : std::atan2(-A, B);
  };
  const double ok_elbow = std::atan2(20.0, 150.0), ok_folded = std::atan2(-20.0, -150.0);
  const std::vector<Pose6> okamura = {
      {ok, "q = 0 (wrist)", vec({0, 0, 0, 0, 0, 0}), {{"C1", {4, 6}}}, S::Wrist},
      {ok, "wrist q5 = 0", vec({0.3, 0.5, -0.4, 0.7, 0, 0.2}), {{"C1", {4, 6}}}, S::Wrist},
      {ok, "elbow stretched", vec({0.3, 0.5, ok_elbow, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {ok, "elbow folded", vec({0.3, 0.5, ok_folded, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {ok, "elbow, q4 = 0", vec({0.3, 0.5, ok_elbow, 0, 0.6, 0.2}), {{"C2", {2, 3, 5}}}, S::Arm},
      {ok, "shoulder q3 = 0", vec({0.3, ok_shoulder(0, false), 0, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {ok, "shoulder q3 = 0 (2nd)", vec({0.3, ok_shoulder(0, true), 0, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {ok, "shoulder q3 = 0.4", vec({0.3, ok_shoulder(0.4, false), 0.4, 0.7, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {ok, "elbow 7.595 deg printed", vec({0.3, 0.5, 7.595 * kDeg, 0.7, 0.6, 0.2}), {}, S::None},
      {ok, "shoulder -85.426 deg printed", vec({0.3, -85.426 * kDeg, 0, 0.7, 0.6, 0.2}), {}, S::None},
  };
  poses.insert(poses.end(), okamura.begin(), okamura.end());

  // Stanford (§2.1): det J = -q3^2 sin q2 sin q5. Paden-Sastry's example 5 (C5) is q2 = 0 with axis 5
  // turned into the plane of axes 1, 2 and 4 (added below).
  const std::string st = "stanford_corke.yaml";
  const std::vector<Pose6> stanford = {
      {st, "wrist q5 = 0", vec({0.3, 0.7, 0.6, 0.4, 0, 0.2}), {{"C1", {4, 6}}}, S::Wrist},
      {st, "q2 = 0 (prismatic C6-like)", vec({0.3, 0, 0.6, 0.4, 0.5, 0.2}), {{"other", {}}}, S::Arm},
      {st, "regular pose", vec({0, M_PI / 4, 0.6, 0, M_PI / 4, 0}), {}, S::None},
  };
  poses.insert(poses.end(), stanford.begin(), stanford.end());

  // MLS elbow, l0 = l1 = l2 = 1 (§3): det J = l1 l2 sin q3 (l1 cos q2 + l2 cos(q2 + q3)) cos q5.
  const std::string el = "elbow_mls.yaml";
  const double l1 = 1.0, l2 = 1.0, q3 = 1.0;
  const double el_shoulder = std::atan2(l1 + l2 * std::cos(q3), l2 * std::sin(q3));
  const std::vector<Pose6> elbow = {
      {el, "wrist q5 = pi/2", vec({0.3, 0.5, 0.7, 0.4, M_PI / 2, 0.2}), {{"C1", {4, 6}}}, S::Wrist},
      {el, "q = 0 (elbow, q4 = 0)", vec({0, 0, 0, 0, 0, 0}), {{"C2", {2, 3, 5}}}, S::Arm},
      {el, "elbow straight", vec({0.3, 0.5, 0, 0.4, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {el, "elbow folded", vec({0.3, 0.5, M_PI, 0.4, 0.6, 0.2}), {{"C6", {}}}, S::Arm},
      {el, "shoulder (W on axis 1)", vec({0.3, el_shoulder, q3, 0.4, 0.6, 0.2}), {{"C3", {1, 4, 5, 6}}}, S::Arm},
  };
  poses.insert(poses.end(), elbow.begin(), elbow.end());

  // Rhino on the slide (§4.2), joints: slide, j1..j5. det J = -a2 a3 cos q1 sin q3 sin(q2 + q3 + q4).
  const std::string rh = "rhino_xr3_slide.yaml";
  const double a3 = 22.86, a4 = 0.95;
  const double c1_q2 = -M_PI / 2, c1_q3 = std::atan2(-a4, std::sqrt(a3 * a3 - a4 * a4));  // a3 sin q3 = -a4
  const std::vector<Pose6> rhino = {
      {rh, "q = 0", vec({0, 0, 0, 0, 0, 0}), {{"C2", {3, 4, 5}}, {"C7", {1, 2, 6}}}, S::None},
      {rh, "Schilling home, q1 = 0", vec({30, 0, -M_PI / 2, M_PI / 2, 0, -M_PI / 2}), {{"C7", {1, 2, 6}}}, S::None},
      {rh, "q1 = 0, q234 = 0", vec({30, 0, 0.5, 0.7, -1.2, 0.3}), {{"C7", {1, 2, 6}}}, S::None},
      {rh, "q3 = 0", vec({30, 0.3, 0.5, 0, 0.4, 0.2}), {{"C2", {3, 4, 5}}}, S::None},
      {rh, "cos q1 = 0", vec({30, M_PI / 2, 0.5, 0.7, 0.4, 0.3}), {{"other", {}}}, S::None},
      {rh, "q234 = 0, q1 != 0", vec({30, 0.3, 0.5, 0.7, -1.2, 0.2}), {{"other", {}}}, S::None},
      {rh, "axis 5 on axis 1", vec({30, 0.3, c1_q2, c1_q3, -c1_q2 - c1_q3, 0.2}), {{"C1", {2, 6}}}, S::None},
  };
  poses.insert(poses.end(), rhino.begin(), rhino.end());
  return poses;
}

// Stanford, Paden-Sastry example 5: q2 = 0 puts axes 1, 2 and 4 in one plane (normal z1 x z2); turn
// axis 5 about axis 4 into it: n . (cos q4 z5 + sin q4 (z4 x z5)) = 0 with z4, z5 taken at q4 = 0.
VecX stanfordCoplanar() {
  const PoeModel m = robot("stanford_corke.yaml").poeModel();
  VecX q = vec({0.3, 0, 0.6, 0, 0.5, 0.2});
  const std::vector<JointLine> lines = jointLines(m, q);
  const Vec3 n = lines[0].direction.cross(lines[1].direction);
  const Vec3 z4 = lines[3].direction, z5 = lines[4].direction;
  q[3] = std::atan2(-n.dot(z5), n.dot(z4.cross(z5)));
  return q;
}

}  // namespace

TEST(Singularity, ListedPosesAreClassified) {
  std::vector<Pose6> poses = listedPoses();
  poses.push_back({"stanford_corke.yaml", "q2 = 0, axes 1,2,4,5 coplanar", stanfordCoplanar(),
                   {{"C5", {1, 2, 4, 5}}}, Pose6::Split::Arm});
  std::printf("%-28s %-30s %-22s %-34s %4s %10s\n", "robot", "pose", "expected", "reported", "rank", "sigma_min");
  for (const Pose6& p : poses) {
    const RobotFile file = robot(p.file);
    const SingularityReport r = analyzeSingularity(file.poeModel(), p.q);
    std::printf("%-28s %-30s %-22s %-34s %4d %10.2e\n", file.name.c_str(), p.label.c_str(),
                expectedText(p.expected).c_str(), classesText(r).c_str(), r.rank, r.sigma_min);
    SCOPED_TRACE(file.name + ": " + p.label);
    if (p.expected.empty()) {
      EXPECT_FALSE(r.singular);
      EXPECT_EQ(r.rank, 6);
      EXPECT_TRUE(r.classes.empty()) << classesText(r);
      EXPECT_GT(r.sigma_min, 1e-9);
      continue;
    }
    EXPECT_TRUE(r.singular);
    EXPECT_LT(r.rank, 6);
    EXPECT_LT(r.sigma_min, 1e-14);
    for (const Expected& e : p.expected) EXPECT_TRUE(reported(r, e)) << expectedText({e}) << " not in " << classesText(r);
    if (p.expected.front().id == "other") {
      ASSERT_EQ(r.classes.size(), 1u) << classesText(r);
      EXPECT_FALSE(r.null_space.empty());
    }
    if (p.split != Pose6::Split::None) {
      ASSERT_TRUE(r.decoupled.applies);
      EXPECT_EQ(r.decoupled.wrist_joints, (std::array<int, 3>{4, 5, 6}));
      EXPECT_EQ(r.decoupled.wrist_singular, p.split == Pose6::Split::Wrist);
      EXPECT_EQ(r.decoupled.arm_singular, p.split == Pose6::Split::Arm);
    }
  }
}

namespace {
bool hasListedClass(const SingularityReport& r) {
  return std::any_of(r.classes.begin(), r.classes.end(), [](const SingularClass& c) { return c.id != "other"; });
}

// "A class is reported iff the rank is deficient" (conventions.md), both directions: a regular pose has
// no class; a rank-deficient one has at least one, each naming its joints, `other` only when no listed
// class explains the deficiency. Empty when the report keeps the rule.
std::string iffViolation(const SingularityReport& r) {
  if (!r.singular && !r.classes.empty()) return "regular, but classes " + classesText(r);
  if (r.singular && r.classes.empty()) return "rank deficient, but no class";
  for (const SingularClass& c : r.classes) {
    if (c.joints.empty()) return "class " + c.id + " names no joint";
    if (c.id == "other" && hasListedClass(r)) return "`other` next to a listed class: " + classesText(r);
  }
  return "";
}
}  // namespace

TEST(Singularity, OtherNamesTheDependentScrews) {
  // Rhino with cos q1 = 0: the slide depends on the three parallel axes 2-4 (joints 1, 3, 4, 5).
  const PoeModel m = robot("rhino_xr3_slide.yaml").poeModel();
  const SingularityReport r = analyzeSingularity(m, vec({30, M_PI / 2, 0.5, 0.7, 0.4, 0.3}));
  ASSERT_EQ(r.classes.size(), 1u);
  EXPECT_EQ(r.classes[0].id, "other");
  EXPECT_EQ(r.classes[0].joints, (std::vector<int>{1, 3, 4, 5}));
  ASSERT_EQ(r.null_space.size(), 1u);
}

TEST(Singularity, RandomPosesClassIffRankDeficient) {
  const char* files[] = {"puma560_corke.yaml",  "puma560_corke_poe.yaml", "puma560_okamura_nominal.yaml",
                         "puma560_okamura_actual.yaml", "stanford_corke.yaml", "elbow_mls.yaml",
                         "rhino_xr3_slide.yaml", "panda.yaml"};
  std::mt19937_64 rng(1984);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), unit(0.0, 1.0);
  for (const char* name : files) {
    const RobotFile file = robot(name);
    const PoeModel m = file.poeModel();
    const int samples = m.dof() == 6 ? 10000 : 1000;
    int singular = 0, mismatches = 0, split_mismatches = 0;
    double smallest = 1e300;
    VecX q(m.dof());
    for (int s = 0; s < samples; ++s) {
      for (int i = 0; i < m.dof(); ++i) {
        const Joint& j = m.joint(i);
        q[i] = j.range ? (*j.range)[0] + unit(rng) * ((*j.range)[1] - (*j.range)[0]) : angle(rng);
      }
      const SingularityReport r = analyzeSingularity(m, q);
      singular += r.singular;
      smallest = std::min(smallest, r.sigma_min);
      if (!iffViolation(r).empty()) ++mismatches;
      if (r.decoupled.applies && m.dof() == 6 && r.singular != (r.decoupled.wrist_singular || r.decoupled.arm_singular)) {
        ++split_mismatches;
      }
    }
    std::printf("%-30s %5d poses: %d singular, smallest sigma_min %.3g, class/rank mismatches %d, split mismatches %d\n",
                file.name.c_str(), samples, singular, smallest, mismatches, split_mismatches);
    EXPECT_EQ(mismatches, 0) << name;
    EXPECT_EQ(split_mismatches, 0) << name;
  }
  // Random poses are almost never singular, so the direction "rank deficient => a class" is exercised on
  // the listed singular poses and on random perturbations of them from 1e-6 to 1e-16 (both sides of the
  // rank threshold), `other` poses included.
  int singular = 0, regular = 0, mismatches = 0;
  for (const Pose6& p : listedPoses()) {
    const PoeModel m = robot(p.file).poeModel();
    std::vector<VecX> qs = {p.q};
    for (double size = 1e-6; size >= 1e-16; size /= 10) {
      VecX dq(m.dof());
      for (int i = 0; i < m.dof(); ++i) dq[i] = angle(rng);
      qs.push_back(p.q + size * dq.normalized());
    }
    for (const VecX& q : qs) {
      const SingularityReport r = analyzeSingularity(m, q);
      (r.singular ? singular : regular) += 1;
      const std::string violation = iffViolation(r);
      if (!violation.empty()) {
        ++mismatches;
        std::printf("mismatch: %s %s rank %d: %s\n", m.name().c_str(), p.label.c_str(), r.rank, violation.c_str());
      }
    }
  }
  std::printf("listed poses and perturbations: %d singular, %d regular, %d mismatches\n", singular, regular, mismatches);
  EXPECT_GT(singular, 100);  // both directions are exercised
  EXPECT_GT(regular, 100);
  EXPECT_EQ(mismatches, 0);
}

TEST(Singularity, ClassGeometryIsData) {
  // the numbers the CLI words: C3's common point lies on its axes, C6's line meets every axis, C7 names
  // its prismatic joint (checked on the joint lines, independently of how the classes were found)
  // distance between two lines; parallel lines meet at infinity (P-S example 6: "possibly at infinity")
  auto lineDistance = [](const JointLine& a, const Vec3& point, const Vec3& direction) {
    const Vec3 n = a.direction.cross(direction);
    return n.norm() < 1e-9 ? 0.0 : std::abs((point - a.point).dot(n)) / n.norm();
  };
  const std::vector<Pose6> poses = listedPoses();
  int c3 = 0, c6 = 0, c7 = 0;
  for (const Pose6& p : poses) {
    const PoeModel m = robot(p.file).poeModel();
    const SingularityReport r = analyzeSingularity(m, p.q);
    for (const SingularClass& c : r.classes) {
      SCOPED_TRACE(m.name() + ": " + p.label + ": " + c.id);
      if (c.id == "C3") {
        ++c3;
        for (int j : c.joints) {
          const JointLine& l = r.lines[static_cast<size_t>(j - 1)];
          EXPECT_LE((c.point - l.point).cross(l.direction).norm(), 1e-9 * m.lengthScale());
        }
      }
      if (c.id == "C6") {
        ++c6;
        EXPECT_NEAR(c.direction.norm(), 1.0, 1e-12);
        EXPECT_EQ(c.joints.size(), static_cast<size_t>(m.dof()));
        for (const JointLine& l : r.lines) {
          if (c.at_infinity) {
            EXPECT_LE(std::abs(l.direction.dot(c.direction)), 1e-9);
          } else {
            EXPECT_LE(lineDistance(l, c.point, c.direction), 1e-9 * m.lengthScale());
          }
        }
      }
      if (c.id == "C7") {
        ++c7;
        ASSERT_GE(c.prismatic_joint, 1);
        EXPECT_EQ(m.joint(c.prismatic_joint - 1).type, JointType::Prismatic);
        EXPECT_NE(std::find(c.joints.begin(), c.joints.end(), c.prismatic_joint), c.joints.end());
      }
    }
  }
  EXPECT_GT(c3, 0);
  EXPECT_GT(c6, 0);
  EXPECT_GT(c7, 0);
}

namespace {
// n revolute joints, all axes parallel to z through (i, 0, 0): a planar chain, rank 3.
PoeModel parallelChain(int n) {
  std::vector<JointSpec> joints(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) joints[static_cast<size_t>(i)].twist << 0, 0, 1, 0, -i, 0;
  Pose tool;
  tool.p = Vec3(n, 0, 0);
  return PoeModel(joints, tool);
}

// n revolute joints with seeded random axes: rank 6, null space of dimension n - 6.
PoeModel randomChain(int n, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  std::vector<JointSpec> joints(static_cast<size_t>(n));
  for (JointSpec& j : joints) {
    const Vec3 w = lowpair_test::draw3(normal, rng).normalized();
    const Vec3 p = lowpair_test::draw3(normal, rng);
    j.twist << w, p.cross(w);
  }
  return PoeModel(joints, Pose());
}

// J_n x for every returned null vector, and the basis orthonormal.
void expectNullBasis(const PoeModel& m, const VecX& q, const SingularityReport& r) {
  Data data(m);
  Mat6X Jn(6, m.dof());
  computeJacobians(m, data, q);
  getGeometricJacobian(data, Jn);
  dimensionlessJacobian(m, Jn);
  for (size_t a = 0; a < r.null_space.size(); ++a) {
    ASSERT_EQ(r.null_space[a].size(), m.dof());
    EXPECT_LE((Jn * r.null_space[a]).norm(), 1e-11 * std::sqrt(m.dof())) << "vector " << a;
    for (size_t b = 0; b <= a; ++b) {
      EXPECT_NEAR(r.null_space[a].dot(r.null_space[b]), a == b ? 1.0 : 0.0, 1e-12) << a << ", " << b;
    }
  }
}
}  // namespace

TEST(Singularity, LongChainsSkipTheClassSearch) {
  std::mt19937_64 rng(11);
  for (int n : {kClassSearchMaxJoints, kClassSearchMaxJoints + 1, 300}) {
    SCOPED_TRACE(n);
    const PoeModel m = parallelChain(n);
    const VecX q = VecX::Constant(n, 0.1);
    const SingularityReport r = analyzeSingularity(m, q);
    EXPECT_EQ(r.rank, 3);  // planar: v_x, v_y, w_z
    EXPECT_TRUE(r.singular);
    EXPECT_EQ(r.nullity, n - 3);
    EXPECT_EQ(r.null_space.size(), static_cast<size_t>(n - 3));
    expectNullBasis(m, q, r);
    EXPECT_EQ(r.classes_searched, n <= kClassSearchMaxJoints);
    if (r.classes_searched) {
      EXPECT_FALSE(r.classes.empty());  // C4: all axes parallel
    } else {
      EXPECT_TRUE(r.classes.empty());
    }
  }
  // a bounded null space: the first vectors of the same basis, the dimension still counted
  const PoeModel m = randomChain(500, rng);
  const VecX q = VecX::Constant(500, 0.2);
  SingularityOptions options;
  options.max_null_vectors = 4;
  const SingularityReport r = analyzeSingularity(m, q, options);
  EXPECT_FALSE(r.singular);
  EXPECT_EQ(r.rank, 6);
  EXPECT_EQ(r.nullity, 494);
  ASSERT_EQ(r.null_space.size(), 4u);
  expectNullBasis(m, q, r);
  options.max_null_vectors = 0;
  EXPECT_TRUE(analyzeSingularity(m, q, options).null_space.empty());
  options.max_null_vectors = -1;
  EXPECT_THROW(analyzeSingularity(m, q, options), std::invalid_argument);
}

TEST(Singularity, BoundedNullSpaceOfAShortChain) {
  // Panda (7 joints) at a regular pose: one self-motion vector; asking for none keeps the count
  const PoeModel m = robot("panda.yaml").poeModel();
  const VecX q = vec({0.1, -0.3, 0.2, -1.5, 0.1, 1.5, 0.3});
  const SingularityReport all = analyzeSingularity(m, q);
  EXPECT_FALSE(all.singular);
  EXPECT_EQ(all.nullity, 1);
  ASSERT_EQ(all.null_space.size(), 1u);
  expectNullBasis(m, q, all);
  SingularityOptions none;
  none.max_null_vectors = 0;
  const SingularityReport r = analyzeSingularity(m, q, none);
  EXPECT_EQ(r.nullity, 1);
  EXPECT_TRUE(r.null_space.empty());
  EXPECT_EQ(r.rank, all.rank);
}

TEST(Singularity, ReportsConditionAndBlocks) {
  const PoeModel m = robot("elbow_mls.yaml").poeModel();
  const SingularityReport r = analyzeSingularity(m, vec({0.3, 0.5, 0.7, 0.4, 0.6, 0.2}));
  EXPECT_FALSE(r.singular);
  EXPECT_EQ(r.rank_linear, 3);
  EXPECT_EQ(r.rank_angular, 3);
  // independently of the SVD: manipulability sqrt(det(J_n J_n^T)), condition sqrt(lambda_max / lambda_min)
  Data data(m);
  Mat6X Jn(6, m.dof());
  computeJacobians(m, data, vec({0.3, 0.5, 0.7, 0.4, 0.6, 0.2})); getGeometricJacobian(data, Jn);
  dimensionlessJacobian(m, Jn);
  const Mat6 JJt = Jn * Jn.transpose();
  const Eigen::SelfAdjointEigenSolver<Mat6> eig(JJt);
  EXPECT_NEAR(r.manipulability, std::sqrt(JJt.determinant()), 1e-12 * r.manipulability);
  EXPECT_NEAR(r.condition, std::sqrt(eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff()), 1e-9 * r.condition);
  EXPECT_THROW(analyzeSingularity(m, vec({0, 0})), std::invalid_argument);
}

TEST(Singularity, DimensionlessJacobianRejectsWrongColumns) {
  // it scales column i for every joint i: a Jacobian with fewer columns is rejected, in every build type
  const PoeModel m = robot("elbow_mls.yaml").poeModel();
  Mat6X J = Mat6X::Zero(6, 5);
  try {
    dimensionlessJacobian(m, J);
    ADD_FAILURE() << "a 6 x 5 Jacobian was accepted for 6 joints";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "dimensionlessJacobian: the Jacobian has 5 columns, the model has 6 joints");
  }
}

TEST(Singularity, ClassesAndRankAgreeNearSingularPoses) {
  // The tolerance band: perturb every listed singular pose by |dq| from 1e-3 down to 1e-16 in random
  // directions; wherever the rank test flips, the line classes must flip with it (6-joint robots).
  // The flip must happen inside the band, or that check holds vacuously (an analysis that always answered
  // "regular" would pass it): each pose itself is singular with its listed classes, and at |dq| = 1e-3 it
  // is regular without a class. There sigma_min is first order in the distance to the singular set
  // (robots.md §7: det J is a product of factors with simple zeros; where two vanish, as for the Rhino at
  // q = 0, each deficiency is first order), about c |dq| |cos| for the component cos of the random unit
  // direction across the set; c >= 1e-3 for the listed poses (smallest for the folded elbow of Corke's
  // PUMA: a2 = 0.4318 and sqrt(a3^2 + d4^2) = 0.4323 fold the wrist centre to 0.5 mm of joint 2's axis,
  // so a second factor of det J is small too), so sigma_min >= 1e-6 |cos|, above the rank threshold
  // 1.3e-12 sigma_max (< 3e-12 here) unless |cos| < 3e-6. The listed regular poses (qn, the poses printed
  // in rounded degrees) are regular without a class.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  int checked = 0, mismatches = 0, singular = 0, exact_singular = 0, far_regular = 0, listed_regular = 0;
  double far_sigma_min = 1e300;
  for (const Pose6& p : listedPoses()) {
    const PoeModel m = robot(p.file).poeModel();
    SCOPED_TRACE(m.name() + ": " + p.label);
    const SingularityReport exact = analyzeSingularity(m, p.q);
    if (p.expected.empty()) {
      EXPECT_FALSE(exact.singular) << "rank " << exact.rank << ", sigma_min " << exact.sigma_min;
      EXPECT_TRUE(exact.classes.empty()) << classesText(exact);
      listed_regular += !exact.singular && exact.classes.empty();
      continue;
    }
    // a dependency without a listed class (`other`) has no classes to flip: not in this check
    if (p.expected[0].id == "other") continue;
    EXPECT_TRUE(exact.singular) << "rank " << exact.rank << ", sigma_min " << exact.sigma_min;
    for (const Expected& e : p.expected) {
      EXPECT_TRUE(reported(exact, e)) << expectedText({e}) << " not in " << classesText(exact);
    }
    exact_singular += exact.singular;
    for (double size = 1e-3; size >= 1e-16; size /= 10) {
      const bool far = size == 1e-3;
      for (int k = 0; k < 20; ++k) {
        VecX dq(m.dof());
        for (int i = 0; i < m.dof(); ++i) dq[i] = normal(rng);
        const VecX q = p.q + size * dq.normalized();
        const SingularityReport r = analyzeSingularity(m, q);
        ++checked;
        singular += r.singular;
        // these poses have a listed class: the rank test and the line classes must flip together
        if (r.singular != hasListedClass(r)) {
          ++mismatches;
          std::printf("mismatch: %s %s |dq| %.0e rank %d sigma_min %.3g classes %s\n", m.name().c_str(),
                      p.label.c_str(), size, r.rank, r.sigma_min, classesText(r).c_str());
        }
        if (far) {
          EXPECT_FALSE(r.singular) << "|dq| 1e-3: rank " << r.rank << ", sigma_min " << r.sigma_min;
          EXPECT_TRUE(r.classes.empty()) << "|dq| 1e-3: " << classesText(r);
          far_regular += !r.singular && r.classes.empty();
          far_sigma_min = std::min(far_sigma_min, r.sigma_min);
        }
      }
    }
  }
  std::printf("%d perturbed poses, %d singular, %d class/rank mismatches; %d listed singular poses singular with "
              "their classes, %d regular at |dq| 1e-3 (smallest sigma_min %.3g); %d listed regular poses regular\n",
              checked, singular, mismatches, exact_singular, far_regular, far_sigma_min, listed_regular);
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(exact_singular, 0);
  EXPECT_GT(far_regular, 0);
  EXPECT_GT(listed_regular, 0);
}
