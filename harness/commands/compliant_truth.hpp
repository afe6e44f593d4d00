#pragma once
/// @file compliant_truth.hpp
/// The compliant "actual" robot as a ground truth for simulated measurements (issue 27): MuJoCo's robot with
/// a spring in each joint, each commanded pose measured where the robot comes to rest under gravity
/// (mujoco::CompliantActual, docs/validation.md "A compliant actual robot"). `lowpair simulate MODEL
/// --stiffness K1,...` measures it; without a stiffness nothing changes.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "commands/arguments.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::commands {

/// The tool pose of a compliant robot at commanded motion x (MuJoCo's motion variable: qpos - qpos0).
struct CompliantTruth {
  std::function<Pose(const VecX& x)> tipPose;  ///< throws UsageError (stiffness) when the robot finds no stable rest
  std::string description;                     ///< one line for a measurement file's comments
};

/// @param stiffness one per joint of `robot`, per unit of its motion x: N m/rad (revolute, helical) or N/m
///        (prismatic), in MuJoCo's units (lengths in metres); 0: rigid
/// @throws UsageError (subject: stiffness as `spelling` spells it) for a count or a value that is negative
///         or not finite; io::RobotFileError ("FILE: no masses: ...") when the model has no mass model
CompliantTruth compliantTruth(std::shared_ptr<const mujoco::MujocoRobot> robot, const std::vector<double>& stiffness,
                              const ArgumentSpelling& spelling);

}  // namespace lowpair::commands
