#pragma once
/// @file arguments.hpp
/// Bad arguments of a command, for the checks the CLI and the Python module share: the error, and how each
/// front end spells an argument in its messages (the CLI "--noise-position", Python "noise_position").

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

#include "io/robot_file.hpp"
#include "lowpair/calibration.hpp"

namespace lowpair::commands {

/// A usage error about an argument (not a file): printed as "error: SUBJECT: message" by the CLI, raised as
/// lowpair.Error("SUBJECT: message") by Python. SUBJECT is the argument as the front end spells it, or a file.
struct UsageError : std::runtime_error {
  UsageError(std::string subject, const std::string& message)
      : std::runtime_error(message), subject_(std::move(subject)) {}
  const std::string& subject() const { return subject_; }

 private:
  std::string subject_;
};

/// How a front end spells its arguments: a shared check names an argument by its Python name (snake_case)
/// and its messages read as the caller's own.
struct ArgumentSpelling {
  /// "noise_position" -> "--noise-position" (CLI) or "noise_position" (Python)
  std::function<std::string(const std::string& name)> name;
  /// ("measure", "targets") -> "--measure targets" (CLI) or "measure='targets'" (Python)
  std::function<std::string(const std::string& name, const std::string& value)> setting;
};

/// "pose", "position" or "targets" (measureName's words) as a Measure. @throws UsageError naming `measure`
inline Measure parseMeasure(const std::string& text, const ArgumentSpelling& spelling) {
  for (const Measure m : {Measure::Pose, Measure::Position, Measure::Targets}) {
    if (text == measureName(m)) return m;
  }
  throw UsageError(spelling.name("measure"), "expected 'pose', 'position' or 'targets', got " + io::quotedFileText(text));
}

}  // namespace lowpair::commands
