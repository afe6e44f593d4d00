#include "validation/validate.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
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
#include "mujoco/mujoco_robot.hpp"
#include "io/robot_file.hpp"
#include "io/urdf_reader.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::commands;
using namespace lowpair::mujoco;

namespace fs = std::filesystem;


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
  SampledVariable sampled;  // q, its map to the motion x (x_i = motions[i].motion(q_i)), ranges and unit
  std::vector<std::unique_ptr<Comparison>> comparisons;
};

// A robot file whose size L differs from the model's by a power of ten (10, 100, 1000) is almost always
// a unit mix-up (an MJCF states no unit): say so once on stderr, naming the units that would explain it and
// the option that fixes it.
void noteScaleMismatch(const RobotFile& file, const PoeModel& model, const std::string& model_unit,
                       const std::string& model_path) {
  const double ratio = file.poeModel().lengthScale() / model.lengthScale();
  for (const double factor : {10.0, 100.0, 1000.0, 0.1, 0.01, 0.001}) {
    if (std::abs(ratio / factor - 1.0) > 0.01) continue;
    // the unit the model's numbers would be in if the robot file's unit is right
    std::string implied = "another unit";
    if (const std::optional<double> m = metresPerUnit(file.length_unit)) {
      for (const char* unit : {"km", "m", "dm", "cm", "mm", "um"}) {
        if (std::abs(*metresPerUnit(unit) / (*m * factor) - 1.0) < 1e-9) implied = unit;
      }
    }
    std::fprintf(stderr,
                 "note: %s: its lengths are %g times those of %s: is the robot file in %s and the model in %s? "
                 "state the model's unit with --length-unit U (a scenario's length_unit)%s\n",
                 file.path.c_str(), factor, model_path.c_str(),
                 file.length_unit.empty() ? "another unit" : file.length_unit.c_str(), implied.c_str(),
                 model_unit.empty() ? "" : (" (stated: " + model_unit + ")").c_str());
    return;
  }
}

Setup prepare(const Scenario& scenario) {
  Setup setup;
  setup.robot = std::make_unique<MujocoRobot>(scenario.model, scenario.tip, scenario.base);
  const MujocoRobot& robot = *setup.robot;
  setup.poe = std::make_unique<PoeModel>(robot.poeModel());
  const PoeModel& poe = *setup.poe;
  const double L = setup.L = poe.lengthScale();

  // the sampled variable (a joint_variables robot file's q, or MuJoCo's own) and its ranges: commands/sampling.hpp
  setup.sampled =
      sampledVariable(robot, scenario.joint_variables, scenario.model, scenario.tip, scenario.ranges, scenario.path);

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
    // a URDF is in metres, an MJCF in its scenario's length_unit when one is stated: a robot file in another
    // unit is compared in the model's (as export converts it)
    const std::string model_unit = urdf ? std::string("m") : scenario.length_unit;
    if (!model_unit.empty() && !file.length_unit.empty() && file.length_unit != model_unit) {
      file = inUnit(file, model_unit);
    }
    noteScaleMismatch(file, poe, model_unit, scenario.model);
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
          for (int i = 0; i < n; ++i) x[i] = setup.sampled.motions[static_cast<size_t>(i)].motion(q[i]);
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
  for (int i = 0; i < n; ++i) x[i] = setup.sampled.motions[static_cast<size_t>(i)].motion(sp.q[static_cast<size_t>(i)]);
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
    const auto& r = setup.sampled.ranges[static_cast<size_t>(i)];
    q[i] = !scenario.map_fixed.empty() ? scenario.map_fixed[static_cast<size_t>(i)]
           : setup.robot->joints()[static_cast<size_t>(i)].type == JointType::Prismatic ? 0.5 * (r[0] + r[1])
                                                                                        : 0.4;
  }
  const int size = 151;
  result.map_joints = joints;
  result.map_fixed.assign(q.data(), q.data() + q.size());
  for (int i = 0; i < n; ++i) {
    result.map_prismatic.push_back(setup.robot->joints()[static_cast<size_t>(i)].type == JointType::Prismatic);
  }
  result.map_size = size;
  result.map_range_x = setup.sampled.ranges[static_cast<size_t>(joints[0] - 1)];
  result.map_range_y = setup.sampled.ranges[static_cast<size_t>(joints[1] - 1)];
  result.map_log_sigma.assign(static_cast<size_t>(size * size), 0.0);
  Data data(*setup.poe);
  Mat6X J(6, n);
  for (int a = 0; a < size; ++a) {
    for (int b = 0; b < size; ++b) {
      q[joints[0] - 1] = result.map_range_x[0] + (result.map_range_x[1] - result.map_range_x[0]) * b / (size - 1);
      q[joints[1] - 1] = result.map_range_y[0] + (result.map_range_y[1] - result.map_range_y[0]) * a / (size - 1);
      for (int i = 0; i < n; ++i) x[i] = setup.sampled.motions[static_cast<size_t>(i)].motion(q[i]);
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
  const SampleStream stream(std::move(poses), setup.sampled.ranges, seed, lo, hi);
  if (stream.size() == 0) throw RobotFileError(subject(scenario) + ": nothing to validate (no samples in this shard and no named poses)");

  ScenarioResult result;
  result.scenario = scenario;
  result.size = setup.L;
  result.samples = static_cast<int>(stream.size());
  const int threads =
      options.threads > 0 ? std::min(options.threads, kMaxThreads)
                          : static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, static_cast<unsigned>(kMaxThreads)));
  runSamples(setup, stream, threads, result);

  MujocoRobot::Evaluator mujoco(*setup.robot);
  for (const SingularPose& sp : scenario.singular_poses) {
    result.singular_poses.push_back(checkSingularPose(setup, mujoco, sp));
    result.pass = result.pass && result.singular_poses.back().pass;
  }
  if (options.singularity_map && n >= 3) singularityMap(scenario, setup, result);
  if (options.shard == 1) {
    for (const CalibrationCase& c : scenario.calibrations) {
      result.calibrations.push_back(runCalibrationCase(scenario, c, *setup.robot, setup.sampled));
      result.pass = result.pass && result.calibrations.back().pass;
    }
  }
  return result;
}

}  // namespace lowpair::validation
