#include "validate.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/singularity.hpp"
#include "mujoco_robot.hpp"
#include "robot_file.hpp"
#include "urdf_reader.hpp"

namespace lowpair {

namespace fs = std::filesystem;

int runWorkers(int threads, const std::function<void(int)>& work, const ThreadStarter& start) {
  threads = std::max(1, threads);
  std::vector<std::exception_ptr> errors(static_cast<size_t>(threads));
  auto guarded = [&](int t) {
    try {
      work(t);
    } catch (...) {
      errors[static_cast<size_t>(t)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(threads - 1));
  int started = 1;
  for (int t = 1; t < threads; ++t) {
    try {
      std::function<void()> job = [&guarded, t] { guarded(t); };
      std::thread th = start ? start(std::move(job)) : std::thread(std::move(job));
      if (!th.joinable()) break;
      pool.push_back(std::move(th));  // no allocation: reserved
    } catch (...) {
      break;  // no more threads (std::system_error, std::bad_alloc): run with those started
    }
    ++started;
  }
  guarded(0);
  for (auto& th : pool) th.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return started;
}

namespace {

// splitmix64: decorrelated per-sample seeds, so a sample's q depends only on (seed, index) and the
// results do not depend on the thread count or the shard.
unsigned long long mix(unsigned long long x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// The first outputs of std::mt19937_64 seeded with one value, bit for bit, without its full state: output
// k < 156 of the first twist needs state words k, k + 1 and k + 156 of the seeding only, so the seeding
// stops at word 156 + (outputs drawn) instead of filling 312 words and twisting them all (0.75 us instead
// of 4.5 us for a 6-joint sample here; the random stream, and with it every result, is unchanged:
// tests/validate_test.cpp checks it against std::mt19937_64).
class Mt19937_64Prefix {
 public:
  using result_type = std::uint_fast64_t;
  static constexpr int kMaxOutputs = 156;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }

  explicit Mt19937_64Prefix(result_type seed) { x_[0] = seed; }

  result_type operator()() {
    if (k_ >= kMaxOutputs) throw std::logic_error("Mt19937_64Prefix: more than 156 outputs");
    const int k = k_++;
    for (; seeded_ <= k + kM; ++seeded_) {  // seeding of std::mersenne_twister_engine, word by word
      const result_type prev = x_[static_cast<size_t>(seeded_ - 1)];
      x_[static_cast<size_t>(seeded_)] = 6364136223846793005ULL * (prev ^ (prev >> 62)) + static_cast<result_type>(seeded_);
    }
    const result_type y = (x_[static_cast<size_t>(k)] & kUpper) | (x_[static_cast<size_t>(k + 1)] & kLower);
    result_type z = x_[static_cast<size_t>(k + kM)] ^ (y >> 1) ^ ((y & 1) ? kA : 0);  // the twist of word k
    z ^= (z >> 29) & 0x5555555555555555ULL;  // tempering
    z ^= (z << 17) & 0x71D67FFFEDA60000ULL;
    z ^= (z << 37) & 0xFFF7EEE000000000ULL;
    return z ^ (z >> 43);
  }

 private:
  static constexpr int kM = 156;
  static constexpr result_type kA = 0xB5026F5AA96619E9ULL, kUpper = ~result_type{0} << 31, kLower = ~kUpper;
  std::array<result_type, 312> x_;  // words 0 .. seeded_ - 1 are set
  int seeded_ = 1, k_ = 0;
};

template <class Engine>
void drawSample(Engine& rng, const std::vector<std::array<double, 2>>& ranges, Eigen::Ref<VecX> q) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const auto& r = ranges[static_cast<size_t>(i)];
    q[i] = r[0] + unit(rng) * (r[1] - r[0]);
  }
}

}  // namespace

void addMeasurementNoise(unsigned long long seed, unsigned long long index, double sd_position, double sd_rotation,
                         Pose& T) {
  if (sd_position == 0.0 && sd_rotation == 0.0) return;
  constexpr unsigned long long kNoiseStream = 0x6E6F6973652D7374ULL;  // "noise-st"
  std::mt19937_64 rng(mix(mix(seed ^ kNoiseStream) + index));
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec3 dp, n;
  for (int k = 0; k < 3; ++k) dp[k] = sd_position * normal(rng);
  for (int k = 0; k < 3; ++k) n[k] = sd_rotation * normal(rng);
  T.p += dp;
  T.R = expSO3(n) * T.R;
}

PoeModel matchingModel(const RobotFile& file, const MujocoRobot& robot, const std::string& model_path,
                       const std::string& tip) {
  const PoeModel m = file.poeModel();
  if (m.dof() != robot.dof()) {
    throw RobotFileError(file.path + ": has " + std::to_string(m.dof()) + " joints but the chain to '" + tip + "' in " +
                         model_path + " has " + std::to_string(robot.dof()));
  }
  for (int i = 0; i < m.dof(); ++i) {
    const MujocoJoint& j = robot.joints()[static_cast<size_t>(i)];
    if (m.joint(i).type != j.type) {
      throw RobotFileError(file.path + ": joint " + std::to_string(i + 1) + " is " + jointTypeName(m.joint(i).type) +
                           " but MuJoCo joint '" + j.name + "' is " + jointTypeName(j.type));
    }
  }
  return m;
}

std::vector<std::array<double, 2>> samplingRanges(const PoeModel& model) {
  std::vector<std::array<double, 2>> ranges;
  for (const Joint& j : model.joints()) {
    if (j.range) {
      ranges.push_back(*j.range);
    } else if (j.type == JointType::Prismatic) {
      ranges.push_back({-model.size(), model.size()});
    } else {
      ranges.push_back({-M_PI, M_PI});
    }
  }
  return ranges;
}

void randomSample(unsigned long long seed, unsigned long long index, const std::vector<std::array<double, 2>>& ranges,
                  Eigen::Ref<VecX> q) {
  const unsigned long long s = mix(seed * 0x100000001B3ULL + index);
  // one engine call per draw in libstdc++ and libc++ (generate_canonical<double, 53> of a 64-bit engine); room for two
  if (2 * q.size() <= Mt19937_64Prefix::kMaxOutputs) {
    Mt19937_64Prefix rng(s);
    drawSample(rng, ranges, q);
  } else {
    std::mt19937_64 rng(s);
    drawSample(rng, ranges, q);
  }
}

namespace {

// The samples of one run, in the sampled variable, generated where they are used: the named poses (first
// shard only), then this shard's slice [first, last) of the random stream. Sample `index` of the run is
// always the same q, whoever asks for it.
class SampleStream {
 public:
  SampleStream(std::vector<VecX> poses, std::vector<std::array<double, 2>> ranges, unsigned long long seed,
               long long first, long long last)
      : poses_(std::move(poses)), ranges_(std::move(ranges)), seed_(seed), first_(first), last_(last) {}

