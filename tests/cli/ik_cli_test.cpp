// lowpair ik, compensate and fk --q-file (docs/ik.md): fk --q-file equals fk --q bit for bit, ik solves the
// targets fk --q-file writes (every row ok, checked by fk again), unreachable rows are reported per row with
// exit 1, compensation round trips through both robots' FK, and bad input is exit 2 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "csv_text.hpp"

namespace {

using namespace lowpair_test;
using nlohmann::json;
using Csv = csv_test::Table;
using csv_test::rearranged;
using csv_test::replaced;
using csv_test::split;

Csv parseCsv(const std::string& text) { return csv_test::parseTable(text); }

// The CSV lines of a data row: its fields joined again.
std::string joined(const std::vector<std::string>& fields, size_t first, size_t count) {
  std::string out;
  for (size_t i = first; i < first + count; ++i) out += (i > first ? "," : "") + fields[i];
  return out;
}

CliRun ok(const std::string& args) {
  const CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
  return r;
}

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 rotation(double w, double x, double y, double z) {
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

// The angle between two unit quaternions (scalar first) as rotations.
double angleBetween(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  const double w = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double x = a[0] * b[1] - a[1] * b[0] - a[2] * b[3] + a[3] * b[2];
  const double y = a[0] * b[2] + a[1] * b[3] - a[2] * b[0] - a[3] * b[1];
  const double z = a[0] * b[3] - a[1] * b[2] + a[2] * b[1] - a[3] * b[0];
  return 2 * std::atan2(std::sqrt(x * x + y * y + z * z), std::abs(w));
}

std::array<double, 4> quaternion(const Csv& csv, size_t row) {
  return {csv.number(row, "qw"), csv.number(row, "qx"), csv.number(row, "qy"), csv.number(row, "qz")};
}

const std::string kPuma = modelPath("puma560_corke.yaml");              // D-H, m, ranges
const std::string kOkamuraNominal = modelPath("puma560_okamura_nominal.yaml");  // POE, mm
const std::string kOkamuraActual = modelPath("puma560_okamura_actual.yaml");    // POE, mm, helical joints
const std::string kStanford = modelPath("stanford_corke.yaml");        // D-H, m, a prismatic joint

// A measurement CSV of `poses` random joint vectors of `robot` (simulate; its q columns are the input of fk
// --q-file and compensate).
std::string simulated(const std::string& robot, int poses, int seed, const std::string& name) {
  const CliRun r = ok("simulate " + robot + " --poses " + std::to_string(poses) + " --seed " + std::to_string(seed));
  return writeScratchFile(name, r.out);
}

// The target CSV without joint columns: x,y,z,qw,qx,qy,qz (or x,y,z) of every row of a measurement CSV.
std::string withoutJoints(const Csv& csv, int dof, const std::string& unit, const std::string& name) {
  std::string text = "# length_unit: " + unit + "\n" + joined(csv.header, static_cast<size_t>(dof), csv.header.size() - dof) + "\n";
  for (const auto& row : csv.rows) text += joined(row, static_cast<size_t>(dof), row.size() - dof) + "\n";
  return writeScratchFile(name, text);
}

}  // namespace

// ---- fk --q-file ------------------------------------------------------------------------------------------------------

TEST(FkQFile, EqualsFkQBitForBit) {
  // D-H and POE robot files, the file's model and the other one, a prismatic and helical joints, and a row with
  // a joint angle of 1e7 rad (beyond the sine kernel's range: libm)
  for (const std::string& robot : {kPuma, kOkamuraActual, kStanford}) {
    const Csv input = parseCsv(runCli("simulate " + robot + " --poses 12 --seed 5").out);
    std::string text = "q1,q2,q3,q4,q5,q6,x,y,z,qw,qx,qy,qz\n";
    for (const auto& row : input.rows) text += joined(row, 0, row.size()) + "\n";
    text += "1e7," + joined(input.rows[0], 1, input.rows[0].size() - 1) + "\n";
    const std::string q_file = writeScratchFile("fk_bits.csv", text);
    for (const std::string model : {"", " --model poe", " --model dh"}) {
      const json file_rows = json::parse(ok("fk " + robot + " --q-file " + q_file + " --json" + model).out)["rows"];
      const Csv csv = parseCsv(ok("fk " + robot + " --q-file " + q_file + model).out);
      ASSERT_EQ(file_rows.size(), input.rows.size() + 1);
      ASSERT_EQ(csv.rows.size(), input.rows.size() + 1);
      for (size_t k = 0; k < csv.rows.size(); ++k) {
        const std::string q = joined(csv.rows[k], 0, 6);
        const json single = json::parse(ok("fk " + robot + " --q " + q + " --json" + model).out);
        // the 4x4 matrix, every entry: JSON numbers read back bit for bit
        EXPECT_EQ(file_rows[k]["T_base_tool"], single["T_base_tool"]) << robot << model << " row " << k;
        // the CSV's position (17 digits: bit for bit) and its quaternion (the same rotation to rounding)
        const auto T = single["T_base_tool"].get<std::vector<std::vector<double>>>();
        for (int i = 0; i < 3; ++i) EXPECT_EQ(csv.number(k, std::string(1, "xyz"[i])), T[i][3]) << robot << " row " << k;
        const std::array<double, 4> qt = quaternion(csv, k);
        EXPECT_GE(qt[0], 0.0);
        EXPECT_NEAR(qt[0] * qt[0] + qt[1] * qt[1] + qt[2] * qt[2] + qt[3] * qt[3], 1.0, 4e-16);
        const Mat3 R = rotation(qt[0], qt[1], qt[2], qt[3]);
        for (int a = 0; a < 3; ++a) {
          for (int b = 0; b < 3; ++b) EXPECT_NEAR(R[a][b], T[a][b], 2e-15) << robot << " row " << k;  // a few eps each way
        }
      }
    }
  }
}

TEST(FkQFile, PositionAndTargetsAndAnIkOutputAsInput) {
  // a robot file with two targets on its tool
  std::string yaml;
  {
    std::ifstream in(kPuma);
    yaml.assign(std::istreambuf_iterator<char>(in), {});
  }
  const std::string robot = writeScratchFile("puma_targets.yaml", yaml + "targets:\n  - {name: a, point: [0.01, 0, 0.1]}\n"
                                                                        "  - {name: b, point: [0, -0.02, 0.05]}\n");
  // the q columns of another command's output are input too: q1..q6,residual,status
  const std::string q_file = writeScratchFile("fk_q_only.csv", "# joint values\nq1,q2,q3,q4,q5,q6,residual,status\n"
                                                               "0.1,0.2,-0.3,0.4,0.5,0.6,0,ok\n-1,1,-1,1,-1,1,0,ok\n");
  const Csv position = parseCsv(ok("fk " + robot + " --q-file " + q_file + " --measure position").out);
  EXPECT_EQ(position.header, split("q1,q2,q3,q4,q5,q6,x,y,z"));
  ASSERT_EQ(position.rows.size(), 2u);
  const Csv targets = parseCsv(ok("fk " + robot + " --q-file " + q_file + " --measure targets").out);
  EXPECT_EQ(targets.header, split("q1,q2,q3,q4,q5,q6,target,x,y,z"));
  ASSERT_EQ(targets.rows.size(), 4u);
  EXPECT_NE(std::find(targets.comments.begin(), targets.comments.end(), "# length_unit: m"), targets.comments.end());
  const double points[2][3] = {{0.01, 0, 0.1}, {0, -0.02, 0.05}};
  const char* qs[2] = {"0.1,0.2,-0.3,0.4,0.5,0.6", "-1,1,-1,1,-1,1"};
  for (size_t k = 0; k < 2; ++k) {
    const json T = json::parse(ok("fk " + robot + " --q " + qs[k] + " --json").out)["T_base_tool"];
    for (int i = 0; i < 3; ++i) EXPECT_EQ(position.number(k, std::string(1, "xyz"[i])), T[i][3].get<double>());
    for (size_t t = 0; t < 2; ++t) {
      const size_t row = 2 * k + t;
      EXPECT_EQ(targets.rows[row][6], t == 0 ? "a" : "b");
      for (int i = 0; i < 3; ++i) {
        const double expected = T[i][0].get<double>() * points[t][0] + T[i][1].get<double>() * points[t][1] +
                                T[i][2].get<double>() * points[t][2] + T[i][3].get<double>();
        EXPECT_NEAR(targets.number(row, std::string(1, "xyz"[i])), expected, 1e-15);
      }
    }
  }
}

TEST(FkQFile, OutWritesTheFileAndSaysSo) {
  const std::string q_file = simulated(kPuma, 4, 9, "fk_out_in.csv");
  const std::string out = scratch() + "/fk_out.csv";
  const CliRun r = ok("fk " + kPuma + " --q-file " + q_file + " --out " + out);
  EXPECT_EQ(r.out, "4 pose measurements written to " + out + "\n");
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, ok("fk " + kPuma + " --q-file " + q_file).out);
}

