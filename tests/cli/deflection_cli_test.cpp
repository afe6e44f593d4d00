// calibrate --compliance / --backlash, identifiability with them, and fk / compensate of a file holding a compliance
// (docs/calibration.md "Beyond geometry"). The "actual" robot is the nominal PUMA 560 of Wu et al.'s loop with link
// masses, joints 2 and 3 compliant and joint 2 with backlash; its measurements come from the library's forward
// kinematics at the deflected joints (gravityTorques, moveSigns), written here as a measurement CSV.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "csv_text.hpp"
#include "lowpair/deflection.hpp"
#include "lowpair/gravity.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

namespace {

using namespace lowpair;
using namespace lowpair_test;
using nlohmann::json;

// The PUMA's twists (models/puma560_okamura_nominal.yaml) and tool, with masses: one source for the file and the model.
const double kTwists[6][6] = {{0, 0, 1, 0, 0, 0},      {0, -1, 0, 0, 0, 0},     {0, -1, 0, 0, 0, -100},
                              {0, 0, -1, -50, 250, 0}, {0, -1, 0, -20, 0, -250}, {0, 0, -1, -50, 250, 0}};
const double kTool[6] = {0, 0, 0, 250, 50, -20};
const double kMass[6] = {10, 17, 5, 1, 0.5, 0.1};
const double kCom[6][3] = {{0, 0, -100}, {50, -30, 10}, {180, -20, 0}, {250, 50, 0}, {250, 50, -10}, {250, 50, -20}};
const double kPayload = 2.0, kPayloadCom[3] = {0, 0, 30};

PoeModel pumaModel() {
  std::vector<JointSpec> joints(6);
  for (int i = 0; i < 6; ++i) joints[static_cast<size_t>(i)].twist = Eigen::Map<const Vec6>(kTwists[i]);
  return PoeModel::fromToolTwist(joints, Eigen::Map<const Vec6>(kTool));
}

MassModel pumaMasses() {
  MassModel m;
  for (int i = 0; i < 6; ++i) m.links.push_back({kMass[i], Vec3(kCom[i][0], kCom[i][1], kCom[i][2])});
  m.payload = {kPayload, Vec3(kPayloadCom[0], kPayloadCom[1], kPayloadCom[2])};
  m.metres_per_unit = 1e-3;
  return m;
}

std::string numbers(const double* x, int n) {
  std::ostringstream s;
  s.precision(17);
  for (int k = 0; k < n; ++k) s << (k ? ", " : "") << x[k];
  return s.str();
}

// The robot file: with masses (or without), with compliance values per joint (none when empty).
std::string pumaFile(bool masses, const std::vector<double>& compliance = {}) {
  std::string text = "name: puma-masses\nlength_unit: mm\nangle_unit: rad\npoe:\n  joints:\n";
  for (int i = 0; i < 6; ++i) {
    text += "    - {name: j" + std::to_string(i + 1) + ", twist: [" + numbers(kTwists[i], 6) + "]";
    if (masses) text += ", mass: " + numbers(&kMass[i], 1) + ", com: [" + numbers(kCom[i], 3) + "]";
    if (!compliance.empty() && compliance[static_cast<size_t>(i)] != 0.0) text += ", compliance: " + numbers(&compliance[static_cast<size_t>(i)], 1);
    text += "}\n";
  }
  text += "  tool: [" + numbers(kTool, 6) + "]\n";
  if (masses) text += "payload: {mass: 2, com: [" + numbers(kPayloadCom, 3) + "]}\n";
  return text;
}

// The actual robot's deflections: joints 2 and 3 compliant, joint 2 with backlash.
JointDeflection actualDeflection() {
  JointDeflection d;
  d.compliance = VecX::Zero(6);
  d.backlash = VecX::Zero(6);
  d.compliance[1] = 5e-5;  // rad/(N m): ~1e-3 rad under the 20-30 N m on joint 2
  d.compliance[2] = 1e-4;
  d.backlash[1] = 5e-4;    // rad
  return d;
}

std::vector<VecX> randomPoses(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<VecX> qs;
  for (int k = 0; k < count; ++k) {
    VecX q(6);
    for (int i = 0; i < 6; ++i) q[i] = u(rng);
    qs.push_back(q);
  }
  return qs;
}

// Measurement CSV (pose) of the actual robot at the deflected joints; noise per coordinate when asked.
std::string measurementCsv(const std::vector<VecX>& qs, double noise_position, double noise_rotation, unsigned seed,
                           bool sign_column = false) {
  const PoeModel model = pumaModel();
  const MassModel masses = pumaMasses();
  const JointDeflection d = actualDeflection();
  const std::vector<VecX> signs = moveSigns(qs);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n;
  std::ostringstream s;
  s.precision(17);
  s << "# length_unit: mm\nq1,q2,q3,q4,q5,q6,x,y,z,qw,qx,qy,qz" << (sign_column ? ",s2" : "") << "\n";
  for (size_t k = 0; k < qs.size(); ++k) {
    const VecX q = deflectedJoints(d, qs[k], PoseLoad{gravityTorques(model, masses, qs[k]), signs[k]});
    Pose T = poeForwardKinematics(model, q);
    const double x = n(rng), y = n(rng), z = n(rng), a = n(rng), b = n(rng), c = n(rng);
    T.p += noise_position * Vec3(x, y, z);
    T.R = expSO3(noise_rotation * Vec3(a, b, c)) * T.R;
    const Eigen::Quaterniond r(T.R);
    for (int i = 0; i < 6; ++i) s << qs[k][i] << ",";
    s << T.p.x() << "," << T.p.y() << "," << T.p.z() << "," << r.w() << "," << r.x() << "," << r.y() << "," << r.z();
    if (sign_column) s << "," << signs[k][1];
    s << "\n";
  }
  return s.str();
}

json runJson(const std::string& args) {
  const CliRun r = runCli(args);
  EXPECT_EQ(r.status, 0) << args << "\n" << r.err << r.out;
  return json::parse(r.out);
}

// The deflection entry of calibrate's JSON for joint `joint` (1-based) and kind.
json entry(const json& j, int joint, const std::string& kind) {
  for (const json& d : j["deflections"]) {
    if (d["joint"] == joint && d["kind"] == kind) return d;
  }
  ADD_FAILURE() << "no " << kind << " of joint " << joint << " in " << j["deflections"].dump();
  return json();
}

TEST(DeflectionCli, NoiseFreeLoopRecoversComplianceAndBacklash) {
  const std::string nominal = writeScratchFile("puma_masses.yaml", pumaFile(true));
  const std::string m = writeScratchFile("deflected.csv", measurementCsv(randomPoses(50, 1), 0.0, 0.0, 2));
  const std::string out = scratch() + "/calibrated.yaml";
  const json j = runJson("calibrate " + nominal + " --measurements " + m + " --compliance 2,j3 --backlash 2 --json --out " + out);
  const JointDeflection truth = actualDeflection();
  EXPECT_EQ(j["accepted"], true) << j["verdict"];
  EXPECT_EQ(j["rank"], j["expected"]);
  EXPECT_EQ(j["expected"].get<int>(), 36 + 3);  // 4r + n + 6 for the PUMA's 6R, and one per deflection
  for (const auto& [joint, kind, value] : std::vector<std::tuple<int, std::string, double>>{
           {2, "compliance", truth.compliance[1]}, {3, "compliance", truth.compliance[2]}, {2, "backlash", truth.backlash[1]}}) {
    const json d = entry(j, joint, kind);
    EXPECT_NEAR(d["value"].get<double>(), value, 1e-6 * value) << kind << joint;
    EXPECT_EQ(d["unit"], kind == "compliance" ? "rad/(N m)" : "rad");
    std::printf("j%d.%s %.10g (true %.10g), sd %.3g\n", joint, kind.c_str(), d["value"].get<double>(), value, d["sd"].get<double>());
  }
  EXPECT_EQ(entry(j, 2, "backlash")["signs"], "the measurements' order");
  // the written file holds them, and fk applies its compliance (the backlash needs the approach: not applied)
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("compliance: "), std::string::npos) << text;
  EXPECT_NE(text.find("backlash: "), std::string::npos) << text;
  EXPECT_NE(text.find("payload: "), std::string::npos) << text;
  const PoeModel model = pumaModel();
  const MassModel masses = pumaMasses();
  for (const VecX& q : randomPoses(5, 7)) {
    std::ostringstream qtext;
    qtext.precision(17);
    for (int i = 0; i < 6; ++i) qtext << (i ? "," : "") << q[i];
    const CliRun r = runCli("fk " + out + " --q " + qtext.str() + " --json");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("compliance applied"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("backlash not applied"), std::string::npos) << r.err;
    const json f = json::parse(r.out);
    JointDeflection compliance_only;
    compliance_only.compliance = truth.compliance;
    const Pose T = poeForwardKinematics(model, deflectedJoints(compliance_only, q, PoseLoad{gravityTorques(model, masses, q), VecX()}));
    const Pose T_rigid = poeForwardKinematics(model, q);
    const json& F = f["T_base_tool"];
    const Vec3 p_fk(F[0][3].get<double>(), F[1][3].get<double>(), F[2][3].get<double>());
    // the fit's estimate is exact to ~1e-9 relative: the position to 1e-6 mm; the compliance moves it ~0.1 mm
    EXPECT_LE((p_fk - T.p).norm(), 1e-6) << f.dump();
    EXPECT_GT((p_fk - T_rigid.p).norm(), 1e-2);
  }
}

