// calibrate --select cv over levels x prior widths x deflections on/off, and --cv-score (docs/calibration.md
// "Selection by cross-validation"): every candidate scored on the same partitions, the table in JSON and text, the
// chosen candidate fitted; the argument errors.
//
// The data (all seeded, made by `simulate`, 5 folds x 2 partitions: 10 fits per candidate, under a second each here):
// - compliant: MuJoCo's PUMA 560 with masses resting on springs k = 8e4, 4e4, 1e4 N m/rad on joints 2, 3, 5 (as
//   compliant_loop_cli_test.cpp), 40 positions at 0.01 mm; rigid: the same robot without springs. Its nominal,
//   models/puma560_masses.yaml, is its geometry: only the deflections separate the candidates.
// - perturbed: the nominal's D-H moved by 1-3 mrad and 0.5-1.5 mm (kPerturbed below), positions at 0.05 mm: 12
//   poses (36 rows for up to 36 parameters) and 60.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.hpp"

namespace {

using namespace lowpair_test;
using nlohmann::json;

const std::string kNominal = modelPath("puma560_masses.yaml");
const std::string kActual = modelPath("puma560_masses.xml") + " --tip tool";
const std::string kSprings = " --stiffness 0,8e4,4e4,0,1e4,0";
const std::string kCv = " --select cv --folds 5 --repeats 2";

// The nominal's D-H with errors of the size a prior of 1-3 (mrad, mm) describes: theta 1-3 mrad, d and a 0.5-1.5 mm,
// alpha 1-2 mrad (masses left out: simulate does not need them).
const char* const kPerturbed = R"(name: puma560-perturbed
length_unit: m
angle_unit: rad
dh:
  base:  {theta: 0, d: 0, alpha: 0, a: 0}
  joints:
    - {name: j1, type: revolute, theta: 0.002, d: 0.001, alpha: 1.5717963267948966, a: 0, range: [-2.792526803190927, 2.792526803190927]}
    - {name: j2, type: revolute, theta: 0.003, d: 0, alpha: 0.002, a: 0.4328, range: [-0.7853981633974483, 3.9269908169872414]}
    - {name: j3, type: revolute, theta: -0.002, d: 0.15155, alpha: -1.5707963267948966, a: 0.0193, range: [-3.9269908169872414, 0.7853981633974483]}
    - {name: j4, type: revolute, theta: 0.001, d: 0.4308, alpha: 1.5692963267948966, a: 0, range: [-1.9198621771937625, 2.9670597283903604]}
    - {name: j5, type: revolute, theta: -0.002, d: 0, alpha: -1.5697963267948966, a: 0.0005, range: [-1.7453292519943295, 1.7453292519943295]}
    - {name: j6, type: revolute, theta: 0.003, d: 0, alpha: 0, a: 0, range: [-4.642575810304916, 4.642575810304916]}
  tool:  {theta: 0, d: 0.2}
)";

std::string simulated(const std::string& name, const std::string& args) {
  const std::string path = scratch() + "/" + name;
  const CliRun r = runCli("simulate " + args + " --out " + shellQuote(path));
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return path;
}

json selection(const std::string& measurements, const std::string& args) {
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(measurements) + kCv + " " +
                          args + " --json");
  EXPECT_TRUE(r.status == 0 || r.status == 1) << args << "\n" << r.err;
  const json j = json::parse(r.out);
  return j["cross_validation"];
}

const json& chosen(const json& cv) {
  for (const json& c : cv["candidates"]) {
    if (c["chosen"] == true) return c;
  }
  ADD_FAILURE() << "no chosen candidate: " << cv.dump();
  return cv;
}

// The candidate of `level` with `prior` (null: none) and compliance `on`.
const json& candidate(const json& cv, const std::string& level, const json& prior, bool compliance) {
  for (const json& c : cv["candidates"]) {
    if (c["parameters"] == level && c["prior"] == prior && c["compliance"] == compliance) return c;
  }
  ADD_FAILURE() << "no candidate " << level << " " << prior << " " << compliance << ": " << cv.dump();
  return cv;
}

}  // namespace

