// The calibration commands of the lowpair command line: identifiability and calibrate, the paper's loop
// through the CLI (measurements from simulate, the model from MuJoCo's actual PUMA), their rejections, and
// the measurement CSV's columns by name. simulate is in simulate_cli_test.cpp, calibrate on tracker data
// in calibration_tracker_cli_test.cpp.
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

// ---- identifiability and calibrate: the paper's loop through the CLI (issue 9's "done when") -----------

namespace {

using namespace lowpair_test;
using namespace calibration_cli;
namespace fs = std::filesystem;

using csv_test::Csv;
using csv_test::rearranged;
using csv_test::replaced;

nlohmann::json jsonOf(const std::string& args) {
  const CliRun r = runCli(args + " --json");
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return nlohmann::json::parse(r.out);
}

// The D-H table rows of `poe2dh` (everything between the column header and the blank line).
std::vector<std::string> dhRows(const std::string& robot) {
  const CliRun r = runCli("poe2dh " + shellQuote(robot));
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<std::string> rows;
  std::istringstream in(r.out);
  bool table = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("row ", 0) == 0) {
      table = true;
    } else if (table && line.empty()) {
      break;
    } else if (table) {
      rows.push_back(line);
    }
  }
  return rows;
}

}  // namespace

TEST(Identifiability, PumaRankIsThePaperCountAndDhLosesFive) {
  const auto pose = jsonOf("identifiability " + shellQuote(kNominal));
  EXPECT_EQ(pose["expected"], 36);  // 4 x 6 revolute + 6 scales + 6 tool
  EXPECT_EQ(pose["rank"], 36);
  EXPECT_EQ(pose["full_model"]["rank"], 36);
  EXPECT_EQ(pose["parameters"].size(), 36u);
  EXPECT_EQ(pose["joints"]["revolute"], 6);
  EXPECT_TRUE(pose["condition"].is_number());
  for (const char* k : {"O1", "O2", "O3", "O4", "O5"}) EXPECT_GT(pose["observability"][k].get<double>(), 0.0) << k;
  // base z on joint 1, joints 2 and 3 parallel, joint 6 on the tool z: five D-H directions undetermined
  EXPECT_EQ(pose["dh"]["rank"], 31);
  EXPECT_TRUE(pose["dh"]["condition"].is_null());
  EXPECT_EQ(pose["dh"]["undetermined"].size(), 5u);
  // position only: 33 at most, and this tool point is the wrist centre, so the wrist is not seen (24)
  const auto position = jsonOf("identifiability " + shellQuote(kNominal) + " --measure position");
  EXPECT_EQ(position["expected"], 33);
  EXPECT_EQ(position["rank"], 24);
  for (const auto& direction : position["undetermined"]) {
    for (const auto& term : direction) {
      const std::string name = term["parameter"];
      EXPECT_TRUE(name.rfind("j4.", 0) == 0 || name.rfind("j5.", 0) == 0 || name.rfind("j6.", 0) == 0 ||
                  name.rfind("tool.r", 0) == 0)
          << name;
    }
  }
}

// Wu et al.'s case: the nominal PUMA calibrated from noise-free measurements of the actual robot (MuJoCo)
// must be the actual robot: FK to 1e-9 L on held-out poses, and its D-H table is Table II (actual) as poe2dh
// prints it from Table I. The measurements are in the actual's base frame, so the robot in the measurement
// frame (--frame measurement) is the actual; the default file is in the nominal's base frame (base_frame_cli_test).
TEST(Calibrate, NoiseFreeLoopRecoversTheActualPuma) {
  const std::string m = simulateTo("noise_free.csv", kMujocoActual + " --poses 50 --seed 1");
  const std::string cal = scratch() + "/cal.yaml";
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) +
                          " --free-pitch --frame measurement --out " + shellQuote(cal));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("rank 42 of 42"), std::string::npos) << r.out;
  const double L = jsonOf("poe2dh " + shellQuote(kActualYaml))["size"];
  // held-out: the same 200 random joint vectors (same seed, same [-pi, pi] ranges) through both robot files
  const Csv calibrated = simulate(shellQuote(cal) + " --poses 200 --seed 7");
  const Csv actual = simulate(shellQuote(kActualYaml) + " --poses 200 --seed 7");
  ASSERT_EQ(calibrated.rows.size(), 200u);
  double max_position = 0, max_rotation = 0;
  for (size_t k = 0; k < 200; ++k) {
    ASSERT_EQ(calibrated.rows[k].q, actual.rows[k].q);
    double d2 = 0;
    for (int i = 0; i < 3; ++i) d2 += std::pow(calibrated.rows[k].p[i] - actual.rows[k].p[i], 2);
    max_position = std::max(max_position, std::sqrt(d2));
    max_rotation = std::max(max_rotation, angleBetween(calibrated.rows[k].quaternion, actual.rows[k].quaternion));
  }
  EXPECT_LE(max_position, 1e-9 * L);
  EXPECT_LE(max_rotation, 1e-9);
  const auto calibrated_rows = dhRows(cal), actual_rows = dhRows(kActualYaml);
  ASSERT_EQ(calibrated_rows.size(), 8u);  // base, 6 joints, tool
  EXPECT_EQ(calibrated_rows, actual_rows);
}