// ---- ik ---------------------------------------------------------------------------------------------------------------

TEST(IkCli, SolvesEveryTargetOfFkQFileFromRandomSeeds) {
  for (const std::string& robot : {kPuma, kStanford, kOkamuraActual}) {
    const std::string q_file = simulated(robot, 30, 21, "ik_q.csv");
    const Csv poses = parseCsv(ok("fk " + robot + " --q-file " + q_file).out);
    const std::string unit = robot == kOkamuraActual ? "mm" : "m";
    const std::string targets = withoutJoints(poses, 6, unit, "ik_targets.csv");
    const std::string out = scratch() + "/ik_solutions.csv";
    const CliRun r = runCli("ik " + robot + " --poses " + targets + " --out " + out);
    ASSERT_EQ(r.status, 0) << robot << "\n" << r.out << r.err;
    EXPECT_NE(r.out.find("30 ok"), std::string::npos) << r.out;
    std::ifstream in(out);
    const Csv solutions = parseCsv(std::string((std::istreambuf_iterator<char>(in)), {}));
    EXPECT_EQ(solutions.header, split("q1,q2,q3,q4,q5,q6,residual,status"));
    ASSERT_EQ(solutions.rows.size(), 30u);
    // the robot size L: 1e-10 L is the solver's default tolerance (PUMA ~0.9 m, Stanford ~1.7 m, Okamura ~900 mm)
    const double L = robot == kOkamuraActual ? 1000.0 : 2.0;
    for (size_t k = 0; k < 30; ++k) {
      EXPECT_EQ(solutions.rows[k].back(), "ok");
      EXPECT_LE(solutions.number(k, "residual"), 1e-10 * L);
    }
    // the solutions put the tool on the targets: fk --q-file of the ik output
    const Csv again = parseCsv(ok("fk " + robot + " --q-file " + out).out);
    for (size_t k = 0; k < 30; ++k) {
      double d2 = 0.0;
      for (const char* c : {"x", "y", "z"}) d2 += std::pow(again.number(k, c) - poses.number(k, c), 2);
      EXPECT_LE(std::sqrt(d2), 1e-10 * L) << robot << " row " << k;
      EXPECT_LE(angleBetween(quaternion(again, k), quaternion(poses, k)), 1e-10) << robot << " row " << k;
    }
  }
}

