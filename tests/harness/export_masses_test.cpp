// Masses through lowpair export (issue 27, "Written and used"): a robot file's link masses, payload and gravity
// written into the URDF's and MJCF's inertials, read back by MuJoCo (harness/mujoco/mujoco_dynamics.hpp: the
// bodies' masses and centres of mass lumped per link, nothing of lowpair's export code), give the same masses
// and MuJoCo's gravity force equals the library's gravityTorques of the original file at random poses. The
// compliance and backlash, which neither format holds, go to the side file and read back from it.
//
// Bound of the gravity comparison: 64 eps sum_k m_k |g| 2L, the rounding of sums of products of that size (as
// mujoco_dynamics_test.cpp). models/puma560_masses.yaml gives joint 1's link no mass: the export puts the
// token mass kExportMass at that link's frame origin, on joint 1's vertical axis, where its weight has no
// moment about any joint axis it loads (joint 1's alone).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "io/export.hpp"
#include "io/robot_file.hpp"
#include "lowpair/gravity.hpp"
#include "mujoco/mujoco_dynamics.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "scratch_folder.hpp"

using namespace lowpair;
using namespace lowpair::io;
using namespace lowpair::mujoco;
using export_helpers::scratch;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

const std::string kPuma = std::string(LOWPAIR_MODELS) + "/puma560_masses.yaml";

// The exported file read back by MuJoCo: the stated masses (the payload lumped into the last link, to which it
// is welded), the same gravity, the same gravity force as the library's on the original at 50 random poses.
void expectSameLoads(const RobotFile& file, ExportFormat format, const std::string& name) {
  const std::string path = scratch().write(name, exportRobot(file, format, {}).text);
  const MujocoRobot robot(path, "tool");
  const MujocoDynamics dynamics(robot);
  ASSERT_EQ(dynamics.masses().status, MassStatus::Ok) << massProblem(dynamics.masses(), path);
  const MassModel& stated = *file.masses;
  const MassModel& read = dynamics.masses().masses;
  ASSERT_EQ(read.links.size(), stated.links.size());
  const double L = file.poeModel().lengthScale();
  const size_t last = stated.links.size() - 1;
  for (size_t j = 0; j < stated.links.size(); ++j) {
    if (stated.links[j].mass == 0.0) {
      EXPECT_EQ(read.links[j].mass, kExportMass) << j;  // the token mass a moving body needs
      continue;
    }
    const double m = stated.links[j].mass + (j == last ? stated.payload.mass : 0.0);
    EXPECT_NEAR(read.links[j].mass, m, 4 * kEps * m) << j;
    if (j < last) {
      EXPECT_LE((read.links[j].com - stated.links[j].com).norm(), 64 * kEps * L) << j;
    }
  }
  EXPECT_LE((read.gravity - stated.gravity).norm(), 4 * kEps * stated.gravity.norm());

  const PoeModel poe = file.poeModel();
  double total = stated.payload.mass;
  for (const PointMass& p : stated.links) total += p.mass;
  const double bound = 64 * kEps * total * stated.gravity.norm() * 2 * L;
  MujocoDynamics::Evaluator eval(dynamics);
  std::mt19937_64 rng(2727);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int sample = 0; sample < 50; ++sample) {
    VecX q(poe.dof());
    for (Eigen::Index i = 0; i < q.size(); ++i) q[i] = angle(rng);
    const VecX tau = eval.gravityForce(q);  // every scale 1, every offset 0: the exported motion is q
    EXPECT_LE((gravityTorques(poe, stated, q) - tau).cwiseAbs().maxCoeff(), bound) << q.transpose();
    ASSERT_GT(tau.cwiseAbs().maxCoeff(), 1.0);  // a load worth comparing: the arm's links weigh kilograms
  }
}

TEST(ExportMasses, MjcfCarriesLinkMassesPayloadAndGravity) {
  const RobotFile file = readRobotFile(kPuma);
  ASSERT_TRUE(file.masses.has_value());
  ASSERT_GT(file.masses->payload.mass, 0.0);
  expectSameLoads(file, ExportFormat::Mjcf, "puma_masses.xml");
}

TEST(ExportMasses, UrdfCarriesLinkMassesAndThePayloadOnTheToolLink) {
  expectSameLoads(readRobotFile(kPuma), ExportFormat::Urdf, "puma_masses.urdf");
}

// Another gravity (the base turned on its side): the MJCF's <option gravity> is the file's, and MuJoCo's load follows.
TEST(ExportMasses, MjcfCarriesTheFilesGravity) {
  RobotFile file = readRobotFile(kPuma);
  file.masses->gravity = Vec3(9.81, 0.0, 0.0);
  expectSameLoads(file, ExportFormat::Mjcf, "puma_sideways.xml");
}

// A file without masses exports as before: token-mass inertials, zero gravity in the MJCF.
TEST(ExportMasses, WithoutMassesTheTokenMassesAndZeroGravityStay) {
  const RobotFile file = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_corke.yaml");
  ASSERT_FALSE(file.masses.has_value());
  const std::string mjcf = exportRobot(file, ExportFormat::Mjcf, {}).text;
  // every inertial the 1 g token mass (a simulator needs one), none other
  size_t token = 0, masses = 0;
  for (size_t at = mjcf.find("mass=\""); at != std::string::npos; at = mjcf.find("mass=\"", at + 1)) {
    ++masses;
    token += mjcf.compare(at, 12, "mass=\"0.001\"") == 0;
  }
  EXPECT_GT(masses, 0u);
  EXPECT_EQ(token, masses);
  EXPECT_NE(mjcf.find("gravity=\"0 0 0\""), std::string::npos);
  EXPECT_EQ(mjcf.find("payload"), std::string::npos);
  const std::string urdf = exportRobot(file, ExportFormat::Urdf, {}).text;
  EXPECT_EQ(urdf.find("Masses:"), std::string::npos);
}

// Compliance and backlash: a comment in the URDF/MJCF and the side file, which reads back with the same values.
TEST(ExportMasses, DeflectionsGoToTheSideFile) {
  RobotFile file = readRobotFile(kPuma);
  file.deflection.compliance = VecX::Zero(6);
  file.deflection.compliance[1] = 2e-5;  // rad per N m
  file.deflection.backlash = VecX::Zero(6);
  file.deflection.backlash[4] = 1e-3;  // rad
  for (const ExportFormat format : {ExportFormat::Urdf, ExportFormat::Mjcf}) {
    const ExportedRobot out = exportRobot(file, format, {});
    EXPECT_NE(out.text.find("Joint compliance and backlash"), std::string::npos) << exportFormatName(format);
    ASSERT_TRUE(out.joint_variables.has_value()) << exportFormatName(format);
    const RobotFile side = readRobotFile(scratch().write(std::string("side_") + exportFormatName(format) + ".yaml",
                                                         *out.joint_variables));
    EXPECT_EQ(side.deflection.compliance, file.deflection.compliance) << exportFormatName(format);
    EXPECT_EQ(side.deflection.backlash, file.deflection.backlash) << exportFormatName(format);
    ASSERT_TRUE(side.masses.has_value());
    EXPECT_EQ(side.masses->payload.mass, file.masses->payload.mass);
  }
}

}  // namespace
