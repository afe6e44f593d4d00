// The masses of a MuJoCo robot's chain and MuJoCo's gravity force on it (harness/mujoco/mujoco_dynamics.hpp).
//
// - A hand-written chain: the link masses and centres of mass lumped by hand (a body fixed to a link, a
//   body beyond the tip, a finger moved by a joint outside the chain, a body the chain does not move), in a
//   rotated base frame.
// - Every shipped model with seeded random masses (mass_variants.hpp), MJCF and URDF: MuJoCo's generalized
//   gravity force (minus qfrc_bias, recursive Newton-Euler over MuJoCo's own bodies) equals the sum over the
//   mass model's links of J_k^T m_k g, J_k MuJoCo's Jacobian (mj_jac) of link k's centre of mass carried
//   rigidly from qpos0 to x. The two sides share only MuJoCo's kinematics: one is RNE over the bodies, the
//   other the lumped links' point masses, so a wrong lumping, centre of mass, base frame, gravity or dof
//   mapping (helical: hinge + pitch * slide) shows. Bound: 64 eps sum_k m_k |g| (|p_k| + L), rounding of
//   sums of products of that size.
// - The key test of issue 27's mass model: the library's gravityTorques (lowpair/gravity.hpp: the POE
//   model MujocoRobot extracts and the mass model here, nothing of MuJoCo's dynamics) equals MuJoCo's
//   gravity force at the same random configurations, to the same bound.
// - Files without masses: no inertials, masses from geometry.
// - models/puma560_masses.xml and .yaml, the compliant loop's PUMA: both hold Corke's published centres of mass
//   (computed here from Corke's r in the D-H link frames) and give the same gravity load.
#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>

#include "io/robot_file.hpp"
#include "lowpair/gravity.hpp"
#include "mass_variants.hpp"
#include "mujoco/mujoco_dynamics.hpp"
#include "mujoco/mujoco_robot.hpp"

using namespace lowpair;
using namespace lowpair::mujoco;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// World -> stand (rotated +90 deg about x, the base) -> a (j1: hinge about the stand's z) -> b (j2: slide
// along x) with the tip site; a_fixed is fixed to a, beyond fixed to b after the tip, finger on b moved by
// the joint f outside the chain (ref 0.3: qpos0 = 0.3, at which the finger is where the XML puts it: MuJoCo's
// `ref` is the joint value of the model's own configuration). Positions in the
// stand's frame are the XML's (no rotation below the stand).
const char* const kChain = R"(<mujoco model="chain">
  <option gravity="0 0 -9.81"/>
  <worldbody>
    <body name="ground" pos="3 0 0"><inertial pos="0 0 0" mass="40" diaginertia="1 1 1"/></body>
    <body name="stand" pos="0 0 0.1" quat="0.70710678118654757 0.70710678118654757 0 0">
      <inertial pos="0 0 0" mass="7" diaginertia="1 1 1"/>
      <body name="a" pos="0 0 0.5">
        <inertial pos="0.1 0 0" mass="2" diaginertia=".01 .01 .01"/>
        <joint name="j1" type="hinge" axis="0 0 1"/>
        <body name="a_fixed" pos="0 0.2 0"><inertial pos="0 0 0.1" mass="1" diaginertia=".01 .01 .01"/></body>
        <body name="b" pos="0.4 0 0">
          <inertial pos="0.2 0 0" mass="3" diaginertia=".01 .01 .01"/>
          <joint name="j2" type="slide" axis="1 0 0"/>
          <site name="tool" pos="0.3 0 0"/>
          <body name="beyond" pos="0.3 0 0"><inertial pos="0 0 -0.1" mass="0.5" diaginertia=".01 .01 .01"/></body>
          <body name="finger" pos="0.3 0.1 0">
            <joint name="f" type="hinge" axis="1 0 0" ref="0.3"/>
            <inertial pos="0 0.1 0" mass="0.25" diaginertia=".01 .01 .01"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
)";

