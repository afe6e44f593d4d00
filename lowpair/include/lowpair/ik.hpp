#pragma once
/// @file ik.hpp
/// Inverse kinematics of a POE model, and compensation of a calibrated model (docs/ik.md).
///
/// **The problem.** Find q with `F(q) = T_target`, where `F(q) = T_base_tool(q) * Trans(point_tool)` is the
/// tool frame moved to a point of the tool (the tool origin by default): the whole frame (Measure::Pose) or
/// its origin only (Measure::Position).
///
/// **The solver.** Damped least squares (Levenberg-Marquardt) on the error
/// `r = [p_target - p_F; log(R_target R_F^T)]` (position first, then the rotation vector in the base frame;
/// only `p` for Position), with the geometric Jacobian at the point `p_F` (computeJacobians, then
/// spatialToGeometric) made dimensionless as the singularity analysis does (dimensionlessJacobian:
/// lengths over the robot size L, joint variables over their scale, prismatic ones times L). In those units
/// the step is `du = J^T (J J^T + mu I)^-1 r` (`(J^T J + mu I)^-1 J^T r` when the joints are fewer than the
/// task rows): for mu -> 0 the minimum-norm Gauss-Newton step, so a redundant robot (n > 6, or n > 3 for
/// Position) moves as little as the linearized task allows (in the motion norm: radians of every revolute
/// and helical joint, lengths over L of every prismatic one). mu starts at `IkOptions::damping`, is divided
/// by 10 after a step that lowers `|r|` and multiplied by 10 after one that does not (the step is then
/// retried from the same q). The rotation error enters through `log`, whose derivative is the angular
/// velocity up to `O(|r|)`: near the solution the iteration is Newton's, quadratic.
///
/// **Joint ranges.** RangePolicy::Clamp (default): the seed and every iterate stay in the joints' ranges.
/// A revolute joint that leaves its range is first moved by whole turns (`2 pi / scale` in q: the same
/// pose) when that lands inside; otherwise it is held at the limit and the step is solved again for the
/// other joints. RangePolicy::Report: the iteration ignores the ranges; a solution outside one (after
/// whole turns) is returned with status OutOfRange.
///
/// **Statuses.** Ok: within both tolerances, at a regular configuration. Singular: within the tolerances,
/// but the task Jacobian at the solution is singular (kIkSingularRatio). Unreachable: the target point is
/// beyond the chain's reach bound (a proof, kIkReachRounding), or the iteration stopped at a stationary
/// point of `|r|` above the tolerances (kIkStationary: no joint motion lowers the error to first order,
/// ranges ignored; from this seed: another seed may find a solution if the target lies in the workspace).
/// OutOfRange: stationary once the joints held at their limits are held there (Clamp), or a solution
/// outside a range (Report); `IkResult::joint` names the joint. NotConverged: the iteration limit, or no
/// step changes q any more (the error's rounding floor is above the tolerances).
///
/// **Cost and allocation.** Each iteration is one computeJacobians, a `6 x n` scaling and an `m x m`
/// Cholesky factorization (`m` = 6 or 3 task rows); a converged solution then gets its singular values
/// (Householder QR of the `m x n` Jacobian, Jacobi SVD of the `m x m` factor). Measured on the PUMA 560
/// (bench/bench_ik.cpp, docs/ik.md): ~0.6 us per iteration, 6 iterations from 0.3 rad per joint, and ~4.5 us
/// for the singular values (IkOptions::check_singularity). Nothing allocates after the IkWorkspace is built,
/// the reason string excepted, which is written only on failure (tests/lib/alloc_test.cpp).

#include <cmath>
#include <limits>
#include <string>

#include "lowpair/kinematics.hpp"
#include "lowpair/measure.hpp"
#include "lowpair/model.hpp"
#include "lowpair/tolerances.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

// --- the solver's thresholds, and why they have their value ------------------------------------------------

/// Default convergence tolerance: position error `<= kIkTolerance * L`, rotation error `<= kIkTolerance` rad.
/// A converged iteration reaches the rounding floor of the forward kinematics, about `16 (n + 1) eps S`
/// (S the distance scale of the configuration, a few L; 2.5e-14 L for six joints at S = L), and the step that
/// gets there is known to `cond(J)` times that. 1e-10 is above the floor by more than three orders of
/// magnitude, so a solution with condition number up to ~1e3 converges to it, and below it Newton's quadratic
/// convergence makes a tighter tolerance cost at most one more iteration.
constexpr double kIkTolerance = 1e-10;

