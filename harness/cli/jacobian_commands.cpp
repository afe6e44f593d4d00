// jacobian, singular (design.md "The lowpair command line"; Paden & Sastry 1984).
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "lowpair/tolerances.hpp"
#include "io/output.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below

using nlohmann::json;

namespace {

// A number for JSON: non-finite values (an infinite condition number) become null.
json number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

// Null vectors printed (text and JSON) at most: a robot of up to 6 joints, or any rank loss of a 6-joint
// arm, is printed in full; beyond that the basis is the self-motion of a redundant chain, n numbers per
// vector, and the rest is counted, not printed (10,000 joints would print ~1 GB).
constexpr int kPrintedNullVectors = 6;

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
std::string classDescription(const SingularClass& c) {
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

json singularJson(const RobotFile& file, const VecX& q, const SingularityReport& r) {
  json classes = json::array();
  for (const SingularClass& c : r.classes) {
    classes.push_back({{"class", c.id}, {"joints", c.joints}, {"description", classDescription(c)}});
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
          {"size", r.size},
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

void printSingular(std::ostream& out, const RobotFile& file, const SingularityReport& r) {
  auto sci = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3e", x);
    return std::string(buf);
  };
  out << robotLabel(file) << ": " << (r.singular ? "SINGULAR" : "regular") << ", rank " << r.rank << " of "
      << std::min(6, r.dof) << " (" << r.dof << " joints; linear " << r.rank_linear << ", angular "
      << r.rank_angular << ")\n";
  out << "  dimensionless Jacobian (linear rows / L, L = " << fixed(r.size) << " " << file.length_unit
      << "): sigma_min " << sci(r.sigma_min) << ", manipulability " << sci(r.manipulability) << ", condition "
      << (std::isfinite(r.condition) ? sci(r.condition) : std::string("inf")) << ", rank tolerance "
      << sci(r.tolerance) << "\n";
  out << "  singular values:";
  for (Eigen::Index k = 0; k < r.singular_values.size(); ++k) out << " " << sci(r.singular_values(k));
  out << "\n";
  if (!r.classes_searched) {
    out << "  classes: not searched (" << r.dof << " joints; the class search takes at most " << kClassSearchMaxJoints
        << ")\n";
  }
  for (const SingularClass& c : r.classes) out << "  " << c.id << ": " << classDescription(c) << "\n";
  if (r.decoupled.applies) {
    const auto& d = r.decoupled;
    out << "  decoupled (Paden-Sastry 5): wrist joints " << d.wrist_joints[0] << ", " << d.wrist_joints[1] << ", "
        << d.wrist_joints[2] << " -> wrist " << (d.wrist_singular ? "SINGULAR" : "regular") << " (sigma_min "
        << sci(d.wrist_sigma_min) << "), arm " << (d.arm_singular ? "SINGULAR" : "regular") << " (sigma_min "
        << sci(d.arm_sigma_min) << ")\n";
  } else {
    out << "  decoupled (Paden-Sastry 5): no three consecutive revolute axes meet in a point\n";
  }
  for (const VecX& x : r.null_space) {
    out << (r.singular ? "  null vector" : "  self-motion (null vector)") << " (unit-screw coefficients):";
    for (Eigen::Index i = 0; i < x.size(); ++i) out << " " << fixed(x(i), 6);
    out << "\n";
  }
  const int omitted = r.nullity - static_cast<int>(r.null_space.size());
  if (omitted > 0) {
    out << "  (" << omitted << " more null vectors not printed: the null space has dimension " << r.nullity << ")\n";
  }
}

}  // namespace

void addJacobianCommands(CLI::App& app, Commands& commands) {
  struct Options {
    RobotSource robot;
    std::string q_text, frame = "spatial";
    bool as_json = false;
  };
  auto o = std::make_shared<Options>();

  auto* jac = app.add_subcommand("jacobian", "manipulator Jacobian at q (spatial/body [w; v], geometric [v; w])");
  addRobotArgument(*jac, o->robot);
  jac->add_option("--q", o->q_text, "joint values Q1,Q2,... (rad for revolute/helical, length for prismatic)")
      ->required();
  jac->add_option("--frame", o->frame,
                  "spatial ([w; v] in the base frame), body ([w; v] in the tool frame) or geometric "
                  "(Paden-Sastry eq. 3.13: [v; w], v = tool-origin velocity, base coordinates)")
      ->check(CLI::IsMember({"spatial", "body", "geometric"}));
  jac->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(jac, [o] {
    const RobotFile file = loadRobot(o->robot);
    const VecX q = parseJointVector(o->q_text, file.dof(), o->robot.path);
    const PoeModel model = file.poeModel();
    Data data(model);
    Mat6X J(6, model.dof());
    computeJacobians(model, data, q);
    if (o->frame == "spatial") getSpatialJacobian(data, J);
    if (o->frame == "body") getBodyJacobian(data, J);
    if (o->frame == "geometric") getGeometricJacobian(data, J);
    const bool geometric = o->frame == "geometric";
    if (o->as_json) {
      json rows = json::array();
      for (int r = 0; r < 6; ++r) rows.push_back(toVector(J.row(r).transpose()));
      json j = {{"name", file.name},
                {"source", file.path},
                {"frame", o->frame},
                {"rows", geometric ? "[v; w]" : "[w; v]"},
                {"length_unit", file.length_unit},
                {"q", toVector(q)},
                {"jacobian", rows}};
      std::cout << jsonText(j) << "\n";
    } else {
      std::cout << o->frame << " Jacobian of " << robotLabel(file) << " (rows "
                << (geometric ? "[v; w]" : "[w; v]") << ", angular in rad, linear in "
                << (file.length_unit.empty() ? "length" : file.length_unit) << ", per unit joint variable):\n";
      const char* names[2][6] = {{"wx", "wy", "wz", "vx", "vy", "vz"}, {"vx", "vy", "vz", "wx", "wy", "wz"}};
      for (int r = 0; r < 6; ++r) {
        std::cout << "  " << names[geometric ? 1 : 0][r];
        for (int c = 0; c < J.cols(); ++c) {
          const std::string cell = fixed(J(r, c), 6);
          std::cout << std::string(cell.size() < 13 ? 13 - cell.size() : 1, ' ') << cell;
        }
        std::cout << "\n";
      }
    }
    return 0;
  });

  auto* sing = app.add_subcommand("singular", "singularity analysis at q: rank, sigma_min, classes C1..C7, wrist/arm split");
  addRobotArgument(*sing, o->robot);
  sing->add_option("--q", o->q_text, "joint values Q1,Q2,... (rad for revolute/helical, length for prismatic)")
      ->required();
  sing->add_flag("--json", o->as_json, "print JSON");
  commands.emplace_back(sing, [o] {
    const RobotFile file = loadRobot(o->robot);
    const VecX q = parseJointVector(o->q_text, file.dof(), o->robot.path);
    SingularityOptions options;
    options.max_null_vectors = kPrintedNullVectors;
    const SingularityReport r = analyzeSingularity(file.poeModel(), q, options);
    if (o->as_json) {
      std::cout << jsonText(singularJson(file, q, r)) << "\n";
    } else {
      printSingular(std::cout, file, r);
    }
    return 0;
  });
}

}  // namespace lowpair::cli