TEST(MujocoMasses, HandWrittenChainLumpsEachBodyIntoTheLinkThatMovesIt) {
  const std::string path = mass_variants::scratch().write("chain.xml", kChain);
  const MujocoRobot robot(path, "tool", "stand");
  const MujocoDynamics dynamics(robot);
  const ModelMasses& mm = dynamics.masses();
  ASSERT_EQ(mm.status, MassStatus::Ok) << massProblem(mm, path);
  ASSERT_EQ(mm.masses.links.size(), 2u);
  // link 1: a (2 kg at (0.1, 0, 0.5)) and a_fixed (1 kg at (0, 0.2, 0.6)); link 2: b (3 kg at (0.6, 0, 0.5)),
  // beyond (0.5 kg at (0.7, 0, 0.4)), finger (0.25 kg at (0.7, 0.2, 0.5), unturned at qpos0 = ref); stand
  // and ground: none
  const Vec3 com1 = (2 * Vec3(0.1, 0, 0.5) + 1 * Vec3(0, 0.2, 0.6)) / 3;
  const Vec3 finger(0.7, 0.2, 0.5);
  const Vec3 com2 = (3 * Vec3(0.6, 0, 0.5) + 0.5 * Vec3(0.7, 0, 0.4) + 0.25 * finger) / 3.75;
  EXPECT_NEAR(mm.masses.links[0].mass, 3.0, 4 * kEps * 3);
  EXPECT_NEAR(mm.masses.links[1].mass, 3.75, 4 * kEps * 3.75);
  EXPECT_LE((mm.masses.links[0].com - com1).norm(), 16 * kEps) << mm.masses.links[0].com.transpose();
  EXPECT_LE((mm.masses.links[1].com - com2).norm(), 16 * kEps) << mm.masses.links[1].com.transpose();
  // gravity (0, 0, -9.81) seen from the stand turned +90 deg about x: (0, -9.81, 0)
  EXPECT_LE((mm.masses.gravity - Vec3(0, -9.81, 0)).norm(), 16 * kEps * 9.81) << mm.masses.gravity.transpose();
  EXPECT_EQ(mm.masses.metres_per_unit, 1.0);
  EXPECT_EQ(mm.masses.payload.mass, 0.0);
}

TEST(MujocoMasses, ShippedMjcfHasItsPlaceholderMassesAndNoGravity) {
  // models/*.xml are kinematic models: 1 kg at each body's origin and <option gravity="0 0 0">
  const MujocoRobot robot(std::string(LOWPAIR_MODELS) + "/puma560_corke.xml", "tool");
  const MujocoDynamics dynamics(robot);
  const ModelMasses& mm = dynamics.masses();
  ASSERT_EQ(mm.status, MassStatus::Ok);
  ASSERT_EQ(mm.masses.links.size(), 6u);
  for (const PointMass& p : mm.masses.links) EXPECT_EQ(p.mass, 1.0);
  EXPECT_EQ(mm.masses.gravity, Vec3::Zero());
  MujocoDynamics::Evaluator eval(dynamics);
  EXPECT_EQ(eval.gravityForce(VecX::Constant(6, 0.3)), VecX::Zero(6));
}

