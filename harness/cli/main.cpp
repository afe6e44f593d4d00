// The lowpair command line (design.md "The lowpair command line"). Exit status: 0 ok, 1 a validation
// fell outside tolerance, 2 bad input or usage (one line on stderr: "error: FILE: what is wrong").

#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include <lowpair/version.hpp>

#include "cli/commands.hpp"
#include "io/joint_table.hpp"
#include "io/one_line.hpp"
#include "commands/sampling.hpp"
#include "lowpair/interrupt.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below

VecX parseJointVector(const std::string& text, int dof, const std::string& subject) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto begin = item.find_first_not_of(" \t");
    const auto end = item.find_last_not_of(" \t");
    const std::string token = begin == std::string::npos ? "" : item.substr(begin, end - begin + 1);
    char* stop = nullptr;
    const double x = std::strtod(token.c_str(), &stop);
    if (token.empty() || *stop != '\0') throw UsageError(subject, "--q: '" + token + "' is not a number");
    if (!std::isfinite(x)) throw UsageError(subject, "--q: '" + token + "' is not finite");
    values.push_back(x);
  }
  if (static_cast<int>(values.size()) != dof) {
    throw UsageError(subject, "--q: expected " + std::to_string(dof) + " joint values, got " +
                                  std::to_string(values.size()));
  }
  return Eigen::Map<VecX>(values.data(), static_cast<Eigen::Index>(values.size()));
}

VecX parseJointVector(const std::string& text, const RobotFile& robot, const std::string& subject) {
  const VecX q = parseJointVector(text, robot.dof(), subject);
  const PoeModel model = robot.poeModel();
  if (const int i = firstJointBeyondLimits(model, q); i >= 0) {
    throw UsageError(subject, "--q: q" + std::to_string(i + 1) + ": " + commands::jointValueProblem(model, i, q[i]));
  }
  return q;
}

void checkJointRows(const JointTable& table, const PoeModel& model) {
  if (table.dof != model.dof()) return;  // (a target table without seeds)
  for (size_t k = 0; k < table.rows(); ++k) {
    if (const int i = firstJointBeyondLimits(model, table.row(k)); i >= 0) {
      throw RobotFileError(table.path + ":" + std::to_string(table.lines[k]) + ": q" + std::to_string(i + 1) + ": " +
                           commands::jointValueProblem(model, i, table.row(k)[i]));
    }
  }
}

void addRobotArgument(CLI::App& sub, RobotSource& source) {
  sub.add_option("ROBOT", source.path, "robot file (.yaml), or a model (.xml MJCF, .urdf) with --tip")->required();
  sub.add_option("--tip", source.tip, "model file: the tip site or body");
  sub.add_option("--base", source.base, "model file: the base body (default: the world)");
}

namespace {

// The one error line: "error: " and the message with every control character (a newline in a file name,
// a YAML key or a --tip value) folded into a space, so the contract holds whatever the input held.
// SIGINT (Ctrl-C): the long loops poll it (lowpair/interrupt.hpp) and the command ends with exit 130 and nothing
// written (every output is written whole at the end); a second SIGINT ends the process at once.
volatile std::sig_atomic_t sigint_received = 0;

extern "C" void onSigint(int) {
  if (sigint_received) _exit(130);
  sigint_received = 1;
}

bool sigintReceived() { return sigint_received != 0; }

// validate runs worker threads that do not poll: it keeps the default SIGINT (the process ends at once)
void catchSigint(const CLI::App& sub) {
  if (sub.get_name() == "validate") return;
  std::signal(SIGINT, onSigint);
  lowpair::setInterruptCheck(&sigintReceived);
}

int reportError(const std::string& message) {
  std::cerr << io::oneLine("error: " + message) << "\n";
  return 2;
}

// Standard output that could not be written (a full disk, /dev/full, a closed pipe) is a failed command:
// exit 2 with one line, never exit 0 with the output lost. (The reason is not named: the write that failed
// may lie behind other calls, so errno no longer tells it.)
int checkedExit(int status) {
  std::cout.flush();
  const bool failed = !std::cout || std::fflush(stdout) != 0 || std::ferror(stdout);
  return failed ? reportError("stdout: cannot write") : status;
}

// The subject of an error the library raised about the subcommand's input: its first positional argument
// (the robot, scenario or model file), whatever order the options came in.
std::string inputOf(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    for (const CLI::Option* opt : sub->get_options([](const CLI::Option* o) { return o->get_positional(); })) {
      if (!opt->results().empty()) return opt->results().front();
    }
    return sub->get_name();
  }
  return "lowpair";
}

}  // namespace

}  // namespace lowpair::cli

namespace {

// An option given an empty value (`--out ''`) is refused: the subcommands read an empty value as the option not
// given, so `plan --out ''` wrote nothing at exit 0. Flags (no value) are not options with values.
void refuseEmptyValues(const CLI::App& sub) {
  for (const CLI::Option* option : sub.get_options()) {
    if (option->get_type_size() == 0) continue;
    for (const std::string& value : option->results()) {
      if (value.empty()) throw lowpair::cli::UsageError(option->get_name(), "is empty: give a value or leave the option out");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace lowpair::cli;
  using lowpair::io::RobotFileError;
  CLI::App app{"lowpair: POE and D-H kinematics of serial robots (Wu et al. 2019; Paden & Sastry 1984)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lowpair " LOWPAIR_VERSION_STRING);  // lowpair/version.hpp: the CMake project version
  Commands commands;
  addConvertCommands(app, commands);
  addJacobianCommands(app, commands);
  addValidateCommand(app, commands);
  addSimulateCommand(app, commands);
  addCalibrateCommands(app, commands);
  addExportCommand(app, commands);
  addIkCommands(app, commands);
  addPlanCommand(app, commands);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {  // prints "lowpair X.Y.Z" on stdout, exit 0
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return reportError(std::string(e.what()) + " (see lowpair --help)");
  }
  try {
    for (const auto& [sub, run] : commands) {
      if (!sub->parsed()) continue;
      refuseEmptyValues(*sub);
      catchSigint(*sub);
      return checkedExit(run());
    }
  } catch (const lowpair::Interrupted&) {
    std::cerr << "error: interrupted (SIGINT): stopped, nothing written\n";
    return 130;
  } catch (const RobotFileError& e) {
    return reportError(e.what());
  } catch (const UsageError& e) {
    return reportError(e.subject() + ": " + e.what());
  } catch (const std::filesystem::filesystem_error& e) {  // "FILE: what", the path std::filesystem names
    return reportError((e.path1().empty() ? std::string("filesystem") : e.path1().string()) + ": " +
                       e.code().message());
  } catch (const std::bad_alloc&) {  // the subcommand's input is the subject: it asked for the memory
    return reportError(inputOf(app) + ": out of memory");
  } catch (const std::invalid_argument& e) {  // the library about the subcommand's input
    const std::string subject = inputOf(app), what = e.what();
    return reportError(what.rfind(subject + ":", 0) == 0 ? what : subject + ": " + what);
  } catch (const std::exception& e) {  // a report that failed ("report: ..."): the message names its subject
    return reportError(e.what());
  }
  return 2;
}
