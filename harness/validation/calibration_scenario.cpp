#include "validation/calibration_scenario.hpp"

#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "validation/calibration_output.hpp"
#include "lowpair/kinematics.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "validation/validate.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::mujoco;

namespace {

std::vector<double> positionErrors(const PoeModel& model, const std::vector<Measurement>& measurements) {
  std::vector<double> errors;
  Data data(model);
  for (const Measurement& m : measurements) {
    forwardKinematics(model, data, m.q);
    errors.push_back((m.T_base_tool.p - data.T_base_tool.p).norm());
  }
  return errors;
}

}  // namespace

MeasurementFile simulatedMeasurements(const CalibrationCase& c, MujocoRobot::Evaluator& mujoco,
                                      const std::vector<JointMotion>& variables, const std::vector<Range>& ranges,
                                      int first, int count, bool noisy, std::string label) {
  MeasurementFile file;
  file.path = std::move(label);
  file.measure = c.position_only ? Measure::Position : Measure::Pose;
  file.dof = static_cast<int>(variables.size());
  VecX q(file.dof), x(file.dof);
  for (int s = first; s < first + count; ++s) {
    randomSample(c.seed, static_cast<unsigned long long>(s), ranges, q);
    for (int i = 0; i < file.dof; ++i) x[i] = variables[static_cast<size_t>(i)].motion(q[i]);
    Pose T = mujoco.tipPose(x);
    if (noisy) addMeasurementNoise(c.seed, static_cast<unsigned long long>(s), c.noise_position, c.noise_rotation, T);
    file.measurements.push_back(Measurement{q, T});
  }
  return file;
}

CalibrationCaseResult runCalibrationCase(const Scenario& scenario, const CalibrationCase& config,
                                         const MujocoRobot& robot, const SampledVariable& sampled) {
  const RobotFile nominal_file = readRobotFile(config.nominal);
  const PoeModel nominal = nominal_file.poeModel();
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
  if (identificationEntries(config.poses, nominal.dof(), 7.0) > kMaxJacobianEntries) {
    throw RobotFileError(scenario.path + ": calibration '" + config.name + "': " + std::to_string(config.poses) +
                         " poses of a " + std::to_string(nominal.dof()) + "-joint robot exceed the Jacobian size limit");
  }
  MujocoRobot::Evaluator mujoco(robot);
  const std::string where = scenario.name + ", calibration '" + config.name + "'";
  const MeasurementFile fit =
      simulatedMeasurements(config, mujoco, sampled.motions, sampled.ranges, 0, config.poses, true, where + ": simulated measurements");
  const std::optional<MeasurementFile> validation =
      simulatedMeasurements(config, mujoco, sampled.motions, sampled.ranges, config.poses, config.validation_poses, false,
              where + ": noise-free validation measurements");

  CalibrationOptions options;
  options.measure = fit.measure;
  options.free_pitch = config.free_pitch;
  if (config.noise_position > 0) options.sigma_position = config.noise_position;
  if (config.noise_rotation > 0) options.sigma_rotation = config.noise_rotation;
  const auto start = std::chrono::steady_clock::now();
  const CalibrationResult result = calibrate(nominal, fit.measurements, options);
  const DhUncertainty dh = dhUncertainty(result);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto report = std::make_shared<const CalibrationReport>(
      makeCalibrationReport(nominal_file, fit, validation, result, dh, seconds));

  CalibrationCaseResult out;
  out.config = config;
  out.rank = result.rank.rank;
  out.expected = result.expected.total();
  out.iterations = result.iterations;
  out.converged = result.converged;
  out.seconds = seconds;
  out.fit_before = result.before;
  out.fit_after = result.after;
  const ValidationResiduals& v = *report->validation_residuals;
  out.validation_before = v.before;
  out.validation_after = v.after;
  out.validation_position_before = positionErrors(nominal, validation->measurements);
  out.validation_position_after = positionErrors(result.model, validation->measurements);
  out.report = report;

  // acceptance: never pass on a number that was not measured (NaN fails every comparison below)
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) {
      out.pass = false;
      out.failures.push_back(what);
    }
  };
  const std::string u = nominal_file.length_unit.empty() ? "" : " " + nominal_file.length_unit;
  require(v.after.rms_position <= config.tolerance_position,
          "validation RMS position " + fixed(v.after.rms_position, 6) + u + " > tolerance " +
              fixed(config.tolerance_position, 6) + u);
  if (config.tolerance_rotation && !config.position_only) {
    require(v.after.rms_rotation <= *config.tolerance_rotation,
            "validation RMS rotation " + fixed(v.after.rms_rotation, 9) + " rad > tolerance " +
                fixed(*config.tolerance_rotation, 9) + " rad");
  }
  if (config.min_improvement) {
    const double ratio = v.before.rms_position / v.after.rms_position;
    require(ratio >= *config.min_improvement, "improvement " + fixed(ratio, 1) + "x < required " +
                                                  fixed(*config.min_improvement, 1) + "x");
  }
  require(result.converged, "did not converge");
  // (a rank below the count is not a failure: position measurements of a tool point on the last axis, for
  // one, cannot see that axis; calibrate's text and JSON name the undetermined directions)
  return out;
}

}  // namespace lowpair::validation
