// plan: choose the poses of a calibration (docs/plan.md).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
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


void printPlan(std::ostream& out, const PlanReport& r, const std::string& out_path) {
  const PlanResult& p = r.plan;
  const CalibrationResult& c = r.expected->calibration;
  const std::string u = lengthUnit(r.file);
  const std::vector<std::string>& names = r.parameters;
  out << "plan of " << p.indices.size() << " poses (" << measurementsText(r.measure)
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
  row("random sets of " + std::to_string(p.indices.size()) + ", median (" + std::to_string(kPlanRandomSets) + ")",
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
  if (!out_path.empty()) out << r.q.size() << " joint vectors written to " << out_path << "\n";
  out << "time: plan " << fixed(r.seconds_plan, 3) << " s (" << p.swaps << " exchange(s) in " << p.passes
      << " pass(es)" << (p.work_limit ? ", ended at the work limit: PlanOptions::max_exchange_work, docs/plan.md" : "")
      << "), random sets " << fixed(r.seconds_random, 3) << " s, standard deviations "
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
    const PlanReport r = makePlanReport(loadRobot(o->robot, cliSpelling()), request, cliSpelling());
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