TEST(MujocoMasses, FilesWithoutMassesSayWhy) {
  const auto& s = mass_variants::scratch();
  // no inertial anywhere: every body weighs the copy's bound
  const std::string bare = s.write("bare.xml", R"(<mujoco><worldbody><body name="a">
    <joint name="j" type="hinge" axis="0 0 1"/><site name="tool" pos="1 0 0"/></body></worldbody></mujoco>)");
  const MujocoRobot bare_robot(bare, "tool");
  const MujocoDynamics bare_dynamics(bare_robot);
  EXPECT_EQ(bare_dynamics.masses().status, MassStatus::NoInertials);
  EXPECT_TRUE(bare_dynamics.masses().masses.empty());
  EXPECT_NE(massProblem(bare_dynamics.masses(), bare).find("no masses"), std::string::npos);
  // the moving body's mass comes from its geom, which no copy keeps; the static one's does not matter
  const std::string geoms = s.write("geoms.xml", R"(<mujoco><worldbody>
    <body name="pillar"><geom type="box" size="1 1 1"/></body>
    <body name="arm"><joint name="j" type="hinge" axis="0 0 1"/><geom type="capsule" fromto="0 0 0 1 0 0" size="0.05"/>
    <site name="tool" pos="1 0 0"/></body></worldbody></mujoco>)");
  const MujocoRobot geom_robot(geoms, "tool");
  const MujocoDynamics geom_dynamics(geom_robot);
  EXPECT_EQ(geom_dynamics.masses().status, MassStatus::MassFromGeoms);
  EXPECT_EQ(geom_dynamics.masses().bodies, std::vector<std::string>{"'arm'"});
  EXPECT_NE(massProblem(geom_dynamics.masses(), geoms).find("'arm'"), std::string::npos);
  // a URDF whose links have no <inertial>
  const std::string urdf = s.write("bare.urdf", R"(<robot name="bare"><link name="base"/><link name="arm"/>
    <link name="tool"/><joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint><joint name="t" type="fixed"><parent link="arm"/>
    <child link="tool"/><origin xyz="1 0 0"/></joint></robot>)");
  const MujocoRobot urdf_robot(urdf, "tool");
  EXPECT_EQ(MujocoDynamics(urdf_robot).masses().status, MassStatus::NoInertials);
  // a URDF link with a collision shape and no <inertial>: MuJoCo would weigh the shape
  const std::string shaped = s.write("shaped.urdf", R"(<robot name="shaped"><link name="base"/><link name="arm">
    <collision><geometry><box size="1 0.1 0.1"/></geometry></collision></link>
    <link name="tool"/><joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint><joint name="t" type="fixed"><parent link="arm"/>
    <child link="tool"/><origin xyz="1 0 0"/></joint></robot>)");
  const MujocoRobot shaped_robot(shaped, "tool");
  const MujocoDynamics shaped_dynamics(shaped_robot);
  EXPECT_EQ(shaped_dynamics.masses().status, MassStatus::MassFromGeoms);
  EXPECT_EQ(shaped_dynamics.masses().bodies, std::vector<std::string>{"'arm'"});
}

// sum_k J_k(x)^T m_k g with J_k MuJoCo's Jacobian of link k's centre of mass carried rigidly by the body of
// joint k from qpos0 to x; also the bound 64 eps sum_k m_k |g| (|p_k| + L).
VecX weightTorques(const MujocoDynamics& dynamics, const VecX& x, double& bound) {
  const mjModel* m = dynamics.model();
  const MujocoRobot& robot = dynamics.robot();
  const MassModel& mm = dynamics.masses().masses;
  std::unique_ptr<mjData, void (*)(mjData*)> d0(mj_makeData(m), mj_deleteData), d(mj_makeData(m), mj_deleteData);
  mj_kinematics(m, d0.get());
  for (size_t i = 0; i < robot.joints().size(); ++i) {
    const MujocoJoint& j = robot.joints()[i];
    d->qpos[j.qpos] += x[static_cast<Eigen::Index>(i)];
    if (j.slide_qpos >= 0) d->qpos[j.slide_qpos] += j.pitch * x[static_cast<Eigen::Index>(i)];
  }
  mj_kinematics(m, d.get());
  mj_comPos(m, d.get());
  const Pose T_world_base = robot.T_base_world().inverse();
  const Vec3 g_world = T_world_base.R * mm.gravity;
  const double L = robot.poeModel().lengthScale();
  std::vector<double> jacp(static_cast<size_t>(3 * m->nv));
  VecX tau = VecX::Zero(robot.dof());
  bound = 0;
  auto bodyPose = [](const mjData* data, int b) {
    Pose T;
    T.p = Eigen::Map<const Vec3>(data->xpos + 3 * b);
    T.R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(data->xmat + 9 * b);
    return T;
  };
  for (size_t k = 0; k < mm.links.size(); ++k) {
    const int body = m->jnt_bodyid[m->dof_jntid[robot.joints()[k].dof]];
    const Vec3 p = bodyPose(d.get(), body) * (bodyPose(d0.get(), body).inverse() * (T_world_base * mm.links[k].com));
    mj_jac(m, d.get(), jacp.data(), nullptr, p.data(), body);
    const Vec3 f = mm.links[k].mass * g_world;
    for (size_t i = 0; i < robot.joints().size(); ++i) {
      const MujocoJoint& j = robot.joints()[i];
      for (int r = 0; r < 3; ++r) {
        double column = jacp[static_cast<size_t>(r * m->nv + j.dof)];
        if (j.slide_dof >= 0) column += j.pitch * jacp[static_cast<size_t>(r * m->nv + j.slide_dof)];
        tau[static_cast<Eigen::Index>(i)] += f[r] * column;
      }
    }
    bound += 64 * kEps * f.norm() * (p.norm() + L);
  }
  return tau;
}