// Every candidate, one row each, on the same partitions; the final fit is the chosen candidate's.
TEST(CalibrateSelection, ComplianceOnAndOffAreCandidatesAndTheCompliantDataChooseOn) {
  const std::string m = simulated("compliant.csv", kActual + " --measure position --noise-position 1e-5 --poses 40 --seed 1" + kSprings);
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + kCv +
                          " --noise-position 1e-5 --compliance 2,3,5 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  const json& cv = j["cross_validation"];
  EXPECT_EQ(cv["score"], "rms");
  ASSERT_EQ(cv["candidates"].size(), 6u);  // 3 levels x compliance off, on
  int chosen_rows = 0;
  for (const json& c : cv["candidates"]) {
    chosen_rows += c["chosen"].get<bool>() ? 1 : 0;
    EXPECT_TRUE(c["prior"].is_null());
    EXPECT_FALSE(c["backlash"].get<bool>());
    EXPECT_TRUE(c["score_sd"].is_number());  // 2 partitions
  }
  EXPECT_EQ(chosen_rows, 1);
  const json& best = chosen(cv);
  EXPECT_EQ(best["compliance"], true);
  EXPECT_EQ(cv["chosen"], best["parameters"]);
  // the springs' deflections (0.2-1 mrad) are 10-50 times the noise at the tool: off is far worse at every level
  for (const char* level : {"full", "lines", "offsets"}) {
    EXPECT_GT(candidate(cv, level, nullptr, false)["score"].get<double>(),
              5 * candidate(cv, level, nullptr, true)["score"].get<double>()) << level;
  }
  // the final fit is the chosen candidate's: its level and the three compliances
  EXPECT_EQ(j["parameter_set"], best["parameters"]);
  EXPECT_EQ(j["deflections"].size(), 3u);
}

// Rigid data: the compliances explain nothing. The rule (the levels' rule, reused): the least score wins, so "on" may
// win by a hair of noise; it must then be within its sd of "off" at the same level.
TEST(CalibrateSelection, RigidDataChooseComplianceOffOrATieWithinTheSd) {
  const std::string m = simulated("rigid.csv", kActual + " --measure position --noise-position 1e-5 --poses 40 --seed 1");
  const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + kCv +
                          " --noise-position 1e-5 --compliance 2,3,5 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const json j = json::parse(r.out);
  const json& best = chosen(j["cross_validation"]);
  if (best["compliance"] == true) {
    const json& off = candidate(j["cross_validation"], best["parameters"], nullptr, false);
    EXPECT_LE(off["score"].get<double>() - best["score"].get<double>(), best["score_sd"].get<double>()) << j.dump();
  } else {
    EXPECT_FALSE(j.contains("deflections"));  // off chosen: the final fit is rigid
  }
}

// 12 poses at 0.05 mm of a robot 1-3 mrad and mm off its nominal: a prior of that size (1 or 3) beats no prior by
// more than the no-prior score's sd; with 60 poses the data decide alone: the chosen candidate is within its sd of no
// prior at its level, and a prior narrower than the errors (0.3) is worse than none by more than its sd.
TEST(CalibrateSelection, FewPosesChooseAPriorOfTheErrorsSizeManyPosesNeedNone) {
  const std::string actual = writeScratchFile("perturbed.yaml", kPerturbed);
  const std::string few = simulated("few.csv", shellQuote(actual) + " --measure position --poses 12 --seed 1 --noise-position 5e-5");
  const std::string many = simulated("many.csv", shellQuote(actual) + " --measure position --poses 60 --seed 1 --noise-position 5e-5");
  const json f = selection(few, "--noise-position 5e-5 --prior-grid default");
  ASSERT_EQ(f["candidates"].size(), 18u);  // 3 levels x (none + 5 widths)
  const json& fb = chosen(f);
  ASSERT_TRUE(fb["prior"].is_number()) << f.dump();
  EXPECT_GE(fb["prior"].get<double>(), 1.0);
  EXPECT_LE(fb["prior"].get<double>(), 3.0);
  const json& f_none = candidate(f, fb["parameters"], nullptr, false);
  EXPECT_LT(fb["score"].get<double>() + f_none["score_sd"].get<double>(), f_none["score"].get<double>()) << f.dump();

  const json g = selection(many, "--noise-position 5e-5 --prior-grid default");
  const json& gb = chosen(g);
  const json& g_none = candidate(g, gb["parameters"], nullptr, false);
  EXPECT_LE(std::abs(gb["score"].get<double>() - g_none["score"].get<double>()), gb["score_sd"].get<double>()) << g.dump();
  const json& narrow = candidate(g, gb["parameters"], 0.3, false);
  EXPECT_GT(narrow["score"].get<double>(), g_none["score"].get<double>() + narrow["score_sd"].get<double>());
}

