// Issue 27 in the loop: a compliant MuJoCo actual calibrated with --compliance, end to end, through the CLI only
// (docs/calibration.md, "A compliant arm, end to end").
//
// The actual: models/puma560_masses.xml (Corke's PUMA 560 geometry, Armstrong-Khatib-Burdick masses, a 2 kg
// tool, gravity on) with joint springs k = 8e4, 4e4, 1e4 N m/rad on joints 2, 3 and 5, measured by `simulate
// --stiffness` where it rests under gravity, 0.01 mm of noise per coordinate. The nominal: its robot file
// models/puma560_masses.yaml (the same masses as keys, no compliance). Nothing on the nominal's side knows k.
//
// The numbers the checks come from (sigma = 1e-5 m per coordinate, N = 200 training poses, p = the fit's
// rank):
// - c_i: the fit's own standard deviation: within 2 sd of 1/k_i, and that sd below 5 % of 1/k_i, so that the
//   2-sd band lies within 10 % of the value.
// - held-out RMS (3-D distance, other poses measured the same way): the noise of the held-out measurement
//   itself, 3 sigma^2, plus the calibrated model's prediction error at a pose like the training ones, p sigma^2
//   / N on average (the trace of the hat matrix spread over the N poses): sigma sqrt(3 + p/N); within 1.5x.
// - compensation: the compensated commands, run on the compliant actual without noise, miss the nominal's
//   poses by the model's prediction error alone, about sigma sqrt(p/N); checked against 3x the held-out RMS.
#include <gtest/gtest.h>

#include <chrono>
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

const std::string kActual = modelPath("puma560_masses.xml") + " --tip tool";
const std::string kNominal = modelPath("puma560_masses.yaml");
const std::string kStiffness = "0,8e4,4e4,0,1e4,0";  // N m/rad; 0: rigid (joint 1 vertical, 4 and 6 nearly unloaded)
struct Spring {
  int joint;  // 1-based
  double k;
};
const std::vector<Spring> kSprings = {{2, 8e4}, {3, 4e4}, {5, 1e4}};
constexpr double kSigma = 1e-5;  // m per coordinate: 0.01 mm
constexpr int kTrain = 200, kHeldOut = 200, kProgram = 20;

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

std::string slurpFile(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

void run(const std::string& args) {
  const CliRun r = runCli(args);
  ASSERT_EQ(r.status, 0) << args << "\n" << r.err << r.out;
}

// RMS and largest 3-D distance between the positions of two measurement CSVs row by row (the same q order).
struct Distances {
  double rms = 0, max = 0;
};
Distances distances(const std::string& a_path, const std::string& b_path) {
  const csv_test::Csv a = csv_test::parseCsv(slurpFile(a_path)), b = csv_test::parseCsv(slurpFile(b_path));
  EXPECT_EQ(a.rows.size(), b.rows.size());
  Distances d;
  for (size_t k = 0; k < a.rows.size() && k < b.rows.size(); ++k) {
    double s = 0;
    for (int c = 0; c < 3; ++c) s += (a.rows[k].p[c] - b.rows[k].p[c]) * (a.rows[k].p[c] - b.rows[k].p[c]);
    d.rms += s;
    d.max = std::max(d.max, std::sqrt(s));
  }
  d.rms = std::sqrt(d.rms / static_cast<double>(a.rows.size()));
  return d;
}

// The measurements, calibrations with and without --compliance: made once for the tests below.
class CompliantLoop : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto start = std::chrono::steady_clock::now();
    train_ = scratch() + "/train.csv";
    held_ = scratch() + "/held.csv";
    calibrated_ = scratch() + "/cal.yaml";
    const std::string measure = "simulate " + kActual + " --measure position --noise-position 1e-5 --stiffness " + kStiffness;
    run(measure + " --poses " + std::to_string(kTrain) + " --seed 1 --out " + train_);
    run(measure + " --poses " + std::to_string(kHeldOut) + " --seed 2 --out " + held_);
    const std::string calibrate = "calibrate " + kNominal + " --measurements " + train_ + " --validation " + held_ +
                                  " --noise-position 1e-5 --json";
    const CliRun compliant = runCli(calibrate + " --compliance 2,3,5 --out " + calibrated_);
    ASSERT_EQ(compliant.status, 0) << compliant.err;
    with_ = json::parse(compliant.out);
    const CliRun rigid = runCli(calibrate);  // the same data, no --compliance
    ASSERT_FALSE(rigid.out.empty()) << rigid.err;
    without_ = json::parse(rigid.out);
    std::printf("measured (2 x %d poses) and calibrated twice in %.2f s; without --compliance: exit %d\n", kTrain,
                seconds(start), rigid.status);
  }
  static std::string train_, held_, calibrated_;
  static json with_, without_;
};
std::string CompliantLoop::train_, CompliantLoop::held_, CompliantLoop::calibrated_;
json CompliantLoop::with_, CompliantLoop::without_;

