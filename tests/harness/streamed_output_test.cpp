// Outputs written as they are made (issue 30: 10^6 rows of `fk --q-file --json` held as one JSON document took
// 3.7 GB): writeJsonWithRows gives jsonText's bytes, writeFileAtomically with a writer is all or nothing, and
// writeMeasurements checks every row before its first byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/atomic_file.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "scratch_folder.hpp"

using namespace lowpair::io;
using nlohmann::json;

namespace {

namespace fs = std::filesystem;
using measurements_helpers::scratch;

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// writeJsonWithRows of head and rows against jsonText of the document holding them
void expectSameBytes(const json& head, const json& rows) {
  std::ostringstream streamed;
  writeJsonWithRows(streamed, head, "rows", rows.size(), [&](size_t k) { return rows[k]; });
  json document = head;
  document["rows"] = rows;
  EXPECT_EQ(streamed.str(), jsonText(document));
}

// A row as the CLI's: nested arrays and objects, a null, a string with a quote, a newline and bytes that are not
// UTF-8 (jsonText writes U+FFFD for them), a key of its own called "rows"
json row(int k) {
  return {{"line", k},
          {"q", {0.1 * k, -2.5e-17, 1e300}},
          {"T", {{1, 0}, {0, 1}}},
          {"sigma_min", nullptr},
          {"reason", "a \"quoted\"\nline \xff\xfe"},
          {"rows", json::array()},
          {"empty", json::object()}};
}

}  // namespace

TEST(StreamedJson, EqualsTheWholeDocumentByteForByte) {
  const json head = {{"a_first", "before rows"}, {"name", "x\ny"}, {"counts", {{"ok", 3}}}, {"z_last", {1, 2}}};
  expectSameBytes(head, json::array());  // "[]"
  expectSameBytes(head, json::array({row(1)}));
  expectSameBytes(head, json::array({row(1), row(2), row(3)}));
  expectSameBytes(head, json::array({1, "two", nullptr, json::array()}));  // rows that are not objects
  expectSameBytes(json::object(), json::array({row(7)}));                  // "rows" alone
  // a string of the head that reads like the key's line is not taken for it (no raw newline inside a dump)
  expectSameBytes({{"a", "\n \"rows\": []"}, {"nested", {{"rows", json::array()}}}}, json::array({row(4)}));
}

TEST(StreamedJson, RefusesAHeadThatHoldsTheKey) {
  std::ostringstream out;
  EXPECT_THROW(writeJsonWithRows(out, {{"rows", 1}}, "rows", 0, [](size_t) { return json(); }), std::invalid_argument);
  EXPECT_THROW(writeJsonWithRows(out, json::array(), "rows", 0, [](size_t) { return json(); }), std::invalid_argument);
  EXPECT_TRUE(out.str().empty());
}

TEST(StreamedFile, WritesWhatTheWriterWritesBeyondItsBuffer) {
  const std::string dir = scratch() + "/streamed";
  fs::create_directories(dir);
  const std::string path = dir + "/big.csv";
  std::string expected;
  for (int k = 0; k < 20000; ++k) expected += std::to_string(k) + ",row\n";  // 190 KB: three 64 KiB writes and more
  writeFileAtomically(path, [](std::ostream& out) {
    for (int k = 0; k < 20000; ++k) out << k << ",row\n";
  });
  EXPECT_EQ(readText(path), expected);
}

TEST(StreamedFile, AWriterThatThrowsLeavesTheTargetAndNoTemporary) {
  const std::string dir = scratch() + "/streamed_throw";
  fs::create_directories(dir);
  const std::string path = dir + "/kept.csv";
  writeFileAtomically(path, std::string("old\n"));
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << std::string(200000, 'x');  // some of it already on the temporary
                                     throw std::runtime_error("interrupted");
                                   }),
               std::runtime_error);
  EXPECT_EQ(readText(path), "old\n");
  int entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);  // no temporary left
}

TEST(StreamedFile, AFailedWriteIsNamedAndReplacesNothing) {
  try {
    writeFileAtomically(scratch() + "/no/such/folder/x.csv", [](std::ostream& out) { out << "x"; });
    ADD_FAILURE() << "no error";
  } catch (const RobotFileError& e) {
    EXPECT_NE(std::string(e.what()).find("x.csv: cannot write: "), std::string::npos) << e.what();
  }
  if (fs::exists("/dev/full")) {  // a device is written directly: the failed write is an error, not exit 0
    EXPECT_THROW(writeFileAtomically("/dev/full", [](std::ostream& out) { out << std::string(100000, 'x'); }),
                 RobotFileError);
  }
}

TEST(StreamedMeasurements, EveryRowIsCheckedBeforeTheFirstByte) {
  lowpair::Measurement good{lowpair::VecX::Zero(2), lowpair::Pose{}, -1};
  lowpair::Measurement bad{lowpair::VecX::Zero(3), lowpair::Pose{}, -1};  // another joint count, last
  std::ostringstream out;
  EXPECT_THROW(writeMeasurements(out, lowpair::Measure::Pose, {good, good, bad}, {"c"}), std::invalid_argument);
  EXPECT_TRUE(out.str().empty());
  writeMeasurements(out, lowpair::Measure::Pose, {good, good}, {"c"});
  EXPECT_EQ(out.str(), formatMeasurements(lowpair::Measure::Pose, {good, good}, {"c"}));
  EXPECT_EQ(out.str(), "# c\nq1,q2,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,1,0,0,0\n0,0,0,0,0,1,0,0,0\n");
}
