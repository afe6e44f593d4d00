#include "validation/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "commands/calibration_output.hpp"
#include "io/robot_file.hpp"
#include "io/yaml_reader.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::commands;

namespace fs = std::filesystem;

namespace {

std::string relative(const std::string& scenario_path, const std::string& file) {
  if (file.empty() || fs::path(file).is_absolute()) return file;
  return (fs::path(scenario_path).parent_path() / file).lexically_normal().string();
}

std::vector<double> numbers(const YamlReader& in, const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence()) yamlError(in.path(), node, what + " must be a list of numbers");
  std::vector<double> out;
  for (size_t i = 0; i < node.size(); ++i) out.push_back(in.number(node[i], what + "[" + std::to_string(i) + "]"));
  return out;
}

// `targets:` a non-empty list of distinct target names (the model's sites; runCalibrationCase checks them there)
std::vector<std::string> readTargetNames(const YamlReader& in, const YAML::Node& node, const std::string& where) {
  if (!node.IsSequence() || node.size() == 0) yamlError(in.path(), node, where + " must be a non-empty list of site names");
  if (node.size() > static_cast<size_t>(kMaxTargets)) {
    yamlError(in.path(), node, where + " lists " + std::to_string(node.size()) + " targets, more than " +
                                   std::to_string(kMaxTargets));
  }
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string what = where + "[" + std::to_string(i) + "]";
    const std::string name = in.string(node[i], what);
    const std::string problem = targetNameProblem(name);
    if (!problem.empty()) yamlError(in.path(), node[i], what + " " + problem + " (" + kTargetNameRule + ")");
    if (!seen.insert(name).second) yamlError(in.path(), node[i], what + " '" + name + "' is listed twice");
    names.push_back(name);
  }
  return names;
}

PlanCriterion readCriterion(const YamlReader& in, const YAML::Node& node, const std::string& what) {
  const std::string text = in.string(node, what);
  for (const PlanCriterion c : {PlanCriterion::D, PlanCriterion::O1}) {
    if (text == planCriterionName(c)) return c;
  }
  yamlError(in.path(), node, what + " must be D or O1, got '" + text + "'");
}

// `plan: D` (or O1), or `plan: {criterion: D|O1, candidates: M}`: M from `poses` (planPoses chooses that many
// of them) to kMaxPlanCandidates
CasePlan readCasePlan(const YamlReader& in, const YAML::Node& node, int poses, const std::string& where) {
  CasePlan plan;
  if (node.IsScalar()) {
    plan.criterion = readCriterion(in, node, where + ".plan");
    if (poses > plan.candidates) {
      yamlError(in.path(), node, where + ": plan chooses the " + std::to_string(poses) + " poses among " +
                                     std::to_string(plan.candidates) + " candidates (the default): give plan.candidates >= poses");
    }
    return plan;
  }
  in.allowOnly(node, where + ".plan", {"criterion", "candidates"});
  if (node["criterion"]) plan.criterion = readCriterion(in, node["criterion"], where + ".plan.criterion");
  if (node["candidates"]) {
    plan.candidates = static_cast<int>(in.integer(node["candidates"], where + ".plan.candidates", 1, kMaxPlanCandidates));
  }
  if (poses > plan.candidates) {
    yamlError(in.path(), node["candidates"] ? node["candidates"] : node,
              where + ": plan.candidates " + std::to_string(plan.candidates) + " is below poses " + std::to_string(poses) +
                  " (the plan chooses the poses among the candidates)");
  }
  return plan;
}

// `compensate: {tolerance: T, allowed_not_ok: K}`: T a positive length, K in [0, validation_poses]
CaseCompensation readCaseCompensation(const YamlReader& in, const YAML::Node& node, int validation_poses,
                                      const std::string& where) {
  in.allowOnly(node, where + ".compensate", {"tolerance", "allowed_not_ok", "base_frame"});
  if (!node["tolerance"]) {
    yamlError(in.path(), node, where + ".compensate: missing 'tolerance' (RMS position error after compensation, length)");
  }
  CaseCompensation k;
  k.tolerance = in.number(node["tolerance"], where + ".compensate.tolerance");
  if (!(k.tolerance > 0) || k.tolerance > kMaxMagnitude) {
    yamlError(in.path(), node["tolerance"], where + ".compensate.tolerance must be positive and at most 1e100 (length)");
  }
  if (node["allowed_not_ok"]) {
    k.allowed_not_ok = static_cast<int>(
        in.integer(node["allowed_not_ok"], where + ".compensate.allowed_not_ok", 0, validation_poses));
  }
  if (node["base_frame"]) k.base_frame = in.boolean(node["base_frame"], where + ".compensate.base_frame");
  return k;
}

