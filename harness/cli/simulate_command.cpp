// lowpair simulate ROBOT --poses N [--seed S] [--measure pose|position] [--noise-position S] [--noise-rotation S]
//                  [--joint-variables FILE.yaml] [--out FILE.csv]
// Measurements of the tool frame (measurements.hpp) at N random joint vectors: from the library's FK of a
// robot file, or from MuJoCo (the ground truth) for a model file's chain; with optional Gaussian noise.
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "io/atomic_file.hpp"
#include "cli/commands.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "io/measurements.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/output.hpp"
#include "validation/validate.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::mujoco;
using namespace lowpair::validation;

namespace fs = std::filesystem;

namespace {

constexpr int kMaxPoses = 1000000;

struct SimulateOptions {
  RobotSource robot;
  int poses = 0;
  long long seed = 1;
  std::string measure = "pose";
  double noise_position = 0.0, noise_rotation = 0.0;
  std::string joint_variables, out;
};

// What is measured: the tool pose at the sampled joint variable q, the ranges q is drawn from, and the
// comment lines that say so.
struct Truth {
  std::function<Pose(const VecX& q)> tipPose;
  std::vector<std::array<double, 2>> ranges;  // per joint, in q
  std::string source;       // where the tool frame comes from
  std::string variable;     // whose joint variable q is
  std::string length_unit;  // "" when unknown
};

Truth robotFileTruth(const SimulateOptions& o) {
  const RobotFile file = loadRobot(o.robot);
  auto model = std::make_shared<const PoeModel>(file.poeModel());
  auto data = std::make_shared<Data>(*model);
  Truth truth;
  truth.tipPose = [model, data](const VecX& q) {
    forwardKinematics(*model, *data, q);
    return data->T_base_tool;
  };
  truth.ranges = samplingRanges(*model);
  truth.source = "the library's POE forward kinematics of " + file.path + " (" + robotLabel(file) +
                 (file.dh ? ", converted from its D-H table)" : ")");
  truth.variable = file.path;
  truth.length_unit = file.length_unit;
  return truth;
}

// MuJoCo's tip pose at the motion x_i = variables[i].motion(q_i); q is the --joint-variables file's
// variable, else MuJoCo's own (qpos - qpos0).
Truth modelTruth(const SimulateOptions& o) {
  if (o.robot.tip.empty()) throw UsageError(o.robot.path, "--tip NAME is required with a model file");
  auto robot = std::make_shared<const MujocoRobot>(o.robot.path, o.robot.tip, o.robot.base);
  const int n = robot->dof();
  SampledVariable sampled = sampledVariable(*robot, o.joint_variables, o.robot.path, o.robot.tip);
  Truth truth;
  truth.variable = sampled.file_model ? o.joint_variables + " (motion x = scale (q + offset))"
                                      : "MuJoCo's qpos - qpos0 of " + o.robot.path;
  truth.length_unit = sampled.length_unit;
  truth.ranges = sampled.ranges;
  std::vector<JointMotion> variables = std::move(sampled.motions);
  auto evaluator = std::make_shared<MujocoRobot::Evaluator>(*robot);
  truth.tipPose = [robot, evaluator, variables, x = VecX(n)](const VecX& q) mutable {
    for (Eigen::Index i = 0; i < q.size(); ++i) x[i] = variables[static_cast<size_t>(i)].motion(q[i]);
    return evaluator->tipPose(x);
  };
  truth.source = "MuJoCo's pose of '" + o.robot.tip + "'" +
                 (o.robot.base.empty() ? "" : " relative to '" + o.robot.base + "'") + " in " + o.robot.path;
  return truth;
}

void checkNoise(const char* option, double sd, double limit) {
  if (!std::isfinite(sd) || sd < 0) throw UsageError(option, "expected a finite number >= 0, got " + shortest(sd));
  if (sd > limit) throw UsageError(option, shortest(sd) + " is above " + shortest(limit));
}

std::vector<std::string> describe(const SimulateOptions& o, const Truth& truth) {
  std::ostringstream command, noise, ranges;
  command << "lowpair simulate " << o.robot.path;
  if (!o.robot.tip.empty()) command << " --tip " << o.robot.tip;
  if (!o.robot.base.empty()) command << " --base " << o.robot.base;
  if (!o.joint_variables.empty()) command << " --joint-variables " << o.joint_variables;
  command << " --poses " << o.poses << " --seed " << o.seed << " --measure " << o.measure << " --noise-position "
          << shortest(o.noise_position) << " --noise-rotation " << shortest(o.noise_rotation);
  const std::string unit = truth.length_unit.empty() ? "length" : truth.length_unit;
  noise << "noise: position sd " << shortest(o.noise_position) << " " << unit << " per coordinate";
  if (o.measure == "pose") {
    noise << ", rotation R <- exp(n) R with n ~ N(0, s^2 I3), s = " << shortest(o.noise_rotation) << " rad";
  }
  ranges << "q: the joint variable of " << truth.variable << ", uniform in";
  for (const auto& r : truth.ranges) ranges << " [" << shortest(r[0]) << ", " << shortest(r[1]) << "]";
  std::vector<std::string> comments{command.str(), "tool frame: " + truth.source,
          std::to_string(o.poses) + " " + o.measure + " measurements, seed " + std::to_string(o.seed),
          noise.str(),
          ranges.str(),
          "x,y,z: tool position in the base frame (" + unit + ")" +
              (o.measure == "pose" ? "; qw,qx,qy,qz: its rotation, unit quaternion" : "")};
  // read back by readMeasurements, checked by calibrate against the nominal's unit
  if (isUnitLabel(truth.length_unit)) comments.push_back("length_unit: " + truth.length_unit);
  return comments;
}

int simulate(const SimulateOptions& o) {
  // a rotation noise above pi rad is a uniformly random rotation; a position noise up to 1e100 keeps every
  // coordinate within what the measurement reader takes (checked per measurement below)
  checkNoise("--noise-position", o.noise_position, kMaxMagnitude);
  checkNoise("--noise-rotation", o.noise_rotation, M_PI);
  if (o.measure == "position" && o.noise_rotation > 0) {  // as calibrate rejects it
    throw UsageError("--noise-rotation", "position measurements have no rotation to perturb");
  }
  const std::string ext = fs::path(o.robot.path).extension().string();
  const bool model_file = ext == ".xml" || ext == ".urdf";
  if (!model_file && !o.joint_variables.empty()) {
    throw UsageError(o.robot.path, "--joint-variables goes with a model file (.xml or .urdf), not a robot file");
  }
  const Truth truth = model_file ? modelTruth(o) : robotFileTruth(o);
  const Measure measure = o.measure == "pose" ? Measure::Pose : Measure::Position;
  // every number written must be one the measurement reader takes (|x| <= 1e100): the joint values (within
  // the ranges), the robot's reach, then what the noise adds
  for (const auto& r : truth.ranges) {
    if (!(std::max(std::abs(r[0]), std::abs(r[1])) <= kMaxMagnitude)) {
      throw UsageError(o.robot.path, "a joint range reaches " + shortest(std::max(std::abs(r[0]), std::abs(r[1]))) +
                                         ", above the 1e100 the measurement reader takes");
    }
  }
  const auto seed = static_cast<unsigned long long>(o.seed);

  std::vector<Measurement> measurements(static_cast<size_t>(o.poses));
  for (size_t k = 0; k < measurements.size(); ++k) {
    Measurement& m = measurements[k];
    m.q.resize(static_cast<Eigen::Index>(truth.ranges.size()));
    randomSample(seed, k, truth.ranges, m.q);
    m.T_base_tool = truth.tipPose(m.q);
    const auto beyond = [&m] { return !(m.T_base_tool.p.cwiseAbs().maxCoeff() <= kMaxMagnitude); };
    if (beyond()) {
      throw UsageError(o.robot.path, "measurement " + std::to_string(k + 1) +
                                         " has a coordinate above 1e100 in magnitude, which no reader takes");
    }
    addMeasurementNoise(seed, k, o.noise_position, o.noise_rotation, m.T_base_tool);
    if (beyond()) {
      throw UsageError("--noise-position", "measurement " + std::to_string(k + 1) +
                                               " has a coordinate above 1e100 in magnitude, which no reader takes");
    }
  }
  const std::string text = formatMeasurements(measure, measurements, describe(o, truth));
  if (o.out.empty()) {
    std::cout << text;
  } else {
    writeFileAtomically(o.out, text);  // all or nothing
    std::cout << measurements.size() << " " << o.measure << " measurements written to " << o.out << "\n";
  }
  return 0;
}

}  // namespace

void addSimulateCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<SimulateOptions>();
  auto* sub = app.add_subcommand("simulate", "measurements of the tool frame at random joint vectors (CSV)");
  addRobotArgument(*sub, o->robot);
  sub->add_option("--poses", o->poses, "number of measurements, 1 to 1000000")
      ->required()
      ->check(CLI::Range(1, kMaxPoses));
  // seeds are whole numbers in [0, 2^53], as for validate
  sub->add_option("--seed", o->seed, "seed in [0, 2^53] (default 1); the same seed gives the same file")
      ->check(CLI::Range(0LL, kMaxSeed));
  sub->add_option("--measure", o->measure, "pose (position and rotation, default) or position")
      ->check(CLI::IsMember({"pose", "position"}));
  sub->add_option("--noise-position", o->noise_position, "standard deviation per coordinate (length unit, default 0)");
  sub->add_option("--noise-rotation", o->noise_rotation, "standard deviation per axis of exp(n) (rad, default 0)");
  sub->add_option("--joint-variables", o->joint_variables,
                  "model file: a robot file of the same chain whose joint variable (scale, offset, ranges) is sampled");
  sub->add_option("--out", o->out, "write the CSV here (all or nothing) instead of standard output");
  commands.emplace_back(sub, [o] { return simulate(*o); });
}

}  // namespace lowpair::cli