struct Worst {
  double links = 0, library = 0;  // error / bound
};

void expectGravityIsTheLinksWeight(const std::string& path, const std::string& tip, const std::string& base,
                                   std::mt19937_64& rng, Worst& worst) {
  SCOPED_TRACE(path);
  const MujocoRobot robot(path, tip, base);
  const MujocoDynamics dynamics(robot);
  ASSERT_EQ(dynamics.masses().status, MassStatus::Ok) << massProblem(dynamics.masses(), path);
  ASSERT_GT(dynamics.masses().masses.gravity.norm(), 9.0);
  MujocoDynamics::Evaluator eval(dynamics);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), stroke(-0.2, 0.2);
  double max_library = 0, max_load = 0;
  for (int sample = 0; sample < 50; ++sample) {
    VecX x(robot.dof());
    for (int i = 0; i < robot.dof(); ++i) {
      x[i] = robot.joints()[static_cast<size_t>(i)].type == JointType::Prismatic ? stroke(rng) : angle(rng);
    }
    double bound = 0;
    const VecX reference = weightTorques(dynamics, x, bound);
    const VecX tau = eval.gravityForce(x);
    const VecX library = gravityTorques(robot.poeModel(), dynamics.masses().masses, x);
    const double error = (tau - reference).cwiseAbs().maxCoeff();
    const double library_error = (library - tau).cwiseAbs().maxCoeff();
    worst.links = std::max(worst.links, error / bound);
    worst.library = std::max(worst.library, library_error / bound);
    max_library = std::max(max_library, library_error);
    max_load = std::max(max_load, tau.cwiseAbs().maxCoeff());
    EXPECT_LE(error, bound) << "x = " << x.transpose() << "\nMuJoCo " << tau.transpose() << "\nlinks  "
                            << reference.transpose();
    EXPECT_LE(library_error, bound) << "x = " << x.transpose() << "\nMuJoCo  " << tau.transpose() << "\nlowpair "
                                    << library.transpose();
    ASSERT_GT(reference.norm(), 1.0);  // a load worth comparing
  }
  std::printf("%-28s max |tau_lowpair - tau_mujoco| %.3g (largest load %.3g)\n",
              std::filesystem::path(path).filename().c_str(), max_library, max_load);
}

// Standard D-H link transform A = Rz(theta) Tz(d) Tx(a) Rx(alpha).
Pose dhLink(double theta, double d, double a, double alpha) {
  Pose A;
  A.R = (Eigen::AngleAxisd(theta, Vec3::UnitZ()) * Eigen::AngleAxisd(alpha, Vec3::UnitX())).toRotationMatrix();
  A.p = Vec3(a * std::cos(theta), a * std::sin(theta), d);
  return A;
}

