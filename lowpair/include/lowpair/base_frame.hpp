#pragma once
/// @file base_frame.hpp
/// The robot's base frame from its geometry, the gauge of a calibration with an unknown measurement frame
/// (docs/calibration.md "The base frame as the gauge").
///
/// With an unknown measurement frame, any rigid motion of every twist, the tool and the targets, with the
/// measurement frame moved back, predicts the same measurements: the base is a gauge. It is fixed the way
/// robot makers define a base, from joint 1's line, its zero and the foot of the common normal to joint 2.
/// The frame `F` (a pose in the model's coordinates) of a model with unit directions `d_i` (the axis `w` of a
/// revolute/helical joint, the direction `v` of a prismatic one) at the zero configuration (the twists as the
/// model holds them):
/// - `z = d_1`. Joint 1's line: its axis (revolute/helical); for a prismatic joint 1, whose twist fixes only a
///   direction, the line along `d_1` through the tool point (`toolPose().p`).
/// - origin: the foot on joint 1's line of the common normal to the first later revolute/helical axis `k`
///   not parallel to it (`|d_1 x d_k| > kBaseFrameParallel`, joint 2 on most arms; intersecting axes: the
///   intersection). Where every later axis is parallel (a planar arm) or prismatic: the tool point's
///   projection on joint 1's line.
/// - x: `unit(d_1 x d_k)` for the first later joint `k` (of any type) whose direction is not parallel to
///   `d_1` (joint 1's zero: the common normal's direction, the same for intersecting and skew axes). Where
///   there is none: the perpendicular from joint 1's line to the tool point; where the tool point is on that
///   line (within kBaseFrameParallel L), the tool's x axis (else its y axis) made perpendicular to `z`.
/// The choices (which joint, which fallback) are made once on the nominal (baseFrameRule) and applied as they
/// are to the calibrated model, so that a calibrated axis a hair off the nominal's parallel band cannot switch
/// the rule. Every construction is equivariant: `baseFrame(movedModel(m, T), rule) = T baseFrame(m, rule)`.

#include "lowpair/model.hpp"

namespace lowpair {

/// Axes whose directions' cross product is at most this (the sine of their angle) count as parallel for the
/// base-frame rule: the foot of a common normal moves by (the axes' error) / sin, 100x at this bound.
constexpr double kBaseFrameParallel = 1e-2;

/// Which geometry fixes the base frame: decided on the nominal (see the file comment).
struct BaseFrameRule {
  /// The revolute/helical joint (0-based) whose common normal with joint 1's line gives the origin; -1:
  /// the tool point's projection on joint 1's line.
  int foot_joint = -1;
  /// The joint whose direction gives x = unit(d_1 x d_k); -1: the fallback below.
  int direction_joint = -1;
  enum class XFallback { None, ToolPoint, ToolX, ToolY };
  XFallback fallback = XFallback::None;  ///< used when direction_joint is -1
};

/// The rule's choices for `nominal`.
BaseFrameRule baseFrameRule(const PoeModel& nominal);

/// The base frame `T_model_frame` of `model` (its pose in the model's coordinates) by `rule`.
Pose baseFrame(const PoeModel& model, const BaseFrameRule& rule);

/// A model (a calibrated one, in the measurement frame) moved into the nominal's base frame.
struct BaseFrameGauge {
  BaseFrameRule rule;       ///< baseFrameRule(nominal)
  /// The nominal's base frame in the model's (the measurement) frame: `baseFrame(model) baseFrame(nominal)^-1`.
  Pose T_measurement_base;
  /// `movedModel(model, T_measurement_base^-1)`: its joint 1 line, zero direction and foot are the nominal's.
  PoeModel model;
};

/// @param model a model of the nominal's robot in another frame (same joint count and types)
/// @throws std::invalid_argument when the joint counts differ
BaseFrameGauge toNominalBase(const PoeModel& model, const PoeModel& nominal);
/// The same with the rule given (baseFrameRule(nominal) computed once).
BaseFrameGauge toNominalBase(const PoeModel& model, const PoeModel& nominal, const BaseFrameRule& rule);

}  // namespace lowpair
