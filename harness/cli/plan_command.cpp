// plan: choose the poses of a calibration (docs/plan.md).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "commands/calibration_output.hpp"
#include "commands/plan_report.hpp"
#include "commands/sampling.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::commands;

namespace {

struct Options {
  RobotSource robot;
  int poses = 0, candidates = 5000;
  std::string measure = "pose", criterion = "D", out;
  long long seed = 1;
  bool free_pitch = false, as_json = false;
  std::optional<double> noise_position, noise_rotation;
  // feasible plans (docs/plan.md "Feasible plans")
  std::string model;
  bool collisions = false;
  std::optional<double> floor;
  std::vector<std::string> ranges;
  double range_margin = 0.0;
  // line of sight (docs/plan.md "Line of sight")
  std::string tracker;
  double smr_angle = kDefaultSmrAngleDeg;
  bool partial = false;
};

std::string lengthUnit(const RobotFile& file) { return file.length_unit.empty() ? "length" : file.length_unit; }

// log det to 4 decimals, "-inf" for a set that does not determine every direction
std::string logDetText(double x) { return std::isfinite(x) ? fixed(x, 4) : "-inf"; }

std::string significant(double x, int digits) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

void appendNumber17(std::string& out, double x) {
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
                   " (best of " + std::to_string(kPlanRandomSets) + " random sets: log det " +
                   logDetText(r.random_log_det.best) + "); rank " + std::to_string(r.plan.rank.rank) + " of " +
                   std::to_string(r.plan.expected.total()));
  if (r.feasibility && !r.feasibility->model.empty()) {
    const FeasibilityReport& f = *r.feasibility;
    s += commentLine("feasible: " + std::to_string(f.kept) + " of " + std::to_string(f.drawn) + " candidates " +
                     (f.checked ? "free of contacts in " + f.model : "kept, nothing checked in " + f.model));
    if (f.tracker) {
      s += commentLine("line of sight from the tracker at (" + significant((*f.tracker)[0], 17) + ", " +
                       significant((*f.tracker)[1], 17) + ", " + significant((*f.tracker)[2], 17) + "): " +
                       (f.partial ? "--partial, each pose measures the targets plan --json lists under measured"
                                  : "every pose sees every target"));
    }
  }
  s += commentLine("q: the robot file's joint variables (rad for revolute and helical joints, " + lengthUnit(r.file) +
                   " for prismatic ones)");
  for (int i = 0; i < n; ++i) s += (i ? ",q" : "q") + std::to_string(i + 1);
  s += "\n";
  for (const VecX& q : r.q) {
    for (int i = 0; i < n; ++i) {
      if (i) s += ",";
      appendNumber17(s, q[i]);
    }
    s += "\n";
  }
  return s;
}

// The ranges sampled, what the collision check rejected and kept (plan with --range, --model, ...).
void printFeasibility(std::ostream& out, const PlanReport& r) {
  const FeasibilityReport& f = *r.feasibility;
  const std::string u = lengthUnit(r.file);
  out << "sampled ranges (rad for revolute/helical joints, " << u << " for prismatic):";
  for (size_t i = 0; i < f.ranges.size(); ++i) {
    out << (i ? "," : "") << " q" << i + 1 << " [" << significant(f.ranges[i][0], 6) << ", "
        << significant(f.ranges[i][1], 6) << "]";
    if (f.range_source[i] != "file" && f.range_source[i] != "default") out << " (" << f.range_source[i] << ")";
  }
  out << "\n";
  if (!f.model.empty()) {
    out << "collision check in " << f.model << ": ";
    if (!f.checked) {
      out << "nothing checked (no geom can collide)\n";
    } else {
      out << f.collision_geoms << " collision geom(s)";
      if (f.floor) out << ", floor at z = " << significant(*f.floor, 6) << (r.file.length_unit.empty() ? "" : " " + u);
      out << " (" << fixed(f.seconds, 3) << " s)\n";
    }
  }
  if (f.tracker) {
    out << "line of sight from the tracker at (" << significant((*f.tracker)[0], 6) << ", " << significant((*f.tracker)[1], 6)
        << ", " << significant((*f.tracker)[2], 6) << ")" << (r.file.length_unit.empty() ? "" : " " + u)
        << ": rays stop " << significant(kSmrRadiusMetres * 1000.0, 4) << " mm before each SMR's centre, SMR angle "
        << significant(f.smr_angle_deg, 6) << " deg"
        << (f.partial ? "; --partial: a pose measures the targets it sees (at least one)" : "") << "\n";
  }
  out << "candidates: " << f.drawn << " drawn, " << f.rejected() << " rejected (self-collision " << f.self_collision
      << ", world geometry " << f.world << ", floor " << f.floor_contact;
  if (f.tracker) out << ", occluded " << f.occluded << ", angle " << f.angle;
  out << "), " << f.kept << " kept";
  if (f.partial) out << " (" << f.partial_kept << " of them see only some targets)";
  out << "\n";
  if (!f.occluders.empty()) {
    out << "most frequent occluders:";
    for (size_t k = 0; k < f.occluders.size() && k < 3; ++k) {
      out << (k ? "," : "") << " " << f.occluders[k].geom << " in " << f.occluders[k].candidates;
    }
    out << " candidates\n";
  }
  if (!f.pairs.empty()) {
    out << "most frequent contacts:";
    for (size_t k = 0; k < f.pairs.size() && k < 3; ++k) {
      out << (k ? "," : "") << " '" << f.pairs[k].body1 << "'-'" << f.pairs[k].body2 << "' in " << f.pairs[k].candidates;
    }
    out << " candidates\n";
  }
}

