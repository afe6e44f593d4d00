// Robot files' masses and deflections (docs/file_formats.md "Masses, compliance, backlash"): per joint `mass`,
// `com`, `compliance`, `backlash`, top-level `payload:` and `gravity:`; read in the file's units, written by the POE
// and D-H writers and read back bit for bit (17 significant digits), bad values refused naming file, line and key,
// and inUnit converting the centres of mass.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "robot_file_helpers.hpp"
#include "scratch_folder.hpp"
#include "io/robot_file.hpp"
#include "lowpair/convert.hpp"

using namespace lowpair::io;

namespace lowpair {
namespace {

using export_helpers::scratch;

using robot_file_helpers::robotFileError;
using robot_file_helpers::sameBits;

std::string write(const std::string& name, const std::string& text) { return scratch().write(name, text); }


// A prismatic joint, then a revolute one, in mm and deg.
const std::string kHead =
    "name: two\n"
    "length_unit: mm\n"
    "angle_unit: deg\n"
    "poe:\n"
    "  joints:\n";
const std::string kTool = "  tool_pose: [[1, 0, 0, 200], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n";

TEST(RobotFileLoads, ReadInTheFileUnits) {
  const std::string path = write("loads.yaml", kHead +
      "    - {twist: [0, 0, 0, 0, 0, 1], mass: 12.5, com: [0, 0, 300], compliance: 2e-6, backlash: 0.01}\n"
      "    - {twist: [0, 1, 0, 0, 0, 100], mass: 4, com: [150, 0, 0], compliance: 1e-4, backlash: 0.05}\n" + kTool +
      "payload: {mass: 2, com: [0, 0, 30]}\n"
      "gravity: [0, 0, -9.80665]\n");
  const RobotFile f = readRobotFile(path);
  ASSERT_TRUE(f.masses.has_value());
  ASSERT_EQ(f.masses->links.size(), 2u);
  EXPECT_EQ(f.masses->links[0].mass, 12.5);
  EXPECT_EQ(f.masses->links[1].com, Vec3(150, 0, 0));
  EXPECT_EQ(f.masses->payload.mass, 2.0);
  EXPECT_EQ(f.masses->payload.com, Vec3(0, 0, 30));
  EXPECT_EQ(f.masses->gravity, Vec3(0, 0, -9.80665));
  EXPECT_EQ(f.masses->metres_per_unit, 1e-3);
  // a sliding joint's in length units; a turning one's in the angle unit, read in radians
  EXPECT_EQ(f.deflection.compliance[0], 2e-6);
  EXPECT_EQ(f.deflection.backlash[0], 0.01);
  EXPECT_DOUBLE_EQ(f.deflection.compliance[1], 1e-4 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(f.deflection.backlash[1], 0.05 * M_PI / 180.0);
}

TEST(RobotFileLoads, AbsentKeysLeaveNothing) {
  const RobotFile f = readRobotFile(write("plain.yaml", kHead +
      "    - {twist: [0, 0, 0, 0, 0, 1]}\n"
      "    - {twist: [0, 1, 0, 0, 0, 100]}\n" + kTool));
  EXPECT_FALSE(f.masses.has_value());
  EXPECT_TRUE(f.deflection.empty());
  // gravity alone: masses without links or payload (the default payload is massless)
  const RobotFile g = readRobotFile(write("gravity.yaml", kHead + "    - {twist: [0, 0, 0, 0, 0, 1]}\n" + kTool + "gravity: [0, -9.81, 0]\n"));
  ASSERT_TRUE(g.masses.has_value());
  EXPECT_TRUE(g.masses->links.empty());
  EXPECT_EQ(g.masses->gravity, Vec3(0, -9.81, 0));
}

TEST(RobotFileLoads, WrittenAndReadBackBitForBit) {
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const std::string angle_unit : {"rad", "deg"}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<JointSpec> specs(3);
      specs[0].twist << 0, 0, 1, 0, 0, 0;
      specs[1].twist << 0, 0, 0, 1, 0, 0;
      specs[2].twist << 0, 1, 0, 0, 0, 250 * u(rng);
      const PoeModel model(specs, Pose{});
      RobotFileExtras extras;
      MassModel m;
      for (int i = 0; i < 3; ++i) m.links.push_back({20.0 * std::abs(u(rng)), 500.0 * Vec3(u(rng), u(rng), u(rng))});
      m.payload = {3.0 * std::abs(u(rng)), 100.0 * Vec3(u(rng), u(rng), u(rng))};
      m.gravity = 9.81 * Vec3(u(rng), u(rng), u(rng));
      m.metres_per_unit = 1e-3;
      extras.masses = m;
      extras.deflection.compliance = 1e-5 * Vec3(u(rng), u(rng), u(rng));
      extras.deflection.backlash = 1e-3 * Vec3(u(rng), 0.0, u(rng));  // a zero: no key, read back as 0
      RobotFile like;
      like.length_unit = "mm";
      like.angle_unit = angle_unit;
      const std::string path = write("round.yaml", formatPoeRobotFile(model, like, "round", "", {}, extras));
      const RobotFile back = readRobotFile(path);
      ASSERT_TRUE(back.masses.has_value());
      for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(sameBits(back.masses->links[static_cast<size_t>(i)].mass, m.links[static_cast<size_t>(i)].mass));
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(sameBits(back.masses->links[static_cast<size_t>(i)].com[k], m.links[static_cast<size_t>(i)].com[k]));
      }
      EXPECT_TRUE(sameBits(back.masses->payload.mass, m.payload.mass));
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(sameBits(back.masses->payload.com[k], m.payload.com[k]));
        EXPECT_TRUE(sameBits(back.masses->gravity[k], m.gravity[k]));
      }
      // bit for bit in rad; through the degree conversion (x 180/pi and back) to rounding, as offsets
      const double tol = angle_unit == "rad" ? 0.0 : 4e-16;
      for (int i = 0; i < 3; ++i) {
        const bool slides = i == 1;  // a sliding joint's values are lengths: never converted
        const double t = slides ? 0.0 : tol;
        EXPECT_NEAR(back.deflection.compliance[i], extras.deflection.compliance[i], t * std::abs(extras.deflection.compliance[i])) << i;
        EXPECT_NEAR(back.deflection.backlash[i], extras.deflection.backlash[i], t * std::abs(extras.deflection.backlash[i])) << i;
      }
      // the D-H writer carries the same keys
      const RobotFile dh = readRobotFile(write("round_dh.yaml", formatDhRobotFile(poeToDh(model).model, like, "round", "", {}, extras)));
      ASSERT_TRUE(dh.masses.has_value());
      EXPECT_TRUE(sameBits(dh.masses->links[2].com[0], m.links[2].com[0]));
      EXPECT_NEAR(dh.deflection.compliance[2], extras.deflection.compliance[2], tol * std::abs(extras.deflection.compliance[2]));
    }
  }
}

