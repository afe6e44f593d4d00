#pragma once
// Joint ranges as the inverse-kinematics solvers use them (ik.cpp, ik_closed_form.cpp): whole turns of a
// revolute joint, membership, moving a value into a range by whole turns. Internal, not installed.
#include <cmath>

#include "lowpair/joint.hpp"

namespace lowpair::ik_ranges {

// A revolute joint repeats its pose every 2 pi / scale in q (a helical one slides on: it never does).
inline bool periodic(const Joint& joint) { return joint.type == JointType::Revolute; }
inline double period(const Joint& joint) { return 2.0 * M_PI / joint.scale; }

inline bool inRange(const Joint& joint, double q) {
  return !joint.range || (q >= (*joint.range)[0] && q <= (*joint.range)[1]);
}

// q moved by whole periods into [lo, hi] when that is possible (false otherwise, q unchanged)
inline bool wrapInto(const Joint& joint, double& q) {
  const auto& range = *joint.range;
  if (!periodic(joint)) return false;
  const double P = period(joint);
  const double moved = q - std::floor((q - range[0]) / P) * P;  // in [lo, lo + P) up to rounding
  if (!(moved >= range[0] && moved <= range[1])) return false;
  q = moved;
  return true;
}

}  // namespace lowpair::ik_ranges
