// lowpair plan (docs/plan.md): the report, the --out joint-vector CSV, the JSON fields, rank-deficient and
// position-only plans, targets, and bad input (exit 2, one line).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"

using lowpair_test::expectRejected;
using lowpair_test::modelPath;
using lowpair_test::runCli;
using lowpair_test::scratch;
using lowpair_test::writeScratchFile;
using nlohmann::json;

namespace {

const std::string kPuma = modelPath("puma560_okamura_nominal.yaml");

// The data lines of a --out CSV (after `#` comments and the header), each split at commas.
struct QFile {
  std::vector<std::string> comments;
  std::string header;
  std::vector<std::vector<double>> rows;
};

QFile readQFile(const std::string& path) {
  std::ifstream in(path);
  QFile f;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("#", 0) == 0) {
      f.comments.push_back(line);
      continue;
    }
    if (f.header.empty()) {
      f.header = line;
      continue;
    }
    std::vector<double> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(std::stod(cell));
    f.rows.push_back(row);
  }
  return f;
}

json planJson(const std::string& args) {
  const lowpair_test::CliRun r = runCli("plan " + args + " --json");
  EXPECT_EQ(r.status, 0) << r.err;
  return json::parse(r.out);
}

}  // namespace

TEST(PlanCli, PrintsThePlanAndWritesTheJointVectors) {
  const std::string out = scratch() + "/planned.csv";
  const lowpair_test::CliRun r = runCli("plan " + kPuma + " --poses 12 --candidates 500 --seed 3 --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  for (const std::string& expected : std::vector<std::string>{
           "plan of 12 poses (pose measurements) of puma560-okamura-nominal", "from 500 random candidates (seed 3)",
           "criterion D", "planned", "random sets of 12, median (100)", "random sets, best", "rank 36 of 36",
           "every parameter is determined", "expected standard deviations", "default: 1e-5 L and 1e-5 rad",
           "D-H table of the nominal", "planned poses", "12 joint vectors written to " + out}) {
    EXPECT_NE(r.out.find(expected), std::string::npos) << "missing '" << expected << "' in:\n" << r.out;
  }
  const QFile f = readQFile(out);
  EXPECT_EQ(f.header, "q1,q2,q3,q4,q5,q6");
  ASSERT_EQ(f.rows.size(), 12u);
  for (const auto& row : f.rows) EXPECT_EQ(row.size(), 6u);
  ASSERT_GE(f.comments.size(), 2u);
  EXPECT_NE(f.comments[0].find("lowpair plan"), std::string::npos);
  EXPECT_NE(f.comments[0].find("seed 3"), std::string::npos);
  EXPECT_NE(f.comments[1].find("puma560-okamura-nominal"), std::string::npos);
  bool criterion = false;
  for (const auto& c : f.comments) criterion |= c.find("criterion D") != std::string::npos;
  EXPECT_TRUE(criterion);

  // the file holds the JSON's joint vectors digit for digit (17 significant digits read back exactly)
  const json j = planJson(kPuma + " --poses 12 --candidates 500 --seed 3");
  ASSERT_EQ(j["q"].size(), 12u);
  for (size_t k = 0; k < 12; ++k) {
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(f.rows[k][i], j["q"][k][i].get<double>()) << k << " " << i;
  }
}