// Noisy loop: 0.01 mm and 1e-5 rad, 50 poses; 200 noise-free validation poses.
TEST(Calibrate, NoisyLoopReachesTheNoiseLevel) {
  const std::string m =
      simulateTo("noisy.csv", kMujocoActual + " --poses 50 --seed 1 --noise-position 0.01 --noise-rotation 1e-5");
  const std::string v = simulateTo("validation.csv", kMujocoActual + " --poses 200 --seed 2");
  const auto j = jsonOf("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + " --validation " +
                        shellQuote(v) + " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch");
  EXPECT_TRUE(j["converged"].get<bool>());
  EXPECT_EQ(j["rank"], 42);
  EXPECT_EQ(j["expected"], 42);
  const double before = j["validation"]["before"]["rms_position"], after = j["validation"]["after"]["rms_position"];
  EXPECT_LE(after, 0.01);
  EXPECT_GE(before / after, 100.0);
  EXPECT_LT(j["after"]["rms_position"].get<double>(), j["before"]["rms_position"].get<double>());
  // the stated noise is right, so the variance factor is near 1 (chi-square with 300 - 42 dof: 1 +- 0.25)
  EXPECT_NEAR(j["variance_factor"].get<double>(), 1.0, 0.25);
  for (const auto& joint : j["dh"]["joints"]) EXPECT_TRUE(joint["sd"]["d"].is_number()) << joint;
}

// Three poses cannot determine 42 parameters: a result (exit 0) whose rank report names what is missing,
// finite numbers everywhere (JSON has no NaN: a non-finite number would print as null).
TEST(Calibrate, TooFewPosesReportsTheUndeterminedParameters) {
  const std::string m = simulateTo("three.csv", kMujocoActual + " --poses 3 --seed 4");
  const CliRun text = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m));
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("do not determine"), std::string::npos) << text.out;
  const auto j = jsonOf("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m));
  EXPECT_LE(j["rank"].get<int>(), 18);  // 3 poses x 6 rows
  EXPECT_EQ(j["expected"], 36);
  EXPECT_EQ(j["undetermined"].size(), 36u - j["rank"].get<size_t>());
  for (const char* k : {"rms_position", "max_position", "rms_rotation", "max_rotation"}) {
    EXPECT_TRUE(j["after"][k].is_number()) << k;
  }
  EXPECT_FALSE(j["warnings"].empty());
}

TEST(CalibrateRejects, BadMeasurementFilesWithFileAndLineAndWriteNothing) {
  const std::string good = simulateTo("good.csv", shellQuote(kActualYaml) + " --poses 5 --seed 1");
  // measurements of the nominal itself: residuals at rounding level stay finite at 1e-160 (1e-13 / 1e-160),
  // the Jacobian's columns (L / 1e-160 ~ 1e163) do not once squared for their norms; an unscaled column took
  // the whole rank (exit 0 with a wrong rank warning)
  const std::string exact = simulateTo("edge_exact.csv", shellQuote(kNominal) + " --poses 20 --seed 4");
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(exact) + " --noise-position 1e-160",
                 "calibrate: the weighted residuals or Jacobian overflow (sigma_position 1e-160", kNominal);
  std::ifstream in(good);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string cal = scratch() + "/never.yaml";
  // a data line with one number missing
  const auto last = text.rfind(',', text.size() - 2);
  const std::string short_line = scratch() + "/short.csv";
  std::ofstream(short_line) << text.substr(0, last) << "\n";
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(short_line) + " --out " +
                     shellQuote(cal),
                 ":" + std::to_string(lines) + ": ", short_line);
  // measurements of a 6-joint robot for a 1-joint nominal
  const std::string one_joint = scratch() + "/one_joint.yaml";
  std::ofstream(one_joint) << "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0]}\n  tool: [0, 0, 0, 1, 0, 0]\n";
  expectRejected("calibrate " + shellQuote(one_joint) + " --measurements " + shellQuote(good) + " --out " +
                     shellQuote(cal),
                 "6 joint columns", good);
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(good) +
                     " --noise-position -1 --out " + shellQuote(cal),
                 "positive");
  EXPECT_FALSE(fs::exists(cal));
}

