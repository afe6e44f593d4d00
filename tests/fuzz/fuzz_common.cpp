#include "fuzz_common.hpp"

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"

namespace lowpair_fuzz {

using namespace lowpair;

namespace {
bool finite(const DhParams& r) {
  return std::isfinite(r.theta) && std::isfinite(r.d) && std::isfinite(r.alpha) && std::isfinite(r.a);
}
}  // namespace

void checkPoeModel(const PoeModel& model) {
  FUZZ_CHECK(std::isfinite(model.size()) && model.size() > 0.0);
  for (const Joint& j : model.joints()) FUZZ_CHECK(j.twist.allFinite() && std::isfinite(j.scale));
  FUZZ_CHECK(finite(model.toolPose()));
  for (const VecX& q : fixedConfigurations(rangesOf(model.joints()))) {
    FUZZ_CHECK(finite(poeForwardKinematics(model, q)));
  }
}

void checkConversion(const PoeModel& model) {
  if (model.dof() == 0) return;
  const DhConversion conv = poeToDh(model);
  const DhModel& dh = conv.model;
  FUZZ_CHECK(finite(dh.base()) && std::isfinite(dh.toolTheta()) && std::isfinite(dh.toolD()));
  for (const DhJoint& j : dh.joints()) FUZZ_CHECK(finite(j.link) && std::isfinite(j.pitch) && std::isfinite(j.scale));
  FUZZ_CHECK(std::isfinite(conv.scale) && std::isfinite(conv.size));
  const FkCheck check = checkDhConversion(model, dh, 8);
  if (!(std::isfinite(check.max_rotation) && std::isfinite(check.max_translation)))
    std::fprintf(stderr, "checkDhConversion: max_rotation %g max_translation %g scale %g\n", check.max_rotation,
                 check.max_translation, check.scale);
  FUZZ_CHECK(std::isfinite(check.max_rotation) && std::isfinite(check.max_translation) && std::isfinite(check.scale));
  for (const VecX& q : fixedConfigurations(rangesOf(dh.joints()))) FUZZ_CHECK(finite(dhForwardKinematics(dh, q)));
}

}  // namespace lowpair_fuzz
