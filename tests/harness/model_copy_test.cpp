// Kinematics-only model copies for MuJoCo 2.2.2 (harness/model_copy.hpp) and what MujocoRobot accepts
// through them (issue 10; issue 11 findings 8 and 9). The files are in tests/data/mjcf and
// tests/data/urdf_mujoco; the expected geometry is written by hand in their header comments and here.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <unistd.h>

#include "mujoco/model_copy.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::mujoco;

namespace lowpair {
namespace {

namespace fs = std::filesystem;

std::string data(const std::string& rel) { return std::string(LOWPAIR_TEST_DATA) + "/" + rel; }

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// The note that mentions `part`, or "" (with every note in the failure message).
std::string noteWith(const std::vector<std::string>& notes, const std::string& part) {
  for (const auto& n : notes) {
    if (contains(n, part)) return n;
  }
  return "";
}

std::string joined(const std::vector<std::string>& notes) {
  std::string s;
  for (const auto& n : notes) s += n + "\n";
  return s;
}

Mat3 rot(const Vec3& axis, double angle) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }
Pose trans(double x, double y, double z) {
  Pose T;
  T.p = Vec3(x, y, z);
  return T;
}
Pose rotation(const Vec3& axis, double angle) {
  Pose T;
  T.R = rot(axis, angle);
  return T;
}

void expectPoseNear(const Pose& actual, const Pose& expected, double tol, const std::string& what) {
  EXPECT_LE((actual.p - expected.p).norm(), tol) << what << "\n" << actual.p.transpose() << "\n" << expected.p.transpose();
  EXPECT_LE((actual.R - expected.R).norm(), tol) << what << "\n" << actual.R << "\n" << expected.R;
}

void expectTwist(const Joint& j, JointType type, const Vec6& twist) {
  EXPECT_EQ(j.type, type) << j.name;
  EXPECT_LE((j.twist - twist).norm(), 1e-15) << j.name << ": " << j.twist.transpose() << " vs " << twist.transpose();
}

Vec6 twist(double w0, double w1, double w2, double v0, double v1, double v2) {
  Vec6 t;
  t << w0, w1, w2, v0, v1, v2;
  return t;
}

// Temporary copies go to a folder of this test's own, so leftovers can be counted.
class ModelCopyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tmp_ = fs::temp_directory_path() / ("lowpair_model_copy_test_" + std::to_string(::getpid()));
    fs::create_directories(tmp_);
    old_tmpdir_ = std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "";
    ::setenv("TMPDIR", tmp_.c_str(), 1);
  }
  void TearDown() override {
    if (old_tmpdir_.empty()) {
      ::unsetenv("TMPDIR");
    } else {
      ::setenv("TMPDIR", old_tmpdir_.c_str(), 1);
    }
    fs::remove_all(tmp_);
  }
  size_t leftovers() const { return static_cast<size_t>(std::distance(fs::directory_iterator(tmp_), fs::directory_iterator())); }

  // A RobotFileError from MujocoRobot (the CLI's exit status 2) naming the file and every part.
  void expectRejected(const std::string& path, const std::string& tip, std::initializer_list<std::string> parts) {
    try {
      const MujocoRobot robot(path, tip);
      ADD_FAILURE() << path << ": accepted";
    } catch (const RobotFileError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
      for (const auto& part : parts) EXPECT_TRUE(contains(msg, part)) << "missing '" << part << "' in: " << msg;
    }
    EXPECT_EQ(leftovers(), 0u) << path << ": a temporary copy was left behind";
  }

  fs::path tmp_;
  std::string old_tmpdir_;
};

// ---- MJCF written for MuJoCo >= 2.3 ----

