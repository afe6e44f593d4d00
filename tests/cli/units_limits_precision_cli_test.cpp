// What the commands check and print where ordinary use meets their edges: length units (a scenario's
// measurements against its nominal, validate's robot file against an MJCF, --length-unit), the limits of
// the readers and writers (comment streams, a file for another robot, hexadecimal floats, URDF loops, MJCF
// depth, joint values outside their range), names in errors (a tip not found), printed precision (D-H and
// residual tables, numbers in one-line errors, the calibrated D-H table's width and its fixed entries, the
// nearly-parallel note), calibrate --json's fields and values, and every scenario's sample count.
// Written as one test per item of the "rough edges" issue (hence the suite name RoughEdges), each failing on
// the code before its fix; items 1-4 are in output_files_test.cpp and hostile_input_test.cpp, item 8 in
// validate_cli_test.cpp (ValidateReport.UserStringsInSummaryAreEscaped).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
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

// Item 14: every parameter's value is in the JSON. The actual robot differs from the nominal only in the
// offsets of joints 2 and 4; offsets add exactly (CalibrationResult::estimate), so a noise-free fit of the
// offsets level finds them to the rounding of the fit: FK's rounding, 16 (n + 1) eps L (fkRounding; L ~ 1e3
// mm: 2.5e-11 mm), over levers of at least 100 mm: 2.5e-13 rad (measured: 1.5e-16). Joints 1 and 6 trade with
// the base's and the tool's turn about their axes: undetermined, standard deviation null.
TEST(RoughEdges, CalibrateJsonParameterValues) {
  std::ifstream in(kNominal);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [joint, offset] : {std::pair<std::string, std::string>{"{name: j2, type: revolute,", "0.001"},
                                     {"{name: j4, type: revolute,", "-0.002"}}) {
    const size_t at = text.find(joint);
    ASSERT_NE(at, std::string::npos) << joint;
    text.insert(at + joint.size(), " offset: " + offset + ",");
  }
  const std::string actual = writeScratchFile("offsets_actual.yaml", text);
  const std::string m = scratch() + "/offsets.csv";
  ASSERT_EQ(runCli("simulate " + shellQuote(actual) + " --poses 30 --seed 8 --out " + shellQuote(m)).status, 0);
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) +
                          " --parameters offsets --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::map<std::string, double> value;
  std::map<std::string, nlohmann::json> sd;
  for (const auto& p : j["parameters"]) {
    value[p["name"].get<std::string>()] = p["value"].get<double>();
    sd[p["name"].get<std::string>()] = p["standard_deviation"];
  }
  EXPECT_TRUE(sd.at("j1.offset").is_null());
  EXPECT_TRUE(sd.at("j6.offset").is_null());
  const double kTolerance = 16.0 * 7.0 * std::numeric_limits<double>::epsilon() * 1000.0 / 100.0;  // rad
  EXPECT_NEAR(value.at("j2.offset"), 0.001, kTolerance);
  EXPECT_NEAR(value.at("j3.offset"), 0.0, kTolerance);
  EXPECT_NEAR(value.at("j4.offset"), -0.002, kTolerance);
  EXPECT_NEAR(value.at("j5.offset"), 0.0, kTolerance);
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
  auto withQ1 = [&](const std::string& name, const std::string& q1, const std::string& next_q1 = "") {
    std::string text;
    for (size_t k = 0; k < lines.size(); ++k) {
      std::string line = lines[k];
      if (k == first_data) line = q1 + line.substr(line.find(','));
      if (k == first_data + 1 && !next_q1.empty()) line = next_q1 + line.substr(line.find(','));
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
  // a near value, then a far one: the warning, then the refusal (exit 2, the error the last line, no stdout)
  const std::string both = withQ1("both.csv", "2.9", "1e6");
  const CliRun b = runCli("calibrate " + shellQuote(robot) + " --measurements " + shellQuote(both));
  EXPECT_EQ(b.status, 2) << b.err;
  EXPECT_TRUE(b.out.empty()) << b.out;
  EXPECT_EQ(b.err.rfind("warning: " + both + ":" + std::to_string(first_data + 1) + ": q1 = 2.9 is outside", 0), 0u)
      << b.err;
  const std::string error_line = "\nerror: " + both + ":" + std::to_string(first_data + 2) + ": q1 = 1e+06 is outside";
  EXPECT_NE(b.err.find(error_line), std::string::npos) << b.err;
  EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 2) << b.err;
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

// Item 12 (the rest): the calibrated D-H table fits 120 columns; the entries the D-H convention sets (the row
// placed by a prismatic axis: a = d = 0) print as fixed, not as a rounding-level standard deviation, and are
// flagged in the JSON.
TEST(RoughEdges, CalibratedDhTableFitsAndSaysFixed) {
  const std::string stanford = modelPath("stanford_corke.yaml");  // joint 3 prismatic
  const std::string m = scratch() + "/stanford.csv";
  ASSERT_EQ(runCli("simulate " + shellQuote(stanford) + " --poses 40 --seed 2 --noise-position 1e-5 --noise-rotation 1e-5 --out " +
                   shellQuote(m)).status, 0);
  const std::string args = "calibrate " + shellQuote(stanford) + " --measurements " + shellQuote(m) +
                           " --noise-position 1e-5 --noise-rotation 1e-5";
  const CliRun r = runCli(args);
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out.substr(r.out.find("calibrated D-H table")));
  std::string line;
  int rows = 0;
  bool fixed_row = false;
  while (std::getline(lines, line) && line.rfind("(standard deviations", 0) != 0) {
    EXPECT_LE(line.size(), 120u) << line;
    ++rows;
    // the row placed by joint 3's axis is row 2; in the deviations table its d and a are "fixed"
    std::istringstream fields(line);
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), std::istream_iterator<std::string>()};
    if (f.size() >= 6 && f[0] == "2" && f[3] == "fixed" && f[5] == "fixed") fixed_row = true;
  }
  EXPECT_GE(rows, 2 * (1 + 6 + 2));  // two tables: header, base, 6 rows, tool
  EXPECT_TRUE(fixed_row) << r.out;
  const CliRun j = runCli(args + " --json");
  ASSERT_EQ(j.status, 0) << j.err;
  const auto row2 = nlohmann::json::parse(j.out)["dh"]["joints"][1];
  EXPECT_EQ(row2["fixed"], nlohmann::json::array({"d", "a"})) << row2.dump();
  EXPECT_EQ(row2["sd"]["d"], 0.0);
  EXPECT_EQ(row2["sd"]["a"], 0.0);
  EXPECT_EQ(row2["d"], 0.0);
  EXPECT_EQ(row2["a"], 0.0);
}

