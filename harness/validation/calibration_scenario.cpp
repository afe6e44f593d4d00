#include "validation/calibration_scenario.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "commands/calibration_output.hpp"
#include "lowpair/base_frame.hpp"
#include "lowpair/kinematics.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "validation/validate.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::commands;
using namespace lowpair::mujoco;

namespace {

// The position error of every measurement against a model's prediction (targets: their points).
std::vector<double> positionErrors(const PoeModel& model, const std::vector<Measurement>& measurements, Measure measure,
                                   const std::vector<Vec3>& target_points) {
  std::vector<double> errors;
  for (const Measurement& m : measurements) {
    errors.push_back((m.T_base_tool.p - predictedMeasurement(model, m, measure, target_points).p).norm());
  }
  return errors;
}

// `file`'s measurements with their target indices mapped by name onto `names` (the fit's targets).
std::vector<Measurement> targetsByName(const MeasurementFile& file, const std::vector<std::string>& names) {
  std::vector<Measurement> out = file.measurements;
  if (file.measure != Measure::Targets) return out;
  for (Measurement& m : out) {
    if (m.target == kPoseMeasurement) continue;  // a pose among target measurements
    const std::string& name = file.target_names[static_cast<size_t>(m.target)];
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) throw RobotFileError(file.path + ": target '" + name + "' is not one of the fit's");
    m.target = static_cast<int>(it - names.begin());
  }
  return out;
}

// "17 (pose 6, smr_b)" (1-based) for a fitting measurement, "17" without targets
std::string measurementLabel(const MeasurementFile& fit, size_t k) {
  std::string label = std::to_string(k + 1);
  const Measurement& m = fit.measurements[k];
  if (fit.measure == Measure::Targets && m.target >= 0) {
    label += " (pose " + std::to_string(k / fit.target_names.size() + 1) + ", " +
             fit.target_names[static_cast<size_t>(m.target)] + ")";
  }
  return label;
}

std::string listed(const MeasurementFile& fit, const std::vector<size_t>& rows) {
  constexpr size_t kMaxListed = 10;
  std::string text;
  for (size_t i = 0; i < rows.size() && i < kMaxListed; ++i) text += (i ? ", " : "") + measurementLabel(fit, rows[i]);
  if (rows.size() > kMaxListed) text += ", ... (" + std::to_string(rows.size()) + " in all)";
  return text;
}

}  // namespace

MeasurementSetup caseMeasurementSetup(const CalibrationCase& c, const MujocoRobot& robot, bool noisy) {
  MeasurementSetup setup;
  setup.measure = c.measure();
  for (const std::string& site : c.targets) setup.targets.push_back(robot.siteInTip(site));
  if (c.frame) {
    const auto& f = *c.frame;
    setup.T_frame_base = measurementFrame(Vec3(f[0], f[1], f[2]), Vec3(f[3], f[4], f[5])).inverse();
  }
  if (noisy) {
    setup.sd_position = c.noise_position;
    setup.sd_rotation = c.noise_rotation;
  }
  return setup;
}

namespace {

// Pose k of `q` measured with the noise of stream row `first + k` (appendMeasurements).
MeasurementFile measureAt(const CalibrationCase& c, const MeasurementSetup& setup, MujocoRobot::Evaluator& mujoco,
                          const std::vector<JointMotion>& variables, const std::vector<VecX>& q, unsigned long long first,
                          std::string label) {
  MeasurementFile file;
  file.path = std::move(label);
  file.measure = setup.measure;
  file.dof = static_cast<int>(variables.size());
  if (setup.measure == Measure::Targets) file.target_names = c.targets;
  file.measurements.reserve(q.size() * static_cast<size_t>(rowsPerPose(setup)));
  VecX x(file.dof);
  for (size_t k = 0; k < q.size(); ++k) {
    for (int i = 0; i < file.dof; ++i) x[i] = variables[static_cast<size_t>(i)].motion(q[k][i]);
    appendMeasurements(setup, c.seed, first + k, q[k], mujoco.tipPose(x), file.measurements);
  }
  return file;
}

}  // namespace

MeasurementFile simulatedMeasurements(const CalibrationCase& c, const MeasurementSetup& setup, MujocoRobot::Evaluator& mujoco,
                                      const std::vector<JointMotion>& variables, const std::vector<Range>& ranges,
                                      int first, int count, std::string label) {
  const auto start = static_cast<unsigned long long>(first);
  return measureAt(c, setup, mujoco, variables, randomSamples(c.seed, start, count, ranges), start, std::move(label));
}

