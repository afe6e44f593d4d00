#pragma once
/// @file line_of_sight.hpp
/// A laser tracker's line of sight to the SMRs on a robot's tool (`lowpair plan --tracker`, docs/plan.md "Line of
/// sight"), judged by MuJoCo's ray casting (mj_ray) on the collision copy of a CollisionChecker at the
/// configuration last given to its contactsAt. Every geom of the copy blocks a ray (collision and visual geoms
/// alike, the floor included) except those MuJoCo's mj_ray skips: a geom drawn fully transparent (alpha 0).
/// Positions are MuJoCo's world frame, metres.

#include <string>

#include "lowpair/types.hpp"
#include "mujoco/collision_check.hpp"

namespace lowpair::mujoco {

class LineOfSight {
 public:
  /// @param checker the collision copy; it must outlive this object
  explicit LineOfSight(const CollisionChecker& checker) : checker_(checker) {}

  /// The robot's base frame in the world at the current configuration (the base body's pose; identity for the
  /// world).
  Pose T_world_base() const;

  /// A geom of the world's geometry (bodies welded to the world, the floor) that holds the point `p_world` at the
  /// current configuration; -1 for none. A primitive or mesh holds the point when rays from it along +z and -z
  /// both meet the geom (from inside a closed surface every ray leaves through it; from outside a convex one at
  /// most one direction meets it): exact for MuJoCo's convex primitives and convex meshes. The floor holds the
  /// points below it.
  int worldGeomHolding(const Vec3& p_world) const;

  /// The first geom the segment from `from_world` to `to_world` meets, the last `stop` metres before `to_world`
  /// left out (the SMR's own radius: its centre sits that far from the surface it rests on); -1 when none.
  int blocker(const Vec3& from_world, const Vec3& to_world, double stop) const;

  /// "geom 'NAME' of body 'BODY'" (unnamed: "geom N"); the floor: "the floor".
  std::string geomText(int geom) const;
  /// The body of `geom` as CollisionChecker::bodyName names it ("floor" for the floor).
  std::string geomBody(int geom) const;

 private:
  const CollisionChecker& checker_;
};

}  // namespace lowpair::mujoco
