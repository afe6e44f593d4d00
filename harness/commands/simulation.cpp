// The checks and the measurement loop of `simulate` for the CLI and the Python module (simulation.hpp).
#include "commands/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "io/output.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::commands {

namespace {

// a rotation noise above pi rad is a uniformly random rotation; a position noise up to 1e100 keeps every
// coordinate within what the measurement reader takes (checked per measurement)
void checkNoiseLevel(const std::string& name, double sd, double limit) {
  if (!std::isfinite(sd) || sd < 0) throw UsageError(name, "expected a finite number >= 0, got " + io::shortest(sd));
  if (sd > limit) throw UsageError(name, io::shortest(sd) + " is above " + io::shortest(limit));
}

UsageError tooLarge(const std::string& subject, size_t row) {
  return UsageError(subject, "measurement " + std::to_string(row + 1) +
                                 " has a coordinate above 1e100 in magnitude, which no reader takes");
}

bool beyondReader(const Measurement& m) { return !(m.T_base_tool.p.cwiseAbs().maxCoeff() <= kMaxMagnitude); }

}  // namespace

void checkTargetList(const std::vector<std::string>& names, const ArgumentSpelling& spelling) {
  if (names.empty()) {
    // no target measured means no measurement: refused here, before anything is drawn (an empty result set used to
    // reach the caller, and Python's Measurements.q read the first of no rows)
    throw UsageError(spelling.name("targets"), "is empty: name at least one target, or leave it out to measure every "
                                               "target of the robot file");
  }
  std::set<std::string> seen;
  for (const std::string& name : names) {
    const std::string problem = io::targetNameProblem(name);
    if (!problem.empty()) {
      throw UsageError(spelling.name("targets"), io::quotedFileText(name) + " " + problem + " (" + io::kTargetNameRule + ")");
    }
    if (!seen.insert(name).second) throw UsageError(spelling.name("targets"), io::quotedFileText(name) + " is given twice");
  }
  if (names.size() > static_cast<size_t>(io::kMaxTargets)) {
    throw UsageError(spelling.name("targets"),
                     std::to_string(names.size()) + " targets, more than " + std::to_string(io::kMaxTargets));
  }
}

std::vector<Target> numberedRobotFileTargets(const io::RobotFile& file, const ArgumentSpelling& spelling) {
  if (file.targets.empty()) {
    throw UsageError(file.path, spelling.setting("measure", "targets") +
                                    " needs a `targets:` list in the robot file (docs/file_formats.md)");
  }
  std::vector<Target> targets = file.targets;
  for (Target& t : targets) t.name.clear();  // the error model numbers unnamed targets
  return targets;
}

std::vector<std::string> robotFileTargets(const std::vector<Target>& file_targets,
                                          const std::optional<std::vector<std::string>>& names,
                                          const std::string& robot_subject, const ArgumentSpelling& spelling,
                                          std::vector<Vec3>& points) {
  if (file_targets.empty()) {
    throw UsageError(robot_subject, spelling.setting("measure", "targets") +
                                        ": the robot file lists no targets (a 'targets:' list of {name, point})");
  }
  std::vector<std::string> out;
  if (names) {
    checkTargetList(*names, spelling);
    out = *names;
  } else {
    for (const Target& t : file_targets) out.push_back(t.name);
  }
  for (const std::string& name : out) {
    const auto it = std::find_if(file_targets.begin(), file_targets.end(), [&](const Target& t) { return t.name == name; });
    if (it == file_targets.end()) {
      std::string known;
      for (const Target& t : file_targets) known += (known.empty() ? "" : ", ") + t.name;
      throw UsageError(spelling.name("targets"), io::quotedFileText(name) + " is not a target of " + robot_subject +
                                                     " (its targets: " + known + ")");
    }
    points.push_back(*it->point_tool);
  }
  return out;
}

void checkSimulationArguments(Measure measure, double noise_position, double noise_rotation, bool targets_given,
                              const ArgumentSpelling& spelling) {
  checkNoiseLevel(spelling.name("noise_position"), noise_position, kMaxMagnitude);
  checkNoiseLevel(spelling.name("noise_rotation"), noise_rotation, M_PI);
  if (measure != Measure::Pose && noise_rotation > 0) {  // as calibrate rejects it
    throw UsageError(spelling.name("noise_rotation"),
                     std::string(measurementsText(measure)) + " have no rotation to perturb");
  }
  if (targets_given && measure != Measure::Targets) {
    throw UsageError(spelling.name("targets"), "goes with " + spelling.setting("measure", "targets"));
  }
}

