// Rough edges a real user hits (issue "rough edges"): one test per numbered item, each failing on the
// code before its fix. Items 1-4 are in output_files_test.cpp and hostile_input_test.cpp, item 8 in
// harness_test.cpp (ValidateReport.UserStringsInSummaryAreEscaped).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace {

using namespace lowpair_test;

const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");

// A measurement CSV of the 6-joint nominal from `simulate`.
std::string simulated(const std::string& name, const std::string& options) {
  const std::string path = scratch() + "/" + name;
  const CliRun r = runCli("simulate " + shellQuote(kNominal) + " " + options + " --out " + shellQuote(path));
  EXPECT_EQ(r.status, 0) << r.err;
  return path;
}

// Item 5: a stream of comment lines ends at the line limit (it never ended); a file for another robot is
// rejected at its header (before the rest is read: the broken line 3 is never reached); hexadecimal
// floats, which no writer produces, are not numbers here.
TEST(RoughEdges, MeasurementReaderLimitsAndHeader) {
  {
    const std::string path = scratch() + "/comments.csv";
    std::ofstream out(path);
    for (long long k = 0; k < 1100001; ++k) out << "#\n";
  }
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(scratch() + "/comments.csv"),
                 "more than 1100000 lines (comments and blank lines count)");
  const std::string five = writeScratchFile("five.csv", "q1,q2,q3,q4,q5,x,y,z\nbroken line\n");
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(five), "has 5 joint columns",
                 five);
  const std::string hex =
      writeScratchFile("hex.csv", "q1,q2,q3,q4,q5,q6,x,y,z\n0x1.8p+4,0,0,0,0,0,1,2,3\n");
  expectRejected("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(hex),
                 "'0x1.8p+4' is not a decimal number", hex + ":2");
}

// Item 6: a link that is the child of two joints (a closed loop) was opened silently by urdfdom.
TEST(RoughEdges, UrdfLinkWithTwoParentsIsRejected) {
  const std::string urdf = writeScratchFile("loop.urdf", R"(<robot name="loop">
  <link name="base"/><link name="a"/><link name="b"/><link name="tool"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>
  <joint name="j2" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
  <joint name="j3" type="continuous"><parent link="base"/><child link="b"/><axis xyz="0 0 1"/></joint>
  <joint name="t" type="fixed"><parent link="b"/><child link="tool"/><origin xyz="1 0 0"/></joint>
</robot>
)");
  expectRejected("poe2dh " + shellQuote(urdf) + " --tip tool", "link 'b' is the child of joints 'j2' and 'j3'",
                 urdf + ": line 5: ");
}

// A POE robot file of n revolute joints about z, each 0.1 further along x.
std::string longChain(int n) {
  std::ostringstream out;
  out << "name: chain" << n << "\nlength_unit: m\npoe:\n  joints:\n";
  for (int i = 0; i < n; ++i) out << "    - {type: revolute, twist: [0, 0, 1, 0, " << -0.1 * i << ", 0]}\n";
  out << "  tool_pose: [[1, 0, 0, " << 0.1 * n << "], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n";
  return writeScratchFile("chain" + std::to_string(n) + ".yaml", out.str());
}

// Item 7: an MJCF nests one body per joint; past tinyxml2's depth of 100 lowpair cannot read it back, so
// export refuses instead of writing it. A chain that fits is written and reads back.
TEST(RoughEdges, MjcfExportRefusesWhatCannotBeReadBack) {
  const std::string fits = longChain(90), deep = longChain(100);
  const std::string xml = scratch() + "/chain90.xml";
  ASSERT_EQ(runCli("export " + shellQuote(fits) + " --format mjcf --out " + shellQuote(xml)).status, 0);
  const CliRun back = runCli("poe2dh " + shellQuote(xml) + " --tip tool --json");
  EXPECT_EQ(back.status, 0) << back.err;
  expectRejected("export " + shellQuote(deep) + " --format mjcf --out " + shellQuote(scratch() + "/chain100.xml"),
                 "100 joints: an MJCF nests one body per joint", deep);
  EXPECT_FALSE(std::ifstream(scratch() + "/chain100.xml").good());
}

