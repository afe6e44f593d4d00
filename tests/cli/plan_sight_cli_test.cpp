// lowpair plan --tracker (docs/plan.md "Line of sight"): on the four bundled robots with capsule geometry (the
// PUMA 560, the Stanford arm, the Rhino XR-3 on its slide, the elbow manipulator) and on a Menagerie-style arm on a
// table with a fixture, every planned pose is checked here, independently, in MuJoCo (the MJCF loaded as it is:
// mj_forward, ncon, mj_ray from the tracker to each SMR at the tool site, the angle to its normal; a slide's q
// scaled to metres; the floor by the moving geoms' lowest points); --partial's measured lists are checked both ways
// (listed: seen; not listed: hidden); the plan beats the best of 100 random sets of the feasible candidates; a
// tracker inside the world's geometry (exit 2), no feasible candidate (exit 1, nothing written), bad
// --tracker/--smr-angle/normal (exit 2); and the loop: the planned poses simulated on an actual robot and
// calibrated.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "plan_sight_helpers.hpp"

using lowpair_test::expectRejected;
using lowpair_test::runCli;
using lowpair_test::scratch;
using lowpair_test::writeScratchFile;
using nlohmann::json;

namespace {

using plan_sight::kCellXml;
using plan_sight::kCellYaml;
using plan_sight::kData;
const std::string kPumaXml = kData + "puma560_capsules.xml", kPumaYaml = kData + "puma560_smr_normals.yaml";
// the ray stops this far before an SMR's centre (a 1.5-inch SMR's radius, docs/plan.md), metres
constexpr double kSmrRadius = 0.01905;
constexpr double kDeg = M_PI / 180.0;

struct Case {
  std::string yaml, xml;
  double metres;                // per robot file length unit
  std::vector<double> tracker;  // base frame = MuJoCo's world frame in these models, robot file unit
  std::string extra;            // narrowed ranges, the floor
  std::vector<double> normal;   // every target of a file faces this way (tool frame)
};

const Case kPuma{kPumaYaml, kPumaXml, 1e-3, {800, -200, 0},
                 "--range 2:0:3.14 --range 5:-1.5:1.5 --candidates 3000", {0, 0, -1}};
const Case kCell{kCellYaml, kCellXml, 1.0, {1.2, -0.6, 0.8}, "--candidates 3000", {0, 1, 0}};
// the Stanford arm: its floor at the pedestal's foot (z = 0)
const Case kStanford{kData + "stanford_smr.yaml", kData + "stanford_capsules.xml", 1.0, {1.2, 0.8, 1.6},
                     "--floor 0 --candidates 3000", {0, 0, 1}};
// the Rhino XR-3 on its slide (cm; the MJCF in metres): its floor 5 mm below the carriage
const Case kRhino{kData + "rhino_smr.yaml", kData + "rhino_capsules.xml", 0.01, {120, 50, 40},
                  "--floor -1.5 --candidates 3000", {0, 0, 1}};
// the elbow manipulator: its floor at the pedestal's foot (z = 0)
const Case kElbow{kData + "elbow_smr.yaml", kData + "elbow_capsules.xml", 1.0, {3, 1.5, 2},
                  "--floor 0 --candidates 3000", {0, 1, 0}};

std::string trackerText(const Case& c) {
  return std::to_string(c.tracker[0]) + "," + std::to_string(c.tracker[1]) + "," + std::to_string(c.tracker[2]);
}

json plan(const Case& c, const std::string& args) {
  const lowpair_test::CliRun r = runCli("plan " + c.yaml + " --model " + c.xml + " --tip tool --measure targets --tracker " +
                                        trackerText(c) + " " + c.extra + " " + args + " --json");
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? json::parse(r.out) : json::object();
}

// The MJCF loaded by MuJoCo as it is: the independent judge of contacts and rays.
class Judge {
 public:
  explicit Judge(const Case& c)
      : m_(mj_loadXML(c.xml.c_str(), nullptr, error_, sizeof error_), mj_deleteModel),
        d_(nullptr, mj_deleteData),
        metres_(c.metres) {
    if (m_) d_.reset(mj_makeData(m_.get()));
  }
  bool loaded() const { return m_ && d_; }
  const char* error() const { return error_; }
  // mj_forward at q (every joint of these models is a chain joint, in order; qpos = qpos0 + q, a slide's q
  // from the robot file's unit to MuJoCo's metres)
  int contactsAt(const std::vector<double>& q) {
    mju_copy(d_->qpos, m_->qpos0, m_->nq);
    for (size_t i = 0; i < q.size(); ++i) {
      d_->qpos[m_->jnt_qposadr[i]] += m_->jnt_type[i] == mjJNT_SLIDE ? q[i] * metres_ : q[i];
    }
    mj_forward(m_.get(), d_.get());
    return d_->ncon;
  }
  // Whether the tracker sees the SMR at `point_tool` (metres, tool site frame) with normal `normal_tool`:
  // no geom on the ray before the SMR's radius, and within `angle` of the normal.
  bool sees(const std::vector<double>& tracker_m, const std::vector<double>& point_tool,
            const std::vector<double>& normal_tool, double angle) const {
    const int site = mj_name2id(m_.get(), mjOBJ_SITE, "tool");
    const double* R = d_->site_xmat + 9 * site;  // row-major
    double p[3], n[3], v[3];
    for (int r = 0; r < 3; ++r) {
      p[r] = d_->site_xpos[3 * site + r];
      n[r] = 0.0;
      for (int k = 0; k < 3; ++k) {
        p[r] += R[3 * r + k] * point_tool[k];
        n[r] += R[3 * r + k] * normal_tool[k];
      }
      v[r] = p[r] - tracker_m[r];
    }
    const double length = mju_norm3(v);
    int geom = -1;
    const double x = mj_ray(m_.get(), d_.get(), tracker_m.data(), v, nullptr, 1, -1, &geom);
    if (x >= 0.0 && x * length < length - kSmrRadius) return false;
    double cross[3];
    const double back[3] = {-v[0], -v[1], -v[2]};
    mju_cross(cross, n, back);
    return std::atan2(mju_norm3(cross), mju_dot3(n, back)) <= angle;
  }
  // The lowest point of the moving bodies' capsules and boxes (world z; row-major frames, column 2 the z axis):
  // a capsule's centre height - |R_zz| half length - radius, a box's centre height - sum_k |R_zk| half size k.
  double lowestMovingPoint() const {
    double lowest = INFINITY;
    for (int g = 0; g < m_->ngeom; ++g) {
      if (m_->body_weldid[m_->geom_bodyid[g]] == 0) continue;
      const double* R = d_->geom_xmat + 9 * g;
      const double* size = m_->geom_size + 3 * g;
      double low = d_->geom_xpos[3 * g + 2];
      if (m_->geom_type[g] == mjGEOM_CAPSULE) {
        low -= std::abs(R[8]) * size[1] + size[0];
      } else if (m_->geom_type[g] == mjGEOM_BOX) {
        low -= std::abs(R[6]) * size[0] + std::abs(R[7]) * size[1] + std::abs(R[8]) * size[2];
      } else {
        ADD_FAILURE() << "geom type " << m_->geom_type[g] << " has no lowest point here";
      }
      lowest = std::min(lowest, low);
    }
    return lowest;
  }

