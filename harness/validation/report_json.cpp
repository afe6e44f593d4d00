// `lowpair validate --json` and report.json (report.hpp validationJson).
#include "validation/report.hpp"

#include "io/output.hpp"
#include "lowpair/se3.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below

using nlohmann::json;

namespace {

std::vector<size_t> oneBased(const std::vector<size_t>& rows) {
  std::vector<size_t> out;
  for (const size_t r : rows) out.push_back(r + 1);
  return out;
}

// count, RMS and max position (and rotation for a pose task: null otherwise; null for a number not measured)
json statisticsJson(const ResidualStatistics& s, bool rotation) {
  return {{"count", s.count},
          {"rms_position", finiteOrNull(s.rms_position)},
          {"max_position", finiteOrNull(s.max_position)},
          {"rms_rotation", rotation ? finiteOrNull(s.rms_rotation) : json(nullptr)},
          {"max_rotation", rotation ? finiteOrNull(s.max_rotation) : json(nullptr)}};
}

json planJson(const CalibrationCase& config, const CasePlanResult& p) {
  auto value = [](const PlanValue& v) {
    return json{{"log_det", finiteOrNull(v.log_det)}, {"O1", v.o1}, {"rank", v.rank}};
  };
  return {{"criterion", planCriterionName(p.plan.criterion)},
          {"candidates", config.plan->candidates},
          {"samples", p.plan.indices},
          {"planned", value(p.plan.value)},
          {"first_samples", value(p.first)},
          {"greedy", value(p.plan.start)},
          {"swaps", p.plan.swaps},
          {"passes", p.plan.passes},
          {"rank", p.plan.rank.rank},
          {"expected", p.plan.expected.total()},
          {"seconds", p.seconds}};
}

json compensationJson(const CalibrationCase& config, const CompensationResult& k) {
  const bool rotation = k.measure == Measure::Pose;
  json statuses = json::object();
  for (size_t s = 0; s < k.statuses.size(); ++s) statuses[ikStatusName(static_cast<IkStatus>(s))] = k.statuses[s];
  json not_ok = json::array();
  for (const CompensationResult::Row& r : k.not_ok) {
    not_ok.push_back({{"validation_pose", r.row + 1}, {"status", ikStatusName(r.status)}, {"reason", r.reason}});
  }
  return {{"measure", measureName(k.measure)},
          {"target", k.point_name.empty() ? json(nullptr) : json(k.point_name)},
          {"point_tool", {k.point_tool.x(), k.point_tool.y(), k.point_tool.z()}},
          {"length_scale", k.length_scale},
          {"tolerance", config.compensation->tolerance},
          {"allowed_not_ok", config.compensation->allowed_not_ok},
          {"before", statisticsJson(k.before, rotation)},
          {"after", statisticsJson(k.after, rotation)},
          {"statuses", statuses},
          {"not_ok", not_ok},
          {"tool_determined", k.tool_determined},
          {"base_frame", k.base_frame},
          {"rigid_motion_after", {{"translation", k.rigid_after.p.norm()}, {"angle", rotationAngle(k.rigid_after.R)}}},
          {"seconds", k.seconds}};
}

}  // namespace

json validationJson(const std::vector<ScenarioResult>& results, const RunOptions& options) {
  json doc;
  bool pass = true;
  doc["scenarios"] = json::array();
  for (const auto& r : results) {
    json s = {{"name", r.scenario.name},  {"file", r.scenario.path}, {"model", r.scenario.model},
              {"tip", r.scenario.tip},    {"samples", r.samples},    {"seed", options.seed ? *options.seed : r.scenario.seed},
              {"size", r.size},           {"seconds", r.seconds},    {"pass", r.pass}};
    if (options.shards > 1) s["shard"] = std::to_string(options.shard) + "/" + std::to_string(options.shards);
    s["comparisons"] = json::array();
    for (const auto& c : r.comparisons) {
      json j = {{"name", c.name},
                {"max_rotation", c.max_rotation},
                {"mean_rotation", c.mean_rotation},
                {"p99_rotation", c.p99_rotation},
                {"max_translation", c.max_translation},
                {"mean_translation", c.mean_translation},
                {"p99_translation", c.p99_translation},
                {"tolerance_rotation", c.tolerance_rotation},
                {"tolerance_translation", c.tolerance_translation},
                {"worst_q", c.worst_q},
                {"non_finite", c.non_finite},
                {"pass", c.pass}};
      if (c.pose) j["max_rotation_euler_zyx"] = c.max_rotation_euler;
      s["comparisons"].push_back(j);
    }
    if (!r.singular_poses.empty()) {
      s["singular_poses"] = json::array();
      for (const auto& sp : r.singular_poses) {
        s["singular_poses"].push_back({{"name", sp.name}, {"q", sp.q}, {"expected", sp.expected},
                                       {"reported", sp.reported}, {"rank", sp.rank_library},
                                       {"rank_mujoco", sp.rank_mujoco}, {"dof", sp.dof},
                                       {"sigma_min", sp.sigma_min}, {"pass", sp.pass}});
      }
    }
    if (!r.calibrations.empty()) {
      s["calibrations"] = json::array();
      for (const auto& c : r.calibrations) {
        json j = calibrationJson(*c.report);
        j["name"] = c.config.name;
        j["pass"] = c.pass;
        j["failures"] = c.failures;
        // the scenario's own checks: validation in the measurement frame, blunders (1-based measurements)
        j["acceptance"] = {{"validation_rms_position_before", c.validation_before.rms_position},
                           {"validation_rms_position_after", c.validation_after.rms_position},
                           {"validation_rms_rotation_after", c.validation_after.rms_rotation},
                           {"blunders", oneBased(c.blunders)},
                           {"missed_blunders", oneBased(c.missed_blunders)},
                           {"false_outliers", oneBased(c.false_outliers)}};
        if (c.plan) j["plan"] = planJson(c.config, *c.plan);
        if (c.compensation) j["compensation"] = compensationJson(c.config, *c.compensation);
        s["calibrations"].push_back(j);
      }
    }
    pass = pass && r.pass;
    doc["scenarios"].push_back(s);
  }
  doc["pass"] = pass;
  return doc;
}

}  // namespace lowpair::validation
