#pragma once
/// @file collision_check.hpp
/// Contacts of a MuJoCo chain at a configuration (`lowpair plan`'s feasible candidates, docs/plan.md "Feasible
/// plans"). The model is loaded through a collision copy (ModelCopy with CopyContent::Collision: geoms,
/// meshes when their files are present, `<contact>` pairs and excludes), with an optional floor: a plane
/// `z = floor_z` of the base frame (geom "lowpair-floor", contype and conaffinity all ones, so it meets every
/// geom that collides with anything). At each configuration: mj_kinematics, then mj_collision, which applies
/// MuJoCo's own filtering (bodies welded together, a body and its parent, contype/conaffinity, `<exclude>`;
/// `<pair>`s added); a configuration is free when d->ncon is 0.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/types.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::mujoco {

/// Where a configuration touches: two moving bodies, a moving body and the world's geometry (a body welded
/// to the world: a table, a fixture, the base), or the floor.
enum class ContactKind { Self, World, Floor };

/// The contacts at one configuration.
struct ContactReport {
  int contacts = 0;                          ///< d->ncon
  ContactKind kind = ContactKind::Self;      ///< the first of Self, World, Floor met (when contacts > 0)
  std::vector<std::array<int, 2>> bodies;    ///< the distinct body pairs in contact (ids, smaller first)
};

class CollisionChecker {
 public:
  /// @param robot the chain: its joints' qpos addresses are those of the collision copy (copies drop no joint)
  /// @param floor_z the floor's height in the base frame (model lengths); none: no floor
  /// @throws io::RobotFileError for a model MuJoCo cannot load with its geometry (a mesh it cannot read)
  CollisionChecker(const MujocoRobot& robot, std::optional<double> floor_z);
  ~CollisionChecker();
  CollisionChecker(const CollisionChecker&) = delete;
  CollisionChecker& operator=(const CollisionChecker&) = delete;

  /// The model's geoms that can collide (contype or conaffinity not 0), the floor not counted.
  int collisionGeoms() const { return collision_geoms_; }
  /// The contacts at motion variables `x` (per chain joint: qpos = qpos0 + x, a helical slide pitch x; every
  /// other joint at qpos0).
  ContactReport contactsAt(const Eigen::Ref<const VecX>& x);
  /// A body's name for messages: its MJCF name, or "body N" when it has none; "floor" for the floor's body
  /// when the floor is meant (ContactKind::Floor pairs use -1 for the floor).
  std::string bodyName(int body) const;
  /// The collision copy's notes (mesh files not found, attributes MuJoCo 2.2.2 does not know), without "note: ";
  /// not emitted: the caller knows which the robot's own load gave already.
  const std::vector<std::string>& notes() const { return notes_; }
  /// The collision copy and its data at the configuration last given to contactsAt (line_of_sight.hpp reads them).
  const mjModel_* model() const { return model_.get(); }
  const mjData_* data() const { return data_.get(); }
  /// The floor's geom id; -1 without a floor.
  int floorGeom() const { return floor_geom_; }
  const MujocoRobot& robot() const { return robot_; }

 private:
  struct ModelDeleter {
    void operator()(mjModel_* m) const;
  };
  const MujocoRobot& robot_;
  std::unique_ptr<mjModel_, ModelDeleter> model_;
  std::unique_ptr<mjData_, void (*)(mjData_*)> data_;
  int floor_geom_ = -1, collision_geoms_ = 0;
  std::vector<std::string> notes_;
};

}  // namespace lowpair::mujoco
