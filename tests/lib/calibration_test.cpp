// Calibration (calibration.hpp) against references that do not come from the calibration code:
//
// 1. The identification Jacobian against central differences of forward kinematics of ErrorModel::apply,
//    column by column, on 1,000 seeded random robots (tests/common/random_robot.hpp: every joint type, degenerate
//    geometry), with and without free pitch; apply(0) and the type-preserving rule of apply.
// 2. Identifiability: the numeric rank equals the paper's count 5h + 4r + 2t + n + 6 (Wu et al. §V; 3 for
//    the tool with position-only measurements) on 1,000 random robots and hand-built joint mixes, and it
//    equals the rank of the unreduced error model. Position-only measurements of a tool point lying on the
//    last joint lines lose more, by an amount derived below (the count is an "at most").
// 3. D-H: exactly parallel consecutive axes cost the D-H parameterization one rank; nearly parallel ones
//    keep the rank but not the conditioning. The POE parameterization has no such singularity.
// 4. The calibration loop with the FK of a perturbed "actual" model as truth: noise-free, noisy (the
//    stated covariance against the realized error), position-only, too few poses, bad input.
// 5. dhUncertainty against the spread of repeated noisy calibrations and at nearly parallel axes.
//
// Scales. L = model.lengthScale(). Parameters are compared in "scaled units": a length or pitch parameter of
// size L, an angle of 1 rad and a scale increment of 1 are each one unit (parameterUnit).
//
// Forward-kinematics rounding (used by several bounds). A chain of n joints is n + 1 pose products and n
// joint exponentials; each product adds ~3 eps relative to the magnitudes involved and each sine/cosine
// of a motion |x| <= 4 adds ~|x| eps; every point involved lies within the distance scale S of the
// configuration (below), so one FK is accurate to eps_fk = 16 (n + 1) eps S in position and
// 16 (n + 1) eps in rotation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "calibration_helpers.hpp"
#include "random_robot.hpp"

using namespace lowpair;
using lowpair_test::geometryName;
using lowpair_test::randomRobot;
using lowpair_test::RandomRobot;

using namespace calibration_helpers;

// ---- 1. the identification Jacobian ---------------------------------------------------------------------
//
// Column k against central differences of FK(apply(+-h u_k e_k)) at q (u_k = parameterUnit), i.e. per
// scaled unit: rotation rows against logSO3(R+ R-^T) / 2h (BCH: the h^2 terms cancel, the error is
// O(h^2)), position rows against (p+ - p-) / 2h. Error bound per column:
//   truncation: h^2 rho^3 S (position), h^2 rho^3 (rotation), where rho is the angular rate of the tool's
//     motion along the parameter: a tilt conjugates the joint by a unit-rate rotation (two rotations of
//     rate 1, rho = 2); a scale turns the joint by rate |q + offset| (rho = |q + offset| for revolute and
//     helical joints; prismatic: a translation, affine in t); shifts, pitches and tool translations
//     translate (affine, rho = 0); a tool rotation turns about a line through the tool point (position
//     constant, rotation exactly exp(t r) R, rho = 0). The third derivative of a point under motions of
//     total rate rho at distance <= S is <= rho^3 S; the Taylor term's 1/6 is dropped (a factor 6 of margin
//     for the constants of the composition and of BCH).
//   rounding: two FKs of accuracy eps_fk, divided by 2h: eps_fk / h (apply's own rounding of the twists
//     is of the same order and included in the factor 16 of eps_fk).
// h = cbrt(eps) = 6.1e-6: for a 7-joint robot the bound is 3.7e-11 rho^3 S + 4.7e-9 S.
TEST(ErrorModelJacobian, ColumnsMatchCentralDifferencesOnRandomRobots) {
  std::mt19937_64 rng(20190205);
  const double h = std::cbrt(kEpsilon);
  Failures failures;
  double worst_ratio = 0.0, worst_fk = 0.0;
  int columns = 0;
  std::map<std::string, int> robots_by_geometry;
  for (int r = 0; r < 1000; ++r) {
    const RandomRobot robot = randomRobot(rng);
    const PoeModel& model = robot.model;
    const bool free_pitch = r % 2 == 1;
    const ErrorModel em(model, ErrorModelSpec{free_pitch});
    ++robots_by_geometry[geometryName(robot.geometry)];
    ASSERT_EQ(em.size(), identifiableCount(model, Measure::Pose, ErrorModelSpec{free_pitch}).total());
    const double L = model.lengthScale();
    const int n = model.dof();
    const VecX q = lowpair_test::randomConfiguration(model, rng);
    MatX J(6, em.size()), Jp(3, em.size());
    const Pose T = em.jacobian(q, Measure::Pose, J);
    const Pose Tp = em.jacobian(q, Measure::Position, Jp);
    const Pose T_ref = poeForwardKinematics(model, q);
    const double S = distanceScale(model, q, T_ref);
    const double e_fk = fkRounding(n);
    // the returned pose is the model's FK (two evaluations, each within eps_fk)
    const double fk_dev = std::max({(T.p - T_ref.p).norm() / S, rotationError(T.R, T_ref.R), (Tp.p - T_ref.p).norm() / S});
    worst_fk = std::max(worst_fk, fk_dev / (2 * e_fk));
    if (!(fk_dev <= 2 * e_fk)) failures.add(format("robot %g: jacobian's pose differs from FK by %.3g (bound %.3g)", r, fk_dev, 2 * e_fk));
    // apply(0) is the model
    const Pose T0 = poeForwardKinematics(em.apply(VecX::Zero(em.size())), q);
    const double apply0 = std::max((T0.p - T_ref.p).norm() / S, rotationError(T0.R, T_ref.R));
    if (!(apply0 <= 2 * e_fk)) failures.add(format("robot %g: apply(0) moves FK by %.3g (bound %.3g)", r, apply0, 2 * e_fk));
    for (int k = 0; k < em.size(); ++k) {
      const Parameter& p = em.parameters()[static_cast<size_t>(k)];
      const double unit = parameterUnit(p, L);
      VecX d = VecX::Zero(em.size());
      d[k] = h * unit;
      const Pose plus = poeForwardKinematics(em.apply(d), q), minus = poeForwardKinematics(em.apply(-d), q);
      const Vec3 fd_rot = logSO3(plus.R * minus.R.transpose()) / (2 * h);
      const Vec3 fd_pos = (plus.p - minus.p) / (2 * h);
      double rho = 0.0;
      if (p.kind == ParameterKind::Tilt) rho = 2.0;
      if (p.kind == ParameterKind::Scale && model.joint(p.joint).type != JointType::Prismatic) {
        rho = std::abs(q[p.joint] + model.joint(p.joint).offset);
      }
      const double tol_rot = h * h * rho * rho * rho + e_fk / h;
      const double tol_pos = (h * h * rho * rho * rho + e_fk / h) * S;
      const double err_rot = (J.col(k).head<3>() * unit - fd_rot).norm();
      const double err_pos = (J.col(k).tail<3>() * unit - fd_pos).norm();
      const double err_pos_only = (Jp.col(k) * unit - fd_pos).norm();
      worst_ratio = std::max({worst_ratio, err_rot / tol_rot, err_pos / tol_pos, err_pos_only / tol_pos});
      if (!(err_rot <= tol_rot && err_pos <= tol_pos && err_pos_only <= tol_pos)) {
        failures.add("robot " + std::to_string(r) + " (" + typeString(model) + ", " + geometryName(robot.geometry) +
                     (free_pitch ? ", free pitch" : "") + ") column " + p.name +
                     format(": rotation error %.3g (bound %.3g), position %.3g / S (bound %.3g / S)", err_rot, tol_rot,
                            std::max(err_pos, err_pos_only) / S, tol_pos / S));
      }
      ++columns;
    }
  }
  std::printf("%d columns on 1000 robots:", columns);
  for (const auto& [g, c] : robots_by_geometry) std::printf(" %s %d", g.c_str(), c);
  std::printf("\nworst error / bound: columns %.3g, pose of jacobian() and apply(0) vs FK %.3g\n", worst_ratio, worst_fk);
  EXPECT_EQ(failures.count, 0);
}

