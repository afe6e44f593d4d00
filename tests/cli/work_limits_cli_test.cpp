// The work limits of an identification (issue 30, docs/cli.md "Limits"; harness/commands/limits.hpp): many
// targets, many poses at the most folds and repeats, many candidates of many targets are refused before any
// work starts (exit 2, one line naming the argument and the limit); before, each ran for minutes to hours.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "cli_runner.hpp"
#include "targets_robot.hpp"

namespace {

using namespace lowpair_test;

const std::string kNominal = modelPath("puma560_okamura_nominal.yaml");

void expectRefusal(const std::string& args, const std::string& subject, const std::string& what) {
  const CliRun r = runCli(args);
  EXPECT_EQ(r.status, 2) << args << "\n" << r.out.substr(0, 500);
  EXPECT_EQ(r.err.rfind("error: " + subject + ": ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace

// identifiability with 1000 targets on 2 poses (before: killed at 120 s): one pose alone is over, so the robot
// file is named; 100 targets on 2 poses (work 2.6e8: about 1.5 s) are within
TEST(WorkLimits, IdentifiabilityOfManyTargetsIsRefusedBeforeTheWork) {
  const std::string many = nominalWithTargets(1000);
  expectRefusal("identifiability " + many + " --measure targets --poses 2", many, "exceed the identification");
  const std::string some = nominalWithTargets(100);
  const CliRun r = runCli("identifiability " + some + " --measure targets --poses 2");
  EXPECT_EQ(r.status, 0) << r.err;
}

// calibrate of 1,200 rows of 1000 targets (before: killed at 120 s): the fit's file is named
TEST(WorkLimits, CalibrateOfManyTargetsIsRefusedBeforeTheWork) {
  std::string csv = "q1,q2,q3,q4,q5,q6,target,x,y,z\n";
  for (int k = 0; k < 1200; ++k) csv += "0.1,0.2,0.3,0.4,0.5," + std::to_string(k / 1000) + ",t" + std::to_string(k % 1000) + ",1,2,3\n";
  const std::string path = writeScratchFile("many_targets.csv", csv);
  expectRefusal("calibrate " + kNominal + " --measurements " + path, path, "work per SVD");
}

// --select cv of 2,000 poses at 20 folds and 100 repeats: 6001 fits (before: about an hour); --repeats is named
TEST(WorkLimits, CrossValidationBeyondItsWorkIsRefusedNamingRepeats) {
  const std::string fit = scratch() + "/cv2000.csv";
  ASSERT_EQ(runCli("simulate " + modelPath("puma560_okamura_actual.yaml") + " --poses 2000 --seed 3 --out " + fit).status, 0);
  expectRefusal("calibrate " + kNominal + " --measurements " + fit + " --select cv --folds 20 --repeats 100", "--repeats",
                "exceed the cross-validation work limit");
}

// plan --poses 1000 from 46,296 candidates (before: 288 s; the greedy steps alone 153 s): --candidates is named
TEST(WorkLimits, PlanBeyondItsSearchWorkIsRefusedNamingCandidates) {
  expectRefusal("plan " + kNominal + " --poses 1000 --candidates 46296", "--candidates", "exceed the plan's work limit");
}

// plan of 1000 targets: the stacked candidates' SVD is over whatever --candidates says: the robot file is named
TEST(WorkLimits, PlanOfManyTargetsIsRefusedBeforeTheWork) {
  const std::string many = nominalWithTargets(1000);
  expectRefusal("plan " + many + " --measure targets --poses 1 --candidates 1", many, "exceed the identification");
}
