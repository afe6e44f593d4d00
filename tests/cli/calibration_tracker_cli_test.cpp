// calibrate on tracker data (docs/calibration.md "Tracker data"): blunders named, refused or weighed down,
// another robot's or shuffled measurements refused, parameter levels and cross-validation. simulate's tracker
// options and the tracker scenario cases are in tracker_cli_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "calibration_cli_helpers.hpp"
#include "cli_runner.hpp"
#include "csv_text.hpp"

// ---- tracker data (docs/calibration.md "Tracker data") --------------------------------------------------

namespace {

using namespace lowpair_test;
using namespace calibration_cli;
namespace fs = std::filesystem;

// The data lines `simulate --blunders` lists in its comments ("# blunders: 63:75 92:104 ..." as
// measurement:line pairs).
std::vector<long long> blunderLines(const std::string& csv_path) {
  std::ifstream in(csv_path);
  std::vector<long long> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("# blunders: ", 0) != 0 || line.find(':', 12) == std::string::npos || line.find(" measurements") != std::string::npos) continue;
    std::stringstream pairs(line.substr(12));
    for (std::string pair; pairs >> pair;) lines.push_back(std::stoll(pair.substr(pair.find(':') + 1)));
  }
  return lines;
}

const std::string kTracker = " --measure targets --targets smr_a,smr_b,smr_c --frame 0.3,-1.2,2.0,3000,-800,400";

}  // namespace

// A tracker 3 m away, 3 SMRs with unknown points, 5 % blunders of 5 mm: least squares is refused (exit 1,
// nothing written, the blunders' lines named first); Huber and Cauchy flag exactly the blunders' lines, are
// accepted, write the SMRs' points, and predict held-out points to the noise.
TEST(CalibrateTracker, BlundersAreNamedRefusedOrWeighedDown) {
  const std::string fit = simulateTo("tracker.csv", kMujocoActual + kTracker +
                                                        " --poses 100 --seed 3 --noise-position 0.01 --blunders 15,5");
  const std::string held = simulateTo("tracker_v.csv", kMujocoActual + kTracker + " --poses 100 --seed 4");
  const std::vector<long long> blunders = blunderLines(fit);
  ASSERT_EQ(blunders.size(), 15u);
  const std::string out = scratch() + "/tracker_cal.yaml";
  const std::string base = "calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(fit) + " --validation " +
                           shellQuote(held) + " --noise-position 0.01 --free-pitch --out " + shellQuote(out);
  const CliRun squared = runCli(base);
  EXPECT_EQ(squared.status, 1) << squared.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(std::count(squared.err.begin(), squared.err.end(), '\n'), 1) << squared.err;
  EXPECT_EQ(squared.err.rfind("error: " + fit + ": calibration rejected, nothing written: variance factor", 0), 0u)
      << squared.err;
  // the five worst lines named are blunders
  const size_t at = squared.err.find("worst lines ");
  ASSERT_NE(at, std::string::npos);
  std::stringstream named(squared.err.substr(at + 12));
  for (int k = 0; k < 5; ++k) {
    long long line = 0;
    std::string rest;
    named >> line >> rest;
    EXPECT_NE(std::find(blunders.begin(), blunders.end(), line), blunders.end()) << "line " << line << " named";
  }
  for (const char* loss : {"huber", "cauchy"}) {
    fs::remove(out);
    const CliRun r = runCli(base + " --loss " + loss + " --json");
    ASSERT_EQ(r.status, 0) << loss << ": " << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["accepted"].get<bool>());
    std::vector<long long> flagged;
    for (const auto& m : j["residuals"]) {
      if (m["outlier"].get<bool>()) flagged.push_back(m["line"].get<long long>());
    }
    std::vector<long long> expected = blunders;
    std::sort(expected.begin(), expected.end());
    std::sort(flagged.begin(), flagged.end());
    EXPECT_EQ(flagged, expected) << loss;
    EXPECT_EQ(j["rank"].get<int>(), 5 * 6 + 6 + 3 * 3) << loss;  // helical 3-6 with free pitch, 3 targets
    EXPECT_LE(j["validation"]["after"]["rms_position"].get<double>(), 0.01) << loss;
    EXPECT_EQ(j["targets"].size(), 3u);
    EXPECT_EQ(j["measurement_frame"].size(), 4u);
    std::ifstream written(out);
    const std::string text((std::istreambuf_iterator<char>(written)), {});
    EXPECT_NE(text.find("targets:"), std::string::npos) << loss;
    EXPECT_NE(text.find("smr_b"), std::string::npos) << loss;
  }
}