CalibrationCase readCalibrationCase(const YamlReader& in, const YAML::Node& node, size_t index) {
  const std::string& path = in.path();
  in.allowOnly(node, "a calibration case",
               {"name", "nominal", "poses", "validation_poses", "seed", "measure", "free_pitch", "noise",
                "tolerance", "targets", "frame", "blunders", "loss", "plan", "compensate"});
  CalibrationCase c;
  c.name = node["name"] ? in.string(node["name"], "calibration name") : "calibration" + std::to_string(index + 1);
  const std::string where = "calibration '" + c.name + "'";
  if (!node["nominal"]) yamlError(path, node, where + ": missing 'nominal' (the robot file to calibrate)");
  c.nominal = relative(path, in.string(node["nominal"], where + ".nominal"));
  if (node["poses"]) c.poses = static_cast<int>(in.integer(node["poses"], where + ".poses", 1, kMaxCalibrationMeasurements));
  if (node["validation_poses"]) {
    c.validation_poses =
        static_cast<int>(in.integer(node["validation_poses"], where + ".validation_poses", 1, kMaxCalibrationPoses));
  }
  if (node["seed"]) c.seed = static_cast<unsigned long long>(in.integer(node["seed"], where + ".seed", 0, kMaxSeed));
  if (node["targets"]) c.targets = readTargetNames(in, node["targets"], where + ".targets");
  if (node["measure"]) {
    const std::string m = in.string(node["measure"], where + ".measure");
    if (m != "pose" && m != "position" && m != "targets") {
      yamlError(path, node["measure"], where + ".measure must be pose, position or targets");
    }
    if ((m == "targets") != !c.targets.empty()) {
      yamlError(path, node["measure"], where + ": measure " + m +
                                           (c.targets.empty() ? " needs targets: [SITE, ...]" : " with targets (their measure is targets)"));
    }
    c.position_only = m == "position";
  }
  // every fitting measurement is a row of the identification Jacobian: poses x targets of them
  const long long rows = static_cast<long long>(c.poses) * std::max<long long>(1, static_cast<long long>(c.targets.size()));
  if (rows > kMaxCalibrationMeasurements) {
    yamlError(path, node["targets"], where + ": " + std::to_string(c.poses) + " poses x " + std::to_string(c.targets.size()) +
                                         " targets = " + std::to_string(rows) + " measurements, more than " +
                                         std::to_string(kMaxCalibrationMeasurements));
  }
  const bool points = c.measure() != Measure::Pose;  // position or targets: no rotation measured
  if (node["free_pitch"]) {
    c.free_pitch = in.boolean(node["free_pitch"], where + ".free_pitch");
  }
  if (const YAML::Node noise = node["noise"]) {
    in.allowOnly(noise, where + ".noise", {"position", "rotation"});
    c.noise_position = in.numberOr(noise, "position", 0.0, where + ".noise");
    c.noise_rotation = in.numberOr(noise, "rotation", 0.0, where + ".noise");
    if (c.noise_position < 0 || c.noise_rotation < 0) yamlError(path, noise, where + ".noise must be >= 0");
    if (c.noise_rotation > M_PI) yamlError(path, noise, where + ".noise.rotation must be at most pi (rad)");
    if (points && noise["rotation"]) {
      yamlError(path, noise, where + ": noise.rotation given for " + measureName(c.measure()) +
                                 " measurements (points: no rotation is measured)");
    }
  }
  if (const YAML::Node f = node["frame"]) {
    in.allowOnly(f, where + ".frame", {"rotation", "translation"});
    std::array<double, 6> frame{};
    for (const auto& [key, first] : {std::pair<const char*, size_t>{"rotation", 0}, {"translation", 3}}) {
      if (!f[key]) continue;
      const std::string what = where + ".frame." + key;
      const std::vector<double> v = in.vector(f[key], 3, what);
      for (size_t k = 0; k < 3; ++k) {
        if (!(std::abs(v[k]) <= kMaxMagnitude)) yamlError(path, f[key], what + " has a value above 1e100 in magnitude");
        frame[first + k] = v[k];
      }
    }
    c.frame = frame;
  }
  if (const YAML::Node b = node["blunders"]) {
    in.allowOnly(b, where + ".blunders", {"count", "size"});
    if (!b["count"] || !b["size"]) yamlError(path, b, where + ".blunders needs count and size");
    c.blunders = in.integer(b["count"], where + ".blunders.count", 0, kMaxCalibrationMeasurements);
    if (c.blunders > rows) {
      yamlError(path, b["count"], where + ".blunders.count " + std::to_string(c.blunders) + " is more than the case's " +
                                      std::to_string(rows) + " fitting measurements");
    }
    c.blunder_size = in.number(b["size"], where + ".blunders.size");
    if (!(c.blunder_size > 0) || c.blunder_size > kMaxMagnitude) {
      yamlError(path, b["size"], where + ".blunders.size must be positive and at most 1e100 (length)");
    }
  }
  if (node["loss"]) {
    const std::string loss = in.string(node["loss"], where + ".loss");
    bool known = false;
    for (const Loss l : {Loss::Squared, Loss::Huber, Loss::Cauchy}) {
      if (loss == lossName(l)) {
        c.loss = l;
        known = true;
      }
    }
    if (!known) yamlError(path, node["loss"], where + ".loss must be squared, huber or cauchy, got '" + loss + "'");
  }
  if (const YAML::Node p = node["plan"]) c.plan = readCasePlan(in, p, c.poses, where);
  if (const YAML::Node k = node["compensate"]) c.compensation = readCaseCompensation(in, k, c.validation_poses, where);
  const YAML::Node t = node["tolerance"];
  if (!t) yamlError(path, node, where + ": missing 'tolerance' (at least position: validation RMS after, length)");
  in.allowOnly(t, where + ".tolerance", {"position", "rotation", "improvement"});
  if (!t["position"]) yamlError(path, t, where + ".tolerance: missing 'position'");
  c.tolerance_position = in.number(t["position"], where + ".tolerance.position");
  if (t["rotation"]) {
    if (points) yamlError(path, t, where + ": tolerance.rotation given for " + measurementsText(c.measure()));
    c.tolerance_rotation = in.number(t["rotation"], where + ".tolerance.rotation");
  }
  if (t["improvement"]) c.min_improvement = in.number(t["improvement"], where + ".tolerance.improvement");
  for (const double v : {c.tolerance_position, c.tolerance_rotation.value_or(1.0), c.min_improvement.value_or(1.0)}) {
    if (!(v > 0)) yamlError(path, t, where + ".tolerance values must be positive");
  }
  return c;
}

}  // namespace

