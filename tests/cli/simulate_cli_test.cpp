// The simulate command of the lowpair command line: measurements of the tool frame at random joint vectors,
// the measurement CSV of harness/measurements.hpp (its seed, its truth from a robot file or MuJoCo, its noise,
// --out and its rejections). The calibration commands are in calibration_cli_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "calibration_cli_helpers.hpp"
#include "cli_runner.hpp"
#include "csv_text.hpp"

namespace {

using namespace lowpair_test;
using namespace calibration_cli;
namespace fs = std::filesystem;

using csv_test::Csv;
using csv_test::parseCsv;
using csv_test::Quaternion;
using csv_test::Row;
using csv_test::split;
using Mat3 = std::array<std::array<double, 3>, 3>;

// The rotation of a unit quaternion.
Mat3 rotation(const Quaternion& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

std::string joined(const std::vector<double>& q) {
  std::ostringstream out;
  out.precision(17);
  for (size_t i = 0; i < q.size(); ++i) out << (i ? "," : "") << q[i];
  return out.str();
}

}  // namespace

TEST(Simulate, SameSeedSameFileOtherSeedOtherFile) {
  const CliRun a = runCli("simulate " + kNominal + " --poses 5 --seed 3");
  const CliRun b = runCli("simulate " + kNominal + " --poses 5 --seed 3");
  const CliRun c = runCli("simulate " + kNominal + " --poses 5 --seed 4");
  ASSERT_EQ(a.status, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  const Csv csv = parseCsv(a.out), other = parseCsv(c.out);
  EXPECT_EQ(csv.header, split("q1,q2,q3,q4,q5,q6,x,y,z,qw,qx,qy,qz"));
  ASSERT_EQ(csv.rows.size(), 5u);
  ASSERT_EQ(other.rows.size(), 5u);
  for (size_t k = 0; k < 5; ++k) EXPECT_NE(csv.rows[k].q, other.rows[k].q);
  // the comments say what produced the file
  ASSERT_FALSE(csv.comments.empty());
  EXPECT_EQ(csv.comments[0].rfind("# lowpair simulate " + kNominal, 0), 0u) << csv.comments[0];
  EXPECT_NE(a.out.find("seed 3"), std::string::npos);
  EXPECT_NE(a.out.find("(mm)"), std::string::npos);
  // sample k does not depend on --poses
  const Csv longer = simulate(kNominal + " --poses 7 --seed 3");
  for (size_t k = 0; k < 5; ++k) EXPECT_EQ(longer.rows[k].q, csv.rows[k].q);
}

TEST(Simulate, RobotFileMeasurementsAreItsForwardKinematics) {
  const Csv csv = simulate(kNominal + " --poses 5 --seed 3");
  ASSERT_EQ(csv.rows.size(), 5u);
  for (const Row& row : csv.rows) {
    for (double q : row.q) {
      EXPECT_GE(q, -M_PI);
      EXPECT_LE(q, M_PI);
    }
    const CliRun fk = runCli("fk " + kNominal + " --json --q " + joined(row.q));
    ASSERT_EQ(fk.status, 0) << fk.err;
    const auto T = nlohmann::json::parse(fk.out)["T_base_tool"];
    const Mat3 R = rotation(row.quaternion);
    for (int r = 0; r < 3; ++r) {
      const double p = T[r][3].get<double>();
      EXPECT_NEAR(row.p[static_cast<size_t>(r)], p, 1e-12 * std::max(1.0, std::abs(p)));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(R[static_cast<size_t>(r)][static_cast<size_t>(c)], T[r][c].get<double>(), 1e-12);
    }
  }
}

// MuJoCo's tip pose of the MJCF at the robot file's joint variable is the library's FK of that robot file:
// the same q (same ranges, same seed), the same measurements.
TEST(Simulate, MujocoTruthAgreesWithTheRobotFile) {
  const Csv mujoco = simulate(kActualXml + " --tip tool --joint-variables " + kActualYaml + " --poses 20 --seed 1");
  const Csv library = simulate(kActualYaml + " --poses 20 --seed 1");
  ASSERT_EQ(mujoco.rows.size(), 20u);
  ASSERT_EQ(library.rows.size(), 20u);
  const CliRun size = runCli("poe2dh " + kActualYaml + " --json");
  ASSERT_EQ(size.status, 0) << size.err;
  const double L = nlohmann::json::parse(size.out)["size"].get<double>();  // about 255 mm
  for (size_t k = 0; k < 20; ++k) {
    EXPECT_EQ(mujoco.rows[k].q, library.rows[k].q) << "the two sample different joint ranges";
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(mujoco.rows[k].p[i], library.rows[k].p[i], 1e-9 * L);
    EXPECT_LT(angleBetween(mujoco.rows[k].quaternion, library.rows[k].quaternion), 1e-9);
  }
  // without --joint-variables q is MuJoCo's own variable (scale 1): other measurements at the same q
  const Csv own = simulate(kActualXml + " --tip tool --poses 20 --seed 1 --measure position");
  EXPECT_EQ(own.header.back(), "z");
  double moved = 0;  // by the robot file's joint scales (|w| of its twists, up to 1.00004)
  for (size_t k = 0; k < 20; ++k) {
    EXPECT_EQ(own.rows[k].q, library.rows[k].q);
    for (size_t i = 0; i < 3; ++i) moved = std::max(moved, std::abs(own.rows[k].p[i] - library.rows[k].p[i]));
  }
  EXPECT_GT(moved, 1e-4);
}

// The noise is what it says: sd 0.01 per position coordinate, rotation exp(n) with n ~ N(0, s^2 I3) (so
// the angle's RMS is s sqrt(3)); q and the noise-free pose do not change.
TEST(Simulate, NoiseHasTheStatedStandardDeviation) {
  const std::string base = kNominal + " --poses 2000 --seed 5";
  const Csv clean = simulate(base);
  const Csv noisy = simulate(base + " --noise-position 0.01 --noise-rotation 0.01");
  const Csv position_only = simulate(base + " --noise-position 0.01");
  ASSERT_EQ(clean.rows.size(), 2000u);
  ASSERT_EQ(noisy.rows.size(), 2000u);
  ASSERT_EQ(position_only.rows.size(), 2000u);
  double sum = 0, sum2 = 0, angle2 = 0;
  for (size_t k = 0; k < 2000; ++k) {
    ASSERT_EQ(noisy.rows[k].q, clean.rows[k].q);
    for (size_t i = 0; i < 3; ++i) {
      const double d = noisy.rows[k].p[i] - clean.rows[k].p[i];
      sum += d;
      sum2 += d * d;
      // a pose's position noise does not depend on the rotation noise
      EXPECT_EQ(position_only.rows[k].p[i], noisy.rows[k].p[i]);
    }
    EXPECT_LT(angleBetween(position_only.rows[k].quaternion, clean.rows[k].quaternion), 1e-14);
    const double a = angleBetween(clean.rows[k].quaternion, noisy.rows[k].quaternion);
    angle2 += a * a;
  }
  const double n = 6000, mean = sum / n;
  const double sd = std::sqrt((sum2 - n * mean * mean) / (n - 1));
  EXPECT_NEAR(sd, 0.01, 0.05 * 0.01);
  EXPECT_LT(std::abs(mean), 5 * 0.01 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(angle2 / 2000), 0.01 * std::sqrt(3.0), 0.05 * 0.01 * std::sqrt(3.0));
}

TEST(Simulate, OutWritesTheFileAndOnlyTheFile) {
  const std::string path = scratch() + "/simulated.csv";
  const CliRun r = runCli("simulate " + kNominal + " --poses 3 --measure position --out " + path);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "3 position measurements written to " + path + "\n");
  EXPECT_EQ(std::ifstream(path).good(), true);
  std::ifstream in(path);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  EXPECT_EQ(text, runCli("simulate " + kNominal + " --poses 3 --measure position").out);
}

TEST(SimulateRejects, BadArguments) {
  const std::string robot = kNominal + " ";
  expectRejected("simulate " + robot + "--poses 0", "not in range", "--poses");
  expectRejected("simulate " + robot + "--poses 1000001", "not in range", "--poses");
  expectRejected("simulate " + robot, "--poses is required");
  expectRejected("simulate " + robot + "--poses 2 --noise-position -1", "expected a finite number >= 0, got -1",
                 "--noise-position");
  expectRejected("simulate " + robot + "--poses 2 --noise-position nan", "got nan", "--noise-position");
  expectRejected("simulate " + robot + "--poses 2 --noise-rotation inf", "got inf", "--noise-rotation");
  expectRejected("simulate " + robot + "--poses 2 --measure foo", "foo not in {pose,position,targets}", "--measure");
  expectRejected("simulate " + robot + "--poses 2 --seed -1", "not in range", "--seed");
  expectRejected("simulate " + robot + "--poses 2 --seed 9007199254740993", "not in range", "--seed");
  expectRejected("simulate " + robot + "--poses 2 --tip tool", "--tip/--base go with a model file", kNominal);
  expectRejected("simulate " + robot + "--poses 2 --joint-variables " + kActualYaml,
                 "--joint-variables goes with a model file", kNominal);
  expectRejected("simulate " + kActualXml + " --poses 2", "--tip NAME is required with a model file", kActualXml);
  expectRejected("simulate " + kActualXml + " --tip nowhere --poses 2", "nowhere", kActualXml);
  expectRejected("simulate " + modelPath("missing.yaml") + " --poses 2", "cannot open file", modelPath("missing.yaml"));
}

TEST(SimulateRejects, JointVariablesOfAnotherChain) {
  const std::string two_joints = writeScratchFile("two_joints.yaml", R"(name: two-joints
poe:
  joints:
    - {type: revolute, twist: [0, 0, 1, 0, 0, 0]}
    - {twist: [0, -1, 0, 0, 0, -1]}
  tool: [0, 0, 0, 1, 0, 0]
)");
  expectRejected("simulate " + kActualXml + " --tip tool --poses 2 --joint-variables " + two_joints,
                 "has 2 joints but the chain to 'tool' in " + kActualXml + " has 6", two_joints);
  expectRejected("simulate " + kActualXml + " --tip tool --poses 2 --joint-variables " + kNominal,
                 "joint 3 is revolute but MuJoCo joint 'j3' is helical", kNominal);
}

TEST(SimulateRejects, OutIntoAMissingFolderCreatesNothing) {
  const std::string folder = scratch() + "/no_such_folder";
  expectRejected("simulate " + kNominal + " --poses 2 --out " + folder + "/m.csv",
                 "cannot write: No such file or directory", folder + "/m.csv");
  EXPECT_FALSE(fs::exists(folder));
  fs::create_directories(scratch() + "/a_folder/inside");
  expectRejected("simulate " + kNominal + " --poses 2 --out " + scratch() + "/a_folder", "cannot write: is a directory");
  EXPECT_TRUE(fs::is_directory(scratch() + "/a_folder/inside"));
}
