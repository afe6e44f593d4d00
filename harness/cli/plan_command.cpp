// plan: choose the poses of a calibration (docs/plan.md).
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli/commands.hpp"
#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/plan.hpp"
#include "lowpair/tolerances.hpp"
#include "validation/calibration_output.hpp"
#include "validation/sampling.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::validation;

using nlohmann::json;

namespace {

/// Upper bounds of `plan`: the poses chosen, the candidates, and the numbers of their blocks (candidates x
/// rows x parameters): the blocks are held about four times (scaled, the SVD's copy, in the determined
/// directions, the search's working copy), so 1e7 numbers is about 320 MB.
constexpr int kMaxPlanPoses = 1000;
constexpr int kMaxPlanCandidates = 100000;
constexpr double kMaxPlanEntries = 1e7;
/// The random sets of N the plan is compared with.
constexpr int kRandomSets = 100;
/// The noise assumed when none is stated: position 1e-5 L per coordinate, rotation 1e-5 rad per axis.
constexpr double kDefaultRelativeNoise = 1e-5;

constexpr double kDeg = 180.0 / M_PI;

struct Options {
  RobotSource robot;
  int poses = 0, candidates = 5000;
  std::string measure = "pose", criterion = "D", out;
  long long seed = 1;
  bool free_pitch = false, as_json = false;
  std::optional<double> noise_position, noise_rotation;
};

// The value and its spread over the random sets.
struct Spread {
  double median = 0.0, best = 0.0;
};

Spread spread(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const size_t n = x.size();
  return {n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]), x.back()};
}

// Everything `plan` prints, computed once (the renderers below only format it).
struct PlanReport {
  RobotFile file;
  Measure measure = Measure::Pose;
  PlanCriterion criterion = PlanCriterion::D;
  int candidates = 0;
  long long seed = 0;
  PlanResult plan;
  std::vector<std::string> parameters;  // the columns' names
  std::vector<VecX> q;  // the planned joint vectors, in index order
  Spread random_log_det, random_o1;
  std::optional<ExpectedUncertainty> expected;
  std::string noise_source;  // stated, derived or the default, in words
  std::string out;
  double seconds_plan = 0.0, seconds_random = 0.0, seconds_uncertainty = 0.0;
};

std::string lengthUnit(const RobotFile& file) { return file.length_unit.empty() ? "length" : file.length_unit; }

// log det to 4 decimals, "-inf" for a set that does not determine every direction
std::string logDetText(double x) { return std::isfinite(x) ? fixed(x, 4) : "-inf"; }

std::string significant(double x, int digits) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

json finiteOrNull(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

void appendNumber(std::string& out, double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 17);  // %.17g
  out.append(buffer, result.ptr);
}

// One `#` line (a control character in a robot's name or path becomes a space: the line stays one line).
std::string commentLine(const std::string& text) {
  std::string line = "# ";
  for (const char ch : text) line += static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f ? ' ' : ch;
  return line + "\n";
}

// The --out CSV: `#` lines saying what it is, the header q1..qn, one planned joint vector per line.
std::string qFileText(const PlanReport& r) {
  const int n = r.q.empty() ? 0 : static_cast<int>(r.q.front().size());
  std::string s = commentLine("planned calibration poses (lowpair plan): " + std::to_string(r.q.size()) + " of " +
                              std::to_string(r.candidates) + " random candidates, seed " + std::to_string(r.seed));
  s += commentLine("robot: " + robotLabel(r.file) + " (" + r.file.path + ")");
  s += commentLine("measure: " + std::string(measureName(r.measure)) + ", criterion " + planCriterionName(r.criterion) +
                   ": log det " + logDetText(r.plan.value.log_det) + ", O1 " + significant(r.plan.value.o1, 6) +
                   " (best of " + std::to_string(kRandomSets) + " random sets: log det " +
                   logDetText(r.random_log_det.best) + "); rank " + std::to_string(r.plan.rank.rank) + " of " +
                   std::to_string(r.plan.expected.total()));
  s += commentLine("q: the robot file's joint variables (rad for revolute and helical joints, " + lengthUnit(r.file) +
                   " for prismatic ones)");
  for (int i = 0; i < n; ++i) s += (i ? ",q" : "q") + std::to_string(i + 1);
  s += "\n";
  for (const VecX& q : r.q) {
    for (int i = 0; i < n; ++i) {
      if (i) s += ",";
      appendNumber(s, q[i]);
    }
    s += "\n";
  }
  return s;
}


