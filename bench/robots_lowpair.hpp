#pragma once
// The benchmark robots as lowpair models (Eigen side of robots.hpp).
#include "lowpair/model.hpp"
#include "robots.hpp"

namespace lowpair_bench {

struct RobotModels {
  lowpair::PoeModel poe;
  lowpair::DhModel dh;  // the robot file's D-H table, or poeToDh of its POE model (Panda)
};

const RobotModels& robotModels(RobotId id);

// Geometric Jacobian [v; w] at the tool origin (Paden-Sastry eq. 3.13), 6 x dof. Uses the library's
// geometricJacobian when lowpair/jacobian.hpp exists, else the same formula from the POE FK prefixes.
void referenceGeometricJacobian(const lowpair::PoeModel& model, const double* q, double* jac_rowmajor);

}  // namespace lowpair_bench
