// The collision copy (ModelCopy with CopyContent::Collision, model_copy.hpp) and CollisionChecker
// (collision_check.hpp): what the copy keeps (geoms, meshes whose files exist, contact excludes), and the
// contacts and their kinds at configurations whose geometry is worked out by hand for
// tests/data/mjcf/feasible_arm.xml (metres: column 0..0.3 at the origin, shoulder link 0.3 long at z = 0.3,
// upper arm 0.4, forearm 0.35, hand 0.12; a box fixture around (0.55, 0.35)).

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>

#include <unistd.h>

#include "mujoco/collision_check.hpp"
#include "mujoco/model_copy.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair {
namespace {

using namespace lowpair::mujoco;
namespace fs = std::filesystem;

const std::string kArm = std::string(LOWPAIR_TEST_DATA) + "/mjcf/feasible_arm.xml";

VecX q4(double a, double b, double c, double d) {
  VecX q(4);
  q << a, b, c, d;
  return q;
}

// The body pairs of a report as names, "a|b" with the names sorted.
std::vector<std::string> pairNames(const ContactReport& r, const CollisionChecker& c) {
  std::vector<std::string> out;
  for (const auto& [b1, b2] : r.bodies) {
    std::string x = c.bodyName(b1), y = c.bodyName(b2);
    if (y < x) std::swap(x, y);
    out.push_back(x + "|" + y);
  }
  return out;
}

bool has(const std::vector<std::string>& v, const std::string& x) { return std::find(v.begin(), v.end(), x) != v.end(); }

TEST(CollisionChecker, ContactsAndTheirKindsOnTheArm) {
  const MujocoRobot robot(kArm, "tool");
  CollisionChecker checker(robot, std::nullopt);
  EXPECT_EQ(checker.collisionGeoms(), 6);
  // stretched out, turned away from the fixture: free
  EXPECT_EQ(checker.contactsAt(q4(-1.5, 0, 0, 0)).contacts, 0);
  // turned towards the fixture (atan2(0.35, 0.55)): the upper arm goes through the box, world geometry
  const ContactReport fixture = checker.contactsAt(q4(0.567, 0, 0, 0));
  EXPECT_GT(fixture.contacts, 0);
  EXPECT_EQ(fixture.kind, ContactKind::World);
  EXPECT_TRUE(has(pairNames(fixture, checker), "fixture|upper"));
  // upper arm raised 0.5 rad, forearm folded back over it: the hand lands on the shoulder link (self); the
  // forearm passes the shoulder link too, but <exclude> removes that pair, and the column (parent of the
  // shoulder, welded to the world) is excluded from the shoulder
  const ContactReport folded = checker.contactsAt(q4(0, -0.5, 3.276, 0));
  EXPECT_GT(folded.contacts, 0);
  EXPECT_EQ(folded.kind, ContactKind::Self);
  const auto names = pairNames(folded, checker);
  EXPECT_TRUE(has(names, "hand|shoulder")) << ::testing::PrintToString(names);
  EXPECT_FALSE(has(names, "forearm|shoulder"));
  // upper arm pointing down 1.2 rad: below z = 0 at its end, but nothing is there without a floor
  EXPECT_EQ(checker.contactsAt(q4(0, 1.2, 0, 0)).contacts, 0);
}

TEST(CollisionChecker, FloorInTheBaseFrame) {
  const MujocoRobot robot(kArm, "tool");
  CollisionChecker checker(robot, 0.0);
  EXPECT_EQ(checker.collisionGeoms(), 6);  // the floor is not counted
  const ContactReport down = checker.contactsAt(q4(0, 1.2, 0, 0));
  EXPECT_GT(down.contacts, 0);
  EXPECT_EQ(down.kind, ContactKind::Floor);
  EXPECT_TRUE(has(pairNames(down, checker), "floor|upper")) << ::testing::PrintToString(pairNames(down, checker));
  EXPECT_EQ(checker.contactsAt(q4(-1.5, 0, 0, 0)).contacts, 0);  // z = 0.3 everywhere, radius 0.04
  // a floor above the shoulder: the shoulder link (child of the column, which is welded to the world) meets it
  CollisionChecker high(robot, 0.5);
  const ContactReport r = high.contactsAt(q4(-1.5, 0, 0, 0));
  EXPECT_EQ(r.kind, ContactKind::Floor);
  EXPECT_TRUE(has(pairNames(r, high), "floor|shoulder"));
}

// A binary STL tetrahedron, faces outward.
void writeTetrahedron(const fs::path& path) {
  const float v[4][3] = {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {0, 0, 0.1f}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::ofstream out(path, std::ios::binary);
  const char header[80] = {};
  out.write(header, 80);
  const std::uint32_t n = 4;
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& f : faces) {
    const float normal[3] = {0, 0, 0};
    out.write(reinterpret_cast<const char*>(normal), sizeof normal);
    for (const int i : f) out.write(reinterpret_cast<const char*>(v[i]), 3 * sizeof(float));
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

TEST(CollisionCopy, KeepsGeomsAndMeshesWhoseFilesExist) {
  const fs::path folder = fs::temp_directory_path() / ("lowpair_collision_copy_" + std::to_string(::getpid()));
  fs::create_directories(folder / "meshes");
  writeTetrahedron(folder / "meshes" / "tet.stl");
  const fs::path model = folder / "model.xml";
  std::ofstream(model) << R"(<mujoco>
  <compiler meshdir="meshes"/>
  <asset>
    <texture name="grid" type="2d" builtin="checker" width="8" height="8" rgb1="1 1 1" rgb2="0 0 0"/>
    <material name="red" rgba="1 0 0 1" texture="grid"/>
    <mesh name="tet" file="tet.stl"/>
    <mesh name="gone" file="gone.stl"/>
  </asset>
  <worldbody>
    <geom name="table" type="box" size="0.5 0.5 0.01" material="red"/>
    <body name="link" pos="0 0 0.2">
      <joint name="j" type="hinge" axis="0 0 1"/>
      <geom name="solid" type="mesh" mesh="tet" material="red"/>
      <geom name="missing" type="mesh" mesh="gone"/>
      <site name="tool" pos="0.1 0 0"/>
    </body>
  </worldbody>
  <contact><exclude body1="world" body2="link"/></contact>
</mujoco>
)";
  std::vector<std::string> notes;
  {
    const ModelCopy copy(model.string(), &notes, CopyContent::Collision);
    char error[1000] = "";
    std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(copy.path().c_str(), nullptr, error, sizeof error),
                                                   mj_deleteModel);
    ASSERT_TRUE(m) << error;
    EXPECT_EQ(m->ngeom, 2);  // the table and the tetrahedron
    EXPECT_EQ(m->nmesh, 1);
    EXPECT_EQ(m->nmat, 0);
    EXPECT_EQ(m->nexclude, 1);
    EXPECT_GE(mj_name2id(m.get(), mjOBJ_GEOM, "solid"), 0);
    EXPECT_EQ(mj_name2id(m.get(), mjOBJ_GEOM, "missing"), -1);
  }
  bool noted = false;
  for (const auto& n : notes) noted = noted || n.find("mesh file 'gone.stl' not found") != std::string::npos;
  EXPECT_TRUE(noted);
  {
    const ModelCopy kinematics(model.string(), nullptr);  // the kinematics copy keeps none of it
    char error[1000] = "";
    std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(kinematics.path().c_str(), nullptr, error, sizeof error),
                                                   mj_deleteModel);
    ASSERT_TRUE(m) << error;
    EXPECT_EQ(m->ngeom, 0);
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace lowpair
