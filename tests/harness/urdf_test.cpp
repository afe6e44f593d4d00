// URDF through urdfdom (harness/urdf_reader.hpp): the POE model read from a URDF against the URDF's own
// semantics composed by hand (origin * motion about the normalized axis, joint after joint), against
// MuJoCo's reading of the same file, the mimic-helical convention, and one-line errors.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <stdlib.h>  // mkdtemp

#include <console_bridge/console.h>

#include <Eigen/Geometry>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/robot_file.hpp"
#include "io/urdf_reader.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::mujoco;

namespace lowpair {
namespace {

namespace fs = std::filesystem;

std::string data(const std::string& name) { return std::string(LOWPAIR_TEST_DATA) + "/urdf/" + name; }

// A fresh folder for files written by a test (unique: other builds may run this test at the same time).
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "lowpair_urdf_test_XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string path = (path_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

 private:
  fs::path path_;
};

// ---- the URDF semantics, written out independently of the reader ---------------------------------

enum class Kind { Revolute, Continuous, Prismatic, Fixed };

// One <joint> as written in the file: origin xyz and rpy, axis (any length), limits.
struct UrdfJoint {
  std::string name;
  Kind kind;
  Eigen::Vector3d xyz, rpy, axis;
  std::optional<std::array<double, 2>> range;
};

constexpr double kHalfPi = 1.5707963267948966;
constexpr double kPi = 3.141592653589793;

// tests/data/urdf/arm6.urdf, joint for joint
const std::vector<UrdfJoint> kArm6 = {
    {"shoulder_pan", Kind::Revolute, {0, 0, 0.1625}, {0, 0, 0}, {0, 0, 2}, {{-3.1, 3.1}}},
    {"shoulder_lift", Kind::Revolute, {0.05, 0.138, 0}, {0, kHalfPi, 0}, {0, 3, 0}, {{-2, 2.5}}},
    {"boom", Kind::Prismatic, {0, -0.12, 0.425}, {0.3, -0.2, 0.1}, {1, 0, 1}, {{0, 0.3}}},
    {"flange3_joint", Kind::Fixed, {0, 0, 0.39225}, {0.1, 0.2, -0.3}, {0, 0, 0}, std::nullopt},
    {"wrist_roll", Kind::Continuous, {0.01, 0.02, 0.03}, {-kHalfPi, 0, 0}, {0, 0, -0.5}, std::nullopt},
    {"wrist_pitch", Kind::Revolute, {0, 0.093, 0}, {0.25, 0.5, 0.75}, {1, 2, 3}, {{-2.5, 2.5}}},
    {"wrist_yaw", Kind::Revolute, {0, 0, 0.09465}, {0, 0, kPi}, {0.001, 0, 0.25}, {{-6.28, 6.28}}},
    {"tool0_joint", Kind::Fixed, {0, 0.0823, 0}, {-kHalfPi, 0, 0}, {0, 0, 0}, std::nullopt},
};

// tests/data/urdf/helical.urdf, the chain to 'tool' (screw_slide mimics screw: 0.05 m/rad)
const std::vector<UrdfJoint> kHelical = {
    {"j1", Kind::Revolute, {0, 0, 0.4}, {0, 0, 0}, {0, 0, 1}, {{-3, 3}}},
    {"screw", Kind::Revolute, {0.3, 0.1, 0.2}, {kHalfPi, 0, 0.4}, {0, 0, 2}, {{-6, 6}}},
    {"screw_slide", Kind::Prismatic, {0, 0, 0}, {0, 0, 0}, {0, 0, 5}, {{-0.3, 0.3}}},
    {"j3", Kind::Revolute, {0, 0.2, 0.1}, {0, 0.3, 0}, {1, 0, 0}, {{-2, 2}}},
    {"tool_joint", Kind::Fixed, {0.1, 0, 0}, {0, 0, 0}, {0, 0, 0}, std::nullopt},
};
constexpr double kScrewPitch = 0.05;

// URDF origin: translation xyz, then fixed-axis roll-pitch-yaw R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Isometry3d origin(const UrdfJoint& j) {
  return Eigen::Translation3d(j.xyz) * Eigen::AngleAxisd(j.rpy.z(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(j.rpy.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(j.rpy.x(), Eigen::Vector3d::UnitX());
}

// The joint's motion in its own frame: a turn by `value` about, or a slide by `value` along, the unit axis.
Eigen::Isometry3d motion(const UrdfJoint& j, double value) {
  const Eigen::Vector3d u = j.axis.normalized();
  if (j.kind == Kind::Prismatic) return Eigen::Isometry3d(Eigen::Translation3d(value * u));
  return Eigen::Isometry3d(Eigen::AngleAxisd(value, u));
}

bool moves(const UrdfJoint& j) { return j.kind != Kind::Fixed; }

// T_base_tip: origin * motion, joint after joint; `values` holds one value per moving joint.
Eigen::Isometry3d handFk(const std::vector<UrdfJoint>& chain, const std::vector<double>& values) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  size_t k = 0;
  for (const UrdfJoint& j : chain) {
    T = T * origin(j);
    if (moves(j)) T = T * motion(j, values.at(k++));
  }
  EXPECT_EQ(k, values.size());
  return T;
}

// Seeded configurations inside each joint's limits (continuous joints over [-pi, pi]), the zero one first.
std::vector<std::vector<double>> configurations(const std::vector<UrdfJoint>& chain, int count) {
  std::mt19937_64 rng(20261124);
  std::vector<std::vector<double>> qs;
  std::vector<double> zero;
  for (const UrdfJoint& j : chain) {
    if (moves(j)) zero.push_back(0.0);
  }
  qs.push_back(zero);
  for (int s = 0; s < count; ++s) {
    std::vector<double> q;
    for (const UrdfJoint& j : chain) {
      if (!moves(j)) continue;
      const std::array<double, 2> r = j.range.value_or(std::array<double, 2>{-kPi, kPi});
      q.push_back(std::uniform_real_distribution<double>(r[0], r[1])(rng));
    }
    qs.push_back(q);
  }
  return qs;
}

VecX toVec(const std::vector<double>& q) {
  return Eigen::Map<const VecX>(q.data(), static_cast<Eigen::Index>(q.size()));
}

// Largest rotation-entry and translation differences between the library's pose and the hand product.
struct Deviation {
  double rotation = 0.0, translation = 0.0;
};
Deviation deviation(const Pose& T, const Eigen::Isometry3d& expected) {
  return {(T.R - expected.linear()).cwiseAbs().maxCoeff(), (T.p - expected.translation()).norm()};
}

// ---- (1) the arm: FK against the hand-composed URDF chain; names, types, ranges ------------------

TEST(UrdfArm, ForwardKinematicsEqualsHandComposedUrdfChain) {
  const RobotFile file = readUrdf(data("arm6.urdf"), "tool0");
  ASSERT_TRUE(file.poe);
  const PoeModel& model = *file.poe;
  ASSERT_EQ(model.dof(), 6);
  const double L = model.lengthScale();
  for (const auto& q : configurations(kArm6, 20)) {
    const Deviation d = deviation(poeForwardKinematics(model, toVec(q)), handFk(kArm6, q));
    EXPECT_LE(d.rotation, 1e-14) << "q[0] = " << q[0];
    EXPECT_LE(d.translation, 1e-14 * L) << "q[0] = " << q[0];
  }
}

TEST(UrdfArm, NamesTypesRangesAndUnitsAsWritten) {
  const RobotFile file = readUrdf(data("arm6.urdf"), "tool0");
  EXPECT_EQ(file.path, data("arm6.urdf"));
  EXPECT_EQ(file.name, "arm6");
  EXPECT_EQ(file.length_unit, "m");
  EXPECT_EQ(file.angle_unit, "rad");
  const PoeModel& model = *file.poe;
  std::vector<const UrdfJoint*> moving;
  for (const UrdfJoint& j : kArm6) {
    if (moves(j)) moving.push_back(&j);
  }
  ASSERT_EQ(model.dof(), static_cast<int>(moving.size()));
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& joint = model.joint(i);
    const UrdfJoint& written = *moving[static_cast<size_t>(i)];
    EXPECT_EQ(joint.name, written.name);
    EXPECT_EQ(joint.type, written.kind == Kind::Prismatic ? JointType::Prismatic : JointType::Revolute) << joint.name;
    EXPECT_EQ(joint.scale, 1.0) << joint.name;  // axes of any length are directions, not scales
    EXPECT_EQ(joint.offset, 0.0) << joint.name;
    EXPECT_EQ(joint.range, written.range) << joint.name;  // none for the continuous joint
  }
  EXPECT_FALSE(model.joint(3).range);  // wrist_roll is continuous
}

TEST(UrdfArm, BaseLinkInsideTheChain) {
  // from link2 (the child of shoulder_lift) to tool0: the hand product of the joints after it
  const RobotFile file = readUrdf(data("arm6.urdf"), "tool0", "link2");
  const PoeModel& model = *file.poe;
  const std::vector<UrdfJoint> tail(kArm6.begin() + 2, kArm6.end());
  ASSERT_EQ(model.dof(), 4);
  EXPECT_EQ(model.joint(0).name, "boom");
  for (const auto& q : configurations(tail, 10)) {
    const Deviation d = deviation(poeForwardKinematics(model, toVec(q)), handFk(tail, q));
    EXPECT_LE(d.rotation, 1e-14);
    EXPECT_LE(d.translation, 1e-14 * model.lengthScale());
  }
  // a tip inside the chain: the flange link after the middle fixed joint
  const RobotFile part = readUrdf(data("arm6.urdf"), "flange3");
  const std::vector<UrdfJoint> head(kArm6.begin(), kArm6.begin() + 4);
  ASSERT_EQ(part.poe->dof(), 3);
  for (const auto& q : configurations(head, 5)) {
    const Deviation d = deviation(poeForwardKinematics(*part.poe, toVec(q)), handFk(head, q));
    EXPECT_LE(d.rotation, 1e-14);
    EXPECT_LE(d.translation, 1e-14 * part.poe->lengthScale());
  }
}

TEST(UrdfArm, MeshlessVariantIsTheSameModel) {
  // arm6_nomesh.urdf (for MuJoCo) must carry exactly the kinematics of arm6.urdf
  const PoeModel a = *readUrdf(data("arm6.urdf"), "tool0").poe;
  const PoeModel b = *readUrdf(data("arm6_nomesh.urdf"), "tool0").poe;
  ASSERT_EQ(a.dof(), b.dof());
  for (int i = 0; i < a.dof(); ++i) {
    EXPECT_EQ(a.joint(i).name, b.joint(i).name);
    EXPECT_EQ(a.joint(i).twist, b.joint(i).twist);
    EXPECT_EQ(a.joint(i).range, b.joint(i).range);
  }
  EXPECT_EQ(a.toolPose().matrix(), b.toolPose().matrix());
}

TEST(UrdfArm, ParsingPrintsNothingAndRestoresConsoleBridge) {
  const console_bridge::LogLevel before = console_bridge::getLogLevel();
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  (void)readUrdf(data("arm6.urdf"), "tool0");
  EXPECT_THROW(readUrdf(data("malformed.urdf"), "tip"), RobotFileError);
  EXPECT_THROW(readUrdf(data("unsupported.urdf"), "tip_floating"), RobotFileError);
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
  EXPECT_EQ(console_bridge::getLogLevel(), before);
}

// ---- (2) the same arm through MuJoCo ----------------------------------------------------------------

void expectSameAsMujoco(const std::string& path) {
  const PoeModel model = *readUrdf(path, "tool0").poe;
  const MujocoRobot robot(path, "tool0");
  ASSERT_EQ(robot.dof(), model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    EXPECT_EQ(robot.joints()[static_cast<size_t>(i)].name, model.joint(i).name);
    EXPECT_EQ(robot.joints()[static_cast<size_t>(i)].type, model.joint(i).type);
  }
  MujocoRobot::Evaluator mujoco(robot);
  const double L = model.lengthScale();
  for (const auto& q : configurations(kArm6, 20)) {
    const Pose T = poeForwardKinematics(model, toVec(q));
    const Pose M = mujoco.tipPose(toVec(q));  // scale 1: MuJoCo's motion variables are the joint values
    EXPECT_LE((T.R - M.R).cwiseAbs().maxCoeff(), 1e-12) << path;
    EXPECT_LE((T.p - M.p).norm(), 1e-12 * L) << path;
  }
}

TEST(UrdfMujoco, MeshlessArmGivesMujocosForwardKinematics) { expectSameAsMujoco(data("arm6_nomesh.urdf")); }

// the file itself: MuJoCo reads it through a kinematics-only copy (package:// meshes, the file's own
// <mujoco> block and the commented <robot> must not get in the way)
TEST(UrdfMujoco, ArmWithMeshesGivesMujocosForwardKinematics) { expectSameAsMujoco(data("arm6.urdf")); }

// ---- (3) a revolute joint and a prismatic joint mimicking it on its axis: one helical joint ----------

TEST(UrdfMimic, PrismaticMimickingTheRevoluteBeforeItIsOneHelicalJoint) {
  const RobotFile file = readUrdf(data("helical.urdf"), "tool");
  const PoeModel& model = *file.poe;
  ASSERT_EQ(model.dof(), 3);  // j1, screw (helical), j3; the finger mimic and the floating camera are off the chain
  EXPECT_EQ(model.joint(0).type, JointType::Revolute);
  const Joint& screw = model.joint(1);
  EXPECT_EQ(screw.name, "screw");
  EXPECT_EQ(screw.type, JointType::Helical);
  EXPECT_NEAR(screw.pitch, kScrewPitch, 1e-16);
  EXPECT_EQ(screw.scale, 1.0);
  EXPECT_EQ(screw.range, (std::array<double, 2>{-6, 6}));  // the revolute's limits
  EXPECT_EQ(model.joint(2).name, "j3");

  for (const auto& q3 : configurations({kHelical[0], kHelical[1], kHelical[3]}, 20)) {
    // the URDF chain with four moving joints: the slide follows the screw, 0.05 * q along its axis
    const std::vector<double> q4 = {q3[0], q3[1], kScrewPitch * q3[1], q3[2]};
    const Deviation d = deviation(poeForwardKinematics(model, toVec(q3)), handFk(kHelical, q4));
    EXPECT_LE(d.rotation, 1e-14);
    EXPECT_LE(d.translation, 1e-14 * model.lengthScale());
  }
}

TEST(UrdfMimic, SlideAgainstTheRevoluteAxisGivesNegativePitch) {
  std::ifstream in(data("helical.urdf"));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string axis = "<axis xyz=\"0 0 5\"/>";
  ASSERT_NE(text.find(axis), std::string::npos) << "helical.urdf changed: update this test";
  text.replace(text.find(axis), axis.size(), "<axis xyz=\"0 0 -5\"/>");
  const TempDir dir;
  const PoeModel model = *readUrdf(dir.write("reversed.urdf", text), "tool").poe;
  ASSERT_EQ(model.dof(), 3);
  EXPECT_EQ(model.joint(1).type, JointType::Helical);
  EXPECT_NEAR(model.joint(1).pitch, -kScrewPitch, 1e-16);
}

// ---- (4) errors: one line, starting with the file ------------------------------------------------

void expectError(const std::string& path, const std::string& tip, const std::string& base,
                 const std::vector<std::string>& mentions) {
  try {
    (void)readUrdf(path, tip, base);
    ADD_FAILURE() << path << " --tip " << tip << ": no error";
  } catch (const RobotFileError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    for (const std::string& m : mentions) EXPECT_NE(what.find(m), std::string::npos) << "'" << m << "' in: " << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << " --tip " << tip << ": not a RobotFileError: " << e.what();
  }
}

TEST(UrdfErrors, UnsupportedJointsAreNamed) {
  const std::string f = data("unsupported.urdf");
  expectError(f, "tip_floating", "", {"'free'", "floating"});
  expectError(f, "tip_planar", "", {"'slider2d'", "planar"});
  expectError(f, "tip_mimic_offset", "", {"'offset_slide'", "offset"});
  expectError(f, "tip_mimic_nonadjacent", "", {"'far_slide'", "'r0'", "just before"});
  expectError(f, "tip_mimic_axis", "", {"'tilted_slide'", "same axis line"});
  expectError(f, "tip_mimic_revolute", "", {"'twin'", "revolute joint cannot mimic"});
  expectError(f, "tip_mimic_double", "", {"'slide_twice'", "already mimicked"});
  expectError(f, "tip_zero_axis", "", {"'dead'", "zero axis"});
}

TEST(UrdfErrors, UnknownOrUnrelatedLinks) {
  const std::string f = data("arm6.urdf");
  expectError(f, "no_such_link", "", {"tip 'no_such_link' is not a link"});
  expectError(f, "tool0", "no_such_base", {"base 'no_such_base' is not a link"});
  expectError(f, "link2", "link4", {"base 'link4' is not an ancestor of tip 'link2'"});
  expectError(f, "tool0", "tool0", {"no moving joint"});
  expectError(f, "tool0", "link6", {"no moving joint"});  // only the fixed tool joint
  // a link off the chain is not an ancestor either
  expectError(data("helical.urdf"), "tool", "camera", {"not an ancestor"});
}

TEST(UrdfErrors, FilesThatAreNotUrdf) {
  expectError(data("malformed.urdf"), "tip", "", {"not a valid URDF"});
  expectError(data("empty.urdf"), "tip", "", {"not a valid URDF: empty file"});
  expectError(data(""), "tip", "", {"is a directory"});
  expectError(data("no_such_file.urdf"), "tip", "", {"cannot open file"});

  const TempDir dir;
  const auto write = [&](const std::string& name, const std::string& bytes) { return dir.write(name, bytes); };
  // binary junk; Latin-1 in an otherwise valid file; a NUL byte after a valid document
  expectError(write("junk.png.urdf", std::string("\x89PNG\r\n\x1a\n\xff\xfe\x00\x01", 12)), "tip", "",
              {"not a valid URDF"});
  expectError(write("junk.urdf", "\xc3\x28\xa0\xa1\xe2\x28\xa1\xf0\x90\x28\xbc"), "tip", "", {"not UTF-8"});
  expectError(write("latin1.urdf", "<robot name=\"caf\xe9\"><link name=\"a\"/></robot>"), "a", "", {"not UTF-8"});
  expectError(write("nul.urdf", std::string("<robot name=\"r\"><link name=\"a\"/></robot>") + '\0' + "<x"), "a", "",
              {"NUL"});
  // XML that is not a URDF, and a joint whose parent link does not exist
  expectError(write("not_robot.urdf", "<?xml version=\"1.0\"?><mujoco model=\"m\"/>"), "a", "", {"not a valid URDF"});
  expectError(write("dangling.urdf",
                    "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"continuous\">"
                    "<parent link=\"nowhere\"/><child link=\"b\"/></joint></robot>"),
              "b", "", {"not a valid URDF"});
  // a joint name with a newline stays on one line in the message
  expectError(write("newline.urdf",
                    "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>"
                    "<joint name=\"bad&#10;name\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/>"
                    "<limit effort=\"1\" velocity=\"1\"/></joint></robot>"),
              "b", "", {"planar"});
}

TEST(UrdfErrors, HostileNumbersAndTrees) {
  const TempDir dir;
  const std::string two_links = "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>";
  expectError(dir.write("nan.urdf", two_links + "<joint name=\"j\" type=\"continuous\"><parent link=\"a\"/>"
                                                "<child link=\"b\"/><origin xyz=\"nan 0 0\"/></joint></robot>"),
              "b", "", {"not a valid URDF", "[j]"});
  expectError(dir.write("limits.urdf", two_links + "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>"
                                                   "<child link=\"b\"/><limit lower=\"2\" upper=\"1\" effort=\"1\" "
                                                   "velocity=\"1\"/></joint></robot>"),
              "b", "", {"(j)", "lo > hi"});
  // a loop that urdfdom accepts (the root is elsewhere): the walk up from the tip must end
  expectError(dir.write("cycle.urdf", "<robot name=\"r\"><link name=\"r\"/><link name=\"a\"/><link name=\"b\"/>"
                                      "<link name=\"c\"/><joint name=\"j0\" type=\"continuous\"><parent link=\"r\"/>"
                                      "<child link=\"c\"/></joint><joint name=\"j1\" type=\"continuous\">"
                                      "<parent link=\"a\"/><child link=\"b\"/></joint><joint name=\"j2\" "
                                      "type=\"continuous\"><parent link=\"b\"/><child link=\"a\"/></joint></robot>"),
              "b", "", {"not an ancestor"});
}

// ---- (5) poe2dh on the arm: the D-H table reproduces the URDF's FK --------------------------------

TEST(UrdfDh, ArmConvertsToDhWithTheSameForwardKinematics) {
  const PoeModel model = *readUrdf(data("arm6.urdf"), "tool0").poe;
  const DhConversion dh = poeToDh(model);
  ASSERT_EQ(dh.model.dof(), 6);
  for (const auto& q : configurations(kArm6, 20)) {
    const Deviation d = deviation(dhForwardKinematics(dh.model, toVec(q)), handFk(kArm6, q));
    EXPECT_LE(d.rotation, 1e-13);
    EXPECT_LE(d.translation, 1e-13 * dh.scale);
  }
  const FkCheck check = checkDhConversion(model, dh.model);
  EXPECT_LE(check.max_translation, 1e-13 * check.scale);
}

}  // namespace
}  // namespace lowpair