TEST(IkCli, RowSeedsAndPositionTargets) {
  // fk's output as it is: every row carries its q (the seed, here the solution itself)
  const std::string q_file = simulated(kPuma, 5, 22, "ik_seeded_q.csv");
  const std::string poses = writeScratchFile("ik_seeded.csv", ok("fk " + kPuma + " --q-file " + q_file).out);
  const json j = json::parse(ok("ik " + kPuma + " --poses " + poses + " --json").out);
  EXPECT_EQ(j["seeds"], "file");
  EXPECT_EQ(j["task"], "pose");
  ASSERT_EQ(j["rows"].size(), 5u);
  for (const json& row : j["rows"]) {
    EXPECT_EQ(row["status"], "ok");
    EXPECT_EQ(row["seed"], "file");
    EXPECT_EQ(row["iterations"], 0);
    EXPECT_EQ(row["reason"], "");
    EXPECT_EQ(row["rank"], 6);
    for (const char* key : {"q", "position_error", "rotation_error", "sigma_min", "line"}) EXPECT_TRUE(row.contains(key)) << key;
  }
  // x,y,z only: position targets (redundant for six joints: the minimum-norm steps)
  const Csv positions = parseCsv(ok("fk " + kPuma + " --q-file " + q_file + " --measure position").out);
  const std::string targets = withoutJoints(positions, 6, "m", "ik_positions.csv");
  const CliRun r = ok("ik " + kPuma + " --poses " + targets + " --json");
  const json p = json::parse(r.out);
  EXPECT_EQ(p["task"], "position");
  for (const json& row : p["rows"]) {
    EXPECT_EQ(row["status"], "ok");
    EXPECT_EQ(row["rotation_error"], 0.0);
  }
}

