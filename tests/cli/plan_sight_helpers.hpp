#pragma once
// What plan_sight_cli_test and plan_sight_study share: the test data of tests/data/collision/ and the actual
// Menagerie-style cell the loop calibrates.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.hpp"

namespace plan_sight {

const std::string kData = std::string(LOWPAIR_TEST_DATA) + "/collision/";
const std::string kCellXml = kData + "menagerie_arm_cell.xml", kCellYaml = kData + "menagerie_arm_cell.yaml";

// The actual cell, written to the scratch folder: the nominal's elbow axis moved 0.3 mm along x and wrist 1's
// tilted 1 mrad (each twist kept revolute: w . v = 0). Returns its path ("" when the nominal changed).
inline std::string actualCell() {
  std::ifstream in(kCellYaml);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"-0.51400000000000001, 0, 0]", "-0.51400000000000001, 0, 0.0003]"},
                                 {"[0, 1, 0, -0.90600000000000003", "[0, 1, 0.001, -0.90600000000000003"}}) {
    const size_t at = text.find(from);
    if (at == std::string::npos) {
      ADD_FAILURE() << kCellYaml << " no longer holds " << from;
      return "";
    }
    text.replace(at, from.size(), to);
  }
  return lowpair_test::writeScratchFile("cell_actual.yaml", text);
}

}  // namespace plan_sight
