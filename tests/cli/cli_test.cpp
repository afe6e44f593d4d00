// The lowpair command line: outputs on the project's robot files and rejection of bad input
// (exit status 2, one line "error: FILE: ..." on stderr).
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

std::string model(const std::string& name) { return modelPath(name); }
std::string writeFile(const std::string& name, const std::string& text) { return writeScratchFile(name, text); }
CliRun run(const std::string& args) { return runCli(args); }

const char* kGoodPoe = R"(name: tiny
length_unit: m
poe:
  joints:
    - {type: revolute, twist: [0, 0, 1, 0, 0, 0]}
    - {twist: [0, -1, 0, 0, 0, -1]}
  tool: [0, 0, 0, 1, 0, 0]
)";

}  // namespace

TEST(CliPoe2dh, PumaActualJsonReproducesTableII) {
  const CliRun r = run("poe2dh " + model("puma560_okamura_actual.yaml") + " --json --standard");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const double deg = M_PI / 180;
  EXPECT_EQ(j["length_unit"], "mm");
  EXPECT_NEAR(j["base"]["theta"].get<double>() / deg, 63.4349, 0.5e-4);
  EXPECT_NEAR(j["base"]["d"].get<double>(), 1.0000, 0.5e-4);
  EXPECT_NEAR(j["joints"][1]["d"].get<double>(), -567.6554, 0.5e-4);
  EXPECT_NEAR(j["joints"][2]["a"].get<double>(), 153.3035, 0.5e-4);
  EXPECT_NEAR(j["joints"][5]["alpha"].get<double>() / deg, 175.0748, 0.5e-4);
  EXPECT_NEAR(j["joints"][5]["a"].get<double>(), -0.7202, 0.5e-4);
  EXPECT_EQ(j["joints"][5]["type"], "helical");
  EXPECT_NEAR(j["joints"][5]["pitch"].get<double>() * deg, 0.0502, 0.5e-4);  // mm/rad -> mm/deg
  EXPECT_NEAR(j["joints"][0]["scale"].get<double>(), 1.0000005, 0.5e-7);
  EXPECT_FALSE(j["joints"][0].contains("pitch"));
  EXPECT_NEAR(j["tool"]["theta"].get<double>() / deg, 83.1872, 0.5e-4);
  EXPECT_NEAR(j["tool"]["d"].get<double>(), -35.4328, 0.5e-4);
  EXPECT_GT(j["size"].get<double>(), 250.0);
}

TEST(CliPoe2dh, NominalTableHasExactZeros) {
  const CliRun r = run("poe2dh " + model("puma560_okamura_nominal.yaml") + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["base"]["theta"].get<double>(), 0.0);
  EXPECT_EQ(j["joints"][0]["theta"].get<double>(), 0.0);
  EXPECT_EQ(j["joints"][1]["theta"].get<double>(), 0.0);
  EXPECT_EQ(j["joints"][1]["a"].get<double>(), 100.0);
}

TEST(CliPoe2dh, HumanAndModifiedTables) {
  const CliRun human = run("poe2dh " + model("puma560_okamura_actual.yaml") + " --standard");
  ASSERT_EQ(human.status, 0) << human.err;
  EXPECT_NE(human.out.find("-567.6554"), std::string::npos) << human.out;
  EXPECT_NE(human.out.find("theta(deg)"), std::string::npos);
  const CliRun mod = run("poe2dh " + model("puma560_okamura_actual.yaml") + " --modified --json --standard");
  ASSERT_EQ(mod.status, 0) << mod.err;
  const auto j = nlohmann::json::parse(mod.out);
  EXPECT_EQ(j["convention"], "modified");
  EXPECT_TRUE(j["tool"].contains("alpha"));
  EXPECT_EQ(j["joints"].size(), 6u);
}

TEST(CliEveryModel, ConvertsAndRoundTrips) {
  for (const char* name : {"puma560_okamura_nominal.yaml", "puma560_okamura_actual.yaml", "puma560_corke.yaml",
                           "puma560_corke_poe.yaml", "stanford_corke.yaml", "rhino_xr3_slide.yaml", "elbow_mls.yaml",
                           "panda.yaml"}) {
    const CliRun r = run("poe2dh " + model(name) + " --json");
    ASSERT_EQ(r.status, 0) << name << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_LE(j["fk_check"]["max_rotation"].get<double>(), 1e-12) << name;
    EXPECT_LE(j["fk_check"]["max_translation"].get<double>(), 1e-12 * j["fk_check"]["scale"].get<double>()) << name;
    EXPECT_EQ(run("dh2poe " + model(name) + " --json").status, 0) << name;
  }
}

