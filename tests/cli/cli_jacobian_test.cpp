// `lowpair jacobian` and `lowpair singular`: JSON shape on the project's robot files, and rejection of
// bad input (exit status 2, one line "error: FILE: ..." on stderr, nothing on stdout).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "cli_runner.hpp"
#include <string>

namespace {

using namespace lowpair_test;

CliRun run(const std::string& args) { return runCli(args); }
std::string model(const std::string& name) { return modelPath(name); }

size_t countOf(const std::string& text, const std::string& what) {
  size_t count = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

// A robot file of n revolute joints with seeded random axes (file_formats.md, `poe:`), and "--q 0.1,...".
std::string randomRobotFile(int n, const std::string& name) {
  std::mt19937_64 rng(2024);
  std::normal_distribution<double> normal;
  std::ostringstream yaml;
  yaml.precision(17);
  yaml << "name: random-" << n << "\nlength_unit: m\npoe:\n  joints:\n";
  for (int i = 0; i < n; ++i) {
    const double w[3] = {normal(rng), normal(rng), normal(rng)}, p[3] = {normal(rng), normal(rng), normal(rng)};
    const double v[3] = {p[1] * w[2] - p[2] * w[1], p[2] * w[0] - p[0] * w[2], p[0] * w[1] - p[1] * w[0]};  // p x w
    yaml << "    - {type: revolute, twist: [" << w[0] << ", " << w[1] << ", " << w[2] << ", " << v[0] << ", " << v[1]
         << ", " << v[2] << "]}\n";
  }
  yaml << "  tool: [0, 0, 0, 0.5, 0.2, 0.1]\n";
  return writeScratchFile(name, yaml.str());
}

std::string constantQ(int n, double x) {
  std::string q = "--q ";
  for (int i = 0; i < n; ++i) q += (i ? "," : "") + std::to_string(x);
  return q;
}

}  // namespace

TEST(CliJacobian, SpatialIsDefaultAndShapeIsSixByN) {
  const CliRun r = run("jacobian " + model("elbow_mls.yaml") + " --q 0,0,0,0,0,0 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["name"], "elbow-mls");
  EXPECT_EQ(j["frame"], "spatial");
  EXPECT_EQ(j["q"].size(), 6u);
  ASSERT_EQ(j["jacobian"].size(), 6u);
  for (const auto& row : j["jacobian"]) EXPECT_EQ(row.size(), 6u);
  // at q = 0 the spatial columns are the zero-configuration twists [w; v]: joint 2 = [-1,0,0; 0,-1,0]
  const double expected[6] = {-1, 0, 0, 0, -1, 0};
  for (int r6 = 0; r6 < 6; ++r6) EXPECT_NEAR(j["jacobian"][r6][1].get<double>(), expected[r6], 1e-15);
}

TEST(CliJacobian, GeometricRowsAreLinearFirst) {
  const CliRun r = run("jacobian " + model("elbow_mls.yaml") + " --q 0,0,0,0,0,0 --frame geometric --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["frame"], "geometric");
  // joint 1 (z through the origin), tool at (0, 2, 1): v = z x (0, 2, 1) = (-2, 0, 0), w = z
  const double expected[6] = {-2, 0, 0, 0, 0, 1};
  for (int r6 = 0; r6 < 6; ++r6) EXPECT_NEAR(j["jacobian"][r6][0].get<double>(), expected[r6], 1e-15);
  const CliRun body = run("jacobian " + model("panda.yaml") + " --q 0,0,0,-1.5,0,1.5,0 --frame body --json");
  ASSERT_EQ(body.status, 0) << body.err;
  const auto jb = nlohmann::json::parse(body.out);
  EXPECT_EQ(jb["frame"], "body");
  for (const auto& row : jb["jacobian"]) EXPECT_EQ(row.size(), 7u);
}

TEST(CliJacobian, HumanReadableOutput) {
  const CliRun r = run("jacobian " + model("puma560_corke.yaml") + " --q 0,0,0,0,0,0");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("spatial Jacobian"), std::string::npos) << r.out;
  const CliRun s = run("singular " + model("puma560_corke.yaml") + " --q 0,0,0,0,0,0");
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_NE(s.out.find("SINGULAR"), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("C1: joint axes 4 and 6 are collinear"), std::string::npos) << s.out;
}

TEST(CliSingular, PumaWristJson) {
  const CliRun r = run("singular " + model("puma560_corke.yaml") + " --q 0.3,0.5,-0.4,0.7,0,0.2 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["name"], "puma560-corke");
  EXPECT_EQ(j["q"].size(), 6u);
  EXPECT_EQ(j["rank"], 5);
  EXPECT_EQ(j["dof"], 6);
  EXPECT_EQ(j["singular"], true);
  EXPECT_LT(j["sigma_min"].get<double>(), 1e-14);
  EXPECT_TRUE(j["manipulability"].is_number());
  // condition is sigma_max / sigma_min: null (infinite) exactly when sigma_min is 0
  EXPECT_EQ(j["condition"].is_null(), j["sigma_min"].get<double>() == 0.0);
  if (!j["condition"].is_null()) {
    EXPECT_GT(j["condition"].get<double>(), 1e14);
  }
  ASSERT_GE(j["classes"].size(), 1u);
  EXPECT_EQ(j["classes"][0]["class"], "C1");
  EXPECT_EQ(j["classes"][0]["joints"], nlohmann::json::array({4, 6}));
  EXPECT_EQ(j["classes"][0]["description"], "joint axes 4 and 6 are collinear");
  EXPECT_EQ(j["decoupled"]["applies"], true);
  EXPECT_EQ(j["decoupled"]["wrist_joints"], nlohmann::json::array({4, 5, 6}));
  EXPECT_EQ(j["decoupled"]["wrist_singular"], true);
  EXPECT_EQ(j["decoupled"]["arm_singular"], false);
}

TEST(CliSingular, RegularPoseHasNoClasses) {
  const CliRun r = run("singular " + model("stanford_corke.yaml") + " --q 0,0.7853981633974483,0.6,0,0.7853981633974483,0 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["singular"], false);
  EXPECT_EQ(j["rank"], 6);
  EXPECT_TRUE(j["classes"].empty());
  EXPECT_TRUE(j["null_space"].empty());
}

TEST(CliSingular, EveryClassIsWorded) {
  // the sentences the CLI builds from the classes' joints and geometry (conventions.md, "Singularities")
  const CliRun rhino = run("singular " + model("rhino_xr3_slide.yaml") + " --q 0,0,0,0,0,0");
  ASSERT_EQ(rhino.status, 0) << rhino.err;
  EXPECT_NE(rhino.out.find("\n  C2: joint axes 3, 4 and 5 are parallel and coplanar\n"), std::string::npos) << rhino.out;
  EXPECT_NE(rhino.out.find("\n  C7: prismatic joint 1 is normal to the plane of the parallel joint axes 2 and 6\n"),
            std::string::npos)
      << rhino.out;
  const CliRun other = run("singular " + model("stanford_corke.yaml") + " --q 0.3,0,0.6,0.4,0.5,0.2");
  ASSERT_EQ(other.status, 0) << other.err;
  EXPECT_NE(other.out.find("\n  other: the screws of joints 1, 2, 4, 5 and 6 are linearly dependent (no listed class)\n"),
            std::string::npos)
      << other.out;
  const CliRun c3 = run("singular " + model("stanford_corke.yaml") + " --q 0.3,0.5,0,0.4,0.6,0.2");
  ASSERT_EQ(c3.status, 0) << c3.err;
  EXPECT_NE(c3.out.find("\n  C3: joint axes 2, 4, 5 and 6 pass through one point (-0.0455101, 0.147122, 0.412)\n"),
            std::string::npos)
      << c3.out;
  const CliRun elbow = run("singular " + model("elbow_mls.yaml") + " --q 0,0,0,0,0,0");
  ASSERT_EQ(elbow.status, 0) << elbow.err;
  EXPECT_NE(elbow.out.find("\n  C5: joint axes 2, 3, 5 and 6 lie in one plane\n"), std::string::npos) << elbow.out;
  EXPECT_NE(elbow.out.find("\n  C6: all 6 joint axes meet the line through ("), std::string::npos) << elbow.out;
  const CliRun wrist = run("singular " + model("puma560_corke.yaml") + " --q 0,0,0,0,0,0");
  ASSERT_EQ(wrist.status, 0) << wrist.err;
  EXPECT_NE(wrist.out.find("\n  C6: all 6 joint axes meet one line at infinity: all are perpendicular to ("),
            std::string::npos)
      << wrist.out;
  // a short chain prints every null vector and says nothing about the class search
  EXPECT_EQ(wrist.out.find("not searched"), std::string::npos);
  EXPECT_EQ(wrist.out.find("not printed"), std::string::npos);
}

TEST(CliSingular, LongChainIsBounded) {
  // 3,000 joints: the class search is skipped (conventions.md limit, kClassSearchMaxJoints = 64) and at
  // most 6 of the 2,994 null vectors are printed, so the output grows like n, not n^2 (~85 MB before).
  const int n = 3000;
  const std::string file = randomRobotFile(n, "random3000.yaml");
  const std::string q = constantQ(n, 0.1);
  const CliRun text = run("singular " + file + " " + q);
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("random-3000: regular, rank 6 of 6 (3000 joints;"), std::string::npos)
      << text.out.substr(0, 500);
  EXPECT_NE(text.out.find("\n  classes: not searched (3000 joints; the class search takes at most 64)\n"),
            std::string::npos)
      << text.out.substr(0, 500);
  EXPECT_EQ(countOf(text.out, "self-motion (null vector)"), 6u);
  EXPECT_NE(text.out.find("\n  (2988 more null vectors not printed: the null space has dimension 2994)\n"),
            std::string::npos);
  EXPECT_LT(text.out.size(), 6u * n * 12 + 4000);  // 6 vectors of n numbers "-0.123456 "

  const CliRun json = run("singular " + file + " " + q + " --json");
  ASSERT_EQ(json.status, 0) << json.err;
  EXPECT_LT(json.out.size(), 6u * n * 40 + 200000);  // q, lines of 6 vectors of n doubles
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["dof"], n);
  EXPECT_EQ(j["rank"], 6);
  EXPECT_EQ(j["classes_searched"], false);
  EXPECT_TRUE(j["classes"].empty());
  EXPECT_EQ(j["nullity"], n - 6);
  ASSERT_EQ(j["null_space"].size(), 6u);
  for (const auto& x : j["null_space"]) EXPECT_EQ(x.size(), static_cast<size_t>(n));
}

TEST(CliSingular, ShortChainJsonCountsTheNullSpace) {
  const CliRun r = run("singular " + model("panda.yaml") + " --q 0.1,-0.3,0.2,-1.5,0.1,1.5,0.3 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["classes_searched"], true);
  EXPECT_EQ(j["nullity"], 1);
  EXPECT_EQ(j["null_space"].size(), 1u);
}

TEST(CliJacobian, RejectsBadJointVectors) {
  const std::string puma = model("puma560_corke.yaml");
  expectRejected("jacobian " + puma + " --q 0,0,0", "expected 6 joint values, got 3");
  expectRejected("singular " + puma + " --q 0,0,0,0,0,0,0", "expected 6 joint values, got 7");
  expectRejected("jacobian " + puma + " --q 0,0,x,0,0,0", "'x' is not a number");
  expectRejected("singular " + puma + " --q 0,0,nan,0,0,0", "not finite");
  expectRejected("jacobian " + puma + " --q 0,0,0,0,0,0 --frame world", "frame");
  expectRejected("singular " + model("no_such_robot.yaml") + " --q 0", "no_such_robot.yaml");
  const CliRun missing = run("jacobian " + puma);
  EXPECT_EQ(missing.status, 2);
}
