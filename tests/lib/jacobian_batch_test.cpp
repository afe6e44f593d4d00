// computeJacobiansBatch (jacobian.hpp): every row equals the single computeJacobians + get to rounding
// (tests/common/jacobian_batch_check.hpp derives the bound), on random robots of every joint type and geometry
// (tests/common/random_robot.hpp), POE and D-H, at counts that fill no, one, several and partial SIMD blocks; the
// libm fallback for huge joint values; the size checks. The bundled robots: tests/harness/jacobian_batch_models_test.cpp.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "expect_invalid.hpp"
#include "jacobian_batch_check.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "random_robot.hpp"

using namespace lowpair;
using jacobian_batch_check::batchMismatch;

namespace {

MatX randomConfigurations(const PoeModel& model, Eigen::Index count, std::mt19937_64& rng) {
  MatX q(count, model.dof());
  for (Eigen::Index k = 0; k < count; ++k) q.row(k) = lowpair_test::randomConfiguration(model, rng).transpose();
  return q;
}

}  // namespace

TEST(JacobiansBatch, EqualsSingleFormOnRandomRobots) {
  std::mt19937_64 rng(291);
  double worst_poe = 0.0, worst_dh = 0.0;
  const int robots = lowpair_test::robotCount(300);
  for (int r = 0; r < robots; ++r) {
    const lowpair_test::RandomRobot robot = lowpair_test::randomRobot(rng);
    const PoeModel& model = robot.model;
    const DhConversion conversion = poeToDh(model);
    // 0 .. 18 rows: none, a partial 4- or 8-lane block, whole blocks and a remainder
    const MatX q = randomConfigurations(model, r % 19, rng);
    const double e_poe = batchMismatch(model, q, model.lengthScale());
    // the D-H table's own scale max(L, |d|, |a|) (docs/conversion.md): near parallel axes |d| can be 1e10 L
    const double e_dh = batchMismatch(conversion.model, q, conversion.scale);
    EXPECT_LE(e_poe, 1.0) << "robot " << r << " (" << lowpair_test::geometryName(robot.geometry) << "), POE";
    EXPECT_LE(e_dh, 1.0) << "robot " << r << " (" << lowpair_test::geometryName(robot.geometry) << "), D-H";
    worst_poe = std::max(worst_poe, e_poe);
    worst_dh = std::max(worst_dh, e_dh);
  }
  RecordProperty("worst_poe_over_bound", std::to_string(worst_poe));
  RecordProperty("worst_dh_over_bound", std::to_string(worst_dh));
}

TEST(JacobiansBatch, CountsZeroAndOne) {
  std::mt19937_64 rng(292);
  const PoeModel model = lowpair_test::randomRobot(rng).model;
  MatX jacobians(0, 6 * model.dof()), poses(0, 12);
  EXPECT_NO_THROW(computeJacobiansBatch(model, MatX(0, model.dof()), JacobianFrame::Body, jacobians, poses));
  EXPECT_LE(batchMismatch(model, randomConfigurations(model, 1, rng), model.lengthScale()), 1.0);
}

TEST(JacobiansBatch, WritesIntoBlocksOfLargerMatrices) {
  // outputs that are the top rows of taller matrices (column stride != rows), as a caller working in chunks passes
  std::mt19937_64 rng(296);
  const PoeModel model = lowpair_test::randomRobot(rng).model;
  const int n = model.dof();
  const MatX q = randomConfigurations(model, 11, rng);
  MatX jacobians(11, 6 * n), poses(11, 12), tall_jacobians = MatX::Constant(32, 6 * n, 7.0), tall_poses(32, 12);
  for (const JacobianFrame frame : {JacobianFrame::Spatial, JacobianFrame::Body, JacobianFrame::Geometric}) {
    computeJacobiansBatch(model, q, frame, jacobians, poses);
    computeJacobiansBatch(model, q, frame, tall_jacobians.topRows(11), tall_poses.topRows(11));
    EXPECT_TRUE(tall_jacobians.topRows(11) == jacobians);
    EXPECT_TRUE(tall_poses.topRows(11) == poses);
    EXPECT_TRUE((tall_jacobians.bottomRows(21).array() == 7.0).all());  // nothing written beyond the block
  }
}

TEST(JacobiansBatch, HugeJointValuesFallBackToLibm) {
  // beyond the sine kernel's range (|angle| > 1e6) the whole call uses libm, as the single form does
  std::mt19937_64 rng(293);
  for (int r = 0; r < 20; ++r) {
    const PoeModel model = lowpair_test::randomRobot(rng).model;
    MatX q = randomConfigurations(model, 7, rng);
    q(3, 0) = 3e7;  // one value of one row
    EXPECT_LE(batchMismatch(model, q, model.lengthScale()), 1.0) << "robot " << r;
  }
}

TEST(JacobiansBatch, RejectsWrongSizes) {
  std::mt19937_64 rng(294);
  PoeModel model = lowpair_test::randomRobot(rng).model;
  while (model.dof() != 6) model = lowpair_test::randomRobot(rng).model;
  const DhModel dh = poeToDh(model).model;
  MatX jacobians(10, 36), poses(10, 12), narrow(10, 30), short_poses(9, 12);
  const auto spatial = JacobianFrame::Spatial;
  lowpair_test::expectInvalid([&] { computeJacobiansBatch(model, MatX::Zero(10, 5), spatial, jacobians, poses); },
                "computeJacobiansBatch: q has 5 columns, the model has 6 joints");
  lowpair_test::expectInvalid([&] { computeJacobiansBatch(dh, MatX::Zero(10, 6), spatial, jacobians, short_poses); },
                "computeJacobiansBatch: poses is 9 x 12, expected 10 x 12 (a row per configuration of q)");
  lowpair_test::expectInvalid([&] { computeJacobiansBatch(model, MatX::Zero(10, 6), spatial, narrow, poses); },
                "computeJacobiansBatch: jacobians is 10 x 30, expected 10 x 36 (a row per configuration of q, 6 "
                "columns per joint)");
  EXPECT_NO_THROW(computeJacobiansBatch(dh, MatX::Zero(10, 6), spatial, jacobians, poses));
}
