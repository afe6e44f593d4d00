#pragma once
/// @file messages.hpp
/// MuJoCo's messages as lowpair prints them: on one line, and through handlers that keep stdout clean.

#include <string>

namespace lowpair::mujoco {

/// A MuJoCo message (its load errors and warnings span several lines) on one line: newlines, carriage returns
/// and tabs become spaces, runs of spaces one space, trailing spaces dropped. nullptr gives "".
std::string mujocoLine(const char* text);

/// MuJoCo's default handlers print to stdout (breaking --json) and append to MUJOCO_LOG.TXT in the working
/// directory. Ours, installed once per process: a warning is one "note: MuJoCo: ..." line on stderr; a fatal
/// error (MuJoCo must not continue after one) is the CLI's one "error: FILE: MuJoCo: ..." line and exit status 2,
/// FILE the model this thread is loading (setLoadingModel).
void installMujocoHandlers();

/// The model this thread loads, named by the fatal-error handler (which gets no context from MuJoCo).
void setLoadingModel(const std::string& path);

/// Where the loader's notes go (MuJoCo's warnings, what a model copy dropped), one sentence each without
/// "note: ": by default a "note: TEXT" line on stderr; the Python module collects them and issues warnings.
using NoteSink = void (*)(const std::string& text);
/// Installs `sink` for the whole process (nullptr: stderr); returns the previous one.
NoteSink setNoteSink(NoteSink sink);
/// Sends a note to the installed sink.
void emitNote(const std::string& text);

}  // namespace lowpair::mujoco
