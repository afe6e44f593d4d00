#pragma once
/// @file ik_closed_form.hpp
/// Every inverse-kinematics solution of a 6-joint chain in closed form, where the geometry of its POE model
/// allows it (docs/ik.md, "Closed form"). The tools are the Paden-Kahan subproblems (Murray, Li, Sastry,
/// *A Mathematical Introduction to Robotic Manipulation*, 1994, §3.2.2; Paden & Sastry 1984):
/// SP1 a rotation about one axis taking a point to a point, SP2 rotations about two intersecting axes taking a
/// point to a point, SP3 a rotation about one axis taking a point to a given distance from another point.
///
/// **Geometries** (closedFormStructure, detected from the joint lines of the model, never from names):
/// - ClosedFormKind::SphericalWrist: revolute axes 4, 5, 6 meet at a point c (the wrist centre); revolute axes
///   1, 2 meet at a point s (the shoulder); joint 3 revolute or prismatic. `G = T_target exp(xi_T)^-1` moves c
///   to G c; joint 3 alone sets |G c - s|: SP3 about axis 3 (revolute, 2 roots: elbow), or the quadratic
///   `|c + x v_3 - s| = |G c - s|` (prismatic, 2 roots); SP2 about axes 1, 2 then takes exp(xi_3 x_3) c to G c
///   (2 roots: shoulder); SP2 about axes 4, 5 takes a point of axis 6 where the wrist rotation does (2 roots:
///   wrist), SP1 gives joint 6. PUMA 560 (revolute 3), Stanford arm (prismatic 3): up to 8 solutions.
/// - ClosedFormKind::ParallelTriple: revolute axes 2, 3, 4 parallel (direction u), axes 5 and 6 meeting at a
///   point c, axis 1 and axis 5 not parallel to u (Universal Robots' arms). Rotations about axes parallel to u
///   keep the component along u of points and directions: `u . exp(-xi_1 x_1) G c = u . c` fixes joint 1
///   (2 roots: shoulder), `u . R_5 w_6 = (R_1 u) . R_G w_6` joint 5 (2 roots: wrist), SP1 on directions joint 6,
///   then the planar 3R arm: SP3 about axis 3 (2 roots: elbow), SP1 for joint 2, the remaining turn joint 4.
///   The analytic reduction of Hawkins (2013) for UR arms, written on the POE lines: up to 8 solutions.
///
/// **Nearly of that geometry.** A calibrated model's lines miss the exact geometry by its errors. Lines count as
/// meeting (parallel) when they miss by at most `tolerance L` (`tolerance` rad), kClosedFormNearly by default;
/// a helical joint counts as revolute when |pitch| <= tolerance L. The structure keeps the *projection*: the
/// meeting lines moved through their common point, the parallel ones turned to a common direction, pitches
/// dropped. The subproblems solve the projection exactly; every candidate is then checked through FK of the
/// true model and, when it misses the tolerances, refined by the damped Newton iteration of ik.hpp from it
/// (RangePolicy::Report); its residual is reported. An exact model (a D-H file) is its own projection to
/// rounding: its candidates pass the check without refinement.
///
/// **Joint variables.** The subproblems give motions x_i; a solution is `q_i = x_i / scale_i - offset_i`
/// (JointMotion::variable), a revolute joint's x first taken in (-pi, pi], then q moved by whole turns into
/// the joint's range when that is possible. A joint whose angle a subproblem leaves free (an axis through the
/// point it should move: the wrist singular with axes 4 and 6 aligned, a target on axis 1) gets motion 0 and
/// the solution the flag `singular`.
///
/// **Cost and allocation.** A target: some 30 joint exponentials, 100 atan2 and one FK check per candidate,
/// ~80,000 instructions on the PUMA 560 for its 8 solutions, 5 us on the shared benchmark machine against 108 us
/// for one solution of KDL's LMA (bench/bench_ik.cpp, docs/ik.md), refinement aside. Nothing allocates after the
/// ClosedFormWorkspace is built, a refinement's failure message excepted (tests/lib/alloc_test.cpp).

#include <array>
#include <string>