// apply keeps what the error model says it keeps (calibration.hpp): Ad(exp(eta)) keeps |w| = 1, w.v (the
// pitch) and w = 0, so types and pitches survive any joint perturbation; the pitch and scale increments
// add; names, offsets and ranges are kept; the tool moves by exp([r; p_T x r + t]), i.e. r turns it about
// base-parallel axes through its own point and t translates it.
// Tolerances: a pitch w.v is a dot product of entries of size <= |v| <= L + |h| after a rigid motion
// whose own rounding is a few eps: 64 eps (L + |h|); unit norms and types to 64 eps; a scale increment is
// one addition: eps (scale + |ds|); the tool's point under a rotation about a line through it moves by
// the rounding of exp and one product: 64 eps (|p| + L).
TEST(ErrorModelApply, KeepsJointTypesPitchesAndAddsIncrements) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n;
  Failures failures;
  int pitched = 0;
  for (int r = 0; r < 500; ++r) {
    const PoeModel model = randomRobot(rng).model;
    const bool free_pitch = r % 2 == 1;
    const ErrorModel em(model, ErrorModelSpec{free_pitch});
    const double L = model.lengthScale();
    // large joint perturbations (angles ~0.3 rad, lengths ~0.3 L), pitch increments only when `with_pitch`
    for (const bool with_pitch : {false, true}) {
      const VecX d = smallDelta(em, 0.3, with_pitch, rng);
      const PoeModel moved = em.apply(d);
      ASSERT_EQ(moved.dof(), model.dof());
      for (int i = 0; i < model.dof(); ++i) {
        const Joint& a = model.joint(i);
        const Joint& b = moved.joint(i);
        double dh = 0.0, ds = 0.0;
        for (int k = 0; k < em.size(); ++k) {
          const Parameter& p = em.parameters()[static_cast<size_t>(k)];
          if (p.joint == i && p.kind == ParameterKind::Pitch) dh = d[k];
          if (p.joint == i && p.kind == ParameterKind::Scale) ds = d[k];
        }
        const std::string where = "robot " + std::to_string(r) + " joint " + std::to_string(i + 1);
        const double new_pitch = a.pitch + dh;
        const JointType expected_type = a.type == JointType::Prismatic ? JointType::Prismatic
                                        : new_pitch != 0.0              ? JointType::Helical
                                                                        : JointType::Revolute;
        if (b.type != expected_type) failures.add(where + ": type " + jointTypeName(b.type) + ", expected " + jointTypeName(expected_type));
        if (std::abs(b.pitch - new_pitch) > 64 * kEpsilon * (L + std::abs(new_pitch))) {
          failures.add(where + format(": pitch %.17g, expected %.17g", b.pitch, new_pitch));
        }
        if (std::abs(b.scale - (a.scale + ds)) > kEpsilon * (a.scale + std::abs(ds))) {
          failures.add(where + format(": scale %.17g, expected %.17g", b.scale, a.scale + ds));
        }
        if (b.offset != a.offset || b.name != a.name || b.range != a.range) failures.add(where + ": offset, name or range changed");
        const double w = b.axis().norm();
        if (a.type == JointType::Prismatic ? (w != 0.0 || std::abs(b.moment().norm() - 1) > 64 * kEpsilon)
                                           : std::abs(w - 1) > 64 * kEpsilon) {
          failures.add(where + ": not a unit twist of its type");
        }
        if (b.type == JointType::Helical) ++pitched;
      }
    }
    // the tool: translation alone, rotation alone
    const Pose& T = model.toolPose();
    const int tool0 = em.size() - 6;
    VecX d = VecX::Zero(em.size());
    const Vec3 t = 0.3 * L * lowpair_test::draw3(n, rng), rot = 0.5 * lowpair_test::draw3(n, rng);
    d.segment<3>(tool0 + 3) = t;
    const Pose translated = em.apply(d).toolPose();
    d.segment<3>(tool0 + 3).setZero();
    d.segment<3>(tool0) = rot;
    const Pose turned = em.apply(d).toolPose();
    const double tol = 64 * kEpsilon * (T.p.norm() + L);
    if (!((translated.p - (T.p + t)).norm() <= tol && rotationError(translated.R, T.R) <= 64 * kEpsilon)) {
      failures.add("robot " + std::to_string(r) + ": tool translation is not T.p + t");
    }
    if (!((turned.p - T.p).norm() <= tol && rotationError(turned.R, expSO3(rot) * T.R) <= 64 * kEpsilon)) {
      failures.add("robot " + std::to_string(r) + ": tool rotation does not turn about the tool point");
    }
  }
  std::printf("%d helical joints after apply\n", pitched);
  EXPECT_GT(pitched, 0);
  EXPECT_EQ(failures.count, 0);
}

