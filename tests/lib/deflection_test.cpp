// Joint deflections (deflection.hpp) in the error model, identifiability and the fit:
// 1. the sign rule of moveSigns on a hand-made sequence; poseLoads' refusals;
// 2. the identification Jacobian with deflections (every column, compliance and backlash included) against
//    central differences of forward kinematics at the deflected joint values of ErrorModel::apply and
//    applyDeflection, on random robots of every joint type;
// 3. identifiability: the numeric rank equals the count plus one per compliant or backlash joint;
// 4. calibration loops: a robot whose joints deflect under gravity and backlash, measured at the deflected
//    joints, recovered to rounding without noise and within 3 standard deviations with noise;
// 5. refusals: a vertical first axis (no gravity torque), a backlash joint that always moves one way.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "calibration_helpers.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/deflection.hpp"
#include "lowpair/gravity.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

namespace {

using namespace lowpair;
using namespace calibration_helpers;

TEST(MoveSigns, LastMoveKeptWhereTheJointDoesNotMove) {
  const std::vector<VecX> q = {Eigen::Vector2d(0, 5), Eigen::Vector2d(1, 5), Eigen::Vector2d(1, 4), Eigen::Vector2d(0.5, 4),
                               Eigen::Vector2d(0.5, 4), Eigen::Vector2d(2, 6)};
  const std::vector<VecX> s = moveSigns(q);
  const double expected[6][2] = {{0, 0}, {1, 0}, {1, -1}, {-1, -1}, {-1, -1}, {1, 1}};
  ASSERT_EQ(s.size(), 6u);
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(s[k][0], expected[k][0]) << "pose " << k;
    EXPECT_EQ(s[k][1], expected[k][1]) << "pose " << k;
  }
  EXPECT_TRUE(moveSigns({}).empty());
}

TEST(PoseLoads, RefuseBadSigns) {
  std::mt19937_64 rng(1);
  const PoeModel model = jointMix("RR", 1.0, rng);
  const std::vector<VecX> q = {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1)};
  EXPECT_THROW(poseLoads(model, MassModel{}, q, false, {Eigen::Vector2d(0, 2), Eigen::Vector2d(1, 1)}), std::invalid_argument);
  EXPECT_THROW(poseLoads(model, MassModel{}, q, false, {Eigen::Vector2d(0, 0)}), std::invalid_argument);
  EXPECT_THROW(poseLoads(model, MassModel{}, q, false, {VecX::Zero(3), VecX::Zero(3)}), std::invalid_argument);
  EXPECT_NO_THROW(poseLoads(model, MassModel{}, q, true, moveSigns(q)));
}

// 1-20 kg per link and payload, lengths in mm
MassModel randomMasses(const PoeModel& model, std::mt19937_64& rng) {
  MassModel m = lowpair_test::randomMasses(model, rng, 1.0);
  m.metres_per_unit = 1e-3;
  return m;
}

// The spec with every joint's compliance and backlash whose input varies over the poses' loads.
ErrorModelSpec deflectionSpec(const PoeModel& model, const std::vector<PoseLoad>& loads) {
  ErrorModelSpec spec;
  for (int i = 0; i < model.dof(); ++i) {
    for (const bool compliance : {true, false}) {
      ErrorModelSpec one;
      (compliance ? one.compliance_joints : one.backlash_joints).push_back(i);
      try {
        checkDeflections(model, one, loads);
        (compliance ? spec.compliance_joints : spec.backlash_joints).push_back(i);
      } catch (const std::invalid_argument&) {
      }
    }
  }
  return spec;
}

// One scaled unit of a parameter: L for lengths, 1 rad, 1 for scales, and for a compliance the amount that turns
// (or slides) the joint by one unit at the pose's load.
double unitOf(const Parameter& p, double L, const PoseLoad& load) {
  if (p.kind == ParameterKind::Compliance) {
    const double tau = std::abs(load.torque[p.joint]);
    return (p.unit == "length/N" ? L : 1.0) / tau;
  }
  return p.unit == "length" || p.unit == "length/rad" ? L : 1.0;
}

