#include "mujoco/messages.hpp"

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

void installMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_warning = [](const char* msg) { std::fprintf(stderr, "note: MuJoCo: %s\n", mujocoLine(msg).c_str()); };
    mju_user_error = [](const char* msg) {
      std::fprintf(stderr, "error: %s: MuJoCo: %s\n", g_loading.c_str(), mujocoLine(msg).c_str());
      std::fflush(stderr);
      std::_Exit(2);
    };
  });
}

}  // namespace lowpair::mujoco