// fk --q-file and ik --poses find their columns by name (csv_columns.hpp): the robot's joint names in another
// order, a quaternion in ROS's order (qx,qy,qz,qw) and an extra column give the same output bit for bit
// (apart from the file's path), and the extra column is named in one note.
TEST(IkCli, ColumnsAreFoundByName) {
  const std::string q_file = simulated(kPuma, 5, 24, "names_q.csv");  // puma560_corke's joints are j1..j6
  const std::string q_text = ok("simulate " + kPuma + " --poses 5 --seed 24").out;
  const std::string named_q = writeScratchFile(
      "names_q_named.csv", rearranged(q_text, {{"q6", "j6"}, {"q5", "j5"}, {"", "operator"}, {"q4", "j4"}, {"q3", "j3"},
                                               {"q2", "j2"}, {"q1", "j1"}, {"x", "x"}}));
  const CliRun fk = ok("fk " + kPuma + " --q-file " + q_file), fk_named = runCli("fk " + kPuma + " --q-file " + named_q);
  EXPECT_EQ(fk_named.status, 0) << fk_named.err;
  EXPECT_EQ(replaced(fk_named.out, named_q, q_file), fk.out);
  EXPECT_EQ(fk_named.err, "note: " + named_q + ":" + std::to_string(std::count(q_text.begin(), q_text.begin() + static_cast<std::ptrdiff_t>(q_text.find("\nq1")), '\n') + 2) +
                              ": ignored the column 'operator' (not a column lowpair reads)\n");
  const std::string poses = writeScratchFile("names_poses.csv", fk.out);
  const std::string ros = writeScratchFile(
      "names_poses_ros.csv", rearranged(fk.out, {{"x", "x"}, {"y", "y"}, {"z", "z"}, {"qx", "qx"}, {"qy", "qy"}, {"qz", "qz"},
                                                 {"qw", "qw"}, {"q1", "j1"}, {"q2", "j2"}, {"q3", "j3"}, {"q4", "j4"},
                                                 {"q5", "j5"}, {"q6", "j6"}}));
  const CliRun ik = ok("ik " + kPuma + " --poses " + poses + " --json"), ik_ros = ok("ik " + kPuma + " --poses " + ros + " --json");
  EXPECT_EQ(replaced(ik_ros.out, ros, poses), ik.out);
  EXPECT_EQ(json::parse(ik.out)["seeds"], "file");
}

TEST(IkCli, UnreachableRowIsReportedAndExitsOne) {
  const std::string poses = writeScratchFile("ik_unreachable.csv",
                                             "# length_unit: m\nx,y,z,qw,qx,qy,qz\n"
                                             "0.3,0.2,0.4,1,0,0,0\n"   // line 3: reachable
                                             "10,0,0,1,0,0,0\n"        // line 4: 10 m from a 0.9 m arm
                                             "0.2,-0.3,0.3,0,1,0,0\n");
  const CliRun csv_run = runCli("ik " + kPuma + " --poses " + poses);
  EXPECT_EQ(csv_run.status, 1) << csv_run.err;
  EXPECT_TRUE(csv_run.err.empty()) << csv_run.err;
  const Csv csv = parseCsv(csv_run.out);
  ASSERT_EQ(csv.rows.size(), 3u);
  EXPECT_EQ(csv.rows[1].back(), "unreachable");
  EXPECT_GT(csv.number(1, "residual"), 8.0);
  EXPECT_NE(csv.rows[0].back(), "unreachable");
  EXPECT_NE(std::find_if(csv.comments.begin(), csv.comments.end(),
                         [](const std::string& c) { return c.find("1 unreachable") != std::string::npos; }),
            csv.comments.end());
  // the text output names the row, its line and why
  const CliRun text = runCli("ik " + kPuma + " --poses " + poses + " --out " + scratch() + "/ik_unreachable_out.csv");
  EXPECT_EQ(text.status, 1);
  EXPECT_NE(text.out.find(poses + ":4: unreachable: the target point is"), std::string::npos) << text.out;
  const json j = json::parse(runCli("ik " + kPuma + " --poses " + poses + " --json").out);
  EXPECT_EQ(j["counts"]["unreachable"], 1);
  EXPECT_EQ(j["rows"][1]["line"], 4);
  EXPECT_NE(j["rows"][1]["reason"].get<std::string>().find("reach"), std::string::npos);
}

