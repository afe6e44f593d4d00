#pragma once
// The nominal PUMA (POE, mm) with k targets on its tool, spread over a 160 mm cube (not collinear): the robot
// file of the work-limit tests (work_limits_cli_test, limits_table_cli_test, third_audit_cli_test).
#include <cstdio>
#include <string>

#include "cli_runner.hpp"

namespace lowpair_test {

inline std::string nominalWithTargets(int k) {
  std::string text = "name: puma-targets\nlength_unit: mm\nangle_unit: rad\npoe:\n  joints:\n"
                     "    - {type: revolute, twist: [0, 0, 1, 0, 0, 0]}\n"
                     "    - {type: revolute, twist: [0, -1, 0, 0, 0, 0]}\n"
                     "    - {type: revolute, twist: [0, -1, 0, 0, 0, -100]}\n"
                     "    - {type: revolute, twist: [0, 0, -1, -50, 250, 0]}\n"
                     "    - {type: revolute, twist: [0, -1, 0, -20, 0, -250]}\n"
                     "    - {type: revolute, twist: [0, 0, -1, -50, 250, 0]}\n"
                     "  tool: [0, 0, 0, 250, 50, -20]\ntargets:\n";
  char line[128];
  for (int t = 0; t < k; ++t) {
    std::snprintf(line, sizeof line, "  - {name: t%d, point: [%d, %d, %d]}\n", t, (t * 37) % 160 - 80, (t * 61) % 160 - 80,
                  (t * 89) % 160 - 80);
    text += line;
  }
  return writeScratchFile("puma_" + std::to_string(k) + "_targets.yaml", text);
}

}  // namespace lowpair_test