// Item 9: a scenario's calibration case compares the measurements' unit with the nominal's (a URDF in
// metres against a nominal in mm was reported as a robot error of 186 m); simulate rejects a rotation
// noise for position measurements as calibrate does; numbers in one-line errors have at most 17 digits.
TEST(RoughEdges, ScenarioUnitsSimulateNoiseAndShortNumbers) {
  const std::string scenario = writeScratchFile(
      "units.yaml", "name: units\nmodel: " + modelPath("rhino_xr3_slide.urdf") +
                        "\ntip: tool\nsamples: 10\ncalibration:\n  - name: mixed\n    nominal: " +
                        modelPath("rhino_xr3_slide.yaml") +
                        "\n    poses: 40\n    validation_poses: 10\n    tolerance: {position: 1}\n");
  expectRejected("validate " + shellQuote(scenario), "are in m but the nominal", scenario);
  expectRejected("simulate " + shellQuote(kNominal) + " --poses 3 --measure position --noise-rotation 0.001",
                 "position measurements have no rotation to perturb", "--noise-rotation");
  const std::string huge = writeScratchFile(
      "huge_noise.yaml", "name: huge\nmodel: " + modelPath("stanford_corke_actual.xml") +
                             "\ntip: tool\nsamples: 10\ncalibration:\n  - name: loud\n    nominal: " +
                             modelPath("stanford_corke.yaml") +
                             "\n    poses: 40\n    validation_poses: 10\n    noise: {position: 1e300}\n"
                             "    tolerance: {position: 1}\n");
  const CliRun r = runCli("validate " + shellQuote(huge));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_LT(r.err.size(), 400u) << r.err;
  EXPECT_EQ(r.err.find("000000000000000000"), std::string::npos) << r.err;
}

// Item 11: a tip that is not found lists what exists.
TEST(RoughEdges, TipNotFoundListsTheNames) {
  expectRejected("fk " + shellQuote(modelPath("elbow_mls.xml")) + " --tip nowhere --q 0,0,0,0,0,0", "sites: 'tool'");
  expectRejected("fk " + shellQuote(modelPath("elbow_mls.urdf")) + " --tip nowhere --q 0,0,0,0,0,0", "links: '");
}

// Item 14: calibrate --json: pitch only on helical rows, rotation statistics null for position
// measurements, the length unit, and the correlations of the determined parameters.
TEST(RoughEdges, CalibrateJsonFields) {
  const std::string m = simulated("position.csv", "--poses 40 --seed 3 --measure position --noise-position 0.01");
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["before"]["max_rotation"].is_null());
  EXPECT_TRUE(j["after"]["rms_rotation"].is_null());
  EXPECT_EQ(j["length_unit"], "mm");
  for (const auto& row : j["dh"]["joints"]) {
    EXPECT_EQ(row.contains("pitch"), row["type"] == "helical") << row.dump();
  }
  const auto& c = j["correlation"];
  const size_t n = c["parameters"].size();
  ASSERT_GT(n, 0u);
  ASSERT_EQ(c["matrix"].size(), n);
  // a correlation matrix: unit diagonal, entries in [-1, 1], to the rounding of cov_ab / (sd_a sd_b), where
  // cov = A A^T and sd are the row norms of A (calibration.hpp): sums of at most `parameters` products,
  // each adding eps of relative error
  const double rounding = 2.0 * static_cast<double>(j["parameters"].size()) * std::numeric_limits<double>::epsilon();
  for (size_t a = 0; a < n; ++a) {
    EXPECT_NEAR(c["matrix"][a][a].get<double>(), 1.0, rounding);
    for (size_t b = 0; b < n; ++b) EXPECT_LE(std::abs(c["matrix"][a][b].get<double>()), 1.0 + rounding);
  }
}

