// All-or-nothing file writing (harness/atomic_file.hpp): replacing without a temporary left behind, relative
// paths, a missing folder, a folder as the target, an unwritable folder, a write that fails part way.
// The measurement CSV is in measurements_test.cpp.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "io/atomic_file.hpp"
#include "io/robot_file.hpp"
#include "scratch_folder.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

namespace {

using namespace lowpair;
namespace fs = std::filesystem;

using measurements_helpers::scratch;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string writeError(const std::string& path, const std::string& content) {
  try {
    writeFileAtomically(path, content);
  } catch (const RobotFileError& e) {
    return e.what();
  }
  return "";
}

// Names in `dir` starting with '.' (the temporaries writeFileAtomically creates).
int hiddenFiles(const std::string& dir) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(dir)) count += entry.path().filename().string()[0] == '.';
  return count;
}

}  // namespace

TEST(AtomicFile, WritesAndReplacesLeavingNoTemporary) {
  const std::string dir = scratch() + "/atomic";
  fs::create_directories(dir);
  const std::string path = dir + "/out.csv";
  writeFileAtomically(path, "first\n");
  EXPECT_EQ(readText(path), "first\n");
  writeFileAtomically(path, "second");
  EXPECT_EQ(readText(path), "second");
  writeFileAtomically(path, "");
  EXPECT_TRUE(fs::exists(path));
  EXPECT_EQ(fs::file_size(path), 0u);
  EXPECT_EQ(hiddenFiles(dir), 0);
}

TEST(AtomicFile, RelativePathInTheCurrentFolder) {
  const fs::path previous = fs::current_path();
  fs::create_directories(scratch() + "/cwd");
  fs::current_path(scratch() + "/cwd");
  writeFileAtomically("here.txt", "x");
  fs::current_path(previous);
  EXPECT_EQ(readText(scratch() + "/cwd/here.txt"), "x");
}

TEST(AtomicFile, MissingFolderThrowsAndCreatesNothing) {
  const std::string path = scratch() + "/no/such/folder/out.csv";
  EXPECT_EQ(writeError(path, "text"), path + ": cannot write: No such file or directory");
  EXPECT_FALSE(fs::exists(scratch() + "/no"));
}

TEST(AtomicFile, DirectoryTargetThrowsAndKeepsIt) {
  const std::string dir = scratch() + "/target_dir";
  fs::create_directories(dir + "/inside");
  EXPECT_EQ(writeError(dir, "text"), dir + ": cannot write: is a directory");
  EXPECT_EQ(writeError(dir + "/", "text"), dir + "/: cannot write: not a file name");
  EXPECT_TRUE(fs::is_directory(dir + "/inside"));
  EXPECT_EQ(hiddenFiles(scratch()), 0);
}

TEST(AtomicFile, UnwritableFolderThrows) {
  if (geteuid() == 0) GTEST_SKIP() << "root writes into read-only folders";
  const std::string dir = scratch() + "/read_only";
  fs::create_directories(dir);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  EXPECT_EQ(writeError(dir + "/out.csv", "text"), dir + "/out.csv: cannot write: Permission denied");
  fs::permissions(dir, fs::perms::owner_all);
  EXPECT_TRUE(fs::is_empty(dir));
}

// A full disk, simulated by a file size limit (EFBIG after a partial write): the write fails, the old
// file is untouched and the temporary is gone. In a child process, which alone gets the limit.
TEST(AtomicFile, FailedWriteKeepsTheOldFile) {
  const std::string dir = scratch() + "/full";
  fs::create_directories(dir);
  const std::string path = dir + "/out.csv";
  writeFileAtomically(path, "old content\n");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit;
    getrlimit(RLIMIT_FSIZE, &limit);
    limit.rlim_cur = 4096;
    setrlimit(RLIMIT_FSIZE, &limit);
    const std::string message = writeError(path, std::string(1 << 20, 'x'));
    _exit(message == path + ": cannot write: File too large" ? 0 : 1);
  }
  int status = 0;
  waitpid(child, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child's write did not fail as expected";
  EXPECT_EQ(readText(path), "old content\n");
  EXPECT_EQ(hiddenFiles(dir), 0);
}
