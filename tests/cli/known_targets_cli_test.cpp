// SMRs at known points pin the tool (issue 26, docs/calibration.md "Known targets"): a tracker 3.1 m away measures
// three SMRs on MuJoCo's actual PUMA; with their points known (a calibrated nest: the MJCF's sites in its tool
// frame) the calibrated file's tool is the actual's, and the actual commanded with the compensated joints puts
// its TCP on the nominal program to within 3x the noise. With the points unknown, the file says `tool_frame:
// nominal` and compensate flags the undetermined tool.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "rigid_fit.hpp"
#include "csv_text.hpp"

namespace {

using namespace lowpair_test;
using nlohmann::json;

const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");
const std::string kActualYaml = modelPath("puma560_okamura_actual.yaml");
const std::string kMujocoActual = modelPath("puma560_okamura_actual.xml") + " --tip tool --joint-variables " + kActualYaml;
const std::string kFrame = "0.3,-1.2,2.0,3000,-800,400";  // the tracker: 3.1 m from the robot
constexpr double kNoise = 0.01;                            // mm per coordinate

CliRun ok(const std::string& args) {
  CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The SMRs in the actual's tool frame, from models/puma560_okamura_actual.xml (body link6): the tool site at
// `tool` turned by `quat` (w, x, y, z), the SMR sites at their positions: p_tool = R^T (p_site - tool).
std::string knownTargetsYaml() {
  const Eigen::Vector3d tool(1.0850465287987296, 1.694279339839009, -44.07164376362795);
  const Eigen::Quaterniond q(0.9999250009374954, 0.009999750001874993, -0.004999875000937497, 0.004999875000937497);
  const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  const std::vector<std::pair<std::string, Eigen::Vector3d>> sites = {
      {"smr_a", {71, 2, -34}}, {"smr_b", {-29, 67, -44}}, {"smr_c", {-34, -58, -24}}};
  std::string text = "targets:\n";
  char line[256];
  for (const auto& [name, p] : sites) {
    const Eigen::Vector3d t = R.transpose() * (p - tool);
    std::snprintf(line, sizeof line, "  - {name: %s, point: [%.17g, %.17g, %.17g], known: true}\n", name.c_str(), t.x(), t.y(), t.z());
    text += line;
  }
  return text;
}

// Row k's TCP position in a pose CSV (simulate's output).
Points csvPoints(const std::string& path) {
  Points out;
  for (const csv_test::Row& row : csv_test::parseCsv(slurp(path)).rows) out.emplace_back(row.p[0], row.p[1], row.p[2]);
  return out;
}

Points fkPoints(const std::string& robot, const std::string& q_file) {
  Points p;
  const json fk = json::parse(ok("fk " + robot + " --q-file " + q_file + " --json").out);
  for (const json& row : fk["rows"]) {
    const auto T = row["T_base_tool"].get<std::vector<std::vector<double>>>();
    p.emplace_back(T[0][3], T[1][3], T[2][3]);
  }
  return p;
}


struct Compensated {
  json out;
  RigidFit after;  // the actual's TCP at the compensated joints vs the nominal program
};

// compensate CAL against the nominal program q, then MuJoCo's actual commanded with the result.
Compensated compensateAndCommand(const std::string& cal, const std::string& q, const std::string& tag) {
  const std::string q2 = scratch() + "/kt_" + tag + "_q2.csv", reached = scratch() + "/kt_" + tag + "_reached.csv";
  // (exit 1: some rows not ok, listed; the ok ones are written)
  const CliRun comp = runCli("compensate " + cal + " --nominal " + kNominal + " --q-file " + q + " --out " + q2 + " --json");
  EXPECT_TRUE(comp.status == 0 || comp.status == 1) << comp.err;
  Compensated c{json::parse(comp.out), {}};
  ok("simulate " + kMujocoActual + " --q-file " + q2 + " --out " + reached);
  const Points wanted_all = fkPoints(kNominal, q), reached_all = csvPoints(reached);
  EXPECT_EQ(wanted_all.size(), c.out["rows"].size());
  EXPECT_EQ(reached_all.size(), c.out["rows"].size());
  Points wanted, got;
  for (size_t k = 0; k < c.out["rows"].size() && k < reached_all.size() && k < wanted_all.size(); ++k) {
    if (c.out["rows"][k]["status"] != "ok") continue;
    wanted.push_back(wanted_all[k]);
    got.push_back(reached_all[k]);
  }
  EXPECT_GE(got.size(), 180u) << comp.out.substr(0, 1000);
  c.after = rigidFit(got, wanted);
  return c;
}

}  // namespace

TEST(KnownTargetsCli, KnownSmrsPinTheTcpUnknownOnesAreFlagged) {
  const std::string dir = scratch();
  const std::string fit = dir + "/kt_fit.csv", q = dir + "/kt_q.csv";
  ok("simulate " + kMujocoActual + " --poses 60 --seed 11 --measure targets --targets smr_a,smr_b,smr_c --frame " + kFrame +
     " --noise-position 0.01 --out " + fit);
  ok("simulate " + kNominal + " --poses 200 --seed 41 --out " + q);  // the nominal program
  const std::string known_nominal = writeScratchFile("kt_nominal_known.yaml", slurp(kNominal) + knownTargetsYaml());
  const std::string args = " --measurements " + fit + " --noise-position 0.01 --free-pitch --json --out ";

  // known points: the tool frame is a parameter, the count 6 * 5 (free pitch) + 6 scales + the tool's 6 = 42
  const std::string cal_known = dir + "/kt_cal_known.yaml";
  const json k = json::parse(ok("calibrate " + known_nominal + args + cal_known).out);
  ASSERT_TRUE(k["accepted"].get<bool>()) << k["reason"];
  EXPECT_TRUE(k["tool_frame"]["determined"].get<bool>());
  EXPECT_EQ(k["expected"].get<int>(), 6 * 5 + 6 + 6);
  EXPECT_EQ(k["rank"].get<int>(), 6 * 5 + 6 + 6);
  EXPECT_EQ(slurp(cal_known).find("tool_frame:"), std::string::npos);
  EXPECT_NE(slurp(cal_known).find("known: true"), std::string::npos);
  const Compensated pinned = compensateAndCommand(cal_known, q, "known");
  EXPECT_TRUE(pinned.out["tool_determined"].get<bool>());
  std::printf("known SMRs: the actual's TCP at the compensated joints vs the nominal program: RMS %.4g mm after the rigid "
              "motion (%.4g mm, %.3g rad; the actual's base error)\n",
              pinned.after.rms, pinned.after.translation, pinned.after.angle);
  EXPECT_LE(pinned.after.rms, 3.0 * kNoise);

  // unknown points (the nominal lists none): the file keeps the nominal's tool and says so; compensate flags it
  const std::string cal_unknown = dir + "/kt_cal_unknown.yaml";
  const json u = json::parse(ok("calibrate " + kNominal + args + cal_unknown).out);
  ASSERT_TRUE(u["accepted"].get<bool>()) << u["reason"];
  EXPECT_FALSE(u["tool_frame"]["determined"].get<bool>());
  EXPECT_NE(slurp(cal_unknown).find("tool_frame: nominal"), std::string::npos);
  const Compensated flange = compensateAndCommand(cal_unknown, q, "unknown");
  EXPECT_FALSE(flange.out["tool_determined"].get<bool>());
  EXPECT_NE(flange.out["tool_note"].get<std::string>().find("compensated for the flange; the tool frame is the nominal's"),
            std::string::npos);
  const CliRun text = runCli("compensate " + cal_unknown + " --nominal " + kNominal + " --q-file " + q);
  EXPECT_NE(text.err.find("note: compensated for the flange"), std::string::npos) << text.err;
  std::printf("unknown SMRs: TCP RMS %.4g mm after the rigid motion (flagged: the tool is the nominal's)\n", flange.after.rms);
  EXPECT_GT(flange.after.rms, 10.0 * kNoise);  // the tool's error is left in: what the flag warns of

  // the controller's table (export --format dh) keeps the flag and the measurement frame: compensate with it
  // says the same
  const std::string dh = dir + "/kt_cal_unknown_dh.yaml";
  ok("export " + cal_unknown + " --format dh --out " + dh);
  EXPECT_NE(slurp(dh).find("tool_frame: nominal"), std::string::npos);
  EXPECT_NE(slurp(dh).find("measurement_frame:"), std::string::npos);
  const CliRun from_dh = runCli("compensate " + dh + " --nominal " + kNominal + " --q-file " + q + " --json");
  EXPECT_FALSE(json::parse(from_dh.out)["tool_determined"].get<bool>());
}

// A robot file's `known:` and `tool_frame:` keys: misspelt values are exit 2 naming the key.
TEST(KnownTargetsCli, BadKnownOrToolFrameValuesExitTwo) {
  const std::string base = slurp(kNominal);
  const std::string bad_known = writeScratchFile("kt_bad_known.yaml", base + "targets:\n  - {name: a, point: [1, 2, 3], known: yes}\n");
  const CliRun a = runCli("fk " + bad_known + " --q 0,0,0,0,0,0");
  EXPECT_EQ(a.status, 2);
  EXPECT_NE(a.err.find("known must be true or false"), std::string::npos) << a.err;
  const std::string bad_tool = writeScratchFile("kt_bad_tool.yaml", base + "tool_frame: flange\n");
  const CliRun b = runCli("fk " + bad_tool + " --q 0,0,0,0,0,0");
  EXPECT_EQ(b.status, 2);
  EXPECT_NE(b.err.find("tool_frame"), std::string::npos) << b.err;
}

namespace {

// The data rows of a measurement CSV (no comments, no header).
std::vector<std::string> dataRows(const std::string& path) {
  std::vector<std::string> rows;
  std::istringstream in(slurp(path));
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    rows.push_back(line);
  }
  return rows;
}

// q1..q6 of a CSV row, and the rest after them.
std::pair<std::string, std::string> splitJoints(const std::string& row) {
  size_t at = 0;
  for (int i = 0; i < 6; ++i) at = row.find(',', at) + 1;
  return {row.substr(0, at), row.substr(at)};
}

}  // namespace

