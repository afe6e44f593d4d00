#include "lowpair/joint.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "check.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

std::string jointLabel(int index, const std::string& name) {
  std::ostringstream out;
  out << "joint " << index + 1;
  if (!name.empty()) out << " (" << name << ")";
  return out.str();
}

double safeNorm(const Vec3& u) {
  // |u| by the plain sum of squares where no square can overflow or underflow (its rounding is what
  // every other computation sees: a unit axis keeps |w| = 1 exactly), by Eigen's scaled norm otherwise
  constexpr double kPlainNormMin = 1e-150, kPlainNormMax = 1e150;  // squares stay normal doubles
  const double plain = u.norm();
  return plain > kPlainNormMin && plain < kPlainNormMax ? plain : u.stableNorm();
}

Joint normalizeJoint(const JointSpec& spec, int index, double size) {
  const std::string label = jointLabel(index, spec.name);
  LP_CHECK(spec.twist.allFinite(), label << ": twist has a non-finite entry");
  LP_CHECK(std::isfinite(spec.offset), label << ": offset is not finite");
  if (spec.range) {
    const auto& r = *spec.range;
    LP_CHECK(std::isfinite(r[0]) && std::isfinite(r[1]), label << ": range is not finite");
    LP_CHECK(r[0] <= r[1], label << ": range [" << r[0] << ", " << r[1] << "] has lo > hi");
  }
  Joint j;
  j.name = spec.name;
  j.offset = spec.offset;
  j.range = spec.range;
  const Vec3 w = spec.twist.head<3>();
  const Vec3 v = spec.twist.tail<3>();
  const double w_norm = safeNorm(w);
  const double v_norm = safeNorm(v);
  if (w_norm == 0.0) {
    LP_CHECK(v_norm > 0.0, label << ": twist is zero");
    LP_CHECK(!spec.type || *spec.type == JointType::Prismatic,
             label << ": declared " << jointTypeName(*spec.type)
                   << " but its twist has w = 0 (a prismatic joint)");
    j.type = JointType::Prismatic;
    j.scale = v_norm;
    j.twist << Vec3::Zero(), v / v_norm;
    return j;
  }
  LP_CHECK(!spec.type || *spec.type != JointType::Prismatic,
           label << ": declared prismatic but its twist has w != 0 (|w| = " << w_norm << ")");
  j.scale = w_norm;
  Vec3 w_unit = w / w_norm;
  Vec3 v_unit = v / w_norm;
  const double pitch = w_unit.dot(v_unit);
  // judged against the robot's size when known: a twist moved metres away carries rounding of eps times the
  // move in v, which can be far above eps |v| when its axis ends up near the origin
  const bool pitch_is_rounding = std::abs(w.dot(v)) <= kPitchZero * kEps * w_norm * std::max(v_norm, w_norm * size);
  JointType type = spec.type ? *spec.type : (pitch_is_rounding ? JointType::Revolute : JointType::Helical);
  if (type == JointType::Revolute) {
    LP_CHECK(pitch_is_rounding,
             label << ": declared revolute but its twist has pitch w.v/|w|^2 = " << pitch
                   << " (|w.v| / (|w| |v|) = " << std::abs(w.dot(v)) / (w_norm * v_norm)
                   << ", above the rounding tolerance " << kPitchZero * kEps << "); declare it helical");
    v_unit -= pitch * w_unit;  // remove the rounding-level pitch
    j.pitch = 0.0;
  } else {
    j.pitch = pitch;
  }
  j.type = type;
  j.twist << w_unit, v_unit;
  // a twist whose |v| / |w| (or pitch) does not fit in a double cannot be evaluated: say so here
  LP_CHECK(j.twist.allFinite() && std::isfinite(j.pitch) && std::isfinite(j.scale),
           label << ": twist cannot be normalized in double precision (|w| = " << w_norm << ", |v| = " << v_norm
                 << ")");
  return j;
}

double lengthScaleOfSpecs(const std::vector<JointSpec>& joints, const Vec3& p_tool) {
  double size = p_tool.allFinite() ? safeNorm(p_tool) : 0.0;
  for (const JointSpec& s : joints) {
    const Vec3 w = s.twist.head<3>(), v = s.twist.tail<3>();
    const double w_norm = safeNorm(w);
    if (w_norm == 0.0 || !s.twist.allFinite()) continue;
    const double distance = safeNorm((w / w_norm).cross(v / w_norm));
    if (std::isfinite(distance)) size = std::max(size, distance);
  }
  return size;
}

}  // namespace lowpair