TEST(DeflectionJacobian, EveryColumnAgreesWithCentralDifferencesAtTheDeflectedJoints) {
  std::mt19937_64 rng(271);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int columns = 0;
  for (const std::string types : {"RRRRRR", "RRPRRR", "HRPHRR", "RPPR", "PRHRP"}) {
    for (int trial = 0; trial < 10; ++trial) {
      const PoeModel model = jointMix(types, 1000.0, rng);
      const MassModel masses = randomMasses(model, rng);
      const std::vector<VecX> qs = uniformPoses(model, 8, rng);
      const std::vector<PoseLoad> loads = poseLoads(model, masses, qs, true, moveSigns(qs));
      ErrorModelSpec spec = deflectionSpec(model, loads);
      spec.deflection.compliance = 1e-5 * VecX::Random(model.dof());
      spec.deflection.backlash = 1e-3 * VecX::Random(model.dof());
      const ErrorModel em(model, spec);
      const double L = model.lengthScale();
      const int n = em.size();
      for (size_t m = 0; m < qs.size(); ++m) {
        MatX J(6, n);
        const Pose T = em.jacobian(qs[m], loads[m], Measure::Pose, J);
        const VecX q_deflected = deflectedJoints(spec.deflection, qs[m], loads[m]);
        const Pose T_fk = poeForwardKinematics(model, q_deflected);
        const double S = distanceScale(model, q_deflected, T_fk);
        EXPECT_LE((T.p - T_fk.p).norm(), fkRounding(model.dof()) * S);
        for (int k = 0; k < n; ++k) {
          const Parameter& p = em.parameters()[static_cast<size_t>(k)];
          const double unit = unitOf(p, L, loads[m]);
          if (!std::isfinite(unit)) continue;  // no load on this joint at this pose
          const double h = 1e-5 * unit;
          auto at = [&](double step) {
            const VecX d = step * VecX::Unit(n, k);
            return poeForwardKinematics(em.apply(d), deflectedJoints(em.applyDeflection(d), qs[m], loads[m]));
          };
          const Pose plus = at(h), minus = at(-h);
          const Vec3 dtheta = logSO3(plus.R * minus.R.transpose()) / (2.0 * h);
          const Vec3 dp = (plus.p - minus.p) / (2.0 * h);
          // per scaled unit: truncation (h/unit)^2 S, rounding eps_fk S / (h/unit)
          const double tol_p = 1e-9 * S + fkRounding(model.dof()) * S / 1e-5, tol_r = tol_p / S;
          EXPECT_LE((J.col(k).tail<3>() - dp).norm() * unit, 10.0 * tol_p) << types << " " << p.name;
          EXPECT_LE((J.col(k).head<3>() - dtheta).norm() * unit, 10.0 * tol_r) << types << " " << p.name;
          ++columns;
        }
      }
    }
  }
  EXPECT_GT(columns, 1000);
}

TEST(DeflectionIdentifiability, RankEqualsCountPlusOnePerDeflection) {
  std::mt19937_64 rng(31);
  int analyses = 0, deflections = 0;
  for (const std::string types : {"RRRRRR", "RRPRRR", "HRPHRR", "PRRRR", "RPPR", "RRRRRRR"}) {
    for (int trial = 0; trial < 8; ++trial) {
      const PoeModel model = jointMix(types, std::pow(10.0, trial % 3), rng);
      MassModel masses = randomMasses(model, rng);
      masses.gravity = 9.81 * lowpair_test::unitVector(rng);
      const std::vector<VecX> qs = uniformPoses(model, 40, rng);
      const std::vector<PoseLoad> loads = poseLoads(model, masses, qs, true, moveSigns(qs));
      for (const Measure measure : {Measure::Pose, Measure::Position}) {
        const ErrorModelSpec spec = deflectionSpec(model, loads);
        const int k = static_cast<int>(spec.compliance_joints.size() + spec.backlash_joints.size());
        const int expected = identifiableCount(model, measure).total() + k;
        const Identifiability id = analyzeIdentifiability(model, qs, measure, spec, loads);
        EXPECT_EQ(id.expected.total(), expected) << types;
        EXPECT_EQ(id.poe.rank, expected) << types << " " << measureName(measure) << ", " << k << " deflections";
        EXPECT_EQ(id.poe.columns, identifiableCount(model, Measure::Pose).total() + k) << types;
        EXPECT_EQ(id.full_model_rank, expected) << types << " " << measureName(measure);
        ++analyses;
        deflections += k;
      }
    }
  }
  std::printf("%d analyses, %d deflection parameters\n", analyses, deflections);
  EXPECT_GT(deflections, 10 * analyses);
}