MeasurementFile measuredAt(const CalibrationCase& c, const MeasurementSetup& setup, MujocoRobot::Evaluator& mujoco,
                           const std::vector<JointMotion>& variables, const std::vector<VecX>& q, std::string label) {
  return measureAt(c, setup, mujoco, variables, q, 0, std::move(label));
}

namespace {

// The case's plan (CasePlan) on the nominal: the candidates are samples 0 .. M-1 of the case's stream over the
// scenario's ranges; `q` gets the chosen ones, in sample order.
CasePlanResult planCase(const Scenario& scenario, const CalibrationCase& config, const RobotFile& nominal_file,
                        const PoeModel& nominal, const std::vector<Range>& ranges, std::vector<VecX>& q) {
  const CasePlan& p = *config.plan;
  PlanOptions options;
  options.measure = config.measure();
  options.free_pitch = config.free_pitch;
  options.criterion = p.criterion;
  for (const std::string& name : config.targets) {  // the planner knows the nominal only
    const auto known = std::find_if(nominal_file.targets.begin(), nominal_file.targets.end(),
                                    [&](const Target& t) { return t.name == name && t.point_tool; });
    if (known == nominal_file.targets.end()) {
      throw RobotFileError(scenario.path + ": calibration '" + config.name + "': plan: with targets the nominal " +
                           config.nominal + " must list every target's point (the plan is made on the nominal); '" +
                           name + "' is not among its targets:");
    }
    options.targets.push_back(Target{name, known->point_tool, known->known});
  }
  // the candidates' blocks: rows per pose x (at most 7 columns per joint and the tool's 6 or targets' 3 each)
  const double targets = static_cast<double>(config.targets.size());
  const double rows = options.measure == Measure::Targets ? 3.0 * targets : options.measure == Measure::Position ? 3.0 : 6.0;
  const double columns = 7.0 * nominal.dof() + (options.measure == Measure::Targets ? 3.0 * targets : 6.0);
  if (const auto problem = planSizeProblem(p.candidates, config.poses, rows, columns, options.max_exchange_work,
                                           config.targets.size() > 1)) {  // the shared limits of `plan`
    throw RobotFileError(scenario.path + ": calibration '" + config.name + "': plan: " + problem->text);
  }
  const std::vector<VecX> candidates = randomSamples(config.seed, 0, p.candidates, ranges);
  CasePlanResult out;
  const auto start = std::chrono::steady_clock::now();
  const PlanCandidates blocks = planCandidates(nominal, candidates, options);
  out.plan = planPoses(blocks, config.poses, options);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<int> first(static_cast<size_t>(config.poses));
  for (size_t k = 0; k < first.size(); ++k) first[k] = static_cast<int>(k);
  out.first = evaluatePlan(blocks, first);
  q.clear();
  for (const int index : out.plan.indices) q.push_back(candidates[static_cast<size_t>(index)]);
  return out;
}

// The case's compensation (CompensationResult) of the nominal programs `programs` (the validation joint vectors).
CompensationResult compensateCase(const CalibrationCase& config, const PoeModel& nominal, const CalibrationResult& result,
                                  const MeasurementSetup& setup, MujocoRobot::Evaluator& mujoco,
                                  const std::vector<JointMotion>& variables, const std::vector<VecX>& programs) {
  CompensationResult out;
  out.tool_determined = result.tool_rank >= 6;
  out.base_frame = config.compensation->base_frame;
  // the task and what MuJoCo's actual robot shows of it, in its base frame without noise: the tool frame, or
  // its origin (position measurements), or where the targets left the tool frame undetermined the first
  // target's point (the point the calibration determined)
  MeasurementSetup actual;
  actual.measure = config.measure() == Measure::Targets && out.tool_determined ? Measure::Pose : config.measure();
  IkOptions options;
  options.measure = actual.measure == Measure::Pose ? Measure::Pose : Measure::Position;
  if (actual.measure == Measure::Targets) {
    actual.targets = {setup.targets.front()};  // the site, in MuJoCo's tip frame
    options.point_tool = result.target_points.front();  // the calibrated point, in the calibrated tool frame
    out.point_name = config.targets.front();
  }
  out.measure = options.measure;
  out.point_tool = options.point_tool;
  out.length_scale = nominal.lengthScale();
  // the calibrated model predicts the measurements in the measurement frame: into the base frame, by the
  // case's known frame, or as calibrate --out writes it (the nominal's base frame: no knowledge of the frame)
  const PoeModel calibrated = out.base_frame ? toNominalBase(result.model, nominal).model
                              : config.frame ? movedModel(result.model, setup.T_frame_base.inverse())
                                             : result.model;
  const auto start = std::chrono::steady_clock::now();
  Data data(nominal);
  IkWorkspace work(nominal);
  std::vector<Measurement> before, after;
  const int n = nominal.dof();
  VecX x(n);
  auto command = [&](const VecX& q, const VecX& q_commanded, std::vector<Measurement>& out_rows, size_t k) {
    for (int i = 0; i < n; ++i) x[i] = variables[static_cast<size_t>(i)].motion(q_commanded[i]);
    appendMeasurements(actual, config.seed, k, q, mujoco.tipPose(x), out_rows);  // the row's q: the program
  };
  for (size_t k = 0; k < programs.size(); ++k) {
    const VecX& q = programs[k];
    command(q, q, before, k);
    const IkResult& r = compensate(nominal, calibrated, data, q, options, work);
    ++out.statuses[static_cast<size_t>(r.status)];
    if (r.status == IkStatus::Ok) {
      command(q, r.q, after, k);
    } else {
      out.not_ok.push_back({static_cast<int>(k), r.status, r.reason});
    }
  }
  // errors against the nominal's prediction at the program q (its target), of the point compensated; with
  // base_frame up to one rigid motion (the actual's base differs from the nominal's: the gauge)
  const std::vector<Vec3> points{options.point_tool};
  const bool point_task = actual.measure == Measure::Targets;
  const std::vector<Vec3> task_points = point_task ? points : std::vector<Vec3>{};
  const std::vector<Target> task_targets =
      point_task ? std::vector<Target>{Target{out.point_name, options.point_tool, true}} : std::vector<Target>{};
  auto statistics = [&](const std::vector<Measurement>& rows, Pose& rigid) {
    if (out.base_frame && !rows.empty()) rigid = registerMeasurementFrame(nominal, rows, actual.measure, task_targets).T_meas_base;
    return residualStatistics(movedModel(nominal, rigid), rows, actual.measure, task_points);
  };
  out.before = statistics(before, out.rigid_before);
  out.after = statistics(after, out.rigid_after);
  if (after.empty()) {  // nothing was commanded: no number to pass on
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.after.rms_position = out.after.max_position = out.after.rms_rotation = out.after.max_rotation = nan;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

namespace {

// The case against its nominal before anything is measured: the chain's joints, the length unit, the noise
// and the size of the identification Jacobian. @throws io::RobotFileError naming the scenario and the case
void checkCase(const Scenario& scenario, const CalibrationCase& config, const RobotFile& nominal_file,
               const PoeModel& nominal, const MujocoRobot& robot, const SampledVariable& sampled) {
  if (nominal.dof() != robot.dof()) {
    throw RobotFileError(config.nominal + ": has " + std::to_string(nominal.dof()) + " joints but the chain to '" +
                         scenario.tip + "' in " + scenario.model + " has " + std::to_string(robot.dof()) +
                         " (calibration '" + config.name + "' of " + scenario.path + ")");
  }
  // the measurements' length unit against the nominal's: in another, it would be fitted as a robot of the
  // wrong size
  const std::string& measured_unit = sampled.length_unit;
  if (!measured_unit.empty() && !nominal_file.length_unit.empty() && measured_unit != nominal_file.length_unit) {
    throw RobotFileError(scenario.path + ": calibration '" + config.name + "': the measurements of " + scenario.model +
                         " are in " + measured_unit + " but the nominal " + config.nominal + " is in " +
                         nominal_file.length_unit + ": give a nominal in the measurements' unit");
  }
  if (config.noise_position > nominal.lengthScale()) {
    throw RobotFileError(scenario.path + ": calibration '" + config.name + "': noise.position " +
                         shortest(config.noise_position) + " exceeds the robot size L = " +
                         shortest(nominal.lengthScale()));
  }
  const Measure measure = config.measure();
  // the identification Jacobian: 6 rows per pose, or 3 per target and pose; 7 columns per joint at most
  // (5 line parameters, scale, offset) and the tool's 6 or the targets' 3 each
  const double targets = static_cast<double>(config.targets.size());
  const double rows = measure == Measure::Targets ? 3.0 * targets * config.poses : 6.0 * config.poses;
  const double columns = 7.0 * nominal.dof() + (measure == Measure::Targets ? 3.0 * targets : 6.0);
  // the limits of `calibrate` (commands/limits.hpp): the Jacobian and the SVD's V, and one SVD's work
  if (const std::string over = identificationOverLimit(IdentificationSize{rows, columns}); !over.empty()) {
    throw RobotFileError(scenario.path + ": calibration '" + config.name + "': " + std::to_string(config.poses) +
                         " poses of a " + std::to_string(nominal.dof()) + "-joint robot " + over);
  }
}

// calibrate's options for the case: its measure, loss and noise, and its targets (a nominal's point of the
// same name starts the estimate, or is known).
CalibrationOptions caseOptions(const CalibrationCase& config, const RobotFile& nominal_file) {
  CalibrationOptions options;
  options.measure = config.measure();
  options.free_pitch = config.free_pitch;
  options.loss = config.loss;
  if (config.noise_position > 0) options.sigma_position = config.noise_position;
  if (config.noise_rotation > 0) options.sigma_rotation = config.noise_rotation;
  for (const std::string& name : config.targets) {
    Target t{name, std::nullopt};
    for (const Target& listed : nominal_file.targets) {
      if (listed.name == name) t = listed;  // its point starts the estimate, or is known
    }
    options.targets.push_back(t);
  }
  return options;
}

// The case's acceptance on `out` (filled but for pass and failures) against the fit `result` of `fit`, whose
// measurements `blunders` were moved.
void checkAcceptance(const CalibrationCase& config, const RobotFile& nominal_file, const CalibrationResult& result,
                     const MeasurementFile& fit, const std::vector<size_t>& blunders, CalibrationCaseResult& out) {
  const Measure measure = config.measure();
  // acceptance: never pass on a number that was not measured (NaN fails every comparison below)
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) {
      out.pass = false;
      out.failures.push_back(what);
    }
  };
  const ResidualStatistics& v = out.validation_after;
  const std::string u = nominal_file.length_unit.empty() ? "" : " " + nominal_file.length_unit;
  require(v.rms_position <= config.tolerance_position,
          "validation RMS position " + fixed(v.rms_position, 6) + u + " > tolerance " +
              fixed(config.tolerance_position, 6) + u);
  if (config.tolerance_rotation && measure == Measure::Pose) {
    require(v.rms_rotation <= *config.tolerance_rotation,
            "validation RMS rotation " + fixed(v.rms_rotation, 9) + " rad > tolerance " +
                fixed(*config.tolerance_rotation, 9) + " rad");
  }
  if (config.min_improvement) {
    const double ratio = out.validation_before.rms_position / v.rms_position;
    require(ratio >= *config.min_improvement, "improvement " + fixed(ratio, 1) + "x < required " +
                                                  fixed(*config.min_improvement, 1) + "x");
  }
  require(result.converged, "did not converge");
  require(result.accepted, "the fit was rejected: " + result.reason);
  if (config.compensation) {
    const CompensationResult& k = *out.compensation;
    const int not_ok = static_cast<int>(k.not_ok.size());
    require(k.after.rms_position <= config.compensation->tolerance,
            "compensation: RMS position after " + fixed(k.after.rms_position, 9) + u + " > tolerance " +
                fixed(config.compensation->tolerance, 9) + u);
    if (not_ok > config.compensation->allowed_not_ok) {
      std::string counts;
      for (size_t s = 0; s < k.statuses.size(); ++s) {
        if (s != static_cast<size_t>(IkStatus::Ok) && k.statuses[s] > 0) {
          counts += (counts.empty() ? "" : ", ") + std::to_string(k.statuses[s]) + " " + ikStatusName(static_cast<IkStatus>(s));
        }
      }
      require(false, "compensation: " + std::to_string(not_ok) + " of " + std::to_string(k.count()) +
                         " rows not ok (" + counts + "), at most " + std::to_string(config.compensation->allowed_not_ok) +
                         " allowed; first: validation pose " + std::to_string(k.not_ok.front().row + 1) + ": " +
                         k.not_ok.front().reason);
    }
  }
  // blunders: the case says the robust fit finds exactly them
  if (config.blunders > 0) {
    require(out.missed_blunders.empty(), std::to_string(out.missed_blunders.size()) + " of " +
                                             std::to_string(blunders.size()) + " blunders not flagged: measurement " +
                                             listed(fit, out.missed_blunders));
    require(out.false_outliers.empty(), std::to_string(out.false_outliers.size()) +
                                            " measurements flagged without a blunder: " + listed(fit, out.false_outliers));
  }
}

}  // namespace

CalibrationCaseResult runCalibrationCase(const Scenario& scenario, const CalibrationCase& config,
                                         const MujocoRobot& robot, const SampledVariable& sampled) {
  const RobotFile nominal_file = readRobotFile(config.nominal);
  const PoeModel nominal = nominal_file.poeModel();
  checkCase(scenario, config, nominal_file, nominal, robot, sampled);
  const Measure measure = config.measure();
  const std::string where = scenario.name + ", calibration '" + config.name + "'";
  MeasurementSetup setup;
  try {
    setup = caseMeasurementSetup(config, robot, true);
  } catch (const RobotFileError& e) {  // a target that is no site fixed to the tip: name the case
    throw RobotFileError(scenario.path + ": calibration '" + config.name + "': targets: " + e.what());
  }
  MeasurementSetup noise_free = setup;
  noise_free.sd_position = noise_free.sd_rotation = 0.0;
  MujocoRobot::Evaluator mujoco(robot);
  std::optional<CasePlanResult> plan;
  std::vector<VecX> fit_q;
  if (config.plan) {
    plan = planCase(scenario, config, nominal_file, nominal, sampled.ranges, fit_q);
  } else {
    fit_q = randomSamples(config.seed, 0, config.poses, sampled.ranges);
  }
  MeasurementFile fit = measuredAt(config, setup, mujoco, sampled.motions, fit_q, where + ": simulated measurements");
  const std::vector<size_t> blunders = addBlunders(config.seed, config.blunders, config.blunder_size, fit.measurements);
  const std::vector<VecX> validation_q = randomSamples(
      config.seed, static_cast<unsigned long long>(config.firstValidationSample()), config.validation_poses, sampled.ranges);
  const std::optional<MeasurementFile> validation = measureAt(config, noise_free, mujoco, sampled.motions, validation_q,
                                                              static_cast<unsigned long long>(config.firstValidationSample()),
                                                              where + ": noise-free validation measurements");

  const CalibrationOptions options = caseOptions(config, nominal_file);
  const auto start = std::chrono::steady_clock::now();
  const CalibrationResult result = calibrate(nominal, fit.measurements, options);
  const DhUncertainty dh = dhUncertainty(result);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  CalibrationCaseResult out;
  out.config = config;
  out.rank = result.rank.rank;
  out.expected = result.expected.total();
  out.iterations = result.iterations;
  out.converged = result.converged;
  out.seconds = seconds;
  out.fit_before = result.before;
  out.fit_after = result.after;
  // validation in the measurement frame: the nominal where the registration put it (before), the calibrated
  // model (after), each with its targets' points
  std::vector<std::string> fit_targets;
  for (const Target& t : options.targets) fit_targets.push_back(t.name);
  const std::vector<Measurement> held_out = targetsByName(*validation, fit_targets);
  const PoeModel registered = movedModel(nominal, result.registration.T_meas_base);
  out.validation_before = residualStatistics(registered, held_out, measure, result.registration.target_points);
  out.validation_after = residualStatistics(result.model, held_out, measure, result.target_points);
  out.validation_position_before = positionErrors(registered, held_out, measure, result.registration.target_points);
  out.validation_position_after = positionErrors(result.model, held_out, measure, result.target_points);
  out.blunders = blunders;
  out.plan = std::move(plan);
  if (config.compensation) {
    out.compensation = compensateCase(config, nominal, result, setup, mujoco, sampled.motions, validation_q);
  }
  for (size_t k = 0; k < result.residuals.size(); ++k) {
    const bool blunder = std::binary_search(blunders.begin(), blunders.end(), k);
    if (blunder && !result.residuals[k].outlier) out.missed_blunders.push_back(k);
    if (!blunder && result.residuals[k].outlier) out.false_outliers.push_back(k);
  }

  checkAcceptance(config, nominal_file, result, fit, blunders, out);
  // (a rank below the count is not a failure: position measurements of a tool point on the last axis, for
  // one, cannot see that axis; calibrate's text and JSON name the undetermined directions)
  out.report = std::make_shared<const CalibrationReport>(
      makeCalibrationReport(nominal_file, std::move(fit), validation, result, dh, seconds));
  return out;
}

}  // namespace lowpair::validation