/// Default iteration limit. From a seed 0.3 rad per joint away the iteration converges in 4-8 steps
/// (quadratically); at a singular solution it converges only linearly, with ratio 1/2 for a rank deficiency of
/// one, about 35 steps from 1 to 1e-10; 100 leaves room for the damping's rejected steps on top of that.
constexpr int kIkMaxIterations = 100;

/// Default initial damping mu, in units of the dimensionless Jacobian squared (its entries are O(1)). The step
/// along a singular direction of J is `sigma / (sigma^2 + mu)` times the error's component instead of
/// `1 / sigma`, so mu damps the directions whose singular value is below sqrt(mu): with 0.1, those where a
/// radian of joint motion moves the task by less than ~0.3 L (or 0.3 rad). There a full Gauss-Newton step is
/// longer than the linear model can be trusted for (near a wrist singularity it turns joints 4 and 6 by
/// ~pi onto the other wrist branch, often into a range limit). This value is a measured choice, not a
/// derived one: from seeds 0.3 rad per joint away (5000 random targets each), Marquardt's classical 1e-3
/// solves 99.1 % of the PUMA 560's pose targets, 1e-2 99.5 %, 0.1 99.6 % and 1 99.7 % (one iteration more);
/// a random generic helical/prismatic robot 96.5 %, 98.7 %, 99.4 %, 99.5 %. mu is divided by 10 at every
/// successful step, so Newton's quadratic convergence returns after a few. The normal matrix always gets at
/// least `eps tr(J J^T)`, so its Cholesky factorization exists even at a singular configuration with mu = 0.
constexpr double kIkDamping = 0.1;

/// Stationarity test: `|J^T r| <= kIkStationary |J|_F |r|` (dimensionless J and r). The cost `|r|^2` is
/// computed with a relative rounding error of a few eps, so its first-order change along a unit step of
/// relative size h is resolved only when it exceeds eps / h; the smallest step that changes q relative to its
/// size is ~eps, and the test balances the two at sqrt(eps) (the usual relative gradient test of unconstrained
/// minimization). At a regular configuration `|J^T r| >= sigma_min |r|`, so the test can hold only when
/// `cond(J) >= 1 / sqrt(eps) ~ 7e7`: a stationary point above the tolerance has a singular or rank-deficient
/// task Jacobian (a stretched arm reaching for a point beyond it, a pose a robot with fewer joints cannot take).
constexpr double kIkStationary = 1.4901161193847656e-08;  // sqrt(eps) = 2^-26

/// Singular solution: `sigma_min <= max(rank tolerance, kIkSingularRatio(tau) sigma_max)` of the dimensionless
/// task Jacobian, tau = max(position tolerance in L, rotation tolerance in rad). The rank tolerance is the
/// library's rule (singularity.hpp: `1e3 max(6, n) eps sigma_max`). A solution converged to tau can still lie
/// up to sqrt(tau) from an exactly singular configuration: on a workspace boundary (the elbow stretched) the
/// error grows only quadratically with the distance from it. sigma_min changes at unit rate with that distance
/// (the dimensionless Jacobian's derivatives are O(1)), so `sigma_min <= sqrt(tau) sigma_max` cannot be told
/// from a singular solution (1e-5 at the default tolerance: a condition number above 1e5).
inline double ikSingularRatio(double tolerance) { return std::sqrt(tolerance); }

/// The reach bound's margin: the target point is unreachable when its distance from the chain's first axis
/// point exceeds `R (1 + kIkReachRounding) + position tolerance`, R the bound (IkResult::reach). R is a sum of
/// n + 1 distances, each computed to a few eps; 16 (n + 1) eps is the FK's own rounding allowance
/// (tests' fkRounding), so kIkReachRounding = 16 eps per joint, times n + 1.
constexpr double kIkReachRounding = 16.0 * kEps;

// --- options, result, workspace --------------------------------------------------------------------------------

/// What the solver returns as status (the CLI writes ikStatusName).
enum class IkStatus { Ok, OutOfRange, Singular, Unreachable, NotConverged };

/// "ok", "out_of_range", "singular", "unreachable", "not_converged".
const char* ikStatusName(IkStatus status);

/// How the joints' ranges are used (file comment).
enum class RangePolicy { Clamp, Report };

