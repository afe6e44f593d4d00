// lowpair validate: an MJCF the project has never seen (arbitrary pos/quat/euler, joint pos/axis/ref,
// a coupled hinge+slide), an independently written robot file checked against it, a negative control,
// rejected inputs, thread/shard independence, and no report on failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "cli_runner.hpp"

namespace {

using namespace lowpair_test;

CliRun run(const std::string& args) { return runCli(args); }
std::string writeFile(const std::string& name, const std::string& text) { return writeScratchFile(name, text); }
std::string model(const std::string& name) { return modelPath(name); }
std::string tempDir() { return scratch(); }

// Body frames rotated with euler (degrees, MuJoCo's default) and quat, joint anchors off the body
// origin, nonzero refs, and a helical joint as a hinge plus a coupled slide (pitch 0.1 m/rad).
const char* kUnseenMjcf = R"(<mujoco model="unseen">
  <worldbody>
    <body name="b1" pos="0 0 1" euler="0 0 90">
      <inertial pos="0 0 0" mass="0.1" diaginertia="0.01 0.01 0.01"/>
      <joint name="j1" type="hinge" pos="0 0.5 0" axis="1 0 0" ref="0.3"/>
      <body name="b2" pos="1 0 0">
        <inertial pos="0 0 0" mass="0.1" diaginertia="0.01 0.01 0.01"/>
        <joint name="j2" type="slide" axis="0 0 1" ref="0.2"/>
        <body name="b3" pos="0 0 0.5" quat="0.70710678118654757 0.70710678118654757 0 0">
          <inertial pos="0 0 0" mass="0.1" diaginertia="0.01 0.01 0.01"/>
          <joint name="j3" type="hinge" axis="0 0 1"/>
          <joint name="j3s" type="slide" axis="0 0 1"/>
          <site name="tool" pos="0.2 0 0"/>
        </body>
      </body>
    </body>
  </worldbody>
  <equality><joint joint1="j3s" joint2="j3" polycoef="0 0.1 0 0 0"/></equality>
</mujoco>
)";

// Written by hand from the geometry above: axis 1 is world y through (-0.5, 0, 1); joint 2 slides along
// world z; axis 3 is world x through (0, 1, 1.5) with pitch 0.1; the tool sits at (0, 1.2, 1.5) with
// rotation Rz(90 deg) Rx(90 deg).
const char* kUnseenRobot = R"(name: unseen
length_unit: m
poe:
  joints:
    - {twist: [0, 1, 0, -1, 0, -0.5]}
    - {type: prismatic, twist: [0, 0, 0, 0, 0, 1]}
    - {type: helical, twist: [1, 0, 0, 0.1, 1.5, -1]}
  tool_pose: [[0, 0, 1, 0], [1, 0, 0, 1.2], [0, 1, 0, 1.5], [0, 0, 0, 1]]
)";


// The same kind of chain as a URDF: massless links (MuJoCo needs the mass bounds the harness adds) and a
// tool link attached by a fixed joint (kept only because the harness loads a copy with fusestatic="false").
const char* kUnseenUrdf = R"(<?xml version="1.0"?>
<robot name="unseen_urdf">
  <link name="base_link"/>
  <link name="l1"/>
  <link name="l2"><inertial><mass value="0.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l3"/>
  <link name="tool"/>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="l1"/>
    <origin xyz="0 0 1" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.5" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="l3"/><child link="tool"/><origin xyz="0.2 0 0"/></joint>
</robot>
)";

// By hand: axis 1 is world y through (0, 0, 1); joint 2 slides along z; axis 3 is world x through
// (0, 1, 1.5); the tool link sits at (0, 1.2, 1.5) with rotation Rz(90 deg) Rx(90 deg).
const char* kUnseenUrdfRobot = R"(name: unseen-urdf
poe:
  joints:
    - {twist: [0, 1, 0, -1, 0, 0]}
    - {type: prismatic, twist: [0, 0, 0, 0, 0, 1], range: [-0.5, 0.5]}
    - {twist: [1, 0, 0, 0, 1.5, -1]}
  tool_pose: [[0, 0, 1, 0], [1, 0, 0, 1.2], [0, 1, 0, 1.5], [0, 0, 0, 1]]
)";

}  // namespace