TEST(IkCli, TargetsInAnotherUnitAreConverted) {
  const std::string q_file = simulated(kPuma, 5, 23, "ik_mm_q.csv");
  const Csv poses = parseCsv(ok("fk " + kPuma + " --q-file " + q_file).out);
  std::string text = "# length_unit: mm\nx,y,z,qw,qx,qy,qz\n";
  for (size_t k = 0; k < poses.rows.size(); ++k) {
    char line[256];
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%s\n", 1000 * poses.number(k, "x"), 1000 * poses.number(k, "y"),
                  1000 * poses.number(k, "z"), joined(poses.rows[k], 9, 4).c_str());
    text += line;
  }
  const CliRun r = runCli("ik " + kPuma + " --poses " + writeScratchFile("ik_mm.csv", text) + " --out " + scratch() + "/ik_mm_out.csv");
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("converted from mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("5 ok"), std::string::npos) << r.out;
}

TEST(IkCli, SameSeedSameSolutions) {
  const std::string q_file = simulated(kPuma, 6, 24, "ik_seed_q.csv");
  const std::string targets = withoutJoints(parseCsv(ok("fk " + kPuma + " --q-file " + q_file).out), 6, "m", "ik_seed.csv");
  const std::string seeded = ok("ik " + kPuma + " --poses " + targets + " --seed 3 --seeds 4").out;
  EXPECT_EQ(seeded, ok("ik " + kPuma + " --poses " + targets + " --seed 3 --seeds 4").out);
  // and the seed is used: another seed starts from other joint vectors, which reach other branches
  EXPECT_NE(seeded, ok("ik " + kPuma + " --poses " + targets + " --seed 4 --seeds 4").out);
}

// ---- compensate -------------------------------------------------------------------------------------------------------

TEST(CompensateCli, CalibratedRobotReproducesTheNominalPoses) {
  // nominal q -> compensated q' of the actual (calibrated) PUMA: FK_actual(q') = FK_nominal(q)
  const std::string q_file = simulated(kOkamuraNominal, 40, 31, "comp_q.csv");
  const std::string out = scratch() + "/comp_out.csv";
  const CliRun r = runCli("compensate " + kOkamuraActual + " --nominal " + kOkamuraNominal + " --q-file " + q_file + " --out " + out);
  std::ifstream in(out);
  const Csv solutions = parseCsv(std::string((std::istreambuf_iterator<char>(in)), {}));
  ASSERT_EQ(solutions.rows.size(), 40u);
  const Csv wanted = parseCsv(ok("fk " + kOkamuraNominal + " --q-file " + q_file).out);
  const Csv got = parseCsv(ok("fk " + kOkamuraActual + " --q-file " + out).out);
  int ok_rows = 0;
  for (size_t k = 0; k < 40; ++k) {
    if (solutions.rows[k].back() != "ok") continue;  // listed in the text output; a row near a boundary may fail
    ++ok_rows;
    double d2 = 0.0;
    for (const char* c : {"x", "y", "z"}) d2 += std::pow(got.number(k, c) - wanted.number(k, c), 2);
    EXPECT_LE(std::sqrt(d2), 1e-10 * 1000.0) << "row " << k;  // L ~ 900 mm
    EXPECT_LE(angleBetween(quaternion(got, k), quaternion(wanted, k)), 1e-10) << "row " << k;
  }
  EXPECT_GE(ok_rows, 38) << r.out;
  EXPECT_EQ(r.status, ok_rows == 40 ? 0 : 1);
  // position: the tool origin only
  const json j = json::parse(runCli("compensate " + kOkamuraActual + " --nominal " + kOkamuraNominal + " --q-file " + q_file +
                                    " --measure position --json")
                                 .out);
  EXPECT_EQ(j["measure"], "position");
  EXPECT_GE(j["counts"]["ok"].get<int>(), 38);
}

