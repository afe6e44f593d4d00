#include "mujoco/compliant_actual.hpp"

#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace lowpair::mujoco {

namespace {

// Central-difference step of the Newton Jacobian (rad or metres): the Jacobian only steers the iteration
// (the residual decides convergence), and h^2 times the third derivative is far below its size.
constexpr double kJacobianStep = 1e-6;
// Step halvings before an iteration gives up.
constexpr int kMaxHalvings = 40;

double maxRelative(const VecX& r, const VecX& k) { return r.size() ? r.cwiseQuotient(k).cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

void CompliantActual::ModelDeleter::operator()(mjModel_* m) const { mj_deleteModel(m); }

CompliantActual::CompliantActual(const MujocoDynamics& dynamics, const VecX& stiffness)
    : dynamics_(&dynamics),
      model_(mj_copyModel(nullptr, dynamics.model())),
      data_(mj_makeData(model_.get()), mj_deleteData),
      tip_(dynamics.robot()) {
  const MujocoRobot& robot = dynamics.robot();
  if (stiffness.size() != robot.dof()) {
    throw std::invalid_argument("stiffness: expected " + std::to_string(robot.dof()) + " values (one per joint), got " +
                                std::to_string(stiffness.size()));
  }
  mjModel* m = model_.get();
  m->opt.disableflags &= ~mjDSBL_PASSIVE;  // the springs are passive forces
  k_ = VecX::Zero(robot.dof());
  for (Eigen::Index i = 0; i < stiffness.size(); ++i) {
    const double k = stiffness[i];
    if (!(k >= 0)) {
      throw std::invalid_argument("stiffness of joint " + std::to_string(i + 1) +
                                  ": expected >= 0 (0 or inf: rigid), got " + std::to_string(k));
    }
    const MujocoJoint& j = robot.joints()[static_cast<size_t>(i)];
    const bool compliant = k > 0 && std::isfinite(k);
    m->jnt_stiffness[m->dof_jntid[j.dof]] = compliant ? k : 0.0;
    if (j.slide_dof >= 0) m->jnt_stiffness[m->dof_jntid[j.slide_dof]] = 0.0;  // the slide follows the hinge
    k_[i] = k;
    if (compliant) compliant_.push_back(i);
  }
}

CompliantActual::~CompliantActual() = default;

VecX CompliantActual::residual(const VecX& x) {
  const mjModel* m = model_.get();
  mjData* d = data_.get();
  setChainConfiguration(dynamics_->robot(), m, d, x);
  mj_fwdPosition(m, d);
  mj_fwdVelocity(m, d);
  const VecX bias = chainForce(dynamics_->robot(), d->qfrc_bias);
  const VecX passive = chainForce(dynamics_->robot(), d->qfrc_passive);
  VecX r(static_cast<Eigen::Index>(compliant_.size()));
  for (size_t c = 0; c < compliant_.size(); ++c) {
    r[static_cast<Eigen::Index>(c)] = bias[compliant_[c]] - passive[compliant_[c]];
  }
  return r;
}

MatX CompliantActual::residualJacobian(const VecX& x) {
  const Eigen::Index n = static_cast<Eigen::Index>(compliant_.size());
  MatX J(n, n);
  for (Eigen::Index c = 0; c < n; ++c) {
    VecX plus = x, minus = x;
    plus[compliant_[static_cast<size_t>(c)]] += kJacobianStep;
    minus[compliant_[static_cast<size_t>(c)]] -= kJacobianStep;
    J.col(c) = (residual(plus) - residual(minus)) / (2 * kJacobianStep);
  }
  return J;
}

Equilibrium CompliantActual::settle(const Eigen::Ref<const VecX>& x_commanded) {
  const MujocoRobot& robot = dynamics_->robot();
  if (x_commanded.size() != robot.dof()) {
    throw std::invalid_argument("settle: expected " + std::to_string(robot.dof()) + " joint values, got " +
                                std::to_string(x_commanded.size()));
  }
  mjModel* m = model_.get();
  for (size_t i = 0; i < robot.joints().size(); ++i) {  // the springs' rest: the commanded configuration
    const int qpos = robot.joints()[i].qpos;
    m->qpos_spring[qpos] = m->qpos0[qpos] + x_commanded[static_cast<Eigen::Index>(i)];
  }
  VecX k_c(static_cast<Eigen::Index>(compliant_.size()));
  for (size_t c = 0; c < compliant_.size(); ++c) k_c[static_cast<Eigen::Index>(c)] = k_[compliant_[c]];

  Equilibrium eq;
  eq.x = x_commanded;
  VecX r = residual(eq.x);
  double size = maxRelative(r, k_c);
  while (size > kSettleTolerance && eq.iterations < kMaxSettleIterations) {
    const VecX step = residualJacobian(eq.x).partialPivLu().solve(-r);
    if (!step.allFinite()) break;
    ++eq.iterations;
    bool improved = false;
    double t = 1.0;
    for (int h = 0; h <= kMaxHalvings && !improved; ++h, t /= 2) {
      VecX x_try = eq.x;
      for (size_t c = 0; c < compliant_.size(); ++c) x_try[compliant_[c]] += t * step[static_cast<Eigen::Index>(c)];
      const VecX r_try = residual(x_try);
      const double size_try = maxRelative(r_try, k_c);
      if (size_try < size || size_try <= kSettleTolerance) {
        eq.x = x_try;
        r = r_try;
        size = size_try;
        improved = true;
      }
    }
    if (!improved) break;
  }
  eq.residual = size;
  eq.converged = size <= kSettleTolerance;
  if (!compliant_.empty()) {
    const MatX J = residualJacobian(eq.x);
    const MatX symmetric = (J + J.transpose()) / 2;
    eq.stable = Eigen::SelfAdjointEigenSolver<MatX>(symmetric, Eigen::EigenvaluesOnly).eigenvalues().minCoeff() > 0;
  }
  eq.T_base_tip = tip_.tipPose(eq.x);
  return eq;
}

}  // namespace lowpair::mujoco
