// poe2dh, dh2poe, fk (--q, or --q-file: a measurement CSV of the tool at every row's joint values).
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "commands/deflection_inputs.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_columns.hpp"
#include "io/joint_table.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below

using nlohmann::json;

namespace {

struct FkFileOptions {
  std::string q_file, out, measure = "pose";
  std::string approach;  // --approach: the signs of a file's backlash (deflection_inputs.hpp)
};

// fk --frame measurement: the robot file's measurement_frame (T_measurement_base), which FK then predicts in
// (the frame of a tracker's measurements); identity for --frame base.
Pose frameOf(const RobotFile& file, const std::string& frame) {
  if (frame != "measurement") return Pose{};
  if (!file.measurement_frame) {
    throw UsageError(file.path, "--frame measurement: the robot file has no measurement_frame (calibrate --out records it)");
  }
  return *file.measurement_frame;
}

// fk --q-file: what was read and computed, every row checked before anything is written.
struct FkRows {
  JointTable table;
  Measure measure = Measure::Pose;
  std::vector<std::string> target_names;
  std::vector<Pose> T;  // T_frame_tool at each row (each target's point: T * point_tool)
  size_t perRow() const { return measure == Measure::Targets ? target_names.size() : 1; }
};

// The rows of fk --q-file, each evaluated by the same call as fk --q (poeForwardKinematics /
// dhForwardKinematics): the rows equal fk --q bit for bit. (forwardKinematicsBatch agrees with it only to
// rounding: 2 eps in R, 9 eps L in p measured, docs/ik.md.)
// @throws RobotFileError naming the file and line of a row whose tool (or a target) lies beyond 1e100
FkRows fkRows(const RobotFile& file, const std::string& robot_path, const std::string& kind, const FkFileOptions& o,
              const Pose& T_frame_base) {
  FkRows r;
  r.table = readJointTable(o.q_file, TableKind::Joints, file.dof(), robot_path, csvJointNames(file));
  JointTable& table = r.table;
  for (const std::string& note : table.notes) std::cerr << "note: " << note << "\n";
  // prismatic joint values in the robot's unit (revolute and helical q are rad)
  if (const std::string note = convertTableUnit(table, file.length_unit, robot_path, prismaticJoints(file.poeModel()));
      !note.empty()) {
    std::cerr << "note: " << note << "\n";
  }
  checkJointRows(table, file.poeModel());
  r.measure = commands::parseMeasure(o.measure, cliSpelling());
  if (r.measure == Measure::Targets) {
    if (file.targets.empty()) {
      throw UsageError(robot_path, "--measure targets: the robot file lists no targets (a 'targets:' list of {name, point})");
    }
    for (const Target& t : file.targets) r.target_names.push_back(t.name);
  }
  const auto rows = static_cast<long long>(table.rows()), per_row = static_cast<long long>(r.perRow());
  if (rows * per_row > kMaxMeasurements) {
    throw UsageError(o.q_file, std::to_string(rows) + " rows x " + std::to_string(per_row) + " targets = " +
                                   std::to_string(rows * per_row) + " measurements, more than the " +
                                   std::to_string(kMaxMeasurements) + " a measurement file holds");
  }
  const std::optional<PoeModel> poe = kind == "poe" ? std::optional<PoeModel>(file.poeModel()) : std::nullopt;
  const std::optional<DhModel> dh =
      kind == "dh" ? std::optional<DhModel>(file.dh ? *file.dh : poeToDh(*file.poe).model) : std::nullopt;
  const PoeModel model = file.poeModel();  // (the gravity load of a compliance: deflection_inputs.hpp)
  std::vector<VecX> rows_q;  // (only --approach reads them)
  for (size_t k = 0; !o.approach.empty() && k < table.rows(); ++k) rows_q.push_back(table.row(k));
  const std::vector<VecX> signs = commands::approachSigns(o.approach, rows_q, file.dof(), false, cliSpelling());
  if (const std::string note = commands::deflectionNote(file, !signs.empty()); !note.empty()) std::cerr << "note: " << note << "\n";
  const auto beyond = [](const Vec3& p) { return !(p.cwiseAbs().maxCoeff() <= kMaxMagnitude); };
  r.T.reserve(table.rows());
  for (size_t k = 0; k < table.rows(); ++k) {
    const VecX q_stand = commands::standingJoints(file, model, table.row(k), signs.empty() ? VecX() : signs[k]);
    const Pose T = T_frame_base * (poe ? poeForwardKinematics(*poe, q_stand) : dhForwardKinematics(*dh, q_stand));
    const std::string where = o.q_file + ":" + std::to_string(table.lines[k]);
    for (size_t t = 0; r.measure == Measure::Targets && t < file.targets.size(); ++t) {
      if (beyond(T * *file.targets[t].point_tool)) {
        throw RobotFileError(where + ": target " + file.targets[t].name + " lies beyond 1e100, which no reader takes");
      }
    }
    if (r.measure != Measure::Targets && beyond(T.p)) throw RobotFileError(where + ": the tool lies beyond 1e100, which no reader takes");
    r.T.push_back(T);
  }
  return r;
}

// fk --q-file: the tool frame (Pose), its origin (Position) or each target's point (Targets) at every row's q,
// as a measurement CSV (io/measurements.hpp), or JSON. Rows are computed and checked first, then written as they
// are formatted (10^6 rows: neither the CSV nor the JSON is held whole; docs/cli.md "Limits").
int fkFromFile(const RobotFile& file, const std::string& robot_path, const std::string& kind, const FkFileOptions& o,
               bool as_json, const Pose& T_frame_base) {
  const FkRows r = fkRows(file, robot_path, kind, o, T_frame_base);
  const size_t per_row = r.perRow(), count = r.table.rows() * per_row;
  // measurement i: row i / per_row, and for targets the target i % per_row
  const auto point = [&](size_t i) { return r.T[i / per_row] * *file.targets[i % per_row].point_tool; };
  const std::string unit = file.length_unit.empty() ? "length" : file.length_unit;
  const std::string what = r.measure == Measure::Pose   ? "x,y,z: tool position in the base frame (" + unit + "); qw,qx,qy,qz: its rotation, unit quaternion"
                           : r.measure == Measure::Position ? "x,y,z: tool position in the base frame (" + unit + ")"
                                                            : "x,y,z: the target's point in the base frame (" + unit + "), one row per target of " + robot_path;
  std::vector<std::string> comments{"lowpair fk " + robot_path + " --q-file " + o.q_file + " --measure " + o.measure + " --model " + kind,
                                    "forward kinematics of the " + kind + " model at the q1..qn of every row of " + o.q_file +
                                        " (the same evaluation as fk --q, bit for bit)",
                                    what};
  if (isUnitLabel(file.length_unit)) comments.push_back("length_unit: " + file.length_unit);
  const StreamWriter csv = [&](std::ostream& out) {
    MeasurementWriter writer(out, r.measure, file.dof(), r.target_names);
    writer.writeHeader(comments);
    for (size_t i = 0; i < count; ++i) {
      const auto q = r.table.row(i / per_row);
      if (r.measure == Measure::Targets) {
        writer.write(q, Pose{Mat3::Identity(), point(i)}, static_cast<int>(i % per_row));
      } else {
        writer.write(q, r.measure == Measure::Pose ? r.T[i] : Pose{Mat3::Identity(), r.T[i].p});
      }
    }
  };
  if (!o.out.empty()) writeFileAtomically(o.out, csv);
  if (as_json) {
    const auto row = [&](size_t i) {
      json j = {{"line", r.table.lines[i / per_row]}, {"q", toVector(r.table.row(i / per_row))}};
      if (r.measure == Measure::Targets) {
        j["target"] = file.targets[i % per_row].name;
        j["p"] = toVector(point(i));
      } else if (r.measure == Measure::Pose) {
        j["T_base_tool"] = poseJson(r.T[i]);
      } else {
        j["p"] = toVector(r.T[i].p);
      }
      return j;
    };
    writeJsonWithRows(std::cout, {{"name", file.name}, {"source", file.path}, {"model", kind},
                                  {"length_unit", file.length_unit}, {"q_file", o.q_file}, {"measure", o.measure}},
                      "rows", count, row);
    std::cout << "\n";
  } else if (!o.out.empty()) {
    // ("300 target measurements", "50 pose measurements")
    std::cout << count << " " << (o.measure == "targets" ? std::string("target") : o.measure)
              << " measurements written to " << o.out << "\n";
  } else {
    csv(std::cout);
  }
  return 0;
}

}  // namespace

