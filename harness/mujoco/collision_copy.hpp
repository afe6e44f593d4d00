#pragma once
/// @file collision_copy.hpp
/// Inside the mujoco room: what a collision copy (ModelCopy with CopyContent::Collision, model_copy.hpp)
/// keeps of a model's geometry, applied to the parsed file before it is written to the temporary folder.

#include <tinyxml2.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace lowpair::mujoco::detail {

/// Where an element was written ("FILE: line N"), for notes.
using ElementOrigin = std::function<std::string(const tinyxml2::XMLElement*)>;

/// An MJCF (includes already inlined): every `<asset>` reduced to its `<mesh>` elements, each `file` made
/// absolute (relative to `folder`, the main model's folder, and the file's meshdir or assetdir); a mesh whose
/// file is missing is dropped with its geoms and the `<pair>`s naming them (one note per mesh); `material`
/// removed from geoms (materials and textures go), height-field geoms dropped.
void keepMjcfCollisionGeometry(tinyxml2::XMLElement* root, const std::filesystem::path& folder,
                               const ElementOrigin& where, std::vector<std::string>& notes);

/// A URDF: each `<collision>` mesh `filename` made absolute (relative to `folder` and the `<mujoco>` block's
/// meshdir); a collision whose mesh is a `package://` URI or a missing file is dropped with a note.
void keepUrdfCollisionGeometry(tinyxml2::XMLElement* robot, const std::filesystem::path& folder,
                               const ElementOrigin& where, std::vector<std::string>& notes);

}  // namespace lowpair::mujoco::detail