// ---- ik --all, compensate on the nominal branch ------------------------------------------------------------------

// 17 significant digits: reads back bit for bit
std::string exact(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

const std::string kPumaPoe = modelPath("puma560_corke_poe.yaml");
// the PUMA's lines moved by ~1e-4 rad and 1e-4 L: nearly of the spherical-wrist geometry (the file says how)
const std::string kPumaCalibrated = modelPath("../tests/data/puma560_corke_calibrated.yaml");
const std::string kUr5e = modelPath("../tests/data/ur5e.yaml");

TEST(IkAllCli, EverySolutionOfEachTargetWithItsBranch) {
  for (const std::string& robot : {kPuma, kUr5e}) {
    const Csv sim = parseCsv(ok("simulate " + robot + " --poses 6 --seed 41").out);
    const std::string targets = withoutJoints(sim, 6, "m", "all_targets.csv");
    const json j = json::parse(ok("ik " + robot + " --poses " + targets + " --all --json").out);
    EXPECT_NE(j["closed_form"], "none");
    ASSERT_EQ(j["rows"].size(), 6u);
    std::string q_text = "q1,q2,q3,q4,q5,q6\n";
    std::vector<size_t> target_of;
    for (size_t k = 0; k < 6; ++k) {
      const json& row = j["rows"][k];
      // up to 8 (the PUMA's random targets have 8; a UR's may have 4 or 6: some planar-arm distances out of reach)
      EXPECT_GE(row["count"].get<int>(), 2) << robot << " row " << k;
      EXPECT_LE(row["count"].get<int>(), 8) << robot << " row " << k;
      if (robot == kPuma) {
        EXPECT_EQ(row["count"], 8) << " row " << k;
      }
      std::set<std::string> branches;
      bool own = false;
      for (const json& s : row["solutions"]) {
        branches.insert(s["branch"].dump());
        const auto q = s["q"].get<std::vector<double>>();
        double far = 0.0;  // this solution against the simulated row's q, revolute joints modulo 2 pi
        for (size_t i = 0; i < 6; ++i) far = std::max(far, std::abs(std::remainder(q[i] - sim.number(k, "q" + std::to_string(i + 1)), 2 * M_PI)));
        own |= far <= 1e-6;
        for (size_t i = 0; i < 6; ++i) q_text += (i ? "," : "") + exact(q[i]);
        q_text += "\n";
        target_of.push_back(k);
      }
      EXPECT_EQ(branches.size(), row["solutions"].size()) << robot << " row " << k;  // every branch at most once
      EXPECT_TRUE(own) << robot << " row " << k << ": the simulated configuration is not among the solutions";
    }
    // every solution reaches its target through fk (L < 1.1 m for both: 1e-12 L)
    const Csv reached = parseCsv(ok("fk " + robot + " --q-file " + writeScratchFile("all_q.csv", q_text)).out);
    ASSERT_EQ(reached.rows.size(), target_of.size());
    for (size_t r = 0; r < target_of.size(); ++r) {
      double d2 = 0.0;
      for (const char* c : {"x", "y", "z"}) d2 += std::pow(reached.number(r, c) - sim.number(target_of[r], c), 2);
      EXPECT_LE(std::sqrt(d2), 1.1e-12) << robot << " solution " << r;
      EXPECT_LE(angleBetween(quaternion(reached, r), quaternion(sim, target_of[r])), 1e-12) << robot << " solution " << r;
    }
    // the CSV: one line per solution
    const Csv csv = parseCsv(ok("ik " + robot + " --poses " + targets + " --all").out);
    EXPECT_EQ(csv.rows.size(), target_of.size());
    EXPECT_EQ(csv.header.front(), "line");
    EXPECT_EQ(csv.header.back(), "rotation");
  }
}

TEST(IkAllCli, UnreachableTargetHasNoSolutionExit1) {
  const std::string targets = writeScratchFile("all_far.csv", "x,y,z,qw,qx,qy,qz\n0.3,0.2,0.5,1,0,0,0\n5,0,0,1,0,0,0\n");
  const CliRun r = runCli("ik " + kPuma + " --poses " + targets + " --all --json");
  EXPECT_EQ(r.status, 1) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["counts"]["without_solution"], 1);
  EXPECT_EQ(j["rows"][1]["count"], 0);
  EXPECT_GT(j["rows"][0]["count"].get<int>(), 0);
}