// ---- 2. identifiability ---------------------------------------------------------------------------------
//
// For each model, measure and free-pitch choice: max(10, ceil(2 count / rows per pose)) uniform poses.
// Asserted:
//   - identifiableCount's breakdown against the joint types counted here (free pitch: revolute counted
//     as helical), tool 6 / 3;
//   - poe.rank == count - loss, loss from positionOnlyLoss (0 for pose measurements);
//   - full_model_rank == count - loss as well (the reduced model loses nothing; the offsets add nothing),
//     full_model_columns = 6n + pitches + 2n + 6, poe.columns = ErrorModel size;
//   - one undetermined direction per missing rank; condition finite and observability > 0 iff full rank;
//   - dh.rank <= count - loss (every D-H model is a POE model, so the D-H Jacobian's range is inside the full
//     error model's), for tables whose lengths stay within 1e3 L (DhConversion::scale; kIllConditioned):
//     beyond that, nearly parallel axes put lengths up to 1e13 L into the table, the D-H Jacobian's
//     entries then carry rounding of eps scale / L relative to their column, column scaling turns that into
//     singular values far above any eps-level rank tolerance, and its numeric rank says nothing.
namespace {

struct RankTally {
  int analyses = 0, degenerate = 0;
  std::map<std::string, int> fails_by_geometry, fails_by_kind;
};

void checkIdentifiability(const PoeModel& model, Measure measure, bool free_pitch, const std::string& label,
                          std::mt19937_64& rng, RankTally& tally, Failures& failures) {
  const TypeCount types = countTypes(model);
  const ParameterCount count = identifiableCount(model, measure, ErrorModelSpec{free_pitch});
  const int per = measure == Measure::Pose ? 6 : 3;
  const int poses = std::max(10, (2 * count.total() + per - 1) / per);
  const std::vector<VecX> qs = uniformPoses(model, poses, rng);
  const Identifiability id = analyzeIdentifiability(model, qs, measure, ErrorModelSpec{free_pitch});
  const std::string where = label + " " + typeString(model) + " " + measureName(measure) + (free_pitch ? " free-pitch" : "");
  ++tally.analyses;
  bool ok = true;
  auto fail = [&](const std::string& what) {
    failures.add(where + ": " + what);
    ok = false;
  };
  const int helical = types.helical + (free_pitch ? types.revolute : 0);
  if (count.helical != helical || count.revolute != (free_pitch ? 0 : types.revolute) ||
      count.prismatic != types.prismatic || count.scales != model.dof() || count.tool != per) {
    fail("identifiableCount breakdown");
  }
  if (id.expected.total() != count.total()) fail("Identifiability::expected differs from identifiableCount");
  const int expected_total = 5 * helical + 4 * (free_pitch ? 0 : types.revolute) + 2 * types.prismatic + model.dof() + per;
  if (count.total() != expected_total) fail("count total");
  const int loss = measure == Measure::Position ? positionOnlyLoss(model) : 0;
  if (loss > 0) ++tally.degenerate;
  const int expected_rank = count.total() - loss;
  // the singular values of the scaled Jacobian from the smaller to the larger of the two ranks
  auto around = [&](const RankAnalysis& a) {
    std::string out = format(" (tolerance %.3g; sigma", a.tolerance);
    for (int k = std::max(0, std::min(a.rank, expected_rank) - 1); k <= std::max(a.rank, expected_rank) && k < a.columns; ++k) {
      out += format(" %.3g", a.singular_values[k]);
    }
    return out + ")";
  };
  if (id.poe.rank != expected_rank) {
    ++tally.fails_by_kind["minimal rank"];
    fail("rank " + std::to_string(id.poe.rank) + ", expected " + std::to_string(expected_rank) + " (count " +
         std::to_string(count.total()) + ", loss " + std::to_string(loss) + ")" + around(id.poe));
  }
  if (id.full_model_rank != expected_rank) {
    ++tally.fails_by_kind["full error model rank"];
    fail("full error model rank " + std::to_string(id.full_model_rank) + ", expected " + std::to_string(expected_rank) +
         around(analyzeRank(fullErrorModelJacobian(model, qs, measure, ErrorModelSpec{free_pitch}), measure, model.lengthScale(), poses)));
  }
  const int em_size = ErrorModel(model, ErrorModelSpec{free_pitch}).size();
  if (id.poe.columns != em_size || static_cast<int>(id.parameters.size()) != em_size) fail("poe columns");
  if (id.full_model_columns != 8 * model.dof() + helical + 6) fail("full model columns");
  if (static_cast<int>(id.poe.undetermined.size()) != id.poe.columns - id.poe.rank) fail("undetermined directions");
  const bool full = id.poe.rank == id.poe.columns;
  if (full != std::isfinite(id.poe.condition) || full != (id.poe.observability[1] > 0.0)) fail("condition / observability");
  const double dh_scale = poeToDh(model).scale / model.lengthScale();
  if (dh_scale <= 1e3 && id.dh.rank > expected_rank) {
    ++tally.fails_by_kind["D-H rank above the count"];
    fail("D-H rank " + std::to_string(id.dh.rank) + " > " + std::to_string(expected_rank) + around(id.dh));
  }
  if (!ok) ++tally.fails_by_geometry[label];
}

}  // namespace

TEST(Identifiability, RankEqualsCountOnRandomRobots) {
  std::mt19937_64 rng(1902);
  Failures failures;
  RankTally tally;
  for (int r = 0; r < lowpair_test::robotCount(1000); ++r) {
    const RandomRobot robot = randomRobot(rng);
    const std::string label = geometryName(robot.geometry);
    checkIdentifiability(robot.model, Measure::Pose, false, label, rng, tally, failures);
    checkIdentifiability(robot.model, Measure::Position, false, label, rng, tally, failures);
    checkIdentifiability(robot.model, r % 2 == 0 ? Measure::Pose : Measure::Position, true, label, rng, tally, failures);
  }
  std::printf("%d analyses; position-only with parameters lost to the tool point's place: %d\n", tally.analyses,
              tally.degenerate);
  for (const auto& [g, c] : tally.fails_by_geometry) std::printf("  failing geometry %s: %d\n", g.c_str(), c);
  for (const auto& [k, c] : tally.fails_by_kind) std::printf("  failing check %s: %d\n", k.c_str(), c);
  EXPECT_EQ(failures.count, 0);
  EXPECT_GT(tally.degenerate, 0);  // the position-only exception is exercised
}

// The mixes of design.md (RRRRRR 36, RRPRRR 34, HRPHRR 36, PRRRR 29, HHHHPP 36, RPPR 22, RRRRRRR 41 for
// pose measurements), 20 generic robots each at sizes 0.1-1000.
TEST(Identifiability, RankEqualsCountOnJointMixes) {
  std::mt19937_64 rng(5);
  const std::vector<std::pair<std::string, int>> mixes = {{"RRRRRR", 36}, {"RRPRRR", 34}, {"HRPHRR", 36}, {"PRRRR", 29},
                                                          {"HHHHPP", 36}, {"RPPR", 22},   {"RRRRRRR", 41}};
  Failures failures;
  RankTally tally;
  for (const auto& [types, pose_count] : mixes) {
    for (int r = 0; r < 20; ++r) {
      const PoeModel model = jointMix(types, std::pow(10.0, -1.0 + 4.0 * r / 19.0), rng);
      EXPECT_EQ(identifiableCount(model, Measure::Pose).total(), pose_count) << types;
      EXPECT_EQ(identifiableCount(model, Measure::Position).total(), pose_count - 3) << types;
      for (const Measure m : {Measure::Pose, Measure::Position}) {
        for (const bool free_pitch : {false, true}) checkIdentifiability(model, m, free_pitch, types, rng, tally, failures);
      }
    }
  }
  EXPECT_EQ(tally.degenerate, 0);
  EXPECT_EQ(failures.count, 0);
}

