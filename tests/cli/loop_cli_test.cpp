// Planned, compensated, measured from files: `simulate --q-file` (exactly the given joint vectors: a random run
// replayed from its own q gives the same file; q read back bit for bit; the same tool as `fk --q-file`; bad files
// exit 2 with `error: FILE:LINE: what`), and the scenario cases' `plan:` (the poses `lowpair plan` chooses, a
// criterion above the first N samples') and `compensate:` (the shipped cases pass; noise-free to 1e-9 L).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
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
using nlohmann::json;

constexpr double kEps = std::numeric_limits<double>::epsilon();

const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");
const std::string kActualXml = modelPath("puma560_okamura_actual.xml");
const std::string kActualYaml = modelPath("puma560_okamura_actual.yaml");
const std::string kPumaMujoco = kActualXml + " --tip tool --joint-variables " + kActualYaml;
const std::string kStanfordMujoco = modelPath("stanford_corke_actual.xml") + " --tip tool";
const std::string kPumaScenario = std::string(LOWPAIR_SCENARIOS) + "/puma560_okamura_actual.yaml";
const std::string kStanfordScenario = std::string(LOWPAIR_SCENARIOS) + "/stanford_corke_actual.yaml";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// A measurement CSV as lines: comments apart, the header and the data rows as written.
struct CsvLines {
  std::vector<std::string> comments, rows;
  std::string header;
};

CsvLines csvLines(const std::string& text) {
  CsvLines csv;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      csv.comments.push_back(line);
    } else if (csv.header.empty()) {
      csv.header = line;
    } else {
      csv.rows.push_back(line);
    }
  }
  return csv;
}

// The numbers of a data row (a `target` column's name is skipped).
std::vector<double> numbers(const std::string& row) {
  std::vector<double> out;
  std::stringstream in(row);
  std::string field;
  while (std::getline(in, field, ',')) {
    char* end = nullptr;
    const double x = std::strtod(field.c_str(), &end);
    if (end != field.c_str()) out.push_back(x);
  }
  return out;
}

CliRun ok(const std::string& args) {
  CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r;
}

