// Calibration's identification side (calibration.hpp, identifiability.hpp) against references that do not
// come from the calibration code:
// 1. The identification Jacobian against central differences of forward kinematics of ErrorModel::apply,
//    column by column, on 1,000 seeded random robots (tests/common/random_robot.hpp: every joint type, degenerate
//    geometry), with and without free pitch; apply(0) and the type-preserving rule of apply.
// 2. Identifiability: the numeric rank equals the paper's count 5h + 4r + 2t + n + 6 (Wu et al. §V; 3 for
//    the tool with position-only measurements) on 1,000 random robots and hand-built joint mixes, and it
//    equals the rank of the unreduced error model. Position-only measurements of a tool point lying on the
//    last joint lines lose more, by an amount derived below (the count is an "at most").
// 3. D-H: exactly parallel consecutive axes cost the D-H parameterization one rank; nearly parallel ones
//    keep the rank but not the conditioning. The POE parameterization has no such singularity.
// The calibration loops and the D-H standard deviations are in calibration_test.cpp.
//
// Scales (L, scaled units: parameterUnit) and the forward-kinematics rounding eps_fk (fkRounding) used by
// the bounds: calibration_helpers.hpp.
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
