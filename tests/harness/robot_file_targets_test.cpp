// Robot files' `targets:` (docs/file_formats.md): named points on the tool (laser-tracker SMRs), read in the
// tool frame and the file's length_unit, written by the POE and D-H writers and read back bit for bit, the
// errors naming file, line and target, the limit of a thousand, and the writers refusing what would not read
// back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "robot_file_helpers.hpp"
#include "scratch_folder.hpp"
#include "io/export.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

namespace lowpair {
namespace {

using export_helpers::scratch;

// Robot files' `targets:` (docs/file_formats.md): named points on the tool (laser-tracker SMRs), tool frame,
// length_unit.

using robot_file_helpers::robotFileError;
using robot_file_helpers::sameBits;


// A two-joint POE robot in mm, its `targets:` key on line 8 and its first entry on line 9.
const std::string kTwoJoints =
    "name: two\n"
    "length_unit: mm\n"
    "poe:\n"
    "  joints:\n"
    "    - {twist: [0, 0, 1, 0, 0, 0]}\n"
    "    - {twist: [0, 1, 0, 0, 0, 100]}\n"
    "  tool_pose: [[1, 0, 0, 200], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n";

// Names YAML would read as something else unless yaml-cpp quotes them, and CSV-safe text of every kind.
const std::vector<std::string> kAwkwardNames = {
    "smr_a", "null", "~", "Null", "true", "no", "#3", "-", "a:b", "[x]", "{y}", "&a", "*b", "!t", "%p", "@q",
    "`r", "|", ">", "?", "1e3", "0x10", ".inf", "-.nan", "a#b", "SMR-1/2", std::string(64, 'z')};

std::vector<Target> randomTargets(const std::vector<std::string>& names, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Target> targets;
  for (const std::string& name : names) {
    // magnitudes from 1e-40 to 1e40 (within 1e100 in norm), a negative zero and a subnormal
    Vec3 p;
    for (int i = 0; i < 3; ++i) p[i] = unit(rng) * std::pow(10.0, 40 * unit(rng));
    if (targets.size() == 1) p = Vec3(-0.0, 4.9406564584124654e-324, -9e99);
    targets.push_back({name, p});
  }
  return targets;
}

void expectSameTargets(const std::vector<Target>& written, const std::vector<Target>& read, const std::string& where) {
  ASSERT_EQ(read.size(), written.size()) << where;
  for (size_t k = 0; k < written.size(); ++k) {
    EXPECT_EQ(read[k].name, written[k].name) << where;
    ASSERT_TRUE(read[k].point_tool.has_value()) << where;
    for (int i = 0; i < 3; ++i) {
      EXPECT_TRUE(sameBits((*read[k].point_tool)[i], (*written[k].point_tool)[i]))
          << where << ": target " << written[k].name << "[" << i << "] " << (*written[k].point_tool)[i] << " read as "
          << (*read[k].point_tool)[i];
    }
  }
}

TEST(RobotFileTargets, ReadInTheToolFrameAndLengthUnit) {
  const std::string path = scratch().write("targets_read.yaml", kTwoJoints +
                                                                    "targets:\n"
                                                                    "  - {name: smr_a, point: [10, 0, 5]}\n"
                                                                    "  - name: smr_b\n"
                                                                    "    point: [-10, 0.5, 5e1]\n");
  const RobotFile file = readRobotFile(path);
  ASSERT_EQ(file.targets.size(), 2u);
  EXPECT_EQ(file.targets[0].name, "smr_a");
  EXPECT_EQ(file.targets[1].name, "smr_b");
  ASSERT_TRUE(file.targets[0].point_tool && file.targets[1].point_tool);
  EXPECT_EQ(*file.targets[0].point_tool, Vec3(10, 0, 5));
  EXPECT_EQ(*file.targets[1].point_tool, Vec3(-10, 0.5, 50));
  // the model is the one without targets
  const RobotFile bare = readRobotFile(scratch().write("targets_none.yaml", kTwoJoints));
  EXPECT_TRUE(bare.targets.empty());
  EXPECT_EQ(file.poeModel().toolPose().matrix(), bare.poeModel().toolPose().matrix());
  EXPECT_TRUE(readRobotFile(scratch().write("targets_empty.yaml", kTwoJoints + "targets: []\n")).targets.empty());

  // lengths converted: mm -> m and km; a D-H file (converted to POE by inUnit) keeps its targets
  const RobotFile metres = inMetres(file);
  ASSERT_EQ(metres.targets.size(), 2u);
  EXPECT_EQ(metres.targets[1].name, "smr_b");
  EXPECT_DOUBLE_EQ((*metres.targets[0].point_tool)[0], 0.01);
  EXPECT_DOUBLE_EQ((*metres.targets[1].point_tool)[2], 0.05);
  EXPECT_DOUBLE_EQ((*inUnit(file, "km").targets[1].point_tool)[1], 5e-7);
  RobotFile dh = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_corke.yaml");  // metres
  dh.targets = {{"t", Vec3(0.1, -0.2, 0.3)}};
  const RobotFile dh_mm = inUnit(dh, "mm");
  ASSERT_EQ(dh_mm.targets.size(), 1u);
  EXPECT_DOUBLE_EQ((*dh_mm.targets[0].point_tool)[1], -200.0);
  // beyond 1e100 in the new unit: refused, not carried as a length the library would not evaluate
  RobotFile huge = file;
  huge.targets[0].point_tool = Vec3(9e99, 0, 0);
  try {
    inUnit(huge, "um");
    ADD_FAILURE() << "a target point of 9e102 um was converted";
  } catch (const RobotFileError& e) {
    EXPECT_NE(std::string(e.what()).find("target 'smr_a': point in um has magnitude 9e+102, above 1e100"), std::string::npos)
        << e.what();
  }
}

TEST(RobotFileTargets, PoeAndDhFilesReadBackBitForBit) {
  const std::vector<Target> targets = randomTargets(kAwkwardNames, 21);
  const RobotFile poe = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_okamura_nominal.yaml");
  const RobotFile dh = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_corke.yaml");
  ASSERT_TRUE(poe.poe && dh.dh);
  const std::string poe_path = scratch().write(
      "targets_poe.yaml", formatPoeRobotFile(*poe.poe, poe, poe.name, poe.description, {"targets test"}, RobotFileExtras{targets}));
  const std::string dh_path =
      scratch().write("targets_dh.yaml", formatDhRobotFile(*dh.dh, dh, dh.name, dh.description, {}, RobotFileExtras{targets}));
  const RobotFile poe_back = readRobotFile(poe_path), dh_back = readRobotFile(dh_path);
  expectSameTargets(targets, poe_back.targets, poe_path);
  expectSameTargets(targets, dh_back.targets, dh_path);
  EXPECT_TRUE(dh_back.dh.has_value());
  // without targets no key is written (existing callers' files are unchanged)
  const std::string plain = formatPoeRobotFile(*poe.poe, poe, poe.name, poe.description, {});
  EXPECT_EQ(plain.find("targets"), std::string::npos);
  EXPECT_TRUE(readRobotFile(scratch().write("targets_plain.yaml", plain)).targets.empty());
  // the file's own targets, written and read again
  const std::string again = scratch().write(
      "targets_again.yaml", formatPoeRobotFile(*poe_back.poe, poe_back, "again", "", {}, RobotFileExtras{poe_back.targets}));
  expectSameTargets(targets, readRobotFile(again).targets, again);
}

TEST(RobotFileTargets, ErrorsNameFileLineAndTarget) {
  const std::string rule = " (a target name is 1-64 printable ASCII characters without spaces, commas or quotes)";
  struct Case {
    std::string targets, error;  // `targets:` and what follows it (line 8 on); the error after "PATH: "
  };
  const Case cases[] = {
      {"targets:\n  - {name: smr, point: [1, 2, 3]}\n", ""},
      {"targets:\n  - {name: a, point: [0, 0, 0]}\n  - {name: b, point: [1, 0, 0]}\n  - {name: a, point: [2, 0, 0]}\n",
       "line 11: targets[2].name 'a' repeats targets[0]'s"},
      {"targets:\n  - {name: \"\", point: [0, 0, 0]}\n", "line 9: targets[0].name '' is empty" + rule},
      {"targets:\n  - {name: a b, point: [0, 0, 0]}\n", "line 9: targets[0].name 'a b' holds a space" + rule},
      {"targets:\n  - {name: \"a,b\", point: [0, 0, 0]}\n", "line 9: targets[0].name 'a,b' holds a comma" + rule},
      {"targets:\n  - {name: 'a\"b', point: [0, 0, 0]}\n", "line 9: targets[0].name 'a\"b' holds a quote" + rule},
      {"targets:\n  - {name: \"\xC2\xB5m\", point: [0, 0, 0]}\n",
       "line 9: targets[0].name '??m' holds a byte outside printable ASCII" + rule},
      {"targets:\n  - {name: \"tab\\there\", point: [0, 0, 0]}\n",
       "line 9: targets[0].name 'tab?here' holds a byte outside printable ASCII" + rule},
      {"targets:\n  - {name: " + std::string(64, 'n') + ", point: [0, 0, 0]}\n", ""},
      {"targets:\n  - {name: " + std::string(65, 'n') + ", point: [0, 0, 0]}\n",
       "line 9: targets[0].name '" + std::string(40, 'n') + "...' has 65 characters (at most 64)" + rule},
      {"targets:\n  - {name: ~, point: [0, 0, 0]}\n", "line 9: targets[0].name must be a string"},
      {"targets:\n  - {name: a, point: [.inf, 0, 0]}\n", "line 9: targets[0].point[0] is not finite ('.inf')"},
      {"targets:\n  - {name: a, point: [0, -.inf, 0]}\n", "line 9: targets[0].point[1] is not finite ('-.inf')"},
      {"targets:\n  - {name: a, point: [0, 0, .nan]}\n", "line 9: targets[0].point[2] is not finite ('.nan')"},
      {"targets:\n  - {name: a, point: [9e99, 0, 0]}\n", ""},
      {"targets:\n  - {name: a, point: [0, 0, 1e101]}\n",
       "line 9: targets[0].point has magnitude 1e+101, above 1e100 (kMaxMagnitude)"},
      {"targets:\n  - {name: a, point: [8e99, 8e99, 0]}\n",
       "line 9: targets[0].point has magnitude 1.13137e+100, above 1e100 (kMaxMagnitude)"},
      {"targets:\n  - {name: a, point: [1e200, 1e200, 1e200]}\n",
       "line 9: targets[0].point has magnitude inf, above 1e100 (kMaxMagnitude)"},
      {"targets:\n  - {name: a, point: [0, 0]}\n", "line 9: targets[0].point must have 3 entries, got 2"},
      {"targets:\n  - {name: a}\n", "line 9: targets[0]: missing 'point' (x, y, z in the tool frame)"},
      {"targets:\n  - {point: [0, 0, 0]}\n", "line 9: targets[0]: missing 'name'"},
      {"targets:\n  - {name: a, point: [0, 0, 0], radius: 1}\n",
       "line 9: unknown key 'radius' in targets[0] (allowed: known, name, normal, point)"},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [0, 0, 0]}\n",
       "line 9: targets[0].normal must be a finite nonzero direction (x, y, z in the tool frame)"},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [-0.0, 0, 0]}\n", "targets[0].normal must be a finite nonzero"},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [1e-320, 0, 0]}\n", ""},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [1e300, 1e300, 0]}\n", ""},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [0, .nan, 1]}\n", "targets[0].normal[1] is not finite"},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [0, 1]}\n", "targets[0].normal must have 3 entries, got 2"},
      {"targets:\n  - {name: a, point: [0, 0, 0], normal: [1e-300, 0, 0]}\n", ""},
      {"targets: {name: a, point: [0, 0, 0]}\n", "line 8: targets must be a list of {name: N, point: [x, y, z]}"},
      {"targets:\n", "targets must be a list of {name: N, point: [x, y, z]}"},
  };
  for (const Case& c : cases) {
    const std::string path = scratch().write("targets_error.yaml", kTwoJoints + c.targets);
    const std::string error = robotFileError(path);
    if (c.error.empty()) {
      EXPECT_EQ(error, "") << c.targets;
    } else {
      EXPECT_EQ(error.substr(0, path.size() + 2), path + ": ") << c.targets;
      EXPECT_NE(error.find(c.error), std::string::npos) << c.targets << "\n  got: " << error;
    }
  }
  // a D-H file takes targets too
  const std::string dh = scratch().write("targets_dh_error.yaml",
                                         "dh:\n  joints:\n    - {type: revolute, a: 1}\n"
                                         "targets:\n  - {name: a, point: [0, 0, 0]}\n  - {name: a, point: [0, 0, 1]}\n");
  EXPECT_EQ(robotFileError(dh), dh + ": line 6: targets[1].name 'a' repeats targets[0]'s");
}

