// lowpair plan's feasible candidates (docs/plan.md "Feasible plans"): the planned poses checked independently
// in MuJoCo (the MJCF loaded here as it is, mj_forward, ncon), the rejected counts, --range and
// --range-margin honoured exactly, bad ranges (exit 2), no feasible candidate (exit 1, nothing written), a
// model without collision geometry (a note), --model beside a robot file, and a robot file's floor in mm.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <random>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_runner.hpp"

using lowpair_test::expectRejected;
using lowpair_test::runCli;
using lowpair_test::scratch;
using nlohmann::json;

namespace {

const std::string kArm = std::string(LOWPAIR_TEST_DATA) + "/mjcf/feasible_arm.xml";
const std::string kArmNoCollision = std::string(LOWPAIR_TEST_DATA) + "/mjcf/feasible_arm_nocollision.xml";
// the chain's joints in order, and their ranges in the MJCF (rad)
const char* const kJoints[] = {"j1", "j2", "j3", "j4"};
const double kRanges[4][2] = {{-3.14159, 3.14159}, {-2.5, 2.5}, {-2.9, 2.9}, {-3, 3}};

json planJson(const std::string& args) {
  const lowpair_test::CliRun r = runCli("plan " + args + " --json");
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? json::parse(r.out) : json::object();
}

// The MJCF loaded by MuJoCo as it is (not through lowpair's copies): the independent judge.
class Judge {
 public:
  Judge() : m_(mj_loadXML(kArm.c_str(), nullptr, error_, sizeof error_), mj_deleteModel), d_(nullptr, mj_deleteData) {
    if (m_) d_.reset(mj_makeData(m_.get()));
  }
  bool loaded() const { return m_ && d_; }
  // mj_forward at the robot's joint vector q (MuJoCo's own variable: qpos = qpos0 + q)
  const mjData* at(const std::vector<double>& q) {
    mju_copy(d_->qpos, m_->qpos0, m_->nq);
    for (size_t i = 0; i < q.size(); ++i) {
      const int adr = m_->jnt_qposadr[mj_name2id(m_.get(), mjOBJ_JOINT, kJoints[i])];
      d_->qpos[adr] = m_->qpos0[adr] + q[i];
    }
    mj_forward(m_.get(), d_.get());
    return d_.get();
  }
  // the lowest point of the moving bodies' capsules (world z)
  double lowestMovingPoint() const {
    double lowest = INFINITY;
    for (int g = 0; g < m_->ngeom; ++g) {
      if (m_->body_weldid[m_->geom_bodyid[g]] == 0) continue;  // the column and the fixture do not move
      const double* R = d_->geom_xmat + 9 * g;                  // row-major: the z axis is column 2
      const double half = m_->geom_size[3 * g + 1], radius = m_->geom_size[3 * g];
      lowest = std::min(lowest, d_->geom_xpos[3 * g + 2] - std::abs(R[8]) * half - radius);
    }
    return lowest;
  }
  std::string bodyName(int geom) const { return mj_id2name(m_.get(), mjOBJ_BODY, m_->geom_bodyid[geom]); }

 private:
  char error_[1000] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m_;
  std::unique_ptr<mjData, void (*)(mjData*)> d_;
};

std::vector<std::vector<double>> plannedQ(const json& j) { return j["q"].get<std::vector<std::vector<double>>>(); }

}  // namespace