  long long size() const { return static_cast<long long>(poses_.size()) + (last_ - first_); }

  void q(long long index, Eigen::Ref<VecX> out) const {
    const auto named = static_cast<long long>(poses_.size());
    if (index < named) {
      out = poses_[static_cast<size_t>(index)];
      return;
    }
    randomSample(seed_, static_cast<unsigned long long>(first_ + (index - named)), ranges_, out);
  }

 private:
  std::vector<VecX> poses_;
  std::vector<std::array<double, 2>> ranges_;
  unsigned long long seed_;
  long long first_, last_;
};

std::string subject(const Scenario& scenario) { return scenario.path.empty() ? scenario.model : scenario.path; }

// Everything a run needs besides the samples: the MuJoCo chain, the sampled variable's joint map, the
// sampling ranges, and the comparisons.
struct Setup {
  std::unique_ptr<MujocoRobot> robot;
  std::unique_ptr<PoeModel> poe;  // extracted from MuJoCo: its joint variable is the motion x
  double L = 1.0;
  std::vector<JointMotion> variables;  // x_i = variables[i].motion(q_i)
  std::vector<std::array<double, 2>> ranges;  // per joint, in the sampled variable
  std::vector<std::unique_ptr<Comparison>> comparisons;
};

Setup prepare(const Scenario& scenario) {
  Setup setup;
  setup.robot = std::make_unique<MujocoRobot>(scenario.model, scenario.tip, scenario.base);
  const MujocoRobot& robot = *setup.robot;
  setup.poe = std::make_unique<PoeModel>(robot.poeModel());
  const PoeModel& poe = *setup.poe;
  const int n = robot.dof();
  const double L = setup.L = poe.size();

  // the sampled variable: the joint_variables robot file's q, or MuJoCo's own (scale 1, offset 0)
  std::optional<PoeModel> variable_model;
  setup.variables.assign(static_cast<size_t>(n), JointMotion{});
  if (!scenario.joint_variables.empty()) {
    variable_model = matchingModel(readRobotFile(scenario.joint_variables), robot, scenario.model, scenario.tip);
    for (int i = 0; i < n; ++i) setup.variables[static_cast<size_t>(i)] = variable_model->joint(i);
  }
  if (!scenario.ranges.empty() && static_cast<int>(scenario.ranges.size()) != n) {
    throw RobotFileError(scenario.path + ": ranges has " + std::to_string(scenario.ranges.size()) + " entries for " +
                         std::to_string(n) + " joints");
  }
  // default ranges: revolute/helical [-pi, pi]; prismatic the variable file's range, else MuJoCo's range
  // mapped into the sampled variable, else [-L, L]
  setup.ranges.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<size_t>(i);
    const MujocoJoint& j = robot.joints()[k];
    if (!scenario.ranges.empty()) {
      setup.ranges[k] = scenario.ranges[k];
    } else if (j.type != JointType::Prismatic) {
      setup.ranges[k] = {-M_PI, M_PI};
    } else if (variable_model && variable_model->joint(i).range) {
      setup.ranges[k] = *variable_model->joint(i).range;
    } else if (j.range) {
      setup.ranges[k] = {setup.variables[k].variable((*j.range)[0]), setup.variables[k].variable((*j.range)[1])};
    } else {
      setup.ranges[k] = {-L, L};
    }
  }