void printPlan(std::ostream& out, const PlanReport& r, const std::string& out_path) {
  const PlanResult& p = r.plan;
  const CalibrationResult& c = r.expected->calibration;
  const std::string u = lengthUnit(r.file);
  const std::vector<std::string>& names = r.parameters;
  out << "plan of " << p.indices.size() << " poses (" << measurementsText(r.measure)
      << (r.measure == Measure::Targets ? ", " + std::to_string(r.file.targets.size()) + " targets each" : std::string())
      << ") of " << robotLabel(r.file)
      << " (" << r.file.path << ") from " << r.candidates << " random candidates (seed " << r.seed << ")\n";
  if (r.feasibility) printFeasibility(out, r);
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
  row("random sets of " + std::to_string(p.indices.size()) + ", median (" + std::to_string(kPlanRandomSets) + ")",
      r.random_log_det.median, r.random_o1.median);
  row("random sets, best", r.random_log_det.best, r.random_o1.best);
  if (r.feasibility) out << "(the random sets are drawn from the " << r.feasibility->kept << " kept candidates)\n";
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
    if (!r.measured.empty()) {
      out << "   measures:";
      for (const std::string& name : measuredTargetNames(r.file, r.measured[k])) out << " " << name;
    }
    out << "\n";
  }
  if (!out_path.empty()) out << r.q.size() << " joint vectors written to " << out_path << "\n";
  out << "time: plan " << fixed(r.seconds_plan, 3) << " s (" << p.swaps << " exchange(s) in " << p.passes
      << " pass(es)" << (p.work_limit ? ", ended at the work limit: PlanOptions::max_exchange_work, docs/plan.md" : "")
      << "), random sets " << fixed(r.seconds_random, 3) << " s, standard deviations "
      << fixed(r.seconds_uncertainty, 3) << " s\n";
}

// --tracker X,Y,Z: three finite numbers.
Vec3 parseTracker(const std::string& text) {
  std::vector<double> v;
  size_t begin = 0;
  while (v.size() < 4) {
    const size_t comma = text.find(',', begin);
    const std::string part = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    double x = 0.0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), x);
    if (part.empty() || ec != std::errc() || end != part.data() + part.size() || !std::isfinite(x)) {
      throw UsageError("--tracker", "expected X,Y,Z (three finite numbers, the base frame), got " + quotedFileText(text));
    }
    v.push_back(x);
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  if (v.size() != 3) {
    throw UsageError("--tracker", "expected X,Y,Z (three finite numbers, the base frame), got " + quotedFileText(text));
  }
  return Vec3(v[0], v[1], v[2]);
}