json planJson(const PlanReport& r) {
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
    return json{{"log_det", finiteOrNull(v.log_det)}, {"O1", v.o1}, {"rank", v.rank},
                {"criterion", finiteOrNull(v.criterion(r.criterion))}};
  };
  auto spreadJson = [](const Spread& s) { return json{{"median", finiteOrNull(s.median)}, {"best", finiteOrNull(s.best)}}; };
  const CalibrationResult& c = r.expected->calibration;
  json parameters = json::array();
  for (size_t k = 0; k < names.size(); ++k) {
    const Parameter& x = c.error_model.parameters()[k];
    parameters.push_back({{"name", x.name}, {"unit", x.unit}, {"sd", finiteOrNull(c.standard_deviation[static_cast<Eigen::Index>(k)])}});
  }
  json q = json::array();
  for (const VecX& x : r.q) q.push_back(toVector(x));
  json o;
  o["name"] = robotLabel(r.file);
  o["source"] = r.file.path;
  o["length_unit"] = r.file.length_unit.empty() ? json(nullptr) : json(r.file.length_unit);
  o["measure"] = measureName(r.measure);
  o["free_pitch"] = c.error_model.freePitch();
  if (r.measure == Measure::Targets) {
    json targets = json::array();
    for (const Target& t : r.file.targets) targets.push_back({{"name", t.name}, {"point", toVector(*t.point_tool)}});
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
  o["random"] = {{"sets", kRandomSets},
                 {"log_det", spreadJson(r.random_log_det)},
                 {"O1", spreadJson(r.random_o1)},
                 {"criterion", spreadJson(r.criterion == PlanCriterion::D ? r.random_log_det : r.random_o1)}};
  o["expected"] = p.expected.total();
  o["joints"] = {{"revolute", p.expected.revolute}, {"prismatic", p.expected.prismatic}, {"helical", p.expected.helical},
                 {"scales", p.expected.scales}, {"tool", p.expected.tool}};
  o["rank"] = p.rank.rank;
  o["candidate_rank"] = p.candidate_rank;
  o["parameters"] = names;
  o["singular_values"] = toVector(p.rank.singular_values);
  o["condition"] = finiteOrNull(p.rank.condition);
  o["undetermined"] = undetermined;
  o["indices"] = p.indices;
  o["q"] = q;
  o["noise"] = {{"position", c.sigma_position},
                {"rotation", r.measure == Measure::Pose ? json(c.sigma_rotation) : json(nullptr)},
                {"source", r.noise_source}};
  o["standard_deviations"] = {{"parameters", parameters}, {"dh", dhUncertaintyJson(r.expected->dh)}};
  o["out"] = r.out.empty() ? json(nullptr) : json(r.out);
  o["seconds"] = {{"plan", r.seconds_plan}, {"random", r.seconds_random}, {"uncertainty", r.seconds_uncertainty}};
  return o;
}


