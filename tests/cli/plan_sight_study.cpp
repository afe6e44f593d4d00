// The done-when's held-out half (issue 28, docs/plan.md "Line of sight"; label `study`, `make study`): on the
// Menagerie-style cell with collisions and a tracker, the 20 planned poses calibrate an actual cell (the elbow's
// axis 0.3 mm off, wrist 1 tilted 1 mrad; 1e-5 m noise) no worse, on 200 held-out poses, than the median of 100
// random sets of 20 of the same feasible candidates. About 210 simulate + calibrate runs: 4 s here.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "plan_sight_helpers.hpp"

using lowpair_test::runCli;
using lowpair_test::scratch;
using lowpair_test::writeScratchFile;
using nlohmann::json;

namespace {

const std::string& kYaml = plan_sight::kCellYaml;
const std::string& kXml = plan_sight::kCellXml;

json jsonOf(const std::string& args) {
  const lowpair_test::CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r.status == 0 ? json::parse(r.out) : json::object();
}

// Held-out RMS position after calibrating the nominal on the actual cell measured at `q` (noise seed `seed`).
double heldOut(const std::string& actual, const std::string& validation, const std::vector<std::vector<double>>& q,
               int seed) {
  std::string csv;
  for (size_t i = 0; i < q[0].size(); ++i) csv += (i ? ",q" : "q") + std::to_string(i + 1);
  csv += "\n";
  for (const auto& row : q) {
    for (size_t i = 0; i < row.size(); ++i) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", row[i]);
      csv += (i ? "," : "") + std::string(buf);
    }
    csv += "\n";
  }
  const std::string q_path = writeScratchFile("study_q.csv", csv), m = scratch() + "/study_m.csv";
  EXPECT_EQ(runCli("simulate " + actual + " --q-file " + q_path + " --measure targets --noise-position 1e-5 --seed " +
                   std::to_string(seed) + " --out " + m).status, 0);
  const json c = jsonOf("calibrate " + kYaml + " --measurements " + m + " --validation " + validation +
                        " --noise-position 1e-5 --json");
  return c.empty() ? 1.0 : c["validation"]["after"]["rms_position"].get<double>();
}

}  // namespace

TEST(PlanSightStudy, PlannedFeasibleSetCalibratesNoWorseThanTheMedianRandomFeasibleSet) {
  const std::string actual_path = plan_sight::actualCell();
  ASSERT_FALSE(actual_path.empty());
  const std::string validation = scratch() + "/study_val.csv";
  ASSERT_EQ(runCli("simulate " + actual_path + " --poses 200 --measure targets --noise-position 1e-5 --seed 99 --out " +
                   validation).status, 0);
  const std::string plan = "plan " + kYaml + " --model " + kXml + " --tip tool --measure targets --tracker 1.2,-0.6,0.8 "
                           "--candidates 3000 --json --poses ";
  const json planned = jsonOf(plan + "20");
  ASSERT_FALSE(planned.empty());
  const int kept = planned["feasibility"]["kept"];
  const json all = jsonOf(plan + std::to_string(kept));  // every feasible candidate
  ASSERT_FALSE(all.empty());
  const auto feasible = all["q"].get<std::vector<std::vector<double>>>();
  // the plan's held-out RMS: the median over 5 noise seeds; each random set gets one of the same 5 seeds
  std::vector<double> plan_rms, random_rms;
  for (int s = 1; s <= 5; ++s) plan_rms.push_back(heldOut(actual_path, validation, planned["q"], s));
  std::mt19937_64 rng(7);
  for (int k = 0; k < 100; ++k) {
    std::vector<std::vector<double>> set;
    std::sample(feasible.begin(), feasible.end(), std::back_inserter(set), 20, rng);
    random_rms.push_back(heldOut(actual_path, validation, set, 1 + k % 5));
  }
  std::sort(plan_rms.begin(), plan_rms.end());
  std::sort(random_rms.begin(), random_rms.end());
  const double plan_median = plan_rms[2], random_median = 0.5 * (random_rms[49] + random_rms[50]);
  std::printf("feasible %d; held-out RMS: planned %.4g (median of 5 seeds), random sets of 20: median %.4g, best %.4g, "
              "worst %.4g\n", kept, plan_median, random_median, random_rms.front(), random_rms.back());
  EXPECT_LE(plan_median, random_median);
}