// A 5 mm blunder (500 sigma) among 40 compliant positions, fitted with Huber's loss (the training fits weigh it down).
// Held out, it dominates the RMS score (Huber's rho grows linearly: measured 1.94 -> 8.87 for the chosen candidate),
// while the trimmed score drops it and the median ignores it: both stay within 25 % of the clean data's and choose
// compliance on as on clean data, the trimmed one the same candidate (the median is the noisier estimate: its choice
// among the "on" levels is within its sd, measured 2.01 vs 2.02). `score`: the clean and the blundered selections.
namespace {

void checkBlunderScores(const std::string& score) {
  const std::string base = kActual + " --measure position --noise-position 1e-5 --poses 40 --seed 1" + kSprings;
  const std::string clean = simulated("clean.csv", base);
  const std::string blunder = simulated("blunder.csv", base + " --blunders 1,0.005");
  const std::string args = "--noise-position 1e-5 --compliance 2,3,5 --loss huber --cv-score " + score;
  const json a = selection(clean, args), b = selection(blunder, args);
  EXPECT_EQ(a["score"], score);
  const json &ca = chosen(a), &cb = chosen(b);
  EXPECT_EQ(ca["compliance"], true) << score;
  EXPECT_EQ(cb["compliance"], true) << score;
  const double ratio = cb["score"].get<double>() / candidate(a, cb["parameters"], nullptr, true)["score"].get<double>();
  if (score == "rms") {
    EXPECT_GT(ratio, 3.0);
  } else {
    EXPECT_LT(ratio, 1.25) << score;
    if (score == "trimmed") {
      EXPECT_EQ(ca["parameters"], cb["parameters"]);
    } else {
      const json& same = candidate(b, ca["parameters"], nullptr, true);
      EXPECT_LE(same["score"].get<double>() - cb["score"].get<double>(), cb["score_sd"].get<double>());
    }
  }
}

}  // namespace

TEST(CalibrateSelection, RmsScoreIsDominatedByAHeldOutBlunder) { checkBlunderScores("rms"); }
TEST(CalibrateSelection, TrimmedScoreIgnoresAHeldOutBlunder) { checkBlunderScores("trimmed"); }
TEST(CalibrateSelection, MedianScoreIgnoresAHeldOutBlunder) { checkBlunderScores("median"); }

// Without a grid, compliance or score the text is the levels' line of before; with them, a table.
TEST(CalibrateSelection, TextTableWithTheChosenLine) {
  const std::string m = simulated("text.csv", kActual + " --measure position --noise-position 1e-5 --poses 20 --seed 2" + kSprings);
  const std::string cmd = "calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + kCv + " --noise-position 1e-5";
  const CliRun plain = runCli(cmd);
  EXPECT_NE(plain.out.find("parameter choice (5-fold cross-validation, 2 partitions;"), std::string::npos) << plain.out;
  const CliRun table = runCli(cmd + " --compliance 2,3 --prior-grid 1,10 --cv-score median");
  EXPECT_NE(table.out.find("held-out score median in noise units"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("  level    prior  compliance  parameters"), std::string::npos) << table.out;
  EXPECT_NE(table.out.find("\nchosen: "), std::string::npos) << table.out;
  // 3 levels x (none, 1, 10) x (off, on): 18 rows, one marked
  size_t rows = 0, marked = 0;
  for (size_t at = table.out.find("\n  full "); at != std::string::npos;) {
    const size_t end = table.out.find('\n', at + 1);
    const std::string line = table.out.substr(at + 1, end - at - 1);
    if (line.rfind("  full ", 0) != 0 && line.rfind("  lines ", 0) != 0 && line.rfind("  offsets ", 0) != 0) break;
    ++rows;
    marked += line.size() > 2 && line.compare(line.size() - 2, 2, " *") == 0 ? 1 : 0;
    at = end;
  }
  EXPECT_EQ(rows, 18u) << table.out;
  EXPECT_EQ(marked, 1u) << table.out;
}

TEST(CalibrateSelection, ArgumentErrors) {
  const std::string m = simulated("args.csv", kActual + " --measure position --noise-position 1e-5 --poses 20 --seed 2");
  const std::string cmd = "calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(m) + " --noise-position 1e-5 ";
  expectRejected(cmd + "--prior-grid 1,3", "--select", "--prior-grid: ");
  expectRejected(cmd + "--cv-score trimmed", "--select", "--cv-score: ");
  expectRejected(cmd + "--select cv --prior-grid 1,-3", "'-3' is not a positive finite width", "--prior-grid: ");
  expectRejected(cmd + "--select cv --prior-grid 1,1", "'1' given twice", "--prior-grid: ");
  expectRejected(cmd + "--select cv --prior-grid 1, --repeats 1", "no width", "--prior-grid: ");
  expectRejected(cmd + "--select cv --prior-grid 1 --prior 3", "not both", "--prior-grid: ");
  // the candidates multiply the fits: 3 x 11 x 2 candidates x 20 folds x 100 repeats is over the work limit
  expectRejected(cmd + "--select cv --folds 20 --repeats 100 --prior-grid 1,2,3,4,5,6,7,8,9,10 --compliance 2,3",
                 "66 candidates", "--repeats: ");
}
