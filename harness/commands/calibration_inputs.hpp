#pragma once
/// @file calibration_inputs.hpp
/// What `lowpair calibrate` checks and derives from its inputs before fitting, shared by the CLI and the
/// Python module's lowpair.calibrate and lowpair.read_measurements: a measurement CSV read for a robot, joint
/// values outside the nominal's ranges, the stated noise, the parameters to fit, the validation set's targets
/// mapped to the fit's, and the nominal's target points.

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/measurements.hpp"
#include "io/robot_file.hpp"
#include "lowpair/calibration.hpp"
#include "commands/arguments.hpp"

namespace lowpair::commands {

/// A joint value beyond this many range widths outside the nominal's range is a wrong column or unit: never
/// fitted silently.
constexpr double kFarOutsideRange = 10.0;

/// At most this many joint values outside the ranges are warned about one by one (then their count).
constexpr int kMaxRangeWarnings = 5;

/// A measurement's joint value outside the nominal's range of that joint.
struct OutsideRange {
  size_t row = 0;  ///< index into the measurements
  int joint = 0;   ///< 0-based
  double q = 0.0;
  std::array<double, 2> range{};
  bool far = false;  ///< more than kFarOutsideRange range widths outside
};

/// Every joint value of `measurements` outside the nominal's ranges, row by row, joint by joint.
std::vector<OutsideRange> jointValuesOutsideRanges(const PoeModel& nominal, const std::vector<Measurement>& measurements);

/// Checks the joint values of `measurements` against the nominal's ranges (jointValuesOutsideRanges): each
/// value outside is described as "WHERE = Q is outside joint J's range [LO, HI] of ROBOT" (WHERE from `where`,
/// ROBOT `robot_name`); the first beyond kFarOutsideRange range widths goes to `refuse` (which throws) with
/// " by more than 10 times its width: a wrong column or unit?" appended, nearer ones before it to `warn`
/// (the first kMaxRangeWarnings of them).
/// @return how many values are outside (a caller says how many in all when more than kMaxRangeWarnings)
int checkJointRanges(const PoeModel& nominal, const std::vector<Measurement>& measurements, const std::string& robot_name,
                     const std::function<std::string(const OutsideRange&)>& where,
                     const std::function<void(const std::string&)>& refuse,
                     const std::function<void(const std::string&)>& warn);

/// A measurement CSV read for a calibration of the robot file `robot` (its POE model `nominal`, named
/// `robot_name` in messages), as `lowpair calibrate` reads --measurements and --validation: the header is
/// checked against the robot before the rest is read (its joint count; its length unit, when both state one
/// and lowpair cannot convert between them), a joint value beyond kFarOutsideRange range widths outside the
/// robot's range is refused, nearer ones are warned about as they are found (`warn`, one line without
/// "warning: ": the first kMaxRangeWarnings, then the count; those before a refusal are warned first), and
/// lengths in another unit lowpair knows are converted to the robot's (`notes`: one line says so;
/// `file.length_unit` is then the robot's).
struct CalibrationMeasurements {
  io::MeasurementFile file;
  std::vector<std::string> notes;  ///< one line each, without "note: "
};
/// @throws io::RobotFileError `FILE[:LINE]: what` (the reader's errors, and the checks above)
CalibrationMeasurements readCalibrationMeasurements(const std::string& path, const io::RobotFile& robot,
                                                    const std::string& robot_name, const PoeModel& nominal,
                                                    const std::function<void(const std::string&)>& warn);

/// The stated measurement noise: each in (0, limit] (position 1e100 length, rotation pi rad).
/// @throws UsageError naming noise_position or noise_rotation as `spelling` spells it
void checkStatedNoise(const std::optional<double>& noise_position, const std::optional<double>& noise_rotation,
                      const ArgumentSpelling& spelling);

/// The parameters to fit: full, lines, offsets, or a comma list of parameter names (spaces and tabs around
/// each trimmed). @throws UsageError naming parameters as `spelling` spells it
void parseParameters(const std::string& text, CalibrationOptions& options, const ArgumentSpelling& spelling);

/// The prior of `--prior TEXT` (docs/calibration.md "A prior on the nominal"): one WIDTH (tilt WIDTH mrad, shift WIDTH mm,
/// scale WIDTH x 0.1 %, offset 10 WIDTH mrad), or `tilt=A,shift=B,scale=C,offset=D` (mrad, mm, %, mrad; a kind left out
/// is free; `inf` for free). Millimetres become the robot's length unit with `metres_per_unit` (1 mm = 1 unit when
/// unknown). @throws UsageError naming prior as `spelling` spells it: a malformed, non-positive or NaN width, an
/// unknown or repeated key
ParameterPrior parsePrior(const std::string& text, std::optional<double> metres_per_unit, const ArgumentSpelling& spelling);
/// The prior of `--prior WIDTH` (tilts WIDTH mrad, shifts WIDTH mm in the robot's unit, scales WIDTH x 0.1 %,
/// offsets 10 WIDTH mrad; 1 mm as one unit when the unit is unknown).
ParameterPrior priorOfWidth(double width, std::optional<double> metres_per_unit);

/// The prior widths `--prior-grid default` compares (docs/calibration.md "Selection"): from 0.3 (a nominal good to
/// a fraction of a mrad and mm, a machined arm) to 50 (hardly a prior), about a factor 3 apart.
constexpr std::array<double, 5> kDefaultPriorGrid{0.3, 1.0, 3.0, 10.0, 50.0};
constexpr int kMaxPriorGrid = 10;
/// `--prior-grid`'s text: `default` (kDefaultPriorGrid) or a comma list of distinct positive finite WIDTHs, at most
/// kMaxPriorGrid. @throws UsageError naming prior_grid
std::vector<double> parsePriorGrid(const std::string& text, const ArgumentSpelling& spelling);

/// Maps the validation set's target indices to the fit's by name and gives it the fit's names.
/// @return the first target the fit does not measure (then nothing is to be used), or nothing
std::optional<std::string> mapValidationTargets(io::MeasurementFile& validation, const std::vector<std::string>& fit_names);

/// The fit's targets: each name with the point of the nominal's `targets:` entry of that name, else none
/// (the fit estimates it).
std::vector<Target> nominalTargets(const io::RobotFile& nominal, const std::vector<std::string>& names);

}  // namespace lowpair::commands