  // the comparisons: poe, dh, each robot file (poses), then the Jacobian
  const double tr = scenario.tol_rotation, tt = scenario.tol_translation * L;
  setup.comparisons.push_back(poseComparison("poe_vs_mujoco", poe, tr, tt));
  setup.comparisons.push_back(poseComparison("dh_vs_mujoco", poeToDh(poe).model, tr, tt));
  const bool urdf = fs::path(scenario.model).extension() == ".urdf";
  if (urdf) {  // the URDF's own reading (urdfdom) against MuJoCo's
    setup.comparisons.push_back(poseComparison(
        "urdfdom_vs_mujoco", matchingModel(readUrdf(scenario.model, scenario.tip, scenario.base), robot, scenario.model, scenario.tip), tr, tt));
  }
  for (const auto& path : scenario.robot_files) {
    RobotFile file = readRobotFile(path);
    // a URDF is in metres: a robot file in another unit is compared in metres (as export converts it)
    if (urdf && !file.length_unit.empty() && file.length_unit != "m") file = inMetres(file);
    const PoeModel m = matchingModel(file, robot, scenario.model, scenario.tip);
    std::string name = "robot_file_vs_mujoco:" + fs::path(path).filename().string();
    if (file.poe) {
      setup.comparisons.push_back(poseComparison(std::move(name), m, tr, tt));
    } else {
      setup.comparisons.push_back(poseComparison(std::move(name), std::move(*file.dh), tr, tt));
    }
  }
  setup.comparisons.push_back(
      jacobianComparison("jacobian_vs_mujoco", poe, scenario.tol_jacobian_rotation, scenario.tol_jacobian_translation * L));
  return setup;
}

// Every sample through every comparison, on `threads` workers taking chunks of consecutive samples from a
// shared counter; per-thread statistics merged after the join (exactly: the results do not depend on the
// thread count or on which thread took which chunk).
void runSamples(const Setup& setup, const SampleStream& stream, int threads, ScenarioResult& result) {
  constexpr long long kChunk = 1024;
  const MujocoRobot& robot = *setup.robot;
  const int n = robot.dof();
  const size_t n_cmp = setup.comparisons.size();
  const long long count = stream.size();
  const long long chunks = (count + kChunk - 1) / kChunk;
  threads = static_cast<int>(std::min<long long>(threads, chunks));

  std::vector<PlotSamples> plots;
  for (size_t c = 0; c < n_cmp; ++c) plots.emplace_back(count, setup.L);
  std::vector<std::vector<ErrorStatistics>> stats(static_cast<size_t>(threads));  // [thread][comparison]
  std::atomic<long long> next_chunk{0};
  std::atomic<bool> stop{false};
  auto work = [&](int t) {
    try {
      MujocoRobot::Evaluator mujoco(robot);
      std::vector<std::unique_ptr<Comparison::Workspace>> workspaces;
      std::vector<ErrorStatistics>& mine = stats[static_cast<size_t>(t)];
      for (const auto& c : setup.comparisons) {
        workspaces.push_back(c->workspace());
        mine.emplace_back(c->toleranceRotation(), c->toleranceTranslation(), setup.L);
      }
      VecX q(n), x(n);
      Mat6X J(6, n);
      while (!stop.load(std::memory_order_relaxed)) {
        const long long chunk = next_chunk.fetch_add(1, std::memory_order_relaxed);
        if (chunk >= chunks) break;
        const long long end = std::min(count, (chunk + 1) * kChunk);
        for (long long s = chunk * kChunk; s < end; ++s) {
          stream.q(s, q);
          for (int i = 0; i < n; ++i) x[i] = setup.variables[static_cast<size_t>(i)].motion(q[i]);
          const Pose T = mujoco.tipJacobian(x, J);  // one mj_kinematics: pose and Jacobian
          const ReferenceSample sample{x, T, J};
          for (size_t c = 0; c < n_cmp; ++c) {
            const SampleErrors e = setup.comparisons[c]->measure(*workspaces[c], sample);
            mine[c].add(s, e);
            plots[c].record(s, e);
          }
        }
      }
    } catch (...) {
      stop = true;  // the others stop early; runWorkers rethrows after the join
      throw;
    }
  };
  const auto start = std::chrono::steady_clock::now();
  result.threads_requested = threads;
  result.threads = runWorkers(threads, work);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  VecX q(n);
  for (size_t c = 0; c < n_cmp; ++c) {
    const Comparison& comparison = *setup.comparisons[c];
    ErrorStatistics total(comparison.toleranceRotation(), comparison.toleranceTranslation(), setup.L);
    for (const auto& mine : stats) {
      if (!mine.empty()) total.merge(mine[c]);
    }
    ComparisonResult cmp;
    cmp.name = comparison.name();
    cmp.pose = comparison.kind() == Comparison::Kind::Pose;
    total.summarize(cmp);
    if (total.worstIndex() >= 0) {
      stream.q(total.worstIndex(), q);
      cmp.worst_q.assign(q.data(), q.data() + q.size());
    }
    cmp.plot_stride = plots[c].stride;
    cmp.rotation_errors = std::move(plots[c].rotation);
    cmp.translation_errors = std::move(plots[c].translation);
    result.pass = result.pass && cmp.pass;
    result.comparisons.push_back(std::move(cmp));
  }
}

// At a singular pose: rank deficient, MuJoCo's Jacobian of the same rank, the expected classes reported.
SingularPoseResult checkSingularPose(const Setup& setup, MujocoRobot::Evaluator& mujoco, const SingularPose& sp) {
  const int n = setup.robot->dof();
  VecX x(n);
  Mat6X J(6, n);
  for (int i = 0; i < n; ++i) x[i] = setup.variables[static_cast<size_t>(i)].motion(sp.q[static_cast<size_t>(i)]);
  const SingularityReport report = analyzeSingularity(*setup.poe, x);
  mujoco.tipJacobian(x, J);
  SingularPoseResult out;
  out.name = sp.name;
  out.q = sp.q;
  out.expected = sp.classes;
  out.dof = n;
  out.rank_library = report.rank;
  out.rank_mujoco = jacobianRank(*setup.poe, J).rank;
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
  return out;
}

// log10 sigma_min of the dimensionless Jacobian over two joints (for the report only).
void singularityMap(const Scenario& scenario, const Setup& setup, ScenarioResult& result) {
  const int n = setup.robot->dof();
  const std::vector<int> joints = scenario.map_joints.empty() ? std::vector<int>{2, 3} : scenario.map_joints;
  for (int j : joints) {
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
    const auto& r = setup.ranges[static_cast<size_t>(i)];
    q[i] = !scenario.map_fixed.empty() ? scenario.map_fixed[static_cast<size_t>(i)]
           : setup.robot->joints()[static_cast<size_t>(i)].type == JointType::Prismatic ? 0.5 * (r[0] + r[1])
                                                                                        : 0.4;
  }
  const int size = 151;
  result.map_joints = joints;
  result.map_size = size;
  result.map_range_x = setup.ranges[static_cast<size_t>(joints[0] - 1)];
  result.map_range_y = setup.ranges[static_cast<size_t>(joints[1] - 1)];
  result.map_log_sigma.assign(static_cast<size_t>(size * size), 0.0);
  Data data(*setup.poe);
  Mat6X J(6, n);
  for (int a = 0; a < size; ++a) {
    for (int b = 0; b < size; ++b) {
      q[joints[0] - 1] = result.map_range_x[0] + (result.map_range_x[1] - result.map_range_x[0]) * b / (size - 1);
      q[joints[1] - 1] = result.map_range_y[0] + (result.map_range_y[1] - result.map_range_y[0]) * a / (size - 1);
      for (int i = 0; i < n; ++i) x[i] = setup.variables[static_cast<size_t>(i)].motion(q[i]);
      computeJacobians(*setup.poe, data, x);
      getGeometricJacobian(data, J);
      result.map_log_sigma[static_cast<size_t>(a * size + b)] =
          std::log10(std::max(1e-17, jacobianRank(*setup.poe, J).singular_values.minCoeff()));
    }
  }
}

}  // namespace