TEST(Validate, UnseenMjcfAndIndependentRobotFile) {
  const std::string xml = writeFile("unseen.xml", kUnseenMjcf);
  const std::string yaml = writeFile("unseen.yaml", kUnseenRobot);
  const CliRun r = run("validate " + xml + " --tip tool --robot " + yaml + " --samples 2000 --json");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["pass"].get<bool>());
  const auto& cmps = j["scenarios"][0]["comparisons"];
  std::vector<std::string> names;
  for (const auto& c : cmps) names.push_back(c["name"]);
  EXPECT_NE(std::find(names.begin(), names.end(), "robot_file_vs_mujoco:unseen.yaml"), names.end());
  for (const auto& c : cmps) {
    EXPECT_LE(c["max_translation"].get<double>(), c["tolerance_translation"].get<double>()) << c["name"];
  }
}

TEST(Validate, UrdfWithFixedToolLinkAndMasslessLinks) {
  const std::string urdf = writeFile("unseen.urdf", kUnseenUrdf);
  const std::string yaml = writeFile("unseen_urdf.yaml", kUnseenUrdfRobot);
  const CliRun r = run("validate " + urdf + " --tip tool --robot " + yaml + " --samples 1000 --json");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["pass"].get<bool>());
  // poe, dh, the URDF read by urdfdom, the robot file, the Jacobian
  ASSERT_EQ(j["scenarios"][0]["comparisons"].size(), 5u);
  EXPECT_EQ(j["scenarios"][0]["comparisons"][2]["name"], "urdfdom_vs_mujoco");
  EXPECT_TRUE(j["scenarios"][0]["comparisons"][2]["pass"].get<bool>());
}

TEST(Validate, NegativeControlPerturbedAxisFails) {
  // the elbow's robot file with axis 2 tilted by 1e-6 rad about its point (0, 0, 1): still revolute
  std::ifstream in(model("elbow_mls.yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::regex axis2(R"(twist: \[-1, 0, 0, 0, -1, 0\])");
  ASSERT_TRUE(std::regex_search(text, axis2)) << "elbow_mls.yaml changed: update this test";
  text = std::regex_replace(text, axis2, "twist: [-0.9999999999995, 0.000001, 0, -0.000001, -0.9999999999995, 0]", std::regex_constants::format_first_only);
  const std::string perturbed = writeFile("perturbed.yaml", text);
  const CliRun r = run("validate " + model("elbow_mls.xml") + " --tip tool --robot " + perturbed + " --samples 500");
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("robot_file_vs_mujoco:perturbed.yaml .* FAIL"))) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("poe_vs_mujoco .* pass"))) << r.out;
}

// (Under the sanitizers, make sanitize: the elbow model's comparisons alone, the same threads and shards. The
// PUMA scenario's calibration cases, which its four runs repeat, took 185 s there; scenario.* runs them once.)
TEST(Validate, ResultsIndependentOfThreadsAndShards) {
  const bool sanitized = std::getenv("LOWPAIR_SANITIZE") != nullptr;
  const std::string s = sanitized ? model("elbow_mls.xml") + " --tip tool"
                                  : std::string(LOWPAIR_SCENARIOS) + "/puma560_okamura_actual.yaml";
  const std::string samples = " --samples 3000";
  const auto one = nlohmann::json::parse(run("validate " + s + samples + " --threads 1 --json").out);
  const auto two = nlohmann::json::parse(run("validate " + s + samples + " --threads 2 --json").out);
  EXPECT_EQ(one["scenarios"][0]["comparisons"], two["scenarios"][0]["comparisons"]);
  const auto a = nlohmann::json::parse(run("validate " + s + samples + " --shard 1/2 --json").out);
  const auto b = nlohmann::json::parse(run("validate " + s + samples + " --shard 2/2 --json").out);
  for (size_t c = 0; c < one["scenarios"][0]["comparisons"].size(); ++c) {
    const double full = one["scenarios"][0]["comparisons"][c]["max_translation"];
    const double ma = a["scenarios"][0]["comparisons"][c]["max_translation"];
    const double mb = b["scenarios"][0]["comparisons"][c]["max_translation"];
    const double merged = std::max(ma, mb);
    EXPECT_EQ(full, merged);
  }
  EXPECT_EQ(a["scenarios"][0]["samples"].get<int>() + b["scenarios"][0]["samples"].get<int>(),
            one["scenarios"][0]["samples"].get<int>());
}

