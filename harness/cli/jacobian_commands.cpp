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
#include "io/singularity_output.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below

using nlohmann::json;

namespace {

void printSingular(std::ostream& out, const RobotFile& file, const SingularityReport& r) {
  auto sci = [](double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3e", x);
    return std::string(buf);
  };
  out << robotLabel(file) << ": " << (r.singular ? "SINGULAR" : "regular") << ", rank " << r.rank << " of "
      << std::min(6, r.dof) << " (" << r.dof << " joints; linear " << r.rank_linear << ", angular "
      << r.rank_angular << ")\n";
  out << "  dimensionless Jacobian (linear rows / L, L = " << fixed(r.length_scale) << " " << file.length_unit
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
  for (const SingularClass& c : r.classes) out << "  " << c.id << ": " << singularClassText(c) << "\n";
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
    const RobotFile file = loadRobot(o->robot, cliSpelling());
    const VecX q = parseJointVector(o->q_text, file, o->robot.path);
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
    const RobotFile file = loadRobot(o->robot, cliSpelling());
    const VecX q = parseJointVector(o->q_text, file, o->robot.path);
    SingularityOptions options;
    options.max_null_vectors = kPrintedNullVectors;
    options.validate();
    const SingularityReport r = analyzeSingularity(file.poeModel(), q, options);
    if (o->as_json) {
      std::cout << jsonText(singularityJson(file, q, r)) << "\n";
    } else {
      printSingular(std::cout, file, r);
    }
    return 0;
  });
}

}  // namespace lowpair::cli