// The calibrated model reaches a simulator: export it as MJCF (with its joint-variable file, since the
// calibrated scales are not 1) and validate the export against the calibrated robot file through MuJoCo.
TEST(Calibrate, CalibratedModelExportsAndValidates) {
  const std::string m = simulateTo("export_fit.csv", kMujocoActual + " --poses 50 --seed 3");
  const std::string cal = scratch() + "/export_cal.yaml";
  ASSERT_EQ(runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + " --free-pitch --out " +
                   shellQuote(cal))
                .status,
            0);
  // without --out the joint-variable file has nowhere to go: a usage error, one line
  expectRejected("export " + shellQuote(cal) + " --format mjcf", "--out");
  expectRejected("export " + shellQuote(cal) + " --format step", "format");
  const std::string xml = scratch() + "/export_cal.xml";
  const CliRun e = runCli("export " + shellQuote(cal) + " --format mjcf --out " + shellQuote(xml));
  ASSERT_EQ(e.status, 0) << e.err;
  EXPECT_TRUE(fs::exists(scratch() + "/export_cal.joint_variables.yaml"));
  const CliRun v = runCli("validate " + shellQuote(xml) + " --tip tool --robot " + shellQuote(cal) + " --samples 2000");
  EXPECT_EQ(v.status, 0) << v.out << v.err;
  EXPECT_NE(v.out.find("robot_file_vs_mujoco:export_cal.yaml"), std::string::npos) << v.out;
}

// Memory stays bounded: calibrate holds 6 rows per fitted measurement, so it fits at most 10,000.
TEST(CalibrateRejects, MoreMeasurementsThanItFits) {
  const std::string big = scratch() + "/big.csv";
  {
    std::ofstream out(big);
    out << "q1,x,y,z\n";
    for (int i = 0; i < 10001; ++i) out << i * 1e-3 << ",1,0,0\n";
  }
  const std::string one_joint = scratch() + "/one_joint_big.yaml";
  std::ofstream(one_joint) << "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0]}\n  tool: [0, 0, 0, 1, 0, 0]\n";
  expectRejected("calibrate " + shellQuote(one_joint) + " --measurements " + shellQuote(big), "at most 10000", big);
}