// Item 16: every bundled scenario validates at least 10,000 random samples.
TEST(RoughEdges, EveryScenarioHasTenThousandSamples) {
  int scenarios = 0;
  for (const auto& entry : std::filesystem::directory_iterator(LOWPAIR_SCENARIOS)) {
    if (entry.path().extension() != ".yaml") continue;
    ++scenarios;
    std::ifstream in(entry.path());
    std::string line;
    long long samples = -1;
    while (std::getline(in, line)) {
      if (line.rfind("samples:", 0) == 0) samples = std::stoll(line.substr(8));
    }
    EXPECT_GE(samples, 10000) << entry.path();
  }
  EXPECT_GE(scenarios, 8);
}


// Item 5, last part: a joint value outside the nominal's range is named with its line: a warning just
// outside, an error beyond 10 range widths (a prismatic q of 1e100 in a 0.3-1.3 range was fitted silently).
TEST(RoughEdges, JointValuesOutsideTheRangeAreNamed) {
  const std::string robot = modelPath("puma560_corke.yaml");  // joint 1: [-160, 160] deg
  const std::string m = scratch() + "/ranges.csv";
  ASSERT_EQ(runCli("simulate " + shellQuote(robot) + " --poses 30 --seed 4 --noise-position 1e-5 --noise-rotation 1e-5"
                   " --out " + shellQuote(m)).status, 0);
  std::ifstream in(m);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  size_t first_data = 0;
  while (lines[first_data].empty() || lines[first_data][0] == '#') ++first_data;
  ++first_data;  // the header
  auto withQ1 = [&](const std::string& name, const std::string& q1) {
    std::string text;
    for (size_t k = 0; k < lines.size(); ++k) {
      std::string line = lines[k];
      if (k == first_data) line = q1 + line.substr(line.find(','));
      text += line + "\n";
    }
    return writeScratchFile(name, text);
  };
  const std::string far = withQ1("far.csv", "1e6");
  expectRejected("calibrate " + shellQuote(robot) + " --measurements " + shellQuote(far),
                 "q1 = 1e+06 is outside joint 1's range", far + ":" + std::to_string(first_data + 1) + ": ");
  const std::string near = withQ1("near.csv", "2.9");
  // (the changed q1 is a blunder of that row: a robust loss flags it and fits the rest)
  const CliRun r = runCli("calibrate " + shellQuote(robot) + " --measurements " + shellQuote(near) +
                          " --noise-position 1e-5 --noise-rotation 1e-5 --loss cauchy");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.rfind("warning: " + near + ":" + std::to_string(first_data + 1) + ": q1 = 2.9 is outside", 0), 0u)
      << r.err;
}