 private:
  char error_[1000] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m_;
  std::unique_ptr<mjData, void (*)(mjData*)> d_;
  double metres_;
};

// The robot file's targets in metres, their unit normals.
struct Smrs {
  std::vector<std::string> names;
  std::vector<std::vector<double>> points, normals;
};
Smrs smrs(const json& j, const Case& c) {
  Smrs s;
  for (const json& t : j["targets"]) {
    s.names.push_back(t["name"]);
    std::vector<double> p = t["point"];
    for (double& x : p) x *= c.metres;
    s.points.push_back(p);
  }
  s.normals.assign(s.names.size(), c.normal);
  return s;
}

std::vector<double> trackerMetres(const Case& c) {
  return {c.tracker[0] * c.metres, c.tracker[1] * c.metres, c.tracker[2] * c.metres};
}

// Every planned pose contact-free and every target it lists seen; with `both_ways`, every target it does not
// list hidden.
void checkPlanInMujoco(const Case& c, const json& j, bool both_ways) {
  Judge judge(c);
  ASSERT_TRUE(judge.loaded()) << judge.error();
  const Smrs s = smrs(j, c);
  const auto q = j["q"].get<std::vector<std::vector<double>>>();
  ASSERT_EQ(j["measured"].size(), q.size());
  for (size_t k = 0; k < q.size(); ++k) {
    EXPECT_EQ(judge.contactsAt(q[k]), 0) << "planned pose " << k;
    const auto listed = j["measured"][k].get<std::vector<std::string>>();
    EXPECT_FALSE(listed.empty()) << "a planned pose measures no target";
    for (size_t t = 0; t < s.names.size(); ++t) {
      const bool is_listed = std::find(listed.begin(), listed.end(), s.names[t]) != listed.end();
      const bool seen = judge.sees(trackerMetres(c), s.points[t], s.normals[t], 30 * kDeg);
      if (is_listed) {
        EXPECT_TRUE(seen) << "pose " << k << " lists " << s.names[t] << ", which MuJoCo finds hidden";
      } else if (both_ways) {
        EXPECT_FALSE(seen) << "pose " << k << " leaves out " << s.names[t] << ", which is seen";
      }
    }
  }
}

// The counts add up, and each of `reasons` rejects some candidates.
void checkCounts(const json& j, const std::vector<std::string>& reasons) {
  const json& f = j["feasibility"];
  const json& r = f["rejected"];
  EXPECT_EQ(f["drawn"].get<int>(), f["kept"].get<int>() + r["total"].get<int>());
  EXPECT_EQ(r["total"].get<int>(), r["self_collision"].get<int>() + r["world"].get<int>() + r["floor"].get<int>() +
                                       r["occluded"].get<int>() + r["angle"].get<int>());
  for (const std::string& reason : reasons) EXPECT_GT(r[reason].get<int>(), 0) << reason;
  ASSERT_FALSE(f["line_of_sight"]["occluders"].empty());
  EXPECT_GT(f["line_of_sight"]["occluders"][0]["candidates"].get<int>(), 0);
}

// A plan without --partial: the counts, every pose in MuJoCo (each measuring every target), and the done-when's
// criterion: at least the best of 100 random sets drawn from the feasible candidates.
json checkedPlan(const Case& c, int poses, const std::vector<std::string>& reasons) {
  const json j = plan(c, "--poses " + std::to_string(poses));
  if (j.empty()) return j;
  checkCounts(j, reasons);
  for (const json& m : j["measured"]) EXPECT_EQ(m.size(), 3u);
  checkPlanInMujoco(c, j, true);
  EXPECT_GE(j["planned"]["log_det"].get<double>(), j["random"]["log_det"]["best"].get<double>());
  return j;
}

// The floor (not in the judge's model, at `floor` in the robot file's unit): every moving geom above it at every
// planned pose.
void checkAboveFloor(const Case& c, const json& j, double floor) {
  Judge judge(c);
  ASSERT_TRUE(judge.loaded()) << judge.error();
  for (const auto& q : j["q"].get<std::vector<std::vector<double>>>()) {
    judge.contactsAt(q);
    EXPECT_GE(judge.lowestMovingPoint(), floor * c.metres);
  }
}

}  // namespace