#include "lowpair/ik.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair {

/// How far a model's lines may miss the exact geometry and still count as of it: distances in units of the
/// robot size L, angles in rad, pitches in L per rad. 1e-3 holds the errors calibration corrects on real arms
/// (a few tenths of a millimetre and milliradian on a 1 m arm; the actual PUMA of Okamura and Park, Table I, with
/// helical joints (joint 6: pitch 0.011 L) and axes 2 and 3 0.18 rad from parallel, is *not* nearly of its nominal's
/// geometry and goes to the numerical solver). From a candidate
/// that far from the true solution, the damped Newton iteration converges quadratically in 3-5 steps; much
/// farther, a candidate may fall into another branch's basin and the numerical solver is the honest tool.
constexpr double kClosedFormNearly = 1e-3;

/// Lines that must not be parallel (two axes of an SP2, axis 1 or 5 against the parallel triple) have sines of
/// at least this, and lines that must be distinct (axis 3 from the points SP3 turns about it) are at least this
/// times L apart. SP2 divides by `|w_1 x w_2|^2` and SP3 by the distances: at 1e-2 the rounding is amplified by
/// at most 1e4 (2e-12 L), which the FK check catches; below it the subproblem is near its degenerate case.
constexpr double kClosedFormSeparation = 1e-2;

/// The most solutions either geometry has (2 x 2 x 2 root choices).
constexpr int kClosedFormMaxSolutions = 8;

enum class ClosedFormKind { None, SphericalWrist, ParallelTriple };

/// "none", "spherical_wrist", "parallel_triple".
const char* closedFormKindName(ClosedFormKind kind);

/// What closedFormStructure found: the geometry, by how much the model misses it, and its exact projection.
struct ClosedFormStructure {
  ClosedFormKind kind = ClosedFormKind::None;
  bool prismatic_elbow = false;  ///< SphericalWrist with joint 3 prismatic (Stanford arm)
  /// The largest miss of the exact geometry: distances over L, angles in rad, pitches over L (0 to rounding
  /// for a D-H model of that geometry). <= the tolerance when kind != None.
  double deviation = 0.0;
  /// Why kind is None: the first condition of each geometry that fails, with its number; empty otherwise.
  std::string reason;
  // the projection (x_i-space POE: T(x) = prod exp(xi_i x_i) tool_pose): per joint the unit direction and a
  // point of the projected line (revolute), or the unit direction (prismatic); the meeting points
  std::array<Vec3, 6> w, p;
  Vec3 shoulder = Vec3::Zero();  ///< SphericalWrist: where axes 1 and 2 meet
  Vec3 wrist = Vec3::Zero();     ///< where axes 4, 5, 6 (SphericalWrist) or axes 5, 6 (ParallelTriple) meet
  Pose tool_pose;                ///< the model's tool pose exp(xi_T)
};

/// Detects the geometry (file comment) within `tolerance` (kClosedFormNearly).
/// @throws std::invalid_argument when tolerance is not in (0, 0.1]
ClosedFormStructure closedFormStructure(const PoeModel& model, double tolerance = kClosedFormNearly);

/// The root taken in each of the three two-root steps (file comment): true for the `+` root. The flags are
/// signs of continuous quantities (the SP2 out-of-plane component, the SP3 and trigonometric square roots), so
/// a solution keeps its flags along any path that crosses no singularity, and the flags of a nominal model's
/// solution name the same branch of a nearly equal calibrated model.
struct IkBranch {
  bool shoulder = false, elbow = false, wrist = false;
  bool operator==(const IkBranch& o) const { return shoulder == o.shoulder && elbow == o.elbow && wrist == o.wrist; }
  bool operator!=(const IkBranch& o) const { return !(*this == o); }
};

struct ClosedFormSolution {
  Vec6 q = Vec6::Zero();
  IkBranch branch;
  /// A subproblem left an angle free or two roots coincided (a singular configuration; branches meet there).
  bool singular = false;
  int out_of_range = -1;        ///< the first 0-based joint outside its range after whole turns; -1 if none
  int refinement_iterations = 0;  ///< Newton steps on the true model (0: the closed form passed the check)
  double position_error = 0.0;  ///< |p_target - p_F| through the true model's FK, length
  double rotation_error = 0.0;  ///< rad
};