Blunders checkBlunders(double count, double size, const ArgumentSpelling& spelling) {
  if (!(count >= 0 && count == std::floor(count) && count <= io::kMaxMeasurements)) {
    throw UsageError(spelling.name("blunders"), "COUNT must be a whole number in [0, " +
                                                    std::to_string(io::kMaxMeasurements) + "], got " + io::shortest(count));
  }
  if (!(size > 0 && size <= kMaxMagnitude)) {
    throw UsageError(spelling.name("blunders"), "SIZE must be positive and at most " + io::shortest(kMaxMagnitude) +
                                                    ", got " + io::shortest(size));
  }
  return {static_cast<long long>(count), size};
}

long long simulationRows(long long poses, int joints, const MeasurementSetup& setup, const std::string& poses_subject,
                         const std::string& robot_subject) {
  if (joints > io::kMaxMeasurementJoints) {
    throw UsageError(robot_subject, std::to_string(joints) + " joints, more than the " +
                                        std::to_string(io::kMaxMeasurementJoints) + " a measurement file holds");
  }
  const long long rows = poses * rowsPerPose(setup);
  if (rows > io::kMaxMeasurements) {
    throw UsageError(poses_subject, std::to_string(poses) + " poses x " + std::to_string(rowsPerPose(setup)) +
                                        " targets = " + std::to_string(rows) + " measurements, more than the " +
                                        std::to_string(io::kMaxMeasurements) + " a measurement file holds");
  }
  if (rows * joints > io::kMaxMeasurementJointValues) {
    throw UsageError(poses_subject, std::to_string(rows) + " measurements x " + std::to_string(joints) + " joints = " +
                                        std::to_string(rows * joints) + " joint values, more than the " +
                                        std::to_string(io::kMaxMeasurementJointValues) + " a measurement file holds");
  }
  return rows;
}

void checkBlunderCount(const Blunders& blunders, long long rows, const ArgumentSpelling& spelling) {
  if (blunders.count > rows) {
    throw UsageError(spelling.name("blunders"), "COUNT " + std::to_string(blunders.count) + " is more than the " +
                                                    std::to_string(rows) + " measurements");
  }
}

SimulatedMeasurements simulateMeasurements(const TipPose& tip_pose, const MeasurementSetup& setup,
                                           unsigned long long seed, const SimulationPoses& poses,
                                           const std::optional<Blunders>& blunders, bool in_frame,
                                           const std::string& robot_subject, const ArgumentSpelling& spelling) {
  for (const Range& r : poses.ranges) {
    if (!poses.q_rows && !(std::max(std::abs(r[0]), std::abs(r[1])) <= kMaxMagnitude)) {
      throw UsageError(robot_subject, "a joint range reaches " + io::shortest(std::max(std::abs(r[0]), std::abs(r[1]))) +
                                          ", above the 1e100 the measurement reader takes");
    }
  }
  SimulatedMeasurements s;
  s.measurements.reserve(static_cast<size_t>(poses.count * rowsPerPose(setup)));
  VecX q(static_cast<Eigen::Index>(poses.ranges.size()));
  for (size_t k = 0; k < static_cast<size_t>(poses.count); ++k) {
    if (poses.q_rows) {
      q = poses.q_rows->row(static_cast<Eigen::Index>(k)).transpose();
    } else {
      randomSample(seed, k, poses.ranges, q);
    }
    const Pose T_base_tool = tip_pose(q);
    if (!(T_base_tool.p.cwiseAbs().maxCoeff() <= kMaxMagnitude)) {
      if (poses.q_rows) poses.given_row_beyond_reach(k);  // a given joint value is the cause: the caller names it
      throw tooLarge(robot_subject, k * static_cast<size_t>(rowsPerPose(setup)));
    }
    const size_t first = s.measurements.size();
    appendMeasurements(setup, seed, k, q, T_base_tool, s.measurements);
    for (size_t r = first; r < s.measurements.size(); ++r) {
      if (beyondReader(s.measurements[r])) throw tooLarge(spelling.name(in_frame ? "frame" : "noise_position"), r);
    }
  }
  if (blunders) {
    s.blunders = addBlunders(seed, blunders->count, blunders->size, s.measurements);
    for (const size_t r : s.blunders) {
      if (beyondReader(s.measurements[r])) throw tooLarge(spelling.name("blunders"), r);
    }
  }
  return s;
}

}  // namespace lowpair::commands
