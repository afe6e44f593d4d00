#pragma once
// Running the `lowpair` CLI from tests: exit status, stdout and stderr of one call, a per-process
// scratch folder removed at exit, and the rejection contract (exit 2, one "error: ..." line, no stdout).
// The including target defines LOWPAIR_CLI (the binary, cli_path.hpp) and LOWPAIR_MODELS (models/).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_path.hpp"

namespace lowpair_test {

struct CliRun {
  int status = -1;
  std::string out, err;
};

// mkdtemp's template: the Xs become a unique suffix.
class ScratchDir {
 public:
  ScratchDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "lowpair_test_XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a scratch folder");
    path_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline const std::string& scratch() {
  static const ScratchDir dir;
  return dir.path();
}

inline CliRun runCli(const std::string& args) {
  const std::string err_path = scratch() + "/stderr.txt";
  const std::string cmd = cliCommand() + " " + args + " 2>" + err_path;
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_path);
  r.err.assign(std::istreambuf_iterator<char>(err), {});
  return r;
}

// (shellQuote: cli_path.hpp)

inline std::string modelPath(const std::string& name) { return std::string(LOWPAIR_MODELS) + "/" + name; }

inline std::string writeScratchFile(const std::string& name, const std::string& text) {
  const std::string path = scratch() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// Bad input: status 2, one stderr line starting "error: <subject>" and containing `what`, no stdout.
inline void expectRejected(const std::string& args, const std::string& what, const std::string& subject = "") {
  const CliRun r = runCli(args);
  EXPECT_EQ(r.status, 2) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.rfind("error: " + subject, 0), 0u) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << "expected '" << what << "' in: " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(r.out.empty()) << "partial output on error: " << r.out;
}

}  // namespace lowpair_test