// Review findings: numbers at the edge of double end as one line, never a hang, inf or NaN. A stated noise
// of 1e-160 squared the weighted residuals past overflow and the damping loop never ended; a joint value of
// 1e155 in a CSV did the same; simulate with noise 1e308 wrote inf into the file.
TEST(CalibrateRejects, NumbersBeyondDoubleEndCleanly) {
  const std::string good = simulateTo("edge.csv", shellQuote(kActualYaml) + " --poses 20 --seed 4");
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(good) + " --noise-position 1e-160",
                 "calibrate: the weighted residuals or Jacobian overflow (sigma_position 1e-160", kNominal);
  // measurements of the nominal itself: residuals at rounding level stay finite at 1e-160 (1e-13 / 1e-160),
  // the Jacobian's columns (L / 1e-160 ~ 1e163) do not once squared for their norms; an unscaled column took
  // the whole rank (exit 0 with a wrong rank warning)
  const std::string exact = simulateTo("edge_exact.csv", shellQuote(kNominal) + " --poses 20 --seed 4");
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(exact) + " --noise-position 1e-160",
                 "calibrate: the weighted residuals or Jacobian overflow (sigma_position 1e-160", kNominal);
  std::ifstream in(good);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const size_t data = text.find("\n", text.find("q1,")) + 1;  // the first data line
  const std::string big = scratch() + "/edge_big.csv";
  std::ofstream(big) << text.substr(0, data) << "1e155" << text.substr(text.find(',', data));
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(big),
                 "'1e155' is above 1e100 in magnitude", big + ":");
  // a slide of scale 1e-3 over [-1e102, 1e102] reaches 1e99 (accepted), but its joint values are beyond
  // what the reader takes: the robot is named, not the noise (review)
  const std::string wide = writeScratchFile(
      "wide_slide.yaml",
      "name: t\nlength_unit: m\npoe:\n  joints:\n    - {twist: [0, 0, 0, 0, 0, 1e-3], range: [-1e102, 1e102]}\n"
      "  tool: [0, 0, 0, 1, 0, 0]\n");
  expectRejected("simulate " + shellQuote(wide) + " --poses 3", "a joint range reaches 1e+102, above the 1e100", wide);
  expectRejected("simulate " + shellQuote(kNominal) + " --poses 3 --noise-position 1e308", "is above 1e+100",
                 "--noise-position");
  expectRejected("simulate " + shellQuote(kNominal) + " --poses 3 --noise-rotation 4", "is above 3.14159",
                 "--noise-rotation");
  // a rotation noise for position measurements weighs nothing: rejected, not silently ignored
  const std::string position = simulateTo("edge_position.csv", shellQuote(kNominal) + " --poses 20 --measure position");
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(position) +
                     " --noise-rotation 1e-4",
                 "holds position measurements", "--noise-rotation");
  // one stated noise: the other is derived and says so (noisy measurements: noise-free ones under a stated
  // 0.01 are rejected, variance factor below 1/100)
  const std::string noisy =
      simulateTo("edge_noisy.csv", shellQuote(kActualYaml) + " --poses 20 --seed 4 --noise-position 0.01 --noise-rotation 1e-5");
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(noisy) +
                          " --noise-position 0.01 --free-pitch --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["noise"]["derived"], "rotation") << r.out;
  const CliRun dh = runCli("poe2dh " + shellQuote(kNominal) + " --json");  // its "size" is L
  ASSERT_EQ(dh.status, 0) << dh.err;
  EXPECT_DOUBLE_EQ(j["noise"]["rotation"].get<double>(), 0.01 / nlohmann::json::parse(dh.out)["size"].get<double>())
      << r.out;
}

// Review finding: a failed export removed an existing joint-variable file (it was written first and removed
// again when the model could not be written). Both are staged now; a failure leaves both names as they were.
TEST(ExportRejects, FailedExportKeepsExistingFiles) {
  const std::string out = scratch() + "/kept.urdf";  // a directory: the model cannot be written
  fs::create_directories(out);
  const std::string variables = scratch() + "/kept.joint_variables.yaml";
  std::ofstream(variables) << "keep me\n";
  expectRejected("export " + shellQuote(kActualYaml) + " --format urdf --out " + shellQuote(out), "is a directory", out);
  std::ifstream in(variables);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), {}), "keep me\n");
  EXPECT_TRUE(fs::is_directory(out));
  for (const auto& e : fs::directory_iterator(scratch()))  // no temporary left behind
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// The hint after a URDF with helical joints suggests an MJCF export beside it; where a file of that name
// exists (models/X.urdf beside the hand-written models/X.xml) it names another file instead of overwriting it.
TEST(Export, HelicalUrdfHintNeverNamesAnExistingFile) {
  const std::string out = scratch() + "/hint/actual.urdf";
  fs::create_directories(scratch() + "/hint");
  const CliRun first = runCli("export " + shellQuote(kActualYaml) + " --format urdf --out " + shellQuote(out));
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.out.find("--out " + scratch() + "/hint/actual.xml,"), std::string::npos) << first.out;
  std::ofstream(scratch() + "/hint/actual.xml") << "<mujoco/>\n";
  const CliRun second = runCli("export " + shellQuote(kActualYaml) + " --format urdf --out " + shellQuote(out));
  ASSERT_EQ(second.status, 0) << second.err;
  EXPECT_NE(second.out.find("--out " + scratch() + "/hint/actual.export.xml,"), std::string::npos) << second.out;
}

