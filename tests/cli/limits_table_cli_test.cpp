// One test per row of docs/cli.md's Limits table (issue 30): just beyond each limit the command is refused with
// exit 2 and one line naming the argument or the file, before the work starts (within kAtOnce, where the work
// refused takes minutes to hours or gigabytes); where it is cheap, the limit itself is accepted. Rows tested
// elsewhere:
//
// | row of the table                                    | test                                                     |
// |-----------------------------------------------------|----------------------------------------------------------|
// | model files: 2 MiB, bytes beyond refused unread     | HostileInput.ModelFilesAreBoundedAndRegular              |
// | targets of a robot file: 1000                       | RobotFileTargets (robot_file_targets_test)               |
// | measurement CSV: 10^6 rows, 64 KiB lines            | Measurements (measurements_test), Loop (loop_cli_test)   |
// | simulate --poses 10^6, rows x targets 10^6          | SimulateCli (simulate_cli_test), loop_cli_test           |
// | simulate --blunders COUNT <= rows                   | tracker_cli_test                                         |
// | calibrate: 10,000 fitted measurements               | CalibrationCli (calibration_cli_test)                    |
// | identifiability / calibrate / --select cv / plan work | WorkLimits (work_limits_cli_test)                      |
// | plan --poses 1000, --candidates 100,000             | PlanCli (plan_cli_test)                                  |
// | the IK work's and the simulated rows' arithmetic    | WorkLimitsArithmetic (tests/harness/work_limits_test)    |
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "cli_runner.hpp"
#include "targets_robot.hpp"

namespace {

using namespace lowpair_test;
namespace fs = std::filesystem;

bool sanitized() { return std::getenv("LOWPAIR_SANITIZE") != nullptr; }

// A refusal "at once": generous (the work refused takes minutes or more), wider under the sanitizers
double atOnce() { return sanitized() ? 10.0 : 2.0; }

double secondsOf(const std::function<void()>& run) {
  const auto start = std::chrono::steady_clock::now();
  run();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Refused before the work: exit 2, one line `error: SUBJECT...` holding `what`, nothing on stdout, at once.
void expectRefusedAtOnce(const std::string& args, const std::string& what, const std::string& subject) {
  EXPECT_LT(secondsOf([&] { expectRejected(args, what, subject); }), atOnce()) << args;
}

// A planar chain of n revolute joints (POE, or with `dh` a D-H table), every axis 1 mm from the last.
std::string chainFile(int n, bool dh = false) {
  std::string text = "name: chain\nlength_unit: m\nangle_unit: rad\n";
  text += dh ? "dh:\n  joints:\n" : "poe:\n  joints:\n";
  for (int k = 0; k < n; ++k) {
    text += dh ? "    - {type: revolute, theta: 0, d: 0, alpha: 0, a: 0.001}\n"
               : "    - {type: revolute, twist: [0, 0, 1, 0, " + std::to_string(-0.001 * k) + ", 0]}\n";
  }
  text += dh ? "  tool: {theta: 0, d: 0}\n" : "  tool: [0, 0, 0, " + std::to_string(0.001 * n) + ", 0, 0]\n";
  return writeScratchFile("chain" + std::to_string(n) + (dh ? "_dh" : "") + ".yaml", text);
}

std::string rowsFile(const std::string& name, const std::string& header, const std::string& row, long long rows) {
  std::string text = header + "\n";
  text.reserve(text.size() + static_cast<size_t>(rows) * (row.size() + 1));
  for (long long k = 0; k < rows; ++k) text += row + "\n";
  return writeScratchFile(name, text);
}

const std::string kPuma = modelPath("puma560_corke.yaml");

}  // namespace

// Model files: 2 MiB (kMaxModelFileBytes) is read; an MJCF counts its includes together (each under the limit,
// many of them were not bounded)
TEST(LimitsTable, ModelFilesOfTwoMiBAreReadAndAnMjcfCountsItsIncludes) {
  std::ifstream in(kPuma);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const size_t limit = size_t{2} << 20;
  while (text.size() + 81 <= limit) text += "#" + std::string(79, 'x') + "\n";
  text += "#" + std::string(limit - text.size() - 2, 'x') + "\n";
  ASSERT_EQ(text.size(), limit);
  const std::string at_limit = writeScratchFile("two_mib.yaml", text);
  const CliRun r = runCli("poe2dh " + at_limit);
  EXPECT_EQ(r.status, 0) << r.err;

  const std::string half = "<mujoco><!--" + std::string(limit / 2, 'x') + "--></mujoco>\n";  // 1 MiB and a bit
  writeScratchFile("part_a.xml", half);
  const std::string part_b = writeScratchFile("part_b.xml", half);
  const std::string main_file = writeScratchFile(
      "two_parts.xml", "<mujoco><include file=\"part_a.xml\"/><include file=\"part_b.xml\"/><worldbody><body name=\"a\">"
                       "<joint type=\"hinge\"/><site name=\"t\" pos=\"1 0 0\"/></body></worldbody></mujoco>\n");
  expectRefusedAtOnce("poe2dh " + main_file + " --tip t", "the model and the files it includes hold", part_b);
}

// Joints: 10,000 (kMaxJoints), a POE or a D-H list; beyond, the robot file is named
TEST(LimitsTable, RobotsOfMoreThanTenThousandJointsAreRefused) {
  const std::string poe = chainFile(10001), dh = chainFile(10001, true);
  expectRefusedAtOnce("poe2dh " + poe, "10001 joints, more than the 10000 a robot may have", poe);
  expectRefusedAtOnce("dh2poe " + dh, "10001 joints, more than the 10000 a robot may have", dh);
  if (sanitized()) return;  // (0.8 s here)
  const CliRun r = runCli("poe2dh " + chainFile(10000));
  EXPECT_EQ(r.status, 0) << r.err;
}

// fk --q-file: rows x targets at most 10^6 (a measurement file); 1000 targets x 1000 rows are written
TEST(LimitsTable, FkQFileRowsTimesTargetsAtMostAMillion) {
  const std::string robot = nominalWithTargets(1000);
  const std::string over = rowsFile("q1001.csv", "q1,q2,q3,q4,q5,q6", "0.1,0.2,0.3,0.4,0.5,0.6", 1001);
  expectRefusedAtOnce("fk " + robot + " --q-file " + over + " --measure targets",
                      "1001 rows x 1000 targets = 1001000 measurements, more than the 1000000", over);
  if (sanitized()) return;  // (1.2 s here)
  const std::string at = rowsFile("q1000.csv", "q1,q2,q3,q4,q5,q6", "0.1,0.2,0.3,0.4,0.5,0.6", 1000);
  const CliRun r = runCli("fk " + robot + " --q-file " + at + " --measure targets --out " + scratch() + "/t1000.csv");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "1000000 target measurements written to " + scratch() + "/t1000.csv\n");
}