// Memory does not grow with --samples (issue 11, finding 5): 2,000,000 samples used 416 MB when every
// sample's q and errors were kept; the statistics are now constant memory and the plot keeps 20,000 points.
// 2,000,000 samples of 5 comparisons would take 160 MB if anything were kept per sample. Under
// AddressSanitizer (make sanitize) the resident set measures ASan's shadow memory and quarantine, not ours,
// and the run costs a minute: there the test runs 200,000 samples and checks the run, not the memory.
TEST(Validate, MemoryDoesNotGrowWithSamples) {
  const bool sanitized = std::getenv("LOWPAIR_SANITIZE") != nullptr;
  const int samples = sanitized ? 200000 : 2000000;
  const CliRun r = run("validate " + model("elbow_mls.xml") + " --tip tool --samples " + std::to_string(samples) +
                       " --threads 2 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  rusage usage{};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &usage), 0);
  if (!sanitized) {
    EXPECT_LT(usage.ru_maxrss, 150 * 1024) << "largest child's resident set, KB";
  }
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["scenarios"][0]["samples"].get<int>(), samples);
  EXPECT_TRUE(j["pass"].get<bool>());
}

namespace {
void expectRejectedWithoutReport(const std::string& args, const std::string& what) {
  const std::string report = tempDir() + "/should_not_exist";
  lowpair_test::expectRejected(args + " --report " + report, what);
  EXPECT_FALSE(std::filesystem::exists(report)) << "report written on a failed run";
}
}  // namespace

TEST(ValidateRejects, BallJointInChain) {
  std::string text = kUnseenMjcf;
  text.replace(text.find("type=\"slide\" axis=\"0 0 1\" ref=\"0.2\""), 35, "type=\"ball\"");
  expectRejectedWithoutReport("validate " + writeFile("ball.xml", text) + " --tip tool", "ball joint");
}

TEST(ValidateRejects, TipNotFound) {
  expectRejectedWithoutReport("validate " + model("elbow_mls.xml") + " --tip nowhere", "tip 'nowhere'");
}

TEST(ValidateRejects, NonlinearEquality) {
  std::string text = kUnseenMjcf;
  text.replace(text.find("0 0.1 0 0 0"), 11, "0 0.1 0.5 0 0");
  expectRejectedWithoutReport("validate " + writeFile("nonlinear.xml", text) + " --tip tool", "polycoef");
}

TEST(ValidateRejects, RobotFileMismatch) {
  expectRejectedWithoutReport("validate " + model("elbow_mls.xml") + " --tip tool --robot " + model("panda.yaml"), "joints");
  expectRejectedWithoutReport("validate " + model("stanford_corke.xml") + " --tip tool --robot " + model("puma560_corke.yaml"),
                 "prismatic");
}

TEST(ValidateRejects, MissingModelAndBadOptions) {
  expectRejectedWithoutReport("validate /nonexistent.xml --tip tool", "cannot open");
  expectRejectedWithoutReport("validate " + model("elbow_mls.xml"), "--tip");
  expectRejectedWithoutReport("validate " + model("elbow_mls.xml") + " --tip tool --shard 3/2", "--shard");
}

