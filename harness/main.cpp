// The lowpair command line (design.md "The lowpair command line"). Exit status: 0 ok, 1 a validation
// fell outside tolerance, 2 bad input or usage (one line on stderr: "error: FILE: what is wrong").

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "output.hpp"
#include "robot_file.hpp"

using namespace lowpair;
using nlohmann::json;

namespace {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

VecX parseJointVector(const std::string& text, int dof) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto begin = item.find_first_not_of(" \t");
    const auto end = item.find_last_not_of(" \t");
    const std::string token = begin == std::string::npos ? "" : item.substr(begin, end - begin + 1);
    char* stop = nullptr;
    const double x = std::strtod(token.c_str(), &stop);
    if (token.empty() || *stop != '\0') throw UsageError("--q: '" + token + "' is not a number");
    if (!std::isfinite(x)) throw UsageError("--q: '" + token + "' is not finite");
    values.push_back(x);
  }
  if (static_cast<int>(values.size()) != dof) {
    throw UsageError("--q: expected " + std::to_string(dof) + " joint values, got " + std::to_string(values.size()));
  }
  return Eigen::Map<VecX>(values.data(), static_cast<Eigen::Index>(values.size()));
}

RobotFile loadRobot(const std::string& path) {
  const auto dot = path.rfind('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
  if (ext == ".xml" || ext == ".urdf") {
    throw RobotFileError(path + ": MJCF/URDF input is read by 'lowpair validate' (this subcommand takes a robot file, .yaml)");
  }
  return readRobotFile(path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lowpair: POE and D-H kinematics of serial robots (Wu et al. 2019; Paden & Sastry 1984)"};
  app.require_subcommand(1);

  std::string robot_path, q_text, model_kind = "file";
  bool as_json = false, modified = false;
  double parallel_threshold = 0.0;

  auto* poe2dh = app.add_subcommand("poe2dh", "POE -> standard D-H table (base, joints, tool, pitch, scale)");
  poe2dh->add_option("ROBOT", robot_path, "robot file (.yaml)")->required();
  poe2dh->add_flag("--json", as_json, "print JSON (angles in rad, pitch in length/rad)");
  poe2dh->add_flag("--modified", modified, "print the same chain as a modified (Craig) D-H table");
  poe2dh->add_option("--parallel-threshold", parallel_threshold,
                     "treat axes with sin(angle) below this as parallel (default: rounding level 16 eps n); "
                     "larger values change the model and the FK check reports by how much");

  auto* dh2poe = app.add_subcommand("dh2poe", "D-H -> POE twists");
  dh2poe->add_option("ROBOT", robot_path, "robot file (.yaml)")->required();
  dh2poe->add_flag("--json", as_json, "print JSON");

  auto* fk = app.add_subcommand("fk", "forward kinematics T_base_tool(q)");
  fk->add_option("ROBOT", robot_path, "robot file (.yaml)")->required();
  fk->add_option("--q", q_text, "joint values Q1,Q2,... (rad for revolute/helical, length for prismatic)")->required();
  fk->add_option("--model", model_kind, "poe or dh (default: the file's own description)")
      ->check(CLI::IsMember({"poe", "dh", "file"}));
  fk->add_flag("--json", as_json, "print JSON");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    std::cerr << "error: " << msg << " (see lowpair --help)\n";
    return 2;
  }

  try {
    const RobotFile file = loadRobot(robot_path);
    if (app.got_subcommand(poe2dh)) {
      ConvertOptions options;
      options.parallel_threshold = parallel_threshold;
      const DhConversion c = poeToDh(file.poeModel(), options);
      if (as_json) {
        std::cout << (modified ? modifiedDhJson(file, c) : dhJson(file, c)).dump(1) << "\n";
      } else if (modified) {
        printModifiedDh(std::cout, file, c);
      } else {
        printDh(std::cout, file, c);
      }
    } else if (app.got_subcommand(dh2poe)) {
      const PoeModel m = file.poeModel();
      if (as_json) {
        std::cout << poeJson(file, m).dump(1) << "\n";
      } else {
        printPoe(std::cout, file, m);
      }
    } else if (app.got_subcommand(fk)) {
      const VecX q = parseJointVector(q_text, file.dof());
      const std::string kind = model_kind == "file" ? (file.poe ? "poe" : "dh") : model_kind;
      Pose T;
      if (kind == "poe") {
        T = poeForwardKinematics(file.poeModel(), q);
      } else {
        T = dhForwardKinematics(file.dh ? *file.dh : poeToDh(*file.poe).model, q);
      }
      if (as_json) {
        json j = {{"name", file.name}, {"source", file.path}, {"model", kind}, {"length_unit", file.length_unit},
                  {"q", std::vector<double>(q.data(), q.data() + q.size())}, {"T_base_tool", poseJson(T)}};
        std::cout << j.dump(1) << "\n";
      } else {
        std::cout << "T_base_tool (" << kind << " model of " << (file.name.empty() ? file.path : file.name) << "):\n";
        printPose(std::cout, T, file.length_unit.empty() ? "length" : file.length_unit);
      }
    }
  } catch (const RobotFileError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const UsageError& e) {
    std::cerr << "error: " << robot_path << ": " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "error: " << robot_path << ": " << e.what() << "\n";
    return 2;
  }
  return 0;
}