TEST(CliPoe2dh, ConditioningWarningsAreWordedFromTheData) {
  // joint 2's axis 1e-7 rad from joint 1's and the tool z 1e-9 rad from joint 2's: rows 1 and 2 and the
  // tool get |d| ~ |p| / angle (the D-H singularity of Wu et al. §V)
  const std::string f = writeFile("nearly_parallel.yaml", R"(name: nearly-parallel
length_unit: m
poe:
  joints:
    - {name: waist, twist: [0, 0, 1, 0, 0, 0]}
    - {name: elbow, twist: [9.999999999999982e-08, 0, 0.999999999999995, 0.399999999999998, -0.2999999999999985, -3.9999999999999935e-08]}
  tool_pose: [[1.0, 0, 1e-09, 0.5], [0, 1, 0, 0.1], [-1e-09, 0, 1.0, 0.2], [0, 0, 0, 1]]
)");
  const CliRun r = run("poe2dh " + f + " --standard");  // the standard table: the Hayati rows have no such d
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string expected[3] = {
      "warning: row of joint 1 (waist): |d| = 3e+06, |a| = 0.4 exceed 1e+03 L (L = 0.548); the line before and "
      "after this row meet at 1e-07 rad: nearly parallel axes make the D-H table ill-conditioned (Wu et al. §V)\n",
      "warning: row of joint 2 (elbow): |d| = 5.02e+06, |a| = 0.3 exceed 1e+03 L (L = 0.548); the line before and "
      "after this row meet at 9.9e-08 rad: nearly parallel axes make the D-H table ill-conditioned (Wu et al. §V)\n",
      "warning: tool: |d_T| = 2.02e+06 exceeds 1e+03 L: the last joint axis is nearly parallel to the tool z axis\n"};
  for (const std::string& w : expected) EXPECT_NE(r.out.find(w), std::string::npos) << w << "\nnot in\n" << r.out;
  EXPECT_NE(r.out.find("FK check: POE vs D-H over 65 configurations"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(run("poe2dh " + f + " --json --standard").out);
  ASSERT_EQ(j["warnings"].size(), 3u);
  EXPECT_EQ("warning: " + j["warnings"][2].get<std::string>() + "\n", expected[2]);
  EXPECT_EQ(j["conditioning"][1]["ill_conditioned"], true);
  EXPECT_EQ(j["conditioning"][0]["ill_conditioned"], false);

  // a threshold above rounding level snaps the axes and says by how much FK moved
  const CliRun snapped = run("poe2dh " + f + " --parallel-threshold 1e-6");
  ASSERT_EQ(snapped.status, 0) << snapped.err;
  EXPECT_NE(snapped.out.find("warning: parallel threshold 1e-06 is above rounding level (7.11e-15): nearly parallel "
                             "axes were snapped; FK deviation "),
            std::string::npos)
      << snapped.out;
  EXPECT_NE(snapped.out.find(" rad over 65 configurations\n"), std::string::npos) << snapped.out;
  // a well-conditioned robot gets no warning
  const CliRun puma = run("poe2dh " + model("puma560_okamura_nominal.yaml"));
  ASSERT_EQ(puma.status, 0) << puma.err;
  EXPECT_EQ(puma.out.find("warning:"), std::string::npos) << puma.out;
}

TEST(CliFk, PoeAndDhAgree) {
  const std::string q = "--q 0.1,-0.2,0.3,-0.4,0.5,-0.6";
  const CliRun a = run("fk " + model("puma560_corke.yaml") + " " + q + " --json --model dh");
  const CliRun b = run("fk " + model("puma560_corke_poe.yaml") + " " + q + " --json --model poe");
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  const auto ja = nlohmann::json::parse(a.out)["T_base_tool"], jb = nlohmann::json::parse(b.out)["T_base_tool"];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(ja[r][c].get<double>(), jb[r][c].get<double>(), 1e-14);
}

TEST(CliErrors, MissingFile) { expectRejected("poe2dh /nonexistent/robot.yaml", "cannot open", "/nonexistent/robot.yaml"); }

TEST(CliErrors, YamlSyntaxWithLine) {
  const std::string f = writeFile("syntax.yaml", "name: x\npoe:\n  joints: [\n    {twist: [0, 0, 1\n");
  expectRejected("poe2dh " + f, "line ", f);
}

TEST(CliErrors, UnknownKey) {
  const std::string f = writeFile("unknown.yaml", std::string(kGoodPoe) + "colour: red\n");
  expectRejected("poe2dh " + f, "unknown key 'colour'", f);
  const std::string g = writeFile("unknown_joint.yaml",
                                  "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0], ofset: 1}\n");
  expectRejected("poe2dh " + g, "unknown key 'ofset'", g);
}

TEST(CliErrors, WrongVectorLength) {
  const std::string f = writeFile("length.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0]}\n");
  expectRejected("poe2dh " + f, "must have 6 entries, got 5", f);
}

TEST(CliErrors, NonFiniteNumber) {
  const std::string f = writeFile("nan.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 1, .nan, 0, 0]}\n");
  expectRejected("poe2dh " + f, "not finite", f);
  const std::string g = writeFile("word.yaml", "poe:\n  joints:\n    - {twist: [0, 0, one, 0, 0, 0]}\n");
  expectRejected("poe2dh " + g, "must be a number", g);
}

TEST(CliErrors, InconsistentJointType) {
  const std::string f =
      writeFile("helical.yaml", "poe:\n  joints:\n    - {type: revolute, twist: [0, 0, 1, 0, 0, 0.5]}\n");
  expectRejected("poe2dh " + f, "declared revolute", f);
  const std::string g = writeFile("prismatic.yaml", "poe:\n  joints:\n    - {type: prismatic, twist: [0, 0, 1, 0, 0, 0]}\n");
  expectRejected("poe2dh " + g, "declared prismatic", g);
  const std::string h = writeFile("zero.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 0, 0, 0, 0]}\n");
  expectRejected("poe2dh " + h, "twist is zero", h);
  const std::string k = writeFile(
      "dhpitch.yaml", "dh:\n  joints:\n    - {type: revolute, theta: 0, d: 0, alpha: 0, a: 1, pitch: 0.5}\n");
  expectRejected("dh2poe " + k, "only for helical", k);
}

TEST(CliErrors, BadToolPose) {
  const std::string f = writeFile(
      "tool.yaml",
      "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0]}\n  tool_pose: [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n");
  expectRejected("poe2dh " + f, "not orthonormal", f);
}

TEST(CliErrors, JointVector) {
  const std::string f = writeFile("good.yaml", kGoodPoe);
  expectRejected("fk " + f + " --q 0.1", "expected 2 joint values, got 1", f);
  expectRejected("fk " + f + " --q 0.1,abc", "'abc' is not a number", f);
  expectRejected("fk " + f + " --q 0.1,nan", "not finite", f);
  EXPECT_EQ(run("fk " + f + " --q 0.1,0.2").status, 0);
}

TEST(CliErrors, Usage) {
  const CliRun r = run("frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_EQ(run("fk " + model("elbow_mls.yaml")).status, 2);  // --q is required
}

TEST(CliModelFiles, PoeToDhFromMjcfMatchesTheRobotFile) {
  // the chain MuJoCo extracts from the actual PUMA's MJCF gives Table II's geometry (scale 1 there)
  const CliRun a = run("poe2dh " + model("puma560_okamura_actual.xml") + " --tip tool --json");
  const CliRun b = run("poe2dh " + model("puma560_okamura_actual.yaml") + " --json");
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  const double L = jb["size"].get<double>();
  for (size_t i = 0; i < 6; ++i) {
    for (const char* k : {"theta", "alpha"}) {
      EXPECT_NEAR(ja["joints"][i][k].get<double>(), jb["joints"][i][k].get<double>(), 1e-12) << i << k;
    }
    for (const char* k : {"d", "a"}) {
      EXPECT_NEAR(ja["joints"][i][k].get<double>(), jb["joints"][i][k].get<double>(), 1e-12 * L) << i << k;
    }
    EXPECT_EQ(ja["joints"][i]["scale"].get<double>(), 1.0);
  }
}

TEST(CliModelFiles, TipRules) {
  expectRejected("fk " + model("elbow_mls.xml") + " --q 0,0,0,0,0,0", "--tip NAME is required", model("elbow_mls.xml"));
  expectRejected("fk " + model("elbow_mls.yaml") + " --tip tool --q 0,0,0,0,0,0", "--tip/--base go with a model file",
                 model("elbow_mls.yaml"));
  expectRejected("jacobian " + model("elbow_mls.xml") + " --tip nowhere --q 0,0,0,0,0,0", "tip 'nowhere'",
                 model("elbow_mls.xml"));
  const CliRun fk = run("fk " + model("elbow_mls.xml") + " --tip tool --q 0,0,0,0,0,0 --json");
  ASSERT_EQ(fk.status, 0) << fk.err;
  // no --tip: the candidates listed as a wrong --tip lists them (it said only "--tip NAME is required")
  const std::string urdf = model("puma560_okamura_nominal.urdf"), mjcf = model("panda.xml");
  const std::string links = "links: 'base', 'j1_link', 'j2_link', 'j3_link', 'j4_link', 'j5_link', 'j6_link', 'tool'";
  const std::string sites = "sites: 'tool'; bodies: 'link1', 'link2', 'link3', 'link4', 'link5', 'link6', 'link7'";
  for (const std::string& command : {"export " + urdf + " --format dh", "fk " + urdf + " --q 0", "simulate " + urdf + " --poses 2",
                                    "validate " + urdf}) {
    expectRejected(command, "--tip NAME is required with a model file; " + links, urdf);
  }
  expectRejected("export " + urdf + " --format dh --tip nope", "tip 'nope' is not a link; " + links, urdf);
  for (const std::string& command : {"export " + mjcf + " --format dh", "simulate " + mjcf + " --poses 2", "validate " + mjcf}) {
    expectRejected(command, "--tip NAME is required with a model file; " + sites, mjcf);
  }
  expectRejected("export " + mjcf + " --format dh --tip nope", "tip 'nope' is neither a site nor a body; " + sites, mjcf);
  const auto T = nlohmann::json::parse(fk.out)["T_base_tool"];
  EXPECT_NEAR(T[1][3].get<double>(), 2.0, 1e-15);  // l1 + l2
  EXPECT_NEAR(T[2][3].get<double>(), 1.0, 1e-15);  // l0
}