TEST(IkAllCli, WithoutClosedFormTheDistinctNumericalSolutions) {
  // the Panda (7 joints): no closed form; the distinct solutions of the random seeds, no branch flags
  const Csv sim = parseCsv(ok("simulate " + modelPath("panda.yaml") + " --poses 2 --seed 3").out);
  const std::string targets = withoutJoints(sim, 7, "m", "all_panda.csv");
  const json j = json::parse(ok("ik " + modelPath("panda.yaml") + " --poses " + targets + " --all --seeds 6 --json").out);
  EXPECT_EQ(j["closed_form"], "none");
  EXPECT_NE(j["closed_form_reason"].get<std::string>().find("7"), std::string::npos);
  for (const json& row : j["rows"]) {
    ASSERT_GT(row["count"].get<int>(), 0);
    for (const json& s : row["solutions"]) EXPECT_TRUE(s["branch"].is_null());
  }
}

// A program of rows crossing no singularity (the wrist centre in front of axis 1, q3 away from the stretched
// elbow at -1.52, q5 away from 0): every compensated row keeps the branch of its nominal row, which is one
// branch for the whole program, and reproduces the nominal pose.
TEST(CompensateCli, KeepsTheNominalBranchOnEveryRow) {
  std::string text = "q1,q2,q3,q4,q5,q6\n";
  const double a[6] = {0.2, 0.2, -0.9, 0.3, 0.8, 0.1}, b[6] = {1.0, 0.5, -0.3, 1.0, 1.2, 1.0};
  for (int row = 0; row <= 20; ++row) {
    for (int i = 0; i < 6; ++i) text += (i ? "," : "") + exact(a[i] + (b[i] - a[i]) * row / 20.0);
    text += "\n";
  }
  const std::string q_file = writeScratchFile("comp_branch_q.csv", text);
  const std::string args = "compensate " + kPumaCalibrated + " --nominal " + kPumaPoe + " --q-file " + q_file;
  const json j = json::parse(ok(args + " --json").out);
  EXPECT_EQ(j["branch_kept"], 21);
  EXPECT_EQ(j["counts"]["ok"], 21);
  for (const json& row : j["rows"]) EXPECT_EQ(row["branch"], j["rows"][0]["branch"]);
  // the old behaviour on request: no branch named
  const json seeded = json::parse(ok(args + " --seeded --json").out);
  EXPECT_EQ(seeded["branch_kept"], 0);
  EXPECT_FALSE(seeded["rows"][0].contains("branch"));
  // the round trip: FK of the calibrated robot at q' = FK of the nominal at q (L = 0.86 m: 1e-10 L)
  const std::string out = scratch() + "/comp_branch_out.csv";
  ok(args + " --out " + out);
  std::ifstream in(out);
  const Csv solutions = parseCsv(std::string((std::istreambuf_iterator<char>(in)), {}));
  ASSERT_EQ(solutions.rows.size(), 21u);
  const Csv wanted = parseCsv(ok("fk " + kPumaPoe + " --q-file " + q_file).out);
  const Csv got = parseCsv(ok("fk " + kPumaCalibrated + " --q-file " + out).out);
  for (size_t k = 0; k < 21; ++k) {
    double d2 = 0.0;
    for (const char* c : {"x", "y", "z"}) d2 += std::pow(got.number(k, c) - wanted.number(k, c), 2);
    EXPECT_LE(std::sqrt(d2), 1e-10 * 0.86) << "row " << k;
    EXPECT_LE(angleBetween(quaternion(got, k), quaternion(wanted, k)), 1e-10) << "row " << k;
    // the compensated joints stay next to the nominal ones (a calibration moves them by ~1e-3 rad, a branch by ~1)
    for (int i = 0; i < 6; ++i) {
      const std::string c = "q" + std::to_string(i + 1);
      EXPECT_NEAR(solutions.number(k, c), a[i] + (b[i] - a[i]) * k / 20.0, 0.01) << "row " << k << " " << c;
    }
  }
}

TEST(IkCliInput, AllNeedsPoseTargets) {
  const std::string targets = writeScratchFile("all_position.csv", "x,y,z\n0.3,0.2,0.5\n");
  expectRejected("ik " + kPuma + " --poses " + targets + " --all", "needs pose targets", "--all");
}