struct IkOptions {
  /// Pose (the frame) or Position (its origin only). Measure::Targets is not a task: pass the target's point
  /// as point_tool and Position.
  Measure measure = Measure::Pose;
  /// The point of the tool that is placed, in the tool frame (length): F = T_base_tool * Trans(point_tool).
  Vec3 point_tool = Vec3::Zero();
  double position_tolerance = kIkTolerance;  ///< as a fraction of the robot size L
  double rotation_tolerance = kIkTolerance;  ///< rad (ignored for Position)
  int max_iterations = kIkMaxIterations;     ///< steps tried, accepted or not; 0: evaluate the seed only
  double damping = kIkDamping;               ///< initial mu (file comment), >= 0
  RangePolicy ranges = RangePolicy::Clamp;
  /// Compute the singular values at a converged solution (status Singular possible). Off: Ok for every
  /// converged solution, rank -1 and sigma_min NaN (saves the QR and the SVD).
  bool check_singularity = true;

  /// The rules inverseKinematics and compensate apply to their options (the CLI and the Python module call
  /// it too); @param function the name the messages start with.
  /// @throws std::invalid_argument for Measure::Targets, a point_tool not finite, a tolerance not positive
  /// and finite, max_iterations < 0 or a damping not >= 0 and finite
  void validate(const char* function = "inverseKinematics") const;
};

struct IkResult {
  IkStatus status = IkStatus::NotConverged;
  VecX q;                       ///< the solution, or the last iterate (the seed for a reach-bound Unreachable)
  int iterations = 0;           ///< steps tried (each one computeJacobians)
  double position_error = 0.0;  ///< |p_target - p_F| at q, length
  double rotation_error = 0.0;  ///< angle of R_F^T R_target at q, rad (0 for Position)
  /// Numerical rank and smallest singular value (the min(m, n)-th) of the dimensionless task Jacobian at q,
  /// for a converged q with check_singularity; -1 and NaN otherwise.
  int rank = -1;
  double sigma_min = std::numeric_limits<double>::quiet_NaN();
  int joint = -1;               ///< OutOfRange: the 0-based joint at or beyond its range; -1 otherwise
  /// The chain's reach bound from its first axis point (length; +inf when a prismatic or helical joint has
  /// no range): every point of the tool is within it, whatever q.
  double reach = std::numeric_limits<double>::infinity();
  /// Why the status is not Ok, one sentence with the numbers; empty for Ok (nothing is built then).
  std::string reason;
  /// Both errors within the tolerances (Ok or Singular).
  bool converged = false;
};

/// Every buffer of the solver for a model of `dof` joints, allocated once. Like Data, a workspace fits
/// every model with its number of joints; each call checks that. Fields are scratch except `result`.
struct IkWorkspace {
  explicit IkWorkspace(const PoeModel& model);
  explicit IkWorkspace(int dof);

  int dof = 0;
  IkResult result;  ///< what inverseKinematics / compensate return a reference to
  // scratch of an iteration: the dimensionless task Jacobian (rows [v; w]) and error at q and at the trial q,
  // the Jacobian with the columns of the joints held at a limit zeroed, the step and the trial q
  Mat6X J, J_trial, J_free;
  Vec6 r = Vec6::Zero(), r_trial = Vec6::Zero();
  VecX du, q_trial, gradient;
  Eigen::VectorXi held;  ///< 1 for a joint held at a limit in the current step (RangePolicy::Clamp)
  MatX qr;               ///< max(n, 6) x 6: the Householder QR behind the singular values
};

// --- the functions ---------------------------------------------------------------------------------------------

/// Solves `F(q) = T_target` from `q_seed` (file comment). In Position mode only `T_target.p` is used.
/// Allocates nothing but `result.reason`, on failure.
/// @param data made for a model with model.dof() joints; on return it holds the FK and Jacobian at result.q
/// @param work made for model.dof() joints; the result is `work.result`, valid until its next use
/// @throws std::invalid_argument, in every build type, for sizes that do not match, a q_seed or target that is
/// not finite, a target rotation that is not orthonormal to kRotationOrthonormal, Measure::Targets, or options
/// out of their domain (tolerances not positive and finite, max_iterations < 0, damping < 0 or not finite)
const IkResult& inverseKinematics(const PoeModel& model, Data& data, const Pose& T_target,
                                  const Eigen::Ref<const VecX>& q_seed, const IkOptions& options, IkWorkspace& work);

/// Compensation: the joint vector q' of the calibrated model that puts the tool where the nominal model puts
/// it at q, `F_calibrated(q') = F_nominal(q)` (the frame, or the point `options.point_tool` of both tools for
/// Position), solved by inverseKinematics seeded at q.
/// @param data, work made for the models' joint count (data is used for both)
/// @throws std::invalid_argument as inverseKinematics, and when the two models' joint counts differ
const IkResult& compensate(const PoeModel& nominal, const PoeModel& calibrated, Data& data,
                           const Eigen::Ref<const VecX>& q, const IkOptions& options, IkWorkspace& work);

}  // namespace lowpair