TEST(MujocoMasses, Puma560MassesFileAndRobotFileHoldCorkesMasses) {
  // Corke RTB mdl_puma560 (Armstrong, Khatib, Burdick 1986): d, a, alpha per row; m; r in D-H frame j
  const double d[6] = {0, 0, 0.15005, 0.4318, 0, 0}, a[6] = {0, 0.4318, 0.0203, 0, 0, 0};
  const double alpha[6] = {M_PI / 2, 0, -M_PI / 2, M_PI / 2, -M_PI / 2, 0};
  const double m[6] = {0, 17.4, 4.8, 0.82, 0.34, 0.09};
  const double r[6][3] = {{0, 0, 0}, {-0.3638, 0.006, 0.2275}, {-0.0203, -0.0141, 0.070}, {0, 0.019, 0}, {0, 0, 0}, {0, 0, 0.032}};
  const std::string models = LOWPAIR_MODELS;
  const io::RobotFile file = io::readRobotFile(models + "/puma560_masses.yaml");
  ASSERT_TRUE(file.masses.has_value());
  const MassModel& stated = *file.masses;
  ASSERT_EQ(stated.links.size(), 6u);
  Pose T_0j;  // D-H frame j at q = 0
  for (size_t j = 0; j < 6; ++j) {
    T_0j = T_0j * dhLink(0, d[j], a[j], alpha[j]);
    EXPECT_EQ(stated.links[j].mass, m[j]) << j;
    const Vec3 com = T_0j * Vec3(r[j][0], r[j][1], r[j][2]);
    EXPECT_LE((stated.links[j].com - com).norm(), 1e-15) << j << ": " << stated.links[j].com.transpose() << " vs " << com.transpose();
  }
  EXPECT_EQ(stated.payload.mass, 2.0);
  EXPECT_EQ(stated.gravity, Vec3(0, 0, -9.81));
  // the MJCF: the same links (its tool body lumped into link 6), the same load as the robot file's at any pose
  const MujocoRobot robot(models + "/puma560_masses.xml", "tool");
  const MujocoDynamics dynamics(robot);
  ASSERT_EQ(dynamics.masses().status, MassStatus::Ok);
  const MassModel& read = dynamics.masses().masses;
  ASSERT_EQ(read.links.size(), 6u);
  for (size_t j = 0; j < 5; ++j) {
    EXPECT_NEAR(read.links[j].mass, m[j], 1e-6) << j;  // the copy's mass bound: link 1 weighs 1e-6 kg there
    if (m[j] > 0) {
      EXPECT_LE((read.links[j].com - stated.links[j].com).norm(), 1e-12) << j;
    }
  }
  EXPECT_NEAR(read.links[5].mass, 0.09 + 2.0, 1e-12);
  EXPECT_EQ(read.gravity, Vec3(0, 0, -9.81));
  const PoeModel poe = file.poeModel();
  MujocoDynamics::Evaluator eval(dynamics);
  std::mt19937_64 rng(560);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  double total = 0;
  for (const PointMass& p : stated.links) total += p.mass;
  const double bound = 64 * kEps * (total + stated.payload.mass) * 9.81 * 2 * poe.lengthScale();
  for (int sample = 0; sample < 50; ++sample) {
    VecX q(6);
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    const VecX tau = eval.gravityForce(q);  // every scale 1, every offset 0: MuJoCo's motion is q
    EXPECT_LE((gravityTorques(poe, stated, q) - tau).cwiseAbs().maxCoeff(), bound) << q.transpose();
    ASSERT_GT(tau.cwiseAbs().maxCoeff(), 1.0);
  }
}

TEST(MujocoMasses, GravityForceIsTheLinksWeightAndTheLibrarysGravityTorques) {
  std::mt19937_64 rng(27);
  Worst worst;
  for (const auto& v : mass_variants::variants(2701)) expectGravityIsTheLinksWeight(v.path, v.tip, v.base, rng, worst);
  const std::string chain = mass_variants::scratch().write("chain_g.xml", kChain);
  expectGravityIsTheLinksWeight(chain, "tool", "stand", rng, worst);
  std::printf("worst error / bound: MuJoCo vs sum J^T m g %.3g, gravityTorques vs MuJoCo %.3g\n", worst.links,
              worst.library);
}

}  // namespace
