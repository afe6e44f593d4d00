// lowpair simulate ROBOT (--poses N | --q-file Q.csv) [--seed S] [--measure pose|position|targets]
//                  [--targets NAME,...] [--frame RX,RY,RZ,X,Y,Z] [--noise-position S] [--noise-rotation S]
//                  [--blunders COUNT,SIZE] [--joint-variables FILE.yaml] [--stiffness K1,...] [--out FILE.csv]
// Measurements of the tool frame, its origin or points fixed on it (measurements.hpp) at N random joint
// vectors, or at the joint vectors of a CSV (`lowpair plan --out`, a measurement file: its q1..qn columns):
// from the library's FK of a robot file, or from MuJoCo (the ground truth) for a model file's chain; in a
// measurement frame (a tracker's), with optional Gaussian noise and blunders (commands/sampling.hpp). The
// noise of row k depends only on (seed, k), whichever way the joint vectors came. With --stiffness (a model
// file), MuJoCo's robot is compliant: each pose is measured where it rests under gravity (compliant_truth.hpp).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/csv_columns.hpp"
#include "io/joint_table.hpp"
#include "cli/commands.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "io/measurements.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "io/output.hpp"
#include "commands/compliant_truth.hpp"
#include "commands/simulation.hpp"
#include "validation/validate.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::mujoco;
using namespace lowpair::commands;
using namespace lowpair::validation;

namespace fs = std::filesystem;

namespace {

constexpr int kBlundersPerCommentLine = 20;

struct SimulateOptions {
  RobotSource robot;
  int poses = 0;       // --poses, or the rows of --q-file
  std::string q_file;  // --q-file ("" for random joint vectors)
  long long seed = 1;
  std::string measure = "pose";
  double noise_position = 0.0, noise_rotation = 0.0;
  std::string joint_variables, out;
  std::optional<std::string> targets, frame, blunders, stiffness;  // as given
};

// What is measured: the tool pose at the sampled joint variable q, the ranges q is drawn from, the points
// targets may name, and the comment lines that say so.
struct Truth {
  std::function<Pose(const VecX& q)> tipPose;
  std::vector<std::array<double, 2>> ranges;  // per joint, in q
  std::string source;       // where the tool frame comes from
  std::string variable;     // whose joint variable q is
  std::string length_unit;  // "" when unknown
  bool model_file = false;
  std::vector<std::string> joint_names;               // the names a --q-file header may use (csv_columns.hpp)
  std::vector<bool> prismatic;                        // per joint: q is a length (a --q-file's unit converts it)
  std::vector<Target> file_targets;                    // a robot file's `targets:` (the default of --targets)
  std::function<Vec3(const std::string&)> sitePoint;  // a model file: a site's point in the tip frame
  std::string compliance;                              // --stiffness: what the poses are (a comment line)
};

std::vector<double> numbers(const std::string& option, const std::string& text, size_t count, const std::string& what);

Truth robotFileTruth(const SimulateOptions& o) {
  const RobotFile file = loadRobot(o.robot, cliSpelling());
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
  truth.file_targets = file.targets;
  for (const Joint& j : model->joints()) truth.joint_names.push_back(j.name);
  truth.prismatic = prismaticJoints(*model);
  return truth;
}

// MuJoCo's tip pose at the motion x_i = variables[i].motion(q_i); q is the --joint-variables file's
// variable, else MuJoCo's own (qpos - qpos0).
Truth modelTruth(const SimulateOptions& o) {
  if (o.robot.tip.empty()) {
    throw UsageError(o.robot.path, "--tip NAME is required with a model file; " + mujoco::tipCandidates(o.robot.path));
  }
  auto robot = std::make_shared<const MujocoRobot>(o.robot.path, o.robot.tip, o.robot.base);
  const int n = robot->dof();
  SampledVariable sampled = sampledVariable(*robot, o.joint_variables, o.robot.path, o.robot.tip);
  Truth truth;
  truth.model_file = true;
  truth.variable = sampled.file_model ? o.joint_variables + " (motion x = scale (q + offset))"
                                      : "MuJoCo's qpos - qpos0 of " + o.robot.path;
  truth.length_unit = sampled.length_unit;
  truth.ranges = sampled.ranges;
  for (const mujoco::MujocoJoint& j : robot->joints()) truth.joint_names.push_back(j.name);
  // q is the joint-variable file's (its joint types), else MuJoCo's qpos - qpos0 (a slide's is a length)
  if (sampled.file_model) {
    truth.prismatic = prismaticJoints(*sampled.file_model);
  } else {
    for (const mujoco::MujocoJoint& j : robot->joints()) truth.prismatic.push_back(j.type == JointType::Prismatic);
  }
  std::vector<JointMotion> variables = std::move(sampled.motions);
  std::function<Pose(const VecX& x)> pose_at;  // MuJoCo's tip at motion x: rigid, or at rest (--stiffness)
  if (o.stiffness) {
    const std::vector<double> k = numbers("--stiffness", *o.stiffness, static_cast<size_t>(n),
                                          "K1,...,K" + std::to_string(n) + " (one stiffness per joint)");
    CompliantTruth compliant = compliantTruth(robot, k, cliSpelling());
    pose_at = std::move(compliant.tipPose);
    truth.compliance = std::move(compliant.description);
  } else {
    auto evaluator = std::make_shared<MujocoRobot::Evaluator>(*robot);
    pose_at = [robot, evaluator](const VecX& x) { return evaluator->tipPose(x); };
  }
  truth.tipPose = [pose_at, variables, x = VecX(n)](const VecX& q) mutable {
    for (Eigen::Index i = 0; i < q.size(); ++i) x[i] = variables[static_cast<size_t>(i)].motion(q[i]);
    return pose_at(x);
  };
  truth.sitePoint = [robot](const std::string& site) { return robot->siteInTip(site); };
  truth.source = "MuJoCo's pose of '" + o.robot.tip + "'" +
                 (o.robot.base.empty() ? "" : " relative to '" + o.robot.base + "'") + " in " + o.robot.path;
  return truth;
}

// "A,B,C" split at commas, each item trimmed of spaces and tabs.
std::vector<std::string> items(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto begin = item.find_first_not_of(" \t");
    const auto end = item.find_last_not_of(" \t");
    out.push_back(begin == std::string::npos ? "" : item.substr(begin, end - begin + 1));
  }
  if (!text.empty() && text.back() == ',') out.push_back("");
  return out;
}