TEST_F(ModelCopyTest, NewerMjcfLoadsAndTheNotesNameWhatWasDropped) {
  const std::string path = data("mjcf/newer_mujoco.xml");
  std::vector<std::string> notes;
  std::string copy_path;
  {
    const ModelCopy copy(path, &notes);
    copy_path = copy.path();
    ASSERT_TRUE(fs::exists(copy_path));
    EXPECT_EQ(fs::path(copy_path).parent_path(), tmp_);
    const std::string text = readText(copy_path);
    // geometry, assets and everything else kinematics does not need is gone; the include is inlined
    for (const char* gone : {"<geom", "<mesh", "<asset", "<actuator", "<sensor", "<camera", "<light", "<contact",
                             "<keyframe", "<visual", "<statistic", "<size", "<tendon", "<include", "<position",
                             "kv=", "resolution=", "implicitfast", "gravcomp", "actuatorfrcrange", "meshdir",
                             "material="}) {
      EXPECT_FALSE(contains(text, gone)) << gone << " still in the copy:\n" << text;
    }
    // the file's settings stay, ours are merged into its <compiler>, comments survive
    EXPECT_TRUE(contains(text, "angle=\"radian\" inertiafromgeom=\"true\"")) << text;  // no geoms left: bounded
    EXPECT_TRUE(contains(text, "autolimits=\"true\"")) << text;
    EXPECT_TRUE(contains(text, "boundmass=\"1e-6\" boundinertia=\"1e-9\"")) << text;
    EXPECT_TRUE(contains(text, "timestep=\"0.002\"")) << text;
    EXPECT_TRUE(contains(text, "the rest of the arm lives in an included file")) << text;
    EXPECT_TRUE(contains(text, "included by newer_mujoco.xml inside link1")) << text;
    EXPECT_TRUE(contains(text, "<site name=\"tool\"")) << text;
  }
  EXPECT_FALSE(fs::exists(copy_path)) << "the copy outlived its ModelCopy";
  EXPECT_EQ(leftovers(), 0u);

  // one note per attribute MuJoCo 2.2.2 does not know, with the file and line it was written on
  EXPECT_EQ(noteWith(notes, "integrator"),
            path + ": line 10: dropped <option integrator='implicitfast'>: not known to MuJoCo 2.2.2, no effect on kinematics")
      << joined(notes);
  EXPECT_EQ(noteWith(notes, "gravcomp"),
            path + ": line 34: dropped <body gravcomp='1'>: not known to MuJoCo 2.2.2, no effect on kinematics")
      << joined(notes);
  EXPECT_TRUE(contains(noteWith(notes, "actuatorfrcrange"), "line 35: dropped <joint actuatorfrcrange='-50 50'>"))
      << joined(notes);
  // and one line saying what kinematics did not need (cameras with resolution, actuators with kv, the
  // meshes whose files do not exist went wholesale)
  const std::string summary = noteWith(notes, "not needed for kinematics");
  for (const char* what : {"4 <geom>", "2 <camera>", "1 <light>", "1 <asset>", "1 <actuator>", "1 <sensor>", "1 <contact>",
                           "1 <keyframe>", "1 <tendon>", "1 <visual>", "1 <statistic>", "1 <size>"}) {
    EXPECT_TRUE(contains(summary, what)) << what << " not in: " << joined(notes);
  }
  EXPECT_EQ(notes.size(), 4u) << joined(notes);
}

TEST_F(ModelCopyTest, NewerMjcfKinematicsMatchTheHandWrittenGeometry) {
  const std::string path = data("mjcf/newer_mujoco.xml");
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  const MujocoRobot robot(path, "tool");
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  // the notes on stderr, one "note: " line each
  std::istringstream lines(err);
  int count = 0;
  for (std::string line; std::getline(lines, line); ++count) EXPECT_EQ(line.rfind("note: " + path + ": ", 0), 0u) << line;
  EXPECT_EQ(count, 4) << err;
  EXPECT_TRUE(contains(err, "dropped <option integrator='implicitfast'>")) << err;

  const PoeModel& poe = robot.poeModel();
  ASSERT_EQ(poe.dof(), 3);
  expectTwist(poe.joint(0), JointType::Revolute, twist(0, 0, 1, 0, 0, 0));        // z through (0, 0, 0.5)
  expectTwist(poe.joint(1), JointType::Revolute, twist(0, -1, 0, 0.8, 0, 0));     // -y through (0, 0, 0.8)
  expectTwist(poe.joint(2), JointType::Prismatic, twist(0, 0, 0, 1, 0, 0));       // along x
  expectPoseNear(poe.toolPose(), Pose{rot(Vec3::UnitX(), M_PI / 2), Vec3(0.4, 0, 1.0)}, 1e-15, "tool at qpos0");
  // ranges from the default class, limited by autolimits (2.2.2 would refuse a range without limited)
  ASSERT_TRUE(poe.joint(0).range.has_value());
  EXPECT_EQ(*poe.joint(0).range, (std::array<double, 2>{-2, 2}));
  ASSERT_TRUE(poe.joint(2).range.has_value());
  EXPECT_EQ(*poe.joint(2).range, (std::array<double, 2>{-0.1, 0.3}));

  // MuJoCo's tip at x (qpos = qpos0 + x; j1's ref 0.3 is its zero) against the body chain written out
  MujocoRobot::Evaluator mujoco(robot);
  for (const Vec3& x : {Vec3(0, 0, 0), Vec3(0.7, -1.2, 0.25), Vec3(-2.9, 0.4, -0.1), Vec3(1.5707963267948966, 3.0, 0.05)}) {
    const Pose expected = trans(0, 0, 0.5) * rotation(Vec3::UnitZ(), x[0]) * trans(0, 0, 0.3) *
                          rotation(Vec3::UnitX(), M_PI / 2) * rotation(Vec3::UnitZ(), x[1]) * trans(0.4 + x[2], 0, 0) *
                          trans(0, 0.2, 0);
    expectPoseNear(mujoco.tipPose(x), expected, 1e-14, "x = " + std::to_string(x[0]) + " " + std::to_string(x[1]));
  }
  EXPECT_EQ(leftovers(), 0u);
}

