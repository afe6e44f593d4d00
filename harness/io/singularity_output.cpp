#include "io/singularity_output.hpp"

#include <cmath>
#include <sstream>
#include <vector>

#include "io/output.hpp"

namespace lowpair::io {

using nlohmann::json;

namespace {

// A number for JSON: non-finite values (an infinite condition number) become null.
json number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

// "4 and 6", "2, 3 and 5" (1-based joint numbers).
std::string jointList(const std::vector<int>& joints) {
  std::ostringstream out;
  for (size_t k = 0; k < joints.size(); ++k) {
    if (k > 0) out << (k + 1 == joints.size() ? " and " : ", ");
    out << joints[k];
  }
  return out.str();
}

std::string vec3Text(const Vec3& v) {
  std::ostringstream out;
  out.precision(6);
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

// One line per class (conventions.md, "Singularities"), from the class's joints and geometry.
}  // namespace

std::string singularClassText(const SingularClass& c) {
  const std::string axes = "joint axes " + jointList(c.joints);
  if (c.id == "C1") return axes + " are collinear";
  if (c.id == "C2") return axes + " are parallel and coplanar";
  if (c.id == "C3") return axes + " pass through one point " + vec3Text(c.point);
  if (c.id == "C4") return axes + " are parallel";
  if (c.id == "C5") return axes + " lie in one plane";
  if (c.id == "C6") {
    const std::string all = "all " + std::to_string(c.joints.size()) + " joint axes meet ";
    return c.at_infinity ? all + "one line at infinity: all are perpendicular to " + vec3Text(c.direction)
                         : all + "the line through " + vec3Text(c.point) + " along " + vec3Text(c.direction);
  }
  if (c.id == "C7") {
    std::vector<int> parallel;
    for (int j : c.joints) {
      if (j != c.prismatic_joint) parallel.push_back(j);
    }
    return "prismatic joint " + std::to_string(c.prismatic_joint) +
           " is normal to the plane of the parallel joint axes " + jointList(parallel);
  }
  return "the screws of joints " + jointList(c.joints) + " are linearly dependent (no listed class)";
}

nlohmann::json singularityJson(const RobotFile& file, const VecX& q, const SingularityReport& r) {
  json classes = json::array();
  for (const SingularClass& c : r.classes) {
    classes.push_back({{"class", c.id}, {"joints", c.joints}, {"description", singularClassText(c)}});
  }
  json decoupled = {{"applies", r.decoupled.applies}};
  if (r.decoupled.applies) {
    decoupled["wrist_joints"] = r.decoupled.wrist_joints;
    decoupled["wrist_point"] = toVector(r.decoupled.wrist_point);
    decoupled["arm_joints"] = r.decoupled.arm_joints;
    decoupled["wrist_singular"] = r.decoupled.wrist_singular;
    decoupled["arm_singular"] = r.decoupled.arm_singular;
    decoupled["wrist_sigma_min"] = r.decoupled.wrist_sigma_min;
    decoupled["arm_sigma_min"] = r.decoupled.arm_sigma_min;
  }
  json null_space = json::array();
  for (const VecX& x : r.null_space) null_space.push_back(toVector(x));
  return {{"name", file.name},
          {"source", file.path},
          {"q", toVector(q)},
          {"length_unit", file.length_unit},
          {"size", r.length_scale},
          {"rank", r.rank},
          {"dof", r.dof},
          {"singular", r.singular},
          {"tolerance", r.tolerance},
          {"singular_values", toVector(r.singular_values)},
          {"sigma_min", r.sigma_min},
          {"manipulability", r.manipulability},
          {"condition", number(r.condition)},
          {"rank_linear", r.rank_linear},
          {"rank_angular", r.rank_angular},
          {"classes_searched", r.classes_searched},
          {"classes", classes},
          {"decoupled", decoupled},
          {"nullity", r.nullity},
          {"null_space", null_space}};
}

}  // namespace lowpair::io