ScenarioResult runScenario(const Scenario& scenario, const RunOptions& options) {
  const Setup setup = prepare(scenario);
  const int n = setup.robot->dof();

  // samples: named poses (first shard only), then this shard's slice of the random stream
  std::vector<VecX> poses;
  if (options.shard == 1) {
    for (const auto& p : scenario.poses) {
      if (static_cast<int>(p.q.size()) != n) {
        throw RobotFileError(scenario.path + ": pose '" + p.name + "' has " + std::to_string(p.q.size()) +
                             " values for " + std::to_string(n) + " joints");
      }
      poses.push_back(Eigen::Map<const VecX>(p.q.data(), n));
    }
  }
  for (const SingularPose& sp : scenario.singular_poses) {
    if (static_cast<int>(sp.q.size()) != n) {
      throw RobotFileError(scenario.path + ": singular pose '" + sp.name + "' has " + std::to_string(sp.q.size()) +
                           " values for " + std::to_string(n) + " joints");
    }
  }
  const long long total = options.samples ? *options.samples : scenario.samples;
  const unsigned long long seed = options.seed ? *options.seed : scenario.seed;
  const long long lo = total * (options.shard - 1) / options.shards, hi = total * options.shard / options.shards;
  const SampleStream stream(std::move(poses), setup.ranges, seed, lo, hi);
  if (stream.size() == 0) throw RobotFileError(subject(scenario) + ": nothing to validate (no samples in this shard and no named poses)");

  ScenarioResult result;
  result.scenario = scenario;
  result.size = setup.L;
  result.samples = static_cast<int>(stream.size());
  const int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  runSamples(setup, stream, threads, result);

  MujocoRobot::Evaluator mujoco(*setup.robot);
  for (const SingularPose& sp : scenario.singular_poses) {
    result.singular_poses.push_back(checkSingularPose(setup, mujoco, sp));
    result.pass = result.pass && result.singular_poses.back().pass;
  }
  if (options.singularity_map && n >= 3) singularityMap(scenario, setup, result);
  if (options.shard == 1) {
    for (const CalibrationCase& c : scenario.calibrations) {
      result.calibrations.push_back(runCalibrationCase(scenario, c, *setup.robot, setup.variables, setup.ranges));
      result.pass = result.pass && result.calibrations.back().pass;
    }
  }
  return result;
}

}  // namespace lowpair
