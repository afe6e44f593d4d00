#pragma once
// The lowpair binary a test runs: the environment's LOWPAIR_TEST_CLI when it is set, else LOWPAIR_CLI, the binary
// of the build tree the including target was built in. `make sanitize` links the test programs build/ compiled
// (their own code is not instrumented either way, tests/CMakeLists.txt) and sets LOWPAIR_TEST_CLI to the sanitized
// binary. The path is single-quoted for /bin/sh, as every argument the tests put on a command line.
#include <cstdlib>
#include <string>

namespace lowpair_test {

// A command line goes through /bin/sh (popen, system): single-quote an argument for it.
inline std::string shellQuote(const std::string& text) {
  std::string out = "'";
  for (const char ch : text) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

inline std::string cliCommand() {
  const char* env = std::getenv("LOWPAIR_TEST_CLI");
  return shellQuote(env != nullptr && *env != '\0' ? std::string(env) : std::string(LOWPAIR_CLI));
}

}  // namespace lowpair_test
