#pragma once
/// @file ik_rows.hpp
/// The rows of `lowpair ik` and `lowpair compensate` (docs/ik.md), shared by the CLI and the Python module:
/// one target solved from random seeds (the sampling convention) with the rule that picks the best attempt,
/// the compensation of joint vectors, and the rows and counts of their JSON.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/ik.hpp"
#include "lowpair/ik_closed_form.hpp"
#include "lowpair/kinematics.hpp"
#include "commands/sampling.hpp"
#include "io/robot_file.hpp"

namespace lowpair::commands {

/// Upper bound on the random seeds per row of `ik` (the CLI's --seeds, Python's seeds=); at least 1.
constexpr int kMaxIkSeeds = 1000;

/// One row of `ik` or `compensate`: the solver's result, the seed it came from and where the row was given.
struct IkRow {
  IkResult result;
  int seed = -1;       ///< ik: the random seed's index s (0..K-1); -1: the row's own seed (or compensate's q)
  long long line = 0;  ///< the input's file line (CLI), or the 0-based row (Python)
  std::optional<IkBranch> branch;  ///< compensate on the nominal branch: the branch kept (JSON "branch")
};

/// The better of two attempts at one row: ok first, then converged (singular, or out of range in Report),
/// then the smaller error (position in L plus rotation). @param L the robot size (PoeModel::lengthScale)
bool betterIkAttempt(const IkResult& a, const IkResult& b, double L);

/// Solves row `row` from up to `seeds` random seeds, sample row * seeds + s of the stream `seed`
/// (commands/sampling.hpp): the first ok attempt is kept, else the best (betterIkAttempt).
/// @param ranges samplingRanges(model)
/// @throws std::invalid_argument as inverseKinematics does
IkRow solveFromRandomSeeds(const PoeModel& model, Data& data, const Pose& target, size_t row, int seeds,
                           unsigned long long seed, const std::vector<Range>& ranges, const IkOptions& options,
                           IkWorkspace& work, long long line);

/// The joint values of `calibrated` that put the tool where `nominal` puts it at each row of `q_nominal`
/// (seeded there); `lines[k]` is row k's line.
/// What compensate cannot promise when the calibration left the tool frame (or, for a pose task, its
/// orientation) at the nominal's (`tool_frame:` of the calibrated file): "" when the task's part of the tool was
/// calibrated. `compensate` prints it as a note and JSON `tool_note` (`tool_determined`: whether it is "").
std::string undeterminedToolNote(const io::RobotFile& calibrated, bool pose);

/// @param keep_branch each row on its nominal row's branch (compensateOnBranch) when branchUnavailable is "";
/// a row with no calibrated solution on its branch (a singular row), and every row otherwise, seeded at q.
std::vector<IkRow> compensateJointRows(const PoeModel& nominal, const PoeModel& calibrated,
                                       const Eigen::Ref<const MatX>& q_nominal, const std::vector<long long>& lines,
                                       const IkOptions& options, bool keep_branch);

/// One solution of `ik --all`: from the closed form (with its branch) or, for a model without one, a distinct
/// converged solution of the numerical solver from one of the random seeds (no branch).
struct IkAllSolution {
  VecX q;
  std::optional<IkBranch> branch;  ///< closed form only
  bool singular = false;           ///< closed form: a free angle or a double root; numerical: status singular
  int out_of_range = -1;           ///< the first 0-based joint outside its range, -1 if none
  int iterations = 0;              ///< Newton steps of the refinement (closed form) or of the solve (numerical)
  double position_error = 0.0, rotation_error = 0.0;
};

/// Every solution found for one target row of `ik --all`.
struct IkAllRow {
  long long line = 0;
  std::vector<IkAllSolution> solutions;
  int dropped = 0;  ///< closed-form candidates that failed the FK check after refinement
};

/// Solutions closer than this (jointDistance: rad, or L for a slide) are one: two converged solves of one solution
/// differ by the tolerance times the condition number, 1e-10 x 1e4; distinct solutions of a 6-joint arm differ by
/// O(1) rad unless the target is singular, where branches meet.
constexpr double kSameSolution = 1e-6;

/// Every solution of `target` (a pose): closed form when `closed` is given (a workspace of a model with one),
/// else the distinct converged solutions from `seeds` random seeds (as solveFromRandomSeeds draws them, every
/// seed tried), ordered as found.
IkAllRow solveAll(const PoeModel& model, ClosedFormWorkspace* closed, Data& data, IkWorkspace& work, const Pose& target,
                  size_t row, int seeds, unsigned long long seed, const std::vector<Range>& ranges,
                  const IkOptions& options, long long line);

/// A deflecting calibrated robot's commands (docs/calibration.md "Beyond geometry"): with appliedDeflection of
/// `calibrated_file` (its compliance under its masses; its backlash when `signs`, one approach-sign vector per row,
/// are given), each row's solution q becomes the command whose joints, deflected, stand at q (commandFor); a row whose
/// command does not converge becomes not_converged. Returns whether a deflection applied (rows unchanged if not).
bool applyDeflection(const io::RobotFile& calibrated_file, const PoeModel& calibrated, std::vector<IkRow>& rows,
                     const std::vector<VecX>& signs);

/// Whether compensateJointRows can keep branches for these models and options, and if not why ("" when it can):
/// both robots need a closed form, the task a pose.
std::string branchUnavailable(const PoeModel& nominal, const PoeModel& calibrated, const IkOptions& options);

/// One row of `ik --all`'s JSON: line, count, dropped, solutions [{q, branch {shoulder, elbow, wrist} or null,
/// singular, out_of_range (1-based joint or null), iterations, position_error, rotation_error}].
nlohmann::json ikAllRowJson(const IkAllRow& row);

/// One row of the JSON of `ik` (with_seed: the row's seed, "file" for its own) and `compensate`.
nlohmann::json ikRowJson(const IkRow& row, bool with_seed);

/// The `counts` of the same JSON: the rows per status, every status named.
nlohmann::json ikCountsJson(const std::vector<IkRow>& rows);

}  // namespace lowpair::commands