// Item 10: an MJCF states no unit. A robot file 1000 times larger than the model is named as a unit
// mix-up, --length-unit states the model's unit (the robot file is converted), and model mode takes
// --tolerance POS,ROT as scenarios do.
TEST(RoughEdges, ValidateUnitsAndTolerance) {
  const std::string mm = writeScratchFile("elbow_mm.yaml", R"(name: elbow-mm
length_unit: mm
poe:
  joints:
    - {type: revolute, twist: [0, 0, 1, 0, 0, 0]}
    - {type: revolute, twist: [-1, 0, 0, 0, -1000, 0]}
    - {type: revolute, twist: [-1, 0, 0, 0, -1000, 1000]}
    - {type: revolute, twist: [0, 0, 1, 2000, 0, 0]}
    - {type: revolute, twist: [-1, 0, 0, 0, -1000, 2000]}
    - {type: revolute, twist: [0, 1, 0, -1000, 0, 0]}
  tool_pose: [[1, 0, 0, 0], [0, 1, 0, 2000], [0, 0, 1, 1000], [0, 0, 0, 1]]
)");
  const std::string model = shellQuote(modelPath("elbow_mls.xml"));
  const CliRun mixed = runCli("validate " + model + " --tip tool --robot " + shellQuote(mm) + " --samples 100");
  EXPECT_EQ(mixed.status, 1) << mixed.err;
  EXPECT_NE(mixed.err.find("its lengths are 1000 times those of"), std::string::npos) << mixed.err;
  EXPECT_NE(mixed.err.find("is the robot file in mm and the model in m?"), std::string::npos) << mixed.err;
  const CliRun stated =
      runCli("validate " + model + " --tip tool --robot " + shellQuote(mm) + " --samples 100 --length-unit m");
  EXPECT_EQ(stated.status, 0) << stated.out << stated.err;
  EXPECT_EQ(stated.err.find("note:"), std::string::npos) << stated.err;
  // a looser tolerance is reported as given
  const CliRun loose = runCli("validate " + model + " --tip tool --samples 100 --tolerance 1e-9,1e-10 --json");
  ASSERT_EQ(loose.status, 0) << loose.err;
  const auto j = nlohmann::json::parse(loose.out);
  const auto& poe = j["scenarios"][0]["comparisons"][0];
  EXPECT_EQ(poe["tolerance_rotation"].get<double>(), 1e-10) << poe.dump();
  expectRejected("validate " + model + " --tip tool --tolerance 1e-9", "expected POS,ROT", "--tolerance");
  expectRejected("validate " + model + " --tip tool --length-unit furlong", "not one lowpair converts", "--length-unit");
}


// Item 12 (in part): the D-H table prints lengths to about 1e-6 L and angles to 1e-6 deg (a UR10e-like
// table in metres printed a3 = 0.57155 as 0.5716), and the residual table 3 significant digits.
TEST(RoughEdges, PrintedPrecision) {
  const std::string dh = writeScratchFile("ur_like.yaml", R"(name: ur-like
length_unit: m
angle_unit: deg
dh:
  joints:
    - {type: revolute, theta: 0, d: 0.1807, alpha: 90, a: 0}
    - {type: revolute, theta: 0, d: 0, alpha: 0, a: -0.6127}
    - {type: revolute, theta: 0, d: 0, alpha: 0, a: -0.57155}
    - {type: revolute, theta: 0, d: 0.17415, alpha: 90, a: 0}
    - {type: revolute, theta: 0, d: 0.11985, alpha: -90.000123, a: 0}
    - {type: revolute, theta: 0, d: 0.11655, alpha: 0, a: 0}
)");
  const CliRun r = runCli("poe2dh " + shellQuote(dh));
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* value : {"0.571550", "0.174150", "0.119850", "0.116550"}) {
    EXPECT_NE(r.out.find(value), std::string::npos) << value << " in\n" << r.out;
  }
  // alpha of row 5 to 1e-6 deg (the canonical table may flip its sign or take the supplement)
  EXPECT_TRUE(r.out.find("90.000123") != std::string::npos || r.out.find("89.999877") != std::string::npos) << r.out;
  const std::string m = simulated("digits.csv", "--poses 40 --seed 5 --noise-position 0.01 --noise-rotation 1e-5");
  const CliRun c = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) +
                          " --noise-position 0.01 --noise-rotation 1e-5");
  ASSERT_EQ(c.status, 0) << c.err;
  std::istringstream lines(c.out);
  std::string line;
  while (std::getline(lines, line) && line.rfind("measurements, after", 0) != 0) {
  }
  std::istringstream fields(line.substr(std::string("measurements, after").size()));
  std::string rms;
  fields >> rms;
  // 3 significant digits: the mantissa has 3 digits (e.g. 0.00823 or 8.23e-03)
  std::string digits;
  for (const char ch : rms.substr(0, rms.find('e'))) {
    if (ch >= '0' && ch <= '9') digits += ch;
  }
  digits.erase(0, digits.find_first_not_of('0'));
  EXPECT_EQ(digits.size(), 3u) << line;
}

}  // namespace