TEST(PlanSight, PumaCapsulesEveryPlannedPoseIsFreeAndSeesEverySmr) {
  EXPECT_FALSE(checkedPlan(kPuma, 12, {"self_collision", "world", "occluded", "angle"}).empty());
}

TEST(PlanSight, MenagerieCellEveryPlannedPoseIsFreeAndSeesEverySmr) {
  EXPECT_FALSE(checkedPlan(kCell, 20, {"self_collision", "world", "occluded", "angle"}).empty());
}

TEST(PlanSight, StanfordCapsulesEveryPlannedPoseIsFreeAndSeesEverySmr) {
  // the boom and the compact wrist never meet (j5 within +-90 deg): no self-collision in this model
  const json j = checkedPlan(kStanford, 12, {"world", "floor", "occluded", "angle"});
  ASSERT_FALSE(j.empty());
  EXPECT_EQ(j["feasibility"]["rejected"]["self_collision"].get<int>(), 0);
  checkAboveFloor(kStanford, j, 0.0);
}

TEST(PlanSight, RhinoCapsulesEveryPlannedPoseIsFreeAndSeesEverySmr) {
  // five revolute joints on a slide in cm: the judge moves the carriage by q1 x 0.01 m
  const json j = checkedPlan(kRhino, 12, {"self_collision", "world", "floor", "occluded", "angle"});
  ASSERT_FALSE(j.empty());
  checkAboveFloor(kRhino, j, -1.5);
}

