#pragma once
// The benchmark robots as plain data (no Eigen at this interface: the KDL translation unit includes it
// and must not share Eigen code with the rest, see README.md). Built once from models/ by robots.cpp.
#include <cmath>
#include <string>
#include <vector>

namespace lowpair_bench {

enum class RobotId { Puma560, Stanford, Panda };
constexpr RobotId kRobots[] = {RobotId::Puma560, RobotId::Stanford, RobotId::Panda};

constexpr int kPool = 1024;  // configurations cycled through, one per iteration

// One D-H row (standard: Rz(theta) Tz(d) Rx(alpha) Tx(a), or modified: Rx(alpha) Tx(a) Rz(theta) Tz(d)).
struct DhRow {
  double theta, d, alpha, a;
};

struct RobotCase {
  std::string name;      // "Puma560", "Stanford", "Panda"
  std::string mjcf;      // models/*.xml, site "tool"
  int dof = 0;
  double size = 1.0;     // robot size L
  std::vector<int> prismatic;  // 1 if joint i is prismatic
  std::vector<double> q;       // kPool x dof, seeded random configurations within the joint ranges
  std::vector<double> pose;    // kPool x 12, library POE FK: R row-major, then p
  std::vector<double> jac;     // kPool x 6 x dof, library geometric Jacobian [v; w], row-major
  // KDL chains. Standard D-H (PUMA, Stanford from their robot files): base row, joint rows
  // (theta includes the joint's constant; the joint variable adds to theta or d), tool (theta, d).
  // Panda: modified D-H export of its POE model (use_modified = true).
  bool use_modified = false;
  DhRow base{};
  std::vector<DhRow> rows;
  DhRow tool{};  // standard: {theta_T, d_T, 0, 0}; modified: {theta_T, d_T, alpha_n, a_n}
  double base_theta = 0, base_d = 0;  // modified: Rz(theta_B) Tz(d_B)
};

const RobotCase& robotCase(RobotId id);

// Largest pose difference (rotation entries and position / size) between `pose12` and the library's
// pose of configuration k, in units of the robot size (1e-12 is the acceptance threshold).
// (Inline: the KDL library uses them too.)
inline double poseMismatch(const RobotCase& robot, int k, const double* pose12) {
  const double* ref = &robot.pose[static_cast<size_t>(k) * 12];
  double err = 0.0;
  for (int e = 0; e < 12; ++e) {
    const double d = std::abs(pose12[e] - ref[e]) / (e < 9 ? 1.0 : robot.size);
    err = d > err || std::isnan(d) ? (std::isnan(d) ? INFINITY : d) : err;
  }
  return err;
}
// Rows v (length, divided by the size) then w (rad) of a row-major 6 x dof geometric Jacobian.
inline double jacobianMismatch(const RobotCase& robot, int k, const double* J) {
  const size_t n = static_cast<size_t>(robot.dof);
  const double* ref = &robot.jac[static_cast<size_t>(k) * 6 * n];
  double err = 0.0;
  for (size_t e = 0; e < 6 * n; ++e) {
    const double d = std::abs(J[e] - ref[e]) / (e < 3 * n ? robot.size : 1.0);
    err = d > err || std::isnan(d) ? (std::isnan(d) ? INFINITY : d) : err;
  }
  return err;
}

constexpr double kAgree = 1e-12;

}  // namespace lowpair_bench
