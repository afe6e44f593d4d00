#pragma once
// Helpers of the calibration commands' tests (simulate_cli_test.cpp, calibration_cli_test.cpp,
// calibration_tracker_cli_test.cpp): `simulate` run and parsed, the angle between two quaternions, the PUMA 560
// robot files of Wu et al.'s loop and MuJoCo's actual PUMA as simulate's truth.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cli_runner.hpp"
#include "csv_text.hpp"

namespace calibration_cli {

using namespace lowpair_test;
using csv_test::Csv;
using csv_test::parseCsv;
using csv_test::Quaternion;

inline Csv simulate(const std::string& args) {
  const CliRun r = runCli("simulate " + args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  return parseCsv(r.out);
}

// The angle of R_a^T R_b from the quaternions: 2 atan2(|vec(conj(a) b)|, |w(conj(a) b)|).
inline double angleBetween(const Quaternion& a, const Quaternion& b) {
  const double w = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double x = a[0] * b[1] - a[1] * b[0] - a[2] * b[3] + a[3] * b[2];
  const double y = a[0] * b[2] + a[1] * b[3] - a[2] * b[0] - a[3] * b[1];
  const double z = a[0] * b[3] - a[1] * b[2] + a[2] * b[1] - a[3] * b[0];
  return 2 * std::atan2(std::sqrt(x * x + y * y + z * z), std::abs(w));
}

inline const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");
inline const std::string kActualYaml = modelPath("puma560_okamura_actual.yaml");
inline const std::string kActualXml = modelPath("puma560_okamura_actual.xml");

inline const std::string kMujocoActual =
    shellQuote(kActualXml) + " --tip tool --joint-variables " + shellQuote(kActualYaml);

// Simulated measurements written to a scratch file.
inline std::string simulateTo(const std::string& name, const std::string& args) {
  const std::string path = scratch() + "/" + name;
  const CliRun r = runCli("simulate " + args + " --out " + shellQuote(path));
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return path;
}

}  // namespace calibration_cli
