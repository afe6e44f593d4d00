#pragma once
/// @file deflection_inputs.hpp
/// What `calibrate` and `identifiability` take of the joints' deflections (docs/calibration.md "Beyond geometry"),
/// shared by the CLI and the Python module: `--compliance JOINTS|all` and `--backlash JOINTS` resolved against the
/// robot and the poses, the masses and deflections of the nominal file, and where each joint's move signs come from.

#include <optional>
#include <string>
#include <vector>

#include "io/robot_file.hpp"
#include "lowpair/calibration.hpp"
#include "commands/arguments.hpp"

namespace lowpair::commands {

/// The joints a calibration fits deflections of, and how their inputs were obtained (numbers for the report).
struct DeflectionChoice {
  std::vector<int> compliance, backlash;  ///< 0-based joints, ascending
  /// `all`: the joints left out because their gravity load does not vary over the poses (0-based)
  std::vector<int> rigid;
  /// Per joint with backlash: its signs from a column of the measurement file (else from the poses' order).
  std::vector<bool> sign_from_column;
  bool any() const { return !compliance.empty() || !backlash.empty(); }
};

/// `text` as joints: a comma list of 1-based indices or joint names (spaces and tabs trimmed), each once, or
/// `all` (when `all` may be given: then every joint, and `all` is set).
/// @throws UsageError naming `option` as `spelling` spells it
std::vector<int> parseJointList(const std::string& text, const PoeModel& model, const std::string& option,
                                const ArgumentSpelling& spelling, bool* all = nullptr);

/// Fills `options`' deflection fields for a fit (or an identifiability analysis) of `measurements` of `nominal`:
/// the nominal file's masses and deflections, the move signs (`sign_columns`/`signs`: a measurement file's
/// columns, else moveSigns of the measurements' order), and the joints of `compliance` and `backlash` (parseJointList
/// texts; `compliance` may be `all`: the joints whose load varies over the measurements).
/// @param data how messages name the measurements (a file path, or "the N random poses")
/// @throws UsageError naming compliance or backlash: a joint named twice, --compliance without masses in the
/// nominal file, a named joint whose load (or sign) does not vary over the measurements (checkDeflections)
DeflectionChoice chooseDeflections(const io::RobotFile& nominal_file, const PoeModel& nominal,
                                   const std::optional<std::string>& compliance, const std::optional<std::string>& backlash,
                                   const std::vector<Measurement>& measurements, const std::vector<bool>& sign_columns,
                                   const std::vector<VecX>& signs, const std::string& data, CalibrationOptions& options,
                                   const ArgumentSpelling& spelling);

/// The move signs of `measurements` for the backlash joints: a measurement file's column where it has one
/// (`sign_columns`, `signs`), else moveSigns of the measurements' order.
std::vector<VecX> measurementMoveSigns(const std::vector<Measurement>& measurements, const std::vector<int>& backlash,
                                       const std::vector<bool>& sign_columns, const std::vector<VecX>& signs);

/// Whether `file` holds a compliance fk and compensate apply (a `compliance` key and masses).
bool appliesCompliance(const io::RobotFile& file);

/// The deflections fk and compensate apply of `file`: its compliance when it has masses, its backlash when the
/// approach signs are given (`with_backlash`); empty when neither.
JointDeflection appliedDeflection(const io::RobotFile& file, bool with_backlash);

/// The joint values `file`'s robot stands at when commanded `q` (`model` its POE model): `q + c tau(q) + b s` with
/// appliedDeflection (its compliance under its masses' load; its backlash when `sign`, the approach signs, is given);
/// `q` when nothing applies.
VecX standingJoints(const io::RobotFile& file, const PoeModel& model, const VecX& q, const VecX& sign = VecX());

/// The approach signs of `--approach` for `rows` joint vectors of `dof` joints: `order` (moveSigns of the rows: each
/// joint's last move from row to row), or a comma list of `dof` signs (-1, 0 or 1) for every row; none for "".
/// @param one_row the command has a single joint vector (`order` is then refused)
/// @throws UsageError naming approach
std::vector<VecX> approachSigns(const std::string& text, const std::vector<VecX>& rows, int dof, bool one_row,
                                const ArgumentSpelling& spelling);

/// The note fk and compensate print about a file's deflections ("" when it holds none): what is applied
/// (`approach`: the approach signs are given).
std::string deflectionNote(const io::RobotFile& file, bool approach = false);

/// The spec an identifiability analysis of the deflections uses (the options' joints and values).
ErrorModelSpec deflectionSpec(const CalibrationOptions& options);

}  // namespace lowpair::commands
