// SMRs at known points pin the tool (issue 26, docs/calibration.md "Known targets"): a tracker 3.8 m away measures
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
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "csv_text.hpp"

namespace {

using namespace lowpair_test;
using nlohmann::json;
using Points = std::vector<Eigen::Vector3d>;

const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");
const std::string kActualYaml = modelPath("puma560_okamura_actual.yaml");
const std::string kMujocoActual = modelPath("puma560_okamura_actual.xml") + " --tip tool --joint-variables " + kActualYaml;
const std::string kFrame = "0.3,-1.2,2.0,3000,-800,400";  // the tracker: 3.8 m from the robot
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

// The RMS distance between a and b left after the best rigid motion (Kabsch), and that motion's size.
struct Rigid {
  double rms = 0.0, translation = 0.0, angle = 0.0;
};
Rigid rigidRms(const Points& a, const Points& b) {
  Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < a.size(); ++k) {
    ca += a[k] / static_cast<double>(a.size());
    cb += b[k] / static_cast<double>(b.size());
  }
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < a.size(); ++k) M += (b[k] - cb) * (a[k] - ca).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  const Eigen::Vector3d t = cb - R * ca;
  double s = 0.0;
  for (size_t k = 0; k < a.size(); ++k) s += (R * a[k] + t - b[k]).squaredNorm();
  return {std::sqrt(s / static_cast<double>(a.size())), t.norm(), Eigen::AngleAxisd(R).angle()};
}

struct Compensated {
  json out;
  Rigid after;  // the actual's TCP at the compensated joints vs the nominal program
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
  c.after = rigidRms(got, wanted);
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