/// Every solution found for one target. `count` solutions, in the order of their branch bits
/// (shoulder, elbow, wrist; - before +); `dropped` candidates failed the FK check even after refinement.
struct ClosedFormResult {
  ClosedFormKind kind = ClosedFormKind::None;
  int count = 0;
  int dropped = 0;
  std::array<ClosedFormSolution, kClosedFormMaxSolutions> solutions;
};

/// Buffers of inverseKinematicsAll for one model, and its structure (allocated once).
struct ClosedFormWorkspace {
  /// Detects the structure (closedFormStructure(model, tolerance)); a model without one gets kind None, and
  /// inverseKinematicsAll then throws.
  explicit ClosedFormWorkspace(const PoeModel& model, double tolerance = kClosedFormNearly);
  ClosedFormStructure structure;
  ClosedFormResult result;  ///< what inverseKinematicsAll returns a reference to
  Data data;                ///< FK checks and refinement
  IkWorkspace ik;           ///< refinement
  std::array<Vec6, 6> twists;  ///< the model's, to check that a call passes the same model
};

/// Every solution of `F(q) = T_target` (F = T_base_tool Trans(point_tool), ik.hpp) of a model with a closed
/// form (file comment). Uses options.point_tool, the tolerances (the FK check and the refinement's) and
/// max_iterations (the refinement's limit); the ranges are reported per solution (out_of_range), never used
/// to drop one. No solution (count 0) when the target is out of reach. Allocates nothing, a failed
/// refinement's reason string excepted.
/// @param work built from this model (checked: its joint twists)
/// @throws std::invalid_argument for a model without a closed form (work.structure.reason), another model
/// than the workspace's, Measure::Position (a 6-joint arm has infinitely many solutions), options out of their
/// domain, a target that is not finite or whose rotation is not one
const ClosedFormResult& inverseKinematicsAll(const PoeModel& model, const Pose& T_target, const IkOptions& options,
                                             ClosedFormWorkspace& work);

/// The branch of configuration q: the flags of the closed-form solution of FK(q) nearest to q (revolute joints
/// compared modulo whole turns, prismatic ones over L). Uses work.result.
/// @return false when FK(q) has no solution within the tolerances (it always has one unless q is singular
/// beyond the solver's reach, e.g. exactly on a double root's rounding edge)
/// @throws std::invalid_argument as inverseKinematicsAll, or for q not finite or of another size
bool branchOf(const PoeModel& model, const Eigen::Ref<const VecX>& q, const IkOptions& options, ClosedFormWorkspace& work,
              IkBranch& branch);

/// Compensation on the nominal row's branch: the solution of the calibrated model for the nominal model's tool
/// pose at q (`F_calibrated(q') = F_nominal(q)`, ik.hpp compensate) whose branch flags are those of q in the
/// nominal model (branchOf), the nearest to q of them (jointDistance) when several share the flags; its revolute
/// joints moved by whole turns to the nearest of q's values their ranges allow.
/// @param nominal_work, calibrated_work built from the two models
/// @return the solution in calibrated_work.result, or nullptr when no calibrated solution has that branch (the
/// pose is out of the calibrated model's reach, or the row is singular and the branches meet there)
/// @throws std::invalid_argument as inverseKinematicsAll for either model, or for q not finite or of another size
const ClosedFormSolution* compensateOnBranch(const PoeModel& nominal, const PoeModel& calibrated,
                                             const Eigen::Ref<const VecX>& q, const IkOptions& options,
                                             ClosedFormWorkspace& nominal_work, ClosedFormWorkspace& calibrated_work);

/// Distance between two joint vectors of the model: revolute joints modulo whole turns (rad of motion), other
/// joints' motion over L for prismatic and in rad for helical; the largest over the joints.
double jointDistance(const PoeModel& model, const Eigen::Ref<const VecX>& a, const Eigen::Ref<const VecX>& b);

}  // namespace lowpair
