// Hostile input (issue 11): each test reproduces one finding of the attack review and fails on the code
// that had it. Input is data: it never becomes a command, and what was not measured never passes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.hpp"

namespace {

using namespace lowpair_test;
namespace fs = std::filesystem;

// The test's own shell call (cli_runner uses popen): single-quote an argument for /bin/sh.
std::string shellQuote(const std::string& text) {
  std::string out = "'";
  for (const char ch : text) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

// Finding 1: a scenario name and a report path that would break out of a quoted gnuplot string or a
// shell command line, each trying to create a marker file through gnuplot's `system`, its `!` shell
// escape, backquotes, or the shell. None may run; the report is complete.
TEST(HostileInput, ScenarioNameAndReportPathNeverRunCommands) {
  const fs::path root = fs::path(scratch()) / "injection";
  fs::create_directories(root);
  const std::string marker = (root / "PWNED").string();
  const std::string name = "evil' ; system('touch " + marker + "') ; print '\n! touch " + marker + "\n`touch " +
                           marker + "` \" ; system(\"touch " + marker + "\") ; \"";
  nlohmann::json name_yaml = name;  // a JSON string is a valid YAML double-quoted scalar
  const std::string scenario = writeScratchFile(
      "injection.yaml", "name: " + name_yaml.dump() + "\nmodel: " + modelPath("elbow_mls.xml") +
                            "\ntip: tool\nsamples: 50\n");
  const std::string report = (root / ("r';touch " + marker + ";'\"$(touch " + marker + ")\"; system")).string();

  const CliRun r = runCli("validate " + shellQuote(scenario) + " --threads 1 --report " + shellQuote(report));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(marker)) << "a command from the scenario name or the report path was executed";
  EXPECT_FALSE(fs::exists("PWNED"));
  ASSERT_TRUE(fs::is_directory(report)) << r.err;
  int pictures = 0;
  for (const auto& entry : fs::directory_iterator(report)) {
    if (entry.path().extension() == ".png" && fs::file_size(entry.path()) > 1000) ++pictures;
  }
  EXPECT_EQ(pictures, 3) << "errors, histogram and singularity-map pictures";
  std::ifstream json(fs::path(report) / "report.json");
  const auto doc = nlohmann::json::parse(json);
  EXPECT_EQ(doc["scenarios"][0]["name"], name) << "the name is reported verbatim";
}

// Finding 2: a range whose width overflows made every sample NaN, and validate passed.
TEST(HostileInput, RangeWhoseWidthOverflowsIsRejected) {
  const std::string scenario = writeScratchFile(
      "huge_range.yaml", "model: " + modelPath("elbow_mls.xml") +
                             "\ntip: tool\nsamples: 10\nranges: [[-1e308, 1e308], [0, 1], [0, 1], [0, 1], [0, 1], "
                             "[0, 1]]\n");
  expectRejected("validate " + shellQuote(scenario), "too wide", scenario);
}

}  // namespace
