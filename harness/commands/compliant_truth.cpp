#include "commands/compliant_truth.hpp"

#include <cmath>
#include <sstream>

#include "io/output.hpp"
#include "mujoco/compliant_actual.hpp"
#include "mujoco/messages.hpp"
#include "mujoco/mujoco_dynamics.hpp"

namespace lowpair::commands {

namespace {

std::string joined(const VecX& v) {
  std::string s;
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? "," : "") + io::shortest(v[i]);
  return s;
}

}  // namespace

CompliantTruth compliantTruth(std::shared_ptr<const mujoco::MujocoRobot> robot, const std::vector<double>& stiffness,
                              const ArgumentSpelling& spelling) {
  const std::string subject = spelling.name("stiffness");
  if (static_cast<int>(stiffness.size()) != robot->dof()) {
    throw UsageError(subject, "expected " + std::to_string(robot->dof()) + " values (one per joint of the chain), got " +
                                  std::to_string(stiffness.size()));
  }
  VecX k(robot->dof());
  for (size_t i = 0; i < stiffness.size(); ++i) {
    if (!(stiffness[i] >= 0) || !std::isfinite(stiffness[i])) {
      throw UsageError(subject, "joint " + std::to_string(i + 1) + ": expected a finite stiffness >= 0 (0: rigid), got " +
                                    io::shortest(stiffness[i]));
    }
    k[static_cast<Eigen::Index>(i)] = stiffness[i];
  }
  auto dynamics = std::make_shared<const mujoco::MujocoDynamics>(*robot);
  if (dynamics->masses().status != mujoco::MassStatus::Ok) {
    throw io::RobotFileError(mujoco::massProblem(dynamics->masses(), robot->path()));
  }
  if (dynamics->masses().masses.gravity == Vec3::Zero()) {
    mujoco::emitNote(robot->path() + ": the model's gravity is zero (<option gravity>): with --stiffness every pose "
                     "rests where it is commanded");
  }
  auto actual = std::make_shared<mujoco::CompliantActual>(*dynamics, k);
  CompliantTruth truth;
  // robot and dynamics live as long as the function (actual points into both)
  truth.tipPose = [robot, dynamics, actual, subject](const VecX& x) {
    const mujoco::Equilibrium eq = actual->settle(x);
    if (!eq.converged || !eq.stable) {
      throw UsageError(subject, std::string(eq.converged ? "the rest is unstable" : "no rest found") + " at x = [" +
                                    joined(x) + "] (residual " + io::shortest(eq.residual) + " after " +
                                    std::to_string(eq.iterations) + " iterations): the joints are too soft to hold "
                                    "the robot against gravity");
    }
    return eq.T_base_tip;
  };
  const Vec3& g = dynamics->masses().masses.gravity;
  truth.description = "compliance: each pose where the robot rests under gravity with joint stiffness [" + joined(k) +
                      "] (N m/rad, N/m for a prismatic joint, per unit of MuJoCo's motion; 0 rigid), the masses and "
                      "gravity [" + joined(g) + "] m/s^2 of " + robot->path() + " (MuJoCo)";
  return truth;
}

}  // namespace lowpair::commands