// `normal:` (plan --tracker's SMR angle): read as a unit vector, none when absent; a subnormal or huge normal
// keeps its direction (the norm is computed scaled), exactly for one nonzero entry.
TEST(RobotFileTargets, NormalsAreUnitVectorsOrNone) {
  const std::string path = scratch().write(
      "targets_normals.yaml", kTwoJoints + "targets:\n  - {name: a, point: [1, 0, 0], normal: [0, 0, -2]}\n"
                                           "  - {name: b, point: [0, 1, 0]}\n"
                                           "  - {name: c, point: [0, 0, 1], normal: [3, 4, 0]}\n"
                                           "  - {name: d, point: [0, 0, 2], normal: [0, 1e-320, 0]}\n");
  const RobotFile f = readRobotFile(path);
  ASSERT_EQ(f.target_normals.size(), 4u);
  ASSERT_TRUE(f.target_normals[0] && f.target_normals[2] && f.target_normals[3]);
  EXPECT_FALSE(f.target_normals[1].has_value());
  EXPECT_EQ(*f.target_normals[0], Vec3(0, 0, -1));  // exact: one nonzero entry divided by its own magnitude
  EXPECT_EQ(*f.target_normals[3], Vec3(0, 1, 0));
  // (0.6, 0.8) to rounding: each entry within an ulp or two of x / 5
  EXPECT_NEAR((*f.target_normals[2])[0], 0.6, 4 * std::numeric_limits<double>::epsilon());
  EXPECT_NEAR((*f.target_normals[2])[1], 0.8, 4 * std::numeric_limits<double>::epsilon());
  EXPECT_NEAR(f.target_normals[2]->norm(), 1.0, 4 * std::numeric_limits<double>::epsilon());
}