void addConvertCommands(CLI::App& app, Commands& commands) {
  struct Options {
    RobotSource robot;
    std::string q_text, model_kind = "file", frame = "base";
    bool as_json = false, modified = false, standard = false;
    double parallel_threshold = 0.0;
  };
  auto o = std::make_shared<Options>();
  auto fk_file = std::make_shared<FkFileOptions>();

  auto* poe2dh = app.add_subcommand("poe2dh", "POE -> standard D-H table (base, joints, tool, pitch, scale)");
  addRobotArgument(*poe2dh, o->robot);
  poe2dh->add_flag("--json", o->as_json, "print JSON (angles in rad, pitch in length/rad)");
  poe2dh->add_flag("--modified", o->modified, "print the same chain as a modified (Craig) D-H table");
  poe2dh->add_option("--parallel-threshold", o->parallel_threshold,
                     "treat axes with sin(angle) below this as parallel (default: rounding level 16 eps n); "
                     "larger values change the model and the FK check reports by how much");
  poe2dh->add_flag("--standard", o->standard,
                   "standard D-H rows only, as published tables give them (no Hayati row: at nearly parallel axes "
                   "d may be far beyond the robot's size)");
  commands.emplace_back(poe2dh, [o] {
    const RobotFile file = loadRobot(o->robot, cliSpelling());
    ConvertOptions options;
    options.parallel_threshold = o->parallel_threshold;
    options.validate();
    const PoeModel poe = file.poeModel();
    options.standard_only = o->standard;
    const DhConversion c = poeToDh(poe, options);
    const FkCheck check = checkDhConversion(poe, c.model);
    if (o->as_json) {
      std::cout << jsonText(o->modified ? modifiedDhJson(file, c, check) : dhJson(file, c, check)) << "\n";
    } else if (o->modified) {
      printModifiedDh(std::cout, file, c, check);
    } else {
      printDh(std::cout, file, c, check);
    }
    return 0;
  });

  auto* dh2poe = app.add_subcommand("dh2poe", "D-H -> POE twists");
  addRobotArgument(*dh2poe, o->robot);
  dh2poe->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(dh2poe, [o] {
    const RobotFile file = loadRobot(o->robot, cliSpelling());
    const PoeModel m = file.poeModel();
    if (o->as_json) {
      std::cout << jsonText(poeJson(file, m)) << "\n";
    } else {
      printPoe(std::cout, file, m);
    }
    return 0;
  });

  auto* fk = app.add_subcommand("fk", "forward kinematics T_base_tool(q)");
  addRobotArgument(*fk, o->robot);
  auto* q_option = fk->add_option("--q", o->q_text, "joint values Q1,Q2,... (rad for revolute/helical, length for prismatic)");
  auto* q_file_option = fk->add_option("--q-file", fk_file->q_file,
                                       "CSV of joint values q1..qn, a row each (other columns ignored: a measurement CSV "
                                       "is one); prints a measurement CSV");
  q_option->excludes(q_file_option);
  q_file_option->excludes(q_option);
  auto* out_option = fk->add_option("--out", fk_file->out, "--q-file: write the CSV here (all or nothing)");
  auto* measure_option = fk->add_option("--measure", fk_file->measure,
                                        "--q-file: pose (default), position, or targets (the robot file's targets: list)")
                             ->check(CLI::IsMember({"pose", "position", "targets"}));
  fk->add_option("--model", o->model_kind, "poe or dh (default: the file's own description)")
      ->check(CLI::IsMember({"poe", "dh", "file"}));
  fk->add_flag("--json", o->as_json, "print JSON");
  fk->add_option("--approach", fk_file->approach,
                 "a file's backlash: each joint's approach sign, S1,...,Sn (-1, 0, 1), or order (--q-file: from the rows' order)");
  fk->add_option("--frame", o->frame,
                 "base (default) or measurement: T_measurement_base T_base_tool(q), the robot file's measurement_frame "
                 "(calibrate --out records it)")
      ->check(CLI::IsMember({"base", "measurement"}));
  commands.emplace_back(fk, [o, fk_file, q_option, q_file_option, out_option, measure_option] {
    if (q_option->count() == 0 && q_file_option->count() == 0) throw UsageError("fk", "give --q Q1,Q2,... or --q-file FILE.csv");
    if (q_file_option->count() == 0 && (out_option->count() > 0 || measure_option->count() > 0)) {
      throw UsageError("fk", "--out and --measure go with --q-file");
    }
    const RobotFile file = loadRobot(o->robot, cliSpelling());
    const std::string kind = o->model_kind == "file" ? (file.poe ? "poe" : "dh") : o->model_kind;
    const Pose T_frame_base = frameOf(file, o->frame);
    if (q_file_option->count() > 0) return fkFromFile(file, o->robot.path, kind, *fk_file, o->as_json, T_frame_base);
    const VecX q = parseJointVector(o->q_text, file, o->robot.path);
    const bool measurement = o->frame == "measurement";
    const std::vector<VecX> signs = commands::approachSigns(fk_file->approach, {q}, file.dof(), true, cliSpelling());
    if (const std::string note = commands::deflectionNote(file, !signs.empty()); !note.empty()) std::cerr << "note: " << note << "\n";
    // q unless the file holds a compliance (or a backlash and --approach is given)
    const VecX q_stand = commands::standingJoints(file, file.poeModel(), q, signs.empty() ? VecX() : signs[0]);
    const Pose T = T_frame_base * (kind == "poe" ? poeForwardKinematics(file.poeModel(), q_stand)
                                                 : dhForwardKinematics(file.dh ? *file.dh : poeToDh(*file.poe).model, q_stand));
    if (o->as_json) {
      json j = {{"name", file.name}, {"source", file.path}, {"model", kind}, {"length_unit", file.length_unit},
                {"q", toVector(q)}, {"T_base_tool", poseJson(T)}};
      if (q_stand != q) j["q_deflected"] = toVector(q_stand);  // where the joints stand (only when deflected)
      if (measurement) {  // the same pose under its own name, and the frame it is in
        j["frame"] = "measurement";
        j["T_measurement_tool"] = j["T_base_tool"];
      }
      std::cout << jsonText(j) << "\n";
    } else {
      std::cout << (measurement ? "T_measurement_tool (" : "T_base_tool (") << kind << " model of " << robotLabel(file)
                << (measurement ? ", in its measurement_frame" : "") << "):\n";
      printPose(std::cout, T, file.length_unit.empty() ? "length" : file.length_unit);
    }
    return 0;
  });
}

}  // namespace lowpair::cli
