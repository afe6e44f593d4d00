#include "validate.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <thread>
#include <variant>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "mujoco_robot.hpp"
#include "robot_file.hpp"
#ifdef LOWPAIR_HAVE_JACOBIAN
#include <Eigen/SVD>

#include "lowpair/jacobian.hpp"
#include "lowpair/singularity.hpp"
#endif

namespace lowpair {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& path, const YAML::Node& node, const std::string& what) {
  std::string where = path + ": ";
  if (node.IsDefined() && node.Mark().line >= 0) where += "line " + std::to_string(node.Mark().line + 1) + ": ";
  throw RobotFileError(where + what);
}

double number(const std::string& path, const YAML::Node& node, const std::string& what) {
  try {
    const double x = node.as<double>();
    if (!std::isfinite(x)) fail(path, node, what + " is not finite");
    return x;
  } catch (const YAML::Exception&) {
    fail(path, node, what + " must be a number");
  }
}

std::string relative(const std::string& scenario_path, const std::string& file) {
  if (file.empty() || fs::path(file).is_absolute()) return file;
  return (fs::path(scenario_path).parent_path() / file).lexically_normal().string();
}

// splitmix64: decorrelated per-sample seeds, so a sample's q depends only on (seed, index) and the
// results do not depend on the thread count or the shard.
unsigned long long mix(unsigned long long x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

struct CheckedFile {
  std::string path;
  RobotFile file;
  std::optional<PoeModel> poe;  // for POE files; D-H files use file.dh
};

}  // namespace

