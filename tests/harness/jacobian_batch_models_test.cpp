// computeJacobiansBatch on every bundled robot (models/*.yaml) and the benchmarks' 4-joint arm
// (tests/data/bench/rrpr_arm.yaml): each file's own description (POE or D-H) and its POE model, every row equal to
// the single computeJacobians + get to rounding (tests/common/jacobian_batch_check.hpp), at 13 configurations (three
// 4-lane blocks and a partial one; one 8-lane block and a partial one) drawn over the joint ranges.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "io/robot_file.hpp"
#include "jacobian_batch_check.hpp"
#include "random_robot.hpp"

using namespace lowpair;
using jacobian_batch_check::batchMismatch;

namespace {

std::vector<std::string> robotFiles() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(LOWPAIR_MODELS)) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path().string());
  }
  files.push_back(std::string(LOWPAIR_TEST_DATA) + "/bench/rrpr_arm.yaml");
  return files;
}

}  // namespace

TEST(JacobiansBatch, EqualsSingleFormOnEveryBundledRobot) {
  const std::vector<std::string> files = robotFiles();
  ASSERT_GE(files.size(), 10u);  // models/ holds 9 robot files, plus the arm: a wrong folder would test nothing
  std::mt19937_64 rng(295);
  for (const std::string& path : files) {
    const io::RobotFile file = io::readRobotFile(path);
    const PoeModel poe = file.poeModel();
    MatX q(13, poe.dof());
    for (Eigen::Index k = 0; k < q.rows(); ++k) q.row(k) = lowpair_test::randomConfiguration(poe, rng).transpose();
    EXPECT_LE(batchMismatch(poe, q, poe.lengthScale()), 1.0) << path << " (POE)";
    if (file.dh) {
      EXPECT_LE(batchMismatch(*file.dh, q, file.dh->lengthScale()), 1.0) << path << " (D-H)";
    }
  }
}