TEST_F(ModelCopyTest, ShippedModelsLoadWithoutNotes) {
  for (const char* model : {"panda.xml", "puma560_okamura_actual.xml", "rhino_xr3_slide.xml"}) {
    std::vector<std::string> notes;
    const ModelCopy copy(std::string(LOWPAIR_MODELS) + "/" + model, &notes);
    EXPECT_TRUE(notes.empty()) << model << ": " << joined(notes);
  }
}

TEST_F(ModelCopyTest, IncludeOfAnIncludedFileIsRejected) {
  const fs::path dir = tmp_ / "includes";
  fs::create_directories(dir);
  std::ofstream(dir / "main.xml") << "<mujoco>\n<include file=\"part.xml\"/>\n<include file=\"part.xml\"/>\n</mujoco>\n";
  std::ofstream(dir / "part.xml") << "<mujoco><worldbody/></mujoco>\n";
  try {
    const ModelCopy copy((dir / "main.xml").string());
    ADD_FAILURE() << "accepted";
  } catch (const RobotFileError& e) {
    EXPECT_TRUE(contains(e.what(), "main.xml: line 3: <include file='part.xml'>: the file is already included")) << e.what();
  }
  fs::remove_all(dir);
  EXPECT_EQ(leftovers(), 0u);
}

// ---- unknown attributes and elements that could shape kinematics: errors naming them, never dropped ----

TEST_F(ModelCopyTest, UnknownKinematicAttributesAndElementsAreErrors) {
  expectRejected(data("mjcf/unknown_joint_attribute.xml"), "tool",
                 {"MuJoCo could not load the model: unrecognized attribute: 'offset' on <joint>",
                  "unknown_joint_attribute.xml: line 5", "<joint> shapes the kinematics"});
  expectRejected(data("mjcf/alignfree_compiler.xml"), "tool",
                 {"unrecognized attribute: 'alignfree' on <compiler>", "alignfree_compiler.xml: line 3"});
  expectRejected(data("mjcf/frame_element.xml"), "tool", {"element <frame>", "frame_element.xml: line 7", "not known to MuJoCo 2.2.2"});
}

// ---- issue 11 finding 8: what the extraction cannot represent is rejected input (exit 2) ----

TEST_F(ModelCopyTest, OneHingeDrivingTwoSlidesIsRejected) {
  expectRejected(data("mjcf/two_slides_one_hinge.xml"), "tool",
                 {"<equality><joint joint1='s2' joint2='h'>", "the hinge 'h' already drives the slide 's1'"});
}

TEST_F(ModelCopyTest, AbsurdRefIsRejected) {
  expectRejected(data("mjcf/huge_ref.xml"), "tool", {"joint 'j1'", "qpos0 (its ref) 1e+308 is no usable zero"});
}

// ---- finding 9: closed loops and couplings of chain joints are rejected, naming the element ----

TEST_F(ModelCopyTest, ClosedLoopsThroughTheChainAreRejected) {
  expectRejected(data("mjcf/connect_loop.xml"), "tool",
                 {"<equality><connect body1='link2' body2='world' name='four_bar'> closes a loop through the chain joint"});
  expectRejected(data("mjcf/weld_tip.xml"), "tool",
                 {"<equality><weld body1='tool' body2='world'> closes a loop through the chain joint 'j1'"});
}

TEST_F(ModelCopyTest, TendonAndFixedJointEqualitiesOnChainJointsAreRejected) {
  expectRejected(data("mjcf/tendon_coupling.xml"), "tool",
                 {"<equality><tendon tendon1='sum' name='hold'> couples the chain joint 'j"});
  expectRejected(data("mjcf/locked_joint.xml"), "tool", {"<equality><joint joint1='j2' name='lock'> fixes the chain joint 'j2'"});
}