// The exception above, constructed: a generic 6R whose tool point is put on the last joint's line loses 3
// (scale and the tilts about the point), and the PUMA with the tool point at its wrist centre (as in the
// file: joints 4, 5, 6 all pass through it) loses 9; with pose measurements both have the full count.
TEST(Identifiability, PositionOnlyLosesJointsThroughTheToolPoint) {
  std::mt19937_64 rng(11);
  const PoeModel generic = jointMix("RRRRRR", 1.0, rng);
  const Joint& last = generic.joint(5);
  const Pose tool{generic.toolPose().R, linePoint(last) + 0.7 * last.axis()};
  const PoeModel on_axis(generic.joints(), tool, "tool on the last axis");
  const PoeModel puma = pumaLike(0.0, false);
  const std::vector<VecX> qs = uniformPoses(generic, 40, rng);
  struct Case {
    const PoeModel* model;
    int position_loss;
  };
  for (const Case& c : {Case{&generic, 0}, Case{&on_axis, 3}, Case{&puma, 9}}) {
    const Identifiability pose = analyzeIdentifiability(*c.model, qs, Measure::Pose);
    const Identifiability position = analyzeIdentifiability(*c.model, qs, Measure::Position);
    EXPECT_EQ(pose.poe.rank, 36) << c.model->name();
    EXPECT_EQ(position.poe.rank, 33 - c.position_loss) << c.model->name();
    EXPECT_EQ(position.full_model_rank, position.poe.rank) << c.model->name();
    EXPECT_EQ(positionOnlyLoss(*c.model), c.position_loss) << c.model->name();
  }
}

// ---- 3. D-H at parallel axes ----------------------------------------------------------------------------
//
// pumaLike(0): joints 2 and 3 exactly parallel and no other consecutive pair. The D-H row between them has
// d free (set to 0): the d of that row and of the next both translate along parallel lines (one column
// redundant) and the tilt of joint 3 in the plane of the two axes is not representable, so the D-H rank
// is exactly one below the POE rank, which is the count (36 columns each for a 6R: 4 + 6 x 5 + 2).
// Tilted by 1e-3 rad about the common normal (alpha = 1e-3): the in-plane tilt is now representable only
// through d moving by a / alpha^2 per rad, so the smallest singular value of the D-H Jacobian shrinks by
// about alpha relative to a generic table; the POE Jacobian is a smooth function of the geometry and its
// conditioning moves by O(alpha). The ratio of the two conditions is therefore of order 1 / alpha = 1e3
// times the ratio at generic geometry; asserting > 10 leaves a factor 100 for the parameterization-
// dependent prefactor. The POE conditions at alpha = 0 and 1e-3 agree within a factor 2.
TEST(Identifiability, DhLosesRankAtParallelAxesPoeDoesNot) {
  std::mt19937_64 rng(560);
  const PoeModel parallel = pumaLike(0.0, false), tilted = pumaLike(1e-3, false);
  std::vector<VecX> qs;
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  for (int k = 0; k < 30; ++k) {
    VecX q(6);
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    qs.push_back(q);
  }
  const Identifiability a = analyzeIdentifiability(parallel, qs, Measure::Pose);
  const Identifiability b = analyzeIdentifiability(tilted, qs, Measure::Pose);
  std::printf("parallel: poe rank %d cond %.3g, dh rank %d (of %d)\n", a.poe.rank, a.poe.condition, a.dh.rank, a.dh.columns);
  std::printf("tilted 1e-3: poe rank %d cond %.3g, dh rank %d cond %.3g, ratio %.3g\n", b.poe.rank, b.poe.condition,
              b.dh.rank, b.dh.condition, b.dh.condition / b.poe.condition);
  EXPECT_EQ(a.expected.total(), 36);
  EXPECT_EQ(a.poe.rank, 36);
  EXPECT_EQ(a.dh.columns, 36);
  EXPECT_EQ(a.dh.rank, a.poe.rank - 1);
  EXPECT_EQ(b.poe.rank, 36);
  EXPECT_EQ(b.dh.rank, b.poe.rank);
  EXPECT_GT(b.dh.condition / b.poe.condition, 10.0);
  EXPECT_LT(std::max(a.poe.condition / b.poe.condition, b.poe.condition / a.poe.condition), 2.0);
}

