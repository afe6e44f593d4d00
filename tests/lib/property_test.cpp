// Property tests over 10,000 seeded random robots (2-7 joints, every joint type, unnormalized twists,
// offsets) with deliberately degenerate geometry: POE FK = converted D-H FK; dhToPoe(poeToDh(m)), the
// modified export and the tool/local forms give the same FK. Bound (design.md): rotation <= 1e-12 rad,
// translation <= 1e-12 * max(L, max |d|, max |a|).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "random_robot.hpp"

using namespace lowpair;
using lowpair_test::geometryName;
using lowpair_test::randomRobot;
using lowpair_test::RandomRobot;

namespace {

struct Worst {
  double rotation = 0, translation = 0;  // translation relative to the bound scale
  void add(const Pose& a, const Pose& b, double scale) {
    rotation = std::max(rotation, rotationError(a.R, b.R));
    translation = std::max(translation, (a.p - b.p).norm() / scale);
  }
};

}  // namespace

TEST(ConversionProperty, TenThousandRandomRobots) {
  std::mt19937_64 rng(20190201);
  std::map<std::string, Worst> by_category;
  Worst dh_roundtrip, modified, tool_form, local_form;
  int robots = 0, samples = 0;
  for (int r = 0; r < lowpair_test::robotCount(10000); ++r) {  // (1,000 under the sanitizers)
    const RandomRobot robot = randomRobot(rng);
    const PoeModel& poe = robot.model;
    const DhConversion c = poeToDh(poe);
    const PoeModel back = dhToPoe(c.model);
    const ModifiedDh mod = toModifiedDh(c.model);
    const ToolPoeModel tool = toToolPoe(poe);
    const LocalPoeModel local = toLocalPoe(poe);
    const PoeModel tool_back = fromToolPoe(tool), local_back = fromLocalPoe(local);
    // the bound's scale max(L, |d|, |a|, |d_T|), read off the table here rather than taken from the library
    double scale = std::max({poe.lengthScale(), std::abs(c.model.base().d), std::abs(c.model.base().a), std::abs(c.model.toolD())});
    for (const DhJoint& j : c.model.joints()) scale = std::max({scale, std::abs(j.link.d), std::abs(j.link.a)});
    EXPECT_EQ(scale, c.scale);
    ASSERT_TRUE(std::isfinite(scale));
    Worst& cat = by_category[geometryName(robot.geometry)];
    Data poe_data(poe);
    Data dh_data(c.model);
    for (int s = 0; s < 20; ++s) {
      const VecX q = lowpair_test::randomConfiguration(poe, rng);
      forwardKinematics(poe, poe_data, q);
      forwardKinematics(c.model, dh_data, q);
      const Pose& ref = poe_data.T_base_tool;
      ASSERT_TRUE(dh_data.T_base_tool.matrix().allFinite());
      cat.add(ref, dh_data.T_base_tool, scale);
      dh_roundtrip.add(ref, poeForwardKinematics(back, q), scale);
      modified.add(ref, modifiedDhForwardKinematics(mod, q), scale);
      tool_form.add(ref, forwardKinematics(tool, q), scale);
      tool_form.add(ref, poeForwardKinematics(tool_back, q), scale);
      local_form.add(ref, forwardKinematics(local, q), scale);
      local_form.add(ref, poeForwardKinematics(local_back, q), scale);
      ++samples;
    }
    ++robots;
  }
  std::printf("%d robots, %d joint vectors each (%d comparisons per form)\n", robots, 20, samples);
  std::printf("%-26s %14s %24s\n", "category", "max rot (rad)", "max trans / max(L,|d|,|a|)");
  Worst all;
  for (const auto& [name, w] : by_category) {
    std::printf("%-26s %14.3g %24.3g\n", name.c_str(), w.rotation, w.translation);
    all.rotation = std::max(all.rotation, w.rotation);
    all.translation = std::max(all.translation, w.translation);
  }
  std::printf("%-26s %14.3g %24.3g\n", "dhToPoe(poeToDh(m))", dh_roundtrip.rotation, dh_roundtrip.translation);
  std::printf("%-26s %14.3g %24.3g\n", "modified D-H export", modified.rotation, modified.translation);
  std::printf("%-26s %14.3g %24.3g\n", "tool POE form", tool_form.rotation, tool_form.translation);
  std::printf("%-26s %14.3g %24.3g\n", "local POE form", local_form.rotation, local_form.translation);
  EXPECT_LE(all.rotation, 1e-12);
  EXPECT_LE(all.translation, 1e-12);
  for (const Worst& w : {dh_roundtrip, modified, tool_form, local_form}) {
    EXPECT_LE(w.rotation, 1e-12);
    EXPECT_LE(w.translation, 1e-12);
  }
}
