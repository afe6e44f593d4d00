// The calibrated robot in its own base frame (issue 26, docs/calibration.md "The base frame as the gauge"):
// tracker data measured metres away calibrate to a robot file in the nominal's base frame, whose FK is the
// actual's up to one rigid motion of the actual's base error, and which compensate takes as it is.
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
#include "rigid_fit.hpp"

namespace {

using namespace lowpair_test;
using nlohmann::json;

const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");
const std::string kActual = modelPath("puma560_okamura_actual.yaml");
const std::string kFrame = "0.3,-1.2,2.0,3000,-800,400";  // the tracker: 3.1 m from the robot, turned 135 deg

CliRun ok(const std::string& args) {
  CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r;
}

// The tool origins of fk --q-file --json.
Points toolPoints(const std::string& robot, const std::string& q_file, const std::string& extra = "") {
  const json rows = json::parse(ok("fk " + robot + " --q-file " + q_file + " --json" + extra).out)["rows"];
  Points p;
  for (const json& row : rows) {
    const auto T = row["T_base_tool"].get<std::vector<std::vector<double>>>();
    p.emplace_back(T[0][3], T[1][3], T[2][3]);
  }
  return p;
}


// The actual's base error, written out from the two robot files by the rule of docs/calibration.md (not by
// the library): the frame F of joint 1's line (z), the foot of its common normal with joint 2 (origin) and
// x = unit(d1 x d2); the actual's FK is the base-frame robot's moved by F_actual F_nominal^-1.
Eigen::Isometry3d baseFrameOfJoints12(const Eigen::Matrix<double, 6, 1>& t1, const Eigen::Matrix<double, 6, 1>& t2) {
  auto line = [](const Eigen::Matrix<double, 6, 1>& t, Eigen::Vector3d& d, Eigen::Vector3d& p) {
    const double n = t.head<3>().norm();
    d = t.head<3>() / n;
    p = d.cross(t.tail<3>() / n);  // the point of the line nearest the origin
  };
  Eigen::Vector3d d1, p1, d2, p2;
  line(t1, d1, p1);
  line(t2, d2, p2);
  const Eigen::Vector3d n = d1.cross(d2);
  Eigen::Matrix3d A;
  A << d1, -d2, -n;
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(p2 - p1);  // p1 + s0 d1 + s2 n = p2 + s1 d2
  Eigen::Isometry3d F = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d x = n.normalized();
  F.linear() << x, d1.cross(x), d1;
  F.translation() = p1 + s(0) * d1;
  return F;
}

Eigen::Isometry3d actualBaseError() {
  Eigen::Matrix<double, 6, 1> n1, n2, a1, a2;  // models/puma560_okamura_{nominal,actual}.yaml, joints 1 and 2
  n1 << 0, 0, 1, 0, 0, 0;
  n2 << 0, -1, 0, 0, 0, 0;
  a1 << 0.04, -0.02, 0.999, 0.02, 0.04, 0;
  a2 << 0, -1.00002, 0, -0.02, 0, 0.05;
  return baseFrameOfJoints12(a1, a2) * baseFrameOfJoints12(n1, n2).inverse();
}

TEST(BaseFrameCli, FarTrackerCalibratesInTheBaseFrameAndCompensates) {
  const std::string dir = scratch();
  const std::string fit = dir + "/bf_fit.csv", val = dir + "/bf_val.csv", cal = dir + "/bf_cal.yaml";
  ok("simulate " + kActual + " --poses 60 --seed 3 --noise-position 0.01 --noise-rotation 1e-5 --frame " + kFrame +
     " --out " + fit);
  ok("simulate " + kActual + " --poses 200 --seed 4 --frame " + kFrame + " --out " + val);
  const json c = json::parse(ok("calibrate " + kNominal + " --measurements " + fit + " --validation " + val +
                                " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch --out " + cal + " --json")
                                 .out);
  ASSERT_TRUE(c["accepted"].get<bool>());
  const double validation_rms = c["validation"]["after"]["rms_position"].get<double>();
  ASSERT_TRUE(c.contains("base_frame"));

  // the calibrated file's FK is the actual's up to one rigid motion: the actual's base error (mm), not the
  // tracker's 3.1 m; fitting that motion leaves no more than the noise
  const std::string q = dir + "/bf_q.csv";
  ok("simulate " + kNominal + " --poses 200 --seed 31 --out " + q);  // joint vectors (q1..q6 and the nominal's pose)
  const Points actual = toolPoints(kActual, q), calibrated = toolPoints(cal, q);
  const RigidFit base = rigidFit(calibrated, actual);
  std::printf("calibrated vs actual: rigid motion %.4g mm, %.3g rad; RMS left %.3g mm (noise 0.01 mm, validation RMS %.3g mm)\n",
              base.translation, base.angle, base.rms, validation_rms);
  // the actual's base error: its joint 1 tilted 0.0447 rad, the foot of the common normal 0.050 mm away
  const Eigen::Isometry3d G = actualBaseError();
  std::printf("the actual's base error (from the files): %.4g mm, %.4g rad; fitted minus it: %.3g mm, %.3g rad\n",
              G.translation().norm(), Eigen::AngleAxisd(G.linear()).angle(), (base.t - G.translation()).norm(),
              Eigen::AngleAxisd(base.R * G.linear().transpose()).angle());
  EXPECT_LE((base.t - G.translation()).norm(), 0.01);  // mm: the noise
  EXPECT_LE(Eigen::AngleAxisd(base.R * G.linear().transpose()).angle(), 1e-4);  // the noise over the reach
  EXPECT_LE(base.translation, 1.0);  // mm, not the tracker's 3.1 m
  EXPECT_LE(base.rms, 0.01);

  // fk --frame measurement predicts in the tracker's frame: the validation file's points
  {
    const json rows = json::parse(ok("fk " + cal + " --q-file " + val + " --frame measurement --json").out)["rows"];
    std::ifstream in(val);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    ASSERT_EQ(rows.size(), 200u);
    const auto T = rows[0]["T_base_tool"].get<std::vector<std::vector<double>>>();
    EXPECT_GT(std::hypot(T[0][3], T[1][3], T[2][3]), 1000.0);  // metres away, in the tracker's frame
  }

  // compensate with the base-frame file and the nominal: no extra step; the actual commanded with the
  // compensated joints reaches the nominal program within 3x the validation RMS, the rigid motion aside
  const std::string q2 = dir + "/bf_q2.csv";
  const CliRun comp = runCli("compensate " + cal + " --nominal " + kNominal + " --q-file " + q + " --out " + q2 + " --json");
  const json cj = json::parse(comp.out);
  const int ok_rows = cj["counts"]["ok"].get<int>();
  EXPECT_GE(ok_rows, 180) << comp.out.substr(0, 2000);
  Points wanted, reached;
  {
    const Points nominal_points = toolPoints(kNominal, q), actual_points = toolPoints(kActual, q2);
    for (size_t k = 0; k < cj["rows"].size(); ++k) {
      if (cj["rows"][k]["status"] != "ok") continue;
      wanted.push_back(nominal_points[k]);
      reached.push_back(actual_points[k]);
    }
  }
  ASSERT_GE(wanted.size(), 3u);
  const RigidFit program = rigidFit(reached, wanted);
  const RigidFit before = rigidFit(actual, toolPoints(kNominal, q));
  std::printf("compensated: %d of 200 ok; actual vs the nominal program: RMS %.3g mm after the rigid motion (%.4g mm, "
              "%.3g rad); uncompensated %.3g mm\n",
              ok_rows, program.rms, program.translation, program.angle, before.rms);
  EXPECT_LE(program.rms, 3.0 * validation_rms);
  // the same rigid motion the other way (actual -> program): the actual's base error
  EXPECT_LE((program.t - G.inverse().translation()).norm(), 0.01);
  EXPECT_LE(Eigen::AngleAxisd(program.R * G.linear()).angle(), 1e-4);
}

TEST(BaseFrameCli, FrameMeasurementKeepsTheTrackersFrameAndTheKeyReadsBack) {
  const std::string dir = scratch();
  const std::string fit = dir + "/bfm_fit.csv", base = dir + "/bfm_base.yaml", meas = dir + "/bfm_meas.yaml";
  ok("simulate " + kActual + " --poses 40 --seed 5 --noise-position 0.01 --noise-rotation 1e-5 --frame " + kFrame +
     " --out " + fit);
  const std::string args = "calibrate " + kNominal + " --measurements " + fit + " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch";
  ok(args + " --out " + base);
  ok(args + " --frame measurement --out " + meas);
  std::ifstream b(base), m(meas);
  const std::string base_text((std::istreambuf_iterator<char>(b)), {}), meas_text((std::istreambuf_iterator<char>(m)), {});
  EXPECT_NE(base_text.find("measurement_frame:"), std::string::npos);
  EXPECT_EQ(meas_text.find("measurement_frame:"), std::string::npos);
  // the base-frame file predicts in the tracker's frame what the measurement-frame file predicts
  const std::string qs = "0.1,-0.4,0.3,0.2,0.5,-0.6";
  const auto T1 = json::parse(ok("fk " + base + " --q " + qs + " --frame measurement --json").out)["T_base_tool"]
                      .get<std::vector<std::vector<double>>>();
  const auto T2 = json::parse(ok("fk " + meas + " --q " + qs + " --json").out)["T_base_tool"].get<std::vector<std::vector<double>>>();
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(T1[i][k], T2[i][k], k == 3 ? 1e-8 : 1e-11) << i << "," << k;
  }
  // the D-H table in the base frame: the gauge's entries are marked
  const CliRun text = ok(args);
  EXPECT_NE(text.out.find("fixed (gauge)"), std::string::npos);
  EXPECT_NE(text.out.find("change per joint (calibrated vs the nominal in the base frame)"), std::string::npos);
  // a robot file without measurement_frame: fk --frame measurement is a usage error
  const CliRun r = runCli("fk " + kNominal + " --q " + qs + " --frame measurement");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("measurement_frame"), std::string::npos);
}

}  // namespace