TEST_F(ModelCopyTest, LoopsAndCouplingsBeyondTheTipAreIgnored) {
  const MujocoRobot robot(data("mjcf/loop_beyond_tip.xml"), "tool");
  ASSERT_EQ(robot.dof(), 1);
  expectTwist(robot.poeModel().joint(0), JointType::Revolute, twist(0, 0, 1, 0, 0, 0));
  expectPoseNear(robot.poeModel().toolPose(), trans(1, 0, 0.5), 1e-15, "tool");
  // the same loop is a rejection once the tip is a finger (its joint closes it)
  expectRejected(data("mjcf/loop_beyond_tip.xml"), "finger_a", {"<equality><connect body1='finger_a' body2='finger_b'>"});
}

// ---- URDF ----

TEST_F(ModelCopyTest, UrdfWithMujocoBlockPackageMeshesAndMasslessLinks) {
  const std::string path = data("urdf_mujoco/mujoco_block.urdf");
  std::vector<std::string> notes;
  {
    const ModelCopy copy(path, &notes);
    const std::string text = readText(copy.path());
    EXPECT_FALSE(contains(text, "filename=\"package://")) << text;
    EXPECT_FALSE(contains(text, "<visual")) << text;
    EXPECT_FALSE(contains(text, "<collision")) << text;
    EXPECT_TRUE(contains(text, "<inertial")) << text;
    EXPECT_TRUE(contains(text, "not_this_one")) << "the leading comment was lost:\n" << text;
    // one <mujoco> block: the file's, its angle and mass bound kept, ours added
    EXPECT_EQ(text.find("<compiler"), text.rfind("<compiler")) << text;
    EXPECT_EQ(text.find("</mujoco>"), text.rfind("</mujoco>")) << text;
    for (const char* setting : {"angle=\"radian\"", "boundmass=\"0.001\"", "fusestatic=\"false\"", "boundinertia=\"1e-9\"",
                                "discardvisual=\"true\"", "strippath=\"false\""}) {
      EXPECT_TRUE(contains(text, setting)) << setting << " not in:\n" << text;
    }
  }
  EXPECT_TRUE(contains(noteWith(notes, "fusestatic"), "line 9: compiler fusestatic='true' replaced by 'false'")) << joined(notes);
  EXPECT_TRUE(contains(noteWith(notes, "not needed for kinematics"), "2 <collision>, 2 <visual>")) << joined(notes);

  ::testing::internal::CaptureStderr();
  const MujocoRobot robot(path, "tool0");
  ::testing::internal::GetCapturedStderr();
  const PoeModel& poe = robot.poeModel();
  ASSERT_EQ(poe.dof(), 2);
  expectTwist(poe.joint(0), JointType::Revolute, twist(0, 0, 1, 0, 0, 0));      // z through (0, 0, 0.2)
  expectTwist(poe.joint(1), JointType::Revolute, twist(0, 1, 0, -0.4, 0, 0));   // y through (0, 0, 0.4)
  expectPoseNear(poe.toolPose(), Pose{rot(Vec3::UnitY(), M_PI / 2), Vec3(0.3, 0, 0.6)}, 1e-15, "tool0");
  EXPECT_EQ(*poe.joint(0).range, (std::array<double, 2>{-3, 3}));
  EXPECT_FALSE(poe.joint(1).range.has_value());  // continuous

  MujocoRobot::Evaluator mujoco(robot);
  for (const Eigen::Vector2d& x : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.9, -0.4), Eigen::Vector2d(-2.5, 2.2)}) {
    const Pose expected = trans(0, 0, 0.2) * rotation(Vec3::UnitZ(), x[0]) * trans(0, 0, 0.2) * rotation(Vec3::UnitY(), x[1]) *
                          trans(0.3, 0, 0.2) * rotation(Vec3::UnitY(), M_PI / 2);
    expectPoseNear(mujoco.tipPose(x), expected, 1e-14, "x = " + std::to_string(x[0]) + " " + std::to_string(x[1]));
  }
  EXPECT_EQ(leftovers(), 0u);
}

TEST_F(ModelCopyTest, UrdfMimicInTheChainIsRejected) {
  expectRejected(data("urdf_mujoco/mimic_helical.urdf"), "carriage",
                 {"joint 'screw_slide' mimics 'screw' (URDF <mimic>), which MuJoCo 2.2.2 ignores"});
  // a chain that stops before the mimicking joint is fine
  const MujocoRobot robot(data("urdf_mujoco/mimic_helical.urdf"), "nut");
  EXPECT_EQ(robot.dof(), 1);
}

TEST_F(ModelCopyTest, FilesThatAreNotModelsAreErrors) {
  expectRejected(data("mjcf/no_such_file.xml"), "tool", {"cannot open file"});
  expectRejected(std::string(LOWPAIR_MODELS) + "/panda.yaml", "tool", {"not well-formed XML"});
}

}  // namespace
}  // namespace lowpair