// `count` finite numbers of magnitude at most 1e100 ("what" names them in the message).
std::vector<double> numbers(const std::string& option, const std::string& text, size_t count, const std::string& what) {
  const std::vector<std::string> tokens = items(text);
  if (tokens.size() != count) {
    throw UsageError(option, "expected " + what + ", got " + std::to_string(tokens.size()) + " value(s)");
  }
  std::vector<double> values;
  for (const std::string& token : tokens) {
    char* stop = nullptr;
    const double x = std::strtod(token.c_str(), &stop);
    if (token.empty() || *stop != '\0') throw UsageError(option, "'" + token + "' is not a number");
    if (!(std::abs(x) <= kMaxMagnitude)) throw UsageError(option, "'" + token + "' is not finite or above 1e100");
    values.push_back(x);
  }
  return values;
}

// --frame RX,RY,RZ,X,Y,Z: T_frame_base (the inverse of the frame's pose in the base)
Pose frameOption(const std::string& text) {
  const std::vector<double> v = numbers("--frame", text, 6, "RX,RY,RZ,X,Y,Z (rotation vector in rad, translation)");
  return measurementFrame(Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5])).inverse();
}

Blunders blundersOption(const std::string& text) {
  const std::vector<double> v = numbers("--blunders", text, 2, "COUNT,SIZE (how many, and their size in the length unit)");
  return checkBlunders(v[0], v[1], cliSpelling());
}

// --targets NAME,...: distinct target names
std::vector<std::string> targetNames(const std::string& text) {
  std::vector<std::string> names = items(text);
  checkTargetList(names, cliSpelling());
  return names;
}

// The targets measured: their names and points in the tool frame (a robot file's list, or MuJoCo sites).
struct MeasuredTargets {
  std::vector<std::string> names;
  std::vector<Vec3> points;
  std::string source;
};

MeasuredTargets measuredTargets(const SimulateOptions& o, const Truth& truth) {
  MeasuredTargets t;
  if (truth.model_file) {
    if (!o.targets) {
      throw UsageError("--targets", "--measure targets with a model file needs --targets SITE,... (sites fixed to the tip)");
    }
    t.names = targetNames(*o.targets);
    for (const std::string& name : t.names) t.points.push_back(truth.sitePoint(name));
    t.source = "MuJoCo sites fixed to '" + o.robot.tip + "', their points in its frame at qpos0";
    return t;
  }
  const auto names = o.targets ? std::optional(items(*o.targets)) : std::nullopt;
  t.names = robotFileTargets(truth.file_targets, names, o.robot.path, cliSpelling(), t.points);
  t.source = "the targets: of " + o.robot.path + " (tool frame)";
  return t;
}

