// The measurement CSV (harness/measurements.hpp): round trips, the writer's format, the reader's comments, units,
// errors and limits, columns by name (csv_columns.hpp, the joint tables of joint_table.hpp), and target
// measurements. All-or-nothing file writing is in atomic_file_test.cpp.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "io/atomic_file.hpp"
#include "io/csv_columns.hpp"
#include "io/joint_table.hpp"
#include "lowpair/se3.hpp"
#include "io/measurements.hpp"
#include "io/robot_file.hpp"
#include "random_robot.hpp"
#include "scratch_folder.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

namespace {

using namespace lowpair;
namespace fs = std::filesystem;

using measurements_helpers::scratch;

std::string writeText(const std::string& name, const std::string& text) {
  const std::string path = scratch() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The RobotFileError message reading `path`, or "" when it reads.
std::string readError(const std::string& path) {
  try {
    readMeasurements(path);
  } catch (const RobotFileError& e) {
    return e.what();
  }
  return "";
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::vector<Measurement> randomMeasurements(int count, int dof, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Measurement> out;
  for (int k = 0; k < count; ++k) {
    Measurement m;
    m.q.resize(dof);
    // magnitudes from subnormal to huge, and a negative zero: all must come back bit for bit
    for (int i = 0; i < dof; ++i) m.q[i] = unit(rng) * std::pow(10.0, 40 * unit(rng));
    m.q[0] = k == 0 ? -0.0 : k == 1 ? 4.9406564584124654e-324 : m.q[0];
    m.T_base_tool.p = lowpair_test::draw3(unit, rng) * 1e3;
    m.T_base_tool.R = expSO3(lowpair_test::draw3(unit, rng) * 3.0);
    out.push_back(m);
  }
  return out;
}

void expectRoundTrip(Measure measure) {
  const auto measurements = randomMeasurements(50, 7, 42);
  const std::string path = writeText("round_trip.csv", formatMeasurements(measure, measurements, {"a comment"}));
  const MeasurementFile file = readMeasurements(path);
  EXPECT_EQ(file.path, path);
  EXPECT_EQ(file.measure, measure);
  EXPECT_EQ(file.dof, 7);
  ASSERT_EQ(file.measurements.size(), measurements.size());
  for (size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& a = measurements[k];
    const Measurement& b = file.measurements[k];
    for (int i = 0; i < 7; ++i) EXPECT_TRUE(sameBits(a.q[i], b.q[i])) << a.q[i] << " read as " << b.q[i];
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(sameBits(a.T_base_tool.p[i], b.T_base_tool.p[i]));
    if (measure == Measure::Pose) {
      EXPECT_LT((a.T_base_tool.R - b.T_base_tool.R).cwiseAbs().maxCoeff(), 1e-14);  // through a quaternion
    } else {
      EXPECT_EQ(b.T_base_tool.R, Mat3::Identity());
    }
  }
}

}  // namespace

TEST(MeasurementCsv, PoseRoundTripIsBitExactInQAndPosition) { expectRoundTrip(Measure::Pose); }

TEST(MeasurementCsv, PositionRoundTripIsBitExact) { expectRoundTrip(Measure::Position); }

TEST(MeasurementCsv, WriterFormat) {
  Measurement m;
  m.q = Eigen::Vector2d(0.1, -2.0);
  m.T_base_tool.p = Vec3(1.0, 2.5, -3.0);
  EXPECT_EQ(formatMeasurements(Measure::Position, {m}, {"made by a test", "two\nlines", ""}),
            "# made by a test\n# two\n# lines\n#\nq1,q2,x,y,z\n0.10000000000000001,-2,1,2.5,-3\n");
  m.T_base_tool.R = expSO3(Vec3(0.0, 0.0, -M_PI / 2));
  EXPECT_EQ(formatMeasurements(Measure::Pose, {m}, {}),
            "q1,q2,x,y,z,qw,qx,qy,qz\n0.10000000000000001,-2,1,2.5,-3,0.70710678118654757,0,0,-0.70710678118654746\n");
  const Measurement different_size{Eigen::Vector3d::Zero(), Pose{}};
  EXPECT_THROW(formatMeasurements(Measure::Pose, {m, different_size}, {}), std::invalid_argument);
  EXPECT_THROW(formatMeasurements(Measure::Pose, {}, {}), std::invalid_argument);
}

// q and -q are the same rotation: the writer picks qw >= 0 (rotations near pi take Eigen's branch that
// can give qw < 0).
TEST(MeasurementCsv, QuaternionScalarIsNonNegative) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Measurement> measurements;
  for (int k = 0; k < 200; ++k) {
    const Vec3 axis = lowpair_test::draw3(unit, rng).normalized();
    measurements.push_back({Eigen::Matrix<double, 1, 1>(0.0), Pose{expSO3(axis * (M_PI - 0.5 * std::abs(unit(rng)))), Vec3::Zero()}});
  }
  std::istringstream text(formatMeasurements(Measure::Pose, measurements, {}));
  std::string line;
  std::getline(text, line);  // header
  int lines = 0;
  while (std::getline(text, line)) {
    const std::string qw = line.substr(line.find(',', line.find(',', line.find(',', line.find(',') + 1) + 1) + 1) + 1);
    EXPECT_NE(qw[0], '-') << line;
    ++lines;
  }
  EXPECT_EQ(lines, 200);
}

TEST(MeasurementCsv, CommentsBlankLinesCrlfAndByteOrderMark) {
  const std::string path = writeText("comments.csv",
                                     "\xEF\xBB\xBF# produced by hand\r\n"
                                     "\r\n"
                                     "   # indented comment\r\n"
                                     " q1 , q2 ,x, y ,z\t\r\n"
                                     "\t\r\n"
                                     "1, 2,3 ,4,5\r\n"
                                     "# between\r\n"
                                     "  -1.5e-3,.25,+7,0,-0\r\n"
                                     "#\r\n"
                                     "6,7,8,9,10");  // no line end at the end
  const MeasurementFile file = readMeasurements(path);
  EXPECT_EQ(file.measure, Measure::Position);
  EXPECT_EQ(file.dof, 2);
  ASSERT_EQ(file.measurements.size(), 3u);
  EXPECT_EQ(file.measurements[0].q, Eigen::Vector2d(1, 2));
  EXPECT_EQ(file.measurements[0].T_base_tool.p, Vec3(3, 4, 5));
  EXPECT_EQ(file.measurements[1].q, Eigen::Vector2d(-1.5e-3, 0.25));
  EXPECT_EQ(file.measurements[2].T_base_tool.p, Vec3(8, 9, 10));
}

// `# length_unit: U` states the unit of x,y,z (calibrate compares it with the nominal's); the same unit
// twice is fine, other comments that merely mention it are not read
TEST(MeasurementCsv, LengthUnitComment) {
  const std::string body = "q1,x,y,z\n0,1,2,3\n";
  EXPECT_EQ(readMeasurements(writeText("u0.csv", body)).length_unit, "");
  EXPECT_EQ(readMeasurements(writeText("u1.csv", "#   length_unit:  mm \r\n" + body + "# length_unit: mm\n")).length_unit, "mm");
  EXPECT_EQ(readMeasurements(writeText("u2.csv", "# the length_unit: is stated below\n# length_unit: m\n" + body)).length_unit,
            "m");
  // what simulate writes reads back
  Measurement m;
  m.q = VecX::Constant(1, 0.5);
  m.T_base_tool.p = Vec3(1, 2, 3);
  const std::string written = writeText("u3.csv", formatMeasurements(Measure::Position, {m}, {"made here", "length_unit: cm"}));
  EXPECT_EQ(readMeasurements(written).length_unit, "cm");
  EXPECT_TRUE(isUnitLabel("mm"));
  EXPECT_FALSE(isUnitLabel(""));
  EXPECT_FALSE(isUnitLabel("a b"));
  EXPECT_FALSE(isUnitLabel("\xC2\xB5m"));  // µm: not ASCII
  EXPECT_FALSE(isUnitLabel(std::string(17, 'm')));
}

TEST(MeasurementCsv, QuaternionIsNormalized) {
  // norm 1 + 4e-7: within 1e-6 of 1
  const std::string path = writeText("quaternion.csv", "q1,x,y,z,qw,qx,qy,qz\n0,1,2,3,0.60000024,0,0.80000032,0\n");
  const Mat3 R = readMeasurements(path).measurements[0].T_base_tool.R;
  EXPECT_LT((R.transpose() * R - Mat3::Identity()).norm(), 1e-15);
  EXPECT_NEAR(R(0, 0), 0.6 * 0.6 - 0.8 * 0.8, 1e-15);  // a turn about y: cos = qw^2 - qy^2
  EXPECT_NEAR(R(0, 2), 2 * 0.6 * 0.8, 1e-15);
}

TEST(MeasurementCsv, ErrorsNameFileAndLine) {
  const std::string header = "q1,q2,q3,q4,q5,q6,x,y,z,qw,qx,qy,qz\n";
  const std::string good = "0,0,0,0,0,0,1,2,3,1,0,0,0\n";
  struct Case {
    std::string text, error;
  };
  const Case cases[] = {
      {"# c\n\n" + header + good + good + good + "0,0,0,0,0,0,1,2,3,1,0,0\n", ":7: expected 13 numbers, got 12"},
      {header + "0,0,0,0,0,0,1,2,3,1,0,0,0,0\n", ":2: expected 13 numbers, got 14"},
      {header + good + "\n", ""},
      {"q1,foo,x,y,z\n", ": no measurements"},  // foo is ignored (csv_columns.hpp)
      {"x,y,z\n", ":1: no joint columns (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"q1,q3,x,y,z\n", ":1: missing column 'q2' (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"q1,x,y\n", ":1: missing column 'z' (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"q1,x,y,z,qw,qx,qy\n", ":1: missing column 'qz' (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"q1,x,y,z,qw,qx,qy,qz,extra\n", ": no measurements"},
      {"q1,x,z,y\n", ": no measurements"},
      {header + good + "\n\n0,0,abc,0,0,0,1,2,3,1,0,0,0\n", ":5: 'abc' is not a number"},
      {header + "0,0,,0,0,0,1,2,3,1,0,0,0\n", ":2: '' is not a number"},
      {header + "0,0,1.5x,0,0,0,1,2,3,1,0,0,0\n", ":2: '1.5x' is not a number"},
      {header + "0,0,1 2,0,0,0,1,2,3,1,0,0,0\n", ":2: '1 2' is not a number"},
      {header + "0,0,nan,0,0,0,1,2,3,1,0,0,0\n", ":2: 'nan' is not a finite number"},
      {header + "0,0,0,0,0,0,inf,2,3,1,0,0,0\n", ":2: 'inf' is not a finite number"},
      {header + "0,0,0,0,0,0,1,-Infinity,3,1,0,0,0\n", ":2: '-Infinity' is not a finite number"},
      {header + "0,0,0,0,0,0,1,2,1e999,1,0,0,0\n", ":2: '1e999' is not a finite number"},
      {header + good + good + "0,0,0,0,0,0,1,2,3,0.5,0,0,0\n", ":4: qw..qz is not a unit quaternion (norm 0.5)"},
      {header + "0,0,0,0,0,0,1,2,3,1.00001,0,0,0\n", ":2: qw..qz is not a unit quaternion (norm 1.00001)"},
      {header + "0,0,0,0,0,0,1,2,3,0,0,0,0\n", ":2: qw..qz is not a unit quaternion (norm 0)"},
      {"# only a header\n" + header, ": no measurements"},
      {"", ": no header line (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"# comments\n\n", ": no header line (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"# length_unit: mm\n" + header + good + "  #length_unit:cm\n", ":4: length_unit 'cm' after length_unit 'mm'"},
      {header + "# length_unit:\n" + good, ":2: length_unit '' is not a unit label (one token of 1-16 printable ASCII characters)"},
      {"# length_unit: milli metre\n" + header + good,
       ":1: length_unit 'milli metre' is not a unit label (one token of 1-16 printable ASCII characters)"},
  };
  for (const Case& c : cases) {
    const std::string path = writeText("m.csv", c.text);
    EXPECT_EQ(readError(path), c.error.empty() ? "" : path + c.error) << c.text;
  }
}

// Columns by name (csv_columns.hpp): shuffled, the robot's joint names, a quaternion in ROS's order
// (qx,qy,qz,qw) and extra columns give the numbers of the canonical file bit for bit.
TEST(MeasurementCsv, ColumnsAreFoundByNameInAnyOrder) {
  const std::vector<std::string> names{"shoulder", "elbow"};
  const std::string rows[] = {"0.25,-1.5,100.125,-2e-3,3.5,0.6,0,0.8,0", "1e-7,2.75,-4,5,6.0625,0.5,0.5,-0.5,0.5"};
  auto file = [&](const std::string& name, const std::string& header, const std::vector<int>& order) {
    std::string text = "# c\n" + header + "\n";
    for (const std::string& row : rows) {
      std::vector<std::string> f;
      std::stringstream in(row);
      for (std::string x; std::getline(in, x, ',');) f.push_back(x);
      for (size_t k = 0; k < order.size(); ++k) text += (k ? "," : "") + (order[k] < 0 ? std::string("any text") : f[static_cast<size_t>(order[k])]);
      text += "\n";
    }
    return writeText(name, text);
  };
  const MeasurementFile canonical = readMeasurements(file("c.csv", "q1,q2,x,y,z,qw,qx,qy,qz", {0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_TRUE(canonical.notes.empty());
  const MeasurementFile others[] = {
      readMeasurements(file("s.csv", "qz,x,q2,qw,z,q1,qy,y,qx", {8, 2, 1, 5, 4, 0, 7, 3, 6})),
      readMeasurements(file("n.csv", "elbow,shoulder,x,y,z,qw,qx,qy,qz", {1, 0, 2, 3, 4, 5, 6, 7, 8}), {}, names),
      readMeasurements(file("r.csv", "q1,q2,x,y,z,qx,qy,qz,qw", {0, 1, 2, 3, 4, 6, 7, 8, 5})),
      readMeasurements(file("e.csv", "time,q1,q2,x,y,z,qw,qx,qy,qz,comment", {-1, 0, 1, 2, 3, 4, 5, 6, 7, 8, -1}), {}, names),
  };
  for (const MeasurementFile& m : others) {
    EXPECT_EQ(m.measure, Measure::Pose) << m.path;
    EXPECT_EQ(m.dof, 2) << m.path;
    ASSERT_EQ(m.measurements.size(), canonical.measurements.size()) << m.path;
    EXPECT_EQ(m.lines, canonical.lines) << m.path;
    for (size_t k = 0; k < m.measurements.size(); ++k) {
      EXPECT_EQ(m.measurements[k].q, canonical.measurements[k].q) << m.path;
      EXPECT_EQ(m.measurements[k].T_base_tool.p, canonical.measurements[k].T_base_tool.p) << m.path;
      EXPECT_EQ(m.measurements[k].T_base_tool.R, canonical.measurements[k].T_base_tool.R) << m.path;
    }
  }
  EXPECT_EQ(canonical.measurements[1].q[0], 1e-7);  // q1 is the first number of the row in every file
  // the ignored columns: one note with the header's line
  EXPECT_EQ(others[3].notes, std::vector<std::string>{others[3].path + ":2: ignored the columns 'time', 'comment' (not a column lowpair reads)"});
  // a target file with its columns shuffled
  const MeasurementFile targets = readMeasurements(writeText("t.csv", "x,target,q2,y,z,q1\n1,smr,0.5,2,3,-0.5\n"));
  EXPECT_EQ(targets.measure, Measure::Targets);
  EXPECT_EQ(targets.target_names, std::vector<std::string>{"smr"});
  EXPECT_EQ(targets.measurements[0].q, (VecX(2) << -0.5, 0.5).finished());
  EXPECT_EQ(targets.measurements[0].T_base_tool.p, Vec3(1, 2, 3));
}

TEST(MeasurementCsv, MissingRepeatedMixedOrMisspeltColumnsAreNamed) {
  const std::vector<std::string> names{"shoulder", "elbow"};
  const std::string expected = " (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)";
  struct Case {
    std::string header, error;
  };
  const Case cases[] = {
      {"q2,x,y,z", ":2: missing column 'q1'" + expected},
      {"elbow,x,y,z", ":2: missing column 'shoulder'" + expected},
      {"q1,x,y,z,qx,qy,qz", ":2: missing column 'qw'" + expected},
      {"q1,y,z,qw,qx,qy,qz", ":2: missing column 'x'" + expected},
      {"q1,comment", ":2: missing column 'x'" + expected},
      {"q1,qw,qx,qy,qz", ":2: missing column 'x'" + expected},
      {"q1,x,y,z,y", ":2: column 'y' repeats (columns 3 and 5)"},
      {"q1,q2,q1,x,y,z", ":2: column 'q1' repeats (columns 1 and 3)"},
      {"q1,x,y,z,qw,qx,qy,qz,qw", ":2: column 'qw' repeats (columns 5 and 9)"},
      {"q1,target,x,y,z,target", ":2: column 'target' repeats (columns 2 and 6)"},
      {"shoulder,elbow,x,shoulder,y,z", ":2: column 'shoulder' repeats (columns 1 and 4)"},
      {"shoulder,q2,x,y,z", ":2: joint columns 'shoulder' and 'q2': q1..qn or the robot's joint names, not both"},
      {"x,y,z,q1,elbow", ":2: joint columns 'q1' and 'elbow': q1..qn or the robot's joint names, not both"},
      {"Q1,x,y,z", ":2: unexpected column 'Q1'" + expected},
      {"q1,x,Y,z", ":2: unexpected column 'Y'" + expected},
      {"q1,x,y,z,QW,qx,qy,qz", ":2: unexpected column 'QW'" + expected},
      {"Shoulder,elbow,x,y,z", ":2: unexpected column 'Shoulder'" + expected},
      {"q0,q1,x,y,z", ":2: unexpected column 'q0'" + expected},
      {"q01,x,y,z", ":2: unexpected column 'q01'" + expected},
      {"q1,q1001,x,y,z", ":2: more than 1000 joint columns"},
      {"q1,q99999999999999999999,x,y,z", ":2: more than 1000 joint columns"},
  };
  for (const Case& c : cases) {
    const std::string path = writeText("bad.csv", "# c\n" + c.header + "\n");
    std::string error;
    try {
      readMeasurements(path, {}, names);
    } catch (const RobotFileError& e) {
      error = e.what();
    }
    EXPECT_EQ(error, path + c.error) << c.header;
  }
  // without the robot's names, a name is just another column, ignored
  const MeasurementFile file = readMeasurements(writeText("ignored.csv", "shoulder,q1,x,y,z\nup,1,2,3,4\n"));
  EXPECT_EQ(file.notes.size(), 1u);
  EXPECT_EQ(file.measurements[0].q[0], 1.0);
}

// Joint names a header may use: every joint named, distinct, none a column name of the rule in any case.
TEST(CsvColumns, UsableJointNames) {
  const std::vector<std::string> good{"base", "shoulder", "elbow"};
  EXPECT_EQ(csvJointNames(good), good);
  for (const std::vector<std::string>& bad : std::vector<std::vector<std::string>>{
           {"base", ""}, {"a", "a"}, {"a", "X"}, {"a", "Target"}, {"a", "q2"}, {"a", "Qw"}, {"q01", "b"}}) {
    EXPECT_TRUE(csvJointNames(bad).empty()) << bad[1];
  }
}

// The joint tables of fk/simulate/compensate --q-file and ik --poses follow the same rule.
TEST(JointTableCsv, ColumnsAreFoundByName) {
  const std::vector<std::string> names{"shoulder", "elbow"};
  const JointTable joints = readJointTable(writeText("q.csv", "t,elbow,x,shoulder\n0.5,2,9,1\n"), TableKind::Joints, 2, "robot",
                                           names);
  EXPECT_EQ(joints.q, (std::vector<double>{1, 2}));
  EXPECT_EQ(joints.notes, std::vector<std::string>{joints.path + ":1: ignored the column 't' (not a column lowpair reads)"});
  const JointTable canonical = readJointTable(writeText("p.csv", "q1,q2,x,y,z,qw,qx,qy,qz\n1,2,3,4,5,0.6,0,0.8,0\n"),
                                              TableKind::Targets, 2, "robot");
  const JointTable ros = readJointTable(writeText("r.csv", "frame,qx,qy,qz,qw,z,y,x,elbow,shoulder\nf1,0,0.8,0,0.6,5,4,3,2,1\n"),
                                        TableKind::Targets, 2, "robot", names);
  EXPECT_TRUE(canonical.notes.empty());
  EXPECT_EQ(ros.notes.size(), 1u);
  EXPECT_TRUE(ros.pose);
  EXPECT_EQ(ros.q, canonical.q);
  EXPECT_EQ(ros.targets[0].p, canonical.targets[0].p);
  EXPECT_EQ(ros.targets[0].R, canonical.targets[0].R);
  auto error = [&](const std::string& text, TableKind kind) {
    const std::string path = writeText("bad.csv", text);
    try {
      readJointTable(path, kind, 2, "robot", names);
    } catch (const RobotFileError& e) {
      return std::string(e.what()).substr(path.size());
    }
    return std::string();
  };
  EXPECT_EQ(error("x,y,z\n", TableKind::Joints), ":1: no joint columns (expected q1..qn or the robot's joint names, and any other columns)");
  EXPECT_EQ(error("q1,elbow\n", TableKind::Joints), ":1: joint columns 'q1' and 'elbow': q1..qn or the robot's joint names, not both");
  EXPECT_EQ(error("q1,q2,x,x\n", TableKind::Joints), ":1: column 'x' repeats (columns 3 and 4)");
  EXPECT_EQ(error("x,y,qw\n", TableKind::Targets), ":1: missing column 'z' (expected [q1..qn,]x,y,z or [q1..qn,]x,y,z,qw,qx,qy,qz)");
  EXPECT_EQ(error("x,y,z,target\n", TableKind::Targets), ":1: unexpected column 'target' (expected [q1..qn,]x,y,z or [q1..qn,]x,y,z,qw,qx,qy,qz)");
  EXPECT_EQ(error("elbow,x,y,z\n", TableKind::Targets), ":1: missing column 'shoulder' (expected [q1..qn,]x,y,z or [q1..qn,]x,y,z,qw,qx,qy,qz)");
}

TEST(MeasurementCsv, FileErrors) {
  const std::string missing = scratch() + "/missing.csv";
  EXPECT_EQ(readError(missing), missing + ": cannot open file");
  EXPECT_EQ(readError(scratch()), scratch() + ": is a directory, not a file");
}

TEST(MeasurementCsv, LongLinesAreRejectedWithTheirLine) {
  const std::string at_limit = "#" + std::string(kMaxMeasurementLineBytes - 1, 'c');
  EXPECT_EQ(readError(writeText("long.csv", at_limit + "\r\nq1,x,y,z\n1,2,3,4\n")), "");
  const std::string path = writeText("long.csv", "q1,x,y,z\n1,2,3,4\n" + at_limit + "c\n");
  EXPECT_EQ(readError(path), path + ":3: line longer than 65536 bytes");
  const std::string no_line_end = writeText("long.csv", std::string(10 << 20, '7'));
  EXPECT_EQ(readError(no_line_end), no_line_end + ":1: line longer than 65536 bytes");
}

TEST(MeasurementCsv, BinaryJunkGivesOneShortPrintableLine) {
  std::string junk;
  for (int i = 0; i < 4096; ++i) junk += static_cast<char>((i * 37 + 11) % 256);
  junk.insert(0, "\x7f" "ELF\x01\x02\n\0\0", 9);
  for (const std::string& text : {junk, "q1,x,y,z\n" + junk, std::string("\xff\xfe" "q\0" "1,x,y,z\n", 11)}) {
    const std::string message = readError(writeText("junk.csv", text));
    ASSERT_FALSE(message.empty());
    EXPECT_LT(message.size(), scratch().size() + 140) << message;
    for (char c : message) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << "raw byte " << int(static_cast<unsigned char>(c));
  }
  const std::string path = writeText("junk.csv", "q1,x,y,z\n1,2,3,\xc3\x28" + std::string(100, 'a') + "\n");
  EXPECT_EQ(readError(path), path + ":2: '?(" + std::string(38, 'a') + "...' is not a number");
}

TEST(MeasurementCsv, JointAndMeasurementLimits) {
  std::string header;
  for (int i = 1; i <= kMaxMeasurementJoints + 1; ++i) header += "q" + std::to_string(i) + ",";
  const std::string wide = writeText("wide.csv", header + "x,y,z\n");
  EXPECT_EQ(readError(wide), wide + ":1: more than 1000 joint columns");

  std::string many = "q1,x,y,z\n";
  many.reserve(9 + 8 * (kMaxMeasurements + 1));
  for (int k = 0; k < kMaxMeasurements; ++k) many += "0,0,0,0\n";
  // the error on line 1000002 means the 1000000 measurements before it were read
  const std::string beyond = writeText("many.csv", many + "0,0,0,0\n");
  EXPECT_EQ(readError(beyond), beyond + ":1000002: more than 1000000 measurements");
}

// Target measurements (a laser tracker's SMRs): one row per target per pose, `q1..qn,target,x,y,z`.
namespace {

// `count` poses of `dof` joints, each measuring every target in `order` (indices into the names).
std::vector<Measurement> targetMeasurements(int count, int dof, const std::vector<int>& order, unsigned seed) {
  std::vector<Measurement> out;
  for (const Measurement& pose : randomMeasurements(count, dof, seed)) {
    for (const int k : order) {
      Measurement m;
      m.q = pose.q;
      m.T_base_tool.p = pose.T_base_tool.p + Vec3::Constant(0.25 * k);
      m.target = k;
      out.push_back(m);
    }
  }
  return out;
}

}  // namespace

TEST(MeasurementCsv, TargetsRoundTripIsBitExactWithNamesInOrderOfFirstAppearance) {
  // names the CSV takes as they stand (YAML and CSV specials but no comma, space or quote)
  const std::vector<std::string> names = {"smr_a", "SMR-2", "#3", "null", "~", "x;y|z", std::string(64, 'n')};
  const std::vector<int> order = {2, 0, 6, 5, 4, 3, 1};  // the file names target 2 first
  const auto measurements = targetMeasurements(20, 6, order, 11);
  const std::string path =
      writeText("targets.csv", formatMeasurements(Measure::Targets, measurements, {"length_unit: mm"}, names));
  const MeasurementFile file = readMeasurements(path);
  EXPECT_EQ(file.measure, Measure::Targets);
  EXPECT_EQ(file.dof, 6);
  EXPECT_EQ(file.length_unit, "mm");
  const std::vector<std::string> first_seen = {names[2], names[0], names[6], names[5], names[4], names[3], names[1]};
  EXPECT_EQ(file.target_names, first_seen);
  ASSERT_EQ(file.measurements.size(), measurements.size());
  for (size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& a = measurements[k];
    const Measurement& b = file.measurements[k];
    ASSERT_GE(b.target, 0);
    ASSERT_LT(static_cast<size_t>(b.target), file.target_names.size());
    EXPECT_EQ(file.target_names[static_cast<size_t>(b.target)], names[static_cast<size_t>(a.target)]) << "row " << k;
    for (int i = 0; i < 6; ++i) EXPECT_TRUE(sameBits(a.q[i], b.q[i])) << a.q[i] << " read as " << b.q[i];
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(sameBits(a.T_base_tool.p[i], b.T_base_tool.p[i]));
    EXPECT_EQ(b.T_base_tool.R, Mat3::Identity());
  }
  // the other measures leave the target unset
  EXPECT_EQ(readMeasurements(writeText("position.csv", "q1,x,y,z\n0,1,2,3\n")).measurements[0].target, -1);
  EXPECT_TRUE(readMeasurements(writeText("position.csv", "q1,x,y,z\n0,1,2,3\n")).target_names.empty());
}

TEST(MeasurementCsv, TargetsWriterFormatAndReaderTrimming) {
  Measurement m;
  m.q = Eigen::Vector2d(0.5, -2.0);
  m.T_base_tool.p = Vec3(1.0, 2.5, -3.0);
  m.target = 1;
  EXPECT_EQ(formatMeasurements(Measure::Targets, {m}, {"smr"}, {"a", "b2"}), "# smr\nq1,q2,target,x,y,z\n0.5,-2,b2,1,2.5,-3\n");
  // a name is trimmed of spaces and tabs as every field is; the same name twice is one target
  const MeasurementFile file =
      readMeasurements(writeText("trim.csv", " q1 ,target\t, x,y,z\n1, \tsmr1 ,2,3,4\n5,smr1,6,7,8\n9,smr2,0,0,0\n"));
  EXPECT_EQ(file.target_names, (std::vector<std::string>{"smr1", "smr2"}));
  ASSERT_EQ(file.measurements.size(), 3u);
  EXPECT_EQ(file.measurements[0].target, 0);
  EXPECT_EQ(file.measurements[1].target, 0);
  EXPECT_EQ(file.measurements[2].target, 1);
  EXPECT_EQ(file.measurements[1].T_base_tool.p, Vec3(6, 7, 8));
  EXPECT_EQ(file.measurements[1].q[0], 5.0);
}

TEST(MeasurementCsv, TargetsWriterRefusesWhatWouldNotReadBack) {
  Measurement m;
  m.q = VecX::Constant(1, 0.0);
  m.target = 0;
  for (const std::string& bad : {std::string(), std::string("a b"), std::string("a,b"), std::string("a\"b"),
                                 std::string("it's"), std::string(65, 'n'), std::string("\xC2\xB5m")}) {
    EXPECT_THROW(formatMeasurements(Measure::Targets, {m}, {}, {bad}), std::invalid_argument) << bad;
  }
  EXPECT_NO_THROW(formatMeasurements(Measure::Targets, {m}, {}, {std::string(64, 'n')}));
  EXPECT_THROW(formatMeasurements(Measure::Targets, {m}, {}, {"a", "a"}), std::invalid_argument);  // repeated
  EXPECT_THROW(formatMeasurements(Measure::Targets, {m}, {}, {}), std::invalid_argument);          // no name for 0
  m.target = 2;
  EXPECT_THROW(formatMeasurements(Measure::Targets, {m}, {}, {"a", "b"}), std::invalid_argument);
  m.target = -2;  // (-1, kPoseMeasurement, is a pose among target measurements: cli/known_targets_cli_test)
  EXPECT_THROW(formatMeasurements(Measure::Targets, {m}, {}, {"a"}), std::invalid_argument);
  EXPECT_THROW(formatMeasurements(Measure::Position, {m}, {}, {"a"}), std::invalid_argument);  // names, no column
  std::vector<std::string> many;
  for (int k = 0; k <= kMaxTargets; ++k) many.push_back("t" + std::to_string(k));
  m.target = 0;
  EXPECT_THROW(formatMeasurements(Measure::Targets, {m}, {}, many), std::invalid_argument);
}

TEST(MeasurementCsv, TargetsErrorsNameFileAndLine) {
  const std::string header = "q1,q2,target,x,y,z\n";
  const std::string rule = " (a target name is 1-64 printable ASCII characters without spaces, commas or quotes)";
  struct Case {
    std::string text, error;
  };
  const Case cases[] = {
      {header + "0,0,smr,1,2,3\n", ""},
      {header + "0,0,smr,1,2,3\n0,0,,1,2,3\n", ":3: target '' is empty" + rule},
      {header + "0,0,  \t ,1,2,3\n", ":2: target '' is empty" + rule},
      {header + "0,0,smr a,1,2,3\n", ":2: target 'smr a' holds a space" + rule},
      {header + "0,0,smr\"a\",1,2,3\n", ":2: target 'smr\"a\"' holds a quote" + rule},
      {header + "0,0,'a',1,2,3\n", ":2: target ''a'' holds a quote" + rule},
      {header + "0,0,\xC2\xB5m,1,2,3\n", ":2: target '??m' holds a byte outside printable ASCII" + rule},
      {header + "0,0," + std::string(64, 'n') + ",1,2,3\n", ""},
      {header + "0,0," + std::string(65, 'n') + ",1,2,3\n",
       ":2: target '" + std::string(40, 'n') + "...' has 65 characters (at most 64)" + rule},
      {header + "0,0,smr,1,2,abc\n", ":2: 'abc' is not a number"},
      {header + "0,0,smr,1,2,nan\n", ":2: 'nan' is not a finite number"},
      {header + "0,0,1,2,3\n", ":2: expected 6 fields, got 5"},
      {header + "0,0,smr,1,2,3,4\n", ":2: expected 6 fields, got 7"},
      // the header: columns by name in any order (a quaternion with a target: mixed data), names in lower case
      {"q1,x,y,z,target\n", ": no measurements"},
      {"target,q1,x,y,z\n", ": no measurements"},
      {"q1,x,target,y,z\n", ": no measurements"},
      {"q1,target,y,x,z\n", ": no measurements"},
      {"q1,target,x,y\n", ":1: missing column 'z' (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"q1,target,x,y,z,qw,qx,qy,qz\n", ": no measurements"},
      {"q1,Target,x,y,z\n", ":1: unexpected column 'Target' (expected q1..qn,x,y,z[,qw,qx,qy,qz] or q1..qn,target,x,y,z)"},
      {"q1,target,x,y,z\n", ": no measurements"},
  };
  for (const Case& c : cases) {
    const std::string path = writeText("t.csv", c.text);
    EXPECT_EQ(readError(path), c.error.empty() ? "" : path + c.error) << c.text;
  }
}

TEST(MeasurementCsv, AtMostAThousandTargetNames) {
  std::string text = "q1,target,x,y,z\n";
  for (int k = 0; k < kMaxTargets; ++k) text += "0,t" + std::to_string(k) + ",1,2,3\n";
  text += "0,t0,1,2,3\n";  // a name seen before is not one more
  const MeasurementFile file = readMeasurements(writeText("thousand.csv", text));
  EXPECT_EQ(file.target_names.size(), static_cast<size_t>(kMaxTargets));
  EXPECT_EQ(file.measurements.back().target, 0);
  const std::string path = writeText("thousand_and_one.csv", text + "0,t1000,1,2,3\n");
  EXPECT_EQ(readError(path), path + ":1003: more than 1000 distinct target names");
}
