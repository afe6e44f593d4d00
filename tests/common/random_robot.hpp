#pragma once
// Seeded random robots for property tests: 2-7 joints of every type, unnormalized twists (scale 0.3-3),
// offsets, sizes 0.1-1000 length units, and on about half of the joints a deliberately degenerate
// relation to the previous axis (one Geometry per robot), and a random, identity or axis-aligned tool.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <random>
#include <vector>

#include "lowpair/gravity.hpp"
#include "lowpair/model.hpp"
#include "lowpair/se3.hpp"

namespace lowpair_test {

using namespace lowpair;

enum class Geometry { Random, Parallel, AntiParallel, NearlyParallel, Collinear, Intersecting, AlongZ, PrismaticAlongRevolute };
inline const char* geometryName(Geometry g) {
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

// Three draws in order (the order of evaluation of a constructor's arguments is unspecified: g++ and clang
// differ, and so would every test's data between the Release and the sanitizer builds).
template <class Distribution>
inline Vec3 draw3(Distribution& d, std::mt19937_64& rng) {
  const double x = d(rng);
  const double y = d(rng);
  const double z = d(rng);
  return Vec3(x, y, z);
}

inline Vec3 unitVector(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return lowpair_test::draw3(n, rng).normalized();
}

// Rotate u by a tiny angle about a random perpendicular axis.
inline Vec3 tilted(const Vec3& u, double angle, std::mt19937_64& rng) {
  Vec3 perp = u.cross(unitVector(rng)).normalized();
  return expSO3(angle * perp) * u;
}

// The sanitizer build's test run (`make sanitize` sets LOWPAIR_SANITIZE), where each computation costs 10-40
// times as much: statistical and property tests run the same code on fewer cases there.
inline bool sanitized() { return std::getenv("LOWPAIR_SANITIZE") != nullptr; }
// How many random robots a property test runs: `full`, or a tenth of it (at least 50) under the sanitizers.
inline int robotCount(int full) {
  return sanitized() ? std::max(50, full / 10) : full;
}

inline RandomRobot randomRobot(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> dof_dist(2, 7), geometry_dist(0, 7), type_dist(0, 9);
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale_dist(0.3, 3.0), log_size(-1.0, 3.0);
  const int n = dof_dist(rng);
  const double size = std::pow(10.0, log_size(rng));  // 0.1 .. 1000 length units
  const Geometry geometry = static_cast<Geometry>(geometry_dist(rng));
  std::vector<JointSpec> joints(static_cast<size_t>(n));
  Vec3 prev_w = unitVector(rng), prev_p = size * lowpair_test::draw3(u, rng);
  for (int i = 0; i < n; ++i) {
    const int t = type_dist(rng);
    JointType type = t < 5 ? JointType::Revolute : (t < 7 ? JointType::Helical : JointType::Prismatic);
    Vec3 w = unitVector(rng);
    Vec3 p = size * lowpair_test::draw3(u, rng);
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
    xi << 3.0 * lowpair_test::draw3(u, rng), size * lowpair_test::draw3(u, rng);
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


/// Joint values: revolute/helical in [-pi, pi], prismatic over the joint's range.
inline VecX randomConfiguration(const PoeModel& model, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), unit(0.0, 1.0);
  VecX q(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    q[i] = j.range ? (*j.range)[0] + unit(rng) * ((*j.range)[1] - (*j.range)[0]) : angle(rng);
  }
  return q;
}

// Point masses of kg_min to 20 kg on every link and the payload, centres within L of the origin in each coordinate
// (links: base frame at the reference configuration; payload: tool frame); gravity and length unit the defaults.
inline MassModel randomMasses(const PoeModel& model, std::mt19937_64& rng, double kg_min = 0.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), kg(kg_min, 20.0);
  MassModel m;
  const double L = model.lengthScale();
  for (int i = 0; i < model.dof(); ++i) m.links.push_back({kg(rng), L * lowpair_test::draw3(u, rng)});
  m.payload = {kg(rng), L * lowpair_test::draw3(u, rng)};
  return m;
}

}  // namespace lowpair_test
