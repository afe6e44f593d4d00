#pragma once
/// @file robot_file_loads.hpp (io internal)
/// The robot file's keys beyond the geometry (docs/file_formats.md "Masses, compliance, backlash"): per joint
/// `mass` (kg), `com` (length_unit, base frame at the reference configuration), `compliance` (angle_unit per
/// N m for a turning joint, length per N for a sliding one) and `backlash` (angle_unit or length); top-level
/// `payload: {mass, com}` (com in the tool frame) and `gravity` (m/s^2, base frame).

#include <optional>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "io/robot_file.hpp"
#include "io/yaml_reader.hpp"

namespace lowpair::io {

/// The per-joint keys, allowed beside a joint's geometry keys.
inline const std::set<std::string> kJointLoadKeys = {"mass", "com", "compliance", "backlash"};

/// One joint's keys as read (compliance and backlash already in radians for a turning joint).
struct JointLoadKeys {
  std::optional<double> mass;
  std::optional<Vec3> com;
  std::optional<double> compliance, backlash;
};

/// Reads a joint's keys: mass finite and >= 0, com 3 finite numbers, both or neither; compliance and backlash
/// finite, times `radians_per_unit` (the file's angle unit for a turning joint, 1 for a sliding one).
/// @throws RobotFileError `FILE: line N: WHERE.KEY ...`
JointLoadKeys readJointLoadKeys(const YamlReader& in, const YAML::Node& joint, const std::string& where,
                                double radians_per_unit);

/// Fills `file.masses` (when a joint states a mass, or `payload:` or `gravity:` is given; metres_per_unit from
/// length_unit, which must be one lowpair converts) and `file.deflection` (when a joint states a compliance or a
/// backlash; 0 for the others) from the joints' keys and the top-level `payload:` and `gravity:`.
/// @throws RobotFileError
void readLoads(const YamlReader& in, const YAML::Node& root, const std::vector<JointLoadKeys>& joints, RobotFile& file);

/// Writes joint `joint`'s keys from `extras` (mass and com when extras.masses has link masses; compliance and
/// backlash when non-zero, divided by `radians_per_unit`), inside the joint's open map.
void writeJointLoadKeys(YAML::Emitter& out, const RobotFileExtras& extras, int joint, double radians_per_unit);

/// The masses (checkMassModel) and deflections (empty or one per joint, finite) of `extras` for a `dof`-joint model.
/// @throws std::invalid_argument naming what is wrong
void checkLoadExtras(const RobotFileExtras& extras, int dof);

/// Writes `payload:` and `gravity:` when extras.masses is set, inside the file's open top-level map.
void writeLoads(YAML::Emitter& out, const RobotFileExtras& extras);

/// `file`'s masses with lengths times `f` (com, payload com; metres_per_unit over f) for inUnit.
void scaleLoads(RobotFile& file, double f);

}  // namespace lowpair::io
