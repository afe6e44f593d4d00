// identifiability, calibrate (docs/calibration.md).
#include <algorithm>
#include <optional>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>

#include "io/atomic_file.hpp"
#include "commands/calibration_inputs.hpp"
#include "commands/calibration_output.hpp"
#include "commands/calibration_run.hpp"
#include "commands/deflection_inputs.hpp"
#include "commands/simulation.hpp"
#include "lowpair/tolerances.hpp"
#include "cli/commands.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "validation/scenario.hpp"
#include "validation/validate.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::mujoco;
using namespace lowpair::commands;
using namespace lowpair::validation;

using nlohmann::json;

namespace {


struct IdentifiabilityOptions {
  RobotSource robot;
  std::string measure = "pose";
  int poses = 50;
  long long seed = 1;
  bool as_json = false, free_pitch = false;
  std::optional<std::string> compliance, backlash;  // joint deflections (deflection_inputs.hpp)
};

int runIdentifiability(const IdentifiabilityOptions& o) {
  const RobotFile file = loadRobot(o.robot, cliSpelling());
  const PoeModel model = file.poeModel();
  const Measure measure = parseMeasure(o.measure, cliSpelling());
  // the full error model has 8 columns per joint + pitches + 6 (+ 3 per target); the D-H one 6 per joint + 6
  const int targets = measure == Measure::Targets ? static_cast<int>(file.targets.size()) : 0;
  if (const auto problem = identifiabilitySizeProblem(o.poses, model.dof(), measure, targets)) {
    // one pose over the limit: the robot (or its targets) is too large whatever --poses says
    throw UsageError(problem->robot ? file.path : std::string("--poses"), problem->text);
  }
  const auto ranges = samplingRanges(model);
  std::vector<VecX> q(static_cast<size_t>(o.poses), VecX(model.dof()));
  for (int i = 0; i < o.poses; ++i) randomSample(static_cast<unsigned long long>(o.seed), static_cast<unsigned long long>(i), ranges, q[static_cast<size_t>(i)]);
  ErrorModelSpec spec;
  spec.free_pitch = o.free_pitch;
  if (measure == Measure::Targets) {
    spec.targets = numberedRobotFileTargets(file, cliSpelling());  // known points: the tool's columns
  }
  // joint deflections: the loads at the random poses, the signs of their order
  CalibrationOptions deflection;
  std::vector<Measurement> poses;
  for (const VecX& qi : q) poses.push_back(Measurement{qi, Pose{}});
  const DeflectionChoice choice = chooseDeflections(file, model, o.compliance, o.backlash, poses, {}, {},
                                                    "the " + std::to_string(o.poses) + " random poses", deflection, cliSpelling());
  const ErrorModelSpec with = deflectionSpec(deflection);
  spec.compliance_joints = with.compliance_joints;
  spec.backlash_joints = with.backlash_joints;
  spec.deflection = with.deflection;
  const Identifiability id = analyzeIdentifiability(model, q, measure, spec, measurementLoads(model, poses, deflection));
  for (const int j : choice.rigid) {
    std::cerr << "note: --compliance all: joint " << j + 1 << " left out: its gravity load does not vary over the random poses\n";
  }
  if (o.as_json) {
    json j = identifiabilityJson(file, id);
    j["poses"] = o.poses;
    j["seed"] = o.seed;
    std::cout << jsonText(j) << "\n";
  } else {
    std::cout << "identifiability of " << robotLabel(file) << " from " << o.poses << " random "
              << measurementsText(measure) << " (seed " << o.seed << ")\n";
    printIdentifiability(std::cout, id);
  }
  return 0;
}

struct CalibrateOptions {
  RobotSource robot;
  std::string measurements, validation, out;
  std::string frame = "base";  // --out: the base-frame robot (with measurement_frame:) or the measurement frame's
  bool as_json = false;
  CalibrationRequest calibration;  // calibrate's arguments beyond its files
};

int runCalibrate(const CalibrateOptions& o) {
  const RobotFile file = loadRobot(o.robot, cliSpelling());
  const PoeModel nominal = file.poeModel();
  std::vector<std::string> notes;
  auto read = [&](const std::string& path) {
    CalibrationMeasurements r = readCalibrationMeasurements(
        path, file, file.path, nominal, [](const std::string& w) { std::cerr << "warning: " << w << "\n"; });
    notes.insert(notes.end(), r.notes.begin(), r.notes.end());
    return std::move(r.file);
  };
  MeasurementFile fit = read(o.measurements);
  if (const auto problem = calibrationSizeProblem(fit, nominal.dof())) {
    throw RobotFileError(fit.path + ": " + *problem +
                         " (docs/cli.md \"Limits\": fit fewer measurements and put the rest in --validation, or measure "
                         "fewer targets)");
  }
  std::optional<MeasurementFile> validation;
  if (!o.validation.empty()) {
    validation = read(o.validation);
    if (validation->measure != fit.measure) {
      throw RobotFileError(validation->path + ": " + measurementsText(validation->measure) + ", but " + fit.path +
                           " holds " + measurementsText(fit.measure));
    }
    // targets by name: the validation file's indices mapped to the fitting file's
    if (const auto unknown = mapValidationTargets(*validation, fit.target_names)) {
      throw RobotFileError(validation->path + ": target " + *unknown + " is not measured in " + fit.path);
    }
  }
  CalibrationRequest request = o.calibration;
  if (request.parameters && request.parameters->empty()) request.parameters.reset();  // --parameters "": the default
  CalibrationReport report = runCalibration(file, nominal, std::move(fit), std::move(validation), request, cliSpelling());
  report.notes = notes;
  const CalibrationResult& result = report.result;
  if (!o.out.empty() && result.accepted) {
    const bool measurement = o.frame == "measurement";
    std::vector<std::string> provenance = calibrationProvenance(report);
    if (measurement) {  // today's file: the robot in the measurement frame
      provenance.back() = "in the measurement frame of " + report.fit.path + " (--frame measurement); loss " +
                          lossName(result.loss) + ", parameters " + parameterSetName(result.parameter_set);
    }
    writeFileAtomically(o.out, formatPoeRobotFile(calibratedModel(report, measurement), file, calibratedName(file),
                                                   "calibrated by lowpair calibrate from " + report.fit.path, provenance,
                                                   RobotFileExtras{calibratedTargets(report), recordedMeasurementFrame(report, measurement),
                                                                   calibratedToolFrame(report.result),
                                                                   calibratedMasses(report, measurement), result.deflection}));
  }
  if (o.as_json) {
    std::cout << jsonText(calibrationJson(report)) << "\n";
  } else {
    printCalibration(std::cout, report);
  }
  if (!result.accepted) {
    std::cout.flush();
    std::cerr << "error: " << rejectionText(report) << "\n";
    return 1;
  }
  return 0;
}

void addIdentifiabilityCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<IdentifiabilityOptions>();
  auto* ident = app.add_subcommand("identifiability",
                                   "rank of the identification Jacobian vs 5h+4r+2t+n+6, POE and D-H (Wu et al. §V)");
  addRobotArgument(*ident, o->robot);
  ident->add_option("--measure", o->measure,
                    "pose (default) or position measurements of the tool, or targets (the robot file's targets: points)")
      ->check(CLI::IsMember({"pose", "position", "targets"}));
  ident->add_option("--poses", o->poses, "random poses (default 50)")->check(CLI::Range(1, kMaxIdentifiabilityPoses));
  ident->add_option("--seed", o->seed, "seed of the random poses (default 1)")->check(CLI::Range(0LL, kMaxSeed));
  ident->add_flag("--free-pitch", o->free_pitch, "give revolute joints a pitch parameter");
  ident->add_option("--compliance", o->compliance,
                    "joints whose compliance under gravity is a parameter: all, or 1-based indices or names (needs masses)");
  ident->add_option("--backlash", o->backlash, "joints whose backlash is a parameter (1-based indices or names)");
  ident->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(ident, [o] { return runIdentifiability(*o); });
}

void addCalibrateCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<CalibrateOptions>();
  auto* cal = app.add_subcommand("calibrate", "identify a POE model from measurements; calibrated D-H table with "
                                              "standard deviations");
  cal->add_option("NOMINAL", o->robot.path, "nominal robot file (.yaml), or a model (.xml MJCF, .urdf) with --tip")
      ->required();
  cal->add_option("--tip", o->robot.tip, "model file: the tip site or body");
  cal->add_option("--base", o->robot.base, "model file: the base body (default: the world)");
  cal->add_option("--measurements", o->measurements, "measurement CSV (lowpair simulate, docs/file_formats.md)")
      ->required();
  cal->add_option("--validation", o->validation, "held-out measurement CSV: residuals before and after");
  CalibrationRequest& request = o->calibration;
  cal->add_option("--noise-position", request.noise_position, "measurement noise, standard deviation per coordinate (length)");
  cal->add_option("--noise-rotation", request.noise_rotation, "measurement noise, standard deviation per axis (rad)");
  cal->add_flag("--free-pitch", request.free_pitch, "identify a pitch on revolute joints too (they may come out helical)");
  cal->add_option("--loss", request.loss, "squared (default), huber or cauchy: robust losses weigh blunders down (IRLS)")
      ->check(CLI::IsMember({"squared", "huber", "cauchy"}));
  cal->add_option("--outlier-threshold", request.outlier_threshold,
                  "flag a measurement whose normalized residual exceeds this (default 5)")
      ->check(CLI::Range(1e-3, 1e6));
  cal->add_option("--parameters", request.parameters,
                  "full (default: every identifiable parameter), lines (no scales), offsets (joint offsets, base, "
                  "tool), or a comma list of parameter names");
  cal->add_option("--select", request.select, "cv: choose full, lines or offsets by repeated k-fold cross-validation")
      ->check(CLI::IsMember({"cv"}));
  cal->add_option("--folds", request.folds, "folds of --select cv (default 5)")
      ->check(CLI::Range(2, kMaxCrossValidationFolds));
  cal->add_option("--repeats", request.repeats,
                  "partitions of the poses into folds for --select cv, the first in order, the others shuffled "
                  "(default " + std::to_string(kCrossValidationRepeats) + ")")
      ->check(CLI::Range(1, kMaxCrossValidationRepeats));
  cal->add_option("--compliance", request.compliance,
                  "fit the compliance under gravity of these joints: all (those whose load varies), or 1-based indices or "
                  "joint names (the nominal file's masses give the load; docs/calibration.md \"Beyond geometry\")");
  cal->add_option("--backlash", request.backlash,
                  "fit the backlash of these joints (1-based indices or names); s from the file's s<i> or s_<name> "
                  "column, else the measurements' order");
  cal->add_option("--prior", request.prior,
                  "a prior on the nominal (MAP): WIDTH (tilts WIDTH mrad, shifts WIDTH mm, scales WIDTH x 0.1 %, offsets "
                  "10 WIDTH mrad) or tilt=..,shift=..,scale=..,offset=.. (mrad, mm, %, mrad; docs/calibration.md)");
  cal->add_option("--out", o->out, "write the calibrated POE robot file (.yaml); only when the fit is accepted");
  cal->add_option("--frame", o->frame,
                  "--out's frame: base (the nominal's base frame, with the measurement frame as measurement_frame:) "
                  "or measurement (the robot in the frame of the measurements)")
      ->check(CLI::IsMember({"base", "measurement"}));
  cal->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(cal, [o] { return runCalibrate(*o); });
}

}  // namespace

void addCalibrateCommands(CLI::App& app, Commands& commands) {
  addIdentifiabilityCommand(app, commands);
  addCalibrateCommand(app, commands);
}

}  // namespace lowpair::cli