// The "actual" robot: the nominal's geometry moved by `delta`, joints deflecting by c tau + b s (tau from the actual
// geometry: what the robot feels), measured at the deflected joints.
struct Actual {
  PoeModel model;
  JointDeflection deflection;
};

std::vector<Measurement> measureDeflected(const Actual& actual, const MassModel& masses, const std::vector<VecX>& qs) {
  const std::vector<PoseLoad> loads = poseLoads(actual.model, masses, qs, true, moveSigns(qs));
  std::vector<Measurement> out;
  for (size_t k = 0; k < qs.size(); ++k) {
    out.push_back(Measurement{qs[k], poeForwardKinematics(actual.model, deflectedJoints(actual.deflection, qs[k], loads[k]))});
  }
  return out;
}

int indexOf(const ErrorModel& em, const std::string& name) {
  for (int k = 0; k < em.size(); ++k) {
    if (em.parameters()[static_cast<size_t>(k)].name == name) return k;
  }
  return -1;
}

// A 6R arm in mm with link masses of 1-20 kg; compliance 1e-6..3e-6 rad/(N m) on joints 2, 3 and 5, backlash 3e-4 rad
// on 2 and 4. (The model's load comes from the nominal's geometry, the robot's from its own: with line errors of
// 1e-4 rad the loads differ by ~1e-4 of themselves, 1e-7 rad of deflection, 1e-4 mm at 1 m: below the noise.)
struct Loop {
  PoeModel nominal;
  MassModel masses;
  Actual actual;
  CalibrationOptions options;
  std::vector<VecX> qs;
};

Loop makeLoop(std::mt19937_64& rng, double geometric_error) {
  const PoeModel nominal = jointMix("RRRRRR", 1000.0, rng);
  const MassModel masses = randomMasses(nominal, rng);
  const ErrorModel em(nominal);
  Actual actual{em.apply(smallDelta(em, geometric_error, false, rng)), {}};
  actual.deflection.compliance = VecX::Zero(6);
  actual.deflection.backlash = VecX::Zero(6);
  actual.deflection.compliance[1] = 2e-6;  // 5e5 N m/rad: a few 1e-4 rad under the arm's 100-500 N m
  actual.deflection.compliance[2] = 3e-6;
  actual.deflection.compliance[4] = 1e-6;
  actual.deflection.backlash[1] = 3e-4;
  actual.deflection.backlash[3] = -3e-4;
  Loop loop{nominal, masses, actual, {}, uniformPoses(nominal, 60, rng)};
  loop.options.compliance_joints = {1, 2, 4};
  loop.options.backlash_joints = {1, 3};
  loop.options.masses = masses;
  return loop;
}

