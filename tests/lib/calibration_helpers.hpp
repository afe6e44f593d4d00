#pragma once
// Helpers of the calibration tests (calibration_test.cpp, identifiability_test.cpp, tracker_test.cpp, ...):
// random poses and perturbations, noise, deviations and the rounding scales their tolerances come from.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "random_robot.hpp"

namespace calibration_helpers {

using namespace lowpair;

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- helpers --------------------------------------------------------------------------------------------

// Scales. L = model.lengthScale(). Parameters are compared in "scaled units": a length or pitch parameter of
// size L, an angle of 1 rad and a scale increment of 1 are each one unit (parameterUnit).

// One scaled unit of a parameter in its own unit: L for lengths and pitches, 1 for angles and scales.
inline double parameterUnit(const Parameter& p, double L) {
  switch (p.kind) {
    case ParameterKind::Shift:
    case ParameterKind::Pitch:
    case ParameterKind::ToolTranslation: return L;
    default: return 1.0;
  }
}

// Joint values uniform in [-pi, pi] (revolute, helical) and [-L, L] (prismatic).
inline VecX uniformJoints(const PoeModel& model, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VecX q(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    q[i] = (model.joint(i).type == JointType::Prismatic ? model.lengthScale() : M_PI) * unit(rng);
  }
  return q;
}

inline std::vector<VecX> uniformPoses(const PoeModel& model, int count, std::mt19937_64& rng) {
  std::vector<VecX> qs;
  for (int k = 0; k < count; ++k) qs.push_back(uniformJoints(model, rng));
  return qs;
}

// The point of a revolute/helical joint's line nearest the base origin (w x v for a unit twist).
inline Vec3 linePoint(const Joint& j) { return j.axis().cross(j.moment()); }

inline double distanceToLine(const Joint& j, const Vec3& p) { return j.axis().cross(p - linePoint(j)).norm(); }

// The distance scale of a configuration: every point the FK or a parameter's motion involves lies within
// S of the base origin and of the tool point. A joint moves points by at most 2|c| + |h x| (rotation about
// a line at distance |c| from the origin, plus the slide) or |x| (prismatic), so the world position of any
// joint line's rest point and of the tool are bounded by the sum.
inline double distanceScale(const PoeModel& model, const VecX& q, const Pose& T_base_tool) {
  double s = T_base_tool.p.norm() + model.lengthScale();
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const double x = std::abs(j.motion(q[i]));
    s += j.type == JointType::Prismatic ? x : 2.0 * linePoint(j).norm() + std::abs(j.pitch) * x;
  }
  return s;
}

// Forward-kinematics rounding (used by several bounds). A chain of n joints is n + 1 pose products and n
// joint exponentials; each product adds ~3 eps relative to the magnitudes involved and each sine/cosine
// of a motion |x| <= 4 adds ~|x| eps; every point involved lies within the distance scale S of the
// configuration (distanceScale, above), so one FK is accurate to eps_fk = 16 (n + 1) eps S in position and
// 16 (n + 1) eps in rotation.
inline double fkRounding(int dof) { return 16.0 * (dof + 1) * kEpsilon; }

struct TypeCount {
  int revolute = 0, prismatic = 0, helical = 0;
};
inline TypeCount countTypes(const PoeModel& model) {
  TypeCount c;
  for (const Joint& j : model.joints()) {
    if (j.type == JointType::Revolute) ++c.revolute;
    if (j.type == JointType::Prismatic) ++c.prismatic;
    if (j.type == JointType::Helical) ++c.helical;
  }
  return c;
}

inline std::string typeString(const PoeModel& model) {
  std::string s;
  for (const Joint& j : model.joints()) s += j.type == JointType::Revolute ? 'R' : j.type == JointType::Prismatic ? 'P' : 'H';
  return s;
}

