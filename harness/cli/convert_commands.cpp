// poe2dh, dh2poe, fk.
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "io/output.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below

using nlohmann::json;

void addConvertCommands(CLI::App& app, Commands& commands) {
  struct Options {
    RobotSource robot;
    std::string q_text, model_kind = "file";
    bool as_json = false, modified = false;
    double parallel_threshold = 0.0;
  };
  auto o = std::make_shared<Options>();

  auto* poe2dh = app.add_subcommand("poe2dh", "POE -> standard D-H table (base, joints, tool, pitch, scale)");
  addRobotArgument(*poe2dh, o->robot);
  poe2dh->add_flag("--json", o->as_json, "print JSON (angles in rad, pitch in length/rad)");
  poe2dh->add_flag("--modified", o->modified, "print the same chain as a modified (Craig) D-H table");
  poe2dh->add_option("--parallel-threshold", o->parallel_threshold,
                     "treat axes with sin(angle) below this as parallel (default: rounding level 16 eps n); "
                     "larger values change the model and the FK check reports by how much");
  commands.emplace_back(poe2dh, [o] {
    const RobotFile file = loadRobot(o->robot);
    ConvertOptions options;
    options.parallel_threshold = o->parallel_threshold;
    const PoeModel poe = file.poeModel();
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
    const RobotFile file = loadRobot(o->robot);
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
  fk->add_option("--q", o->q_text, "joint values Q1,Q2,... (rad for revolute/helical, length for prismatic)")->required();
  fk->add_option("--model", o->model_kind, "poe or dh (default: the file's own description)")
      ->check(CLI::IsMember({"poe", "dh", "file"}));
  fk->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(fk, [o] {
    const RobotFile file = loadRobot(o->robot);
    const VecX q = parseJointVector(o->q_text, file.dof(), o->robot.path);
    const std::string kind = o->model_kind == "file" ? (file.poe ? "poe" : "dh") : o->model_kind;
    const Pose T = kind == "poe" ? poeForwardKinematics(file.poeModel(), q)
                                 : dhForwardKinematics(file.dh ? *file.dh : poeToDh(*file.poe).model, q);
    if (o->as_json) {
      json j = {{"name", file.name}, {"source", file.path}, {"model", kind}, {"length_unit", file.length_unit},
                {"q", toVector(q)}, {"T_base_tool", poseJson(T)}};
      std::cout << jsonText(j) << "\n";
    } else {
      std::cout << "T_base_tool (" << kind << " model of " << robotLabel(file) << "):\n";
      printPose(std::cout, T, file.length_unit.empty() ? "length" : file.length_unit);
    }
    return 0;
  });
}

}  // namespace lowpair::cli