TEST(DeflectionCli, NoisyLoopWithinThreeStandardDeviations) {
  const std::string nominal = writeScratchFile("puma_masses.yaml", pumaFile(true));
  const std::string m = writeScratchFile("noisy.csv", measurementCsv(randomPoses(80, 3), 0.005, 1e-5, 4, true));
  const json j = runJson("calibrate " + nominal + " --measurements " + m +
                         " --compliance 2,3 --backlash 2 --noise-position 0.005 --noise-rotation 1e-5 --json");
  EXPECT_EQ(j["accepted"], true) << j["verdict"];
  const JointDeflection truth = actualDeflection();
  for (const auto& [joint, kind, value] : std::vector<std::tuple<int, std::string, double>>{
           {2, "compliance", truth.compliance[1]}, {3, "compliance", truth.compliance[2]}, {2, "backlash", truth.backlash[1]}}) {
    const json d = entry(j, joint, kind);
    const double estimate = d["value"].get<double>(), sd = d["sd"].get<double>();
    std::printf("j%d.%s %.5g +- %.2g (true %.5g, %.2f sd)\n", joint, kind.c_str(), estimate, sd, value, (estimate - value) / sd);
    EXPECT_LE(std::abs(estimate - value), 3.0 * sd) << kind << joint;
    EXPECT_LT(sd, 0.05 * value) << kind << joint;  // determined: well below the value
  }
  EXPECT_EQ(entry(j, 2, "backlash")["signs"], "its sign column in " + m);
}