TEST(PlanFeasible, EveryPlannedPoseIsContactFreeInAnIndependentMujocoCheck) {
  const json j = planJson(kArm + " --tip tool --collisions --poses 12 --candidates 800 --seed 3");
  ASSERT_TRUE(j.contains("feasibility"));
  const json& f = j["feasibility"];
  EXPECT_TRUE(f["checked"].get<bool>());
  EXPECT_EQ(f["collision_geoms"], 6);  // the column, four links, the fixture
  // every reason occurs on this model, and the counts add up
  EXPECT_GT(f["rejected"]["self_collision"].get<int>(), 0);
  EXPECT_GT(f["rejected"]["world"].get<int>(), 0);
  EXPECT_EQ(f["rejected"]["floor"], 0);  // no --floor
  EXPECT_EQ(f["rejected"]["total"].get<int>(), f["rejected"]["self_collision"].get<int>() + f["rejected"]["world"].get<int>());
  EXPECT_EQ(f["drawn"], 800);
  EXPECT_EQ(f["kept"].get<int>() + f["rejected"]["total"].get<int>(), 800);
  EXPECT_GT(f["kept"].get<int>(), 12);
  // the excluded pair never appears; the pairs' counts are at most the rejected candidates
  for (const json& p : f["pairs"]) {
    const auto b = p["bodies"].get<std::vector<std::string>>();
    EXPECT_FALSE((b[0] == "shoulder" && b[1] == "forearm") || (b[0] == "forearm" && b[1] == "shoulder")) << p;
    EXPECT_LE(p["candidates"].get<int>(), f["rejected"]["total"].get<int>());
  }
  Judge judge;
  ASSERT_TRUE(judge.loaded());
  const auto q = plannedQ(j);
  ASSERT_EQ(q.size(), 12u);
  for (const auto& x : q) {
    const mjData* d = judge.at(x);
    EXPECT_EQ(d->ncon, 0) << "a planned pose in contact: " << json(x) << " first pair "
                          << (d->ncon ? judge.bodyName(d->contact[0].geom1) + "-" + judge.bodyName(d->contact[0].geom2) : "");
  }
  // the plan against random sets of the kept candidates
  EXPECT_GE(j["planned"]["log_det"].get<double>(), j["random"]["log_det"]["best"].get<double>());
  // the indices are the drawn candidates' (sample i of the stream, as simulate draws it) and increase
  const auto idx = j["indices"].get<std::vector<int>>();
  EXPECT_TRUE(std::is_sorted(idx.begin(), idx.end()));
  ASSERT_LT(idx.back(), 800);
  const std::string m = scratch() + "/feasible_samples.csv";
  ASSERT_EQ(runCli("simulate " + kArm + " --tip tool --poses 800 --seed 3 --out " + m).status, 0);
  std::ifstream in(m);
  std::vector<std::vector<double>> samples;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'q') continue;
    std::vector<double> row;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',') && row.size() < 4;) row.push_back(std::stod(cell));
    samples.push_back(row);
  }
  ASSERT_EQ(samples.size(), 800u);
  for (size_t k = 0; k < idx.size(); ++k) EXPECT_EQ(q[k], samples[static_cast<size_t>(idx[k])]) << k;
}

TEST(PlanFeasible, TheJudgeRejectsWhatTheCommandRejects) {
  Judge judge;
  ASSERT_TRUE(judge.loaded());
  // the judge can fail: the stretched arm turned towards the fixture goes through it, turned away it is free
  EXPECT_GT(judge.at({0.567, 0.0, 0.0, 0.0})->ncon, 0);
  EXPECT_EQ(judge.at({-1.5, 0.0, 0.0, 0.0})->ncon, 0);
  // the fraction of uniform draws in contact, by the judge (its own stream) and by the command (its candidates)
  std::mt19937_64 rng(20261128);
  int in_contact = 0;
  const int draws = 4000;
  for (int k = 0; k < draws; ++k) {
    std::vector<double> q(4);
    for (int i = 0; i < 4; ++i) q[static_cast<size_t>(i)] = std::uniform_real_distribution<double>(kRanges[i][0], kRanges[i][1])(rng);
    in_contact += judge.at(q)->ncon > 0;
  }
  const json j = planJson(kArm + " --tip tool --collisions --poses 6 --candidates 4000 --seed 11");
  const double judged = static_cast<double>(in_contact) / draws;
  const double rejected = j["feasibility"]["rejected"]["total"].get<double>() / 4000;
  EXPECT_GT(judged, 0.05);
  EXPECT_LT(judged, 0.6);
  EXPECT_NEAR(rejected, judged, 0.03);  // two binomial estimates of one fraction: standard deviation about 0.007 each
}

TEST(PlanFeasible, FloorKeepsEveryPlannedPoseAboveIt) {
  const json j = planJson(kArm + " --tip tool --floor 0 --poses 10 --candidates 800 --seed 5");
  const json& f = j["feasibility"];
  EXPECT_EQ(f["floor"], 0.0);
  EXPECT_GT(f["rejected"]["floor"].get<int>(), 0);
  EXPECT_EQ(f["kept"].get<int>() + f["rejected"]["self_collision"].get<int>() + f["rejected"]["world"].get<int>() +
                f["rejected"]["floor"].get<int>(),
            800);
  Judge judge;
  ASSERT_TRUE(judge.loaded());
  for (const auto& x : plannedQ(j)) {
    const mjData* d = judge.at(x);
    EXPECT_EQ(d->ncon, 0) << json(x);
    EXPECT_GE(judge.lowestMovingPoint(), 0.0) << json(x);
  }
}