// Measurements of another robot (the Stanford arm's for a 6-joint PUMA nominal) and the right robot's with
// the joint vectors shuffled across rows: exit 1, nothing written, with and without stated noise.
TEST(CalibrateTracker, AnotherRobotOrShuffledRowsAreRefused) {
  const std::string fit = simulateTo("verdict.csv", kMujocoActual + " --poses 40 --seed 8 --noise-position 0.01"
                                                                    " --noise-rotation 1e-5");
  std::ifstream in(fit);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::vector<size_t> data;
  for (size_t k = 0; k < lines.size(); ++k) {
    if (!lines[k].empty() && lines[k][0] != '#' && lines[k][0] != 'q') data.push_back(k);
  }
  std::string shuffled_text;
  std::vector<std::string> out = lines;
  for (size_t k = 0; k + 1 < data.size(); k += 2) {  // swap q1..q6 of neighbouring rows
    auto qs = [](const std::string& l) { size_t p = 0; for (int i = 0; i < 6; ++i) p = l.find(',', p) + 1; return p; };
    const std::string& a = lines[data[k]];
    const std::string& b = lines[data[k + 1]];
    out[data[k]] = b.substr(0, qs(b)) + a.substr(qs(a));
    out[data[k + 1]] = a.substr(0, qs(a)) + b.substr(qs(b));
  }
  for (const auto& l : out) shuffled_text += l + "\n";
  const std::string shuffled = writeScratchFile("shuffled.csv", shuffled_text);
  const std::string stanford =
      simulateTo("stanford.csv", shellQuote(modelPath("stanford_corke.yaml")) + " --poses 40 --seed 8");
  const std::string written = scratch() + "/verdict_cal.yaml";
  for (const std::string& data_file : {shuffled, stanford}) {
    for (const std::string& noise : {std::string(" --noise-position 0.01 --noise-rotation 1e-5"), std::string()}) {
      const CliRun r = runCli("calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(data_file) +
                              " --free-pitch --out " + shellQuote(written) + noise);
      EXPECT_EQ(r.status, 1) << data_file << noise << "\n" << r.err;
      EXPECT_EQ(r.err.rfind("error: " + data_file + ": calibration rejected, nothing written: ", 0), 0u) << r.err;
      EXPECT_FALSE(fs::exists(written));
    }
  }
}

