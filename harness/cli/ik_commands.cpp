// lowpair ik ROBOT --poses POSES.csv [--out Q.csv] [--json] [--seeds K] [--seed S] [--all]
// lowpair compensate CALIBRATED --nominal NOMINAL --q-file Q.csv [--out Q2.csv] [--json] [--measure pose|position]
//                   [--seeded]
// Inverse kinematics of target poses (or positions) and compensation of a calibrated robot (lowpair/ik.hpp,
// docs/ik.md), and the reader of their CSV inputs (also `fk --q-file`'s, convert_commands.cpp).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "commands/deflection_inputs.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_columns.hpp"
#include "io/joint_table.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/ik_closed_form.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"
#include "commands/ik_rows.hpp"
#include "commands/limits.hpp"
#include "commands/sampling.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::commands;

using nlohmann::json;

namespace {

// ---- solutions: the output CSV, the text summary, JSON ---------------------------------------------------------------

// The shortest text that reads back bit for bit.
void appendNumber(std::string& out, double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  out.append(buffer, result.ptr);
}

std::string unitName(const RobotFile& file) { return file.length_unit.empty() ? "length" : file.length_unit; }

// The CSV: comments, `q1..qn,residual,status`, one row per solution in input order, written as it is made.
void writeSolutionsCsv(std::ostream& out, const std::vector<std::string>& comments, int dof,
                       const std::vector<IkRow>& rows) {
  std::string text;
  for (const std::string& c : comments) text += "# " + c + "\n";
  for (int i = 0; i < dof; ++i) text += "q" + std::to_string(i + 1) + ",";
  text += "residual,status\n";
  out << text;
  for (const IkRow& row : rows) {
    const IkResult& s = row.result;
    text.clear();
    for (int i = 0; i < dof; ++i) {
      appendNumber(text, s.q[i]);
      text += ',';
    }
    appendNumber(text, s.position_error);
    text += ',';
    text += ikStatusName(s.status);
    text += '\n';
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
  }
}

struct Summary {
  std::array<long long, 5> count{};
  double worst_position = 0.0, worst_rotation = 0.0;  ///< over the ok rows
  long long worst_line = 0;
  bool all_ok() const { return count[1] + count[2] + count[3] + count[4] == 0; }
};

Summary summarize(const std::vector<IkRow>& rows) {
  Summary s;
  for (const IkRow& row : rows) {
    const IkResult& r = row.result;
    ++s.count[static_cast<size_t>(r.status)];
    if (r.status != IkStatus::Ok) continue;
    if (r.position_error >= s.worst_position) {
      s.worst_position = r.position_error;
      s.worst_line = row.line;
    }
    s.worst_rotation = std::max(s.worst_rotation, r.rotation_error);
  }
  return s;
}

std::string countsText(const Summary& s) {
  std::string text;
  for (size_t k = 0; k < s.count.size(); ++k) {
    if (s.count[k] == 0) continue;
    text += (text.empty() ? "" : ", ") + std::to_string(s.count[k]) + " " + ikStatusName(static_cast<IkStatus>(k));
  }
  return text;
}

std::string sci(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

// Comment lines every output states: what the rows are and how they came out.
std::vector<std::string> summaryComments(const Summary& s, const std::vector<IkRow>& rows, const RobotFile& file,
                                         bool pose) {
  std::vector<std::string> c{std::to_string(rows.size()) + (rows.size() == 1 ? " row: " : " rows: ") + countsText(s)};
  if (s.count[0] > 0) {
    c.push_back("worst residual of the ok rows: " + sci(s.worst_position) + " " + unitName(file) +
                (pose ? ", rotation " + sci(s.worst_rotation) + " rad" : std::string()));
  }
  return c;
}

// The text output: counts, worst residual, the failed rows with their reasons (the first kListedFailures).
void printSummary(std::ostream& out, const std::string& what, const Summary& s, const std::vector<IkRow>& rows,
                  const std::string& input, const RobotFile& file, bool pose) {
  constexpr size_t kListedFailures = 20;
  out << what << "\n";
  out << "  " << countsText(s) << "\n";
  if (s.count[0] > 0) {
    out << "  worst residual of the ok rows: " << sci(s.worst_position) << " " << unitName(file);
    if (pose) out << ", rotation " << sci(s.worst_rotation) << " rad";
    out << " (" << input << ":" << s.worst_line << ")\n";
  }
  size_t listed = 0, failed = 0;
  for (const IkRow& row : rows) {
    const IkResult& r = row.result;
    if (r.status == IkStatus::Ok) continue;
    if (listed++ < kListedFailures) {
      out << "  " << input << ":" << row.line << ": " << ikStatusName(r.status) << ": " << r.reason << " (lengths in "
          << unitName(file) << ")\n";
    }
    ++failed;
  }
  if (failed > kListedFailures) out << "  ... " << failed - kListedFailures << " more rows not ok (the status column lists every one)\n";
}

// Writes the CSV to --out (all or nothing) and the text or JSON to stdout, or the CSV to stdout. Every row is
// solved before: nothing is written on an error. The CSV and the JSON are written as they are made (10^6 rows:
// about 1 KB of JSON values each, never held together; docs/cli.md "Limits").
// @param head the JSON without its "rows": those are ikRowJson of `rows`
int emit(const std::string& out_path, bool as_json, const StreamWriter& csv, const json& head,
         const std::vector<IkRow>& rows, bool with_seed, const std::function<void(std::ostream&)>& text,
         const Summary& s) {
  if (!out_path.empty()) writeFileAtomically(out_path, csv);
  if (as_json) {
    writeJsonWithRows(std::cout, head, "rows", rows.size(), [&](size_t k) { return ikRowJson(rows[k], with_seed); });
    std::cout << "\n";
  } else if (!out_path.empty()) {
    text(std::cout);
    std::cout << "  written to " << out_path << "\n";
  } else {
    csv(std::cout);
  }
  return s.all_ok() ? 0 : 1;
}

// ---- ik ----------------------------------------------------------------------------------------------------------------

struct IkCommandOptions {
  RobotSource robot;
  std::string poses, out;
  bool as_json = false;
  bool all = false;  // --all: every solution per target
  int seeds = 8;
  long long seed = 1;
};

// ---- ik --all ------------------------------------------------------------------------------------------------------

// The CSV of --all: `line,solution,q1..qn,shoulder,elbow,wrist,singular,out_of_range,residual,rotation`, one row per
// solution (branch flags 0/1, empty without a closed form; out_of_range the 1-based joint, 0 for none).
void writeAllCsv(std::ostream& out, const std::vector<std::string>& comments, int dof, const std::vector<IkAllRow>& rows) {
  std::string text;
  for (const std::string& c : comments) text += "# " + c + "\n";
  text += "line,solution,";
  for (int i = 0; i < dof; ++i) text += "q" + std::to_string(i + 1) + ",";
  text += "shoulder,elbow,wrist,singular,out_of_range,residual,rotation\n";
  out << text;
  for (const IkAllRow& row : rows) {
    for (size_t k = 0; k < row.solutions.size(); ++k) {
      const IkAllSolution& x = row.solutions[k];
      text = std::to_string(row.line) + "," + std::to_string(k + 1) + ",";
      for (int i = 0; i < dof; ++i) {
        appendNumber(text, x.q[i]);
        text += ',';
      }
      text += x.branch ? std::string(x.branch->shoulder ? "1," : "0,") + (x.branch->elbow ? "1," : "0,") + (x.branch->wrist ? "1," : "0,")
                       : std::string(",,,");
      text += (x.singular ? "1," : "0,") + std::to_string(x.out_of_range + 1) + ",";
      appendNumber(text, x.position_error);
      text += ',';
      appendNumber(text, x.rotation_error);
      text += '\n';
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
    }
  }
}

int runIkAll(const IkCommandOptions& o, const RobotFile& file, const PoeModel& model, const JointTable& table,
             std::vector<std::string> notes) {
  if (!table.pose) {
    throw UsageError("--all", "needs pose targets (x,y,z,qw,qx,qy,qz): a position leaves a 6-joint arm infinitely many solutions");
  }
  if (table.dof > 0) notes.push_back("the q1..qn columns of " + o.poses + " are not used: --all needs no seeds");
  const int n = model.dof();
  IkOptions options;
  const ClosedFormStructure structure = closedFormStructure(model);
  const bool closed = structure.kind != ClosedFormKind::None;
  // without a closed form every seed of every row is tried: the work bound counts them all (limits.hpp)
  if (const auto problem = ikWorkProblem(table.rows(), closed ? 1 : o.seeds, n, !closed)) throw UsageError("--seeds", *problem);
  std::optional<ClosedFormWorkspace> closed_work;
  if (closed) closed_work.emplace(model);
  const std::vector<Range> ranges = samplingRanges(model);
  Data data(model);
  IkWorkspace work(model);
  std::vector<IkAllRow> rows;
  rows.reserve(table.rows());
  size_t total = 0, without = 0;
  for (size_t k = 0; k < table.rows(); ++k) {
    rows.push_back(solveAll(model, closed ? &*closed_work : nullptr, data, work, table.targets[k], k, o.seeds,
                            static_cast<unsigned long long>(o.seed), ranges, options, table.lines[k]));
    total += rows.back().solutions.size();
    without += rows.back().solutions.empty();
  }
  const std::string method = closed ? "closed form (" + std::string(closedFormKindName(structure.kind)) + ")"
                                    : "numerical: the distinct solutions from " + std::to_string(o.seeds) +
                                          " random seeds per row (sample k*" + std::to_string(o.seeds) + "+s of --seed " +
                                          std::to_string(o.seed) + "), not proven complete; no closed form: " + structure.reason;
  std::vector<std::string> comments{
      "lowpair ik " + o.robot.path + " --poses " + o.poses + " --all" +
          (closed ? std::string() : " --seeds " + std::to_string(o.seeds) + " --seed " + std::to_string(o.seed)),
      "every solution of each pose target of " + o.poses + ", " + method,
      "shoulder, elbow, wrist: the branch flags (docs/ik.md); singular: a free angle or a double root; out_of_range: "
      "the first joint outside its range (0: none); residual: position error (" + unitName(file) + "), rotation (rad)"};
  for (const std::string& note : notes) comments.push_back(note);
  comments.push_back(std::to_string(table.rows()) + " targets: " + std::to_string(total) + " solutions, " +
                     std::to_string(without) + " targets without one");
  if (isUnitLabel(file.length_unit)) comments.push_back("length_unit: " + file.length_unit);
  const StreamWriter csv = [&](std::ostream& out) { writeAllCsv(out, comments, n, rows); };
  if (!o.out.empty()) writeFileAtomically(o.out, csv);
  if (o.as_json) {
    const json head{{"name", file.name},
                    {"source", file.path},
                    {"poses", o.poses},
                    {"length_unit", file.length_unit},
                    {"task", "pose"},
                    {"closed_form", closedFormKindName(structure.kind)},
                    {"closed_form_reason", closed ? json(nullptr) : json(structure.reason)},
                    {"seeds", closed ? json(nullptr) : json(o.seeds)},
                    {"seed", o.seed},
                    {"notes", notes},
                    {"counts", {{"targets", table.rows()}, {"solutions", total}, {"without_solution", without}}}};
    writeJsonWithRows(std::cout, head, "rows", rows.size(), [&](size_t k) { return ikAllRowJson(rows[k]); });
    std::cout << "\n";
  } else if (!o.out.empty()) {
    for (const std::string& note : notes) std::cout << "note: " << note << "\n";
    std::cout << "ik --all: " << table.rows() << " pose targets of " << robotLabel(file) << ", " << method << "\n";
    std::cout << "  " << total << " solutions, " << without << " targets without one\n";
    std::cout << "  written to " << o.out << "\n";
  } else {
    csv(std::cout);
  }
  return without == 0 ? 0 : 1;
}

int runIk(const IkCommandOptions& o) {
  const RobotFile file = loadRobot(o.robot, cliSpelling());
  const PoeModel model = file.poeModel();
  const int n = model.dof();
  JointTable table = readJointTable(o.poses, TableKind::Targets, n, o.robot.path, csvJointNames(file));
  // the solver's work bounded before any row is solved (limits.hpp): --seeds named when the seeds are random
  if (const auto problem = ikWorkProblem(table.rows(), table.dof > 0 ? 1 : o.seeds, n, table.dof == 0)) {
    throw UsageError(table.dof > 0 ? o.poses : "--seeds", *problem);
  }
  std::vector<std::string> notes = table.notes;  // the columns ignored, then a unit conversion
  // positions, and the seeds' prismatic joint values, in the robot's unit
  if (const std::string note = convertTableUnit(table, file.length_unit, file.path, prismaticJoints(model)); !note.empty()) {
    notes.push_back(note);
  }
  checkJointRows(table, model);  // the seeds
  if (o.all) return runIkAll(o, file, model, table, notes);
  IkOptions options;
  options.measure = table.pose ? Measure::Pose : Measure::Position;
  options.validate("inverseKinematics");
  const std::vector<Range> ranges = samplingRanges(model);
  Data data(model);
  IkWorkspace work(model);
  std::vector<IkRow> rows;
  rows.reserve(table.rows());
  for (size_t k = 0; k < table.rows(); ++k) {
    const Pose& target = table.targets[k];
    if (table.dof > 0) {
      rows.push_back({inverseKinematics(model, data, target, table.row(k), options, work), -1, table.lines[k], std::nullopt});
    } else {
      rows.push_back(solveFromRandomSeeds(model, data, target, k, o.seeds, static_cast<unsigned long long>(o.seed), ranges,
                                          options, work, table.lines[k]));
    }
  }

  const Summary s = summarize(rows);
  const char* task = table.pose ? "pose" : "position";
  const std::string seeding = table.dof > 0 ? "each row's q1..qn as its seed"
                                            : std::to_string(o.seeds) + " random seeds per row (sample k*" +
                                                  std::to_string(o.seeds) + "+s of --seed " + std::to_string(o.seed) +
                                                  ", uniform in the joint ranges), the first ok kept";
  std::ostringstream command;
  command << "lowpair ik " << o.robot.path;
  if (!o.robot.tip.empty()) command << " --tip " << o.robot.tip;
  if (!o.robot.base.empty()) command << " --base " << o.robot.base;
  command << " --poses " << o.poses;
  if (table.dof == 0) command << " --seeds " << o.seeds << " --seed " << o.seed;
  std::vector<std::string> comments{command.str(),
                                    "q1..qn: joint values solving the " + std::string(task) + " targets of " + o.poses +
                                        " (row by row), from " + seeding,
                                    "residual: the position error (" + unitName(file) +
                                        "); status: ok, out_of_range, singular, unreachable or not_converged (docs/ik.md)"};
  for (const std::string& note : notes) comments.push_back(note);
  for (const std::string& line : summaryComments(s, rows, file, table.pose)) comments.push_back(line);
  if (isUnitLabel(file.length_unit)) comments.push_back("length_unit: " + file.length_unit);
  const StreamWriter csv = [&](std::ostream& out) { writeSolutionsCsv(out, comments, n, rows); };
  const json head{{"name", file.name},
                  {"source", file.path},
                  {"poses", o.poses},
                  {"length_unit", file.length_unit},
                  {"task", task},
                  {"seeds", table.dof > 0 ? json("file") : json(o.seeds)},
                  {"seed", o.seed},
                  {"notes", notes},
                  {"counts", ikCountsJson(rows)}};
  auto text = [&](std::ostream& out) {
    for (const std::string& note : notes) out << "note: " << note << "\n";
    printSummary(out, "ik: " + std::to_string(rows.size()) + " " + task + " targets of " + robotLabel(file) + ", " + seeding,
                 s, rows, o.poses, file, table.pose);
  };
  return emit(o.out, o.as_json, csv, head, rows, true, text, s);
}

// ---- compensate ----------------------------------------------------------------------------------------------------

struct CompensateOptions {
  RobotSource calibrated;
  std::string nominal, q_file, out, measure = "pose";
  std::string approach;  // --approach: the signs of the calibrated file's backlash
  bool as_json = false;
  bool seeded = false;  // --seeded: the numerical solver seeded at each row, no branch kept
};

// A robot file, or a model file with the command's --tip/--base.
RobotFile loadEither(const std::string& path, const RobotSource& like) {
  const std::string ext = std::filesystem::path(path).extension().string();
  const bool model_file = ext == ".xml" || ext == ".urdf";
  return loadRobot(RobotSource{path, model_file ? like.tip : "", model_file ? like.base : ""}, cliSpelling());
}

int runCompensate(const CompensateOptions& o) {
  const RobotFile calibrated_file = loadRobot(o.calibrated, cliSpelling());
  const RobotFile nominal_file = loadEither(o.nominal, o.calibrated);
  const PoeModel calibrated = calibrated_file.poeModel(), nominal = nominal_file.poeModel();
  if (nominal.dof() != calibrated.dof()) {
    throw UsageError(o.calibrated.path, "has " + std::to_string(calibrated.dof()) + " joints but --nominal " + o.nominal +
                                            " has " + std::to_string(nominal.dof()));
  }
  if (nominal_file.length_unit != calibrated_file.length_unit) {
    throw UsageError(o.calibrated.path, "lengths in " + (calibrated_file.length_unit.empty() ? std::string("no stated unit") : calibrated_file.length_unit) +
                                            " but --nominal " + o.nominal + " in " +
                                            (nominal_file.length_unit.empty() ? std::string("no stated unit") : nominal_file.length_unit) +
                                            ": compensation needs one unit");
  }
  const int n = calibrated.dof();
  JointTable table = readJointTable(o.q_file, TableKind::Joints, n, o.calibrated.path, csvJointNames(calibrated_file));
  if (const auto problem = ikWorkProblem(table.rows(), 1, n, false)) throw UsageError(o.q_file, *problem);
  for (const std::string& note : table.notes) std::cerr << "note: " << note << "\n";
  // prismatic joint values in the robots' unit (one unit: checked above)
  if (const std::string note = convertTableUnit(table, nominal_file.length_unit, o.nominal, prismaticJoints(nominal));
      !note.empty()) {
    std::cerr << "note: " << note << "\n";
  }
  checkJointRows(table, nominal);
  IkOptions options;
  options.measure = o.measure == "pose" ? Measure::Pose : Measure::Position;
  options.validate("compensate");
  // the table's rows, row-major, as the matrix of joint vectors the shared loop takes
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> q_nominal(
      table.q.data(), static_cast<Eigen::Index>(table.rows()), n);
  // the nominal rows' branches kept (closed form), unless --seeded or the models or the task have none
  const std::string no_branch = o.seeded ? "--seeded" : branchUnavailable(nominal, calibrated, options);
  std::vector<IkRow> rows = compensateJointRows(nominal, calibrated, q_nominal, table.lines, options, no_branch.empty());
  const long long kept = std::count_if(rows.begin(), rows.end(), [](const IkRow& r) { return r.branch.has_value(); });
  const std::string method = no_branch.empty() ? "on the nominal row's branch (closed form; " + std::to_string(kept) + " of " +
                                                     std::to_string(rows.size()) + " rows, the others seeded there)"
                                               : "seeded there (" + no_branch + ")";
  // a compliance (and a backlash with --approach): the commands whose joints, deflected, stand where the solution puts them
  std::vector<VecX> rows_q;  // (only --approach reads them)
  for (Eigen::Index k = 0; !o.approach.empty() && k < q_nominal.rows(); ++k) rows_q.push_back(q_nominal.row(k).transpose());
  const std::vector<VecX> signs = commands::approachSigns(o.approach, rows_q, n, false, cliSpelling());
  const std::string deflection_note = commands::deflectionNote(calibrated_file, !signs.empty());
  if (!deflection_note.empty()) std::cerr << "note: " << deflection_note << "\n";
  commands::applyDeflection(calibrated_file, calibrated, rows, signs);
  const JointDeflection applied = commands::appliedDeflection(calibrated_file, !signs.empty());  // (JSON's flags)
  const Summary s = summarize(rows);
  const bool pose = options.measure == Measure::Pose;
  const std::string command = "lowpair compensate " + o.calibrated.path +
                              (o.calibrated.tip.empty() ? "" : " --tip " + o.calibrated.tip) +
                              (o.calibrated.base.empty() ? "" : " --base " + o.calibrated.base) + " --nominal " + o.nominal +
                              " --q-file " + o.q_file + " --measure " + o.measure;
  std::vector<std::string> comments{
      command,
      "q1..qn: joint values of " + o.calibrated.path + " that put the tool " + (pose ? "frame" : "origin") + " where " +
          o.nominal + " puts it at the q of the same row of " + o.q_file + ", " + method,
      "residual: the position error (" + unitName(calibrated_file) +
          "); status: ok, out_of_range, singular, unreachable or not_converged (docs/ik.md)"};
  for (const std::string& line : summaryComments(s, rows, calibrated_file, pose)) comments.push_back(line);
  if (!deflection_note.empty()) comments.push_back("note: " + deflection_note);
  const std::string tool_note = undeterminedToolNote(calibrated_file, pose);
  if (!tool_note.empty()) {
    comments.push_back("note: " + tool_note);
    std::cerr << "note: " << tool_note << "\n";
  }
  if (isUnitLabel(calibrated_file.length_unit)) comments.push_back("length_unit: " + calibrated_file.length_unit);
  const StreamWriter csv = [&](std::ostream& out) { writeSolutionsCsv(out, comments, n, rows); };
  json head{{"name", calibrated_file.name},
            {"source", calibrated_file.path},
            {"nominal", nominal_file.path},
            {"q_file", o.q_file},
            {"length_unit", calibrated_file.length_unit},
            {"measure", o.measure},
            {"tool_determined", tool_note.empty()},
            {"tool_note", tool_note.empty() ? json(nullptr) : json(tool_note)},
            {"counts", ikCountsJson(rows)},
            {"branch_kept", kept}};
  if (applied.compliance.size() > 0) head["compliance_applied"] = true;  // (only then: other outputs unchanged)
  if (applied.backlash.size() > 0) head["backlash_applied"] = true;
  auto text = [&](std::ostream& out) {
    // (the branch named only when kept: the seeded summary reads as before, its CSV comment says why)
    printSummary(out, "compensate: " + std::to_string(rows.size()) + " joint vectors of " + o.q_file + " (" + o.measure +
                          "), " + robotLabel(nominal_file) + " -> " + robotLabel(calibrated_file) +
                          (no_branch.empty() ? ", " + method : std::string()),
                 s, rows, o.q_file, calibrated_file, pose);
  };
  return emit(o.out, o.as_json, csv, head, rows, false, text, s);
}

}  // namespace

void addIkCommands(CLI::App& app, Commands& commands) {
  auto ik_options = std::make_shared<IkCommandOptions>();
  auto* ik = app.add_subcommand("ik", "inverse kinematics of target poses or positions (CSV), row by row");
  addRobotArgument(*ik, ik_options->robot);
  ik->add_option("--poses", ik_options->poses,
                 "CSV of targets: [q1..qn,]x,y,z[,qw,qx,qy,qz] (a row's q1..qn: its seed; without them --seeds random seeds)")
      ->required();
  ik->add_option("--out", ik_options->out, "write the solutions (q1..qn,residual,status) here, all or nothing");
  ik->add_flag("--json", ik_options->as_json, "print JSON (every row: q, iterations, errors, status, reason)");
  ik->add_option("--seeds", ik_options->seeds, "random seeds per row without q columns, 1 to 1000 (default 8)")
      ->check(CLI::Range(1, kMaxIkSeeds));
  ik->add_flag("--all", ik_options->all,
               "every solution of each pose target (closed form where the geometry allows, else the distinct solutions of "
               "--seeds random seeds), with branch flags and residuals");
  ik->add_option("--seed", ik_options->seed, "seed of the random seeds, in [0, 2^53] (default 1)")->check(CLI::Range(0LL, kMaxSeed));
  commands.emplace_back(ik, [ik_options] { return runIk(*ik_options); });

  auto comp_options = std::make_shared<CompensateOptions>();
  auto* comp = app.add_subcommand("compensate", "joint values of a calibrated robot that reproduce the nominal's poses");
  addRobotArgument(*comp, comp_options->calibrated);
  comp->add_option("--nominal", comp_options->nominal, "the nominal robot (file or model) the joint values are for")
      ->required();
  comp->add_option("--q-file", comp_options->q_file, "CSV of nominal joint values q1..qn (other columns ignored)")
      ->required();
  comp->add_option("--out", comp_options->out, "write the compensated joint values (q1..qn,residual,status) here");
  comp->add_flag("--json", comp_options->as_json, "print JSON");
  comp->add_option("--approach", comp_options->approach,
                   "the calibrated file's backlash: each joint's approach sign S1,...,Sn (-1, 0, 1) for every row, or order "
                   "(each joint's last move in the rows' order)");
  comp->add_flag("--seeded", comp_options->seeded,
                 "solve each row with the numerical solver seeded at the nominal q (the default keeps the nominal row's "
                 "branch through the closed form when both robots have one)");
  comp->add_option("--measure", comp_options->measure, "pose (default: the tool frame) or position (the tool origin)")
      ->check(CLI::IsMember({"pose", "position"}));
  commands.emplace_back(comp, [comp_options] { return runCompensate(*comp_options); });
}

}  // namespace lowpair::cli