TEST(PlanFeasible, RangesAreHonouredExactly) {
  const json j = planJson(kArm + " --tip tool --collisions --range 2:-0.5:0.5 --range j3:0:1.5 --poses 8 --candidates 400");
  const json& ranges = j["feasibility"]["ranges"];
  EXPECT_EQ(ranges[1]["lo"], -0.5);
  EXPECT_EQ(ranges[1]["hi"], 0.5);
  EXPECT_EQ(ranges[2]["lo"], 0.0);
  EXPECT_EQ(ranges[2]["hi"], 1.5);
  EXPECT_EQ(ranges[1]["source"], "--range");
  EXPECT_EQ(ranges[0]["source"], "file");
  for (const auto& x : plannedQ(j)) {
    EXPECT_GE(x[1], -0.5);
    EXPECT_LE(x[1], 0.5);
    EXPECT_GE(x[2], 0.0);
    EXPECT_LE(x[2], 1.5);
  }
}

TEST(PlanFeasible, RangeMarginShrinksEveryRange) {
  const json j = planJson(kArm + " --tip tool --range-margin 0.25 --poses 8 --candidates 400");
  EXPECT_FALSE(j["feasibility"]["model"].is_string());  // ranges only: nothing checked, every candidate kept
  EXPECT_EQ(j["feasibility"]["kept"], 400);
  for (const auto& x : plannedQ(j)) {
    for (int i = 0; i < 4; ++i) {
      EXPECT_GE(x[static_cast<size_t>(i)], kRanges[i][0] + 0.25);
      EXPECT_LE(x[static_cast<size_t>(i)], kRanges[i][1] - 0.25);
    }
  }
  EXPECT_DOUBLE_EQ(j["feasibility"]["ranges"][3]["hi"].get<double>(), 2.75);
}

// The arm as a robot file (lowpair export of the MJCF: the same joints, names and ranges).
std::string armRobotFile() {
  const std::string robot = scratch() + "/feasible_arm.yaml";
  const lowpair_test::CliRun e = runCli("export " + kArm + " --tip tool --format poe --out " + robot);
  EXPECT_EQ(e.status, 0) << e.err;
  return robot;
}

TEST(PlanFeasible, BadRangesExitTwoWithOneLine) {
  // the robot file beside the model: an MJCF robot's load gives a note of what kinematics did not need first
  const std::string robot = armRobotFile();
  const std::string plan = "plan " + robot + " --model " + kArm + " --tip tool --poses 5 --candidates 100 ";
  expectRejected(plan + "--range 2:-3:2", "joint 2 (j2): [-3, 2] rad is outside the file's range [-2.5, 2.5] rad",
                 "--range");
  expectRejected(plan + "--range 2:1:0", "LO must be below HI", "--range");
  expectRejected(plan + "--range 2:1:1", "LO must be below HI", "--range");
  expectRejected(plan + "--range 5:0:1", "no joint '5'", "--range");
  expectRejected(plan + "--range elbow:0:1", "no joint 'elbow'", "--range");
  expectRejected(plan + "--range 2:a:1", "LO and HI must be finite numbers", "--range");
  expectRejected(plan + "--range 2:1", "expected J:LO:HI", "--range");
  expectRejected(plan + "--range 2:0:1 --range j2:0:0.5", "given twice", "--range");
  expectRejected(plan + "--range-margin 3", "leaves nothing", "--range-margin");
  expectRejected(plan + "--range-margin -1", "must be a finite number >= 0", "--range-margin");
  // the MJCF as the robot: the same error, last
  const lowpair_test::CliRun r = runCli("plan " + kArm + " --tip tool --poses 5 --range 2:-3:2");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("\nerror: --range: joint 2 (j2): [-3, 2] rad is outside"), std::string::npos) << r.err;
  expectRejected("plan " + lowpair_test::modelPath("puma560_okamura_nominal.yaml") + " --poses 5 --floor 0",
                 "needs a model", "--floor");
  // a floor that is not a finite number: refused before the model is loaded (one line), not a plane at nan or inf
  // in MuJoCo's XML (nan: exit 1 with MuJoCo's parse error; 1e309, read as inf: exit 1, "no candidate is free")
  for (const char* floor : {"nan", "inf", "-inf", "1e309"}) {
    expectRejected("plan " + kArm + " --tip tool --poses 5 --floor " + floor, "must be a finite number", "--floor");
  }
}