// --select cv with --backlash (issue 27, selection): every level with joint 2's backlash on and off (and the
// compliances on and off), on the same partitions. Joint 2's 0.5 mrad of play moves the tool by about 0.2 mm, 40
// times the noise: the choice has it on, and at every level with the compliances on, "backlash off" scores worse
// than "on" by more than the sd of "on" over the partitions.
TEST(DeflectionCli, SelectionChoosesBacklashOnForDataWithBacklash) {
  const std::string nominal = writeScratchFile("puma_masses.yaml", pumaFile(true));
  const std::string m = writeScratchFile("backlash.csv", measurementCsv(randomPoses(80, 5), 0.005, 1e-5, 6, true));
  const json j = runJson("calibrate " + nominal + " --measurements " + m + " --compliance 2,3 --backlash 2 --select cv" +
                         " --folds 5 --repeats 2 --noise-position 0.005 --noise-rotation 1e-5 --json");
  const json& cv = j["cross_validation"];
  ASSERT_EQ(cv["candidates"].size(), 12u) << cv.dump();  // 3 levels x compliance off/on x backlash off/on
  auto find = [&](const json& level, bool compliance, bool backlash) -> const json* {
    for (const json& c : cv["candidates"]) {
      if (c["parameters"] == level && c["compliance"] == compliance && c["backlash"] == backlash) return &c;
    }
    return nullptr;
  };
  const json* best = nullptr;
  for (const json& c : cv["candidates"]) {
    if (c["chosen"] == true) best = &c;
  }
  ASSERT_NE(best, nullptr) << cv.dump();
  EXPECT_EQ((*best)["backlash"], true) << cv.dump();
  EXPECT_EQ((*best)["compliance"], true) << cv.dump();
  for (const char* level : {"full", "lines", "offsets"}) {
    const json* on = find(level, true, true);
    const json* off = find(level, true, false);
    ASSERT_TRUE(on && off) << level;
    EXPECT_GT((*off)["score"].get<double>() - (*on)["score"].get<double>(), (*on)["score_sd"].get<double>()) << level;
  }
  // the final fit is the chosen candidate's: joint 2's backlash among its deflections, with its sign column
  EXPECT_EQ(entry(j, 2, "backlash")["signs"], "its sign column in " + m);
}