Scenario readScenario(const std::string& path) {
  const YAML::Node root = loadYamlFile(path);
  const YamlReader in(path);
  Scenario s;
  s.path = path;
  try {
    in.allowOnly(root, "the scenario", {"name", "description", "model", "tip", "base", "joint_variables",
                                        "robot_files", "length_unit", "samples", "seed", "ranges", "tolerance", "poses",
                                        "singular_poses", "singularity_map", "calibration"});
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
    if (root["length_unit"]) {
      s.length_unit = in.string(root["length_unit"], "length_unit");
      if (!metresPerUnit(s.length_unit)) {
        yamlError(path, root["length_unit"], "length_unit '" + s.length_unit +
                                                 "' is not one lowpair converts (m, mm, cm, dm, um, km, in, ft)");
      }
    }
    if (root["samples"]) s.samples = static_cast<int>(in.integer(root["samples"], "samples", 0, kMaxSamples));
    if (root["seed"]) s.seed = static_cast<unsigned long long>(in.integer(root["seed"], "seed", 0, kMaxSeed));
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
        const YAML::Node joints = m["joints"];
        if (!joints.IsSequence() || joints.size() != 2) {
          yamlError(path, joints, "singularity_map.joints must name two joints (1-based)");
        }
        // whole numbers in range before any conversion to int (a cast of 1e300 is undefined behaviour);
        // the upper bound only keeps the value an int: runScenario checks it against the joint count
        constexpr long long kLargestJointNumber = 1LL << 30;
        for (size_t k = 0; k < 2; ++k) {
          s.map_joints.push_back(
              static_cast<int>(in.integer(joints[k], "singularity_map.joints[]", 1, kLargestJointNumber)));
        }
      }
      if (m["fixed"]) s.map_fixed = numbers(in, m["fixed"], "singularity_map.fixed");
    }
    if (const YAML::Node cases = root["calibration"]) {
      if (!cases.IsSequence() || cases.size() == 0) yamlError(path, cases, "calibration must be a non-empty list of cases");
      for (const auto& c : cases) s.calibrations.push_back(readCalibrationCase(in, c, s.calibrations.size()));
    }
  } catch (const YAML::Exception& e) {
    throw RobotFileError(path + ": line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  return s;
}

}  // namespace lowpair::validation