TEST(PlanCli, JsonFields) {
  const json j = planJson(kPuma + " --poses 15 --candidates 800");
  for (const char* key : {"name", "source", "length_unit", "measure", "free_pitch", "criterion", "poses", "candidates",
                          "seed", "length_scale", "planned", "greedy", "swaps", "passes", "random", "expected", "joints",
                          "rank", "candidate_rank", "parameters", "singular_values", "condition", "undetermined",
                          "indices", "q", "noise", "standard_deviations", "out", "seconds"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["name"], "puma560-okamura-nominal");
  EXPECT_EQ(j["measure"], "pose");
  EXPECT_EQ(j["criterion"], "D");
  EXPECT_EQ(j["poses"], 15);
  EXPECT_EQ(j["candidates"], 800);
  EXPECT_EQ(j["seed"], 1);
  EXPECT_EQ(j["rank"], 36);
  EXPECT_EQ(j["expected"], 36);
  EXPECT_EQ(j["candidate_rank"], 36);
  EXPECT_EQ(j["parameters"].size(), 36u);
  EXPECT_TRUE(j["undetermined"].empty());
  EXPECT_TRUE(j["out"].is_null());
  // the plan beats the best random set; the exchange did not lower the greedy set's value
  const double planned = j["planned"]["log_det"], best = j["random"]["log_det"]["best"];
  EXPECT_GE(planned, best);
  EXPECT_GE(planned, j["greedy"]["log_det"].get<double>());
  EXPECT_GE(j["planned"]["O1"].get<double>(), j["random"]["O1"]["best"].get<double>());
  EXPECT_EQ(j["planned"]["criterion"], j["planned"]["log_det"]);
  EXPECT_EQ(j["random"]["sets"], 100);
  // indices increasing, in range; q one joint vector per index
  ASSERT_EQ(j["indices"].size(), 15u);
  for (size_t k = 1; k < 15; ++k) EXPECT_LT(j["indices"][k - 1].get<int>(), j["indices"][k].get<int>());
  EXPECT_LT(j["indices"][14].get<int>(), 800);
  ASSERT_EQ(j["q"].size(), 15u);
  // the default noise: 1e-5 L and 1e-5 rad
  const double L = j["length_scale"];
  EXPECT_NEAR(j["noise"]["position"].get<double>(), 1e-5 * L, 1e-18 * L);
  EXPECT_EQ(j["noise"]["rotation"], 1e-5);
  // a standard deviation for every parameter and D-H number (finite: every parameter is determined)
  ASSERT_EQ(j["standard_deviations"]["parameters"].size(), 36u);
  for (const auto& p : j["standard_deviations"]["parameters"]) EXPECT_TRUE(p["sd"].is_number()) << p;
  const json& dh = j["standard_deviations"]["dh"];
  ASSERT_EQ(dh["joints"].size(), 6u);
  for (const auto& row : dh["joints"]) {
    for (const char* k : {"theta", "d", "alpha", "a", "scale"}) EXPECT_TRUE(row["sd"].contains(k)) << k;
  }
  EXPECT_TRUE(dh["tool"]["sd"].contains("d"));

  // the noise scales the standard deviations; the criterion changes the number reported, not the plan
  const json once = planJson(kPuma + " --poses 15 --candidates 800 --noise-position 0.005 --noise-rotation 1e-5");
  const json twice = planJson(kPuma + " --poses 15 --candidates 800 --noise-position 0.01 --noise-rotation 2e-5");
  EXPECT_EQ(twice["indices"], j["indices"]);
  EXPECT_EQ(twice["noise"]["source"], "stated");
  for (size_t k = 0; k < 36; ++k) {
    const double sd1 = once["standard_deviations"]["parameters"][k]["sd"];
    const double sd2 = twice["standard_deviations"]["parameters"][k]["sd"];
    EXPECT_NEAR(sd2, 2.0 * sd1, 1e-9 * sd1) << k;
  }
  const json o1 = planJson(kPuma + " --poses 15 --candidates 800 --criterion O1");
  EXPECT_EQ(o1["indices"], j["indices"]);
  EXPECT_EQ(o1["criterion"], "O1");
  EXPECT_EQ(o1["planned"]["criterion"], o1["planned"]["O1"]);
}

TEST(PlanCli, TooFewPosesNameTheUndeterminedDirections) {
  const json j = planJson(kPuma + " --poses 3 --candidates 300");
  EXPECT_EQ(j["rank"], 18);
  EXPECT_EQ(j["undetermined"].size(), 18u);
  EXPECT_TRUE(j["planned"]["log_det"].is_null());
  EXPECT_EQ(j["planned"]["O1"], 0.0);
  EXPECT_TRUE(j["condition"].is_null());
  const lowpair_test::CliRun r = runCli("plan " + kPuma + " --poses 3 --candidates 300");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("rank 18 of 36"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("18 direction(s) not determined (18 for want of poses"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("undetermined"), std::string::npos) << r.out;  // D-H numbers without a standard deviation
}

// Position measurements of the nominal PUMA, whose tool point is the wrist centre: no pose sees the wrist
// turn (rank 24 of 33 whatever the plan, docs/calibration.md); the plan says which directions no candidate
// determines.
TEST(PlanCli, PositionOnlyPumaCannotReachTheCount) {
  const json j = planJson(kPuma + " --poses 20 --candidates 500 --measure position");
  EXPECT_EQ(j["expected"], 33);
  EXPECT_EQ(j["rank"], 24);
  EXPECT_EQ(j["candidate_rank"], 24);
  EXPECT_TRUE(j["planned"]["log_det"].is_number());  // over the directions the candidates determine
  EXPECT_TRUE(j["noise"]["rotation"].is_null());
  const lowpair_test::CliRun r = runCli("plan " + kPuma + " --poses 20 --candidates 500 --measure position");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("that no candidate determines"), std::string::npos) << r.out;
}

TEST(PlanCli, TargetsFromTheRobotFile) {
  std::ifstream in(kPuma);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text += "targets:\n  - {name: smr_a, point: [60, 0, 20]}\n  - {name: smr_b, point: [-30, 52, 20]}\n";
  const std::string robot = writeScratchFile("puma_targets.yaml", text);
  const json j = planJson(robot + " --poses 10 --candidates 400 --measure targets");
  EXPECT_EQ(j["measure"], "targets");
  EXPECT_EQ(j["expected"], 4 * 6 + 6 + 3 * 2);
  EXPECT_EQ(j["rank"], j["expected"]);
  ASSERT_EQ(j["targets"].size(), 2u);
  EXPECT_EQ(j["targets"][0]["name"], "smr_a");
  EXPECT_GE(j["planned"]["log_det"].get<double>(), j["random"]["log_det"]["best"].get<double>());
}

TEST(PlanCli, BadArgumentsExitTwoWithOneLine) {
  const std::string p = "plan " + kPuma;
  expectRejected(p + " --poses 0", "--poses");
  expectRejected(p + " --poses 1001", "--poses");
  expectRejected(p, "--poses");  // required
  expectRejected(p + " --poses 5 --candidates 0", "--candidates");
  expectRejected(p + " --poses 5 --candidates 100001", "--candidates");
  expectRejected(p + " --poses 20 --candidates 10", "cannot be chosen from 10 candidates", "--poses");
  expectRejected(p + " --poses 5 --candidates 50000", "exceed the identification size limit", "--candidates");
  expectRejected(p + " --poses 5 --criterion A", "--criterion");
  expectRejected(p + " --poses 5 --measure joints", "--measure");
  expectRejected(p + " --poses 5 --seed -1", "--seed");
  expectRejected(p + " --poses 5 --noise-position 0", "must be a positive number", "--noise-position");
  expectRejected(p + " --poses 5 --noise-rotation 4", "must be a positive number", "--noise-rotation");
  expectRejected(p + " --poses 5 --measure position --noise-rotation 1e-5", "no rotation", "--noise-rotation");
  expectRejected(p + " --poses 5 --measure targets", "targets:", kPuma);
  expectRejected("plan " + modelPath("no_such_robot.yaml") + " --poses 5", "no_such_robot.yaml");
  // an --out that cannot be written: exit 2, nothing written
  const std::string missing = scratch() + "/no/such/dir/q.csv";
  expectRejected(p + " --poses 5 --candidates 50 --out " + missing, "cannot write");
  EXPECT_FALSE(std::ifstream(missing).good());
}
