#pragma once
/// @file calibration.hpp
/// Identifiability and calibration of POE models (Wu, Crawford, Roberts §V-VI; docs/calibration.md).
/// The umbrella header: every part of the calibration, one topic per header.

#include "lowpair/measure.hpp"           // Measure, Measurement, Target
#include "lowpair/error_model.hpp"       // ParameterCount, ErrorModel, the identification Jacobians
#include "lowpair/identifiability.hpp"   // RankAnalysis, analyzeRank, analyzeIdentifiability
#include "lowpair/registration.hpp"      // residualStatistics, movedModel, registerMeasurementFrame
#include "lowpair/base_frame.hpp"        // baseFrameRule, baseFrame, toNominalBase (the base frame as the gauge)
#include "lowpair/robust_loss.hpp"       // Loss, RobustLoss
#include "lowpair/calibrate.hpp"         // CalibrationOptions, CalibrationResult, calibrate
#include "lowpair/cross_validation.hpp"  // crossValidate
#include "lowpair/dh_uncertainty.hpp"    // dhUncertainty
