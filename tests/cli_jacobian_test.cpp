// `lowpair jacobian` and `lowpair singular`: JSON shape on the project's robot files, and rejection of
// bad input (exit status 2, one line "error: FILE: ..." on stderr, nothing on stdout).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include <string>

namespace {

using namespace lowpair_test;

CliRun run(const std::string& args) { return runCli(args); }
std::string model(const std::string& name) { return modelPath(name); }

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