// A joint-value or target CSV (fk --q-file, ik --poses, compensate --q-file): at most 10^6 rows
TEST(LimitsTable, JointTablesOfMoreThanAMillionRowsAreRefused) {
  if (sanitized()) GTEST_SKIP() << "reads 10^6 rows first (0.5 s here)";
  const std::string over = rowsFile("q_million.csv", "q1,q2,q3,q4,q5,q6", "0,0,0,0,0,0", 1000001);
  expectRejected("compensate " + kPuma + " --nominal " + kPuma + " --q-file " + over, "more than 1000000 rows", over);
  fs::remove(over);
}

// ik --seeds: 1 to 1000, and rows x seeds x 100 iterations x joints at most kMaxIkWork (5.6e9): 9333 rows of
// the 6-joint PUMA at 1000 seeds (about 10 min when no row is solved); one row at 1000 seeds is taken
TEST(LimitsTable, IkSeedsAreBoundedByTheWorkLimit) {
  const std::string far = writeScratchFile("ik_far.csv", "x,y,z\n5,5,5\n");  // beyond the reach: no iteration
  expectRejected("ik " + kPuma + " --poses " + far + " --seeds 1001", "not in range", "--seeds");
  const std::string over = rowsFile("ik_9334.csv", "x,y,z", "0.3,0.1,0.2", 9334);
  expectRefusedAtOnce("ik " + kPuma + " --poses " + over + " --seeds 1000",
                      "1000 seeds x 9334 rows x 100 iterations x 6 joints = 5600400000 exceed the IK work limit "
                      "(5.6e+09 joint-iterations: the default 8 seeds at 10^6 rows of a 7-joint robot): at most 9333 "
                      "rows at 1000 seeds, or at most 999 seeds for 9334 rows",
                      "--seeds");
  const CliRun r = runCli("ik " + kPuma + " --poses " + far + " --seeds 1000 --json");
  EXPECT_EQ(r.status, 1) << r.err;  // unreachable: a row that fails is data
  EXPECT_NE(r.out.find("\"unreachable\": 1"), std::string::npos) << r.out.substr(0, 400);
}

// simulate: at most 1000 joints and 10^8 joint values (what a measurement file holds and its reader takes)
TEST(LimitsTable, SimulateWritesOnlyWhatAMeasurementFileHolds) {
  const std::string wide = chainFile(1001), at = chainFile(1000);
  expectRefusedAtOnce("simulate " + wide + " --poses 1", "1001 joints, more than the 1000 a measurement file holds", wide);
  expectRefusedAtOnce("simulate " + at + " --poses 100001",
                      "100001 measurements x 1000 joints = 100001000 joint values, more than the 100000000", "--poses");
  const CliRun r = runCli("simulate " + at + " --poses 2");
  EXPECT_EQ(r.status, 0) << r.err;
}

// identifiability --poses: 10,000 (0.6 s and 154 MB here)
TEST(LimitsTable, IdentifiabilityPosesAtMostTenThousand) {
  const std::string robot = modelPath("puma560_okamura_nominal.yaml");
  expectRejected("identifiability " + robot + " --poses 10001", "not in range", "--poses");
  if (sanitized()) return;
  const CliRun r = runCli("identifiability " + robot + " --poses 10000 --json");
  EXPECT_EQ(r.status, 0) << r.err;
}

// calibrate --select cv: --folds 2 to 20, --repeats 1 to 100 (their product with the fits' size: WorkLimits)
TEST(LimitsTable, CrossValidationFoldsAndRepeatsAreBounded) {
  const std::string args = "calibrate " + modelPath("puma560_okamura_nominal.yaml") + " --measurements " +
                           rowsFile("cv.csv", "q1,q2,q3,q4,q5,q6,x,y,z", "0,0,0,0,0,0,1,2,3", 3) + " --select cv";
  expectRejected(args + " --folds 21", "not in range", "--folds");
  expectRejected(args + " --folds 1", "not in range", "--folds");
  expectRejected(args + " --repeats 101", "not in range", "--repeats");
}

// validate --threads: at most 256 (738 MB at 256 threads here); --samples: at most 1e8
TEST(LimitsTable, ValidateThreadsAndSamplesAreBounded) {
  const std::string scenario = std::string(LOWPAIR_SCENARIOS) + "/elbow_mls.yaml";
  expectRejected("validate " + scenario + " --threads 257", "not in range", "--threads");
  expectRejected("validate " + scenario + " --samples 100000001", "not in range", "--samples");
  const CliRun r = runCli("validate " + scenario + " --samples 10 --threads 256");
  EXPECT_EQ(r.status, 0) << r.err;
}