std::vector<std::string> describe(const SimulateOptions& o, const Truth& truth, const MeasuredTargets& targets,
                                  int rows) {
  std::ostringstream command, noise, ranges;
  command << "lowpair simulate " << o.robot.path;
  if (!o.robot.tip.empty()) command << " --tip " << o.robot.tip;
  if (!o.robot.base.empty()) command << " --base " << o.robot.base;
  if (!o.joint_variables.empty()) command << " --joint-variables " << o.joint_variables;
  command << (o.q_file.empty() ? " --poses " + std::to_string(o.poses) : " --q-file " + o.q_file) << " --seed " << o.seed
          << " --measure " << o.measure;
  if (o.measure == "targets") {
    std::string names;
    for (const std::string& name : targets.names) names += (names.empty() ? "" : ",") + name;
    command << " --targets " << names;
  }
  if (o.frame) command << " --frame " << *o.frame;
  command << " --noise-position " << shortest(o.noise_position) << " --noise-rotation " << shortest(o.noise_rotation);
  if (o.blunders) command << " --blunders " << *o.blunders;
  if (o.stiffness) command << " --stiffness " << *o.stiffness;
  const std::string unit = truth.length_unit.empty() ? "length" : truth.length_unit;
  const std::string frame = o.frame ? "the measurement frame F" : "the base frame";
  noise << "noise: position sd " << shortest(o.noise_position) << " " << unit << " per coordinate";
  if (o.frame) noise << " of F";
  if (o.measure == "pose") {
    noise << ", rotation R <- exp(n) R with n ~ N(0, s^2 I3)" << (o.frame ? " about F's axes" : "")
          << ", s = " << shortest(o.noise_rotation) << " rad";
  }
  if (o.q_file.empty()) {
    ranges << "q: the joint variable of " << truth.variable << ", uniform in";
    for (const auto& r : truth.ranges) ranges << " [" << shortest(r[0]) << ", " << shortest(r[1]) << "]";
  } else {
    ranges << "q: the joint variable of " << truth.variable << ", the q1..q" << truth.ranges.size() << " of the "
           << o.poses << " rows of " << o.q_file << ", in order (not drawn)";
  }
  std::vector<std::string> comments{command.str(), "tool frame: " + truth.source +
                                                   (truth.compliance.empty() ? "" : " (compliant: see below)"),
          o.measure == "targets" ? std::to_string(rows) + " target measurements (" + std::to_string(o.poses) +
                                       " poses x " + std::to_string(targets.names.size()) + " targets), seed " +
                                       std::to_string(o.seed)
                                 : std::to_string(o.poses) + " " + o.measure + " measurements, seed " +
                                       std::to_string(o.seed)};
  if (o.measure == "targets") {
    std::ostringstream points;
    points << "targets: " << targets.source << ":";
    for (size_t t = 0; t < targets.names.size(); ++t) {
      const Vec3& p = targets.points[t];
      points << " " << targets.names[t] << " [" << shortest(p.x()) << ", " << shortest(p.y()) << ", " << shortest(p.z())
             << "]";
    }
    comments.push_back(points.str());
  }
  if (o.frame) {
    comments.push_back("frame: measurements in the measurement frame F (a tracker's), T_base_F = (exp([RX, RY, RZ]), "
                       "[X, Y, Z]) with --frame RX,RY,RZ,X,Y,Z = " + *o.frame + " (rad, " + unit +
                       "); a measurement is T_F_base times the tool frame, origin or target point in the base frame");
  }
  if (!truth.compliance.empty()) comments.push_back(truth.compliance);
  comments.push_back(noise.str());
  comments.push_back(ranges.str());
  const std::string what = o.measure == "targets" ? "x,y,z: the target's point in " + frame + " (" + unit + ")"
                                                  : "x,y,z: tool position in " + frame + " (" + unit + ")";
  comments.push_back(what + (o.measure == "pose" ? "; qw,qx,qy,qz: its rotation, unit quaternion" : ""));
  // read back by readMeasurements, checked by calibrate against the nominal's unit
  if (isUnitLabel(truth.length_unit)) comments.push_back("length_unit: " + truth.length_unit);
  return comments;
}