Scenario readScenario(const std::string& path) {
  if (!std::ifstream(path)) throw RobotFileError(path + ": cannot open file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw RobotFileError(path + ": line " + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  if (!root.IsMap()) fail(path, root, "a scenario must be a mapping");
  const std::set<std::string> keys = {"name", "model", "tip", "base", "joint_variables", "robot_files", "samples",
                                      "seed", "ranges", "tolerance", "poses", "singular_poses", "description",
                                      "singularity_map"};
  for (const auto& kv : root) {
    if (!keys.count(kv.first.as<std::string>())) fail(path, kv.first, "unknown key '" + kv.first.as<std::string>() + "'");
  }
  Scenario s;
  s.path = path;
  s.name = root["name"] ? root["name"].as<std::string>() : fs::path(path).stem().string();
  if (!root["model"]) fail(path, root, "missing 'model' (an MJCF or URDF file)");
  if (!root["tip"]) fail(path, root, "missing 'tip' (a site or body name)");
  s.model = relative(path, root["model"].as<std::string>());
  s.tip = root["tip"].as<std::string>();
  if (root["base"]) s.base = root["base"].as<std::string>();
  if (root["joint_variables"]) s.joint_variables = relative(path, root["joint_variables"].as<std::string>());
  if (root["robot_files"]) {
    if (!root["robot_files"].IsSequence()) fail(path, root["robot_files"], "robot_files must be a list");
    for (const auto& f : root["robot_files"]) s.robot_files.push_back(relative(path, f.as<std::string>()));
  }
  if (root["samples"]) {
    const double n = number(path, root["samples"], "samples");
    if (n < 0 || n != std::floor(n)) fail(path, root["samples"], "samples must be a non-negative integer");
    s.samples = static_cast<int>(n);
  }
  if (root["seed"]) s.seed = root["seed"].as<unsigned long long>();
  if (root["ranges"]) {
    for (const auto& r : root["ranges"]) {
      if (!r.IsSequence() || r.size() != 2) fail(path, r, "each range must be [lo, hi]");
      const double lo = number(path, r[0], "range"), hi = number(path, r[1], "range");
      if (lo > hi) fail(path, r, "range [lo, hi] needs lo <= hi");
      s.ranges.push_back({lo, hi});
    }
  }
  if (const YAML::Node t = root["tolerance"]) {
    for (const auto& kv : t) {
      const std::string k = kv.first.as<std::string>();
      const double v = number(path, kv.second, "tolerance." + k);
      if (!(v > 0)) fail(path, kv.second, "tolerance." + k + " must be positive");
      if (k == "rotation") s.tol_rotation = v;
      else if (k == "translation") s.tol_translation = v;
      else if (k == "jacobian_rotation") s.tol_jacobian_rotation = v;
      else if (k == "jacobian_translation") s.tol_jacobian_translation = v;
      else fail(path, kv.first, "unknown tolerance '" + k + "'");
    }
  }
  if (const YAML::Node poses = root["poses"]) {
    for (const auto& p : poses) {
      NamedPose np;
      np.name = p["name"] ? p["name"].as<std::string>() : "pose" + std::to_string(s.poses.size() + 1);
      if (!p["q"] || !p["q"].IsSequence()) fail(path, p, "pose '" + np.name + "' needs q: [...]");
      for (const auto& x : p["q"]) np.q.push_back(number(path, x, "pose " + np.name));
      s.poses.push_back(np);
    }
  }
  if (const YAML::Node poses = root["singular_poses"]) {
    for (const auto& p : poses) {
      SingularPose sp;
      sp.name = p["name"] ? p["name"].as<std::string>() : "singular" + std::to_string(s.singular_poses.size() + 1);
      if (!p["q"] || !p["q"].IsSequence()) fail(path, p, "singular pose '" + sp.name + "' needs q: [...]");
      for (const auto& x : p["q"]) sp.q.push_back(number(path, x, "singular pose " + sp.name));
      if (!p["classes"] || !p["classes"].IsSequence() || p["classes"].size() == 0) {
        fail(path, p, "singular pose '" + sp.name + "' needs classes: [C1..C7 or other]");
      }
      for (const auto& c : p["classes"]) {
        const std::string id = c.as<std::string>();
        static const std::set<std::string> ids = {"C1", "C2", "C3", "C4", "C5", "C6", "C7", "other"};
        if (!ids.count(id)) fail(path, c, "unknown class '" + id + "' (C1..C7 or other)");
        sp.classes.push_back(id);
      }
      s.singular_poses.push_back(sp);
    }
  }
  if (const YAML::Node m = root["singularity_map"]) {
    if (m["joints"]) {
      for (const auto& j : m["joints"]) s.map_joints.push_back(j.as<int>());
      if (s.map_joints.size() != 2) fail(path, m["joints"], "singularity_map.joints must name two joints (1-based)");
    }
    if (m["fixed"]) {
      for (const auto& x : m["fixed"]) s.map_fixed.push_back(number(path, x, "singularity_map.fixed"));
    }
  }
  return s;
}

namespace {

#ifdef LOWPAIR_HAVE_JACOBIAN
// Singular values of the dimensionless geometric Jacobian (singularity.hpp): linear rows over L,
// columns over the joint scale, prismatic columns times L.
VecX scaledSingularValues(const PoeModel& model, Mat6X J) {
  const double L = model.size();
  J.topRows<3>() /= L;
  for (int i = 0; i < model.dof(); ++i) {
    J.col(i) *= (model.joint(i).type == JointType::Prismatic ? L : 1.0) / model.joint(i).scale;
  }
  return Eigen::JacobiSVD<MatX>(J).singularValues();
}

// Rank with the rule of singularity.hpp: tol = kRankFactor max(6, n) eps sigma_max.
int scaledRank(const PoeModel& model, const Mat6X& J) {
  const VecX sv = scaledSingularValues(model, J);
  const double tol = kRankFactor * std::max(6, model.dof()) * std::numeric_limits<double>::epsilon() * sv[0];
  int rank = 0;
  for (Eigen::Index k = 0; k < sv.size(); ++k) rank += sv[k] > tol ? 1 : 0;
  return rank;
}
#endif

void summarize(ComparisonResult& c, const std::vector<double>& rot, const std::vector<double>& rot_ea,
               const std::vector<double>& trans, double L, const std::vector<VecX>& qs) {
  const size_t n = rot.size();
  if (n == 0) return;
  auto p99 = [](std::vector<double> v) {
    const size_t k = static_cast<size_t>(std::ceil(0.99 * static_cast<double>(v.size()))) - 1;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
  };
  size_t worst = 0;
  double worst_score = -1;
  double sum_r = 0, sum_t = 0;
  for (size_t i = 0; i < n; ++i) {
    sum_r += rot[i];
    sum_t += trans[i];
    c.max_rotation = std::max(c.max_rotation, rot[i]);
    c.max_translation = std::max(c.max_translation, trans[i]);
    if (!rot_ea.empty()) c.max_rotation_euler = std::max(c.max_rotation_euler, rot_ea[i]);
    const double score = std::max(rot[i] / c.tolerance_rotation, trans[i] / c.tolerance_translation);
    if (score > worst_score) {
      worst_score = score;
      worst = i;
    }
  }
  c.mean_rotation = sum_r / static_cast<double>(n);
  c.mean_translation = sum_t / static_cast<double>(n);
  c.p99_rotation = p99(rot);
  c.p99_translation = p99(trans);
  c.worst_q.assign(qs[worst].data(), qs[worst].data() + qs[worst].size());
  c.pass = c.max_rotation <= c.tolerance_rotation && c.max_translation <= c.tolerance_translation;
  c.rotation_errors.assign(rot.begin(), rot.end());
  c.translation_errors.reserve(n);
  for (double t : trans) c.translation_errors.push_back(static_cast<float>(t / L));
}

}  // namespace

ScenarioResult runScenario(const Scenario& scenario, const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const MujocoRobot robot(scenario.model, scenario.tip, scenario.base);
  const PoeModel& poe = robot.poeModel();
  const int n = robot.dof();
  const DhConversion dh = poeToDh(poe);
  const double L = poe.size();

  // the sampled variable q: a robot file's joint variable (scale, offset) or MuJoCo's own
  std::vector<double> scale(static_cast<size_t>(n), 1.0), offset(static_cast<size_t>(n), 0.0);
  std::vector<std::array<double, 2>> ranges(static_cast<size_t>(n));
  auto checkMatches = [&](const RobotFile& f) {
    const PoeModel m = f.poeModel();
    if (m.dof() != n) {
      throw RobotFileError(f.path + ": has " + std::to_string(m.dof()) + " joints but the chain to '" + scenario.tip +
                           "' in " + scenario.model + " has " + std::to_string(n));
    }
    for (int i = 0; i < n; ++i) {
      if (m.joint(i).type != robot.joints()[static_cast<size_t>(i)].type) {
        throw RobotFileError(f.path + ": joint " + std::to_string(i + 1) + " is " + jointTypeName(m.joint(i).type) +
                             " but MuJoCo joint '" + robot.joints()[static_cast<size_t>(i)].name + "' is " +
                             jointTypeName(robot.joints()[static_cast<size_t>(i)].type));
      }
    }
    return m;
  };
  std::optional<PoeModel> variables;
  if (!scenario.joint_variables.empty()) {
    variables = checkMatches(readRobotFile(scenario.joint_variables));
    for (int i = 0; i < n; ++i) {
      scale[static_cast<size_t>(i)] = variables->joint(i).scale;
      offset[static_cast<size_t>(i)] = variables->joint(i).offset;
    }
  }
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<size_t>(i);
    const MujocoJoint& j = robot.joints()[k];
    if (k < scenario.ranges.size()) {
      ranges[k] = scenario.ranges[k];
    } else if (j.type != JointType::Prismatic) {
      ranges[k] = {-M_PI, M_PI};
    } else if (variables && variables->joint(i).range) {
      ranges[k] = *variables->joint(i).range;
    } else if (j.range) {
      ranges[k] = {(*j.range)[0] / scale[k] - offset[k], (*j.range)[1] / scale[k] - offset[k]};
    } else {
      ranges[k] = {-L, L};
    }
  }
  if (!scenario.ranges.empty() && static_cast<int>(scenario.ranges.size()) != n) {
    throw RobotFileError(scenario.path + ": ranges has " + std::to_string(scenario.ranges.size()) + " entries for " +
                         std::to_string(n) + " joints");
  }
  std::vector<CheckedFile> files;
  for (const auto& path : scenario.robot_files) {
    CheckedFile cf{path, readRobotFile(path), std::nullopt};
    const PoeModel m = checkMatches(cf.file);
    if (cf.file.poe) cf.poe = m;
    files.push_back(std::move(cf));
  }

  // samples: named poses (first shard only), then this shard's slice of the random stream
  std::vector<VecX> qs;
  if (options.shard == 1) {
    for (const auto& p : scenario.poses) {
      if (static_cast<int>(p.q.size()) != n) {
        throw RobotFileError(scenario.path + ": pose '" + p.name + "' has " + std::to_string(p.q.size()) +
                             " values for " + std::to_string(n) + " joints");
      }
      qs.push_back(Eigen::Map<const VecX>(p.q.data(), n));
    }
  }
  const long long total = options.samples ? *options.samples : scenario.samples;
  const unsigned long long seed = options.seed ? *options.seed : scenario.seed;
  const long long lo = total * (options.shard - 1) / options.shards, hi = total * options.shard / options.shards;
  for (long long s = lo; s < hi; ++s) {
    std::mt19937_64 rng(mix(seed * 0x100000001B3ULL + static_cast<unsigned long long>(s)));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    VecX q(n);
    for (int i = 0; i < n; ++i) {
      const auto& r = ranges[static_cast<size_t>(i)];
      q[i] = r[0] + unit(rng) * (r[1] - r[0]);
    }
    qs.push_back(q);
  }
  const size_t count = qs.size();

  const size_t n_pose = 2 + files.size();
#ifdef LOWPAIR_HAVE_JACOBIAN
  const size_t n_cmp = n_pose + 1;
#else
  const size_t n_cmp = n_pose;
#endif
  std::vector<std::vector<double>> rot(n_cmp, std::vector<double>(count)), rot_ea(n_pose, std::vector<double>(count)),
      trans(n_cmp, std::vector<double>(count));

  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), std::max<size_t>(1, count)));
  auto work = [&](int t) {
    MujocoRobot::Evaluator mj(robot);
    PoeData poe_data(poe);
    DhData dh_data(dh.model);
    std::vector<PoeData> poe_files;
    std::vector<DhData> dh_files;
    for (const auto& f : files) {
      if (f.poe) poe_files.emplace_back(*f.poe);
      else dh_files.emplace_back(*f.file.dh);
    }
    VecX x(n), qf(n);
#ifdef LOWPAIR_HAVE_JACOBIAN
    Mat6X J_mj(6, n), J_lib(6, n);
#endif
    for (size_t s = static_cast<size_t>(t); s < count; s += static_cast<size_t>(threads)) {
      for (int i = 0; i < n; ++i) x[i] = scale[static_cast<size_t>(i)] * (qs[s][i] + offset[static_cast<size_t>(i)]);
      const Pose T_mj = mj.tipPose(x);
      auto record = [&](size_t c, const Pose& T) {
        rot[c][s] = rotationError(T_mj.R, T.R);
        rot_ea[c][s] = eulerZyxError(T.R, T_mj.R);
        trans[c][s] = (T.p - T_mj.p).norm();
      };
      forwardKinematics(poe, poe_data, x);
      record(0, poe_data.T_base_tool);
      forwardKinematics(dh.model, dh_data, x);
      record(1, dh_data.T_base_tool);
      size_t ip = 0, id = 0;
      for (size_t f = 0; f < files.size(); ++f) {
        if (files[f].poe) {
          const PoeModel& m = *files[f].poe;
          for (int i = 0; i < n; ++i) qf[i] = x[i] / m.joint(i).scale - m.joint(i).offset;
          forwardKinematics(m, poe_files[ip], qf);
          record(2 + f, poe_files[ip++].T_base_tool);
        } else {
          const DhModel& m = *files[f].file.dh;
          for (int i = 0; i < n; ++i) qf[i] = x[i] / m.joint(i).scale;
          forwardKinematics(m, dh_files[id], qf);
          record(2 + f, dh_files[id++].T_base_tool);
        }
      }
#ifdef LOWPAIR_HAVE_JACOBIAN
      mj.tipJacobian(x, J_mj);
      geometricJacobian(poe, poe_data, x, J_lib);
      // rows [v; w]: linear block in length per unit joint motion, angular in rad per unit
      rot[n_pose][s] = (J_mj.bottomRows<3>() - J_lib.bottomRows<3>()).cwiseAbs().maxCoeff();
      trans[n_pose][s] = (J_mj.topRows<3>() - J_lib.topRows<3>()).cwiseAbs().maxCoeff();
#endif
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& th : pool) th.join();

  ScenarioResult result;
  result.scenario = scenario;
  result.size = L;
  result.samples = static_cast<int>(count);
  for (size_t c = 0; c < n_cmp; ++c) {
    ComparisonResult cmp;
    if (c == 0) cmp.name = "poe_vs_mujoco";
    else if (c == 1) cmp.name = "dh_vs_mujoco";
    else if (c < n_pose) cmp.name = "robot_file_vs_mujoco:" + fs::path(files[c - 2].path).filename().string();
    else cmp.name = "jacobian_vs_mujoco";
    cmp.pose = c < n_pose;
    cmp.tolerance_rotation = cmp.pose ? scenario.tol_rotation : scenario.tol_jacobian_rotation;
    cmp.tolerance_translation = (cmp.pose ? scenario.tol_translation : scenario.tol_jacobian_translation) * L;
    summarize(cmp, rot[c], cmp.pose ? rot_ea[c] : std::vector<double>{}, trans[c], L, qs);
    result.pass = result.pass && cmp.pass;
    result.comparisons.push_back(std::move(cmp));
  }
#ifdef LOWPAIR_HAVE_JACOBIAN
  {
    MujocoRobot::Evaluator mj(robot);
    Mat6X J(6, n);
    VecX x(n);
    for (const SingularPose& sp : scenario.singular_poses) {
      if (static_cast<int>(sp.q.size()) != n) {
        throw RobotFileError(scenario.path + ": singular pose '" + sp.name + "' has " + std::to_string(sp.q.size()) +
                             " values for " + std::to_string(n) + " joints");
      }
      for (int i = 0; i < n; ++i) x[i] = scale[static_cast<size_t>(i)] * (sp.q[static_cast<size_t>(i)] + offset[static_cast<size_t>(i)]);
      const SingularityReport report = analyzeSingularity(poe, x);
      mj.tipJacobian(x, J);
      SingularPoseResult out;
      out.name = sp.name;
      out.q = sp.q;
      out.expected = sp.classes;
      out.dof = n;
      out.rank_library = report.rank;
      out.rank_mujoco = scaledRank(poe, J);
      out.sigma_min = report.sigma_min;
      for (const auto& c : report.classes) {
        out.reported.push_back(c.id);
        std::string d = c.id + "(";
        for (size_t k = 0; k < c.joints.size(); ++k) d += (k ? "," : "") + std::to_string(c.joints[k]);
        out.details.push_back(d + ")");
      }
      out.pass = report.singular && out.rank_library == out.rank_mujoco;
      for (const auto& e : sp.classes) {
        out.pass = out.pass && std::find(out.reported.begin(), out.reported.end(), e) != out.reported.end();
      }
      result.pass = result.pass && out.pass;
      result.singular_poses.push_back(out);
    }
  }
  // singularity map over two joints
  if (n >= 3) {
    std::vector<int> mj = scenario.map_joints.empty() ? std::vector<int>{2, 3} : scenario.map_joints;
    for (int j : mj) {
      if (j < 1 || j > n) throw RobotFileError(scenario.path + ": singularity_map joint " + std::to_string(j) + " out of 1.." + std::to_string(n));
    }
    if (!scenario.map_fixed.empty() && static_cast<int>(scenario.map_fixed.size()) != n) {
      throw RobotFileError(scenario.path + ": singularity_map.fixed needs " + std::to_string(n) + " values");
    }
    VecX q0(n);
    for (int i = 0; i < n; ++i) {
      const auto& r = ranges[static_cast<size_t>(i)];
      q0[i] = !scenario.map_fixed.empty() ? scenario.map_fixed[static_cast<size_t>(i)]
              : robot.joints()[static_cast<size_t>(i)].type == JointType::Prismatic ? 0.5 * (r[0] + r[1])
                                                                                     : 0.4;
    }
    const int size = 151;
    result.map_joints = mj;
    result.map_size = size;
    result.map_range_x = ranges[static_cast<size_t>(mj[0] - 1)];
    result.map_range_y = ranges[static_cast<size_t>(mj[1] - 1)];
    result.map_log_sigma.assign(static_cast<size_t>(size * size), 0.0);
    PoeData data(poe);
    Mat6X J(6, n);
    VecX q = q0, x(n);
    for (int a = 0; a < size; ++a) {
      for (int b = 0; b < size; ++b) {
        q[mj[0] - 1] = result.map_range_x[0] + (result.map_range_x[1] - result.map_range_x[0]) * b / (size - 1);
        q[mj[1] - 1] = result.map_range_y[0] + (result.map_range_y[1] - result.map_range_y[0]) * a / (size - 1);
        for (int i = 0; i < n; ++i) x[i] = scale[static_cast<size_t>(i)] * (q[i] + offset[static_cast<size_t>(i)]);
        geometricJacobian(poe, data, x, J);
        result.map_log_sigma[static_cast<size_t>(a * size + b)] = std::log10(std::max(1e-17, scaledSingularValues(poe, J).minCoeff()));
      }
    }
  }
#endif
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace lowpair