TEST_F(CompliantLoop, IdentifiedComplianceIsOneOverTheStiffness) {
  ASSERT_TRUE(with_.contains("deflections")) << with_.dump();
  EXPECT_EQ(with_["accepted"], true) << with_["verdict"];
  ASSERT_EQ(with_["deflections"].size(), kSprings.size());
  for (size_t s = 0; s < kSprings.size(); ++s) {
    const json& d = with_["deflections"][s];
    EXPECT_EQ(d["joint"], kSprings[s].joint);
    EXPECT_EQ(d["kind"], "compliance");
    EXPECT_EQ(d["unit"], "rad/(N m)");
    const double truth = 1.0 / kSprings[s].k, value = d["value"].get<double>(), sd = d["sd"].get<double>();
    std::printf("j%d.compliance %.4e +- %.2e rad/(N m), 1/k = %.4e: %+.2f sd, %+.2f %%\n", kSprings[s].joint, value,
                sd, truth, (value - truth) / sd, 100 * (value - truth) / truth);
    EXPECT_LE(std::abs(value - truth), 2 * sd) << "joint " << kSprings[s].joint;
    EXPECT_LT(sd, 0.05 * truth) << "joint " << kSprings[s].joint;  // determined: 2 sd within 10 %
    EXPECT_LE(std::abs(value - truth), 0.1 * truth) << "joint " << kSprings[s].joint;
  }
}

TEST_F(CompliantLoop, HeldOutErrorIsTheNoiseWithComplianceAndWellAboveWithout) {
  const double p = with_["rank"].get<double>();
  const double expected = kSigma * std::sqrt(3.0 + p / kTrain);
  const double with = with_["validation"]["after"]["rms_position"].get<double>();
  const double without = without_["validation"]["after"]["rms_position"].get<double>();
  const double before = with_["validation"]["before"]["rms_position"].get<double>();
  std::printf("held-out RMS: nominal %.3g m; calibrated with compliance %.3g m (noise level sigma sqrt(3 + %g/%d) = "
              "%.3g m), without %.3g m: %.1fx\n",
              before, with, p, kTrain, expected, without, without / with);
  EXPECT_EQ(with_["validation"]["after"]["count"], kHeldOut);
  EXPECT_LE(with, 1.5 * expected);
  EXPECT_GE(with, expected / 1.5);
  // the geometry cannot take up a load-dependent joint deflection: the rigid fit stays far above the noise
  EXPECT_GT(without, 5 * expected);
  EXPECT_FALSE(without_.contains("deflections"));
}

TEST_F(CompliantLoop, CompensatedCommandsReachTheNominalPosesOnTheCompliantActual) {
  const auto start = std::chrono::steady_clock::now();
  // the program: the nominal's own poses at random joint vectors (its rigid FK, no noise)
  const std::string program = scratch() + "/program.csv", commands = scratch() + "/commands.csv";
  run("simulate " + kNominal + " --poses " + std::to_string(kProgram) + " --seed 3 --measure position --out " + program);
  const CliRun c = runCli("compensate " + calibrated_ + " --nominal " + kNominal + " --q-file " + program +
                          " --measure position --out " + commands);
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.err.find("compliance applied"), std::string::npos) << c.err;
  // the compliant actual, commanded the compensated joints and, for comparison, the program's own
  const std::string reached = scratch() + "/reached.csv", plain = scratch() + "/plain.csv";
  run("simulate " + kActual + " --q-file " + commands + " --measure position --stiffness " + kStiffness + " --out " + reached);
  run("simulate " + kActual + " --q-file " + program + " --measure position --stiffness " + kStiffness + " --out " + plain);
  const Distances compensated = distances(program, reached), uncompensated = distances(program, plain);
  const double validation = with_["validation"]["after"]["rms_position"].get<double>();
  const double prediction = kSigma * std::sqrt(with_["rank"].get<double>() / kTrain);
  std::printf("compensation on the compliant actual (%d poses, %.2f s): RMS %.3g m (max %.3g; prediction error "
              "sigma sqrt(p/N) %.3g m), 3x held-out RMS %.3g m; uncompensated RMS %.3g m (max %.3g)\n",
              kProgram, seconds(start), compensated.rms, compensated.max, prediction, 3 * validation,
              uncompensated.rms, uncompensated.max);
  EXPECT_LE(compensated.rms, 3 * validation);
  EXPECT_GT(uncompensated.rms, 3 * validation);  // the check can fail: the commands must differ from the program
}

TEST_F(CompliantLoop, VerticalFirstAxisIsRefusedByName) {
  expectRejected("calibrate " + kNominal + " --measurements " + train_ + " --compliance 1",
                 "joint 1 (j1): its gravity load does not vary over the 200 poses (0 N m to 0 N m), no load at all",
                 "--compliance: ");
}

}  // namespace
