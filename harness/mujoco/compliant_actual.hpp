#pragma once
/// @file compliant_actual.hpp
/// A compliant "actual" robot (issue 27; docs/validation.md "A compliant actual robot"): the MuJoCo robot
/// with a spring in each joint, at rest under gravity. The ground truth of joint compliance for a
/// calibration with `--compliance`.
///
/// Joint i commanded to x_i (the motion variable of MujocoRobot's POE model: rad, or metres for a
/// prismatic joint) with stiffness k_i (N m/rad, or N/m) comes to rest at x_eq with
///     k_i (x_eq,i - x_i) = G_i(x_eq)        for each compliant joint (0 < k_i < inf),
///     x_eq,i = x_i                          for each rigid one (k_i = 0 or inf),
/// G the generalized gravity force of MuJoCo's model with the masses (MujocoDynamics), every joint outside
/// the chain held at qpos0. The equation is MuJoCo's force balance at zero velocity: the model copy here has
/// `jnt_stiffness` = k_i and `qpos_spring` = qpos0 + x (a helical joint's spring on its hinge, its slide
/// following), and the residual is `qfrc_bias - qfrc_passive` on the chain's joint variables (mj_fwdPosition,
/// mj_fwdVelocity). Solved by Newton's method (Jacobian by central differences of that residual, step halved
/// until the residual shrinks) rather than by stepping MuJoCo with damping: a static equilibrium needs no
/// dynamics, Newton reaches it to rounding in a few iterations (the springs dominate: the Jacobian is near
/// diag(k)), its residual is the stopping test, and stepping would add the integrator's and the
/// equality constraint's (helical joints) softness and a settling time to choose.

#include <memory>

#include "mujoco/mujoco_dynamics.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::mujoco {

/// At most this many Newton iterations (each 2 n + 1 force evaluations); far more than the 2..5 a stiff
/// robot needs.
constexpr int kMaxSettleIterations = 50;
/// Converged when every compliant joint's residual force over its stiffness, |k_i (x_eq,i - x_i) -
/// G_i| / k_i, is at most this (rad or metres): a thousand times the rounding of `qpos0 + x` near pi
/// (4.4e-16), far below any deflection a calibration resolves.
constexpr double kSettleTolerance = 1e-12;

/// Where a compliant robot comes to rest.
struct Equilibrium {
  VecX x;                  ///< x_eq, the joints' motion at rest
  Pose T_base_tip;         ///< the tip pose at x_eq (MujocoRobot's tip and base)
  int iterations = 0;      ///< Newton iterations taken (0: every joint rigid, or no gravity load)
  double residual = 0.0;   ///< max over compliant joints of |k_i (x_eq,i - x_i) - G_i(x_eq)| / k_i
  bool converged = false;  ///< residual <= kSettleTolerance within kMaxSettleIterations
  bool stable = true;      ///< the stiffness matrix diag(k) - dG/dx is positive definite at x_eq
};

class CompliantActual {
 public:
  /// @param stiffness one per joint of dynamics.robot(): > 0 (N m/rad or N/m), 0 or +inf for a rigid joint
  /// @throws std::invalid_argument for a wrong count, a negative or NaN stiffness
  CompliantActual(const MujocoDynamics& dynamics, const VecX& stiffness);
  ~CompliantActual();
  CompliantActual(const CompliantActual&) = delete;
  CompliantActual& operator=(const CompliantActual&) = delete;

  const VecX& stiffness() const { return k_; }
  /// The rest configuration for commanded motion `x` (not thread-safe: one CompliantActual per thread).
  /// Non-convergence and instability are returned as data (converged, stable).
  /// @throws std::invalid_argument if x.size() != dof
  Equilibrium settle(const Eigen::Ref<const VecX>& x);

 private:
  VecX residual(const VecX& x);  // qfrc_bias - qfrc_passive on the compliant joints
  MatX residualJacobian(const VecX& x);
  struct ModelDeleter {
    void operator()(mjModel_* m) const;
  };
  const MujocoDynamics* dynamics_;
  std::unique_ptr<mjModel_, ModelDeleter> model_;  // the masses' model with the springs
  std::unique_ptr<mjData_, void (*)(mjData_*)> data_;
  MujocoRobot::Evaluator tip_;
  VecX k_;
  std::vector<Eigen::Index> compliant_;  // joints with 0 < k < inf
};

}  // namespace lowpair::mujoco