// ---- bad input: exit 2, one line ------------------------------------------------------------------------------------

TEST(IkCliInput, BadPosesFiles) {
  const std::string base = "ik " + kPuma + " --poses ";
  auto file = [](const std::string& name, const std::string& text) { return writeScratchFile(name, text); };
  expectRejected(base + scratch() + "/no_such.csv", "cannot open file");
  expectRejected(base + file("ik_bad_header.csv", "x,y\n1,2\n"), ":1: missing column 'z'");
  expectRejected(base + file("ik_bad_column.csv", "x,y,Z\n1,2,3\n"), ":1: unexpected column 'Z'");
  expectRejected(base + file("ik_two_x.csv", "x,y,z,x\n1,2,3,4\n"), ":1: column 'x' repeats (columns 1 and 4)");
  expectRejected(base + file("ik_bad_dof.csv", "q1,q2,x,y,z\n0,0,1,2,3\n"), ":1: has 2 joint columns but");
  expectRejected(base + file("ik_bad_number.csv", "# c\nx,y,z\n1,abc,3\n"), ":3: 'abc' is not a number");
  expectRejected(base + file("ik_hex.csv", "x,y,z\n0x1p-3,0,0\n"), "is not a decimal number");
  expectRejected(base + file("ik_nan.csv", "x,y,z\nnan,0,0\n"), "is not a finite number");
  expectRejected(base + file("ik_huge.csv", "x,y,z\n1e101,0,0\n"), "above 1e100");
  expectRejected(base + file("ik_fields.csv", "x,y,z\n1,2\n"), ":2: expected 3 fields, got 2");
  expectRejected(base + file("ik_quaternion.csv", "x,y,z,qw,qx,qy,qz\n0,0,0,1,1,0,0\n"), "not a unit quaternion");
  expectRejected(base + file("ik_empty.csv", "# nothing\n"), "no header line");
  expectRejected(base + file("ik_no_rows.csv", "x,y,z\n"), "no rows");
  expectRejected(base + file("ik_unit.csv", "# length_unit: furlong\nx,y,z\n0,0,0.5\n"), "lowpair converts only");
  expectRejected(base + file("ik_two_units.csv", "# length_unit: m\n# length_unit: mm\nx,y,z\n0,0,0.5\n"), ":2: length_unit 'mm' after");
  expectRejected(base + file("ik_long.csv", "x,y,z\n" + std::string(70000, '1') + ",0,0\n"), ":2: line longer than 65536 bytes");
  expectRejected(base + file("ik_ok.csv", "x,y,z\n0,0,0.5\n") + " --seeds 0", "--seeds");
}

TEST(IkCliInput, BadCompensateAndFkArguments) {
  const std::string q_file = writeScratchFile("comp_q_ok.csv", "q1,q2,q3,q4,q5,q6\n0,0,0,0,0,0\n");
  expectRejected("compensate " + kOkamuraActual + " --nominal " + modelPath("panda.yaml") + " --q-file " + q_file,
                 "has 6 joints but --nominal");
  expectRejected("compensate " + kOkamuraActual + " --nominal " + kPuma + " --q-file " + q_file, "compensation needs one unit");
  expectRejected("compensate " + kOkamuraActual + " --nominal " + kOkamuraNominal + " --q-file " +
                     writeScratchFile("comp_no_q.csv", "x,y,z\n0,0,0\n"),
                 ":1: no joint columns");
  expectRejected("compensate " + kOkamuraActual + " --nominal " + kOkamuraNominal + " --q-file " + q_file + " --measure targets",
                 "--measure");
  expectRejected("fk " + kPuma + " --q 0,0,0,0,0,0 --q-file " + q_file, "excludes");
  expectRejected("fk " + kPuma, "give --q");
  expectRejected("fk " + kPuma + " --q 0,0,0,0,0,0 --measure position", "--out and --measure go with --q-file");
  expectRejected("fk " + kPuma + " --q-file " + q_file + " --measure targets", "lists no targets");
  expectRejected("fk " + kPuma + " --q-file " + writeScratchFile("fk_bad_dof.csv", "q1,q2,q3,x\n0,0,0,1\n"),
                 ":1: has 3 joint columns but");
}