TEST(PlanSight, ElbowCapsulesEveryPlannedPoseIsFreeAndSeesEverySmr) {
  const json j = checkedPlan(kElbow, 12, {"self_collision", "world", "floor", "occluded", "angle"});
  ASSERT_FALSE(j.empty());
  checkAboveFloor(kElbow, j, 0.0);
}

TEST(PlanSight, PartialListsExactlyTheTargetsEachPoseSees) {
  const json j = plan(kPuma, "--poses 20 --partial");
  ASSERT_FALSE(j.empty());
  checkPlanInMujoco(kPuma, j, true);
  int some_hidden = 0;
  for (const json& m : j["measured"]) some_hidden += m.size() < 3u;
  EXPECT_GT(some_hidden, 0) << "the case is meant to plan poses that see only some SMRs";
  EXPECT_GT(j["feasibility"]["line_of_sight"]["partial_kept"].get<int>(), 0);
  // the text lists them too
  const lowpair_test::CliRun text = runCli("plan " + kPuma.yaml + " --model " + kPuma.xml + " --tip tool --measure targets "
                                           "--tracker " + trackerText(kPuma) + " " + kPuma.extra + " --poses 20 --partial");
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("measures: smr_a"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("see only some targets"), std::string::npos) << text.out;
}

TEST(PlanSight, TrackerInsideTheWorldGeometryIsAnInputError) {
  const std::string base = "plan " + kPumaYaml + " --model " + kPumaXml + " --tip tool --measure targets --poses 3 --tracker ";
  // the fixture box is centred at (0.22, -0.24, -0.25) m, the pedestal's axis is z from -0.4 to -0.12 m
  expectRejected(base + "220,-240,-250", "inside geom 'fixture_box' of body 'fixture'", "--tracker");
  expectRejected(base + "0,0,-300", "inside geom 'pedestal'", "--tracker");
  expectRejected(base + "0,0,-500 --floor -400", "inside the floor", "--tracker");
  // just outside the fixture's +x face (0.29 m): not inside
  const lowpair_test::CliRun r = runCli(base + "300,-240,-250 --candidates 50");
  EXPECT_NE(r.status, 2) << r.err;
}