bool contains(const std::vector<std::string>& lines, const std::string& text) {
  return std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

// ---- simulate --q-file ---------------------------------------------------------------------------------------

// The q of a random run, written to a file and measured again with the same seed and noise, give the same file
// but for the comment that says where q came from: every joint value reads back bit for bit, and the noise of row
// k depends only on (seed, k). Robot file and MuJoCo; pose, position and targets; a measurement frame; blunders.
TEST(SimulateQFile, ReplaysARandomRunExactly) {
  struct Setup {
    std::string name, robot, options;
  };
  const std::vector<Setup> setups = {
      {"robot_file_pose", kNominal, "--noise-position 0.01 --noise-rotation 1e-5"},
      {"mujoco_pose_frame_blunders", kPumaMujoco,
       "--noise-position 0.01 --noise-rotation 1e-5 --frame 0.3,-1.2,2.0,3000,-800,400 --blunders 3,5"},
      {"mujoco_targets", kPumaMujoco, "--measure targets --targets smr_a,smr_c --noise-position 0.01 --blunders 4,5"},
      {"mujoco_position_prismatic", kStanfordMujoco, "--measure position --noise-position 1e-5"},
  };
  for (const Setup& s : setups) {
    // the joint vectors: a pose run's (one row per pose), whatever is then measured at them
    const std::string q_file = scratch() + "/replay_q_" + s.name + ".csv";
    ok("simulate " + s.robot + " --poses 25 --seed 9 --out " + q_file);
    const CsvLines random = csvLines(ok("simulate " + s.robot + " --poses 25 --seed 9 " + s.options).out);
    const CsvLines replay = csvLines(ok("simulate " + s.robot + " --q-file " + q_file + " --seed 9 " + s.options).out);
    ASSERT_FALSE(random.rows.empty()) << s.name;
    EXPECT_EQ(replay.header, random.header) << s.name;
    EXPECT_EQ(replay.rows, random.rows) << s.name << ": the same measurements, to the last digit";
    // the comments differ where they say where q came from (and in the command line), nowhere else
    ASSERT_EQ(replay.comments.size(), random.comments.size()) << s.name;
    int differ = 0;
    for (size_t k = 0; k < random.comments.size(); ++k) differ += replay.comments[k] != random.comments[k];
    EXPECT_EQ(differ, 2) << s.name;
    EXPECT_TRUE(contains(replay.comments, "the q1..q6 of the 25 rows of " + q_file)) << s.name;
    EXPECT_TRUE(contains(replay.comments, "--q-file " + q_file)) << s.name;
    EXPECT_FALSE(contains(replay.comments, "uniform in")) << s.name;
  }
}

// The q columns of the output are the file's numbers to the last bit (read as strtod reads them, whatever their
// spelling); other columns, comments, a byte order mark and CRLF line ends are taken as the measurement reader
// takes them; the tool is the one `fk --q-file` computes at the same q.
TEST(SimulateQFile, MeasuresExactlyTheGivenJointVectors) {
  const std::vector<std::string> rows = {"0.1,-0.2,0.30000000000000004,2.5e-1,-3.1415926535897931,1e-300",
                                         " 7 , -0.000123456789012345678 ,1E2, 0,-0.0,  6.283185307179586",
                                         "1.2345678901234567,2,3,4,5,6"};
  std::string text = "\xEF\xBB\xBF# joint vectors by hand\r\nq1,q2,q3,q4,q5,q6,x,y,z,note\r\n";
  for (const std::string& r : rows) text += "# a comment between rows\r\n" + r + ",1,2,3,anything\r\n";
  const std::string q_file = writeScratchFile("given_q.csv", text);
  const CsvLines out = csvLines(ok("simulate " + kNominal + " --q-file " + q_file).out);
  const CsvLines fk = csvLines(ok("fk " + kNominal + " --q-file " + q_file).out);
  ASSERT_EQ(out.rows.size(), rows.size());
  ASSERT_EQ(fk.rows.size(), rows.size());
  const double L = 255.73423705088842;  // the nominal's robot size (plan --json length_scale)
  for (size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double> given = numbers(rows[k]), measured = numbers(out.rows[k]), reference = numbers(fk.rows[k]);
    ASSERT_EQ(measured.size(), 13u);
    for (size_t i = 0; i < 6; ++i) {
      EXPECT_EQ(measured[i], given[i]) << "row " << k << " q" << i + 1;
      EXPECT_EQ(std::signbit(measured[i]), std::signbit(given[i])) << "row " << k << " q" << i + 1;
    }
    for (size_t i = 6; i < 9; ++i) EXPECT_NEAR(measured[i], reference[i], 64 * kEps * L) << "row " << k;
    for (size_t i = 9; i < 13; ++i) EXPECT_NEAR(measured[i], reference[i], 64 * kEps) << "row " << k;
  }
  // MuJoCo too: the same q, through the joint-variable map, measured as given
  const CsvLines mujoco = csvLines(ok("simulate " + kPumaMujoco + " --q-file " + q_file).out);
  ASSERT_EQ(mujoco.rows.size(), rows.size());
  for (size_t k = 0; k < rows.size(); ++k) {
    const std::vector<double> given = numbers(rows[k]), measured = numbers(mujoco.rows[k]);
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(measured[i], given[i]) << "row " << k;
  }
}

// A `lowpair plan --out` file is a q-file: simulate measures the planned joint vectors, in the file's order.
TEST(SimulateQFile, MeasuresAPlan) {
  const std::string q_file = scratch() + "/plan_q.csv";
  ok("plan " + kNominal + " --poses 8 --candidates 300 --out " + q_file);
  const CsvLines plan = csvLines(slurp(q_file));
  const CsvLines out = csvLines(ok("simulate " + kPumaMujoco + " --q-file " + q_file + " --noise-position 0.01").out);
  ASSERT_EQ(plan.rows.size(), 8u);
  ASSERT_EQ(out.rows.size(), 8u);
  for (size_t k = 0; k < plan.rows.size(); ++k) {
    const std::vector<double> q = numbers(plan.rows[k]), measured = numbers(out.rows[k]);
    ASSERT_EQ(q.size(), 6u);
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(measured[i], q[i]) << "row " << k;
  }
  EXPECT_TRUE(contains(out.comments, "8 pose measurements, seed 1"));
}

// Hostile or wrong q-files and options: exit 2, one line `error: FILE:LINE: what` (or the option), no output.
TEST(SimulateQFile, BadInputExitsTwoWithOneLine) {
  expectRejected("simulate " + kNominal, "--poses is required (or --q-file Q.csv", "simulate");
  const std::string good = writeScratchFile("good_q.csv", "q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0\n");
  expectRejected("simulate " + kNominal + " --poses 3 --q-file " + good, "excludes", "--");
  const std::string missing = scratch() + "/no_such_q.csv";
  expectRejected("simulate " + kNominal + " --q-file " + missing, "cannot open file", missing);
  expectRejected("simulate " + kNominal + " --q-file " + scratch(), "is a directory", scratch());
  auto bad = [](const std::string& name, const std::string& text, const std::string& what, int line) {
    const std::string path = writeScratchFile(name + ".csv", text);
    const std::string subject = line > 0 ? path + ":" + std::to_string(line) + ": " : path + ": ";
    expectRejected("simulate " + kNominal + " --q-file " + path, what, subject);
    expectRejected("simulate " + kPumaMujoco + " --q-file " + path, what, subject);
  };
  const std::string header = "# q\nq1,q2,q3,q4,q5,q6\n";
  bad("five_joints", "q1,q2,q3,q4,q5\n0,0,0,0,0\n", "has 5 joint columns but", 1);
  bad("seven_joints", "q1,q2,q3,q4,q5,q6,q7\n0,0,0,0,0,0,0\n", "has 7 joint columns but", 1);
  bad("no_joints", "x,y,z\n1,2,3\n", "no joint columns", 1);
  bad("word", header + "0,0,abc,0,0,0\n", "'abc' is not a number", 3);
  bad("hex", header + "0,0,0x1p-3,0,0,0\n", "is not a decimal number", 3);
  bad("inf", header + "0,0,0,inf,0,0\n", "is not a finite number", 3);
  bad("nan", header + "0,0,0,0,nan,0\n", "is not a finite number", 3);
  bad("overflow", header + "1e999,0,0,0,0,0\n", "is not a finite number", 3);
  bad("huge", header + "0,0,0,0,0,1e101\n", "above 1e100", 3);
  bad("empty_field", header + "0,0,,0,0,0\n", "is not a number", 3);
  bad("short_row", header + "0,0,0,0,0,0\n0,0,0\n", "expected 6 fields, got 3", 4);
  bad("long_line", header + std::string(70000, '0') + "\n", "line longer than 65536 bytes", 3);
  bad("no_rows", header + "# nothing\n", "no rows", 0);
  bad("no_header", "# only comments\n\n", "no header line", 0);
  // more rows x targets than a measurement file holds
  std::string many = "q1,q2,q3,q4,q5,q6\n";
  for (int k = 0; k < 400000; ++k) many += "0,0,0,0,0,0\n";
  const std::string path = writeScratchFile("many_q.csv", many);
  expectRejected("simulate " + kPumaMujoco + " --q-file " + path + " --measure targets --targets smr_a,smr_b,smr_c",
                 "more than the 1000000 a measurement file holds", path);
}

// ---- scenario cases: plan: and compensate: -------------------------------------------------------------------

std::map<std::string, json> casesByName(const json& doc) {
  std::map<std::string, json> cases;
  for (const auto& s : doc["scenarios"]) {
    for (const auto& c : s["calibrations"]) cases[s["name"].get<std::string>() + "/" + c["name"].get<std::string>()] = c;
  }
  return cases;
}

const json& shippedCases() {
  static const json doc = [] {
    const CliRun r = runCli("validate " + kPumaScenario + " " + kStanfordScenario + " --samples 100 --json");
    EXPECT_EQ(r.status, 0) << r.err << r.out.substr(0, 3000);
    return r.status == 0 ? json::parse(r.out) : json();
  }();
  return doc;
}

// Every shipped case passes, and the compensation numbers are consistent: statuses count every row, the rows not
// ok are listed with a reason and not commanded, compensation removes the nominal's error down to the model's.
TEST(LoopScenario, ShippedCasesPass) {
  const json& doc = shippedCases();
  ASSERT_TRUE(doc.contains("pass"));
  EXPECT_TRUE(doc["pass"].get<bool>());
  const auto cases = casesByName(doc);
  const std::vector<std::string> compensated = {"puma560-okamura-actual/noise-free", "puma560-okamura-actual/noisy",
                                                "puma560-okamura-actual/planned-15", "stanford-corke-actual/noisy",
                                                "stanford-corke-actual/tracker-frame"};
  for (const std::string& name : compensated) {
    ASSERT_TRUE(cases.count(name)) << name;
    const json& c = cases.at(name);
    EXPECT_TRUE(c["pass"].get<bool>()) << name << ": " << c["failures"].dump();
    ASSERT_TRUE(c.contains("compensation")) << name;
    const json& k = c["compensation"];
    int rows = 0, not_ok = 0;
    for (const auto& [status, count] : k["statuses"].items()) {
      rows += count.get<int>();
      if (status != "ok") not_ok += count.get<int>();
    }
    EXPECT_EQ(rows, 200) << name;
    EXPECT_EQ(k["before"]["count"].get<int>(), 200) << name;
    EXPECT_EQ(k["after"]["count"].get<int>(), 200 - not_ok) << name << ": only the ok rows are commanded";
    EXPECT_EQ(static_cast<int>(k["not_ok"].size()), not_ok) << name;
    EXPECT_LE(not_ok, k["allowed_not_ok"].get<int>()) << name;
    for (const auto& row : k["not_ok"]) {
      EXPECT_NE(row["status"].get<std::string>(), "ok");
      EXPECT_FALSE(row["reason"].get<std::string>().empty());
    }
    EXPECT_LE(k["after"]["rms_position"].get<double>(), k["tolerance"].get<double>()) << name;
    EXPECT_LT(k["after"]["rms_position"].get<double>(), k["before"]["rms_position"].get<double>() / 100) << name;
    // within 2x the case's validation RMS (the calibrated model's error is what is left)
    EXPECT_LE(k["after"]["rms_position"].get<double>(), 2 * c["acceptance"]["validation_rms_position_after"].get<double>() +
                                                            1e-9 * k["length_scale"].get<double>())
        << name;
    EXPECT_EQ(k["measure"].get<std::string>(), "pose") << name;
    EXPECT_LT(k["after"]["rms_rotation"].get<double>(), k["before"]["rms_rotation"].get<double>()) << name;
  }
  // cases without compensate: have no compensation, those without plan: no plan
  EXPECT_FALSE(cases.at("puma560-okamura-actual/tracker").contains("compensation"));
  EXPECT_FALSE(cases.at("puma560-okamura-actual/noisy").contains("plan"));
}

// The noise-free PUMA: the compensated tool is where the nominal puts it to 1e-9 L (position) and 1e-9 rad, from
// 35 mm and 0.3 rad RMS before.
TEST(LoopScenario, NoiseFreeCompensationReachesOneBillionthOfL) {
  const auto cases = casesByName(shippedCases());
  ASSERT_TRUE(cases.count("puma560-okamura-actual/noise-free"));
  const json& k = cases.at("puma560-okamura-actual/noise-free")["compensation"];
  const double L = k["length_scale"].get<double>();
  // the nominal's robot size, as `plan --json` reports it for the nominal's file (the actual's is 0.7 smaller)
  const CliRun plan = runCli("plan " + kNominal + " --poses 3 --candidates 10 --json");
  ASSERT_EQ(plan.status, 0) << plan.err;
  EXPECT_EQ(L, json::parse(plan.out)["length_scale"].get<double>());
  EXPECT_GT(k["before"]["rms_position"].get<double>(), 0.1 * L);
  EXPECT_LE(k["after"]["rms_position"].get<double>(), 1e-9 * L);
  EXPECT_LE(k["after"]["max_position"].get<double>(), 1e-9 * L);
  EXPECT_LE(k["after"]["max_rotation"].get<double>(), 1e-9);
  EXPECT_GE(k["after"]["count"].get<int>(), 190);
}

// The planned case fits the poses `lowpair plan` chooses from the same candidates (samples 0..M-1 of the case's
// stream), not the first N samples, and their information is larger than the first N samples'.
TEST(LoopScenario, PlanPicksWhatLowpairPlanPicksAndBeatsTheFirstSamples) {
  const auto cases = casesByName(shippedCases());
  ASSERT_TRUE(cases.count("puma560-okamura-actual/planned-15"));
  const json& p = cases.at("puma560-okamura-actual/planned-15")["plan"];
  const std::vector<int> samples = p["samples"].get<std::vector<int>>();
  ASSERT_EQ(samples.size(), 15u);
  std::vector<int> first(15);
  for (int k = 0; k < 15; ++k) first[static_cast<size_t>(k)] = k;
  EXPECT_NE(samples, first);
  EXPECT_TRUE(std::is_sorted(samples.begin(), samples.end()));
  EXPECT_EQ(std::adjacent_find(samples.begin(), samples.end()), samples.end());
  EXPECT_LT(samples.back(), 2000);
  EXPECT_GE(p["planned"]["log_det"].get<double>(), p["first_samples"]["log_det"].get<double>());
  EXPECT_GE(p["planned"]["O1"].get<double>(), p["first_samples"]["O1"].get<double>());
  EXPECT_GE(p["planned"]["log_det"].get<double>(), p["greedy"]["log_det"].get<double>());
  EXPECT_EQ(p["rank"].get<int>(), p["expected"].get<int>());
  const json plan = json::parse(
      ok("plan " + kNominal + " --poses 15 --candidates 2000 --free-pitch --seed 1 --json").out);
  EXPECT_EQ(plan["indices"].get<std::vector<int>>(), samples);
  EXPECT_EQ(plan["planned"]["log_det"].get<double>(), p["planned"]["log_det"].get<double>());
}

// plan: D (the shorthand: 5000 candidates) and plan: {criterion: O1}: the criterion is only the number reported,
// both choose the same poses.
TEST(LoopScenario, PlanShorthandAndCriterion) {
  const std::string head = "model: " + kActualXml + "\ntip: tool\njoint_variables: " + kActualYaml +
                           "\nsamples: 1\ncalibration:\n";
  auto kase = [](const std::string& name, const std::string& plan) {
    return "  - name: " + name + "\n    nominal: " + kNominal +
           "\n    poses: 12\n    validation_poses: 20\n    seed: 4\n    free_pitch: true\n"
           "    noise: {position: 0.01, rotation: 1.0e-5}\n"
           "    tolerance: {position: 1}\n    plan: " + plan + "\n";
  };
  const std::string path = writeScratchFile("plan_shorthand.yaml", head + kase("d", "D") + kase("o1", "{criterion: O1, candidates: 5000}"));
  const CliRun r = ok("validate " + path + " --json");
  const auto cases = casesByName(json::parse(r.out));
  ASSERT_EQ(cases.size(), 2u);
  const json& d = cases.begin()->second["plan"];
  const json& o1 = std::next(cases.begin())->second["plan"];
  EXPECT_EQ(d["criterion"].get<std::string>(), "D");
  EXPECT_EQ(o1["criterion"].get<std::string>(), "O1");
  EXPECT_EQ(d["candidates"].get<int>(), 5000);
  EXPECT_EQ(d["samples"], o1["samples"]);
}

// The new keys are checked like the others: exit 2, one line naming the scenario file and the key.
TEST(LoopScenario, BadKeysExitTwoWithOneLine) {
  const std::string head = "model: " + kActualXml + "\ntip: tool\njoint_variables: " + kActualYaml +
                           "\nsamples: 10\ncalibration:\n  - name: c\n    nominal: " + kNominal +
                           "\n    tolerance: {position: 0.01}\n    poses: 10\n    validation_poses: 20\n";
  auto bad = [&](const std::string& name, const std::string& lines, const std::string& what) {
    const std::string path = writeScratchFile("loop_" + name + ".yaml", head + lines);
    expectRejected("validate " + path, what, path);
  };
  bad("criterion", "    plan: {criterion: A}\n", "plan.criterion must be D or O1, got 'A'");
  bad("shorthand", "    plan: E\n", "plan must be D or O1, got 'E'");
  bad("few_candidates", "    plan: {candidates: 9}\n", "plan.candidates 9 is below poses 10");
  bad("zero_candidates", "    plan: {candidates: 0}\n", "plan.candidates must be a whole number in [1, 100000]");
  bad("many_candidates", "    plan: {candidates: 100001}\n", "plan.candidates must be a whole number in [1, 100000]");
  bad("fraction", "    plan: {candidates: 20.5}\n", "plan.candidates must be a whole number");
  bad("plan_key", "    plan: {criteria: D}\n", "unknown key 'criteria'");
  bad("plan_list", "    plan: [D]\n", "plan must be a mapping");
  bad("no_tolerance", "    compensate: {allowed_not_ok: 1}\n", "compensate: missing 'tolerance'");
  bad("zero_tolerance", "    compensate: {tolerance: 0}\n", "compensate.tolerance must be positive");
  bad("nan_tolerance", "    compensate: {tolerance: .nan}\n", "compensate.tolerance is not finite");
  bad("word_tolerance", "    compensate: {tolerance: small}\n", "compensate.tolerance must be a number");
  bad("allowed", "    compensate: {tolerance: 1, allowed_not_ok: 21}\n", "allowed_not_ok must be a whole number in [0, 20]");
  bad("negative", "    compensate: {tolerance: 1, allowed_not_ok: -1}\n", "allowed_not_ok must be a whole number in [0, 20]");
  bad("compensate_key", "    compensate: {tolerance: 1, rows: 3}\n", "unknown key 'rows'");
  bad("compensate_scalar", "    compensate: 1\n", "compensate must be a mapping");
  // a plan of target measurements needs the targets' points in the nominal (the plan is made on it)
  bad("plan_targets", "    targets: [smr_a]\n    plan: {candidates: 100}\n", "plan: with targets the nominal");
  // the candidates' blocks are bounded as lowpair plan bounds them
  bad("plan_entries", "    plan: {candidates: 40000}\n", "exceed the identification size limit (1e+07 numbers");
}

}  // namespace
