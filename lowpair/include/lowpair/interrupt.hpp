#pragma once
/// @file interrupt.hpp
/// Cooperative interruption of long calls: an application installs a check, and the long loops (each
/// Levenberg-Marquardt iteration and reweighting of calibrate, so every fit of crossValidate; each exchange pass
/// and greedy step of planPoses; the harness's row loops) poll it between steps and throw Interrupted when it
/// says stop. The CLI's SIGINT and the Python module's Ctrl-C (KeyboardInterrupt) use it (docs/cli.md).

#include <stdexcept>

namespace lowpair {

/// True to stop the running call. Called from the thread doing the work, between steps; must be thread safe.
using InterruptCheck = bool (*)();

/// Installs `check` for the whole process (nullptr: none, the default); returns the previous one.
InterruptCheck setInterruptCheck(InterruptCheck check);

/// Thrown by a long call whose interrupt check said stop: nothing it would have returned was made.
struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted") {}
};

/// Polls the installed check. @throws Interrupted when it returns true
void pollInterrupt();

}  // namespace lowpair
