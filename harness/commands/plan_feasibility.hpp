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
#include "commands/arguments.hpp"
#include "commands/sampling.hpp"

namespace lowpair::commands {

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
  bool any() const { return !model.empty() || floor || !ranges.empty() || range_margin != 0.0; }
};

/// A body pair in contact and the number of candidates in which it is.
struct BodyPairCount {
  std::string body1, body2;
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
  double seconds = 0.0;
  int rejected() const { return self_collision + world + floor_contact; }
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

/// The indices of `candidates` the request's model finds free of contacts (all of them without a model),
/// the counts in `report` (drawn, kept, rejected, pairs, note). The model's chain must match the robot file
/// (joint count and types); a robot file's lengths are converted to metres (MuJoCo's) when it states its unit.
/// @throws io::RobotFileError, UsageError (a floor without a model)
std::vector<int> feasibleCandidates(const io::RobotFile& file, const std::vector<VecX>& candidates,
                                    const FeasibilityRequest& request, const ArgumentSpelling& spelling,
                                    FeasibilityReport& report);

}  // namespace lowpair::commands
