// The spatial, body and geometric Jacobians of every shipped robot against MuJoCo (an independent
// implementation: mj_jacSite / mj_jacBody on the MJCF model, harness/mujoco_robot.hpp), at 200 seeded
// random configurations per robot.
//
// Robots: every scenarios/*.yaml (its MJCF `model`, `tip`, optional `base`, and `robot_files`; the
// `joint_variables` file is one of the robot files). Models compared per robot:
//   - the POE model extracted from MuJoCo at qpos0 (scale 1: its joint variable is MuJoCo's motion x),
//   - its D-H form poeToDh(...).model,
//   - each robot file (POE or D-H), with its own joint variable q_i = x_i / scale_i - offset_i, so its
//     Jacobian is MuJoCo's times scale_i (chain rule; x = scale (q + offset)).
// References, all d/dx, from MuJoCo's geometric Jacobian [v; w] (velocity of the tip origin and angular
// velocity, base coordinates) and MuJoCo's tip pose g = (R, p), by the definitions (not the library's
// conversion functions):
//   geometric: [v; w]
//   spatial:   hat(V_s) = (dg/dx) g^-1 = [hat(w)  v - hat(w) p]  ->  [w; v - w x p]
//   body:      hat(V_b) = g^-1 (dg/dx) = [R^T hat(w) R  R^T v]   ->  [R^T w; R^T v]
// Errors are dimensionless as in `lowpair validate` (singularity.hpp's J_n): per unit motion (column /
// scale_i), angular rows in rad, linear rows divided by the robot size L; prismatic columns times L.
// Bound 1e-12, the validate Jacobian tolerance: both sides are double evaluations of the same chain
// (errors of a few eps each, ~1e-15), and the shipped robot files agree with their MJCF models to
// 1e-12 L in pose (the scenarios' validate runs).
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::mujoco;

using namespace lowpair;
namespace fs = std::filesystem;