TEST(PlanSight, NoFeasibleCandidateIsExitOneAndWritesNothing) {
  // under the table top every ray passes through it
  const std::string out = scratch() + "/sight_none.csv";
  std::filesystem::remove(out);
  const lowpair_test::CliRun r = runCli("plan " + kCellYaml + " --model " + kCellXml + " --tip tool --measure targets "
                                        "--tracker 0.3,0.3,-0.3 --poses 5 --candidates 200 --out " + out);
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("no candidate of 200"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("hidden by geom 'table_top'"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(PlanSight, BadTrackerAngleAndNormalsAreInputErrors) {
  const std::string base = "plan " + kPumaYaml + " --model " + kPumaXml + " --tip tool --poses 3 ";
  expectRejected(base + "--measure targets --tracker 1,2", "expected X,Y,Z", "--tracker");
  expectRejected(base + "--measure targets --tracker 1,2,nan", "expected X,Y,Z", "--tracker");
  expectRejected(base + "--measure targets --tracker 1,2,3,4", "expected X,Y,Z", "--tracker");
  expectRejected(base + "--tracker 800,0,0", "needs target measurements", "--tracker");
  expectRejected(base + "--measure targets --tracker 800,0,0 --smr-angle 0", "(0, 180]", "--smr-angle");
  expectRejected(base + "--measure targets --tracker 800,0,0 --smr-angle 181", "(0, 180]", "--smr-angle");
  expectRejected(base + "--measure targets --partial", "goes with --tracker", "--partial");
  expectRejected("plan " + kPumaYaml + " --poses 3 --measure targets --tracker 800,0,0", "needs a model", "--tracker");
  std::ifstream in(kPumaYaml);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const std::string bad : {"[0, 0, 0]", "[0, 0, .nan]", "[-0.0, 0, 0]", "[0, 1]"}) {
    std::string t = text;
    t.replace(t.find("[0, 0, -2]"), 10, bad);
    const std::string path = writeScratchFile("bad_normal.yaml", t);
    expectRejected("plan " + path + " --poses 3", "normal", path);
  }
}

TEST(PlanSight, NormalsAreNormalisedOnLoad) {
  // smr_b's normal is written [0, 0, -2]: read as a unit vector it passes the same angle test as the others;
  // the angle check alone (180 deg: no cone) keeps as many candidates as no normals at all would
  const json wide = plan(kPuma, "--poses 3 --smr-angle 180");
  ASSERT_FALSE(wide.empty());
  EXPECT_EQ(wide["feasibility"]["rejected"]["angle"].get<int>(), 0);
  const json j = plan(kPuma, "--poses 12");
  ASSERT_FALSE(j.empty());
  checkPlanInMujoco(kPuma, j, true);  // the judge uses unit normals: [0, 0, -1] for smr_b
}

TEST(PlanSight, LoopPlannedPosesCalibrateTheActualCell) {
  const std::string actual_path = plan_sight::actualCell();
  ASSERT_FALSE(actual_path.empty());
  const std::string q = scratch() + "/cell_plan.csv", meas = scratch() + "/cell_meas.csv", val = scratch() + "/cell_val.csv";
  const std::string planned = "plan " + kCellYaml + " --model " + kCellXml + " --tip tool --measure targets --tracker " +
                              trackerText(kCell) + " " + kCell.extra + " --poses 20 --out " + q;
  ASSERT_EQ(runCli(planned).status, 0);
  // sigma = 1e-5 m per coordinate: the planned poses measured, and 30 held-out poses
  ASSERT_EQ(runCli("simulate " + actual_path + " --q-file " + q + " --measure targets --noise-position 1e-5 --seed 3 "
                   "--out " + meas).status, 0);
  ASSERT_EQ(runCli("simulate " + actual_path + " --poses 30 --measure targets --noise-position 1e-5 --seed 4 --out " + val)
                .status, 0);
  const lowpair_test::CliRun cal = runCli("calibrate " + kCellYaml + " --measurements " + meas + " --validation " + val +
                                          " --noise-position 1e-5 --json");
  ASSERT_EQ(cal.status, 0) << cal.err;
  const json j = json::parse(cal.out);
  EXPECT_TRUE(j["converged"].get<bool>());
  const double before = j["validation"]["before"]["rms_position"], after = j["validation"]["after"]["rms_position"];
  // a held-out point's noise is sqrt(3) sigma (RMS over three coordinates); the fitted model's own error at
  // 60 rows per 30-odd parameters adds about as much again: 3 sqrt(3) sigma leaves a factor 1.5 beyond both
  EXPECT_LT(after, 3.0 * std::sqrt(3.0) * 1e-5);
  EXPECT_GT(before, 10.0 * after);  // the 0.3 mm / 1 mrad errors were there, and the plan's poses removed them
}
