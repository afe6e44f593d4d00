#include "validate.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <thread>

#include <Eigen/SVD>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "mujoco_robot.hpp"
#include "robot_file.hpp"
#include "yaml_reader.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/singularity.hpp"

namespace lowpair {

namespace fs = std::filesystem;

namespace {

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

namespace {
std::vector<double> numbers(const YamlReader& in, const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence()) yamlError(in.path(), node, what + " must be a list of numbers");
  std::vector<double> out;
  for (size_t i = 0; i < node.size(); ++i) out.push_back(in.number(node[i], what + "[" + std::to_string(i) + "]"));
  return out;
}
}  // namespace

Scenario readScenario(const std::string& path) {
  const YAML::Node root = loadYamlFile(path);
  const YamlReader in(path);
  Scenario s;
  s.path = path;
  try {
    in.allowOnly(root, "the scenario", {"name", "description", "model", "tip", "base", "joint_variables",
                                        "robot_files", "samples", "seed", "ranges", "tolerance", "poses",
                                        "singular_poses", "singularity_map"});
    s.name = root["name"] ? in.string(root["name"], "name") : fs::path(path).stem().string();
    if (!root["model"]) yamlError(path, root, "missing 'model' (an MJCF or URDF file)");
    if (!root["tip"]) yamlError(path, root, "missing 'tip' (a site or body name)");
    s.model = relative(path, in.string(root["model"], "model"));
    s.tip = in.string(root["tip"], "tip");
    if (root["base"]) s.base = in.string(root["base"], "base");
    if (root["joint_variables"]) s.joint_variables = relative(path, in.string(root["joint_variables"], "joint_variables"));
    if (const YAML::Node files = root["robot_files"]) {
      if (!files.IsSequence()) yamlError(path, files, "robot_files must be a list");
      for (const auto& f : files) s.robot_files.push_back(relative(path, in.string(f, "robot_files[]")));
    }
    if (root["samples"]) s.samples = static_cast<int>(in.integer(root["samples"], "samples", 0, kMaxSamples));
    if (root["seed"]) s.seed = static_cast<unsigned long long>(in.integer(root["seed"], "seed", 0, 1LL << 53));
    if (const YAML::Node ranges = root["ranges"]) {
      if (!ranges.IsSequence()) yamlError(path, ranges, "ranges must be a list of [lo, hi]");
      for (const auto& r : ranges) {
        const auto v = in.vector(r, 2, "ranges[]");
        if (v[0] > v[1]) yamlError(path, r, "range [lo, hi] needs lo <= hi");
        // samples are lo + u (hi - lo): the width must be finite too
        if (!std::isfinite(v[1] - v[0])) yamlError(path, r, "range [lo, hi] is too wide (hi - lo overflows)");
        s.ranges.push_back({v[0], v[1]});
      }
    }
    if (const YAML::Node t = root["tolerance"]) {
      in.allowOnly(t, "tolerance", {"rotation", "translation", "jacobian_rotation", "jacobian_translation"});
      const std::pair<const char*, double*> fields[] = {{"rotation", &s.tol_rotation},
                                                        {"translation", &s.tol_translation},
                                                        {"jacobian_rotation", &s.tol_jacobian_rotation},
                                                        {"jacobian_translation", &s.tol_jacobian_translation}};
      for (const auto& [key, value] : fields) {
        if (!t[key]) continue;
        *value = in.number(t[key], std::string("tolerance.") + key);
        if (!(*value > 0)) yamlError(path, t[key], std::string("tolerance.") + key + " must be positive");
      }
    }
    if (const YAML::Node poses = root["poses"]) {
      for (const auto& p : poses) {
        in.allowOnly(p, "a pose", {"name", "q"});
        NamedPose np;
        np.name = p["name"] ? in.string(p["name"], "pose name") : "pose" + std::to_string(s.poses.size() + 1);
        np.q = numbers(in, p["q"], "pose '" + np.name + "' q");
        s.poses.push_back(np);
      }
    }
    if (const YAML::Node poses = root["singular_poses"]) {
      for (const auto& p : poses) {
        in.allowOnly(p, "a singular pose", {"name", "q", "classes"});
        SingularPose sp;
        sp.name = p["name"] ? in.string(p["name"], "singular pose name")
                            : "singular" + std::to_string(s.singular_poses.size() + 1);
        sp.q = numbers(in, p["q"], "singular pose '" + sp.name + "' q");
        const YAML::Node classes = p["classes"];
        if (!classes || !classes.IsSequence() || classes.size() == 0) {
          yamlError(path, p, "singular pose '" + sp.name + "' needs classes: [C1..C7 or other]");
        }
        static const std::set<std::string> ids = {"C1", "C2", "C3", "C4", "C5", "C6", "C7", "other"};
        for (const auto& c : classes) {
          const std::string id = in.string(c, "class");
          if (!ids.count(id)) yamlError(path, c, "unknown class '" + id + "' (C1..C7 or other)");
          sp.classes.push_back(id);
        }
        s.singular_poses.push_back(sp);
      }
    }
    if (const YAML::Node m = root["singularity_map"]) {
      in.allowOnly(m, "singularity_map", {"joints", "fixed"});
      if (m["joints"]) {
        for (double j : numbers(in, m["joints"], "singularity_map.joints")) s.map_joints.push_back(static_cast<int>(j));
        if (s.map_joints.size() != 2) yamlError(path, m["joints"], "singularity_map.joints must name two joints (1-based)");
      }
      if (m["fixed"]) s.map_fixed = numbers(in, m["fixed"], "singularity_map.fixed");
    }
  } catch (const YAML::Exception& e) {
    throw RobotFileError(path + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  return s;
}

namespace {

// Singular values of the dimensionless geometric Jacobian (singularity.hpp).
VecX dimensionlessSingularValues(const PoeModel& model, Mat6X J_geometric) {
  dimensionlessJacobian(model, J_geometric);
  return Eigen::JacobiSVD<MatX>(J_geometric).singularValues();
}

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
    // a sample that was not measured (NaN or inf) is never within tolerance: counted, and the comparison fails
    if (!std::isfinite(rot[i]) || !std::isfinite(trans[i]) || (!rot_ea.empty() && !std::isfinite(rot_ea[i]))) {
      ++c.non_finite;
      if (c.non_finite == 1) worst = i;
      worst_score = std::numeric_limits<double>::infinity();
      continue;
    }
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
  if (c.non_finite > 0) {
    // statistics of what was not measured are not numbers: reported as NaN (JSON null)
    const double nan = std::numeric_limits<double>::quiet_NaN();
    c.max_rotation = c.mean_rotation = c.p99_rotation = c.max_rotation_euler = nan;
    c.max_translation = c.mean_translation = c.p99_translation = nan;
  } else {
    c.mean_rotation = sum_r / static_cast<double>(n);
    c.mean_translation = sum_t / static_cast<double>(n);
    c.p99_rotation = p99(rot);
    c.p99_translation = p99(trans);
  }
  c.worst_q.assign(qs[worst].data(), qs[worst].data() + qs[worst].size());
  c.pass = c.non_finite == 0 && c.max_rotation <= c.tolerance_rotation &&
           c.max_translation <= c.tolerance_translation;
  c.rotation_errors.assign(rot.begin(), rot.end());
  c.translation_errors.reserve(n);
  for (double t : trans) c.translation_errors.push_back(static_cast<float>(t / L));
}

}  // namespace

ScenarioResult runScenario(const Scenario& scenario, const RunOptions& options) {
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
  if (count == 0) {
    throw RobotFileError((scenario.path.empty() ? scenario.model : scenario.path) +
                         ": nothing to validate (no samples in this shard and no named poses)");
  }

  // comparisons: poe, dh, each robot file (poses), then the Jacobian
  const size_t n_pose = 2 + files.size();
  const size_t n_cmp = n_pose + 1;
  std::vector<std::vector<double>> rot(n_cmp, std::vector<double>(count)), rot_ea(n_pose, std::vector<double>(count)),
      trans(n_cmp, std::vector<double>(count));

  int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), count));
  // thread t takes the contiguous block [t count / T, (t + 1) count / T): no shared cache lines
  auto work = [&](int t) {
    MujocoRobot::Evaluator mj(robot);
    Data poe_data(poe);
    Data dh_data(dh.model);
    std::vector<Data> poe_files;
    std::vector<Data> dh_files;
    for (const auto& f : files) {
      if (f.poe) poe_files.emplace_back(*f.poe);
      else dh_files.emplace_back(*f.file.dh);
    }
    VecX x(n), qf(n);
    Mat6X J_mj(6, n), J_lib(6, n);
    const size_t begin = count * static_cast<size_t>(t) / static_cast<size_t>(threads);
    const size_t end = count * static_cast<size_t>(t + 1) / static_cast<size_t>(threads);
    for (size_t s = begin; s < end; ++s) {
      for (int i = 0; i < n; ++i) x[i] = scale[static_cast<size_t>(i)] * (qs[s][i] + offset[static_cast<size_t>(i)]);
      const Pose T_mj = mj.tipJacobian(x, J_mj);  // one mj_kinematics: pose and Jacobian
      auto record = [&](size_t c, const Pose& T) {
        rot[c][s] = rotationError(T_mj.R, T.R);
        rot_ea[c][s] = eulerZyxError(T.R, T_mj.R);
        trans[c][s] = (T.p - T_mj.p).norm();
      };
      computeJacobians(poe, poe_data, x);  // includes the POE FK
      getGeometricJacobian(poe_data, J_lib);
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
      // Jacobians compared dimensionless (singularity.hpp: linear rows / L, prismatic columns x L), so a
      // prismatic column's unitless linear part and a revolute column's length per rad share one scale;
      // the linear difference is stored in length units (times L) like the pose comparisons.
      dimensionlessJacobian(poe, J_mj);
      dimensionlessJacobian(poe, J_lib);
      // maxCoeff may skip NaN: a non-finite Jacobian is recorded as NaN so that the comparison fails
      const bool finite = J_mj.allFinite() && J_lib.allFinite();
      const double nan = std::numeric_limits<double>::quiet_NaN();
      rot[n_pose][s] = finite ? (J_mj.bottomRows<3>() - J_lib.bottomRows<3>()).cwiseAbs().maxCoeff() : nan;
      trans[n_pose][s] = finite ? L * (J_mj.topRows<3>() - J_lib.topRows<3>()).cwiseAbs().maxCoeff() : nan;
    }
  };
  const auto start = std::chrono::steady_clock::now();
  {
    // an exception in a worker (e.g. out of memory) is rethrown here, after every thread has joined
    std::vector<std::exception_ptr> errors(static_cast<size_t>(threads));
    auto guarded = [&](int t) {
      try {
        work(t);
      } catch (...) {
        errors[static_cast<size_t>(t)] = std::current_exception();
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(guarded, t);
    guarded(0);
    for (auto& th : pool) th.join();
    for (const auto& e : errors) {
      if (e) std::rethrow_exception(e);
    }
  }

  ScenarioResult result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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

  // singular poses: rank deficient, MuJoCo's Jacobian of the same rank, the expected classes reported
  {
    MujocoRobot::Evaluator mj(robot);
    Mat6X J(6, n);
    VecX x(n);
    for (const SingularPose& sp : scenario.singular_poses) {
      if (static_cast<int>(sp.q.size()) != n) {
        throw RobotFileError(scenario.path + ": singular pose '" + sp.name + "' has " + std::to_string(sp.q.size()) +
                             " values for " + std::to_string(n) + " joints");
      }
      for (int i = 0; i < n; ++i) {
        x[i] = scale[static_cast<size_t>(i)] * (sp.q[static_cast<size_t>(i)] + offset[static_cast<size_t>(i)]);
      }
      const SingularityReport report = analyzeSingularity(poe, x);
      mj.tipJacobian(x, J);
      const VecX sigma_mj = dimensionlessSingularValues(poe, J);
      SingularPoseResult out;
      out.name = sp.name;
      out.q = sp.q;
      out.expected = sp.classes;
      out.dof = n;
      out.rank_library = report.rank;
      out.rank_mujoco = numericalRank(sigma_mj, rankTolerance(sigma_mj[0], n));
      out.sigma_min = report.sigma_min;
      for (const auto& c : report.classes) {
        std::string d = c.id + "(";
        for (size_t k = 0; k < c.joints.size(); ++k) d += (k ? "," : "") + std::to_string(c.joints[k]);
        out.reported.push_back(d + ")");
      }
      out.pass = report.singular && out.rank_library == out.rank_mujoco;
      for (const auto& e : sp.classes) {
        out.pass = out.pass && std::any_of(report.classes.begin(), report.classes.end(),
                                           [&](const SingularClass& c) { return c.id == e; });
      }
      result.pass = result.pass && out.pass;
      result.singular_poses.push_back(out);
    }
  }

  // singularity map over two joints (for the report only)
  if (options.singularity_map && n >= 3) {
    std::vector<int> mj = scenario.map_joints.empty() ? std::vector<int>{2, 3} : scenario.map_joints;
    for (int j : mj) {
      if (j < 1 || j > n) {
        throw RobotFileError(scenario.path + ": singularity_map joint " + std::to_string(j) + " is not in 1.." +
                             std::to_string(n));
      }
    }
    if (!scenario.map_fixed.empty() && static_cast<int>(scenario.map_fixed.size()) != n) {
      throw RobotFileError(scenario.path + ": singularity_map.fixed needs " + std::to_string(n) + " values");
    }
    VecX q(n), x(n);
    for (int i = 0; i < n; ++i) {
      const auto& r = ranges[static_cast<size_t>(i)];
      q[i] = !scenario.map_fixed.empty() ? scenario.map_fixed[static_cast<size_t>(i)]
             : robot.joints()[static_cast<size_t>(i)].type == JointType::Prismatic ? 0.5 * (r[0] + r[1])
                                                                                    : 0.4;
    }
    const int size = 151;
    result.map_joints = mj;
    result.map_size = size;
    result.map_range_x = ranges[static_cast<size_t>(mj[0] - 1)];
    result.map_range_y = ranges[static_cast<size_t>(mj[1] - 1)];
    result.map_log_sigma.assign(static_cast<size_t>(size * size), 0.0);
    Data data(poe);
    Mat6X J(6, n);
    for (int a = 0; a < size; ++a) {
      for (int b = 0; b < size; ++b) {
        q[mj[0] - 1] = result.map_range_x[0] + (result.map_range_x[1] - result.map_range_x[0]) * b / (size - 1);
        q[mj[1] - 1] = result.map_range_y[0] + (result.map_range_y[1] - result.map_range_y[0]) * a / (size - 1);
        for (int i = 0; i < n; ++i) x[i] = scale[static_cast<size_t>(i)] * (q[i] + offset[static_cast<size_t>(i)]);
        computeJacobians(poe, data, x);
        getGeometricJacobian(data, J);
        result.map_log_sigma[static_cast<size_t>(a * size + b)] =
            std::log10(std::max(1e-17, dimensionlessSingularValues(poe, J).minCoeff()));
      }
    }
  }
  return result;
}

}  // namespace lowpair