TEST(DeflectionCalibration, NoiseFreeLoopRecoversComplianceAndBacklash) {
  std::mt19937_64 rng(2027);
  Loop loop = makeLoop(rng, 0.0);  // the geometry exact: tau is the same for the model and the robot
  const std::vector<Measurement> ms = measureDeflected(loop.actual, loop.masses, loop.qs);
  const CalibrationResult r = calibrate(loop.nominal, ms, loop.options);
  ASSERT_TRUE(r.converged);
  const double L = loop.nominal.lengthScale();
  EXPECT_LE(r.after.rms_position, 1e-9 * L);
  EXPECT_EQ(r.expected.deflections, 5);
  EXPECT_EQ(r.rank.rank, r.expected.total());
  for (const int j : {1, 2, 4}) {
    EXPECT_NEAR(r.deflection.compliance[j], loop.actual.deflection.compliance[j], 1e-6 * loop.actual.deflection.compliance[j]) << j;
    std::printf("j%d.compliance %.12g (true %.12g)\n", j + 1, r.deflection.compliance[j], loop.actual.deflection.compliance[j]);
  }
  for (const int j : {1, 3}) {
    EXPECT_NEAR(r.deflection.backlash[j], loop.actual.deflection.backlash[j], 1e-6 * std::abs(loop.actual.deflection.backlash[j])) << j;
    std::printf("j%d.backlash %.12g (true %.12g)\n", j + 1, r.deflection.backlash[j], loop.actual.deflection.backlash[j]);
  }
  // the estimate is the fitted increment from the nominal's (zero) deflections
  EXPECT_NEAR(r.estimate[indexOf(r.error_model, "j3.compliance")], 3e-6, 1e-6 * 3e-6);
}

TEST(DeflectionCalibration, NoisyLoopWithinThreeStandardDeviations) {
  std::mt19937_64 rng(2028);
  int within = 0, checked = 0;
  for (int trial = 0; trial < 10; ++trial) {
    Loop loop = makeLoop(rng, 1e-4);
    std::vector<Measurement> ms = measureDeflected(loop.actual, loop.masses, loop.qs);
    addNoise(ms, 0.01, 1e-5, rng);
    loop.options.sigma_position = 0.01;
    loop.options.sigma_rotation = 1e-5;
    const CalibrationResult r = calibrate(loop.nominal, ms, loop.options);
    ASSERT_TRUE(r.converged);
    EXPECT_TRUE(r.accepted) << r.reason;
    for (const auto& [name, j, truth] : std::vector<std::tuple<std::string, int, double>>{
             {"j2.compliance", 1, loop.actual.deflection.compliance[1]}, {"j3.compliance", 2, loop.actual.deflection.compliance[2]},
             {"j5.compliance", 4, loop.actual.deflection.compliance[4]}, {"j2.backlash", 1, loop.actual.deflection.backlash[1]},
             {"j4.backlash", 3, loop.actual.deflection.backlash[3]}}) {
      const int k = indexOf(r.error_model, name);
      ASSERT_GE(k, 0) << name;
      const double sd = r.standard_deviation[k];
      const double value = name.find("compliance") != std::string::npos ? r.deflection.compliance[j] : r.deflection.backlash[j];
      ASSERT_TRUE(std::isfinite(sd) && sd > 0.0) << name;
      if (trial == 0) std::printf("%s %.4g +- %.2g (true %.4g)\n", name.c_str(), value, sd, truth);
      within += std::abs(value - truth) <= 3.0 * sd ? 1 : 0;
      ++checked;
    }
  }
  std::printf("%d of %d within 3 sd\n", within, checked);
  // 3 sd holds with probability 0.997 per parameter: at most one miss in 50 (P(two or more) ~ 1 %)
  EXPECT_GE(within, checked - 1);
}

TEST(DeflectionCalibration, RefusesAVerticalFirstAxisAndABacklashThatNeverReverses) {
  std::mt19937_64 rng(7);
  std::vector<Joint> joints = jointMix("RRRRRR", 1000.0, rng).joints();
  joints[0].twist << 0, 0, 1, Vec3(100, 50, 0).cross(Vec3(0, 0, 1));
  const PoeModel model(joints, jointMix("R", 1000.0, rng).toolPose());
  CalibrationOptions options;
  options.masses = randomMasses(model, rng);
  options.compliance_joints = {0};
  const std::vector<VecX> qs = uniformPoses(model, 20, rng);
  const std::vector<Measurement> ms = measure(model, qs);
  try {
    calibrate(model, ms, options);
    ADD_FAILURE() << "no refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint 1: its gravity load does not vary"), std::string::npos) << e.what();
  }
  // joint 2 carries a load: accepted
  options.compliance_joints = {1};
  EXPECT_NO_THROW(calibrate(model, ms, options));
  // joint 3 always moving up: its sign is 1 after the first pose and 0 there, so it varies once; sorted poses and
  // explicit signs of 1 everywhere do not
  options.compliance_joints = {};
  options.backlash_joints = {2};
  options.move_signs.assign(ms.size(), VecX::Ones(6));
  try {
    calibrate(model, ms, options);
    ADD_FAILURE() << "no refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint 3: the sign of its last move is 1 at every one"), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

