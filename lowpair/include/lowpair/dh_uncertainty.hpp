#pragma once
/// @file dh_uncertainty.hpp
/// The standard deviations of a calibrated D-H table (docs/calibration.md).

#include <vector>

#include "lowpair/calibrate.hpp"
#include "lowpair/convert.hpp"

namespace lowpair {

/// Standard deviations of the calibrated D-H table: the parameter covariance propagated through poeToDh by
/// central differences of one standard deviation along the covariance's principal axes (angle differences
/// wrapped; a row whose `a` changes sign is compared on the central table's branch, `(theta - pi, d, -alpha,
/// -a)` with pi moved to the next theta). A D-H number that moves along an undetermined direction is +inf.
/// No standard deviation is below the number's rounding, `eps max(|value|, unit)` (unit: L for lengths and
/// pitches, 1 for angles and scales): a noise-free fit gives that floor, never an exact 0. An entry the
/// conversion fixes by convention has standard deviation 0 and its flag set: a row placed by a prismatic
/// joint's axis has `a = 0` and `d = 0` (docs/conversion.md; `d` only while no offset of the joint before
/// it moves it: one that slides, prismatic, helical or revolute with a fitted pitch, with a nonzero or fitted
/// offset).
struct DhUncertainty {
  DhConversion conversion;              ///< of the calibrated model
  DhParams base;                        ///< standard deviations
  std::vector<DhParams> links;          ///< per joint
  std::vector<double> pitch, scale;     ///< per joint (pitch 0 for non-helical)
  double tool_theta = 0.0, tool_d = 0.0;
  struct Fixed {
    bool d = false, a = false;  ///< set by the D-H convention
    /// set by the base-frame rule (the gauge; dhUncertainty with a nominal): the base row's and joint 1's row's
    /// entries that no parameter moves
    bool gauge_theta = false, gauge_d = false, gauge_alpha = false, gauge_a = false;
  };
  Fixed base_fixed;                 ///< set by the D-H convention or the gauge, not measured (standard deviation 0)
  std::vector<Fixed> links_fixed;   ///< per joint's row
};

DhUncertainty dhUncertainty(const CalibrationResult& result);

/// The same for the calibrated model in `nominal`'s base frame (toNominalBase, base_frame.hpp): every model
/// the propagation visits is moved there first, so the covariance goes through the gauge map numerically
/// (central differences along the principal axes). The entries of the base row and of joint 1's row that
/// no parameter moves (a probe of 1e-6 along each) are the rule's, not measured: standard deviation 0,
/// Fixed::gauge_* set.
DhUncertainty dhUncertainty(const CalibrationResult& result, const PoeModel& nominal);

/// Standard deviations of `T_measurement_base` (toNominalBase of the calibrated model): the rotation about
/// the measurement frame's axes (rad) and the position (length), by the same numerical propagation; +inf
/// where an undetermined direction moves it; never below rounding.
struct MeasurementFrameUncertainty {
  Vec3 rotation = Vec3::Zero(), position = Vec3::Zero();
};
MeasurementFrameUncertainty measurementFrameUncertainty(const CalibrationResult& result, const PoeModel& nominal);

}  // namespace lowpair