// The feasibility options as a request; the model's --tip/--base move from `robot` to it (--model).
FeasibilityRequest feasibilityRequest(const Options& o, RobotSource& robot) {
  FeasibilityRequest f;
  for (const std::string& text : o.ranges) f.ranges.push_back(parseRangeOverride(text, cliSpelling()));
  f.range_margin = o.range_margin;
  if (o.floor && !std::isfinite(*o.floor)) {  // (CLI11 reads 1e309 as inf; nan would reach MuJoCo's XML as 'nan')
    throw UsageError("--floor", "must be a finite number, got " + significant(*o.floor, 6));
  }
  f.floor = o.floor;
  if (!o.tracker.empty()) f.tracker = parseTracker(o.tracker);
  f.smr_angle_deg = o.smr_angle;
  f.partial = o.partial;
  if (o.partial && !f.tracker) throw UsageError("--partial", "goes with --tracker X,Y,Z");
  const std::string ext = std::filesystem::path(robot.path).extension().string();
  const bool model_robot = ext == ".xml" || ext == ".urdf";
  if (!o.model.empty()) {
    if (model_robot) throw UsageError("--model", "goes with a robot file (.yaml); " + robot.path + " is a model: give --collisions");
    if (robot.tip.empty()) throw UsageError("--model", "--tip NAME is required with --model (the chain's tip)");
    f.model = o.model;
    f.tip = robot.tip;
    f.base = robot.base;
    robot.tip.clear();
    robot.base.clear();
  } else if (o.collisions || o.floor || f.tracker) {
    if (!model_robot) {
      throw UsageError(o.collisions ? "--collisions" : o.floor ? "--floor" : "--tracker",
                       "needs a model: the robot as MJCF/URDF, or --model FILE --tip NAME beside a robot file");
    }
    f.model = robot.path;
    f.tip = robot.tip;
    f.base = robot.base;
  }
  return f;
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
                  "random candidate joint vectors, M (default " + std::to_string(kDefaultPlanCandidates) + ", at most " +
                      std::to_string(kMaxPlanCandidates) + ")")
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
  sub->add_option("--model", o->model, "keep only candidates free of contacts in this MJCF/URDF (its chain: --tip NAME "
                                       "[--base NAME]) beside a robot file");
  sub->add_flag("--collisions", o->collisions, "keep only candidates free of contacts in the robot's own model "
                                               "(ROBOT an MJCF/URDF)");
  sub->add_option("--floor", o->floor, "a floor plane z = Z of the base frame (robot file's length unit) the robot "
                                       "must stay above (checks collisions)");
  sub->add_option("--range", o->ranges, "J:LO:HI: sample joint J (index 1..n or name) in [LO, HI] (robot file's "
                                        "units; inside the file's range); repeatable")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sub->add_option("--range-margin", o->range_margin, "shrink every joint's range by X at both ends (robot file's units)");
  sub->add_option("--tracker", o->tracker, "X,Y,Z: a laser tracker there (base frame, robot file's length unit) must "
                                           "see every measured SMR (--measure targets; checks the model's rays)");
  sub->add_option("--smr-angle", o->smr_angle, "an SMR's acceptance half-angle about its normal (degrees, default 30; "
                                               "targets without a normal are not angle-checked)");
  sub->add_flag("--partial", o->partial, "with --tracker: keep a pose that sees some targets, measuring only those");
  commands.emplace_back(sub, [o] {
    PlanRequest request;
    request.measure = parseMeasure(o->measure, cliSpelling());
    request.criterion = o->criterion == "O1" ? PlanCriterion::O1 : PlanCriterion::D;
    request.poses = o->poses;
    request.candidates = o->candidates;
    request.seed = o->seed;
    request.free_pitch = o->free_pitch;
    request.noise_position = o->noise_position;
    request.noise_rotation = o->noise_rotation;
    RobotSource robot = o->robot;
    request.feasibility = feasibilityRequest(*o, robot);
    std::optional<PlanReport> report;
    try {
      report.emplace(makePlanReport(loadRobot(robot, cliSpelling()), request, cliSpelling()));
    } catch (const InfeasiblePlan& e) {
      std::cerr << "error: " << e.what() << "\n";
      return 1;
    }
    const PlanReport& r = *report;
    if (r.feasibility && !r.feasibility->note.empty()) std::cerr << "note: " << r.feasibility->note << "\n";
    if (!o->out.empty()) writeFileAtomically(o->out, qFileText(r));
    if (o->as_json) {
      std::cout << jsonText(planJson(r, o->out)) << "\n";
    } else {
      printPlan(std::cout, r, o->out);
    }
    return 0;
  });
}

}  // namespace lowpair::cli