// compensate's inverse: the command whose joints stand at q_stand, checked through the forward rule.
TEST(CommandFor, StandsWhereAsked) {
  std::mt19937_64 rng(99);
  int solved = 0;
  for (const std::string types : {"RRRRRR", "RRPRRR", "HRPHRR"}) {
    for (int trial = 0; trial < 20; ++trial) {
      const PoeModel model = jointMix(types, 1000.0, rng);
      MassModel masses = randomMasses(model, rng);
      JointDeflection d;
      d.compliance = 3e-6 * VecX::Random(model.dof()).cwiseAbs();
      d.backlash = 3e-4 * VecX::Random(model.dof());
      const VecX q_stand = uniformJoints(model, rng);
      const VecX s = VecX::Random(model.dof()).array().sign().matrix();
      const std::optional<VecX> q = commandFor(model, masses, d, q_stand, s);
      ASSERT_TRUE(q.has_value()) << types;
      const VecX back = deflectedJoints(d, *q, PoseLoad{gravityTorques(model, masses, *q), s});
      // the fixed point to its stopping rule, plus one evaluation's rounding
      EXPECT_LE((back - q_stand).cwiseAbs().maxCoeff(), 32.0 * kEpsilon * (1.0 + q_stand.cwiseAbs().maxCoeff())) << types;
      EXPECT_GT((*q - q_stand).cwiseAbs().maxCoeff(), 1e-6);  // it did move
      ++solved;
    }
  }
  EXPECT_EQ(solved, 60);
}

}  // namespace

namespace {

// Cross-validation fits each fold's deflections on its training poses and predicts the held-out poses at their
// loads and at the move signs of the whole set's order (re-derived from a fold's own order, a held-out pose's sign
// would be the sign of a move it never made): on noise-free data the candidate with both deflections predicts every
// held-out pose to rounding (the fit's own floor, 1e-9 L; 1e-7 of the weighted unit 1/L leaves room for the fold
// fits), while a candidate without one misses by its deflections (1e-4 rad at ~1000 mm: 1e-4 of L).
TEST(DeflectionCalibration, CrossValidationFitsEachFoldsDeflectionsAtTheWholeSetsSigns) {
  std::mt19937_64 rng(2027);
  Loop loop = makeLoop(rng, 0.0);
  const std::vector<Measurement> ms = measureDeflected(loop.actual, loop.masses, loop.qs);
  CrossValidationGrid grid;
  grid.levels = {ParameterSet::Full};
  grid.compliance_off = true;
  grid.backlash_off = true;
  const CrossValidation cv = crossValidate(loop.nominal, ms, loop.options, 5, 1, grid);
  ASSERT_EQ(cv.candidates.size(), 4u);  // compliance off/on x backlash off/on
  for (const CrossValidation::Candidate& c : cv.candidates) {
    ASSERT_FALSE(c.failed);
    std::printf("compliance %d backlash %d: score %.3g\n", c.compliance, c.backlash, c.score);
    if (c.compliance && c.backlash) {
      EXPECT_LE(c.score, 1e-7);
    } else {
      EXPECT_GE(c.score, 1e-5);
    }
  }
  const CrossValidation::Candidate& chosen = cv.candidates[static_cast<size_t>(cv.chosen_index)];
  EXPECT_TRUE(chosen.compliance && chosen.backlash);
  EXPECT_TRUE(std::isnan(chosen.score_sd));  // one partition
}

}  // namespace