// A robot with the given joint letters (R, P, H), generic lines through points in [-L, L]^3, scales in
// [0.5, 2], pitches of 0.05-0.2 L/rad of either sign, offsets in [-0.5, 0.5], a generic tool.
inline PoeModel jointMix(const std::string& types, double L, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale(0.5, 2.0), pitch(0.05, 0.2);
  std::vector<JointSpec> joints;
  for (char t : types) {
    JointSpec s;
    const Vec3 w = lowpair_test::unitVector(rng);
    const Vec3 c = L * lowpair_test::draw3(u, rng);
    const double q_bar = scale(rng);
    if (t == 'P') {
      s.type = JointType::Prismatic;
      s.twist << Vec3::Zero(), w * q_bar;
      s.range = std::array<double, 2>{-L / q_bar, L / q_bar};
    } else {
      const double h = t == 'H' ? (u(rng) < 0 ? -1.0 : 1.0) * pitch(rng) * L : 0.0;
      s.type = t == 'H' ? JointType::Helical : JointType::Revolute;
      s.twist << w * q_bar, (c.cross(w) + h * w) * q_bar;
    }
    s.offset = 0.5 * u(rng);
    joints.push_back(s);
  }
  Vec6 tool;
  tool << 1.5 * lowpair_test::draw3(u, rng), L * lowpair_test::draw3(u, rng);
  return PoeModel(joints, expSE3(tool), types);
}

// A small random perturbation of the error model's parameters: angles N(0, a^2) rad, lengths and pitches
// N(0, (a L)^2), scale increments N(0, a^2) (relative to the scale). Pitch entries 0 unless `pitch`.
inline VecX smallDelta(const ErrorModel& em, double a, bool pitch, std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  const double L = em.model().lengthScale();
  VecX d(em.size());
  for (int k = 0; k < em.size(); ++k) {
    const Parameter& p = em.parameters()[static_cast<size_t>(k)];
    if (p.kind == ParameterKind::Scale) {
      d[k] = a * em.model().joint(p.joint).scale * n(rng);
    } else if (p.kind == ParameterKind::Pitch && !pitch) {
      d[k] = 0.0;
    } else {
      d[k] = a * parameterUnit(p, L) * n(rng);
    }
  }
  return d;
}

inline std::vector<Measurement> measure(const PoeModel& truth, const std::vector<VecX>& qs) {
  std::vector<Measurement> out;
  for (const VecX& q : qs) out.push_back(Measurement{q, poeForwardKinematics(truth, q)});
  return out;
}

// Measurement noise: position N(0, sp^2) per coordinate, rotation exp(N(0, sr^2 I)) R (base frame).
inline void addNoise(std::vector<Measurement>& ms, double sp, double sr, std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  for (Measurement& m : ms) {
    m.T_base_tool.p += sp * lowpair_test::draw3(n, rng);
    m.T_base_tool.R = expSO3(sr * lowpair_test::draw3(n, rng)) * m.T_base_tool.R;
  }
}

// RMS and max of |p_a - p_b| over poses (the validation measure, computed here from FK).
struct Deviation {
  double rms = 0.0, max = 0.0;
};
inline Deviation positionDeviation(const PoeModel& a, const PoeModel& b, const std::vector<VecX>& qs) {
  Deviation d;
  for (const VecX& q : qs) {
    const double e = (poeForwardKinematics(a, q).p - poeForwardKinematics(b, q).p).norm();
    d.rms += e * e;
    d.max = std::max(d.max, e);
  }
  d.rms = std::sqrt(d.rms / static_cast<double>(qs.size()));
  return d;
}

// The largest distance scale of a robot over a set of poses.
inline double maxDistanceScale(const PoeModel& model, const std::vector<VecX>& qs) {
  double s = 0.0;
  for (const VecX& q : qs) s = std::max(s, distanceScale(model, q, poeForwardKinematics(model, q)));
  return s;
}

// Condition of the determined part of a rank analysis: sigma_1 / sigma_rank.
inline double determinedCondition(const RankAnalysis& a) {
  return a.rank > 0 ? a.singular_values[0] / a.singular_values[a.rank - 1] : kInf;
}