// --select cv prints each level's cross-validated score and RMS and fits the level of the least score;
// --parameters offsets fits the joint offsets, the base and the tool only.
TEST(CalibrateTracker, ParameterLevelsAndCrossValidation) {
  const std::string fit = simulateTo("levels.csv", kMujocoActual + " --poses 30 --seed 9 --noise-position 0.01"
                                                                   " --noise-rotation 1e-5");
  const std::string base = "calibrate " + shellQuote(kNominal) + " --measurements " + shellQuote(fit) +
                           " --noise-position 0.01 --noise-rotation 1e-5 --free-pitch --json";
  const CliRun cv = runCli(base + " --select cv");
  ASSERT_LE(cv.status, 1) << cv.err;
  const auto j = nlohmann::json::parse(cv.out);
  ASSERT_EQ(j["cross_validation"]["candidates"].size(), 3u);
  EXPECT_EQ(j["cross_validation"]["folds"], 5);
  EXPECT_EQ(j["cross_validation"]["repeats"], 10);  // the documented default
  double best = 1e300;
  std::string best_name;
  for (const auto& c : j["cross_validation"]["candidates"]) {
    if (!c["failed"].get<bool>() && c["score"].get<double>() < best) {
      best = c["score"].get<double>();
      best_name = c["parameters"].get<std::string>();
    }
  }
  EXPECT_EQ(j["cross_validation"]["chosen"], best_name);
  EXPECT_EQ(j["parameter_set"], best_name);
  const CliRun offsets = runCli(base + " --parameters offsets");
  ASSERT_LE(offsets.status, 1) << offsets.err;
  const auto o = nlohmann::json::parse(offsets.out);
  EXPECT_EQ(o["parameter_set"], "offsets");
  for (const auto& p : o["parameters"]) {
    const std::string name = p["name"].get<std::string>();
    EXPECT_TRUE(name.find(".offset") != std::string::npos || name.rfind("base.", 0) == 0 || name.rfind("tool.", 0) == 0)
        << name;
  }
  expectRejected(base + " --parameters j1.offset,nonsense", "no parameter named 'nonsense'", kNominal);
  expectRejected(base + " --parameters offsets --select cv", "not both", "--select");
  expectRejected(base + " --select cv --repeats 0", "--repeats", "--repeats");
  // one partition: the candidates' scores differ from ten partitions' (the same choice is not promised)
  const CliRun once = runCli(base + " --select cv --repeats 1");
  ASSERT_LE(once.status, 1) << once.err;
  const auto j1 = nlohmann::json::parse(once.out);
  EXPECT_EQ(j1["cross_validation"]["repeats"], 1);
  EXPECT_NE(j1["cross_validation"]["candidates"][0]["score"], j["cross_validation"]["candidates"][0]["score"]);
}

// Fewer poses than folds is the argument's fault, named as such (it said "crossValidate: 3 poses for 20 folds"
// after the nominal's name); measurements that repeat one joint vector say so and how many are distinct.
TEST(CalibrateTracker, FoldsBeyondThePosesNameFoldsAndDuplicates) {
  const std::string fit = simulateTo("folds_fit.csv", kMujocoActual + " --poses 3 --seed 9 --noise-position 0.01");
  const std::string base = "calibrate " + shellQuote(kNominal) + " --select cv --measurements ";
  expectRejected(base + shellQuote(fit) + " --folds 20",
                 "--folds: 20 folds but " + fit + " holds 3 poses; cross-validation deals poses to folds and needs at "
                 "least as many poses as folds (at most 3 folds here, or more poses)",
                 "--folds");
  // one data row repeated 40 times
  std::ifstream in(fit);
  std::string text, line, row;
  bool header = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '#') {
      text += line + "\n";
    } else if (!header) {
      header = true;
      text += line + "\n";
    } else if (row.empty()) {
      row = line;
    }
  }
  for (int k = 0; k < 40; ++k) text += row + "\n";
  const std::string dup = writeScratchFile("folds_dup.csv", text);
  expectRejected(base + shellQuote(dup), "--folds: 5 folds but " + dup + " holds 1 pose: its 40 measurements repeat "
                 "joint vectors, 1 distinct", "--folds");
}

// A robust fit that flags every measurement has no variance factor because of the flags, not for want of
// data (120 target readings, rank 19): it said "variance factor none (no redundancy)".
TEST(CalibrateTracker, EveryReadingFlaggedIsSaidNotNoRedundancy) {
  const std::string data = simulateTo("all_flagged.csv", kMujocoActual + " --poses 40 --seed 3 --measure targets "
                                                                          "--targets smr_a,smr_b,smr_c --noise-position 0.01");
  // offsets only cannot follow the actual robot's geometry: residuals of tens of mm against 0.01 mm noise
  const CliRun r = runCli("calibrate " + shellQuote(modelPath("smr/puma560_okamura_nominal_smr.yaml")) + " --measurements " +
                          shellQuote(data) + " --loss huber --parameters offsets --noise-position 0.01");
  EXPECT_EQ(r.status, 1) << r.err;  // (more than a quarter flagged: rejected)
  EXPECT_NE(r.out.find("outliers (normalized residual > 5): 120 of 120"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("variance factor none (all 120 measurements were flagged as outliers, and it is estimated from "
                       "the others)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("no redundancy"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no variance factor: all 120 measurements were flagged"), std::string::npos) << r.out;
}