// Review finding: position measurements of the PUMA (tool point on the wrist axes) said "rank 30 < 39 ...
// 12 directions" (the 3 tool rotations are in the error model, not in the count) and nothing on why the fit
// stays at about a millimetre on held-out points (docs/calibration.md: 1.3 mm): the warning counts against the
// formula and says the fit is confined to the nominal's determined directions.
TEST(Calibrate, PositionOnlyRankWarningCountsAgainstTheFormula) {
  const std::string m = simulateTo("position_only.csv", shellQuote(kActualYaml) + " --poses 50 --seed 1 --measure position");
  const auto j = jsonOf("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + " --free-pitch");
  const int rank = j["rank"], expected = j["expected"];
  ASSERT_LT(rank, expected);
  const std::string warning = j["warnings"][0];
  EXPECT_NE(warning.find("do not determine " + std::to_string(expected - rank) + " parameter direction(s) of the count"),
            std::string::npos)
      << warning;
  EXPECT_NE(warning.find("the tool rotation"), std::string::npos) << warning;
  EXPECT_NE(warning.find("confined to the directions the nominal determines"), std::string::npos) << warning;
}

// Review finding: the SVD's full V grows as the columns squared, which the Jacobian limit did not count
// (800 joints, one pose: V alone 4,806^2 numbers). Bounded now, naming the limit, before any allocation.
TEST(CalibrateRejects, LongChainsWithinTheMemoryLimit) {
  std::string text = "name: long\nlength_unit: m\npoe:\n  joints:\n";
  for (int i = 0; i < 800; ++i) text += "    - {twist: [0, 0, 1, 0, " + std::to_string(i * 1e-3) + ", 0]}\n";
  text += "  tool: [0, 0, 0, 1, 0, 0]\n";
  const std::string robot = scratch() + "/long_chain.yaml";
  std::ofstream(robot) << text;
  const std::string m = simulateTo("long_chain.csv", shellQuote(robot) + " --poses 1");
  expectRejected("calibrate " + shellQuote(robot) + " --measurements " + shellQuote(m), "numbers at once", m);
  expectRejected("identifiability " + shellQuote(robot) + " --poses 1", "identification size limit", robot);
}

// Review finding: measurements in metres (simulated from a URDF) fitted to a nominal in mm were a silently
// wrong calibration. simulate states the unit (`# length_unit: U`), calibrate compares it with the nominal's.
// A CSV in m for a mm nominal is converted (one note says so) and gives the mm result: the same fit as the
// same numbers written in mm. A unit lowpair does not convert is rejected, naming it.
TEST(Calibrate, MeasurementsInAnotherLengthUnitAreConverted) {
  const std::string urdf = modelPath("puma560_okamura_nominal.urdf");
  const std::string metres = simulateTo("metres.csv", shellQuote(urdf) + " --tip tool --poses 30 --seed 5");
  std::ifstream in(metres);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("\n# length_unit: m\n"), std::string::npos) << text.substr(0, 600);
  // the same measurements in mm: x, y, z times 1000 (decimal shift of the printed digits is not exact in
  // binary, so the two fits agree to rounding of the data: 1e-15 relative, compared at 1e-9)
  std::string mm_text, line;
  std::istringstream lines(text);
  bool header = false;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') {
      mm_text += (line == "# length_unit: m" ? std::string("# length_unit: mm") : line) + "\n";
      continue;
    }
    if (!header) {
      header = true;
      mm_text += line + "\n";
      continue;
    }
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    for (size_t k = 6; k < 9; ++k) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.17g", std::stod(f[k]) * 1000.0);
      f[k] = buf;
    }
    for (size_t k = 0; k < f.size(); ++k) mm_text += (k ? "," : "") + f[k];
    mm_text += "\n";
  }
  const std::string mm = writeScratchFile("millimetres.csv", mm_text);
  const CliRun a = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(metres) + " --json");
  const CliRun b = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(mm) + " --json");
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  ASSERT_EQ(ja["notes"].size(), 1u) << a.out;
  EXPECT_NE(ja["notes"][0].get<std::string>().find("lengths converted from m (its length_unit comment) to mm"),
            std::string::npos);
  EXPECT_EQ(jb["notes"].size(), 0u);
  for (const char* key : {"rms_position", "max_position"}) {
    EXPECT_NEAR(ja["before"][key].get<double>(), jb["before"][key].get<double>(), 1e-9 * jb["before"][key].get<double>());
  }
  for (size_t i = 0; i < 6; ++i) {
    for (const char* key : {"d", "a"}) {
      EXPECT_NEAR(ja["dh"]["joints"][i][key].get<double>(), jb["dh"]["joints"][i][key].get<double>(), 1e-9 * 1000.0);
    }
  }
  const std::string furlongs = writeScratchFile("furlongs.csv", std::regex_replace(text, std::regex("# length_unit: m\n"),
                                                                                  "# length_unit: furlong\n"));
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(furlongs),
                 "lengths in furlong (its length_unit comment) but " + kNominal + " is in mm, and lowpair converts only",
                 furlongs);
  // the same measurements with the URDF (urdfdom, metres) as the nominal: units agree, a noise-free fit
  const CliRun r = runCli("calibrate " + shellQuote(urdf) + " --tip tool --measurements " + shellQuote(metres) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["converged"].get<bool>()) << r.out;
}

