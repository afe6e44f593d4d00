#include "lowpair/gravity.hpp"

#include <cmath>

#include "check.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

namespace {

void checkPointMass(const PointMass& m, const char* what, int index) {
  LP_CHECK(std::isfinite(m.mass) && m.mass >= 0.0,
           "gravityTorques: " << what << (index >= 0 ? " " + std::to_string(index + 1) : std::string())
                              << ": mass " << m.mass << " (must be finite and >= 0)");
  LP_CHECK(m.com.allFinite(), "gravityTorques: " << what << (index >= 0 ? " " + std::to_string(index + 1) : std::string())
                                                 << ": centre of mass not finite");
}

}  // namespace

void checkMassModel(const MassModel& masses, int dof) {
  LP_CHECK(masses.links.empty() || static_cast<int>(masses.links.size()) == dof,
           "gravityTorques: " << masses.links.size() << " link masses for " << dof << " joints (0 or one per joint)");
  for (size_t i = 0; i < masses.links.size(); ++i) checkPointMass(masses.links[i], "link", static_cast<int>(i));
  checkPointMass(masses.payload, "payload", -1);
  LP_CHECK(masses.gravity.allFinite(), "gravityTorques: gravity not finite");
  LP_CHECK(std::isfinite(masses.metres_per_unit) && masses.metres_per_unit > 0.0,
           "gravityTorques: metres_per_unit " << masses.metres_per_unit << " (must be positive and finite)");
}

VecX gravityTorques(const PoeModel& model, const MassModel& masses, const Eigen::Ref<const VecX>& q) {
  const int n = model.dof();
  checkJointVector(q, n);
  checkMassModel(masses, n);
  // P[i] = exp(xi_1 x_1) ... exp(xi_i x_i); joint i's twist at q is Ad(P[i-1]) xi_i
  std::vector<Pose> P(static_cast<size_t>(n) + 1);
  Pose E;
  for (int i = 0; i < n; ++i) {
    jointExp(model.joint(i), q[i], E);
    P[static_cast<size_t>(i) + 1] = P[static_cast<size_t>(i)] * E;
  }
  // the wrench of the gravity forces on links i..n and the payload about the base origin, from the tip back:
  // moment (N x length unit) and force (N)
  const Pose T_tool = P[static_cast<size_t>(n)] * model.toolPose();
  Vec3 force = masses.payload.mass * masses.gravity;
  Vec3 moment = (T_tool.R * masses.payload.com + T_tool.p).cross(force);
  VecX tau(n);
  for (int i = n - 1; i >= 0; --i) {
    if (!masses.links.empty()) {
      const PointMass& link = masses.links[static_cast<size_t>(i)];
      const Vec3 f = link.mass * masses.gravity;
      moment += (P[static_cast<size_t>(i) + 1] * link.com).cross(f);
      force += f;
    }
    const Joint& j = model.joint(i);
    const Vec6 xi = adjointApply(P[static_cast<size_t>(i)], j.twist);
    // the power of the forces per unit of motion: w.M + v.f (N x length unit for turning joints, N for sliding)
    const double power = xi.head<3>().dot(moment) + xi.tail<3>().dot(force);
    const double per_unit = j.type == JointType::Prismatic ? 1.0 : masses.metres_per_unit;
    tau[i] = j.scale * power * per_unit;
  }
  return tau;
}

}  // namespace lowpair