void printPlan(std::ostream& out, const PlanReport& r) {
  const PlanResult& p = r.plan;
  const CalibrationResult& c = r.expected->calibration;
  const std::string u = lengthUnit(r.file);
  const std::vector<std::string>& names = r.parameters;
  out << "plan of " << p.indices.size() << " poses (" << measureName(r.measure) << " measurements"
      << (r.measure == Measure::Targets ? ", " + std::to_string(r.file.targets.size()) + " targets each" : std::string())
      << ") of " << robotLabel(r.file)
      << " (" << r.file.path << ") from " << r.candidates << " random candidates (seed " << r.seed << ")\n";
  out << "criterion " << planCriterionName(r.criterion)
      << (r.criterion == PlanCriterion::D ? " (log det of the information)"
                                          : " (Sun & Hollerbach: geometric mean of the singular values / sqrt(N))")
      << "; rows: position / L = " << significant(r.file.poeModel().lengthScale(), 6) << " " << u
      << (r.measure == Measure::Pose ? ", rotation rad" : "") << "; columns over the candidates' RMS per pose\n";
  char line[200];
  std::snprintf(line, sizeof line, "%-34s %14s %12s\n", "", "log det", "O1");
  out << line;
  auto row = [&](const std::string& label, double log_det, double o1) {
    std::snprintf(line, sizeof line, "%-34s %14s %12s\n", label.c_str(), logDetText(log_det).c_str(), significant(o1, 4).c_str());
    out << line;
  };
  row("planned", p.value.log_det, p.value.o1);
  row("greedy, before " + std::to_string(p.swaps) + " exchange(s)", p.start.log_det, p.start.o1);
  row("random sets of " + std::to_string(p.indices.size()) + ", median (" + std::to_string(kRandomSets) + ")",
      r.random_log_det.median, r.random_o1.median);
  row("random sets, best", r.random_log_det.best, r.random_o1.best);
  if (std::isfinite(p.value.log_det) && std::isfinite(r.random_log_det.median)) {
    out << "the planned information's determinant is " << significant(std::exp(p.value.log_det - r.random_log_det.median), 3)
        << " times the median random set's (O1 " << significant(p.value.o1 / r.random_o1.median, 3) << " times)\n";
  }
  out << "parameters: rank " << p.rank.rank << " of " << p.expected.total() << " (5h + 4r + 2t + n + " << p.expected.tool
      << " = 5x" << p.expected.helical << " + 4x" << p.expected.revolute << " + 2x" << p.expected.prismatic << " + "
      << p.expected.scales << " + " << p.expected.tool << " = " << p.expected.total()
      << (c.error_model.freePitch() ? ", free pitch" : "") << "); the candidates together determine " << p.candidate_rank
      << " of " << names.size() << " columns\n";
  if (p.rank.undetermined.empty()) {
    out << "every parameter is determined\n";
  } else {
    const int for_want_of_poses = p.candidate_rank - p.rank.rank;
    const int never = static_cast<int>(names.size()) - p.candidate_rank;
    out << p.rank.undetermined.size() << " direction(s) not determined (";
    if (for_want_of_poses > 0) out << for_want_of_poses << " for want of poses: more poses determine them";
    if (for_want_of_poses > 0 && never > 0) out << "; ";
    if (never > 0) out << never << " that no candidate determines: the measure does not see them";
    out << "):\n";
    for (size_t k = 0; k < p.rank.undetermined.size(); ++k) {
      out << "  " << k + 1 << ": " << directionText(p.rank.undetermined[k], names) << "\n";
    }
  }

  out << "\nexpected standard deviations after calibrating on the plan, noise " << significant(c.sigma_position, 3) << " "
      << u << " per coordinate";
  if (r.measure == Measure::Pose) out << ", " << significant(c.sigma_rotation, 3) << " rad per axis";
  out << " (" << r.noise_source << ")\nD-H table of the nominal:\n";
  printDhWithDeviations(out, r.file, r.expected->dh, "its expected standard deviations");
  out << "(standard deviations: the parameter covariance of a calibration on these poses at this noise, propagated "
         "through the D-H conversion; they grow without bound as consecutive axes become parallel, docs/plan.md)\n";

  out << "\nplanned poses (q: rad for revolute/helical joints, " << u << " for prismatic):\n";
  for (size_t k = 0; k < r.q.size(); ++k) {
    out << "  " << p.indices[k] << ":";
    for (Eigen::Index i = 0; i < r.q[k].size(); ++i) out << " " << significant(r.q[k][i], 6);
    out << "\n";
  }
  if (!r.out.empty()) out << r.q.size() << " joint vectors written to " << r.out << "\n";
  out << "time: plan " << fixed(r.seconds_plan, 3) << " s (" << p.swaps << " exchange(s) in " << p.passes
      << " pass(es)), random sets " << fixed(r.seconds_random, 3) << " s, standard deviations "
      << fixed(r.seconds_uncertainty, 3) << " s\n";
}

}  // namespace

void addPlanCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<Options>();
  auto* sub = app.add_subcommand("plan", "choose N calibration poses of M random candidates (D-optimal, greedy + "
                                         "exchange); expected D-H standard deviations");
  addRobotArgument(*sub, o->robot);
  sub->add_option("--poses", o->poses, "poses to choose, N (at most " + std::to_string(kMaxPlanPoses) + ")")
      ->required()
      ->check(CLI::Range(1, kMaxPlanPoses));
  sub->add_option("--candidates", o->candidates,
                  "random candidate joint vectors, M (default 5000, at most " + std::to_string(kMaxPlanCandidates) + ")")
      ->check(CLI::Range(1, kMaxPlanCandidates));
  sub->add_option("--measure", o->measure,
                  "pose (default) or position measurements of the tool, or targets (the robot file's targets: points)")
      ->check(CLI::IsMember({"pose", "position", "targets"}));
  sub->add_option("--criterion", o->criterion, "D (log det, default) or O1 (Sun & Hollerbach): the same plan, "
                                                "the number reported")
      ->check(CLI::IsMember({"D", "O1"}));
  sub->add_option("--seed", o->seed, "seed of the candidates and the random sets (default 1)")->check(CLI::Range(0LL, kMaxSeed));
  sub->add_option("--noise-position", o->noise_position,
                  "measurement noise per coordinate (length) for the standard deviations (default 1e-5 L)");
  sub->add_option("--noise-rotation", o->noise_rotation, "measurement noise per axis (rad; default 1e-5)");
  sub->add_flag("--free-pitch", o->free_pitch, "give revolute joints a pitch parameter");
  sub->add_option("--out", o->out, "write the planned joint vectors (CSV q1..qn; lowpair fk/simulate --q-file)");
  sub->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(sub, [o] {
    PlanReport r;
    r.file = loadRobot(o->robot);
    const PoeModel model = r.file.poeModel();
    r.measure = o->measure == "position" ? Measure::Position : o->measure == "targets" ? Measure::Targets : Measure::Pose;
    r.criterion = o->criterion == "O1" ? PlanCriterion::O1 : PlanCriterion::D;
    r.candidates = o->candidates;
    r.seed = o->seed;
    r.out = o->out;
    PlanOptions options;
    options.measure = r.measure;
    options.free_pitch = o->free_pitch;
    options.criterion = r.criterion;
    if (r.measure == Measure::Targets) {
      if (r.file.targets.empty()) {
        throw UsageError(r.file.path, "--measure targets needs a `targets:` list in the robot file (docs/file_formats.md)");
      }
      for (const Target& t : r.file.targets) {
        options.targets.push_back(*t.point_tool);
        options.target_names.push_back(t.name);
      }
    }
    if (o->poses > o->candidates) {
      throw UsageError("--poses", std::to_string(o->poses) + " poses cannot be chosen from " +
                                      std::to_string(o->candidates) + " candidates (--candidates)");
    }
    for (const auto& [value, flag, limit] : {std::tuple{o->noise_position, "--noise-position", kMaxMagnitude},
                                             std::tuple{o->noise_rotation, "--noise-rotation", M_PI}}) {
      if (value && !(*value > 0.0 && *value <= limit)) {
        throw UsageError(flag, "must be a positive number up to " + shortest(limit) + ", got " + shortest(*value));
      }
    }
    if (o->noise_rotation && r.measure != Measure::Pose) {
      throw UsageError("--noise-rotation", std::string(measureName(r.measure)) + " measurements have no rotation to weigh");
    }
    // the candidates' blocks: rows x columns numbers each
    ErrorModelSpec spec;
    spec.free_pitch = o->free_pitch;
    spec.targets = options.targets;
    const double columns = ErrorModel(model, spec).size();
    const double rows = r.measure == Measure::Pose ? 6.0 : 3.0 * std::max<size_t>(1, options.targets.size());
    if (static_cast<double>(o->candidates) * rows * columns > kMaxPlanEntries) {
      const bool robot = rows * columns > kMaxPlanEntries;
      throw UsageError(robot ? r.file.path : std::string("--candidates"),
                       std::to_string(o->candidates) + " candidates of " + shortest(rows) + " rows and " +
                           shortest(columns) + " parameters exceed the identification size limit (" +
                           shortest(kMaxPlanEntries) + " numbers, held about four times): fewer candidates");
    }

    // candidates: the sampling convention (validation/sampling.hpp), stream `seed`, samples 0..M-1
    const auto ranges = samplingRanges(model);
    std::vector<VecX> candidates(static_cast<size_t>(o->candidates), VecX(model.dof()));
    for (int i = 0; i < o->candidates; ++i) {
      randomSample(static_cast<unsigned long long>(o->seed), static_cast<unsigned long long>(i), ranges,
                   candidates[static_cast<size_t>(i)]);
    }
    auto clock = [] { return std::chrono::steady_clock::now(); };
    auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    auto t0 = clock();
    const PlanCandidates c = planCandidates(model, candidates, options);
    r.plan = planPoses(c, o->poses, options);
    for (const Parameter& x : c.parameters) r.parameters.push_back(x.name);
    auto t1 = clock();
    r.seconds_plan = seconds(t0, t1);
    std::vector<double> log_det, o1;
    for (const auto& set : randomPoseSets(c.count(), o->poses, kRandomSets, static_cast<unsigned long long>(o->seed))) {
      const PlanValue v = evaluatePlan(c, set);
      log_det.push_back(v.log_det);
      o1.push_back(v.o1);
    }
    r.random_log_det = spread(log_det);
    r.random_o1 = spread(o1);
    auto t2 = clock();
    r.seconds_random = seconds(t1, t2);
    for (const int i : r.plan.indices) r.q.push_back(candidates[static_cast<size_t>(i)]);

    // the noise of the standard deviations: as stated (the other derived as calibrate does), else the default
    std::optional<double> sigma_position = o->noise_position, sigma_rotation = o->noise_rotation;
    if (!sigma_position && !sigma_rotation) {
      sigma_position = kDefaultRelativeNoise * model.lengthScale();
      if (r.measure == Measure::Pose) sigma_rotation = kDefaultRelativeNoise;
      r.noise_source = "default: 1e-5 L" + std::string(r.measure == Measure::Pose ? " and 1e-5 rad" : "") +
                       "; state --noise-position/--noise-rotation";
    } else if (r.measure != Measure::Pose || (sigma_position && sigma_rotation)) {
      r.noise_source = "stated";
    } else {
      r.noise_source = sigma_position ? "position stated, rotation derived: position / L"
                                      : "rotation stated, position derived: rotation x L";
    }
    r.expected = expectedUncertainty(model, r.q, options, sigma_position, sigma_rotation);
    r.seconds_uncertainty = seconds(t2, clock());

    if (!r.out.empty()) writeFileAtomically(r.out, qFileText(r));
    if (o->as_json) {
      std::cout << jsonText(planJson(r)) << "\n";
    } else {
      printPlan(std::cout, r);
    }
    return 0;
  });
}

}  // namespace lowpair::cli
