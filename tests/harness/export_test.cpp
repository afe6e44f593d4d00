// lowpair export (harness/export.hpp): every format read back by an independent reader gives the model's
// forward kinematics to 1e-12 L (translation) and 1e-12 rad:
//   MJCF -> MuJoCo (MujocoRobot), URDF -> MuJoCo and urdfdom (readUrdf), POE and D-H files -> readRobotFile,
// for every bundled robot, 1,000 seeded random robots of every joint type, a calibrated
// PUMA, tool orientations at and near gimbal lock, and hostile names; then the URDF twins in models/.
// MuJoCo 2.2.2 has no URDF <mimic>, so a URDF with helical joints is read back by urdfdom only.
// The URDF/MJCF joint variable is the motion x = scale (q + offset): MuJoCo and urdfdom are evaluated at x,
// the model at q. The robot files' `targets:`, which the same writers write, are in robot_file_targets_test.cpp.

#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <algorithm>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/export.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "random_robot.hpp"
#include "scratch_folder.hpp"
#include "io/robot_file.hpp"
#include "io/urdf_reader.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::mujoco;

namespace lowpair {
namespace {

namespace fs = std::filesystem;

using export_helpers::scratch;

constexpr double kTolerance = 1e-12;  // rad, and times L for translations
const int kRandomRobots = lowpair_test::robotCount(1000);
const int kRandomRobotsMujoco = kRandomRobots;  // all of them: two MuJoCo loads each, ~9 s of the ~12 s
constexpr int kConfigurations = 8;

// The largest errors seen by one kind of read-back, printed at the end of a test.
struct Worst {
  std::string what;
  double rotation = 0.0, translation = 0.0;  // rad, and relative to L
  long long poses = 0;
  void add(double r, double t_over_L) {
    rotation = std::max(rotation, r);
    translation = std::max(translation, t_over_L);
    ++poses;
  }
  void print() const {
    std::printf("  %-34s %7lld poses: worst rotation %.3g rad, translation %.3g L\n", what.c_str(), poses, rotation,
                translation);
  }
};

Pose fk(const PoeModel& model, const VecX& q) {
  Data data(model);
  forwardKinematics(model, data, q);
  return data.T_base_tool;
}

Pose fk(const DhModel& model, const VecX& q) {
  Data data(model);
  forwardKinematics(model, data, q);
  return data.T_base_tool;
}

VecX motionOf(const PoeModel& model, const VecX& q) {
  VecX x(q.size());
  for (int i = 0; i < model.dof(); ++i) x[i] = model.joint(i).motion(q[i]);
  return x;
}

// Expects `T` equal to `reference` to the tolerance; records the error.
void expectPose(const Pose& reference, const Pose& T, double L, Worst& worst, const std::string& where) {
  const double r = rotationError(reference.R, T.R), t = (reference.p - T.p).norm() / L;
  worst.add(r, t);
  EXPECT_LE(r, kTolerance) << where << ": rotation";
  EXPECT_LE(t, kTolerance) << where << ": translation / L";
}

std::vector<VecX> configurations(const PoeModel& model, std::mt19937_64& rng) {
  std::vector<VecX> qs;
  VecX zero = VecX::Zero(model.dof());
  qs.push_back(zero);
  for (int k = 0; k < kConfigurations; ++k) qs.push_back(lowpair_test::randomConfiguration(model, rng));
  return qs;
}

// The read-backs of one model. `tag` names the files; `mujoco` whether to load them in MuJoCo.
struct RoundTrip {
  Worst poe{"poe file (readRobotFile)"}, dh{"dh file vs POE (well-conditioned)"},
      dh_table{"dh file vs table (relative to scale)"}, mjcf{"mjcf (MuJoCo)"},
      urdf_mujoco{"urdf (MuJoCo)"}, urdf_dom{"urdf (urdfdom, readUrdf)"};
  int dh_frames = 0, line_frames = 0, urdf_mimic_refused = 0;
  void print() const {
    for (const Worst* w : {&poe, &dh_table, &dh, &mjcf, &urdf_mujoco, &urdf_dom}) w->print();
    std::printf("  frames: %d robots with D-H frames, %d with frames on the joint lines\n", dh_frames, line_frames);
    if (urdf_mimic_refused > 0) {
      std::printf("  %d URDFs with helical joints not read by MuJoCo (2.2.2 ignores <mimic>; MujocoRobot refuses them)\n",
                  urdf_mimic_refused);
    }
  }
};

void roundTrip(const RobotFile& file, const std::string& tag, bool mujoco, std::mt19937_64& rng, RoundTrip& out) {
  const PoeModel model = file.poeModel();
  const double L = model.lengthScale();
  const std::vector<VecX> qs = configurations(model, rng);
  std::vector<Pose> reference;
  for (const VecX& q : qs) reference.push_back(fk(model, q));
  const std::vector<std::string> comments = {"export_test " + tag};
  const bool well_conditioned = exportFrames(motionModel(model)).dh;
  (well_conditioned ? out.dh_frames : out.line_frames)++;

  // POE and D-H robot files: the same joint variable q
  for (ExportFormat f : {ExportFormat::Poe, ExportFormat::Dh}) {
    const std::string path = scratch().write(tag + "." + exportFormatName(f) + ".yaml", exportRobot(file, f, comments).text);
    const RobotFile back = readRobotFile(path);
    ASSERT_EQ(back.dof(), model.dof()) << path;
    ASSERT_EQ(f == ExportFormat::Dh, back.dh.has_value()) << path;
    const PoeModel m = back.poeModel();
    for (int i = 0; i < model.dof(); ++i) {
      const Joint &a = model.joint(i), &b = m.joint(i);
      EXPECT_EQ(a.type, b.type) << path << " joint " << i + 1;
      EXPECT_EQ(a.name, b.name) << path << " joint " << i + 1;
      EXPECT_NEAR(a.scale, b.scale, 4e-16 * a.scale) << path << " joint " << i + 1;
      ASSERT_EQ(a.range.has_value(), b.range.has_value()) << path << " joint " << i + 1;
      if (a.range) {
        const double unit = std::max({1.0, std::abs((*a.range)[0]), std::abs((*a.range)[1])});
        EXPECT_NEAR((*a.range)[0], (*b.range)[0], 4e-16 * unit) << path;
        EXPECT_NEAR((*a.range)[1], (*b.range)[1], 4e-16 * unit) << path;
      }
    }
    if (f == ExportFormat::Poe) {
      for (size_t k = 0; k < qs.size(); ++k) expectPose(reference[k], fk(*back.poe, qs[k]), L, out.poe, path);
      continue;
    }
    // the D-H file is poeToDh's table, read back to rounding of its own numbers (|d| up to ~L / angle for
    // nearly parallel axes); where the table is well conditioned (ExportFrames::dh) it also gives the POE FK
    const DhConversion table = poeToDh(model);
    for (size_t k = 0; k < qs.size(); ++k) {
      const Pose T = fk(*back.dh, qs[k]);
      expectPose(fk(table.model, qs[k]), T, table.scale, out.dh_table, path);
      if (well_conditioned) {
        expectPose(reference[k], T, L, out.dh, path);
      }
    }
  }

  // URDF and MJCF: the motion x. The URDF is in metres (a robot file in mm or cm converted): its reference
  // is the model in metres, at the same q
  const PoeModel metres = file.length_unit.empty() || file.length_unit == "m" ? model : inMetres(file).poeModel();
  const double L_metres = metres.lengthScale();
  std::vector<Pose> reference_metres;
  for (const VecX& q : qs) reference_metres.push_back(fk(metres, q));
  const std::string urdf = scratch().write(tag + ".urdf", exportRobot(file, ExportFormat::Urdf, comments).text);
  {
    const RobotFile back = readUrdf(urdf, "tool");
    const PoeModel& m = *back.poe;
    ASSERT_EQ(m.dof(), model.dof()) << urdf;
    for (int i = 0; i < model.dof(); ++i) EXPECT_EQ(m.joint(i).type, model.joint(i).type) << urdf << " joint " << i + 1;
    for (size_t k = 0; k < qs.size(); ++k) {
      expectPose(reference_metres[k], fk(m, motionOf(metres, qs[k])), L_metres, out.urdf_dom, urdf);
    }
  }
  if (!mujoco) return;
  const std::string mjcf = scratch().write(tag + ".xml", exportRobot(file, ExportFormat::Mjcf, comments).text);
  const bool helical = std::any_of(model.joints().begin(), model.joints().end(),
                                   [](const Joint& j) { return j.type == JointType::Helical; });
  for (const std::string& path : {mjcf, urdf}) {
    std::unique_ptr<MujocoRobot> robot;
    try {
      robot = std::make_unique<MujocoRobot>(path, "tool");
    } catch (const RobotFileError& e) {
      // MuJoCo 2.2.2 has no <mimic>: a URDF screw would be two independent joints there, which MujocoRobot
      // refuses; such a URDF is checked through urdfdom above
      const bool mimic = path == urdf && helical && std::string(e.what()).find("mimic") != std::string::npos;
      EXPECT_TRUE(mimic) << e.what();
      out.urdf_mimic_refused += mimic;
      continue;
    }
    ASSERT_EQ(robot->dof(), model.dof()) << path;
    for (int i = 0; i < model.dof(); ++i) {
      EXPECT_EQ(robot->joints()[static_cast<size_t>(i)].type, model.joint(i).type) << path << " joint " << i + 1;
    }
    if (path == mjcf) {
      const PoeModel motion = motionModel(model);
      for (int i = 0; i < model.dof(); ++i) {  // MJCF ranges are the motion's
        const auto& want = motion.joint(i).range;
        const auto& got = robot->joints()[static_cast<size_t>(i)].range;
        ASSERT_EQ(want.has_value(), got.has_value()) << path << " joint " << i + 1;
        if (want) {
          EXPECT_EQ(*want, *got) << path << " joint " << i + 1;
        }
      }
    }
    MujocoRobot::Evaluator evaluator(*robot);
    for (size_t k = 0; k < qs.size(); ++k) {
      if (path == mjcf) {
        expectPose(reference[k], evaluator.tipPose(motionOf(model, qs[k])), L, out.mjcf, path);
      } else {
        expectPose(reference_metres[k], evaluator.tipPose(motionOf(metres, qs[k])), L_metres, out.urdf_mujoco, path);
      }
    }
  }
}

// Every bundled robot: models/*.yaml, and models/*.xml read through MuJoCo with --tip tool.
std::vector<RobotFile> bundledRobots() {
  std::vector<std::string> paths;
  for (const auto& e : fs::directory_iterator(LOWPAIR_MODELS)) paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  std::vector<RobotFile> robots;
  for (const std::string& path : paths) {
    const std::string ext = fs::path(path).extension().string();
    if (ext == ".yaml" && path.find(".joint_variables.") == std::string::npos) {
      robots.push_back(readRobotFile(path));
    } else if (ext == ".xml") {
      RobotFile file;
      file.path = path;
      file.name = fs::path(path).stem().string();
      file.poe = MujocoRobot(path, "tool").poeModel();
      robots.push_back(file);
    }
  }
  return robots;
}

TEST(ExportRoundTrip, EveryBundledRobotInEveryFormat) {
  std::mt19937_64 rng(10);
  RoundTrip worst;
  int count = 0;
  for (const RobotFile& file : bundledRobots()) {
    SCOPED_TRACE(file.path);
    roundTrip(file, "bundled_" + fs::path(file.path).filename().string(), true, rng, worst);
    ++count;
  }
  EXPECT_GE(count, 16);
  std::printf("bundled robots: %d\n", count);
  worst.print();
  EXPECT_EQ(worst.line_frames, 0) << "every bundled robot's URDF/MJCF has D-H frames";
}

TEST(ExportRoundTrip, RandomRobotsOfEveryJointType) {
  std::mt19937_64 rng(20261124);
  RoundTrip worst;
  std::map<JointType, int> types;
  const auto start = std::chrono::steady_clock::now();
  for (int r = 0; r < kRandomRobots; ++r) {
    const lowpair_test::RandomRobot robot = lowpair_test::randomRobot(rng);
    RobotFile file;
    file.path = "random" + std::to_string(r);
    file.name = "random-" + std::to_string(r) + "-" + lowpair_test::geometryName(robot.geometry);
    file.angle_unit = (r % 2) ? "deg" : "rad";  // the D-H and POE writers convert angles, ranges and pitch
    file.length_unit = "mm";
    file.poe = robot.model;
    for (const Joint& j : robot.model.joints()) types[j.type]++;
    SCOPED_TRACE(file.name);
    roundTrip(file, "random" + std::to_string(r), r < kRandomRobotsMujoco, rng, worst);
    if (HasFatalFailure()) return;
  }
  std::printf("random robots: %d (%d through MuJoCo) in %.1f s\n", kRandomRobots, kRandomRobotsMujoco,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  worst.print();
  EXPECT_GT(types[JointType::Revolute], 0);
  EXPECT_GT(types[JointType::Prismatic], 0);
  EXPECT_GT(types[JointType::Helical], 0);
  EXPECT_GT(worst.dh_frames, 0);
  EXPECT_GT(worst.line_frames, 0) << "nearly parallel axes take the joint-line frames";
}

// The tool frame's rotation at and near URDF's gimbal lock (pitch +-pi/2), and at yaw/roll +-pi.
TEST(ExportRoundTrip, ToolRotationsAtAndNearGimbalLock) {
  std::mt19937_64 rng(3);
  RoundTrip worst;
  int k = 0;
  for (double pitch : {M_PI / 2, -M_PI / 2, M_PI / 2 - 1e-9, -M_PI / 2 + 1e-12, M_PI / 2 - 1e-5, 0.0}) {
    for (double yaw : {0.0, 0.7, M_PI, -2.5}) {
      for (double roll : {0.0, -1.2, M_PI}) {
        const Mat3 R = (Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                        Eigen::AngleAxisd(roll, Vec3::UnitX())).toRotationMatrix();
        JointSpec a, b;
        a.twist << 0, 0, 1, 0, 0, 0;
        b.twist << 0, 1, 0, -0.5, (k % 2) * 0.3, 0.2;  // about y through (0.2, 0, 0.5); helical (pitch 0.3) every other
        Pose tool;
        tool.R = R;
        tool.p = Vec3(0.3, -0.2, 0.9);
        RobotFile file;
        file.path = "gimbal" + std::to_string(k);
        file.poe = PoeModel({a, b}, tool);
        roundTrip(file, "gimbal" + std::to_string(k++), true, rng, worst);
      }
    }
  }
  worst.print();
}

// The paper's case: the nominal PUMA calibrated against the actual one (free pitch, noise-free) has
// scales != 1; its URDF (joint variable x) gives the calibrated model's FK.
TEST(ExportRoundTrip, CalibratedPumaToUrdfAndMjcf) {
  const RobotFile nominal = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_okamura_nominal.yaml");
  const PoeModel actual = readRobotFile(std::string(LOWPAIR_MODELS) + "/puma560_okamura_actual.yaml").poeModel();
  std::mt19937_64 rng(5);
  std::vector<Measurement> ms;
  for (int k = 0; k < 50; ++k) {
    Measurement m;
    m.q = lowpair_test::randomConfiguration(actual, rng);
    m.T_base_tool = fk(actual, m.q);
    ms.push_back(m);
  }
  CalibrationOptions options;
  options.free_pitch = true;
  const CalibrationResult result = calibrate(nominal.poeModel(), ms, options);
  RobotFile calibrated = nominal;
  calibrated.path = "calibrated-puma";
  calibrated.poe = result.model;
  ASSERT_TRUE(needsJointVariables(result.model)) << "calibration identifies scales";
  // the calibration is good (the URDF then also reproduces the actual robot)
  for (const Measurement& m : ms) EXPECT_LT((fk(result.model, m.q).p - m.T_base_tool.p).norm(), 1e-6);

  RoundTrip worst;
  roundTrip(calibrated, "calibrated_puma", true, rng, worst);
  worst.print();
  // the joint-variable file comes with it and reads back as the calibrated model
  const ExportedRobot exported = exportRobot(calibrated, ExportFormat::Urdf, {});
  ASSERT_TRUE(exported.joint_variables.has_value());
  const PoeModel variables =
      readRobotFile(scratch().write("calibrated_puma.joint_variables.yaml", *exported.joint_variables)).poeModel();
  for (int i = 0; i < variables.dof(); ++i) {
    EXPECT_NEAR(variables.joint(i).scale, result.model.joint(i).scale, 1e-15);
    EXPECT_NEAR(variables.joint(i).offset, result.model.joint(i).offset, 1e-15);
  }
}

TEST(ExportJointVariables, OnlyWhenSomeScaleOrOffsetDiffers) {
  const auto file = [](const char* name) { return readRobotFile(std::string(LOWPAIR_MODELS) + "/" + name); };
  EXPECT_FALSE(needsJointVariables(file("puma560_okamura_nominal.yaml").poeModel()));
  EXPECT_TRUE(needsJointVariables(file("puma560_okamura_actual.yaml").poeModel()));  // |w| != 1
  EXPECT_FALSE(exportRobot(file("panda.yaml"), ExportFormat::Mjcf, {}).joint_variables.has_value());
  EXPECT_TRUE(exportRobot(file("puma560_okamura_actual.yaml"), ExportFormat::Mjcf, {}).joint_variables.has_value());
  EXPECT_FALSE(exportRobot(file("puma560_okamura_actual.yaml"), ExportFormat::Poe, {}).joint_variables.has_value());
  EXPECT_EQ(jointVariablesPath("out/robot.urdf"), "out/robot.joint_variables.yaml");
  EXPECT_EQ(jointVariablesPath("robot.xml"), "robot.joint_variables.yaml");
  // an offset alone
  RobotFile f = file("panda.yaml");
  std::vector<Joint> joints = f.poe->joints();
  joints[2].offset = 0.25;
  f.poe = PoeModel(joints, f.poe->toolPose());
  EXPECT_TRUE(needsJointVariables(*f.poe));
  const PoeModel motion = motionModel(*f.poe);
  EXPECT_EQ(motion.joint(2).offset, 0.0);
  EXPECT_EQ((*motion.joint(2).range)[0], -2.8973 + 0.25);
}

// ---- names ------------------------------------------------------------------------------------------

// Every element's attributes, for checking names.
void collect(const tinyxml2::XMLElement* e, std::multimap<std::string, std::string>& out) {
  for (; e; e = e->NextSiblingElement()) {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      out.emplace(std::string(e->Name()) + "@" + a->Name(), a->Value());
    }
    collect(e->FirstChildElement(), out);
  }
}

TEST(ExportNames, HostileNamesGiveValidXmlWithSafeUniqueNames) {
  const std::vector<std::string> hostile = {"j\"1'", "<j2>&amp;", "tool", "base\n--><evil/>", "j\"1'", "", "\xff\xfe",
                                            "tool_joint"};
  std::vector<JointSpec> specs(hostile.size());
  for (size_t i = 0; i < hostile.size(); ++i) {
    specs[i].name = hostile[i];
    const Vec3 w = Vec3(i % 3 == 0, i % 3 == 1, i % 3 == 2);
    const Vec3 p(0.1 * i, 0.2, -0.1 * i);
    specs[i].twist << w, p.cross(w) + (i % 2 ? 0.05 : 0.0) * w;  // every other joint helical
    if (i == 5) specs[i].twist << Vec3::Zero(), w;  // a prismatic joint
  }
  RobotFile file;
  file.path = "hostile --> \"path\" <&>\n";
  file.name = "robot\"<name>&\n--";
  file.description = "desc -- with \x01 control and \xc3\x28 bad UTF-8 -->";
  file.poe = PoeModel(specs, Pose());
  const std::vector<std::string> comments = {"made by -- a test -->", "line\nbreak"};
  for (ExportFormat f : {ExportFormat::Urdf, ExportFormat::Mjcf}) {
    const std::string text = exportRobot(file, f, comments).text;
    tinyxml2::XMLDocument doc;
    ASSERT_EQ(doc.Parse(text.c_str()), tinyxml2::XML_SUCCESS) << doc.ErrorStr() << "\n" << text;
    std::multimap<std::string, std::string> attributes;
    collect(doc.RootElement(), attributes);
    std::set<std::string> names;
    int joints = 0;
    for (const auto& [key, value] : attributes) {
      const bool is_name = key == "joint@name" || key == "link@name" || key == "body@name" || key == "site@name";
      if (!is_name) continue;
      EXPECT_EQ(value.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-."),
                std::string::npos)
          << value;
      EXPECT_TRUE(names.insert(value).second) << "duplicate name " << value;
      joints += key == "joint@name";
    }
    EXPECT_TRUE(names.count("base")) << text;
    EXPECT_TRUE(names.count("tool")) << text;
    // the robot name survives, escaped by tinyxml2 (a newline becomes a space)
    const char* robot_name = doc.RootElement()->Attribute(f == ExportFormat::Urdf ? "name" : "model");
    ASSERT_NE(robot_name, nullptr);
    EXPECT_EQ(std::string(robot_name), "robot\"<name>& --");
    if (f == ExportFormat::Urdf) {
      EXPECT_EQ(joints, 8 + 3 + 1);  // 8 joints, 3 mimic slides (joints 2, 4, 8 are helical), the tool joint
      const std::string path = scratch().write("hostile.urdf", text);
      EXPECT_EQ(readUrdf(path, "tool").poe->dof(), 8);
    } else {
      const std::string path = scratch().write("hostile.xml", text);
      EXPECT_EQ(MujocoRobot(path, "tool").dof(), 8);
    }
  }
  // POE and D-H files keep the names as they are (yaml-cpp quotes and escapes them)
  for (ExportFormat f : {ExportFormat::Poe, ExportFormat::Dh}) {
    const std::string path =
        scratch().write(std::string("hostile.") + exportFormatName(f) + ".yaml", exportRobot(file, f, comments).text);
    const RobotFile back = readRobotFile(path);
    // (yaml-cpp writes an invalid UTF-8 byte as U+FFFD)
    const std::string fffd = "\xEF\xBF\xBD";
    EXPECT_EQ(back.name, file.name);
    EXPECT_EQ(back.description, "desc -- with \x01 control and " + fffd + "( bad UTF-8 -->");
    for (size_t i = 0; i < hostile.size(); ++i) {
      if (i != 6) {  // 6: invalid UTF-8
        EXPECT_EQ(back.poeModel().joint(static_cast<int>(i)).name, hostile[i]);
      }
    }
  }
}

TEST(ExportFormat, Names) {
  for (ExportFormat f : {ExportFormat::Urdf, ExportFormat::Mjcf, ExportFormat::Poe, ExportFormat::Dh}) {
    EXPECT_EQ(parseExportFormat(exportFormatName(f)), f);
  }
  EXPECT_THROW(parseExportFormat("sdf"), std::invalid_argument);
}

// ---- the URDF twins in models/ ----------------------------------------------------------------------

// models/<robot>.urdf, made by `lowpair export models/<robot>.yaml --format urdf --out models/<robot>.urdf`:
// robot file, MJCF (the robot's own models/*.xml) and URDF give the same FK. puma560_corke_poe.yaml is the
// POE form of puma560_corke.yaml and shares its MJCF.
TEST(ExportTwins, RobotFileMjcfAndUrdfGiveTheSameFk) {
  const std::map<std::string, std::string> mjcf_of = {{"puma560_corke_poe", "puma560_corke"}};
  std::mt19937_64 rng(7);
  Worst urdf_dom{"twin urdf (urdfdom)"}, urdf_mujoco{"twin urdf (MuJoCo)"}, mjcf{"bundled mjcf (MuJoCo)"};
  int twins = 0;
  for (const auto& e : fs::directory_iterator(LOWPAIR_MODELS)) {
    if (e.path().extension() != ".yaml" || e.path().string().find(".joint_variables.") != std::string::npos) continue;
    const std::string stem = e.path().stem().string();
    SCOPED_TRACE(stem);
    const fs::path urdf = fs::path(LOWPAIR_MODELS) / (stem + ".urdf");
    ASSERT_TRUE(fs::exists(urdf)) << "no URDF twin: run lowpair export " << e.path().string()
                                  << " --format urdf --out " << urdf.string();
    const std::string xml_stem = mjcf_of.count(stem) ? mjcf_of.at(stem) : stem;
    const fs::path xml = fs::path(LOWPAIR_MODELS) / (xml_stem + ".xml");
    ASSERT_TRUE(fs::exists(xml)) << xml;
    const PoeModel model = readRobotFile(e.path().string()).poeModel();
    const double L = model.lengthScale();
    const PoeModel from_urdf = *readUrdf(urdf.string(), "tool").poe;
    const MujocoRobot mjcf_robot(xml.string(), "tool");
    ASSERT_EQ(mjcf_robot.dof(), model.dof());
    MujocoRobot::Evaluator mjcf_eval(mjcf_robot);
    std::unique_ptr<MujocoRobot> urdf_robot;
    std::unique_ptr<MujocoRobot::Evaluator> urdf_eval;
    if (std::none_of(model.joints().begin(), model.joints().end(),
                     [](const Joint& j) { return j.type == JointType::Helical; })) {
      urdf_robot = std::make_unique<MujocoRobot>(urdf.string(), "tool");  // MuJoCo 2.2.2 has no <mimic>
      ASSERT_EQ(urdf_robot->dof(), model.dof());
      urdf_eval = std::make_unique<MujocoRobot::Evaluator>(*urdf_robot);
    }
    // the URDF is in metres (a mm or cm robot file converted), the MJCF in the robot file's unit
    const RobotFile source = readRobotFile(e.path().string());
    const PoeModel metres = source.length_unit == "m" ? model : inMetres(source).poeModel();
    const double L_metres = metres.lengthScale();
    for (const VecX& q : configurations(model, rng)) {
      const Pose T = fk(model, q), T_metres = fk(metres, q);
      const VecX x = motionOf(model, q), x_metres = motionOf(metres, q);
      expectPose(T_metres, fk(from_urdf, x_metres), L_metres, urdf_dom, urdf.string());
      if (urdf_eval) {
        expectPose(T_metres, urdf_eval->tipPose(x_metres), L_metres, urdf_mujoco, urdf.string());
      }
      expectPose(T, mjcf_eval.tipPose(x), L, mjcf, xml.string());
    }
    // the twin is what export makes today
    std::ifstream in(urdf);
    std::stringstream text;
    text << in.rdbuf();
    const std::string made_by =
        "Made by lowpair export from models/" + stem + ".yaml, format urdf, written to models/" + stem + ".urdf.";
    RobotFile file = readRobotFile(e.path().string());
    file.path = "models/" + stem + ".yaml";
    EXPECT_EQ(text.str(), exportRobot(file, ExportFormat::Urdf, {made_by}).text)
        << urdf.string() << " is stale: re-run lowpair export (from the project folder)";
    ++twins;
  }
  EXPECT_GE(twins, 8);
  for (const Worst* w : {&urdf_dom, &urdf_mujoco, &mjcf}) w->print();
}

}  // namespace
}  // namespace lowpair

