// simulate --stiffness: MuJoCo's robot made compliant (harness/commands/compliant_truth.hpp), each pose
// measured where the robot rests under gravity.
//
// The end-to-end check: a PUMA 560 (Corke's geometry, models/puma560_corke.xml) given masses here, by hand,
// measured rigid and with stiffness 1e5 and 1e6 N m/rad on every joint. The library's first-order
// compliance model, the rigid FK of the robot file models/puma560_corke.yaml at q + tau(q)/k with tau the
// library's gravityTorques of the same masses written here as point masses, predicts each compliant position:
// it explains at least 95% of the deflection, and what it misses is second order (a hundred times smaller
// for ten times the stiffness). Nothing of MuJoCo's masses reading or of its equilibrium solver is used on
// the prediction's side.
#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "csv_text.hpp"
#include "io/robot_file.hpp"
#include "lowpair/gravity.hpp"
#include "lowpair/kinematics.hpp"

namespace {

using namespace lowpair_test;

// Link k: its mass (kg) and its inertial's pos in its body frame (bodies unrotated at q = 0).
struct Link {
  double mass;
  lowpair::Vec3 pos, body;  // body: the body's origin in the world at q = 0 (puma560_corke.xml)
};
const std::vector<Link> kLinks = {
    {2.0, {0, 0, 0.1}, {0, 0, 0}},
    {17.4, {0.2, 0, 0.05}, {0, 0, 0}},
    {4.8, {0.02, -0.05, 0.2}, {0.4318, 0, 0}},
    {0.82, {0, 0.02, 0}, {0.4521, -0.15005, 0}},
    {0.34, {0, 0, 0}, {0.4521, -0.15005, 0.4318}},
    {0.09, {0, 0, 0.03}, {0.4521, -0.15005, 0.4318}},
};

std::string pumaWithMasses() {
  std::ifstream in(modelPath("puma560_corke.xml"));
  std::string xml((std::istreambuf_iterator<char>(in)), {});
  std::string out;
  std::smatch m;
  size_t k = 0;
  const std::regex inertial("<inertial [^>]*/>");
  while (std::regex_search(xml, m, inertial)) {
    const Link& l = kLinks.at(k++);
    out += m.prefix().str() + "<inertial pos=\"" + std::to_string(l.pos.x()) + " " + std::to_string(l.pos.y()) + " " +
           std::to_string(l.pos.z()) + "\" mass=\"" + std::to_string(l.mass) + "\" diaginertia=\"0.01 0.01 0.01\"/>";
    xml = m.suffix().str();
  }
  out += xml;
  out = std::regex_replace(out, std::regex("<option gravity=\"0 0 0\"/>"), "<option gravity=\"0 0 -9.81\"/>");
  return writeScratchFile("puma_masses.xml", out);
}

csv_test::Csv simulate(const std::string& model, const std::string& extra) {
  const CliRun r = runCli("simulate " + model + " --tip tool --poses 20 --seed 9 --measure position " + extra);
  EXPECT_EQ(r.status, 0) << r.err;
  return csv_test::parseCsv(r.out);
}

lowpair::Vec3 position(const csv_test::Row& row) { return {row.p[0], row.p[1], row.p[2]}; }

TEST(CompliantSimulation, FirstOrderLibraryModelPredictsTheRestPositions) {
  const std::string model = pumaWithMasses();
  const lowpair::PoeModel poe = lowpair::io::readRobotFile(modelPath("puma560_corke.yaml")).poeModel();
  lowpair::MassModel masses;
  for (const Link& l : kLinks) masses.links.push_back({l.mass, l.body + l.pos});
  masses.gravity = lowpair::Vec3(0, 0, -9.81);
  lowpair::Data data(poe);
  auto fk = [&](const lowpair::VecX& q) {
    lowpair::forwardKinematics(poe, data, q);
    return lowpair::Vec3(data.T_base_tool.p);
  };
  const csv_test::Csv rigid = simulate(model, "");
  ASSERT_EQ(rigid.rows.size(), 20u);
  for (const auto& c : rigid.comments) EXPECT_EQ(c.find("compliance"), std::string::npos) << c;
  double missed[2] = {0, 0};
  int which = 0;
  for (const std::string k : {"1e5", "1e6"}) {
    const csv_test::Csv soft = simulate(model, "--stiffness " + k + "," + k + "," + k + "," + k + "," + k + "," + k);
    ASSERT_EQ(soft.rows.size(), 20u);
    bool described = false;
    for (const auto& c : soft.comments) described = described || c.find("# compliance: each pose where") == 0;
    EXPECT_TRUE(described);
    double deflection = 0, miss = 0;
    for (size_t r = 0; r < soft.rows.size(); ++r) {
      const lowpair::VecX q = Eigen::Map<const lowpair::VecX>(soft.rows[r].q.data(), 6);
      ASSERT_EQ(soft.rows[r].q, rigid.rows[r].q);  // the same commanded joint vectors
      EXPECT_LE((position(rigid.rows[r]) - fk(q)).norm(), 1e-12);
      const lowpair::VecX tau = lowpair::gravityTorques(poe, masses, q);
      const lowpair::Vec3 predicted = fk(q + tau / std::stod(k));
      deflection = std::max(deflection, (position(soft.rows[r]) - position(rigid.rows[r])).norm());
      miss = std::max(miss, (position(soft.rows[r]) - predicted).norm());
    }
    std::printf("k %s: largest deflection %.3g m, largest miss of the first-order prediction %.3g m\n", k.c_str(),
                deflection, miss);
    EXPECT_GT(deflection, 1e-6);
    EXPECT_LE(miss, 0.05 * deflection);
    missed[which++] = miss;
  }
  EXPECT_GT(missed[0] / missed[1], 50.0);
  EXPECT_LT(missed[0] / missed[1], 200.0);
}

TEST(CompliantSimulation, ZeroGravityModelRestsWhereCommanded) {
  // the shipped MJCF has <option gravity="0 0 0">: the same measurements, a note, one more comment line
  const std::string model = modelPath("puma560_corke.xml");
  const CliRun rigid = runCli("simulate " + model + " --tip tool --poses 5 --measure position");
  const CliRun soft = runCli("simulate " + model + " --tip tool --poses 5 --measure position --stiffness 1,1,1,1,1,1");
  ASSERT_EQ(soft.status, 0) << soft.err;
  EXPECT_NE(soft.err.find("gravity is zero"), std::string::npos) << soft.err;
  const csv_test::Csv a = csv_test::parseCsv(rigid.out), b = csv_test::parseCsv(soft.out);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (size_t r = 0; r < a.rows.size(); ++r) EXPECT_EQ(a.rows[r].text, b.rows[r].text);
  EXPECT_EQ(b.comments.size(), a.comments.size() + 1);
}

TEST(CompliantSimulation, StiffnessIsRefusedWhereItCannotApply) {
  const std::string model = pumaWithMasses();
  const std::string base = "simulate " + model + " --tip tool --poses 3 ";
  expectRejected(base + "--stiffness 1e4,1e4", "expected K1,...,K6", "--stiffness");
  expectRejected(base + "--stiffness 1e4,1e4,-1,1e4,1e4,1e4", "joint 3: expected a finite stiffness >= 0", "--stiffness");
  expectRejected(base + "--stiffness 0,1,1,1,1,1", "too soft to hold the robot", "--stiffness");
  expectRejected("simulate " + modelPath("puma560_corke.yaml") + " --poses 3 --stiffness 1,1,1,1,1,1",
                 "goes with a model file", "--stiffness");
  const std::string bare = writeScratchFile("bare.xml", R"(<mujoco><worldbody><body name="a">
    <joint name="j" type="hinge" axis="0 1 0"/><site name="tool" pos="1 0 0"/></body></worldbody></mujoco>)");
  expectRejected("simulate " + bare + " --tip tool --poses 3 --stiffness 10", "no masses", bare);
}

}  // namespace