// ---- 4. calibration loops -------------------------------------------------------------------------------
//
// Noise-free bound. The measurements are FKs of the actual model, each row wrong by eps_fk (rotation) and
// eps_fk S (position). At the solution the weighted, column-scaled problem (rows made dimensionless by L)
// has residual |e| <= sqrt(6 P) eps_fk S / L, so the scaled parameter error is <= |e| / sigma_min, and
// the error it makes at any pose (a block of 6 rows of norm <= sigma_1 / sqrt(P) on average) is
// <= sqrt(6) kappa eps_fk S, kappa = sigma_1 / sigma_min of the determined part. Bound used:
// 4 kappa eps_fk S over the validation poses (and the same for the residual on the measurements).
TEST(Calibration, NoiseFreeRecoversTheActualRobot) {
  std::mt19937_64 rng(31);
  Failures failures;
  double worst_ratio = 0.0, worst_over_L = 0.0, worst_kappa = 0.0;
  int max_iterations = 0, robots = 0;
  std::map<std::string, int> mixes;
  for (int r = 0; r < 60; ++r) {
    const RandomRobot robot = randomRobot(rng);
    const PoeModel& nominal = robot.model;
    const bool free_pitch = r % 2 == 1;
    const ErrorModel em(nominal, ErrorModelSpec{free_pitch});
    const PoeModel actual = em.apply(smallDelta(em, 1e-3, free_pitch, rng));
    const std::vector<VecX> train = uniformPoses(nominal, 50, rng), check = uniformPoses(nominal, 100, rng);
    CalibrationOptions options;
    options.free_pitch = free_pitch;
    const CalibrationResult result = calibrate(nominal, measure(actual, train), options);
    const double L = nominal.lengthScale();
    const double S = std::max(maxDistanceScale(actual, train), maxDistanceScale(actual, check));
    const double kappa = determinedCondition(result.rank);
    const double bound = 4.0 * kappa * fkRounding(nominal.dof()) * S;
    const Deviation v = positionDeviation(result.model, actual, check);
    const std::string where = "robot " + std::to_string(r) + " (" + typeString(nominal) + ", " + geometryName(robot.geometry) +
                              (free_pitch ? ", free pitch" : "") + ")";
    if (!result.converged) failures.add(where + ": not converged");
    if (result.rank.rank != result.expected.total()) {
      failures.add(where + ": rank " + std::to_string(result.rank.rank) + " of " + std::to_string(result.expected.total()));
    }
    if (!(v.max <= bound && result.after.max_position <= bound)) {
      failures.add(where + format(": validation max %.3g L, residual %.3g L, bound %.3g L (kappa %.3g)", v.max / L,
                                  result.after.max_position / L, bound / L, kappa));
    }
    // the product's promise, 1e-9 L, where the derived bound is within it
    if (bound <= 1e-9 * L && !(v.max <= 1e-9 * L)) failures.add(where + format(": validation %.3g L > 1e-9 L", v.max / L));
    // the type rule: a joint is helical after calibration iff the actual one is
    for (int i = 0; i < nominal.dof(); ++i) {
      if (result.model.joint(i).type != actual.joint(i).type) failures.add(where + ": joint type differs from the actual");
    }
    worst_ratio = std::max(worst_ratio, v.max / bound);
    worst_over_L = std::max(worst_over_L, v.max / L);
    worst_kappa = std::max(worst_kappa, kappa);
    max_iterations = std::max(max_iterations, result.iterations);
    ++mixes[typeString(nominal)];
    ++robots;
  }
  std::printf("%d robots (%zu joint mixes): worst validation %.3g L, %.3g of its bound; worst kappa %.3g; <= %d iterations\n",
              robots, mixes.size(), worst_over_L, worst_ratio, worst_kappa, max_iterations);
  EXPECT_EQ(failures.count, 0);
}

// Noisy measurements: sigma_p = 1e-5 L per position coordinate, sigma_r = 1e-5 rad per rotation
// coordinate, stated in the options. Perturbation 1e-2 (rad, L, relative scale) so that the nominal is
// off by ~1e-2 L >= 1000 sigma_p (asserted: a precondition of the test, not a result).
// Poses: P = 8 m for m parameters. Least squares with N = 6P weighted rows leaves a prediction variance
// whose average over poses like the training ones is sigma^2 m / (N - m) per row; even if all of it sat in
// the 3P position rows, the expected validation mean square error is 3 sigma_p^2 m / (3P) = sigma_p^2 / 8,
// RMS 0.35 sigma_p; the realized value is a weighted chi-square of relative spread <= sqrt(2), so RMS
// <= sigma_p holds beyond 4 of its standard deviations. Also asserted:
//   - RMS <= before / 100 (before >= 1000 sigma_p);
//   - the variance factor (cost / (N - rank)) is 1 +- 0.3: its spread is sqrt(2 / (N - m)) <= 0.05;
//   - the stated covariance predicts the realized error: over the robots, the mean of (validation mean
//     square error) / trace(J_p Sigma J_p^T averaged over the validation poses) is in [0.5, 2] (expected 1;
//     each term has relative spread <= sqrt(2), their mean over 30 robots <= 0.26);
//   - every standard deviation finite and positive (full rank).
TEST(Calibration, NoisyMeasurementsReachTheNoiseLevel) {
  std::mt19937_64 rng(47);
  Failures failures;
  double worst_rms = 0.0, ratio_sum = 0.0, vf_min = kInf, vf_max = 0.0, min_before = kInf;
  int robots = 0;
  for (int r = 0; r < 30; ++r) {
    const RandomRobot robot = randomRobot(rng);
    const PoeModel& nominal = robot.model;
    const bool free_pitch = r % 2 == 1;
    const ErrorModel em(nominal, ErrorModelSpec{free_pitch});
    const double L = nominal.lengthScale();
    const double sp = 1e-5 * L, sr = 1e-5;
    const PoeModel actual = em.apply(smallDelta(em, 1e-2, free_pitch, rng));
    const std::vector<VecX> train = uniformPoses(nominal, 8 * em.size(), rng), check = uniformPoses(nominal, 200, rng);
    std::vector<Measurement> ms = measure(actual, train);
    addNoise(ms, sp, sr, rng);
    CalibrationOptions options;
    options.free_pitch = free_pitch;
    options.sigma_position = sp;
    options.sigma_rotation = sr;
    const CalibrationResult result = calibrate(nominal, ms, options);
    const Deviation before = positionDeviation(nominal, actual, check), after = positionDeviation(result.model, actual, check);
    ASSERT_GE(before.rms, 1000 * sp) << "robot " << r << ": the perturbation is too small for this test";
    const std::string where = "robot " + std::to_string(r) + " (" + typeString(nominal) + ", " + geometryName(robot.geometry) +
                              (free_pitch ? ", free pitch" : "") + ")";
    if (!result.converged) failures.add(where + ": not converged");
    if (!result.noise_stated) failures.add(where + ": noise_stated false");
    if (result.rank.rank != result.expected.total()) failures.add(where + ": rank deficient");
    if (!(after.rms <= sp && after.rms <= before.rms / 100)) {
      failures.add(where + format(": validation RMS %.3g sigma_p (before %.3g sigma_p)", after.rms / sp, before.rms / sp));
    }
    if (!(std::abs(result.variance_factor - 1.0) <= 0.3)) failures.add(where + format(": variance factor %.3g", result.variance_factor));
    for (int k = 0; k < em.size(); ++k) {
      const double s = result.standard_deviation[k];
      if (!(std::isfinite(s) && s > 0.0)) failures.add(where + format(": standard deviation %g of parameter %g", s, k));
    }
    // predicted validation mean square error from the covariance at the result
    double predicted = 0.0;
    MatX Jp(3, result.error_model.size());
    for (const VecX& q : check) {
      result.error_model.jacobian(q, Measure::Position, Jp);
      predicted += (Jp * result.covariance * Jp.transpose()).trace();
    }
    predicted /= static_cast<double>(check.size());
    ratio_sum += after.rms * after.rms / predicted;
    worst_rms = std::max(worst_rms, after.rms / sp);
    vf_min = std::min(vf_min, result.variance_factor);
    vf_max = std::max(vf_max, result.variance_factor);
    min_before = std::min(min_before, before.rms / sp);
    ++robots;
  }
  const double mean_ratio = ratio_sum / robots;
  std::printf("%d robots: worst validation RMS %.3g sigma_p (smallest before %.3g sigma_p); variance factor %.3g-%.3g; "
              "realized / predicted mean square error %.3g\n",
              robots, worst_rms, min_before, vf_min, vf_max, mean_ratio);
  EXPECT_EQ(failures.count, 0);
  EXPECT_GE(mean_ratio, 0.5);
  EXPECT_LE(mean_ratio, 2.0);
}