TEST(ValidateRejects, ScenarioValuesAndEmptyRuns) {
  const std::string bad = writeFile("bad_seed.yaml", "model: " + model("elbow_mls.xml") + "\ntip: tool\nseed: abc\n");
  lowpair_test::expectRejected("validate " + bad, "line 3: seed must be a number", bad);
  lowpair_test::expectRejected("validate " + model("elbow_mls.xml") + " --tip tool --samples 0", "nothing to validate");
  lowpair_test::expectRejected("validate " + model("elbow_mls.xml") + " --tip tool --samples 1e12", "--samples");
}

TEST(ValidateReport, ReportThatCannotBeWrittenFailsWithoutOutput) {
  // a file where the report folder should be: the run completes, the report cannot be written
  const std::string blocked = writeFile("blocked", "not a folder");
  lowpair_test::expectRejected("validate " + model("elbow_mls.xml") + " --tip tool --samples 100 --report " + blocked,
                               "blocked");
  for (const auto& entry : std::filesystem::directory_iterator(tempDir())) {
    EXPECT_EQ(entry.path().filename().string().find("blocked.partial"), std::string::npos) << "partial report left";
  }
}

TEST(ValidateReport, PictureOfABoundedSubsampleHistogramOfEverySample) {
  // 50,000 samples: the error picture shows every 3rd (16,667 points), the histogram counts all of them
  const std::string dir = tempDir() + "/report_subsample";
  const CliRun r = run("validate " + model("elbow_mls.xml") + " --tip tool --samples 50000 --report " + dir);
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream summary(dir + "/summary.md");
  const std::string md((std::istreambuf_iterator<char>(summary)), {});
  EXPECT_NE(md.find("1 sample in 3 (16667 of 50000)"), std::string::npos) << md;
  std::ifstream errors(dir + "/elbow_mls_errors.dat");
  std::string line;
  long long rows = 0, last = -1;
  while (std::getline(errors, line)) {
    if (line.empty() || line[0] == '#') continue;
    ++rows;
    last = std::stoll(line.substr(0, line.find(' ')));
  }
  EXPECT_EQ(rows, 16667);
  EXPECT_EQ(last, 49998);
  std::ifstream histogram(dir + "/elbow_mls_histogram.dat");
  std::vector<long long> totals;
  while (std::getline(histogram, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    double edge = 0;
    in >> edge;
    long long v = 0;
    for (size_t c = 0; in >> v; ++c) {
      if (totals.size() <= c) totals.resize(c + 1, 0);
      totals[c] += v;
    }
  }
  ASSERT_EQ(totals.size(), 6u) << "rotation and translation of poe_vs_mujoco, dh_vs_mujoco, jacobian_vs_mujoco";
  for (long long t : totals) EXPECT_EQ(t, 50000);
}

TEST(ValidateReport, WritesJsonSummaryAndPictures) {
  const std::string dir = tempDir() + "/report";
  const CliRun r = run("validate " + model("elbow_mls.xml") + " --tip tool --samples 300 --report " + dir);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"report.json", "summary.md", "elbow_mls_errors.png", "elbow_mls_histogram.png",
                        "elbow_mls_singularity_map.png"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }
}