// Mixed data in one CSV (target and qw..qz columns; a target's row leaves the quaternion empty, a row with an
// empty target is a pose of the tool frame): 30 poses through three SMRs at unknown points and 10 poses of a
// 6-DOF probe, in the tracker's frame, fit together; the probe's poses determine the tool frame, so the file
// keeps no `tool_frame:` key and compensate puts the TCP on the nominal program to within 3x the noise.
TEST(KnownTargetsCli, MixedPoseAndTargetRowsFitTogether) {
  const std::string dir = scratch();
  const std::string smr = dir + "/mx_smr.csv", probe = dir + "/mx_probe.csv", q = dir + "/mx_q.csv";
  ok("simulate " + kMujocoActual + " --poses 30 --seed 12 --measure targets --targets smr_a,smr_b,smr_c --frame " + kFrame +
     " --noise-position 0.01 --out " + smr);
  ok("simulate " + kMujocoActual + " --poses 10 --seed 13 --frame " + kFrame +
     " --noise-position 0.01 --noise-rotation 1e-5 --out " + probe);
  std::string text = "# length_unit: mm\nq1,q2,q3,q4,q5,q6,target,x,y,z,qw,qx,qy,qz\n";
  for (const std::string& row : dataRows(smr)) text += row + ",,,,\n";  // a point: no rotation
  for (const std::string& row : dataRows(probe)) {
    const auto [joints, rest] = splitJoints(row);
    text += joints + "," + rest + "\n";  // an empty target: a pose
  }
  const std::string mixed = writeScratchFile("mx_mixed.csv", text);
  ok("simulate " + kNominal + " --poses 200 --seed 41 --out " + q);
  const std::string cal = dir + "/mx_cal.yaml";
  const json c = json::parse(ok("calibrate " + kNominal + " --measurements " + mixed +
                                " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch --json --out " + cal)
                                 .out);
  ASSERT_TRUE(c["accepted"].get<bool>()) << c["reason"];
  EXPECT_EQ(c["expected"].get<int>(), 6 * 5 + 6 + 6 + 3 * 3);  // the tool's 6, and 3 per unknown point
  EXPECT_EQ(c["rank"].get<int>(), 6 * 5 + 6 + 6 + 3 * 3);
  EXPECT_TRUE(c["tool_frame"]["determined"].get<bool>());
  EXPECT_TRUE(c["residuals"][90]["target"].is_null());        // the first probe row
  EXPECT_TRUE(c["residuals"][90]["rotation"].is_number());
  EXPECT_TRUE(c["residuals"][0]["rotation"].is_null());       // a point
  EXPECT_EQ(slurp(cal).find("tool_frame:"), std::string::npos);
  const Compensated k = compensateAndCommand(cal, q, "mixed");
  EXPECT_TRUE(k.out["tool_determined"].get<bool>());
  std::printf("mixed rows (90 SMR points, 10 probe poses): TCP RMS %.4g mm after the rigid motion (%.4g mm, %.3g rad)\n",
              k.after.rms, k.after.translation, k.after.angle);
  EXPECT_LE(k.after.rms, 3.0 * kNoise);

  // a target's row with a quaternion, a pose's row without one: exit 2 naming the line
  const std::string header = "q1,q2,q3,q4,q5,q6,target,x,y,z,qw,qx,qy,qz\n";
  const CliRun a = runCli("calibrate " + kNominal + " --measurements " +
                          writeScratchFile("mx_bad1.csv", header + "0,0,0,0,0,0,smr_a,1,2,3,1,0,0,0\n"));
  EXPECT_EQ(a.status, 2);
  EXPECT_NE(a.err.find(":2: a target's row leaves qw,qx,qy,qz empty"), std::string::npos) << a.err;
  const CliRun b = runCli("calibrate " + kNominal + " --measurements " +
                          writeScratchFile("mx_bad2.csv", header + "0,0,0,0,0,0,,1,2,3,,,,\n"));
  EXPECT_EQ(b.status, 2);
  EXPECT_NE(b.err.find(":2: "), std::string::npos) << b.err;
}