TEST(RobotFileTargets, AtMostAThousand) {
  std::string list = "targets:\n";
  for (int k = 0; k < kMaxTargets; ++k) list += "  - {name: t" + std::to_string(k) + ", point: [0, 0, " + std::to_string(k) + "]}\n";
  const RobotFile file = readRobotFile(scratch().write("targets_1000.yaml", kTwoJoints + list));
  ASSERT_EQ(file.targets.size(), static_cast<size_t>(kMaxTargets));
  EXPECT_EQ(file.targets.back().name, "t999");
  EXPECT_EQ(*file.targets.back().point_tool, Vec3(0, 0, 999));
  const std::string path = scratch().write("targets_1001.yaml", kTwoJoints + list + "  - {name: t1000, point: [0, 0, 0]}\n");
  EXPECT_EQ(robotFileError(path), path + ": line 9: targets: 1001 targets, at most 1000");
}

// The writers refuse targets readRobotFile would refuse: what they write always reads back.
TEST(RobotFileTargets, WritersRefuseWhatWouldNotReadBack) {
  const RobotFile poe = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_okamura_nominal.yaml");
  const RobotFile dh = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_corke.yaml");
  const auto refused = [&](const std::vector<Target>& targets) {
    bool poe_refused = false, dh_refused = false;
    try {
      formatPoeRobotFile(*poe.poe, poe, "p", "", {}, RobotFileExtras{targets});
    } catch (const std::invalid_argument&) {
      poe_refused = true;
    }
    try {
      formatDhRobotFile(*dh.dh, dh, "d", "", {}, RobotFileExtras{targets});
    } catch (const std::invalid_argument&) {
      dh_refused = true;
    }
    EXPECT_EQ(poe_refused, dh_refused);
    return poe_refused && dh_refused;
  };
  EXPECT_FALSE(refused({{"ok", Vec3(1, 2, 3)}}));
  EXPECT_TRUE(refused({{"", Vec3(1, 2, 3)}}));
  EXPECT_TRUE(refused({{"a b", Vec3(1, 2, 3)}}));
  EXPECT_TRUE(refused({{std::string(65, 'n'), Vec3(1, 2, 3)}}));
  EXPECT_TRUE(refused({{"\xC2\xB5m", Vec3(1, 2, 3)}}));
  EXPECT_TRUE(refused({{"a", Vec3(1, 2, 3)}, {"a", Vec3(4, 5, 6)}}));
  EXPECT_TRUE(refused({{"a", std::nullopt}}));
  EXPECT_TRUE(refused({{"a", Vec3(std::nan(""), 0, 0)}}));
  EXPECT_TRUE(refused({{"a", Vec3(0, std::numeric_limits<double>::infinity(), 0)}}));
  EXPECT_TRUE(refused({{"a", Vec3(0, 0, 2e100)}}));
  std::vector<Target> many;
  for (int k = 0; k <= kMaxTargets; ++k) many.push_back({"t" + std::to_string(k), Vec3::Zero()});
  EXPECT_TRUE(refused(many));
  many.pop_back();
  EXPECT_FALSE(refused(many));
}

}  // namespace
}  // namespace lowpair