// Rough edges 8: scenario and calibration-case names are user strings; in summary.md they are shown as
// text, never as Markdown (a name could close the calibration's code fence, add a heading or a link).
TEST(ValidateReport, UserStringsInSummaryAreEscaped) {
  const std::string name = "evil```\\n# injected [link](http://x) *bold*";
  const std::string scenario = writeFile(
      "markdown.yaml", "name: \"" + name + "\"\nmodel: " + model("stanford_corke_actual.xml") +
                           "\ntip: tool\nsamples: 100\ncalibration:\n  - name: \"case```\\n## case [x](y)\"\n"
                           "    nominal: " + model("stanford_corke.yaml") +
                           "\n    poses: 50\n    validation_poses: 20\n    seed: 11\n"
                           "    noise: {position: 1.0e-5, rotation: 1.0e-5}\n    tolerance: {position: 1.0e-5}\n");
  const std::string dir = tempDir() + "/report_markdown";
  const CliRun r = run("validate " + scenario + " --report " + dir);
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream summary(dir + "/summary.md");
  std::vector<std::string> lines;
  for (std::string line; std::getline(summary, line);) lines.push_back(line);
  // outside code blocks no line may be markup made of a name (inside one, text is verbatim); a block ends
  // only at a fence at least as long as its opening one (CommonMark)
  std::string open_fence;
  for (const std::string& line : lines) {
    const size_t ticks = line.find_first_not_of('`');
    const std::string fence = line.substr(0, ticks == std::string::npos ? line.size() : ticks);
    if (open_fence.empty() && fence.size() >= 3) {
      open_fence = fence;
      continue;
    }
    if (!open_fence.empty()) {
      if (fence.size() >= open_fence.size() && fence == line) open_fence.clear();
      continue;
    }
    EXPECT_NE(line.rfind("# injected", 0), 0u) << "a name became a heading: " << line;
    EXPECT_NE(line.rfind("## case", 0), 0u) << "a name became a heading: " << line;
    EXPECT_EQ(line.find("](http://x)"), std::string::npos) << "a name became a link: " << line;
  }
  EXPECT_TRUE(open_fence.empty()) << "a code block is not closed";
  const std::string md = [&] {
    std::string all;
    for (const std::string& line : lines) all += line + "\n";
    return all;
  }();
  EXPECT_NE(md.find("\\# injected \\[link\\]\\(http\\:\\/\\/x\\) \\*bold\\*"), std::string::npos) << md;
  // the calibration's text block: its fence is longer than the name's run of three backticks
  EXPECT_NE(md.find("\n````\ncalibration of"), std::string::npos) << md;
}

// Rough edges 13: the report's pictures. Tick labels that the (noenhanced) terminal can print ('1e%L', not
// the literal '10^{%L}'), exact zeros left out of log axes (they were drawn at 1e-18 as if data) and
// counted, the singularity map's colour range from its data, axes with units and the fixed joints stated,
// the calibration plot's unit named.
TEST(ValidateReport, PicturesSayWhatTheyShow) {
  const std::string dir = tempDir() + "/report_pictures";
  const CliRun r =
      run("validate " + std::string(LOWPAIR_SCENARIOS) + "/stanford_corke_actual.yaml --samples 300 --report " + dir);
  ASSERT_EQ(r.status, 0) << r.err;
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  const std::string script = slurp(dir + "/stanford-corke-actual.gnuplot");
  ASSERT_FALSE(script.empty());
  EXPECT_EQ(script.find("10^{"), std::string::npos);
  EXPECT_NE(script.find("set format y '1e%L'"), std::string::npos);
  EXPECT_EQ(script.find("set cbrange [-8:0]"), std::string::npos) << "the colour range comes from the data";
  EXPECT_NE(script.find("'q2 (rad)'"), std::string::npos);
  EXPECT_NE(script.find("other joints fixed: q1 = "), std::string::npos);
  EXPECT_NE(script.find("'position error (m)'"), std::string::npos);
  // the elbow's POE and MuJoCo agree exactly on many samples: those zeros are NaN (not drawn) and counted
  const std::string elbow = tempDir() + "/report_zeros";
  ASSERT_EQ(run("validate " + model("elbow_mls.xml") + " --tip tool --samples 300 --report " + elbow).status, 0);
  const std::string errors = slurp(elbow + "/elbow_mls_errors.dat");
  EXPECT_EQ(errors.find("1e-18"), std::string::npos) << "zeros drawn at 1e-18";
  EXPECT_NE(errors.find("NaN"), std::string::npos);
  EXPECT_NE(slurp(elbow + "/elbow_mls.gnuplot").find("errors exactly 0, not drawn (log axis)"), std::string::npos);
}