// Position-only: the tool's orientation is not observed. The tool rotation columns are rotations about
// lines through the tool point, so their position rows are exactly 0: the rank is the count with tool 3,
// i.e. 3 below the number of parameters, the three undetermined directions consist of tool rotations
// only, their standard deviations are +inf, every other one finite, and the tool's orientation is left
// at the nominal (an undetermined direction is not moved; the other parameters do not touch the tool's
// rotation: 64 eps). Robots whose tool point lies on their last lines lose more (positionOnlyLoss) and are
// left out here; they are the subject of the identifiability tests. Validation: the noise-free bound.
TEST(Calibration, PositionOnlyLeavesOnlyTheToolRotationUndetermined) {
  std::mt19937_64 rng(53);
  Failures failures;
  int robots = 0, skipped = 0;
  double worst_ratio = 0.0;
  while (robots < 30) {
    const RandomRobot robot = randomRobot(rng);
    const PoeModel& nominal = robot.model;
    if (positionOnlyLoss(nominal) > 0) {
      ++skipped;
      continue;
    }
    const bool free_pitch = robots % 2 == 1;
    const ErrorModel em(nominal, ErrorModelSpec{free_pitch});
    const PoeModel actual = em.apply(smallDelta(em, 1e-3, free_pitch, rng));
    const std::vector<VecX> train = uniformPoses(nominal, 50, rng), check = uniformPoses(nominal, 100, rng);
    CalibrationOptions options;
    options.measure = Measure::Position;
    options.free_pitch = free_pitch;
    const CalibrationResult result = calibrate(nominal, measure(actual, train), options);
    const std::string where = "robot " + std::to_string(robots) + " (" + typeString(nominal) + ", " +
                              geometryName(robot.geometry) + (free_pitch ? ", free pitch" : "") + ")";
    if (result.expected.tool != 3 || result.expected.total() != em.size() - 3) failures.add(where + ": count");
    if (result.rank.rank != em.size() - 3) {
      failures.add(where + ": rank " + std::to_string(result.rank.rank) + " of " + std::to_string(em.size() - 3));
    }
    if (result.rank.undetermined.size() != 3) failures.add(where + ": not 3 undetermined directions");
    for (const auto& direction : result.rank.undetermined) {
      if (direction.empty()) failures.add(where + ": an undetermined direction names no parameter");
      for (const auto& [column, coefficient] : direction) {
        if (em.parameters()[static_cast<size_t>(column)].kind != ParameterKind::ToolRotation) {
          failures.add(where + ": undetermined direction names " + em.parameters()[static_cast<size_t>(column)].name +
                       format(" (coefficient %.3g)", coefficient));
        }
      }
    }
    for (int k = 0; k < em.size(); ++k) {
      const bool tool_rotation = em.parameters()[static_cast<size_t>(k)].kind == ParameterKind::ToolRotation;
      const double s = result.standard_deviation[k];
      if (tool_rotation ? s != kInf : !std::isfinite(s)) {
        failures.add(where + ": standard deviation of " + em.parameters()[static_cast<size_t>(k)].name + format(" is %g", s));
      }
    }
    // undetermined: the tool's orientation stays where the registration of the measurement frame put it
    const Mat3 registered = result.registration.T_meas_base.R * nominal.toolPose().R;
    if (!(rotationError(result.model.toolPose().R, registered) <= 64 * kEpsilon)) {
      failures.add(where + ": the tool's orientation moved");
    }
    const double S = std::max(maxDistanceScale(actual, train), maxDistanceScale(actual, check));
    const double bound = 4.0 * determinedCondition(result.rank) * fkRounding(nominal.dof()) * S;
    const Deviation v = positionDeviation(result.model, actual, check);
    if (!result.converged || !(v.max <= bound)) {
      failures.add(where + format(": validation max %.3g L, bound %.3g L", v.max / nominal.lengthScale(), bound / nominal.lengthScale()));
    }
    worst_ratio = std::max(worst_ratio, v.max / bound);
    ++robots;
  }
  std::printf("%d robots (%d with the tool point on their last lines left out): worst validation %.3g of its bound\n", robots,
              skipped, worst_ratio);
  EXPECT_EQ(failures.count, 0);
}

// Two poses of a 6R (12 rows for 36 parameters): no throw, a finite model, standard deviations finite or
// +inf (never NaN), no NaN in the covariance, the rank exactly 12 with the other directions undetermined
// and named, and the cost not increased (Levenberg-Marquardt only accepts decreasing steps).
// Rank 12 = the number of rows: at each pose the six tool columns alone have rank 6 (an invertible map of
// the tool's twist), so a combination (a, b) of the two poses' rows that vanishes on them fixes a from b,
// and the joint columns (29 to 36 of them here) are as many equations on the 6 numbers of b, which
// have only b = 0 for generic lines (jointMix) at random poses (measured: sigma_12 >= 0.16 sigma_1, the
// rank tolerance ~8e-12 sigma_1).
TEST(Calibration, TooFewPosesStaysFinite) {
  std::mt19937_64 rng(61);
  for (int r = 0; r < 10; ++r) {
    const PoeModel nominal = jointMix(r % 2 ? "RRRRRR" : "RRPRHR", 1.0 + 100.0 * r, rng);
    const ErrorModel em(nominal, ErrorModelSpec{r % 3 == 0});
    const PoeModel actual = em.apply(smallDelta(em, 1e-2, r % 3 == 0, rng));
    CalibrationOptions options;
    options.free_pitch = r % 3 == 0;
    if (r % 2) options.sigma_position = 1e-4 * nominal.lengthScale();
    std::vector<Measurement> ms = measure(actual, uniformPoses(nominal, 2, rng));
    CalibrationResult result = calibrate(nominal, ms, options);
    SCOPED_TRACE("robot " + std::to_string(r) + " " + typeString(nominal));
    for (const Joint& j : result.model.joints()) EXPECT_TRUE(j.twist.allFinite() && std::isfinite(j.scale) && std::isfinite(j.pitch));
    EXPECT_TRUE(result.model.toolPose().matrix().allFinite());
    for (int k = 0; k < result.standard_deviation.size(); ++k) {
      const double s = result.standard_deviation[k];
      EXPECT_TRUE(s == kInf || (std::isfinite(s) && s >= 0.0)) << em.parameters()[static_cast<size_t>(k)].name << " " << s;
    }
    EXPECT_FALSE(result.covariance.array().isNaN().any());
    EXPECT_EQ(result.rank.rank, 12);
    ASSERT_FALSE(result.rank.undetermined.empty());
    EXPECT_EQ(static_cast<int>(result.rank.undetermined.size()), em.size() - result.rank.rank);
    EXPECT_LE(result.after.rms_position, result.before.rms_position);
    const DhUncertainty dh = dhUncertainty(result);
    for (const DhParams& p : dh.links) EXPECT_FALSE(std::isnan(p.theta) || std::isnan(p.d) || std::isnan(p.alpha) || std::isnan(p.a));
  }
}

