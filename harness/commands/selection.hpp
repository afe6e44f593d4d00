#pragma once
/// @file selection.hpp
/// `calibrate --select cv` (docs/calibration.md "Selection"), for the CLI and the Python module: the candidates
/// (parameter levels x prior widths x the stated compliance and backlash on and off), the score, the limit on the
/// work, the cross-validation, the chosen candidate's options, and the table of scores as text and JSON.

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "io/measurements.hpp"
#include "io/robot_file.hpp"
#include "lowpair/calibration.hpp"
#include "commands/arguments.hpp"
#include "commands/deflection_inputs.hpp"

namespace lowpair::commands {

/// What `--select cv` compared and chose.
struct Selection {
  CrossValidation cv;
  /// Per prior of the grid (CrossValidation::Candidate::prior): its WIDTH, none for no prior; empty without a grid.
  std::vector<std::optional<double>> prior_widths;
  bool given_prior = false;  ///< without a grid, every candidate has the prior given (`--prior`)
};

/// The arguments of a selection (CalibrationRequest's).
struct SelectionRequest {
  int folds = 5, repeats = kCrossValidationRepeats;
  std::optional<std::string> prior_grid;  ///< parsePriorGrid's text
  std::optional<std::string> cv_score;    ///< rms (none: rms), trimmed or median
};

/// The checks of select's companions before any work: prior_grid and cv_score only with select cv, prior_grid not
/// with a prior. @throws UsageError naming the argument
void checkSelectionArguments(const SelectionRequest& request, bool select, bool prior, const ArgumentSpelling& spelling);

/// Cross-validates the candidates on `fit`'s poses (the levels; the prior grid's widths and no prior; the options'
/// compliance and backlash joints on and off), then sets `options` to the chosen candidate's and drops the joints
/// it fits rigid from `deflections`.
/// @throws UsageError naming folds (fewer poses than folds) or repeats (the work limit, limits.hpp);
/// std::invalid_argument as crossValidate
Selection selectByCrossValidation(const io::RobotFile& nominal_file, const PoeModel& nominal, const io::MeasurementFile& fit,
                                  const SelectionRequest& request, CalibrationOptions& options,
                                  DeflectionChoice& deflections, const ArgumentSpelling& spelling);

/// The default selection: the three levels alone, scored by RMS (printed on one line, as before the grid).
bool levelsOnly(const Selection& s);
/// The chosen candidate in words, as the text's last line and Python's repr give it: "lines, prior 3, compliance
/// on, backlash off" (the prior, compliance and backlash only where candidates differ in them).
std::string chosenText(const Selection& s);

/// "rms", "trimmed", "median".
std::string scoreName(CrossValidationScore score);

/// The selection as calibrate prints it: the levels alone with the RMS score (the default) on one line as before;
/// otherwise a table, one row per candidate. `unit`: the robot's length unit; `noise_stated`: the scores' unit.
void printSelection(std::ostream& out, const Selection& s, bool noise_stated, const std::string& unit);
/// JSON `cross_validation`: folds, repeats, score, candidates (one per row: parameters, prior, compliance, backlash,
/// count, rms_position, rms_rotation, score, score_sd, failed, chosen), chosen (the level).
nlohmann::json selectionJson(const Selection& s, Measure measure);

}  // namespace lowpair::commands
