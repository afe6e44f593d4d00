#pragma once
/// @file plan_feasibility.hpp
/// What `lowpair plan` may draw and keep (docs/plan.md "Feasible plans"), for the CLI and the Python module:
/// joint ranges narrowed without editing files (`--range J:LO:HI`, `--range-margin X`), and the candidates a
/// MuJoCo model finds free of contacts (mujoco/collision_check.hpp: self-collision, the model's world
/// geometry, an optional floor).

#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/robot_file.hpp"
#include "lowpair/types.hpp"
#include "commands/arguments.hpp"
#include "commands/sampling.hpp"

namespace lowpair::commands {

/// An SMR's acceptance half-angle when none is given (`--smr-angle`): a common 1.5-inch SMR's (a hollow
/// corner cube accepts about +-30 degrees about its axis).
constexpr double kDefaultSmrAngleDeg = 30.0;
/// How far before an SMR's centre the tracker's ray stops (metres): a 1.5-inch SMR's radius, 19.05 mm. The
/// centre (the target point) sits a radius from the surface the ball rests on, so the last radius of the ray is
/// the ball itself and its nest, not an obstacle.
constexpr double kSmrRadiusMetres = 0.01905;

/// One joint's range as given: `joint` a 1-based index or a joint's name; lo < hi in the robot file's units
/// (its angle_unit for revolute and helical joints, its length unit for prismatic ones).
struct RangeOverride {
  std::string joint;
  double lo = 0.0, hi = 0.0;
};

/// "J:LO:HI" (J may hold colons: the last two split). @throws UsageError naming `range`
RangeOverride parseRangeOverride(const std::string& text, const ArgumentSpelling& spelling);

/// What narrows and filters the candidates. Nothing set: `plan` as before, to the number.
struct FeasibilityRequest {
  /// The MuJoCo model checked for contacts: an MJCF or URDF and its chain ("" for no check).
  std::string model, tip, base;
  /// The floor: z of the base frame in the robot file's length unit, which the robot must stay above.
  std::optional<double> floor;
  std::vector<RangeOverride> ranges;
  double range_margin = 0.0;  ///< shrinks every range at both ends (robot file units)
  /// Line of sight (docs/plan.md "Line of sight"): the tracker's position in the base frame (robot file's length
  /// unit); needs the model and target measurements (the robot file's targets and their normals).
  std::optional<Vec3> tracker;
  double smr_angle_deg = kDefaultSmrAngleDeg;  ///< an SMR's acceptance half-angle about its normal (degrees)
  bool partial = false;  ///< keep a pose that sees at least one target, measuring those it sees
  bool any() const { return !model.empty() || floor || !ranges.empty() || range_margin != 0.0 || tracker; }
};

/// A body pair in contact and the number of candidates in which it is.
struct BodyPairCount {
  std::string body1, body2;
  int candidates = 0;
};

/// A geometry that hid targets and the number of candidates in which it did.
struct OccluderCount {
  std::string geom, body;
  int candidates = 0;
};

/// What was drawn, rejected and kept.
struct FeasibilityReport {
  std::vector<Range> ranges;              ///< the sampled ranges (q: rad or length)
  std::vector<std::string> range_source;  ///< per joint: "file", "default", "--range" (+ ", margin")
  bool checked = false;                   ///< contacts were checked (a model with collision geoms)
  std::string model;                      ///< the model checked ("" none)
  int collision_geoms = 0;
  std::optional<double> floor;
  std::string note;  ///< why nothing was checked ("" when checked or no model)
  int drawn = 0, kept = 0;
  int self_collision = 0, world = 0, floor_contact = 0;  ///< rejected, each candidate under its first reason
  std::vector<BodyPairCount> pairs;                      ///< most frequent first
  /// Line of sight (set with a tracker): the tracker (base frame, robot file's length unit), the angle, the
  /// candidates free of contacts rejected because a target was hidden (first reason: occluded, then angle; with
  /// partial only those that see no target), the geometry that hid targets (most frequent first), and per kept
  /// candidate which targets it measures.
  std::optional<Vec3> tracker;
  double smr_angle_deg = kDefaultSmrAngleDeg;
  bool partial = false;
  int occluded = 0, angle = 0;
  int partial_kept = 0;  ///< kept candidates that measure only some targets (partial)
  std::vector<OccluderCount> occluders;
  std::vector<std::vector<bool>> measured;  ///< per kept candidate, per target (empty without a tracker)
  double seconds = 0.0;
  int rejected() const { return self_collision + world + floor_contact + occluded + angle; }
};

/// No feasible candidate, or fewer than the poses asked for: the CLI's exit status 1 (nothing is written).
struct InfeasiblePlan : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The sampling ranges of `file` (samplingRanges) narrowed by the request: each --range replaces its joint's
/// range, then the margin shrinks every range. @throws UsageError for an unknown joint, a range given twice,
/// LO >= HI, a range outside the file's (or the default) range, a margin that empties a range
std::vector<Range> narrowedRanges(const io::RobotFile& file, const FeasibilityRequest& request,
                                  const ArgumentSpelling& spelling, std::vector<std::string>* source = nullptr);

/// The indices of `candidates` the request's model finds free of contacts (all of them without a model) and,
/// with a tracker, whose targets it sees (every one, or with partial at least one: line_of_sight.hpp; a target
/// is seen when the ray from the tracker meets no geom before the SMR's radius, and the tracker is within the
/// SMR's angle of its normal when it has one), the counts in `report` (drawn, kept, rejected, pairs, occluders,
/// measured, note). The model's chain must match the robot file (joint count and types); a robot file's
/// lengths are converted to metres (MuJoCo's) when it states its unit.
/// @throws io::RobotFileError, UsageError (a floor or a tracker without a model, a tracker without targets, a
/// tracker inside the world's geometry, an angle outside (0, 180])
std::vector<int> feasibleCandidates(const io::RobotFile& file, const std::vector<VecX>& candidates,
                                    const FeasibilityRequest& request, const ArgumentSpelling& spelling,
                                    FeasibilityReport& report);

}  // namespace lowpair::commands
