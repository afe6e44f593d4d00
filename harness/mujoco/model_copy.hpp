#pragma once
/// @file model_copy.hpp
/// Kinematics-only copies of MJCF and URDF files for MuJoCo 2.2.2 (the ground truth), made with tinyxml2,
/// never by string edits (README "Validation against MuJoCo"). MujocoRobot loads every model through one.
///
/// MJCF: `<include>`s inlined (a relative file is relative to the main model's folder, as MuJoCo 2.2.2
/// resolves it also inside included files; a file is included once; at most 16 levels). Dropped, as
/// kinematics does not need them: every `<geom>`, `<camera>` and `<light>`; `<asset>` (meshes, textures,
/// materials, height fields, skins: their files are never opened), `<actuator>`, `<sensor>`, `<contact>`,
/// `<keyframe>`, `<visual>`, `<statistic>`, `<custom>`, `<size>`, `<extension>`, `<deformable>`; default
/// classes of dropped elements; `material` on sites; `<tendon>` unless an `<equality><tendon>` needs it
/// (MujocoRobot then checks which joints it couples; its wrapping geoms go). Tendons change no joint's
/// kinematics by themselves. Compiler settings merged into the file's last `<compiler>` (the last setting
/// of an attribute wins in MuJoCo; one is added when there is none): the file's own settings stay
/// (angle, eulerseq, coordinate, inertiafromgeom, ...), `autolimits="true"` where no compiler sets it
/// (MuJoCo >= 2.3's default, which files written for it rely on; 2.2.2 knows the attribute),
/// `boundmass="1e-6" boundinertia="1e-9"` where absent or not positive (bodies lose their geoms' mass),
/// `fusestatic="false"` (a fused body would take a tip's name with it; fusing changes no pose; a
/// note when the file said otherwise), and meshdir/texturedir/assetdir removed.
/// `<equality><distance>` (between geoms) is rejected.
///
/// URDF: `<visual>` and `<collision>` dropped (so `package://` meshes are never opened), inertials kept,
/// settings merged into the file's `<mujoco><compiler/></mujoco>` block (one is added when there is none):
/// `fusestatic="false"` as above, and where absent `discardvisual="true"`, `boundmass="1e-6"`,
/// `boundinertia="1e-9"`, `strippath="false"`.
///
/// The copy is then loaded with MuJoCo until it loads. When MuJoCo 2.2.2 rejects an attribute or keyword
/// (its schema names the first one, with the element and line), the attribute is removed with a note if it
/// cannot change kinematics: any attribute of `<option>`, `<flag>`, `<size>` and of kept tendons; the
/// newer actuator-force attributes of `<joint>` (actuatorfrcrange, actuatorfrclimited,
/// actuatorgravcomp), `<body gravcomp>`, `<compiler assetdir|saveinertial>`. Anything else (an unknown
/// attribute on body, joint, site, inertial, equality, compiler..., an unknown element such as `<frame>`)
/// and any other load error is an io::RobotFileError naming it with the original file and line, never dropped.
/// Comments survive (they are XML nodes); text outside the root element is kept by tinyxml2 too.
///
/// A copy with CopyContent::Inertials (MujocoDynamics, mujoco_dynamics.hpp: the masses) is the same copy
/// except that every `<inertial>` stays (MJCF and URDF), so the bodies' masses and centres of mass are the
/// file's. Geometry is still dropped: a body whose mass MuJoCo would compute from its geoms (no `<inertial>`
/// and `inertiafromgeom` not "false", or any body with geoms under `inertiafromgeom="true"`) weighs only
/// the mass bound in the copy; massFromGeoms() names those bodies.
///
/// A copy with CopyContent::Collision (CollisionChecker, collision_check.hpp) keeps what MuJoCo's collision
/// detection reads: every `<geom>` (except height fields), geom/mesh/pair defaults, `<contact>` (`<pair>`,
/// `<exclude>`) and the `<mesh>` assets, each mesh file made absolute (meshdir/assetdir of the file); a mesh
/// whose file is missing goes with its geoms, one note each. URDF: `<collision>` stays (a relative mesh
/// made absolute; a `package://` or missing mesh dropped with a note), `<visual>` goes. Materials, textures
/// and skins go; `strippath="false"`.

#include <string>
#include <vector>

namespace lowpair::mujoco {

/// The mass (kg) a copy gives a body with none where the file sets no positive `boundmass`: a body of at
/// most this mass has no inertial of its own (MujocoDynamics).
inline constexpr double kCopyBoundMass = 1e-6;

/// What a model copy keeps besides the kinematics.
enum class CopyContent {
  Kinematics,  ///< no `<inertial>` (MujocoRobot)
  Inertials,   ///< every `<inertial>` kept: the masses are the file's
  Collision,   ///< collision geoms, contact pairs/excludes and meshes kept (no `<inertial>`)
};

/// A new empty file `STEM_XXXXXX.EXT` in the temp folder, its six Xs made unique by mkstemps; the caller removes it.
/// @param ext the extension with its dot (".xml")
/// @throws io::RobotFileError ("MODEL: cannot create a temporary copy in DIR")
std::string createTemporaryFile(const std::string& model, const std::string& stem, const std::string& ext);

/// A temporary kinematics-only copy (a unique file in the temp folder, createTemporaryFile); the file is
/// removed when the object is destroyed. It has been loaded by MuJoCo once when the constructor returns.
class ModelCopy {
 public:
  /// @param path an MJCF (root `<mujoco>`) or URDF (root `<robot>`) file; the root decides, not the extension
  /// @param notes receives, without a "note: " prefix, one line per attribute removed because MuJoCo 2.2.2
  ///        does not know it ("FILE: line N: dropped <option integrator='implicitfast'>: not known to
  ///        MuJoCo 2.2.2, no effect on kinematics"), one per compiler setting replaced, and one summary of
  ///        the elements kinematics did not need ("FILE: not needed for kinematics, dropped: 25 <geom>,
  ///        1 <asset>, ..."); nothing when the file needed no change
  /// @throws io::RobotFileError ("FILE: what"); no temporary file is left behind
  /// @param content CopyContent::Inertials keeps the `<inertial>` elements
  ModelCopy(const std::string& path, std::vector<std::string>* notes = nullptr,
            CopyContent content = CopyContent::Kinematics);
  ~ModelCopy();
  ModelCopy(const ModelCopy&) = delete;
  ModelCopy& operator=(const ModelCopy&) = delete;
  /// The copy to hand to mj_loadXML.
  const std::string& path() const { return copy_; }
  /// CopyContent::Inertials: the bodies whose mass the file leaves to their geoms (which the copy drops), as
  /// "'name'" or, unnamed, "FILE: line N"; empty for a kinematics copy.
  const std::vector<std::string>& massFromGeoms() const { return mass_from_geoms_; }

 private:
  std::string copy_;
  std::vector<std::string> mass_from_geoms_;
};

}  // namespace lowpair::mujoco
