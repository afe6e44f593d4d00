// A laser tracker's line of sight, by MuJoCo's ray casting (line_of_sight.hpp).
#include "mujoco/line_of_sight.hpp"

#include <mujoco/mujoco.h>

namespace lowpair::mujoco {

namespace {

// mj_ray's distance from `p` along `v` to geom g alone (-1 when the ray misses it).
double rayToGeom(const mjModel* m, const mjData* d, int g, const mjtNum p[3], const mjtNum v[3]) {
  if (m->geom_type[g] == mjGEOM_MESH) return mj_rayMesh(m, d, g, p, v);
  if (m->geom_type[g] == mjGEOM_HFIELD) return mj_rayHfield(m, d, g, p, v);
  return mju_rayGeom(d->geom_xpos + 3 * g, d->geom_xmat + 9 * g, m->geom_size + 3 * g, p, v, m->geom_type[g]);
}

}  // namespace

Pose LineOfSight::T_world_base() const {
  const mjData* d = checker_.data();
  const int b = checker_.robot().baseBody();
  Pose T;
  for (int r = 0; r < 3; ++r) {
    T.p[r] = d->xpos[3 * b + r];
    for (int c = 0; c < 3; ++c) T.R(r, c) = d->xmat[9 * b + 3 * r + c];  // row-major
  }
  return T;
}

int LineOfSight::worldGeomHolding(const Vec3& p_world) const {
  const mjModel* m = checker_.model();
  const mjData* d = checker_.data();
  const mjtNum p[3] = {p_world[0], p_world[1], p_world[2]};
  const mjtNum up[3] = {0, 0, 1}, down[3] = {0, 0, -1};
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->body_weldid[m->geom_bodyid[g]] != 0) continue;  // moving geoms: judged by each candidate's rays
    if (m->geom_type[g] == mjGEOM_PLANE) {
      // below the plane: its local z (the plane's normal, column 2 of the row-major frame) is negative
      const double* x = d->geom_xpos + 3 * g;
      const double* R = d->geom_xmat + 9 * g;
      if ((p[0] - x[0]) * R[2] + (p[1] - x[1]) * R[5] + (p[2] - x[2]) * R[8] < 0.0) return g;
      continue;
    }
    if (rayToGeom(m, d, g, p, up) >= 0.0 && rayToGeom(m, d, g, p, down) >= 0.0) return g;
  }
  return -1;
}

int LineOfSight::blocker(const Vec3& from_world, const Vec3& to_world, double stop) const {
  const Vec3 v = to_world - from_world;
  const double length = v.norm();
  if (!(length > stop)) return -1;  // the tracker within the SMR's radius: nothing between them
  const mjtNum p[3] = {from_world[0], from_world[1], from_world[2]};
  const mjtNum vec[3] = {v[0], v[1], v[2]};
  int geom = -1;
  // flg_static 1: the world's geometry blocks too; bodyexclude -1: nothing excluded (the SMR is no geom)
  const double x = mj_ray(checker_.model(), checker_.data(), p, vec, nullptr, 1, -1, &geom);
  // x is in units of |v|: the ray is blocked when it meets a geom before the SMR's surface
  return x >= 0.0 && x * length < length - stop ? geom : -1;
}

std::string LineOfSight::geomBody(int geom) const {
  if (geom == checker_.floorGeom()) return "floor";
  return checker_.bodyName(checker_.model()->geom_bodyid[geom]);
}

std::string LineOfSight::geomText(int geom) const {
  if (geom == checker_.floorGeom()) return "the floor";
  const char* name = mj_id2name(checker_.model(), mjOBJ_GEOM, geom);
  return (name && *name ? "geom '" + std::string(name) + "'" : "geom " + std::to_string(geom)) + " of body '" +
         geomBody(geom) + "'";
}

}  // namespace lowpair::mujoco
