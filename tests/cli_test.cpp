// The lowpair command line: outputs on the project's robot files and rejection of bad input
// (exit status 2, one line "error: FILE: ..." on stderr).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace {

struct CliRun {
  int status = -1;
  std::string out, err;
};

std::string tempDir() {
  static std::string dir = [] {
    char tmpl[] = "/tmp/lowpair_cli_test_XXXXXX";
    return std::string(mkdtemp(tmpl));
  }();
  return dir;
}

CliRun run(const std::string& args) {
  const std::string err_path = tempDir() + "/stderr.txt";
  const std::string cmd = std::string(LOWPAIR_CLI) + " " + args + " 2>" + err_path;
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_path);
  r.err.assign(std::istreambuf_iterator<char>(err), {});
  return r;
}

std::string model(const std::string& name) { return std::string(LOWPAIR_MODELS) + "/" + name; }

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = tempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// Bad input: status 2, a single stderr line starting "error: FILE" and containing `what`.
void expectRejected(const std::string& args, const std::string& file, const std::string& what) {
  const CliRun r = run(args);
  EXPECT_EQ(r.status, 2) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.rfind("error: " + file, 0), 0u) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << "expected '" << what << "' in: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(r.out.empty()) << "partial output on error: " << r.out;
}

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
  const CliRun r = run("poe2dh " + model("puma560_okamura_actual.yaml") + " --json");
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
  const CliRun human = run("poe2dh " + model("puma560_okamura_actual.yaml"));
  ASSERT_EQ(human.status, 0) << human.err;
  EXPECT_NE(human.out.find("-567.6554"), std::string::npos) << human.out;
  EXPECT_NE(human.out.find("theta(deg)"), std::string::npos);
  const CliRun mod = run("poe2dh " + model("puma560_okamura_actual.yaml") + " --modified --json");
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

TEST(CliErrors, MissingFile) { expectRejected("poe2dh /nonexistent/robot.yaml", "/nonexistent/robot.yaml", "cannot open"); }

TEST(CliErrors, YamlSyntaxWithLine) {
  const std::string f = writeFile("syntax.yaml", "name: x\npoe:\n  joints: [\n    {twist: [0, 0, 1\n");
  expectRejected("poe2dh " + f, f, "line ");
}

TEST(CliErrors, UnknownKey) {
  const std::string f = writeFile("unknown.yaml", std::string(kGoodPoe) + "colour: red\n");
  expectRejected("poe2dh " + f, f, "unknown key 'colour'");
  const std::string g = writeFile("unknown_joint.yaml",
                                  "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0], ofset: 1}\n");
  expectRejected("poe2dh " + g, g, "unknown key 'ofset'");
}

TEST(CliErrors, WrongVectorLength) {
  const std::string f = writeFile("length.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0]}\n");
  expectRejected("poe2dh " + f, f, "must have 6 entries, got 5");
}

TEST(CliErrors, NonFiniteNumber) {
  const std::string f = writeFile("nan.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 1, .nan, 0, 0]}\n");
  expectRejected("poe2dh " + f, f, "not finite");
  const std::string g = writeFile("word.yaml", "poe:\n  joints:\n    - {twist: [0, 0, one, 0, 0, 0]}\n");
  expectRejected("poe2dh " + g, g, "must be a number");
}

TEST(CliErrors, InconsistentJointType) {
  const std::string f =
      writeFile("helical.yaml", "poe:\n  joints:\n    - {type: revolute, twist: [0, 0, 1, 0, 0, 0.5]}\n");
  expectRejected("poe2dh " + f, f, "declared revolute");
  const std::string g = writeFile("prismatic.yaml", "poe:\n  joints:\n    - {type: prismatic, twist: [0, 0, 1, 0, 0, 0]}\n");
  expectRejected("poe2dh " + g, g, "declared prismatic");
  const std::string h = writeFile("zero.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 0, 0, 0, 0]}\n");
  expectRejected("poe2dh " + h, h, "twist is zero");
  const std::string k = writeFile(
      "dhpitch.yaml", "dh:\n  joints:\n    - {type: revolute, theta: 0, d: 0, alpha: 0, a: 1, pitch: 0.5}\n");
  expectRejected("dh2poe " + k, k, "only for helical");
}

TEST(CliErrors, BadToolPose) {
  const std::string f = writeFile(
      "tool.yaml",
      "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0]}\n  tool_pose: [[1, 0, 0, 0], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n");
  expectRejected("poe2dh " + f, f, "not orthonormal");
}

TEST(CliErrors, JointVector) {
  const std::string f = writeFile("good.yaml", kGoodPoe);
  expectRejected("fk " + f + " --q 0.1", f, "expected 2 joint values, got 1");
  expectRejected("fk " + f + " --q 0.1,abc", f, "'abc' is not a number");
  expectRejected("fk " + f + " --q 0.1,nan", f, "not finite");
  EXPECT_EQ(run("fk " + f + " --q 0.1,0.2").status, 0);
}

TEST(CliErrors, Usage) {
  const CliRun r = run("frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << r.err;
  EXPECT_EQ(run("fk " + model("elbow_mls.yaml")).status, 2);  // --q is required
}