// Position-only measurements observe one tool point. Walking from the last joint back, keep track of where
// the later joints can take that point: nowhere (Fixed, every later joint leaves it in place), along one
// line (OnLine: later prismatic joints along it, or helical joints about it), or anywhere else (General,
// stop). Joint i's parameters are lost when the point stays on its line:
//   - revolute, line through the point, Fixed: the joint does not move the point, so its scale column
//     dp = (v + w x p) x is 0, and its two tilts about the point (eta = [u; p x u]) give dp = 0 too
//     (R commutes with the line's cross product): 3 lost (free pitch or not: the pitch is 0 at the model
//     and its column, w x, is observable). Still Fixed.
//   - revolute, OnLine along its own line: the point slides along the line, which the joint does not move:
//     the scale column is 0 (1 lost); the tilts are observable (the point leaves the pivot as it slides).
//   - helical about a line through the point (Fixed, or OnLine along its own line): the joint slides the
//     point by h x along the line, so its scale column dp = h w (q + offset) is h / scale times its pitch
//     column w scale (q + offset): 1 lost. Now OnLine.
//   - prismatic, Fixed: now OnLine along its direction; OnLine along its direction: still OnLine.
//   - anything else: General.
// With full pose measurements nothing is lost. (An unobservable direction is a combination of columns that
// vanishes at every pose: the rank drops by exactly the number of independent such combinations.)
inline int positionOnlyLoss(const PoeModel& model) {
  const Vec3 p = model.toolPose().p;
  const double near = 1e-9;  // constructions put the point on a line / make directions equal to rounding
  bool fixed = true;         // else OnLine along `d`
  Vec3 d = Vec3::Zero();
  int loss = 0;
  for (int i = model.dof() - 1; i >= 0; --i) {
    const Joint& j = model.joint(i);
    if (j.type == JointType::Prismatic) {
      if (fixed) {
        fixed = false;
        d = j.moment();
        continue;
      }
      if (d.cross(j.moment()).norm() <= near) continue;
      break;
    }
    const bool through = distanceToLine(j, p) <= near * model.lengthScale();
    const bool along = fixed || d.cross(j.axis()).norm() <= near;
    if (!through || !along) break;
    if (j.type == JointType::Revolute) {
      loss += fixed ? 3 : 1;
    } else {
      loss += 1;
      fixed = false;
      d = j.axis();
    }
  }
  return loss;
}

// Aggregated failures: the first few printed, the number asserted (thousands of robots would otherwise
// drown the output).
struct Failures {
  int count = 0;
  void add(const std::string& what) {
    if (count++ < 15) std::printf("FAIL %s\n", what.c_str());
  }
};

inline std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

// The PUMA 560 of models/puma560_okamura_nominal.yaml (Wu et al. Table I, mm), turned by a generic base
// rotation R0 and given a generic tool orientation, so that of its consecutive lines only joints 2 and 3
// stay parallel (in the file base z || joint 1 and joint 6 || tool z as well, which would cost the D-H
// parameterization rank too). `tilt` turns joint 3 about the common normal (x) of joints 2 and 3.
// `generic` moves joint 1 off the base origin (its line would meet the base z axis there), joint 2 by
// 20 mm and joint 5 by 15 mm along x, so that no two consecutive lines intersect (the file's base-1, 1-2 and
// the wrist 4-5-6 do; a = 0 rows are where the D-H `a >= 0` convention is not differentiable).
inline PoeModel pumaLike(double tilt, bool generic) {
  const Mat3 R0 = expSO3(Vec3(0.3, -0.5, 0.7));
  struct Line {
    Vec3 w, c;
  };
  const Vec3 y(0, -1, 0), z(0, 0, -1);
  const std::vector<Line> lines = {
      {Vec3(0, 0, 1), generic ? Vec3(15, -25, 0) : Vec3::Zero()},
      {y, generic ? Vec3(20, 0, 0) : Vec3::Zero()},
      {expSO3(Vec3(tilt, 0, 0)) * y, Vec3(100, 0, 0)},
      {z, Vec3(250, 50, 0)},
      {y, generic ? Vec3(265, 0, -20) : Vec3(250, 0, -20)},
      {z, Vec3(250, 50, 0)},
  };
  std::vector<JointSpec> joints;
  for (const Line& l : lines) {
    JointSpec s;
    s.type = JointType::Revolute;
    s.twist << R0 * l.w, (R0 * l.c).cross(R0 * l.w);
    joints.push_back(s);
  }
  const Pose T = Pose{R0, Vec3::Zero()} * Pose{Mat3::Identity(), Vec3(250, 50, -20)} *
                 Pose{expSO3(Vec3(0.4, 0.2, -0.6)), Vec3::Zero()};
  return PoeModel(joints, T, "puma-like");
}

}  // namespace calibration_helpers