TEST(Calibration, RejectsBadMeasurements) {
  std::mt19937_64 rng(67);
  const PoeModel nominal = jointMix("RRPRRR", 1.0, rng);
  const std::vector<Measurement> good = measure(nominal, uniformPoses(nominal, 10, rng));
  EXPECT_NO_THROW(calibrate(nominal, good));
  EXPECT_THROW(calibrate(nominal, {}), std::invalid_argument);
  auto bad = [&](auto change) {
    std::vector<Measurement> ms = good;
    change(ms[3]);
    return ms;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(calibrate(nominal, bad([](Measurement& m) { m.q.conservativeResize(5); })), std::invalid_argument);
  EXPECT_THROW(calibrate(nominal, bad([](Measurement& m) { m.q.conservativeResize(7); m.q[6] = 0.0; })), std::invalid_argument);
  EXPECT_THROW(calibrate(nominal, bad([&](Measurement& m) { m.q[2] = nan; })), std::invalid_argument);
  EXPECT_THROW(calibrate(nominal, bad([&](Measurement& m) { m.T_base_tool.p.y() = nan; })), std::invalid_argument);
  EXPECT_THROW(calibrate(nominal, bad([&](Measurement& m) { m.T_base_tool.R(1, 2) = nan; })), std::invalid_argument);
  EXPECT_THROW(calibrate(nominal, bad([](Measurement& m) { m.T_base_tool.p.x() = kInf; })), std::invalid_argument);
  // a position-only calibration reads only the position, but a non-finite number is still bad input
  CalibrationOptions position;
  position.measure = Measure::Position;
  EXPECT_THROW(calibrate(nominal, bad([&](Measurement& m) { m.q[0] = nan; }), position), std::invalid_argument);
}

// residualStatistics against its definition, computed here from FK: |p_meas - p_model| and
// rotationAngle(R_model^T R_meas), RMS and max. Both sides sum the same errors of size ~1e-3 L from FKs
// that agree to eps_fk S: agreement to 2 eps_fk S (position) and 2 eps_fk (rotation).
TEST(ResidualStatistics, MatchesItsDefinition) {
  std::mt19937_64 rng(71);
  for (int r = 0; r < 20; ++r) {
    const PoeModel model = randomRobot(rng).model;
    const ErrorModel em(model);
    const PoeModel other = em.apply(smallDelta(em, 1e-3, false, rng));
    const std::vector<VecX> qs = uniformPoses(model, 25, rng);
    const std::vector<Measurement> ms = measure(other, qs);
    double sp = 0, sr = 0, mp = 0, mr = 0;
    for (const Measurement& m : ms) {
      const Pose T = poeForwardKinematics(model, m.q);
      const double ep = (m.T_base_tool.p - T.p).norm(), er = rotationAngle(T.R.transpose() * m.T_base_tool.R);
      sp += ep * ep;
      sr += er * er;
      mp = std::max(mp, ep);
      mr = std::max(mr, er);
    }
    const double S = maxDistanceScale(model, qs), e = 2 * fkRounding(model.dof());
    const ResidualStatistics pose = residualStatistics(model, ms, Measure::Pose);
    const ResidualStatistics position = residualStatistics(model, ms, Measure::Position);
    EXPECT_EQ(pose.count, 25);
    EXPECT_NEAR(pose.rms_position, std::sqrt(sp / 25), e * S);
    EXPECT_NEAR(pose.max_position, mp, e * S);
    EXPECT_NEAR(pose.rms_rotation, std::sqrt(sr / 25), e);
    EXPECT_NEAR(pose.max_rotation, mr, e);
    EXPECT_NEAR(position.rms_position, std::sqrt(sp / 25), e * S);
    EXPECT_EQ(position.rms_rotation, 0.0);
    EXPECT_EQ(position.max_rotation, 0.0);
  }
}

// ---- 5. D-H standard deviations -------------------------------------------------------------------------
//
// Well posed: pumaLike(0.3, generic) (no consecutive lines parallel or intersecting: every D-H number is a
// smooth function of the POE parameters there). 40 independent noisy calibrations (sigma_p = 1e-5 L,
// sigma_r = 1e-5 rad, 60 poses each, noise stated): the sample standard deviation of every D-H number
// over the 40 calibrated tables against dhUncertainty of the first. At this noise the D-H map is linear
// to ~1e-5 relative, so the prediction is the true standard deviation if the covariance is right, and the
// sample standard deviation of 40 draws has relative spread 1 / sqrt(78) = 0.11: [0.5, 1.6] is beyond 4.5
// of those (lower) and 5 (upper), for every one of the 36 numbers. Revolute joints have pitch 0 and
// standard deviation 0.
TEST(DhUncertainty, MatchesTheSpreadOfRepeatedCalibrations) {
  std::mt19937_64 rng(1984);
  const PoeModel actual = pumaLike(0.3, true);
  const ErrorModel em(actual);
  const PoeModel nominal = em.apply(smallDelta(em, 1e-2, false, rng));
  const double L = nominal.lengthScale(), sp = 1e-5 * L, sr = 1e-5;
  CalibrationOptions options;
  options.sigma_position = sp;
  options.sigma_rotation = sr;
  auto numbers = [](const DhModel& dh) {
    std::vector<double> v;
    auto row = [&](const DhParams& p) { v.insert(v.end(), {p.theta, p.d, p.alpha, p.a}); };
    row(dh.base());
    for (const DhJoint& j : dh.joints()) {
      row(j.link);
      v.push_back(j.scale);
    }
    v.push_back(dh.toolTheta());
    v.push_back(dh.toolD());
    return v;
  };
  auto is_angle = [](size_t k, size_t size) {
    if (k + 2 == size) return true;   // tool theta
    if (k + 1 == size) return false;  // tool d
    const size_t in_row = k < 4 ? k : (k - 4) % 5;
    return in_row == 0 || in_row == 2;
  };
  std::vector<std::vector<double>> samples;
  std::optional<DhUncertainty> predicted;
  for (int rep = 0; rep < 40; ++rep) {
    std::vector<Measurement> ms = measure(actual, uniformPoses(actual, 60, rng));
    addNoise(ms, sp, sr, rng);
    const CalibrationResult result = calibrate(nominal, ms, options);
    ASSERT_TRUE(result.converged);
    ASSERT_EQ(result.rank.rank, 36);
    const DhUncertainty u = dhUncertainty(result);
    if (!predicted) predicted = u;
    samples.push_back(numbers(u.conversion.model));
  }
  // predicted standard deviations in the order of `numbers`
  std::vector<double> sd;
  auto row = [&](const DhParams& p) { sd.insert(sd.end(), {p.theta, p.d, p.alpha, p.a}); };
  row(predicted->base);
  for (size_t i = 0; i < 6; ++i) {
    row(predicted->links[i]);
    sd.push_back(predicted->scale[i]);
    EXPECT_EQ(predicted->pitch[i], 0.0);
  }
  sd.push_back(predicted->tool_theta);
  sd.push_back(predicted->tool_d);
  ASSERT_EQ(sd.size(), samples[0].size());
  const std::vector<std::string> names = {"theta", "d", "alpha", "a"};
  for (size_t k = 0; k < sd.size(); ++k) {
    // deviations from the first sample (angles wrapped), then the sample standard deviation
    double mean = 0.0, sq = 0.0;
    std::vector<double> dev;
    for (const auto& s : samples) {
      const double d = s[k] - samples[0][k];
      dev.push_back(is_angle(k, sd.size()) ? wrapAngle(d) : d);
      mean += dev.back();
    }
    mean /= static_cast<double>(dev.size());
    for (double d : dev) sq += (d - mean) * (d - mean);
    const double sample = std::sqrt(sq / static_cast<double>(dev.size() - 1));
    const double ratio = sample / sd[k];
    EXPECT_TRUE(std::isfinite(sd[k]) && sd[k] > 0.0) << "D-H number " << k << ": " << sd[k];
    EXPECT_GE(ratio, 0.5) << "D-H number " << k << ": sample " << sample << ", predicted " << sd[k];
    EXPECT_LE(ratio, 1.6) << "D-H number " << k << ": sample " << sample << ", predicted " << sd[k];
  }
  std::printf("predicted D-H standard deviations (L = %.4g):", L);
  for (double s : sd) std::printf(" %.2g", s);
  std::printf("\n");
}

// Nearly parallel: pumaLike(1e-3, true), joints 2 and 3 at alpha = 1e-3 rad, a = 80 mm. Two lines at
// distance a and angle alpha about their common normal: an in-plane tilt eps of the second moves the
// common normal's foot along the first by d = -eps a / (eps^2 + alpha^2) ~ -eps a / alpha^2, so the d of
// that row (links[1].d) has standard deviation ~ (a / alpha^2) sigma_eps. At alpha = 0.3 the same
// sensitivity is a / sin^2(0.3) (plus terms of order a / sin(alpha) and 1): the ratio of the two
// sensitivities is >= (sin 0.3 / sin 1e-3)^2 / 2 = 4e4, and the POE parameter standard deviations of the
// two calibrations (same poses, same noise) agree within a factor 10, so the ratio of the d standard
// deviations is > 4e3; asserted > 1e3 (+inf, "not determined", passes as well). The d of a row between
// lines that are not nearly parallel (links[3], joints 4 and 5) stays within a factor 10.
TEST(DhUncertainty, LargeForDOfNearlyParallelAxes) {
  std::mt19937_64 rng(1985);
  const PoeModel well = pumaLike(0.3, true), near = pumaLike(1e-3, true);
  const std::vector<VecX> qs = uniformPoses(well, 60, rng);
  const double L = well.lengthScale(), sp = 1e-5 * L, sr = 1e-5;
  std::vector<Measurement> noise_well = measure(well, qs), noise_near = measure(near, qs);
  std::mt19937_64 noise_rng(3);
  addNoise(noise_well, sp, sr, noise_rng);
  noise_rng.seed(3);  // the same noise on both
  addNoise(noise_near, sp, sr, noise_rng);
  CalibrationOptions options;
  options.sigma_position = sp;
  options.sigma_rotation = sr;
  const DhUncertainty a = dhUncertainty(calibrate(well, noise_well, options));
  const DhUncertainty b = dhUncertainty(calibrate(near, noise_near, options));
  std::printf("sd of d, row 2-3: alpha 0.3 %.3g, alpha 1e-3 %.3g (ratio %.3g); next row %.3g / %.3g; row 4-5 %.3g / %.3g\n",
              a.links[1].d, b.links[1].d, b.links[1].d / a.links[1].d, a.links[2].d, b.links[2].d, a.links[3].d, b.links[3].d);
  EXPECT_TRUE(std::isfinite(a.links[1].d));
  EXPECT_GT(b.links[1].d / a.links[1].d, 1e3);
  EXPECT_FALSE(std::isnan(b.links[1].d));
  EXPECT_LT(std::max(a.links[3].d / b.links[3].d, b.links[3].d / a.links[3].d), 10.0);
}

// The entries the D-H convention sets: a row placed by a prismatic axis has a = 0 always, and d = 0 unless an
// offset of the joint before it slides the row (a prismatic joint with a nonzero offset: d += scale * offset).
// Joint 2 (prismatic, after a revolute) places link_1: a and d fixed; joint 3 (prismatic, after joint 2 with
// offset 0.1) places link_2: a fixed, d not.
TEST(DhUncertainty, FixedByConventionOnlyWhereNothingMovesIt) {
  JointSpec j1, j2, j3;
  j1.twist << 0, 0, 1, 0, 0, 0;
  j2.twist << 0, 0, 0, 1, 0, 0;
  j2.offset = 0.1;
  j3.twist << 0, 0, 0, 0, 1, 0;
  Pose tool;
  tool.p << 0.2, 0.1, 0.3;
  const PoeModel model({j1, j2, j3}, tool, "rpp");
  std::mt19937_64 rng(3);
  const std::vector<Measurement> ms = measure(model, uniformPoses(model, 20, rng));
  CalibrationOptions options;
  options.sigma_position = 1e-4;
  options.sigma_rotation = 1e-4;
  const CalibrationResult result = calibrate(model, ms, options);
  const DhUncertainty dh = dhUncertainty(result);
  EXPECT_FALSE(dh.base_fixed.a || dh.base_fixed.d);  // placed by joint 1, revolute
  EXPECT_TRUE(dh.links_fixed[0].a && dh.links_fixed[0].d);
  EXPECT_EQ(dh.links[0].a, 0.0);
  EXPECT_EQ(dh.links[0].d, 0.0);
  EXPECT_TRUE(dh.links_fixed[1].a);
  EXPECT_FALSE(dh.links_fixed[1].d);
  EXPECT_FALSE(dh.links_fixed[2].a || dh.links_fixed[2].d);  // the last row: the tool's
}
