#pragma once
/// @file plan_report.hpp
/// The report of `lowpair plan` (docs/plan.md), shared by the CLI and the Python module's lowpair.plan: the
/// checks of the request, the candidates (the sampling convention), the plan, its comparison with random sets
/// of the same size, the expected standard deviations at the stated or default noise, and its JSON.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "io/robot_file.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/plan.hpp"
#include "commands/arguments.hpp"
#include "commands/limits.hpp"
#include "commands/plan_feasibility.hpp"

namespace lowpair::commands {

/// Upper bounds of `plan`: the poses chosen and the candidates (the numbers of their blocks and the search's
/// work: planSizeProblem, limits.hpp).
constexpr int kMaxPlanPoses = 1000;
constexpr int kDefaultPlanCandidates = 5000;
constexpr int kMaxPlanCandidates = 100000;
/// The random sets of N the plan is compared with.
constexpr int kPlanRandomSets = 100;

/// What is asked of `plan`. Preconditions (the front end's own checks): poses in [1, kMaxPlanPoses],
/// candidates in [1, kMaxPlanCandidates], seed in [0, kMaxSeed].
struct PlanRequest {
  Measure measure = Measure::Pose;
  PlanCriterion criterion = PlanCriterion::D;
  int poses = 0, candidates = kDefaultPlanCandidates;
  long long seed = 1;
  bool free_pitch = false;
  std::optional<double> noise_position, noise_rotation;  ///< length per coordinate, rad per axis
  FeasibilityRequest feasibility;  ///< narrowed ranges, a model checked for contacts (nothing: as before)
};

/// A value over the random sets: the median and the best (largest).
struct Spread {
  double median = 0.0, best = 0.0;
};

/// Everything `plan` reports, computed once (renderers only format it).
struct PlanReport {
  io::RobotFile file;
  Measure measure = Measure::Pose;
  PlanCriterion criterion = PlanCriterion::D;
  int candidates = 0;
  long long seed = 0;
  PlanResult plan;
  std::vector<std::string> parameters;  ///< the columns' names
  std::vector<VecX> q;                  ///< the planned joint vectors, in index order
  /// With a tracker: per planned pose, per target, whether it measures it (all true without partial).
  std::vector<std::vector<bool>> measured;
  Spread random_log_det, random_o1;
  std::optional<ExpectedUncertainty> expected;
  std::string noise_source;  ///< stated, derived or the default, in words
  double seconds_plan = 0.0, seconds_random = 0.0, seconds_uncertainty = 0.0;
  /// Set when the request narrows ranges or checks a model: the plan's indices are then still the drawn
  /// candidates' (samples 0..M-1), and the random sets are drawn from the kept candidates.
  std::optional<FeasibilityReport> feasibility;
};

/// Checks the request against the robot (targets to measure, poses <= candidates, the noise, the size limit),
/// then plans: candidates are samples 0..M-1 of the stream `seed` (commands/sampling.hpp), the random sets
/// come from the same seed. With a feasibility request the candidates are drawn in the narrowed ranges and
/// only those free of contacts are planned on (plan_feasibility.hpp). @throws UsageError naming the argument
/// as `spelling` spells it, or the robot file; InfeasiblePlan when fewer candidates than poses are kept
PlanReport makePlanReport(const io::RobotFile& file, const PlanRequest& request, const ArgumentSpelling& spelling);

/// The names of the targets `seen` marks, in the file's order.
std::vector<std::string> measuredTargetNames(const io::RobotFile& file, const std::vector<bool>& seen);

/// The JSON of `plan --json`; `out_path`: where the planned joint vectors were written ("" for none: null).
nlohmann::json planJson(const PlanReport& report, const std::string& out_path);

}  // namespace lowpair::commands
