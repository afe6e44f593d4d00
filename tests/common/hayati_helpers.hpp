#pragma once
// Helpers of the Hayati-row tests (hayati_test.cpp, hayati_file_test.cpp).

#include <algorithm>

#include "lowpair/kinematics.hpp"
#include "lowpair/model.hpp"
#include "lowpair/se3.hpp"

namespace hayati_helpers {

// The largest difference of twists (angular parts in rad, linear parts over L) and of tool poses.
inline double poeDifference(const lowpair::PoeModel& a, const lowpair::PoeModel& b) {
  const double L = a.lengthScale();
  double out = 0.0;
  for (int i = 0; i < a.dof(); ++i) {
    const lowpair::Vec6 d = a.joint(i).twist - b.joint(i).twist;
    out = std::max({out, d.head<3>().cwiseAbs().maxCoeff(), d.tail<3>().cwiseAbs().maxCoeff() / L});
  }
  out = std::max(out, lowpair::rotationError(a.toolPose().R, b.toolPose().R));
  return std::max(out, (a.toolPose().p - b.toolPose().p).norm() / L);
}

}  // namespace hayati_helpers
