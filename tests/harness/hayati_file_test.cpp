// Hayati rows in robot files (docs/file_formats.md, `beta`): a calibrated UR-type arm's D-H table written by
// formatDhRobotFile (export --format dh) and read back by readRobotFile equals the calibrated POE to 1e-12 L,
// in rad and in deg files; a standard table is written without beta; beta with a nonfinite value is refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "io/robot_file.hpp"
#include "lowpair/convert.hpp"
#include "hayati_helpers.hpp"
#include "lowpair/se3.hpp"

using namespace lowpair;
using hayati_helpers::poeDifference;

namespace {

PoeModel calibratedUr(double tilt, std::mt19937_64& rng) {
  const double d[6] = {0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823};
  const double a[6] = {0.0, -0.425, -0.39225, 0.0, 0.0, 0.0};
  const double alpha[6] = {M_PI / 2, 0.0, 0.0, M_PI / 2, -M_PI / 2, 0.0};
  std::vector<DhJoint> joints(6);
  for (int i = 0; i < 6; ++i) {
    joints[static_cast<size_t>(i)].link.alpha = alpha[i];
    joints[static_cast<size_t>(i)].link.a = a[i];
    joints[static_cast<size_t>(i)].link.d = d[i];
  }
  const PoeModel nominal = dhToPoe(DhModel(DhParams{}, joints, 0.0, 0.0, "ur5"));
  std::normal_distribution<double> n;
  auto eta = [&]() {
    Vec6 e;
    for (int k = 0; k < 6; ++k) e[k] = n(rng);
    e.head<3>() *= tilt / e.head<3>().norm();
    e.tail<3>() *= 1e-3 * nominal.lengthScale() / e.tail<3>().norm();
    return e;
  };
  std::vector<Joint> moved = nominal.joints();
  for (Joint& j : moved) j.twist = adjointApply(expSE3(eta()), j.twist);
  return PoeModel(std::move(moved), expSE3(eta()) * nominal.toolPose(), "ur5-calibrated");
}

io::RobotFile writeAndRead(const DhModel& dh, const std::string& angle_unit, std::string* text = nullptr) {
  io::RobotFile like;
  like.angle_unit = angle_unit;
  const std::string yaml = io::formatDhRobotFile(dh, like, "ur", "", {});
  if (text) *text = yaml;
  // the process id in the name: ctest runs this program's tests as processes side by side
  const auto path = std::filesystem::temp_directory_path() /
                    ("hayati_file_test_" + std::to_string(::getpid()) + "_" + angle_unit + ".yaml");
  std::ofstream(path) << yaml;
  io::RobotFile back = io::readRobotFile(path.string());
  std::filesystem::remove(path);
  return back;
}


}  // namespace

TEST(HayatiFile, ExportReadBackEqualsTheCalibratedPoe) {
  std::mt19937_64 rng(26);
  double worst = 0.0;
  for (const std::string unit : {"rad", "deg"}) {
    for (const double tilt : {1e-4, 1e-3, 1e-2}) {
      const PoeModel poe = calibratedUr(tilt, rng);
      const DhConversion c = poeToDh(poe);
      std::string text;
      const io::RobotFile back = writeAndRead(c.model, unit, &text);
      ASSERT_TRUE(back.dh.has_value());
      EXPECT_NE(text.find("beta"), std::string::npos);
      EXPECT_TRUE((back.dh->joint(1).link.hayati() && back.dh->joint(2).link.hayati()) || tilt > 1e-3);
      const double e = poeDifference(poe, dhToPoe(*back.dh));
      worst = std::max(worst, e);
      EXPECT_LE(e, 1e-12) << unit << " tilt " << tilt;
    }
  }
  std::printf("export -> read back -> POE: %.3g (rad, L)\n", worst);
}

TEST(HayatiFile, StandardTableHasNoBeta) {
  std::mt19937_64 rng(1);
  const PoeModel exact = dhToPoe(poeToDh(calibratedUr(0.0, rng)).model);
  std::string text;
  const io::RobotFile back = writeAndRead(poeToDh(exact).model, "rad", &text);
  EXPECT_EQ(text.find("beta"), std::string::npos);
  EXPECT_FALSE(back.dh->joint(1).link.hayati());
}