TEST(DeflectionCli, TextOutputAndAllLeavesOutTheVerticalAxis) {
  const std::string nominal = writeScratchFile("puma_masses.yaml", pumaFile(true));
  const std::string m = writeScratchFile("deflected.csv", measurementCsv(randomPoses(50, 1), 0.0, 0.0, 2));
  const CliRun r = runCli("calibrate " + nominal + " --measurements " + m + " --compliance all --backlash 2");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("joint deflections"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("j2.compliance "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" rad/(N m) (load "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("j2.backlash "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("j1: no compliance fitted (--compliance all"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("j1.compliance"), std::string::npos) << r.out;
}

TEST(DeflectionCli, Refusals) {
  const std::string nominal = writeScratchFile("puma_masses.yaml", pumaFile(true));
  const std::string rigid = writeScratchFile("puma_rigid.yaml", pumaFile(false));
  const std::string m = writeScratchFile("deflected.csv", measurementCsv(randomPoses(30, 1), 0.0, 0.0, 2));
  // the vertical first axis carries no gravity load: named, exit 2
  expectRejected("calibrate " + nominal + " --measurements " + m + " --compliance 1,2",
                 "joint 1 (j1): its gravity load does not vary over the 30 poses (0 N m to 0 N m), no load at all", "--compliance: ");
  expectRejected("identifiability " + nominal + " --compliance 1", "joint 1 (j1): its gravity load does not vary", "--compliance: ");
  expectRejected("calibrate " + rigid + " --measurements " + m + " --compliance 2", "states no masses", "--compliance: ");
  expectRejected("calibrate " + nominal + " --measurements " + m + " --compliance 2,2", "joint 2 is named twice", "--compliance: ");
  expectRejected("calibrate " + nominal + " --measurements " + m + " --backlash 7", "'7' is no joint of the robot", "--backlash: ");
  expectRejected("calibrate " + nominal + " --measurements " + m + " --backlash all", "'all' is no joint of the robot", "--backlash: ");
  // a sign column that never changes
  std::string constant = measurementCsv(randomPoses(30, 1), 0.0, 0.0, 2, true);
  for (size_t at = constant.find(",-1\n"); at != std::string::npos; at = constant.find(",-1\n")) constant.replace(at, 4, ",1\n");
  for (size_t at = constant.find(",0\n"); at != std::string::npos; at = constant.find(",0\n")) constant.replace(at, 3, ",1\n");
  const std::string m_constant = writeScratchFile("constant_sign.csv", constant);
  expectRejected("calibrate " + nominal + " --measurements " + m_constant + " --backlash 2",
                 "joint 2 (j2): the sign of its last move is 1 at every one of the 30 poses", "--backlash: ");
}

TEST(DeflectionCli, IdentifiabilityCountsTheDeflections) {
  const std::string nominal = writeScratchFile("puma_masses.yaml", pumaFile(true));
  const json plain = runJson("identifiability " + nominal + " --json");
  const json j = runJson("identifiability " + nominal + " --compliance 2,3,5 --backlash 2,3 --json");
  EXPECT_EQ(j["expected"].get<int>(), plain["expected"].get<int>() + 5) << j.dump();
  EXPECT_EQ(j["rank"], j["expected"]) << j.dump();
  EXPECT_EQ(j["full_model"]["rank"], j["expected"]) << j["full_model"].dump();
}

// compensate of a calibrated file holding a compliance: the commands whose deflected joints put the tool where the
// nominal puts it.
TEST(DeflectionCli, CompensateCommandsTheDeflectedJoints) {
  const JointDeflection truth = actualDeflection();
  std::vector<double> c(truth.compliance.data(), truth.compliance.data() + 6);
  const std::string calibrated = writeScratchFile("puma_compliant.yaml", pumaFile(true, c));
  // a nominal 1 mrad off on joint 3's line: the compensation moves the joints, the compliance moves them more
  const std::string nominal = writeScratchFile("puma_plain.yaml", pumaFile(false));
  std::ostringstream qcsv;
  qcsv.precision(17);
  qcsv << "q1,q2,q3,q4,q5,q6\n";
  const std::vector<VecX> qs = randomPoses(6, 11);
  for (const VecX& q : qs) {
    for (int i = 0; i < 6; ++i) qcsv << (i ? "," : "") << q[i];
    qcsv << "\n";
  }
  const std::string q_file = writeScratchFile("q.csv", qcsv.str());
  const CliRun r = runCli("compensate " + calibrated + " --nominal " + nominal + " --q-file " + q_file + " --json");
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  EXPECT_NE(r.err.find("compliance applied"), std::string::npos) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["compliance_applied"], true);
  const PoeModel model = pumaModel();
  const MassModel masses = pumaMasses();
  JointDeflection compliance_only;
  compliance_only.compliance = truth.compliance;
  ASSERT_EQ(j["rows"].size(), qs.size());
  for (size_t k = 0; k < qs.size(); ++k) {
    const json& row = j["rows"][k];
    ASSERT_EQ(row["status"], "ok") << row.dump();
    VecX q_command(6);
    for (int i = 0; i < 6; ++i) q_command[i] = row["q"][static_cast<size_t>(i)].get<double>();
    const VecX q_stand = deflectedJoints(compliance_only, q_command, PoseLoad{gravityTorques(model, masses, q_command), VecX()});
    const Pose reached = poeForwardKinematics(model, q_stand), wanted = poeForwardKinematics(model, qs[k]);
    EXPECT_LE((reached.p - wanted.p).norm(), 1e-6) << k;  // IK converged to ~1e-10 L; the fixed point to rounding
    EXPECT_GT((q_command - qs[k]).cwiseAbs().maxCoeff(), 1e-4) << k;  // the commands differ by the deflection
  }
}

}  // namespace

namespace {

std::string pumaFileWithBacklash(const std::vector<double>& compliance, const std::vector<double>& backlash) {
  std::string text = pumaFile(true, compliance);
  // backlash keys on the joints that have one: appended inside each joint's flow map
  for (int i = 0; i < 6; ++i) {
    if (backlash[static_cast<size_t>(i)] == 0.0) continue;
    const std::string head = "{name: j" + std::to_string(i + 1) + ",";
    const size_t at = text.find(head);
    const size_t close = text.find('}', at);
    text.insert(close, ", backlash: " + numbers(&backlash[static_cast<size_t>(i)], 1));
  }
  return text;
}

// fk and compensate with --approach apply a file's backlash; export keeps the keys.
TEST(DeflectionCli, ApproachAppliesTheBacklash) {
  const JointDeflection truth = actualDeflection();
  const std::vector<double> c(truth.compliance.data(), truth.compliance.data() + 6), b(truth.backlash.data(), truth.backlash.data() + 6);
  const std::string robot = writeScratchFile("puma_backlash.yaml", pumaFileWithBacklash(c, b));
  const std::string nominal = writeScratchFile("puma_plain.yaml", pumaFile(false));
  const PoeModel model = pumaModel();
  const MassModel masses = pumaMasses();
  const std::vector<VecX> qs = randomPoses(6, 13);
  std::ostringstream qcsv;
  qcsv.precision(17);
  qcsv << "q1,q2,q3,q4,q5,q6\n";
  for (const VecX& q : qs) {
    for (int i = 0; i < 6; ++i) qcsv << (i ? "," : "") << q[i];
    qcsv << "\n";
  }
  const std::string q_file = writeScratchFile("q_backlash.csv", qcsv.str());
  // fk --q with explicit signs: the library's FK at q + c tau + b s
  const VecX s = (VecX(6) << 1, -1, 1, 1, -1, 0).finished();
  std::ostringstream qtext;
  qtext.precision(17);
  for (int i = 0; i < 6; ++i) qtext << (i ? "," : "") << qs[0][i];
  const CliRun f = runCli("fk " + robot + " --q " + qtext.str() + " --approach 1,-1,1,1,-1,0 --json");
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_NE(f.err.find("backlash applied"), std::string::npos) << f.err;
  const json jf = json::parse(f.out);
  const Pose T = poeForwardKinematics(model, deflectedJoints(truth, qs[0], PoseLoad{gravityTorques(model, masses, qs[0]), s}));
  const json& F = jf["T_base_tool"];
  EXPECT_LE((Vec3(F[0][3].get<double>(), F[1][3].get<double>(), F[2][3].get<double>()) - T.p).norm(), 1e-9 * 300.0) << jf.dump();
  // compensate --approach order: the signs of the rows' order
  const CliRun r = runCli("compensate " + robot + " --nominal " + nominal + " --q-file " + q_file + " --approach order --json");
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["backlash_applied"], true);
  const std::vector<VecX> signs = moveSigns(qs);
  for (size_t k = 0; k < qs.size(); ++k) {
    VecX q_command(6);
    for (int i = 0; i < 6; ++i) q_command[i] = j["rows"][k]["q"][static_cast<size_t>(i)].get<double>();
    const VecX q_stand = deflectedJoints(truth, q_command, PoseLoad{gravityTorques(model, masses, q_command), signs[k]});
    EXPECT_LE((poeForwardKinematics(model, q_stand).p - poeForwardKinematics(model, qs[k]).p).norm(), 1e-6) << k;
  }
  // refusals: a wrong count, a value that is no sign, order for one q
  expectRejected("fk " + robot + " --q " + qtext.str() + " --approach 1,1", "signs for 6 joints", "--approach: ");
  expectRejected("fk " + robot + " --q " + qtext.str() + " --approach 1,1,1,1,1,2", "expected 'order' or 6 signs", "--approach: ");
  expectRejected("fk " + robot + " --q " + qtext.str() + " --approach order", "'order' needs rows", "--approach: ");
  // export keeps masses and deflections
  const CliRun e = runCli("export " + robot + " --format poe");
  ASSERT_EQ(e.status, 0) << e.err;
  for (const char* key : {"compliance: ", "backlash: ", "mass: ", "payload: ", "gravity: "}) {
    EXPECT_NE(e.out.find(key), std::string::npos) << key << "\n" << e.out;
  }
}

}  // namespace