TEST(PlanFeasible, NoFeasibleCandidateExitsOneAndWritesNothing) {
  const std::string robot = armRobotFile();
  const std::string out = scratch() + "/infeasible.csv";
  std::filesystem::remove(out);
  // a floor above the shoulder: the shoulder link lies below it in every configuration
  const lowpair_test::CliRun r = runCli("plan " + robot + " --model " + kArm +
                                        " --tip tool --floor 0.5 --poses 5 --candidates 200 --out " + out);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.err.rfind("error: no candidate of 200 is free of contacts", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("'floor' with 'shoulder' (200 candidates)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--floor"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(std::filesystem::exists(out));
  // fewer kept than asked for: the same exit, and the counts add up to the candidates
  const lowpair_test::CliRun few =
      runCli("plan " + robot + " --model " + kArm + " --tip tool --poses 60 --candidates 60 --out " + out);
  EXPECT_EQ(few.status, 1) << few.err;
  EXPECT_EQ(few.err.rfind("error: only ", 0), 0u) << few.err;
  EXPECT_NE(few.err.find(" of 60 are free of contacts"), std::string::npos) << few.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(PlanFeasible, ModelWithoutCollisionGeometryGivesANote) {
  const lowpair_test::CliRun r =
      runCli("plan " + kArmNoCollision + " --tip tool --collisions --poses 6 --candidates 100 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("note: " + kArmNoCollision + ": no geom can collide"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing was checked"), std::string::npos) << r.err;
  const json j = json::parse(r.out);
  EXPECT_FALSE(j["feasibility"]["checked"].get<bool>());
  EXPECT_EQ(j["feasibility"]["kept"], 100);
  EXPECT_EQ(j["feasibility"]["rejected"]["total"], 0);
}

TEST(PlanFeasible, WithoutTheNewOptionsTheJsonHasNoNewField) {
  const json j = planJson(kArm + " --tip tool --poses 6 --candidates 100");
  EXPECT_FALSE(j.contains("feasibility"));
}

TEST(PlanFeasible, ModelBesideARobotFileKeepsTheSameCandidates) {
  const std::string robot = armRobotFile();
  const json own = planJson(kArm + " --tip tool --collisions --poses 6 --candidates 300 --seed 9");
  const json beside = planJson(robot + " --model " + kArm + " --tip tool --poses 6 --candidates 300 --seed 9");
  EXPECT_EQ(beside["feasibility"]["kept"], own["feasibility"]["kept"]);
  EXPECT_EQ(beside["feasibility"]["rejected"], own["feasibility"]["rejected"]);
  expectRejected("plan " + kArm + " --tip tool --model " + kArm + " --poses 5", "goes with a robot file", "--model");
  expectRejected("plan " + robot + " --model " + kArm + " --poses 5", "--tip NAME is required", "--model");
}

TEST(PlanFeasible, TheFloorOfARobotFileInMillimetresIsConvertedToTheModelsMetres) {
  // the robot file's lengths only matter to the check through the floor (the arm has no prismatic joint)
  std::ifstream in(armRobotFile());
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = text.find("angle_unit: rad");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, "length_unit: mm\n");
  const std::string mm = lowpair_test::writeScratchFile("feasible_arm_mm.yaml", text);
  const json in_mm = planJson(mm + " --model " + kArm + " --tip tool --floor 100 --poses 6 --candidates 1000");
  const json in_m = planJson(kArm + " --tip tool --floor 0.1 --poses 6 --candidates 1000");
  EXPECT_EQ(in_mm["feasibility"]["floor"], 100.0);
  EXPECT_GT(in_m["feasibility"]["rejected"]["floor"].get<int>(), 0);
  EXPECT_EQ(in_mm["feasibility"]["rejected"], in_m["feasibility"]["rejected"]);
  EXPECT_EQ(in_mm["feasibility"]["kept"], in_m["feasibility"]["kept"]);
}
