// Property tests over 10,000 seeded random robots (2-7 joints, every joint type, unnormalized twists,
// offsets) with deliberately degenerate geometry: POE FK = converted D-H FK; dhToPoe(poeToDh(m)), the
// modified export and the tool/local forms give the same FK. Bound (design.md): rotation <= 1e-12 rad,
// translation <= 1e-12 * max(L, max |d|, max |a|).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

using namespace lowpair;

namespace {

enum class Geometry { Random, Parallel, AntiParallel, NearlyParallel, Collinear, Intersecting, AlongZ, PrismaticAlongRevolute };
const char* geometryName(Geometry g) {
  switch (g) {
    case Geometry::Random: return "random";
    case Geometry::Parallel: return "parallel";
    case Geometry::AntiParallel: return "anti-parallel";
    case Geometry::NearlyParallel: return "nearly-parallel";
    case Geometry::Collinear: return "collinear";
    case Geometry::Intersecting: return "intersecting";
    case Geometry::AlongZ: return "along-z";
    case Geometry::PrismaticAlongRevolute: return "prismatic-along-revolute";
  }
  return "?";
}

struct RandomRobot {
  PoeModel model;
  Geometry geometry;
};

Vec3 unitVector(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

// Rotate u by a tiny angle about a random perpendicular axis.
Vec3 tilted(const Vec3& u, double angle, std::mt19937_64& rng) {
  Vec3 perp = u.cross(unitVector(rng)).normalized();
  return expSO3(angle * perp) * u;
}

RandomRobot randomRobot(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> dof_dist(2, 7), geometry_dist(0, 7), type_dist(0, 9);
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale_dist(0.3, 3.0), log_size(-1.0, 3.0);
  const int n = dof_dist(rng);
  const double size = std::pow(10.0, log_size(rng));  // 0.1 .. 1000 length units
  const Geometry geometry = static_cast<Geometry>(geometry_dist(rng));
  std::vector<JointSpec> joints(static_cast<size_t>(n));
  Vec3 prev_w = unitVector(rng), prev_p = size * Vec3(u(rng), u(rng), u(rng));
  for (int i = 0; i < n; ++i) {
    const int t = type_dist(rng);
    JointType type = t < 5 ? JointType::Revolute : (t < 7 ? JointType::Helical : JointType::Prismatic);
    Vec3 w = unitVector(rng);
    Vec3 p = size * Vec3(u(rng), u(rng), u(rng));
    // degenerate relations to the previous axis, on about half of the joints
    if (i > 0 && (rng() & 1)) {
      switch (geometry) {
        case Geometry::Random: break;
        case Geometry::Parallel: w = prev_w; break;
        case Geometry::AntiParallel: w = -prev_w; break;
        case Geometry::NearlyParallel: w = tilted(prev_w, std::pow(10.0, -3.0 - 13.0 * (0.5 + 0.5 * u(rng))), rng); break;
        case Geometry::Collinear: w = (rng() & 1) ? prev_w : -prev_w; p = prev_p + size * u(rng) * prev_w; break;
        case Geometry::Intersecting: p = prev_p; break;
        case Geometry::AlongZ: w = Vec3(0, 0, (rng() & 1) ? 1.0 : -1.0); if (rng() & 1) p.setZero(); break;
        case Geometry::PrismaticAlongRevolute: w = prev_w; type = (rng() & 1) ? JointType::Prismatic : type; break;
      }
    } else if (i == 0 && geometry == Geometry::AlongZ) {
      w = Vec3(0, 0, 1);
      p.setZero();
    }
    const double q_bar = scale_dist(rng);
    JointSpec& s = joints[static_cast<size_t>(i)];
    if (type == JointType::Prismatic) {
      s.twist << Vec3::Zero(), w * q_bar;
      s.range = std::array<double, 2>{-size / q_bar, size / q_bar};
    } else {
      const double pitch = type == JointType::Helical ? size * 0.1 * u(rng) : 0.0;
      s.twist << w * q_bar, (p.cross(w) + pitch * w) * q_bar;
      s.type = type == JointType::Helical && pitch == 0.0 ? std::optional<JointType>(JointType::Helical) : std::nullopt;
    }
    if (rng() & 1) s.offset = u(rng);
    prev_w = w;
    prev_p = p;
  }
  // tool: random, identity, or with z along the last axis
  Pose tool;
  const int tool_kind = static_cast<int>(rng() % 3);
  if (tool_kind == 0) {
    Vec6 xi;
    xi << 3.0 * Vec3(u(rng), u(rng), u(rng)), size * Vec3(u(rng), u(rng), u(rng));
    tool = expSE3(xi);
  } else if (tool_kind == 1) {
    const Vec3 z = prev_w;
    const Vec3 x = z.cross(unitVector(rng)).normalized();
    tool.R.col(0) = x;
    tool.R.col(1) = z.cross(x);
    tool.R.col(2) = z;
    tool.p = prev_p + size * u(rng) * z;
  }
  return {PoeModel(joints, tool), geometry};
}

struct Worst {
  double rotation = 0, translation = 0;  // translation relative to the bound scale
  void add(const Pose& a, const Pose& b, double scale) {
    rotation = std::max(rotation, rotationError(a.R, b.R));
    translation = std::max(translation, (a.p - b.p).norm() / scale);
  }
};

}  // namespace

TEST(ConversionProperty, TenThousandRandomRobots) {
  std::mt19937_64 rng(20190201);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), unit(0.0, 1.0);
  std::map<std::string, Worst> by_category;
  Worst dh_roundtrip, modified, tool_form, local_form;
  int robots = 0, samples = 0;
  for (int r = 0; r < 10000; ++r) {
    const RandomRobot robot = randomRobot(rng);
    const PoeModel& poe = robot.model;
    const DhConversion c = poeToDh(poe);
    const PoeModel back = dhToPoe(c.model);
    const ModifiedDh mod = toModifiedDh(c.model);
    const ToolPoeModel tool = toToolPoe(poe);
    const LocalPoeModel local = toLocalPoe(poe);
    const PoeModel tool_back = fromToolPoe(tool), local_back = fromLocalPoe(local);
    const double scale = c.fk_check.scale;  // max(L, |d|, |a|)
    ASSERT_TRUE(std::isfinite(scale));
    Worst& cat = by_category[geometryName(robot.geometry)];
    PoeData poe_data(poe);
    DhData dh_data(c.model);
    VecX q(poe.dof());
    for (int s = 0; s < 20; ++s) {
      for (int i = 0; i < poe.dof(); ++i) {
        const Joint& j = poe.joint(i);
        q[i] = j.range ? (*j.range)[0] + unit(rng) * ((*j.range)[1] - (*j.range)[0]) : angle(rng);
      }
      forwardKinematics(poe, poe_data, q);
      forwardKinematics(c.model, dh_data, q);
      const Pose& ref = poe_data.T_base_tool;
      ASSERT_TRUE(dh_data.T_base_tool.matrix().allFinite());
      cat.add(ref, dh_data.T_base_tool, scale);
      dh_roundtrip.add(ref, poeForwardKinematics(back, q), scale);
      modified.add(ref, modifiedDhForwardKinematics(mod, q), scale);
      tool_form.add(ref, forwardKinematics(tool, q), scale);
      tool_form.add(ref, poeForwardKinematics(tool_back, q), scale);
      local_form.add(ref, forwardKinematics(local, q), scale);
      local_form.add(ref, poeForwardKinematics(local_back, q), scale);
      ++samples;
    }
    ++robots;
  }
  std::printf("%d robots, %d joint vectors each (%d comparisons per form)\n", robots, 20, samples);
  std::printf("%-26s %14s %24s\n", "category", "max rot (rad)", "max trans / max(L,|d|,|a|)");
  Worst all;
  for (const auto& [name, w] : by_category) {
    std::printf("%-26s %14.3g %24.3g\n", name.c_str(), w.rotation, w.translation);
    all.rotation = std::max(all.rotation, w.rotation);
    all.translation = std::max(all.translation, w.translation);
  }
  std::printf("%-26s %14.3g %24.3g\n", "dhToPoe(poeToDh(m))", dh_roundtrip.rotation, dh_roundtrip.translation);
  std::printf("%-26s %14.3g %24.3g\n", "modified D-H export", modified.rotation, modified.translation);
  std::printf("%-26s %14.3g %24.3g\n", "tool POE form", tool_form.rotation, tool_form.translation);
  std::printf("%-26s %14.3g %24.3g\n", "local POE form", local_form.rotation, local_form.translation);
  EXPECT_LE(all.rotation, 1e-12);
  EXPECT_LE(all.translation, 1e-12);
  for (const Worst& w : {dh_roundtrip, modified, tool_form, local_form}) {
    EXPECT_LE(w.rotation, 1e-12);
    EXPECT_LE(w.translation, 1e-12);
  }
}
