// The report of `lowpair plan` for the CLI and the Python module (plan_report.hpp).
#include "commands/plan_report.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "io/output.hpp"
#include "lowpair/tolerances.hpp"
#include "commands/calibration_inputs.hpp"
#include "commands/calibration_output.hpp"
#include "commands/sampling.hpp"

namespace lowpair::commands {

using nlohmann::json;

namespace {

/// The noise assumed when none is stated: position 1e-5 L per coordinate, rotation 1e-5 rad per axis.
constexpr double kDefaultRelativeNoise = 1e-5;

Spread spread(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const size_t n = x.size();
  return {n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]), x.back()};
}

// Fewer kept candidates than poses: what was rejected, and what to look at.
void checkEnoughFeasible(const FeasibilityReport& f, int poses, const ArgumentSpelling& spelling) {
  if (f.kept >= poses) return;
  std::string s = (f.kept == 0 ? "no candidate" : "only " + std::to_string(f.kept)) + " of " + std::to_string(f.drawn) +
                  (f.kept <= 1 ? " is" : " are") + " free of contacts" +
                  (f.tracker ? std::string(f.partial ? " and see a target" : " and see every target") : "") + " in " +
                  f.model + " (" + std::to_string(poses) + " poses asked for); rejected: self-collision " +
                  std::to_string(f.self_collision) + ", world geometry " + std::to_string(f.world) + ", floor " +
                  std::to_string(f.floor_contact);
  if (f.tracker) s += ", occluded " + std::to_string(f.occluded) + ", angle " + std::to_string(f.angle);
  if (!f.pairs.empty()) {
    s += "; most often '" + f.pairs.front().body1 + "' with '" + f.pairs.front().body2 + "' (" +
         std::to_string(f.pairs.front().candidates) + " candidates)";
  }
  if (!f.occluders.empty()) {
    s += "; most often hidden by " + f.occluders.front().geom + " (" + std::to_string(f.occluders.front().candidates) +
         " candidates)";
  }
  throw InfeasiblePlan(s + ": look at the joint ranges (" + spelling.name("range") + ", " + spelling.name("range_margin") +
                       ")" + (f.floor ? ", the floor's height (" + spelling.name("floor") + ")" : std::string()) +
                       (f.tracker ? ", the tracker's position (" + spelling.name("tracker") + "), the SMRs' normals and " +
                                        spelling.name("smr_angle") + (f.partial ? "" : ", " + spelling.name("partial"))
                                  : std::string()) +
                       " and the model's collision geometry (contype/conaffinity, <exclude>); or draw more " +
                       spelling.name("candidates"));
}

json feasibilityJson(const FeasibilityReport& f) {
  json pairs = json::array();
  for (const BodyPairCount& p : f.pairs) pairs.push_back({{"bodies", {p.body1, p.body2}}, {"candidates", p.candidates}});
  json ranges = json::array();
  for (size_t i = 0; i < f.ranges.size(); ++i) {
    ranges.push_back({{"lo", f.ranges[i][0]}, {"hi", f.ranges[i][1]}, {"source", f.range_source[i]}});
  }
  json sight = nullptr;
  if (f.tracker) {
    json occluders = json::array();
    for (const OccluderCount& o : f.occluders) {
      occluders.push_back({{"geom", o.geom}, {"body", o.body}, {"candidates", o.candidates}});
    }
    sight = {{"tracker", io::toVector(*f.tracker)}, {"smr_angle_deg", f.smr_angle_deg}, {"partial", f.partial},
             {"smr_radius_m", kSmrRadiusMetres}, {"partial_kept", f.partial_kept}, {"occluders", occluders}};
  }
  return {{"model", f.model.empty() ? json(nullptr) : json(f.model)},
          {"line_of_sight", sight},
          {"checked", f.checked},
          {"collision_geoms", f.collision_geoms},
          {"floor", f.floor ? json(*f.floor) : json(nullptr)},
          {"note", f.note.empty() ? json(nullptr) : json(f.note)},
          {"ranges", ranges},
          {"drawn", f.drawn},
          {"kept", f.kept},
          {"rejected", {{"total", f.rejected()}, {"self_collision", f.self_collision}, {"world", f.world},
                        {"floor", f.floor_contact}, {"occluded", f.occluded}, {"angle", f.angle}}},
          {"pairs", pairs},
          {"seconds", f.seconds}};
}

}  // namespace