// A validation file whose `# length_unit` is wrong by 1000 (mm values, the comment says m): converted, it lies
// 1e5 mm off a fit whose own RMS is 0.015 mm. It was printed at exit 0 ("validation, after 1.55e+05"); now the
// calibration is refused (exit 1, --out not written) naming the units first. The same file with the right
// comment validates as before (exit 0, 0.00716 mm in docs/calibration.md's walk-through).
TEST(CalibrateRejects, ValidationThatContradictsTheFitByOrdersOfMagnitude) {
  const std::string fit = simulateTo("val_unit_fit.csv", kMujocoActual + " --poses 50 --seed 1 --noise-position 0.01 --noise-rotation 1e-5");
  const std::string good = simulateTo("val_unit_good.csv", kMujocoActual + " --poses 20 --seed 2");
  std::ifstream in(good);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  ASSERT_NE(text.find("\n# length_unit: mm\n"), std::string::npos);
  const std::string wrong = writeScratchFile("val_unit_wrong.csv", std::regex_replace(text, std::regex("# length_unit: mm\n"),
                                                                                    "# length_unit: m\n"));
  const std::string out = scratch() + "/val_unit_cal.yaml";
  const std::string base = "calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(fit) +
                           " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch --out " + shellQuote(out) + " --validation ";
  const CliRun ok = runCli(base + shellQuote(good));
  ASSERT_EQ(ok.status, 0) << ok.err;
  ASSERT_TRUE(fs::exists(out));
  fs::remove(out);
  const CliRun r = runCli(base + shellQuote(wrong));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_FALSE(fs::exists(out)) << "--out written by a refused calibration";
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.rfind("error: " + wrong + ": calibration rejected, nothing written: the validation set contradicts", 0), 0u)
      << r.err;
  // the units first among what to look at: the validation file's comment and the fit's
  const size_t look = r.err.find("look at, in order: units (" + wrong + ": its length_unit comment says m (converted x 1000 to mm); " +
                                 fit + ": its length_unit comment says mm)");
  EXPECT_NE(look, std::string::npos) << r.err;
  EXPECT_NE(r.out.find("verdict: REJECTED: the validation set contradicts"), std::string::npos) << r.out;
  // JSON: the verdict says so too
  const CliRun j = runCli(base + shellQuote(wrong) + " --json");
  EXPECT_EQ(j.status, 1);
  const auto json = nlohmann::json::parse(j.out);
  EXPECT_FALSE(json["accepted"].get<bool>());
  EXPECT_NE(json["verdict"].get<std::string>().find("times the fit's own"), std::string::npos) << json["verdict"];
}

// ---- columns by name (docs/calibration.md "Measurement files (CSV)") -------------------------------------

namespace {

// `calibrate --json` of the measurements `path`, with the path replaced by MEASUREMENTS and the run time
// removed.
nlohmann::json calibrationJson(const std::string& path) {
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(path) +
                          " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch --json");
  EXPECT_EQ(r.status, 0) << path << "\n" << r.err;
  nlohmann::json j = nlohmann::json::parse(replaced(r.out, path, "MEASUREMENTS"));
  j.erase("seconds");
  return j;
}

}  // namespace