TEST(RobotFileLoads, InUnitConvertsTheCentresOfMass) {
  const RobotFile f = readRobotFile(write("unit.yaml", kHead +
      "    - {twist: [0, 0, 0, 0, 0, 1], mass: 1, com: [0, 0, 300], compliance: 2e-6}\n"
      "    - {twist: [0, 1, 0, 0, 0, 100], mass: 4, com: [150, 0, 0]}\n" + kTool + "payload: {mass: 2, com: [0, 0, 30]}\n"));
  const RobotFile m = inMetres(f);
  EXPECT_DOUBLE_EQ(m.masses->links[0].com.z(), 0.3);
  EXPECT_DOUBLE_EQ(m.masses->payload.com.z(), 0.03);
  EXPECT_DOUBLE_EQ(m.masses->metres_per_unit, 1.0);
  EXPECT_EQ(m.deflection.compliance[0], 2e-6);  // a prismatic joint's q keeps the file's unit (the scale absorbs it)
}

TEST(RobotFileLoads, BadValuesRefusedNamingTheKey) {
  struct Case {
    std::string joint, top, what;
  };
  const std::vector<Case> cases = {
      {"mass: -1, com: [0, 0, 0]", "", "poe.joints[0].mass must be >= 0"},
      {"mass: .nan, com: [0, 0, 0]", "", "poe.joints[0].mass is not finite"},
      {"mass: 1", "", "poe.joints[0]: give 'mass' (kg) and 'com'"},
      {"com: [1, 2, 3]", "", "poe.joints[0]: give 'mass' (kg) and 'com'"},
      {"mass: 1, com: [1, 2]", "", "poe.joints[0].com must have 3 entries"},
      {"compliance: .inf", "", "poe.joints[0].compliance is not finite"},
      {"backlash: x", "", "poe.joints[0].backlash must be a number"},
      {"masses: 1", "", "unknown key 'masses'"},
      {"", "payload: {mass: 1}\n", "payload needs 'mass' (kg) and 'com'"},
      {"", "payload: {mass: -2, com: [0, 0, 0]}\n", "payload.mass must be >= 0"},
      {"", "payload: {mass: 2, com: [0, 0, 0], inertia: 1}\n", "unknown key 'inertia' in payload"},
      {"", "gravity: [0, 0]\n", "gravity must have 3 entries"},
  };
  for (const Case& c : cases) {
    const std::string joint = c.joint.empty() ? "" : ", " + c.joint;
    const std::string path = write("bad.yaml", kHead + "    - {twist: [0, 0, 1, 0, 0, 0]" + joint + "}\n" + kTool + c.top);
    const std::string error = robotFileError(path);
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
    EXPECT_NE(error.find(c.what), std::string::npos) << c.joint << c.top << " -> " << error;
  }
  // masses need a length unit to turn lengths into moment arms in metres
  const std::string no_unit = write("no_unit.yaml", "poe:\n  joints:\n    - {twist: [0, 0, 1, 0, 0, 0], mass: 1, com: [1, 0, 0]}\n");
  EXPECT_NE(robotFileError(no_unit).find("masses need the length unit of their centres"), std::string::npos) << robotFileError(no_unit);
}

}  // namespace
}  // namespace lowpair
