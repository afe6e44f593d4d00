#pragma once
/// @file commands.hpp
/// Subcommands of the `lowpair` CLI. Each `add...` registers its subcommands on the app and appends a
/// runner per subcommand; main() parses, runs the one selected and maps errors to exit status 2.
/// A runner returns the exit status (0 ok, 1 a validation fell outside tolerance) and throws
/// io::RobotFileError / UsageError / std::invalid_argument for bad input.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "lowpair/types.hpp"
#include "io/joint_table.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "commands/arguments.hpp"
#include "commands/robot_source.hpp"

namespace lowpair::cli {

using Runner = std::function<int()>;
using Commands = std::vector<std::pair<CLI::App*, Runner>>;

/// A usage error about an argument (not a file): printed as "error: SUBJECT: message". Shared with the
/// checks of the commands room, which the CLI and the Python module both call.
using UsageError = commands::UsageError;

/// The CLI's spelling of an argument in the shared checks' messages: "--noise-position", "--measure targets".
inline commands::ArgumentSpelling cliSpelling() {
  auto option = [](const std::string& name) {
    std::string flag = "--" + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    return flag;
  };
  return {option, [option](const std::string& name, const std::string& value) { return option(name) + " " + value; }};
}

/// Parses "Q1,Q2,..." into `dof` finite numbers. @throws UsageError (subject: `subject`)
VecX parseJointVector(const std::string& text, int dof, const std::string& subject);
/// Parses "Q1,Q2,..." into the robot's joint values, each within its joint's limits (commands::jointValueProblem:
/// the pose at q is finite). @throws UsageError (subject: `subject`, "--q: q3: ...")
VecX parseJointVector(const std::string& text, const io::RobotFile& robot, const std::string& subject);
/// Refuses the first row of `table` whose joint values leave a joint's limits (commands::jointValueProblem).
/// @throws io::RobotFileError "FILE:LINE: q3: ..."
void checkJointRows(const io::JointTable& table, const PoeModel& model);

/// Where a subcommand's robot comes from, read by loadRobot(source, cliSpelling()) (commands/robot_source.hpp,
/// the Python module's lowpair.load too).
using commands::RobotSource;
using commands::loadRobot;

/// Registers ROBOT, --tip and --base on a subcommand.
void addRobotArgument(CLI::App& sub, RobotSource& source);

void addConvertCommands(CLI::App& app, Commands& out);   // poe2dh, dh2poe, fk (convert_commands.cpp)
void addJacobianCommands(CLI::App& app, Commands& out);  // jacobian, singular (jacobian_commands.cpp)
void addValidateCommand(CLI::App& app, Commands& out);   // validate (validate_command.cpp)
void addSimulateCommand(CLI::App& app, Commands& out);   // simulate (simulate_command.cpp)
void addCalibrateCommands(CLI::App& app, Commands& out);  // identifiability, calibrate (calibrate_commands.cpp)
void addExportCommand(CLI::App& app, Commands& out);      // export (export_command.cpp)
void addIkCommands(CLI::App& app, Commands& out);         // ik, compensate (ik_commands.cpp)
void addPlanCommand(CLI::App& app, Commands& out);        // plan (plan_command.cpp)

}  // namespace lowpair::cli