// The comment lines listing the blunders: "measurement (line)" pairs, 1-based, a few per line.
std::vector<std::string> blunderComments(const Blunders& b, const std::vector<size_t>& rows, long long first_data_line,
                                         const std::string& unit) {
  std::vector<std::string> lines{"blunders: " + std::to_string(rows.size()) + " measurements moved by " +
                                 shortest(b.size) + " " + unit + " in random directions (after the noise), listed " +
                                 "as measurement:line (1-based data row : file line)"};
  for (size_t i = 0; i < rows.size(); i += kBlundersPerCommentLine) {
    std::string line = "blunders:";
    for (size_t k = i; k < rows.size() && k < i + kBlundersPerCommentLine; ++k) {
      line += " " + std::to_string(rows[k] + 1) + ":" + std::to_string(first_data_line + static_cast<long long>(rows[k]));
    }
    lines.push_back(line);
  }
  return lines;
}

// Lines a comment takes in the file (formatMeasurements writes one "# " line per line of it).
long long commentLines(const std::vector<std::string>& comments) {
  long long lines = 0;
  for (const std::string& c : comments) lines += 1 + static_cast<long long>(std::count(c.begin(), c.end(), '\n'));
  return lines;
}

int simulate(const SimulateOptions& given) {
  SimulateOptions o = given;  // with --q-file, poses becomes its row count
  const Measure measure = parseMeasure(o.measure, cliSpelling());
  checkSimulationArguments(measure, o.noise_position, o.noise_rotation, o.targets.has_value(), cliSpelling());
  const Pose T_frame_base = o.frame ? frameOption(*o.frame) : Pose();
  const std::optional<Blunders> blunders = o.blunders ? std::optional(blundersOption(*o.blunders)) : std::nullopt;
  const std::string ext = fs::path(o.robot.path).extension().string();
  const bool model_file = ext == ".xml" || ext == ".urdf";
  if (!model_file && !o.joint_variables.empty()) {
    throw UsageError(o.robot.path, "--joint-variables goes with a model file (.xml or .urdf), not a robot file");
  }
  if (!model_file && o.stiffness) {
    throw UsageError("--stiffness", "goes with a model file (.xml or .urdf, MuJoCo's masses), not the robot file " +
                                        o.robot.path);
  }
  const Truth truth = model_file ? modelTruth(o) : robotFileTruth(o);
  MeasurementSetup setup;
  setup.measure = measure;
  MeasuredTargets targets;
  if (setup.measure == Measure::Targets) {
    targets = measuredTargets(o, truth);
    setup.targets = targets.points;
  }
  setup.T_frame_base = T_frame_base;
  setup.sd_position = o.noise_position;
  setup.sd_rotation = o.noise_rotation;
  // --q-file: the joint vectors given, rows of the q1..qn columns (the reader's rules: io/measurements.hpp)
  const auto joints = static_cast<Eigen::Index>(truth.ranges.size());
  JointTable q_table = o.q_file.empty() ? JointTable()
                                        : readJointTable(o.q_file, TableKind::Joints, static_cast<int>(joints), o.robot.path,
                                                         csvJointNames(truth.joint_names));
  for (const std::string& note : q_table.notes) std::cerr << "note: " << note << "\n";
  // prismatic joint values in the measured unit (revolute and helical q are rad)
  if (const std::string note = convertTableUnit(q_table, truth.length_unit, o.robot.path, truth.prismatic); !note.empty()) {
    std::cerr << "note: " << note << "\n";
  }
  const std::vector<long long>& q_lines = q_table.lines;
  const MatX Q = q_table.matrix();
  if (!o.q_file.empty()) o.poses = static_cast<int>(Q.rows());
  const long long rows = simulationRows(o.poses, static_cast<int>(joints), setup, o.q_file.empty() ? "--poses" : o.q_file,
                                       o.robot.path);
  if (blunders) checkBlunderCount(*blunders, rows, cliSpelling());
  SimulationPoses poses;
  poses.count = o.poses;
  poses.ranges = truth.ranges;
  poses.q_rows = o.q_file.empty() ? nullptr : &Q;
  poses.given_row_beyond_reach = [&](size_t k) {
    throw RobotFileError(o.q_file + ":" + std::to_string(q_lines[k]) + ": the tool at this row's q has a coordinate "
                         "above 1e100 in magnitude, which no reader takes");
  };
  const SimulatedMeasurements s = simulateMeasurements(truth.tipPose, setup, static_cast<unsigned long long>(o.seed), poses,
                                                       blunders, o.frame.has_value(), o.robot.path, cliSpelling());
  const std::vector<Measurement>& measurements = s.measurements;
  std::vector<std::string> comments = describe(o, truth, targets, static_cast<int>(rows));
  if (o.blunders) {
    // the file line of data row r: the comments (these included), the header, then the rows
    const std::string unit = truth.length_unit.empty() ? "length" : truth.length_unit;
    const long long before = commentLines(comments) + commentLines(blunderComments(*blunders, s.blunders, 0, unit));
    for (const std::string& line : blunderComments(*blunders, s.blunders, before + 2, unit)) comments.push_back(line);
  }
  // written as it is made (10^6 rows: the text is never held whole), every row checked before the first byte
  const StreamWriter csv = [&](std::ostream& out) {
    writeMeasurements(out, setup.measure, measurements, comments,
                      setup.measure == Measure::Targets ? targets.names : std::vector<std::string>{});
  };
  if (o.out.empty()) {
    csv(std::cout);
  } else {
    writeFileAtomically(o.out, csv);  // all or nothing
    // ("300 target measurements", "50 pose measurements")
    std::cout << measurements.size() << " " << (o.measure == "targets" ? std::string("target") : o.measure)
              << " measurements written to " << o.out << "\n";
  }
  return 0;
}

}  // namespace

void addSimulateCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<SimulateOptions>();
  auto* sub = app.add_subcommand("simulate",
                                 "measurements of the tool frame (CSV) at random joint vectors or at those of a CSV");
  addRobotArgument(*sub, o->robot);
  auto* poses = sub->add_option("--poses", o->poses, "number of random poses (joint vectors), 1 to 1000000")
                    ->check(CLI::Range(1, kMaxSimulatedPoses));
  auto* q_file = sub->add_option("--q-file", o->q_file,
                                 "measure exactly the joint vectors of this CSV instead (its q1..qn columns, e.g. "
                                 "lowpair plan --out or a measurement file; other columns ignored)");
  poses->excludes(q_file);
  q_file->excludes(poses);
  // seeds are whole numbers in [0, 2^53], as for validate
  sub->add_option("--seed", o->seed, "seed in [0, 2^53] (default 1); the same seed gives the same file")
      ->check(CLI::Range(0LL, kMaxSeed));
  sub->add_option("--measure", o->measure,
                  "pose (position and rotation, default), position, or targets (points fixed on the tool, --targets)")
      ->check(CLI::IsMember({"pose", "position", "targets"}));
  sub->add_option("--targets", o->targets,
                  "--measure targets: NAME,... of a robot file's targets (default: all), or sites fixed to the "
                  "tip of a model file; one measurement per target per pose, in this order");
  sub->add_option("--frame", o->frame,
                  "RX,RY,RZ,X,Y,Z: measurements in a frame F (a tracker's) whose pose in the base is "
                  "(exp([RX,RY,RZ]) rad, [X,Y,Z] length); default: the base frame");
  sub->add_option("--noise-position", o->noise_position,
                  "standard deviation per coordinate (length unit, default 0), in the measurement frame");
  sub->add_option("--noise-rotation", o->noise_rotation, "standard deviation per axis of exp(n) (rad, default 0)");
  sub->add_option("--blunders", o->blunders,
                  "COUNT,SIZE: COUNT measurements (seeded) moved by SIZE (length) in random directions; listed "
                  "in the file's comments");
  sub->add_option("--joint-variables", o->joint_variables,
                  "model file: a robot file of the same chain whose joint variable (scale, offset, ranges) is sampled");
  sub->add_option("--stiffness", o->stiffness,
                  "model file: K1,...,Kn joint stiffness (N m/rad, N/m for a prismatic joint; 0 rigid): measure "
                  "each pose where the robot rests under gravity (MuJoCo's masses; docs/validation.md)");
  sub->add_option("--out", o->out, "write the CSV here (all or nothing) instead of standard output");
  commands.emplace_back(sub, [o, poses, q_file] {
    if (poses->count() == 0 && q_file->count() == 0) {
      throw UsageError("simulate", "--poses is required (or --q-file Q.csv: the joint vectors of a CSV)");
    }
    return simulate(*o);
  });
}

}  // namespace lowpair::cli
