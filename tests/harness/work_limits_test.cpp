// The arithmetic of the work limits the CLI and the Python module share (harness/commands/limits.hpp,
// simulation.hpp; docs/cli.md "Limits"), at their boundaries, where running the command at the limit takes
// minutes: the IK work (rows x seeds x 100 iterations x joints), the simulated rows (rows, joints, joint values).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "commands/arguments.hpp"
#include "commands/limits.hpp"
#include "commands/simulation.hpp"

using namespace lowpair;
using namespace lowpair::commands;

// 5.6e9 joint-iterations: the default 8 seeds at 10^6 rows of a 7-joint robot, not one more
TEST(WorkLimitsArithmetic, IkWorkIsTheDefaultSeedsAtTheRowLimitOfASevenJointRobot) {
  EXPECT_FALSE(ikWorkProblem(1000000, 8, 7, true));
  EXPECT_FALSE(ikWorkProblem(1000000, 8, 6, true));
  EXPECT_TRUE(ikWorkProblem(1000001, 8, 7, true));
  EXPECT_TRUE(ikWorkProblem(1000000, 8, 8, true));  // an 8-joint robot: fewer rows or seeds
  // 1000 seeds of the 6-joint PUMA: 9333 rows (the CLI test refuses 9334 at once)
  EXPECT_FALSE(ikWorkProblem(9333, 1000, 6, true));
  const auto over = ikWorkProblem(9334, 1000, 6, true);
  ASSERT_TRUE(over);
  EXPECT_NE(over->find("at most 9333 rows at 1000 seeds, or at most 999 seeds for 9334 rows"), std::string::npos) << *over;
  // one attempt per row (a row's own seed, compensate): 56,000 rows of 1000 joints, the widest a CSV holds
  EXPECT_FALSE(ikWorkProblem(56000, 1, 1000, false));
  const auto wide = ikWorkProblem(56001, 1, 1000, false);
  ASSERT_TRUE(wide);
  EXPECT_EQ(wide->rfind("56001 rows x 100 iterations x 1000 joints = 5600100000 exceed the IK work limit", 0), 0u) << *wide;
  EXPECT_NE(wide->find("at most 56000 rows at 1 attempt"), std::string::npos) << *wide;
  EXPECT_EQ(wide->find("seeds for"), std::string::npos) << *wide;  // no seeds to lower
}

// simulate: 10^6 rows, 1000 joints, 1e8 joint values, whichever comes first
TEST(WorkLimitsArithmetic, SimulatedRowsAreWhatAMeasurementFileHolds) {
  MeasurementSetup setup;
  setup.measure = Measure::Pose;
  EXPECT_EQ(simulationRows(1000000, 100, setup, "--poses", "R"), 1000000);
  EXPECT_EQ(simulationRows(100000, 1000, setup, "--poses", "R"), 100000);
  EXPECT_THROW(simulationRows(1000001, 1, setup, "--poses", "R"), UsageError);
  EXPECT_THROW(simulationRows(100001, 1000, setup, "--poses", "R"), UsageError);
  try {
    simulationRows(1, 1001, setup, "--poses", "R");
    ADD_FAILURE() << "1001 joints taken";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.subject(), "R");
  }
}

// plan: the greedy steps alone at most the exchange budget (2e11): poses x candidates x rows x (columns + rows +
// columns^2); the blocks and their stacked SVD before that
TEST(WorkLimitsArithmetic, PlanSizeNamesWhatIsOver) {
  const double per = 6.0 * (40.0 + 6.0 + 40.0 * 40.0);  // a pose of 6 rows and 40 parameters
  const double most = 2e11 / (1000.0 * per);
  EXPECT_FALSE(planSizeProblem(std::floor(most), 1000, 6, 40, 2e11, false));
  const auto greedy = planSizeProblem(std::floor(most) + 1, 1000, 6, 40, 2e11, false);
  ASSERT_TRUE(greedy);
  EXPECT_FALSE(greedy->robot);
  EXPECT_NE(greedy->text.find("exceed the plan's work limit"), std::string::npos) << greedy->text;
  const auto blocks = planSizeProblem(100000, 1, 6, 40, 2e11, false);  // 2.4e7 numbers
  ASSERT_TRUE(blocks);
  EXPECT_NE(blocks->text.find("exceed the identification size limit (1e+07 numbers"), std::string::npos) << blocks->text;
  const auto one = planSizeProblem(1, 1, 3000, 4000, 2e11, true);  // one candidate alone: the robot is named
  ASSERT_TRUE(one);
  EXPECT_TRUE(one->robot);
}
