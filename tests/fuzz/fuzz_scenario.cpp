// Fuzz target: the scenario reader (harness/scenario.hpp). The input is a scenario (YAML). Allowed:
// RobotFileError. An accepted scenario's numbers are finite and within the documented limits.
#include "fuzz_common.hpp"
#include "io/robot_file.hpp"
#include "validation/scenario.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::validation;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const lowpair_fuzz::TempFile file(".yaml");
  try {
    const lowpair::validation::Scenario s = lowpair::validation::readScenario(file.write(data, size));
    FUZZ_CHECK(s.samples >= 0 && s.samples <= lowpair::validation::kMaxSamples);
    FUZZ_CHECK(s.seed <= static_cast<unsigned long long>(lowpair::commands::kMaxSeed));
    for (const auto& r : s.ranges) FUZZ_CHECK(std::isfinite(r[0]) && std::isfinite(r[1]));
    FUZZ_CHECK(std::isfinite(s.tol_rotation) && std::isfinite(s.tol_translation) &&
               std::isfinite(s.tol_jacobian_rotation) && std::isfinite(s.tol_jacobian_translation));
    for (const auto& p : s.poses)
      for (const double q : p.q) FUZZ_CHECK(std::isfinite(q));
    for (const auto& p : s.singular_poses)
      for (const double q : p.q) FUZZ_CHECK(std::isfinite(q));
    for (const double v : s.map_fixed) FUZZ_CHECK(std::isfinite(v));
    for (const auto& c : s.calibrations) {
      FUZZ_CHECK(c.poses >= 0 && c.poses <= lowpair::validation::kMaxCalibrationPoses);
      FUZZ_CHECK(c.validation_poses >= 0 && c.validation_poses <= lowpair::validation::kMaxCalibrationPoses);
      FUZZ_CHECK(std::isfinite(c.noise_position) && std::isfinite(c.noise_rotation) &&
                 std::isfinite(c.tolerance_position));
      FUZZ_CHECK(!c.tolerance_rotation || std::isfinite(*c.tolerance_rotation));
      FUZZ_CHECK(!c.min_improvement || std::isfinite(*c.min_improvement));
    }
  } catch (const lowpair::io::RobotFileError&) {
  }
  return 0;
}
