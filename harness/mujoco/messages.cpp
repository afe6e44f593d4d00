#include "mujoco/messages.hpp"

#include <atomic>
#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace lowpair::mujoco {

namespace {

thread_local std::string g_loading = "MuJoCo";

}  // namespace

std::string mujocoLine(const char* text) {
  std::string out;
  for (const char* p = text; p && *p; ++p) {
    const char ch = (*p == '\n' || *p == '\r' || *p == '\t') ? ' ' : *p;
    if (ch == ' ' && !out.empty() && out.back() == ' ') continue;
    out += ch;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

void setLoadingModel(const std::string& path) { g_loading = path; }

namespace {
std::atomic<NoteSink> g_note_sink{nullptr};
}  // namespace

NoteSink setNoteSink(NoteSink sink) { return g_note_sink.exchange(sink); }

void emitNote(const std::string& text) {
  if (const NoteSink sink = g_note_sink.load()) {
    sink(text);
  } else {
    std::fprintf(stderr, "note: %s\n", text.c_str());
  }
}

void installMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_warning = [](const char* msg) { emitNote("MuJoCo: " + mujocoLine(msg)); };
    mju_user_error = [](const char* msg) {
      std::fprintf(stderr, "error: %s: MuJoCo: %s\n", g_loading.c_str(), mujocoLine(msg).c_str());
      std::fflush(stderr);
      std::_Exit(2);
    };
  });
}

}  // namespace lowpair::mujoco