// The same measurements with their columns shuffled, the robot's joint names as headers, the quaternion in
// ROS's order (qx,qy,qz,qw) or an extra column calibrate to the same result bit for bit.
TEST(Calibrate, ColumnsAreFoundByNameInAnyOrder) {
  const std::string canonical =
      simulateTo("canonical.csv", shellQuote(kActualYaml) + " --poses 40 --seed 9 --noise-position 0.01 --noise-rotation 1e-5");
  std::ifstream in(canonical);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  auto same = [](const std::string& name) { return std::pair<std::string, std::string>{name, name}; };
  const std::string shuffled = writeScratchFile(
      "shuffled.csv", rearranged(text, {same("qy"), same("x"), same("q3"), same("qz"), same("q1"), same("z"), same("q6"),
                                        same("qw"), same("q2"), same("y"), same("q5"), same("qx"), same("q4")}));
  // the nominal's joints are named j1..j6
  const std::string named = writeScratchFile(
      "named.csv", rearranged(text, {{"q1", "j1"}, {"q2", "j2"}, {"q3", "j3"}, {"q4", "j4"}, {"q5", "j5"}, {"q6", "j6"},
                                     same("x"), same("y"), same("z"), same("qw"), same("qx"), same("qy"), same("qz")}));
  const std::string ros = writeScratchFile(
      "ros.csv", rearranged(text, {same("q1"), same("q2"), same("q3"), same("q4"), same("q5"), same("q6"), same("x"),
                                   same("y"), same("z"), same("qx"), same("qy"), same("qz"), same("qw")}));
  const nlohmann::json expected = calibrationJson(canonical);
  ASSERT_TRUE(expected["accepted"].get<bool>());
  ASSERT_EQ(expected["notes"].size(), 0u);
  EXPECT_EQ(calibrationJson(shuffled), expected);
  EXPECT_EQ(calibrationJson(named), expected);
  EXPECT_EQ(calibrationJson(ros), expected);
  // an unknown column: ignored, one note names it (text: a `note:` line; JSON: notes)
  const std::string extra = writeScratchFile(
      "extra.csv", rearranged(text, {same("q1"), same("q2"), same("q3"), same("q4"), same("q5"), same("q6"), {"", "operator"},
                                     same("x"), same("y"), same("z"), same("qw"), same("qx"), same("qy"), same("qz")}));
  nlohmann::json with_extra = calibrationJson(extra);
  const int header_line = static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("\nq1")), '\n')) + 2;
  ASSERT_EQ(with_extra["notes"].size(), 1u);
  EXPECT_EQ(with_extra["notes"][0], "MEASUREMENTS:" + std::to_string(header_line) +
                                        ": ignored the column 'operator' (not a column lowpair reads)");
  with_extra["notes"] = nlohmann::json::array();
  EXPECT_EQ(with_extra, expected);
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(extra) +
                          " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("note: " + extra + ":" + std::to_string(header_line) + ": ignored the column 'operator'"),
            std::string::npos) << r.out;
}

// A missing, repeated or misspelt column, or both joint spellings: exit 2, one line naming it.
TEST(CalibrateRejects, MissingRepeatedOrMixedColumns) {
  const std::string base = "calibrate " + shellQuote(kNominal) + " --measurements ";
  const std::string row = "0,0,0,0,0,0,1,2,3\n";
  auto bad = [&](const std::string& name, const std::string& header, const std::string& what) {
    const std::string path = writeScratchFile(name, "# c\n" + header + "\n" + row);
    expectRejected(base + shellQuote(path), path + ":2: " + what, path);
  };
  bad("no_q4.csv", "q1,q2,q3,q5,q6,q7,x,y,z", "missing column 'q4'");
  bad("no_j4.csv", "j1,j2,j3,j5,j6,x,y,z,t", "missing column 'j4'");
  bad("no_y.csv", "j1,j2,j3,j4,j5,j6,x,z,t", "missing column 'y'");
  bad("two_x.csv", "q1,q2,q3,q4,q5,x,y,z,x", "column 'x' repeats (columns 6 and 9)");
  bad("two_j2.csv", "j1,j2,j3,j4,j5,j2,x,y,z", "column 'j2' repeats (columns 2 and 6)");
  bad("mixed.csv", "q1,q2,q3,j4,j5,j6,x,y,z", "joint columns 'q1' and 'j4': q1..qn or the robot's joint names, not both");
  bad("case.csv", "q1,q2,q3,q4,q5,q6,X,y,z", "unexpected column 'X'");
  bad("case_joint.csv", "J1,j2,j3,j4,j5,j6,x,y,z", "unexpected column 'J1'");
}
