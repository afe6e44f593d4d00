#pragma once
/// @file ik_rows.hpp
/// The rows of `lowpair ik` and `lowpair compensate` (docs/ik.md), shared by the CLI and the Python module:
/// one target solved from random seeds (the sampling convention) with the rule that picks the best attempt,
/// the compensation of joint vectors, and the rows and counts of their JSON.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "lowpair/ik.hpp"
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

std::vector<IkRow> compensateJointRows(const PoeModel& nominal, const PoeModel& calibrated,
                                       const Eigen::Ref<const MatX>& q_nominal, const std::vector<long long>& lines,
                                       const IkOptions& options);

/// One row of the JSON of `ik` (with_seed: the row's seed, "file" for its own) and `compensate`.
nlohmann::json ikRowJson(const IkRow& row, bool with_seed);

/// The `counts` of the same JSON: the rows per status, every status named.
nlohmann::json ikCountsJson(const std::vector<IkRow>& rows);

}  // namespace lowpair::commands