PlanReport makePlanReport(const io::RobotFile& file, const PlanRequest& request, const ArgumentSpelling& spelling) {
  PlanReport r;
  r.file = file;
  const PoeModel model = r.file.poeModel();
  r.measure = request.measure;
  r.criterion = request.criterion;
  r.candidates = request.candidates;
  r.seed = request.seed;
  PlanOptions options;
  options.measure = r.measure;
  options.free_pitch = request.free_pitch;
  options.criterion = r.criterion;
  if (r.measure == Measure::Targets) {
    if (r.file.targets.empty()) {
      throw UsageError(r.file.path, spelling.setting("measure", "targets") +
                                        " needs a `targets:` list in the robot file (docs/file_formats.md)");
    }
    options.targets = r.file.targets;
  } else if (request.feasibility.tracker) {
    throw UsageError(spelling.name("tracker"), "needs target measurements (" + spelling.setting("measure", "targets") +
                                                   ": the robot file's targets are the SMRs the tracker sees)");
  }
  if (request.poses > request.candidates) {
    throw UsageError(spelling.name("poses"), std::to_string(request.poses) + " poses cannot be chosen from " +
                                                 std::to_string(request.candidates) + " candidates (" +
                                                 spelling.name("candidates") + ")");
  }
  checkStatedNoise(request.noise_position, request.noise_rotation, spelling);
  if (request.noise_rotation && r.measure != Measure::Pose) {
    throw UsageError(spelling.name("noise_rotation"),
                     std::string(measurementsText(r.measure)) + " have no rotation to weigh");
  }
  // the candidates' blocks: rows x columns numbers each
  ErrorModelSpec spec;
  spec.free_pitch = request.free_pitch;
  spec.targets = options.targets;
  const double columns = ErrorModel(model, spec).size();
  const double rows = r.measure == Measure::Pose ? 6.0 : 3.0 * std::max<size_t>(1, options.targets.size());
  if (const auto problem = planSizeProblem(request.candidates, request.poses, rows, columns, options.max_exchange_work,
                                           options.targets.size() > 1)) {
    throw UsageError(problem->robot ? r.file.path : spelling.name("candidates"), problem->text);
  }

  options.validate();

  // candidates: the sampling convention (commands/sampling.hpp), stream `seed`, samples 0..M-1
  std::vector<std::string> range_source;
  const auto ranges = request.feasibility.any() ? narrowedRanges(r.file, request.feasibility, spelling, &range_source)
                                                : samplingRanges(model);
  std::vector<VecX> candidates(static_cast<size_t>(request.candidates), VecX(model.dof()));
  for (int i = 0; i < request.candidates; ++i) {
    randomSample(static_cast<unsigned long long>(request.seed), static_cast<unsigned long long>(i), ranges,
                 candidates[static_cast<size_t>(i)]);
  }
  std::vector<int> drawn_index;  // of each kept candidate (feasibility only)
  if (request.feasibility.any()) {
    r.feasibility.emplace();
    r.feasibility->ranges = ranges;
    r.feasibility->range_source = range_source;
    drawn_index = feasibleCandidates(r.file, candidates, request.feasibility, spelling, *r.feasibility);
    checkEnoughFeasible(*r.feasibility, request.poses, spelling);
    std::vector<VecX> kept;
    for (const int i : drawn_index) kept.push_back(candidates[static_cast<size_t>(i)]);
    candidates = std::move(kept);
    // the information of each kept candidate: the rows of the targets it sees (all of them without --partial)
    if (r.feasibility->partial) options.measured = r.feasibility->measured;
  }
  auto clock = [] { return std::chrono::steady_clock::now(); };
  auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  auto t0 = clock();
  const PlanCandidates c = planCandidates(model, candidates, options);
  r.plan = planPoses(c, request.poses, options);
  for (const Parameter& x : c.parameters) r.parameters.push_back(x.name);
  auto t1 = clock();
  r.seconds_plan = seconds(t0, t1);
  std::vector<double> log_det, o1;
  for (const auto& set :
       randomPoseSets(c.count(), request.poses, kPlanRandomSets, static_cast<unsigned long long>(request.seed))) {
    const PlanValue v = evaluatePlan(c, set);
    log_det.push_back(v.log_det);
    o1.push_back(v.o1);
  }
  r.random_log_det = spread(log_det);
  r.random_o1 = spread(o1);
  auto t2 = clock();
  r.seconds_random = seconds(t1, t2);
  for (const int i : r.plan.indices) {
    r.q.push_back(candidates[static_cast<size_t>(i)]);
    if (r.feasibility && r.feasibility->tracker) r.measured.push_back(r.feasibility->measured[static_cast<size_t>(i)]);
  }
  if (r.feasibility) {
    for (int& i : r.plan.indices) i = drawn_index[static_cast<size_t>(i)];  // the drawn sample's index
  }

  // the noise of the standard deviations: as stated (the other derived as calibrate does), else the default
  std::optional<double> sigma_position = request.noise_position, sigma_rotation = request.noise_rotation;
  if (!sigma_position && !sigma_rotation) {
    sigma_position = kDefaultRelativeNoise * model.lengthScale();
    if (r.measure == Measure::Pose) sigma_rotation = kDefaultRelativeNoise;
    // the CLI's option names in both front ends: the text is part of the JSON the Python tests compare
    r.noise_source = "default: 1e-5 L" + std::string(r.measure == Measure::Pose ? " and 1e-5 rad" : "") +
                     "; state --noise-position/--noise-rotation";
  } else if (r.measure != Measure::Pose || (sigma_position && sigma_rotation)) {
    r.noise_source = "stated";
  } else {
    r.noise_source = sigma_position ? "position stated, rotation derived: position / L"
                                    : "rotation stated, position derived: rotation x L";
  }
  r.expected = expectedUncertainty(model, r.q, options, sigma_position, sigma_rotation,
                                   options.measured.empty() ? std::vector<std::vector<bool>>{} : r.measured);
  r.seconds_uncertainty = seconds(t2, clock());
  return r;
}