namespace lowpair {
namespace {

// Review finding: a mm robot was exported as a URDF with its millimetres written as metres. URDF lengths
// are metres: known units are converted (prismatic q keeps its unit, the scale absorbs the factor), an
// unknown one is refused naming it, a file without a unit gets a note.
TEST(ExportUnits, UrdfLengthsAreMetres) {
  constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
  EXPECT_EQ(metresPerUnit("mm"), 1e-3);
  EXPECT_EQ(metresPerUnit("in"), 0.0254);
  EXPECT_FALSE(metresPerUnit("").has_value());
  EXPECT_FALSE(metresPerUnit("MM").has_value());
  const RobotFile rhino = readRobotFile(std::string(LOWPAIR_MODELS) + "/rhino_xr3_slide.yaml");  // cm, a slide
  ASSERT_EQ(rhino.length_unit, "cm");
  const RobotFile metres = inMetres(rhino);
  EXPECT_EQ(metres.length_unit, "m");
  const PoeModel cm = rhino.poeModel(), m = metres.poeModel();
  std::mt19937_64 rng(3);
  for (const VecX& q : configurations(cm, rng)) {
    const Pose a = fk(cm, q), b = fk(m, q);
    // the same pose, positions / 100: rounding of lengths L (cm) carried through a 1e-2 multiplication
    EXPECT_LE((a.R - b.R).cwiseAbs().maxCoeff(), 64 * kEpsilon);
    EXPECT_LE((a.p * 1e-2 - b.p).cwiseAbs().maxCoeff(), 64 * kEpsilon * m.lengthScale());
  }
  RobotFile odd = rhino;
  odd.length_unit = "furlong";
  try {
    exportRobot(odd, ExportFormat::Urdf, {});
    ADD_FAILURE() << "a unit lowpair cannot convert was exported";
  } catch (const RobotFileError& e) {
    EXPECT_NE(std::string(e.what()).find("length_unit 'furlong' is not one lowpair converts"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(exportRobot(odd, ExportFormat::Mjcf, {}));  // MuJoCo has no unit: the MJCF keeps the file's
  RobotFile none = rhino;
  none.length_unit.clear();
  const ExportedRobot unlabelled = exportRobot(none, ExportFormat::Urdf, {});
  ASSERT_FALSE(unlabelled.notes.empty());
  EXPECT_NE(unlabelled.notes.front().find("states no length_unit"), std::string::npos) << unlabelled.notes.front();
}

}  // namespace
}  // namespace lowpair
