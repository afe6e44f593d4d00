// `--out` and `--report` onto what is not a regular file (issue "rough edges", high 1): a character device
// or FIFO is written directly and stays what it was, a descriptor path reaches the descriptor, a symbolic
// link keeps being a link and its target is replaced, a socket is refused. Device nodes are made in the
// scratch folder (never the system's: on the code before the fix these tests replaced them).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <string>

#include "cli_runner.hpp"

namespace {

using lowpair_test::CliRun;
using lowpair_test::modelPath;
using lowpair_test::runCli;
using lowpair_test::scratch;
using lowpair_test::shellQuote;
namespace fs = std::filesystem;

const std::string kSimulate = "simulate " + modelPath("puma560_corke.yaml") + " --poses 3 --seed 1";

mode_t kindOf(const std::string& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0) return 0;
  return info.st_mode & S_IFMT;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A character device node in the scratch folder with the numbers of /dev/null (1, 3) or /dev/full (1, 7).
// Making one needs CAP_MKNOD (root, as CI runs); without it the test is skipped before doing anything.
bool makeDevice(const std::string& path, unsigned minor) {
  return ::mknod(path.c_str(), S_IFCHR | 0666, makedev(1, minor)) == 0;
}

TEST(OutputFiles, CharacterDeviceIsWrittenNotReplaced) {
  const std::string null_device = scratch() + "/null";
  if (!makeDevice(null_device, 3)) GTEST_SKIP() << "mknod: " << std::strerror(errno) << " (needs root)";
  const CliRun r = runCli(kSimulate + " --out " + shellQuote(null_device));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(kindOf(null_device), static_cast<mode_t>(S_IFCHR)) << "the device node was replaced";
  // no temporary left beside it
  for (const auto& entry : fs::directory_iterator(scratch())) {
    EXPECT_EQ(entry.path().filename().string().find(".null.tmp"), std::string::npos) << entry.path();
  }
}

TEST(OutputFiles, FullDeviceIsExitTwoNamingTheReason) {
  const std::string full_device = scratch() + "/full";
  if (!makeDevice(full_device, 7)) GTEST_SKIP() << "mknod: " << std::strerror(errno) << " (needs root)";
  for (const std::string& command : {kSimulate, "export " + modelPath("puma560_corke.yaml") + " --format urdf"}) {
    const CliRun r = runCli(command + " --out " + shellQuote(full_device));
    EXPECT_EQ(r.status, 2) << command;
    EXPECT_EQ(r.err, "error: " + full_device + ": cannot write: No space left on device\n") << command;
    EXPECT_EQ(kindOf(full_device), static_cast<mode_t>(S_IFCHR)) << command;
  }
}

TEST(OutputFiles, FifoIsWrittenThrough) {
  const std::string fifo = scratch() + "/pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  // the reader opens the FIFO before the writer can finish opening it
  std::future<std::string> received = std::async(std::launch::async, [&fifo] { return slurp(fifo); });
  const CliRun r = runCli(kSimulate + " --out " + shellQuote(fifo));
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string text = received.get();
  EXPECT_NE(text.find("\n# length_unit: m\n"), std::string::npos) << text;
  EXPECT_EQ(text, runCli(kSimulate).out);  // the same CSV as on standard output
  EXPECT_EQ(kindOf(fifo), static_cast<mode_t>(S_IFIFO));
}

// A descriptor path, as /dev/stdout is (a link to /proc/self/fd/1): what is written reaches the
// descriptor (here popen's pipe), and the link is not replaced by a file.
TEST(OutputFiles, DescriptorPathReachesTheDescriptor) {
  const std::string stdout_link = scratch() + "/stdout";
  fs::create_symlink("/proc/self/fd/1", stdout_link);
  const CliRun r = runCli(kSimulate + " --out " + shellQuote(stdout_link));
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string note = "3 pose measurements written to " + stdout_link + "\n";
  EXPECT_EQ(r.out, runCli(kSimulate).out + note);
  EXPECT_EQ(kindOf(stdout_link), static_cast<mode_t>(S_IFLNK));
  // standard output redirected to a file: the CSV follows what was written to it before, the note follows it
  const std::string file = scratch() + "/redirected.csv";
  const std::string command = "(echo first; " + lowpair_test::cliCommand() + " " + kSimulate + " --out " +
                              shellQuote(stdout_link) + ") > " + shellQuote(file);
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  EXPECT_EQ(slurp(file), "first\n" + runCli(kSimulate).out + note);
}

TEST(OutputFiles, SymlinkToRegularFileStaysALink) {
  const std::string target = scratch() + "/real.csv", link = scratch() + "/link.csv";
  std::ofstream(target) << "old\n";
  fs::create_symlink("real.csv", link);  // relative, as `ln -s` makes them
  const CliRun r = runCli(kSimulate + " --out " + shellQuote(link));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(kindOf(link), static_cast<mode_t>(S_IFLNK));
  EXPECT_EQ(slurp(target), runCli(kSimulate).out);
  // a dangling link: its target is created, the link kept
  const std::string dangling = scratch() + "/dangling.csv";
  fs::create_symlink("created.csv", dangling);
  EXPECT_EQ(runCli(kSimulate + " --out " + shellQuote(dangling)).status, 0);
  EXPECT_EQ(kindOf(dangling), static_cast<mode_t>(S_IFLNK));
  EXPECT_EQ(kindOf(scratch() + "/created.csv"), static_cast<mode_t>(S_IFREG));
}

// The replacement keeps the replaced file's permissions: a private file stays private (it became 644 under the
// usual umask), an executable bit stays; a new file gets 0666 less the umask.
TEST(OutputFiles, ReplacedFileKeepsItsMode) {
  for (const mode_t mode : {mode_t{0600}, mode_t{0640}, mode_t{0755}}) {
    const std::string path = scratch() + "/private.csv";
    std::ofstream(path) << "old\n";
    ASSERT_EQ(::chmod(path.c_str(), mode), 0);
    const CliRun r = runCli(kSimulate + " --out " + shellQuote(path));
    EXPECT_EQ(r.status, 0) << r.err;
    struct stat info {};
    ASSERT_EQ(::stat(path.c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 07777, mode);
    EXPECT_EQ(slurp(path), runCli(kSimulate).out);
  }
  const mode_t mask = ::umask(0);
  ::umask(mask);
  const std::string fresh = scratch() + "/fresh.csv";
  fs::remove(fresh);
  EXPECT_EQ(runCli(kSimulate + " --out " + shellQuote(fresh)).status, 0);
  struct stat info {};
  ASSERT_EQ(::stat(fresh.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, 0666 & ~mask);
}

// An empty value is refused, not read as the option not given (plan and calibrate wrote nothing at exit 0).
TEST(OutputFiles, EmptyOutIsExitTwo) {
  for (const std::string& args :
       {kSimulate, "plan " + modelPath("puma560_corke.yaml") + " --poses 3 --candidates 10",
        "fk " + modelPath("puma560_corke.yaml") + " --q 0,0,0,0,0,0"}) {
    const CliRun r = runCli(args + " --out ''");
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_EQ(r.err, "error: --out: is empty: give a value or leave the option out\n") << args;
    EXPECT_EQ(r.out, "") << args;
  }
}

TEST(OutputFiles, SocketIsRefused) {
  const std::string path = scratch() + "/socket";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0) << std::strerror(errno);
  lowpair_test::expectRejected(kSimulate + " --out " + shellQuote(path), "not a regular file, a character device or a FIFO",
                               path);
  EXPECT_EQ(kindOf(path), static_cast<mode_t>(S_IFSOCK));
  ::close(fd);
}

TEST(OutputFiles, ReportOntoADeviceIsRefusedAndKeepsIt) {
  const std::string null_device = scratch() + "/report_null";
  if (!makeDevice(null_device, 3)) GTEST_SKIP() << "mknod: " << std::strerror(errno) << " (needs root)";
  lowpair_test::expectRejected("validate " + modelPath("elbow_mls.xml") + " --tip tool --samples 100 --report " +
                                   shellQuote(null_device),
                               "not a folder", null_device);
  EXPECT_EQ(kindOf(null_device), static_cast<mode_t>(S_IFCHR));
  for (const auto& entry : fs::directory_iterator(scratch())) {
    EXPECT_EQ(entry.path().filename().string().find("report_null.partial"), std::string::npos) << entry.path();
  }
}

}  // namespace
