// LineOfSight (line_of_sight.hpp) on tests/data/mjcf/feasible_arm.xml, whose world geometry is worked out by hand
// (metres): the column, a capsule on the z axis from 0 to 0.3 of radius 0.06 (so it ends at z = 0.36), and the
// fixture box centred at (0.55, 0.35, 0.25) with half sizes 0.12 (x from 0.43 to 0.67), 0.12, 0.25; an optional
// floor at z = 0. Points just inside and just outside each surface (1 mm), rays through the box, and the SMR's
// stop distance on both sides of a face.

#include <gtest/gtest.h>

#include "mujoco/collision_check.hpp"
#include "mujoco/line_of_sight.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair {
namespace {

using namespace lowpair::mujoco;

const std::string kArm = std::string(LOWPAIR_TEST_DATA) + "/mjcf/feasible_arm.xml";

// the arm turned away from the fixture and stretched (free: collision_check_test), so rays near the fixture and
// the column meet only them
const VecX& away() {
  static const VecX q = (VecX(4) << -1.5, 0, 0, 0).finished();
  return q;
}

TEST(LineOfSight, PointsInsideAndOutsideTheWorldGeometry) {
  const MujocoRobot robot(kArm, "tool");
  CollisionChecker checker(robot, 0.0);
  ASSERT_EQ(checker.contactsAt(away()).contacts, 0);
  const LineOfSight sight(checker);
  const auto holder = [&](double x, double y, double z) {
    const int g = sight.worldGeomHolding(Vec3(x, y, z));
    return g < 0 ? std::string("none") : sight.geomText(g);
  };
  const std::string box = "geom 'fixture_box' of body 'fixture'", column = "geom 'column' of body 'base'";
  EXPECT_EQ(holder(0.55, 0.35, 0.25), box);
  EXPECT_EQ(holder(0.669, 0.35, 0.25), box);  // 1 mm inside the +x face
  EXPECT_EQ(holder(0.671, 0.35, 0.25), "none");
  EXPECT_EQ(holder(0.55, 0.35, 0.499), box);  // 1 mm under the top face: the +z ray leaves through it
  EXPECT_EQ(holder(0.55, 0.35, 0.501), "none");  // above it: only the -z ray meets the box
  EXPECT_EQ(holder(0, 0, 0.15), column);
  EXPECT_EQ(holder(0.059, 0, 0.15), column);
  EXPECT_EQ(holder(0.061, 0, 0.15), "none");
  EXPECT_EQ(holder(0, 0, 0.359), column);  // in the upper hemisphere
  EXPECT_EQ(holder(0, 0, 0.361), "none");  // above it the shoulder link is a moving body: not the world's
  EXPECT_EQ(holder(1, 1, -0.001), "the floor");
  EXPECT_EQ(holder(1, 1, 0.001), "none");
}

TEST(LineOfSight, RaysMeetTheFirstGeomBeforeTheSmrsRadius) {
  const MujocoRobot robot(kArm, "tool");
  CollisionChecker checker(robot, std::nullopt);
  ASSERT_EQ(checker.contactsAt(away()).contacts, 0);
  const LineOfSight sight(checker);
  const Vec3 tracker(2, 0.35, 0.25);
  const auto blocker = [&](double x, double stop) {
    const int g = sight.blocker(tracker, Vec3(x, 0.35, 0.25), stop);
    return g < 0 ? std::string("clear") : sight.geomText(g);
  };
  const std::string box = "geom 'fixture_box' of body 'fixture'";
  EXPECT_EQ(blocker(0.42, 0.019), box);      // behind the box: the ray crosses it
  EXPECT_EQ(blocker(0.68, 0.019), "clear");  // in front of its +x face
  // a centre 15 mm inside the +x face (an SMR resting on it, sunk in): the face is within the last 19 mm, not
  // an obstacle; with a 10 mm stop it is one
  EXPECT_EQ(blocker(0.655, 0.019), "clear");
  EXPECT_EQ(blocker(0.655, 0.010), box);
  // the tracker within the stop distance of the SMR: nothing between them
  EXPECT_EQ(sight.blocker(tracker, tracker + Vec3(0.01, 0, 0), 0.019), -1);
  // the base frame is the world's here
  EXPECT_TRUE(sight.T_world_base().R.isIdentity(0.0));
  EXPECT_TRUE(sight.T_world_base().p.isZero(0.0));
}

}  // namespace
}  // namespace lowpair
