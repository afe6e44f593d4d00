// The `# length_unit` comment of a joint-value CSV (fk --q-file, simulate --q-file, compensate --q-file, ik
// --poses seeds): prismatic joint values are lengths and are converted to the robot's unit with one note;
// revolute values are rad and stay; a unit lowpair does not convert is exit 2 naming the unit and the file.
// The Stanford arm (models/stanford_corke.yaml, metres) has one prismatic joint, q3 in [0.3048, 1.27] m.
#include <gtest/gtest.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "csv_text.hpp"

namespace {

using namespace lowpair_test;
using nlohmann::json;

const std::string kStanford = modelPath("stanford_corke.yaml");

// The same joint vector twice: q3 = 0.8 m written in metres, and as 800 in a file that says mm.
const std::string kQMetres = "0.3,-0.4,0.8,0.2,0.5,-0.1";
std::string qFileInMm(const std::string& name, const std::string& unit = "mm") {
  return writeScratchFile(name, "# length_unit: " + unit + "\nq1,q2,q3,q4,q5,q6\n0.3,-0.4,800,0.2,0.5,-0.1\n");
}

std::vector<double> position(const json& T) {
  return {T[0][3].get<double>(), T[1][3].get<double>(), T[2][3].get<double>()};
}

CliRun ok(const std::string& args) {
  const CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r;
}

// Lengths differ from fk --q's by q3's conversion only: 800 x 0.001 is 0.8 to one rounding (1.1e-16 m), which
// moves the tool by as much; 1e-12 m leaves room for the FK's own rounding and fails on 800 m by 14 digits.
constexpr double kSameTool = 1e-12;

TEST(JointTableUnits, FkQFileConvertsPrismaticValuesWithANote) {
  const json single = json::parse(ok("fk " + kStanford + " --q " + kQMetres + " --json").out);
  const std::string q_file = qFileInMm("units_fk.csv");
  const CliRun r = ok("fk " + kStanford + " --q-file " + q_file + " --json");
  const json rows = json::parse(r.out)["rows"];
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(rows[0]["q"][2].get<double>(), 0.8, 1e-16);  // the value in the robot's unit
  EXPECT_DOUBLE_EQ(rows[0]["q"][0].get<double>(), 0.3);     // revolute: rad, as written
  const std::vector<double> p = position(rows[0]["T_base_tool"]), p_single = position(single["T_base_tool"]);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(p[static_cast<size_t>(i)], p_single[static_cast<size_t>(i)], kSameTool);
  EXPECT_NE(r.err.find("note: " + q_file + ": prismatic joint values converted from mm (its length_unit comment) to m "
                       "(the robot's), x 0.001"),
            std::string::npos)
      << r.err;
}

TEST(JointTableUnits, SimulateQFileConvertsPrismaticValues) {
  const std::string q_file = qFileInMm("units_simulate.csv");
  const CliRun r = ok("simulate " + kStanford + " --q-file " + q_file);
  const csv_test::Table csv = csv_test::parseTable(r.out);
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_NEAR(csv.number(0, "q3"), 0.8, 1e-16);
  const json single = json::parse(ok("fk " + kStanford + " --q " + kQMetres + " --json").out);
  const std::vector<double> p = position(single["T_base_tool"]);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(csv.number(0, std::string(1, "xyz"[i])), p[static_cast<size_t>(i)], kSameTool);
  EXPECT_NE(r.err.find("prismatic joint values converted from mm"), std::string::npos) << r.err;
}

TEST(JointTableUnits, CompensateQFileConvertsPrismaticValues) {
  // a robot compensated against itself: the joint values come back as given, in the robot's unit (a seed at
  // the solution: 0 iterations)
  const std::string q_file = qFileInMm("units_compensate.csv");
  const CliRun r = ok("compensate " + kStanford + " --nominal " + kStanford + " --q-file " + q_file + " --json");
  const json row = json::parse(r.out)["rows"][0];
  EXPECT_EQ(row["status"], "ok");
  EXPECT_NEAR(row["q"][2].get<double>(), 0.8, 1e-12);
  EXPECT_NE(r.err.find("prismatic joint values converted from mm"), std::string::npos) << r.err;
}

TEST(JointTableUnits, IkSeedsAndPositionsConvertTogether) {
  // the target and the seed of one row, both in mm: the seed is the solution, so the row is solved where it
  // starts (q3 = 0.8 m), not from a seed 800 m out
  const json single = json::parse(ok("fk " + kStanford + " --q " + kQMetres + " --json").out);
  const std::vector<double> p = position(single["T_base_tool"]);
  const std::string poses = writeScratchFile(
      "units_ik.csv", "# length_unit: mm\nq1,q2,q3,q4,q5,q6,x,y,z\n0.3,-0.4,800,0.2,0.5,-0.1," +
                          std::to_string(p[0] * 1000) + "," + std::to_string(p[1] * 1000) + "," + std::to_string(p[2] * 1000) + "\n");
  const json j = json::parse(ok("ik " + kStanford + " --poses " + poses + " --json").out);
  const json row = j["rows"][0];
  EXPECT_EQ(row["status"], "ok");
  EXPECT_NEAR(row["q"][2].get<double>(), 0.8, 1e-6);  // std::to_string keeps 1e-6 mm of the target
  ASSERT_EQ(j["notes"].size(), 1u);
  EXPECT_NE(j["notes"][0].get<std::string>().find("lengths converted from mm"), std::string::npos) << j["notes"];
}

TEST(JointTableUnits, CalibrateConvertsPrismaticValuesOfAMeasurementFileToo) {
  // the robot's own noise-free positions, written in mm (x, y, z and q3 times 1000): converted back, the nominal
  // fits them to rounding; q3 was taken as metres (800 m, far outside [0.3048, 1.27]: refused as a wrong unit)
  const csv_test::Table m = csv_test::parseTable(runCli("simulate " + kStanford + " --poses 30 --seed 4 --measure position").out);
  std::string text = "# length_unit: mm\nq1,q2,q3,q4,q5,q6,x,y,z\n";
  for (size_t k = 0; k < m.rows.size(); ++k) {
    for (const std::string column : {"q1", "q2", "q3", "q4", "q5", "q6", "x", "y", "z"}) {
      const bool length = column == "q3" || column.size() == 1;
      char buffer[40];
      std::snprintf(buffer, sizeof buffer, "%.17g", m.number(k, column) * (length ? 1000.0 : 1.0));
      text += std::string(column == "q1" ? "" : ",") + buffer;
    }
    text += "\n";
  }
  const std::string mm = writeScratchFile("units_cal_mm.csv", text);
  const json j = json::parse(ok("calibrate " + kStanford + " --measurements " + mm + " --json").out);
  ASSERT_EQ(j["notes"].size(), 1u);
  EXPECT_NE(j["notes"][0].get<std::string>().find("lengths converted from mm (its length_unit comment) to m"),
            std::string::npos);
  // the nominal against its own positions: x 1000 then x 0.001 rounds each length once or twice (a few eps of
  // 2 m); 1e-12 m fails on q3 read as metres by 14 digits
  EXPECT_LT(j["before"]["rms_position"].get<double>(), 1e-12) << j["before"];
}

TEST(JointTableUnits, RevoluteOnlyRobotConvertsNothingAndSaysNothing) {
  const std::string puma = modelPath("puma560_corke.yaml");
  const std::string q_file = writeScratchFile("units_revolute.csv", "# length_unit: mm\nq1,q2,q3,q4,q5,q6\n0.1,0.2,0.3,0.4,0.5,0.6\n");
  const CliRun r = ok("fk " + puma + " --q-file " + q_file + " --json");
  EXPECT_EQ(json::parse(r.out)["rows"][0]["q"], json::parse("[0.1,0.2,0.3,0.4,0.5,0.6]"));
  EXPECT_EQ(r.err, "");
}

TEST(JointTableUnits, AUnitLowpairDoesNotConvertIsExit2NamingItAndTheFile) {
  const std::string q_file = qFileInMm("units_furlong.csv", "furlong");
  for (const std::string& command :
       {"fk " + kStanford + " --q-file " + q_file, "simulate " + kStanford + " --q-file " + q_file,
        "compensate " + kStanford + " --nominal " + kStanford + " --q-file " + q_file}) {
    expectRejected(command, "lengths in furlong (its length_unit comment) but " + kStanford + " is in m", q_file + ": ");
  }
  // a converted value beyond 1e100 in the robot's unit: the row named
  const std::string huge = writeScratchFile("units_huge.csv", "# length_unit: km\nq1,q2,q3,q4,q5,q6\n0,0,1e99,0,0,0\n");
  expectRejected("fk " + kStanford + " --q-file " + huge, "q3 is above 1e100 in m after the unit conversion from km",
                 huge + ":3: ");
}

}  // namespace