namespace {

constexpr int kSamples = 200;
constexpr double kTolerance = 1e-12;

// The files a scenario names, relative paths resolved against the scenario's folder.
struct ScenarioFiles {
  std::string path, name, model, tip, base;
  std::vector<std::string> robot_files;
};

ScenarioFiles readScenarioFiles(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  const fs::path dir = fs::path(path).parent_path();
  auto resolve = [&](const std::string& file) { return (dir / file).lexically_normal().string(); };
  ScenarioFiles s;
  s.path = path;
  s.name = root["name"] ? root["name"].as<std::string>() : fs::path(path).stem().string();
  s.model = resolve(root["model"].as<std::string>());
  s.tip = root["tip"].as<std::string>();
  if (root["base"]) s.base = root["base"].as<std::string>();
  if (root["robot_files"]) {
    for (const auto& f : root["robot_files"]) s.robot_files.push_back(resolve(f.as<std::string>()));
  }
  if (root["joint_variables"]) {  // normally also listed in robot_files
    const std::string jv = resolve(root["joint_variables"].as<std::string>());
    if (std::find(s.robot_files.begin(), s.robot_files.end(), jv) == s.robot_files.end()) s.robot_files.push_back(jv);
  }
  return s;
}

std::vector<std::string> scenarioPaths() {
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(LOWPAIR_SCENARIOS)) {
    if (e.path().extension() == ".yaml") paths.push_back(e.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

struct Reference {
  Mat6X spatial, body, geometric;
};

// Worst dimensionless error over the columns: angular and linear rows separately, and where.
struct Worst {
  double angular = 0.0, linear = 0.0;
  std::string where;
  double max() const { return std::max(angular, linear); }
  void add(const Worst& o, const std::string& at) {
    if (o.max() > max() || where.empty()) where = at;
    angular = std::max(angular, o.angular);
    linear = std::max(linear, o.linear);
  }
};

double finiteOrInf(double e) { return std::isfinite(e) ? e : std::numeric_limits<double>::infinity(); }

Worst compare(const Mat6X& J, const Mat6X& ref, const std::vector<JointMotion>& joints, double L,
              bool angular_first) {
  Worst w;
  for (size_t i = 0; i < joints.size(); ++i) {
    const Eigen::Index c = static_cast<Eigen::Index>(i);
    const bool prismatic = joints[i].type == JointType::Prismatic;
    const Vec6 e = J.col(c) / joints[i].scale - ref.col(c);
    const double ea = (angular_first ? e.head<3>() : e.tail<3>()).cwiseAbs().maxCoeff();
    const double el = (angular_first ? e.tail<3>() : e.head<3>()).cwiseAbs().maxCoeff();
    w.angular = std::max(w.angular, finiteOrInf(prismatic ? ea * L : ea));
    w.linear = std::max(w.linear, finiteOrInf(prismatic ? el : el / L));
  }
  return w;
}

// One library model of the robot (its own joint variables and data).
struct Candidate {
  std::string name;
  std::optional<PoeModel> poe;
  std::optional<DhModel> dh;
  std::vector<JointMotion> joints;
  std::optional<Data> data;
  Worst spatial, body, geometric;
};

template <class Model>
std::vector<JointMotion> motionsOf(const Model& model) {
  std::vector<JointMotion> m;
  for (int i = 0; i < model.dof(); ++i) m.push_back(model.joint(i));
  return m;
}

class JacobianVsMujoco : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(JacobianVsMujoco, SpatialBodyGeometric) {
  const ScenarioFiles s = readScenarioFiles(GetParam());
  const MujocoRobot robot(s.model, s.tip, s.base);
  const PoeModel& extracted = robot.poeModel();
  const int n = robot.dof();
  const double L = extracted.lengthScale();

  std::vector<Candidate> candidates;
  {
    Candidate c{"extracted POE", extracted, std::nullopt, motionsOf(extracted), std::nullopt, {}, {}, {}};
    c.data.emplace(*c.poe);
    candidates.push_back(std::move(c));
    const DhModel dh = poeToDh(extracted).model;
    Candidate d{"extracted D-H", std::nullopt, dh, motionsOf(dh), std::nullopt, {}, {}, {}};
    d.data.emplace(*d.dh);
    candidates.push_back(std::move(d));
  }
  for (const std::string& path : s.robot_files) {
    const RobotFile f = readRobotFile(path);
    Candidate c{fs::path(path).filename().string(), f.poe, f.dh, {}, std::nullopt, {}, {}, {}};
    if (c.poe) {
      c.joints = motionsOf(*c.poe);
      c.data.emplace(*c.poe);
    } else {
      c.joints = motionsOf(*c.dh);
      c.data.emplace(*c.dh);
    }
    candidates.push_back(std::move(c));
  }
  for (const Candidate& c : candidates) {
    ASSERT_EQ(static_cast<int>(c.joints.size()), n) << c.name;
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(c.joints[static_cast<size_t>(i)].type, robot.joints()[static_cast<size_t>(i)].type)
          << c.name << " joint " << i + 1;
    }
  }

  // motions x: revolute/helical in [-pi, pi], prismatic over the MJCF range (else [-L, L])
  std::mt19937_64 rng(20240807);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  MujocoRobot::Evaluator mj(robot);
  Mat6X J_mj(6, n), J(6, n);
  Reference ref{Mat6X(6, n), Mat6X(6, n), Mat6X(6, n)};
  VecX x(n), q(n);
  for (int k = 0; k < kSamples; ++k) {
    for (int i = 0; i < n; ++i) {
      const MujocoJoint& j = robot.joints()[static_cast<size_t>(i)];
      std::array<double, 2> r{-M_PI, M_PI};
      if (j.type == JointType::Prismatic) r = j.range ? *j.range : std::array<double, 2>{-L, L};
      x[i] = r[0] + unit(rng) * (r[1] - r[0]);
    }
    const Pose T = mj.tipJacobian(x, J_mj);
    for (int i = 0; i < n; ++i) {
      const Vec3 v = J_mj.col(i).head<3>(), w = J_mj.col(i).tail<3>();
      ref.geometric.col(i) = J_mj.col(i);
      ref.spatial.col(i) << w, v - w.cross(T.p);
      ref.body.col(i) << T.R.transpose() * w, T.R.transpose() * v;
    }
    for (Candidate& c : candidates) {
      for (int i = 0; i < n; ++i) {
        const JointMotion& m = c.joints[static_cast<size_t>(i)];
        q[i] = x[i] / m.scale - m.offset;  // x = scale (q + offset)
      }
      if (c.poe) computeJacobians(*c.poe, *c.data, q);
      else computeJacobians(*c.dh, *c.data, q);
      getSpatialJacobian(*c.data, J);
      const Worst ws = compare(J, ref.spatial, c.joints, L, true);
      getBodyJacobian(*c.data, J);
      const Worst wb = compare(J, ref.body, c.joints, L, true);
      getGeometricJacobian(*c.data, J);
      const Worst wg = compare(J, ref.geometric, c.joints, L, false);
      std::ostringstream at;
      at << "sample " << k << ", motion x = [" << x.transpose() << "]";
      c.spatial.add(ws, at.str());
      c.body.add(wb, at.str());
      c.geometric.add(wg, at.str());
    }
  }
  for (const Candidate& c : candidates) {
    EXPECT_LE(c.spatial.max(), kTolerance) << s.name << " / " << c.name << " spatial, worst at " << c.spatial.where;
    EXPECT_LE(c.body.max(), kTolerance) << s.name << " / " << c.name << " body, worst at " << c.body.where;
    EXPECT_LE(c.geometric.max(), kTolerance)
        << s.name << " / " << c.name << " geometric, worst at " << c.geometric.where;
  }
  std::printf("%s (L = %g, %d samples): worst dimensionless error (angular / linear)\n", s.name.c_str(), L,
              kSamples);
  for (const Candidate& c : candidates) {
    std::printf("  %-34s spatial %9.2e / %9.2e   body %9.2e / %9.2e   geometric %9.2e / %9.2e\n", c.name.c_str(),
                c.spatial.angular, c.spatial.linear, c.body.angular, c.body.linear, c.geometric.angular,
                c.geometric.linear);
  }
}

INSTANTIATE_TEST_SUITE_P(ShippedRobots, JacobianVsMujoco, ::testing::ValuesIn(scenarioPaths()),
                         [](const ::testing::TestParamInfo<std::string>& scenario) {
                           std::string name = fs::path(scenario.param).stem().string();
                           for (char& ch : name) {
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           }
                           return name;
                         });

// Guard: the glob found the shipped robots (an empty parameter list would silently test nothing).
TEST(JacobianVsMujocoSetup, FindsEveryScenario) { EXPECT_GE(scenarioPaths().size(), 7u); }
