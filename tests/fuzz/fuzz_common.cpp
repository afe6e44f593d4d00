#include "fuzz_common.hpp"

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"

#include <cstring>
#include <optional>

namespace lowpair_fuzz {

using namespace lowpair;

namespace {
bool finite(const DhParams& r) {
  return std::isfinite(r.theta) && std::isfinite(r.d) && std::isfinite(r.alpha) && std::isfinite(r.a);
}
}  // namespace

void checkPoeModel(const PoeModel& model) {
  FUZZ_CHECK(std::isfinite(model.lengthScale()) && model.lengthScale() > 0.0);
  for (const Joint& j : model.joints()) FUZZ_CHECK(j.twist.allFinite() && std::isfinite(j.scale));
  FUZZ_CHECK(finite(model.toolPose()));
  for (const VecX& q : fixedConfigurations(rangesOf(model.joints()))) {
    FUZZ_CHECK(finite(poeForwardKinematics(model, q)));
  }
}

bool checkConversion(const PoeModel& model) {
  if (model.dof() == 0) return false;
  // poeToDh may reject a table beyond the magnitude limits only when the folded offsets can move the frames
  // that far: (2n + 1) L (rotations about axes within L of the origin) plus every joint's offset slide
  std::optional<DhConversion> converted;
  try {
    converted.emplace(poeToDh(model));
  } catch (const std::invalid_argument& e) {
    double reach = (2.0 * model.dof() + 1.0) * model.lengthScale();
    for (const Joint& j : model.joints()) reach += std::abs(j.slideRate() * j.motion(0.0));
    if (!(reach > kMaxMagnitude)) std::fprintf(stderr, "poeToDh threw: %s (reach %g)\n", e.what(), reach);
    FUZZ_CHECK(reach > kMaxMagnitude && std::strncmp(e.what(), "poeToDh: ", 9) == 0);
    return false;
  }
  const DhConversion& conv = *converted;
  const DhModel& dh = conv.model;
  FUZZ_CHECK(finite(dh.base()) && std::isfinite(dh.toolTheta()) && std::isfinite(dh.toolD()));
  for (const DhJoint& j : dh.joints()) FUZZ_CHECK(finite(j.link) && std::isfinite(j.pitch) && std::isfinite(j.scale));
  FUZZ_CHECK(std::isfinite(conv.scale) && std::isfinite(conv.length_scale));
  const FkCheck check = checkDhConversion(model, dh, 8);
  if (!(std::isfinite(check.max_rotation) && std::isfinite(check.max_translation)))
    std::fprintf(stderr, "checkDhConversion: max_rotation %g max_translation %g scale %g\n", check.max_rotation,
                 check.max_translation, check.scale);
  FUZZ_CHECK(std::isfinite(check.max_rotation) && std::isfinite(check.max_translation) && std::isfinite(check.scale));
  for (const VecX& q : fixedConfigurations(rangesOf(dh.joints()))) FUZZ_CHECK(finite(dhForwardKinematics(dh, q)));
  return true;
}

}  // namespace lowpair_fuzz
