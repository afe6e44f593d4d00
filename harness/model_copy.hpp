#pragma once
/// @file model_copy.hpp
/// Kinematics-only copies of MJCF and URDF files for MuJoCo 2.2.2 (the ground truth), made with tinyxml2,
/// never by string edits (README "Validation against MuJoCo"): comments and an existing `<mujoco>` block
/// respected (compiler settings merged), visual and collision geometry, mesh assets, actuators, sensors,
/// cameras, lights, contacts and keyframes dropped, massless bodies bounded, attributes MuJoCo 2.2.2 does
/// not know but that cannot change kinematics removed (each named in a note), anything else it cannot
/// load an error naming it.

#include <string>
#include <vector>

namespace lowpair {

/// A temporary kinematics-only copy; the file is removed when the object is destroyed.
class ModelCopy {
 public:
  /// @param notes receives one line per attribute or element removed that a user may want to know about
  /// @throws RobotFileError ("FILE: what")
  ModelCopy(const std::string& path, std::vector<std::string>* notes = nullptr);
  ~ModelCopy();
  ModelCopy(const ModelCopy&) = delete;
  ModelCopy& operator=(const ModelCopy&) = delete;
  /// The copy to hand to mj_loadXML.
  const std::string& path() const { return copy_; }

 private:
  std::string copy_;
};

}  // namespace lowpair