// Item 12 (the rest): axes parallel but for an angle a file's rounding makes (the IRB 2400 URDF's tool: 4.9e-12
// rad) get a note naming --parallel-threshold, with a value that, given back, makes them parallel.
TEST(RoughEdges, NearlyParallelNotePointsAtTheThreshold) {
  // joint 2 through (1, 0, 0), its axis turned 3e-9 rad from joint 1's about x
  const double t = 3e-9;
  std::ostringstream robot;
  robot.precision(17);
  robot << "name: nearly-parallel\nlength_unit: m\npoe:\n  joints:\n"
        << "    - {type: revolute, twist: [0, 0, 1, 0, 0, 0]}\n"
        << "    - {type: revolute, twist: [0, " << -std::sin(t) << ", " << std::cos(t) << ", 0, " << -std::cos(t) << ", "
        << -std::sin(t) << "]}\n"
        << "  tool: [0, 0, 0, 2, 0, 0]\n";
  const std::string path = writeScratchFile("nearly_parallel.yaml", robot.str());
  const CliRun r = runCli("poe2dh " + shellQuote(path));
  ASSERT_EQ(r.status, 0) << r.err;
  const size_t note = r.out.find("note: row 1: the axes of joints 1 and 2 are parallel but for 3e-09 rad");
  ASSERT_NE(note, std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--parallel-threshold 1e-07 makes them parallel", note), std::string::npos) << r.out;
  const CliRun again = runCli("poe2dh " + shellQuote(path) + " --parallel-threshold 1e-07 --json");
  ASSERT_EQ(again.status, 0) << again.err;
  const auto j = nlohmann::json::parse(again.out);
  EXPECT_TRUE(j["notes"].empty()) << j["notes"].dump();
  EXPECT_TRUE(j["conditioning"][1]["parallel"].get<bool>()) << j["conditioning"].dump();
}

}  // namespace