std::vector<std::string> measuredTargetNames(const io::RobotFile& file, const std::vector<bool>& seen) {
  std::vector<std::string> names;
  for (size_t t = 0; t < seen.size() && t < file.targets.size(); ++t) {
    if (seen[t]) names.push_back(file.targets[t].name);
  }
  return names;
}

json planJson(const PlanReport& r, const std::string& out_path) {
  const PlanResult& p = r.plan;
  const std::vector<std::string>& names = r.parameters;
  json undetermined = json::array();
  for (const auto& direction : p.rank.undetermined) {
    json terms = json::array();
    for (const auto& [column, coefficient] : direction) {
      terms.push_back({{"parameter", names[static_cast<size_t>(column)]}, {"coefficient", coefficient}});
    }
    undetermined.push_back(terms);
  }
  auto value = [&](const PlanValue& v) {
    return json{{"log_det", io::finiteOrNull(v.log_det)}, {"O1", v.o1}, {"rank", v.rank},
                {"criterion", io::finiteOrNull(v.criterion(r.criterion))}};
  };
  auto spreadJson = [](const Spread& s) { return json{{"median", io::finiteOrNull(s.median)}, {"best", io::finiteOrNull(s.best)}}; };
  const CalibrationResult& c = r.expected->calibration;
  json parameters = json::array();
  for (size_t k = 0; k < names.size(); ++k) {
    const Parameter& x = c.error_model.parameters()[k];
    parameters.push_back({{"name", x.name}, {"unit", x.unit}, {"sd", io::finiteOrNull(c.standard_deviation[static_cast<Eigen::Index>(k)])}});
  }
  json q = json::array();
  for (const VecX& x : r.q) q.push_back(io::toVector(x));
  json measured = nullptr;  // per planned pose, the names of the targets it measures (with a tracker)
  if (!r.measured.empty()) {
    measured = json::array();
    for (const std::vector<bool>& seen : r.measured) measured.push_back(measuredTargetNames(r.file, seen));
  }
  json o;
  o["name"] = io::robotLabel(r.file);
  o["source"] = r.file.path;
  o["length_unit"] = r.file.length_unit.empty() ? json(nullptr) : json(r.file.length_unit);
  o["measure"] = measureName(r.measure);
  o["free_pitch"] = c.error_model.freePitch();
  if (r.measure == Measure::Targets) {
    json targets = json::array();
    for (const Target& t : r.file.targets) targets.push_back({{"name", t.name}, {"point", io::toVector(*t.point_tool)}});
    o["targets"] = targets;
  }
  o["criterion"] = planCriterionName(r.criterion);
  o["poses"] = static_cast<int>(p.indices.size());
  o["candidates"] = r.candidates;
  o["seed"] = r.seed;
  o["length_scale"] = r.file.poeModel().lengthScale();
  o["planned"] = value(p.value);
  o["greedy"] = value(p.start);
  o["swaps"] = p.swaps;
  o["passes"] = p.passes;
  o["exchange_work_limit"] = p.work_limit;
  o["random"] = {{"sets", kPlanRandomSets},
                 {"log_det", spreadJson(r.random_log_det)},
                 {"O1", spreadJson(r.random_o1)},
                 {"criterion", spreadJson(r.criterion == PlanCriterion::D ? r.random_log_det : r.random_o1)}};
  o["expected"] = p.expected.total();
  o["joints"] = {{"revolute", p.expected.revolute}, {"prismatic", p.expected.prismatic}, {"helical", p.expected.helical},
                 {"scales", p.expected.scales}, {"tool", p.expected.tool}};
  o["rank"] = p.rank.rank;
  o["candidate_rank"] = p.candidate_rank;
  o["parameters"] = names;
  o["singular_values"] = io::toVector(p.rank.singular_values);
  o["condition"] = io::finiteOrNull(p.rank.condition);
  o["undetermined"] = undetermined;
  o["indices"] = p.indices;
  o["q"] = q;
  o["measured"] = measured;
  o["noise"] = {{"position", c.sigma_position},
                {"rotation", r.measure == Measure::Pose ? json(c.sigma_rotation) : json(nullptr)},
                {"source", r.noise_source}};
  o["standard_deviations"] = {{"parameters", parameters}, {"dh", dhUncertaintyJson(r.expected->dh)}};
  if (r.feasibility) o["feasibility"] = feasibilityJson(*r.feasibility);
  o["out"] = out_path.empty() ? json(nullptr) : json(out_path);
  o["seconds"] = {{"plan", r.seconds_plan}, {"random", r.seconds_random}, {"uncertainty", r.seconds_uncertainty}};
  return o;
}

}  // namespace lowpair::commands
