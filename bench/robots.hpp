#pragma once
// The benchmark robots as plain data (no Eigen at this interface: the KDL translation unit includes it
// and must not share Eigen code with the rest, see README.md). Built once by robots.cpp: the bundled
// robots from models/, the user's robot (BENCH_ROBOT, `lowpair_bench --robot=FILE`) from its file.
#include <cmath>
#include <string>
#include <vector>

namespace lowpair_bench {

enum class RobotId { Puma560, Stanford, Panda, User };
constexpr RobotId kRobots[] = {RobotId::Puma560, RobotId::Stanford, RobotId::Panda};  // the bundled ones
constexpr int kRobotIds = 4;  // caches indexed by RobotId

// The last part of a bundled robot's benchmark names, BM_<Area>_<Impl>_<Name>. (Registration must not
// load the robot to learn it; the user robot's is robotCase(RobotId::User).name, loaded before.)
inline const char* bundledName(RobotId id) {
  return id == RobotId::Puma560 ? "Puma560" : id == RobotId::Stanford ? "Stanford" : "Panda";
}

constexpr int kPool = 1024;  // configurations cycled through, one per iteration

// One D-H row (standard: Rz(theta) Tz(d) Rx(alpha) Tx(a), or modified: Rx(alpha) Tx(a) Rz(theta) Tz(d)).
struct DhRow {
  double theta, d, alpha, a;
};

struct RobotCase {
  std::string name;      // "Puma560", "Stanford", "Panda"; the user's: its name: (or file stem) in CamelCase
  std::string mjcf;      // models/*.xml, site "tool"; the user's: <stem>.xml beside its file (if it exists)
  int dof = 0;
  double size = 1.0;     // robot size L
  std::vector<int> prismatic;  // 1 if joint i is prismatic
  std::vector<double> q;       // kPool x dof, seeded random configurations within the joint ranges
  std::vector<double> pose;    // kPool x 12, library POE FK: R row-major, then p
  std::vector<double> jac;     // kPool x 6 x dof, library geometric Jacobian [v; w], row-major
  // The peers' joint values of the pool, kPool x dof: the motions x = scale (q + offset) of the POE joints
  // (MuJoCo's qpos - qpos0) and of the D-H joints (KDL's; a POE file's offsets are folded into its D-H table).
  std::vector<double> x_mujoco, x_kdl;
  // Per joint, dx/dq = scale of those motions: the peers' Jacobian columns are d/dx, the library's d/dq.
  std::vector<double> scale_mujoco, scale_kdl;
  std::string kdl_unsupported;  // why KDL cannot hold the chain (a helical joint), "" when it can
  // KDL chains. Standard D-H (PUMA, Stanford from their robot files, a user's D-H file): base row, joint
  // rows (theta includes the joint's constant; the joint variable adds to theta or d), tool (theta, d).
  // Panda, a user's POE file: modified D-H export of the POE model (use_modified = true).
  bool use_modified = false;
  DhRow base{};
  std::vector<DhRow> rows;
  DhRow tool{};  // standard: {theta_T, d_T, 0, 0}; modified: {theta_T, d_T, alpha_n, a_n}
  double base_theta = 0, base_d = 0;  // modified: Rz(theta_B) Tz(d_B)
};

const RobotCase& robotCase(RobotId id);

// Reads the user's robot file (a lowpair POE or D-H robot file, .yaml) as RobotId::User and builds its
// case. Call once, before registering benchmarks. Throws std::exception whose message starts with
// `path: ` (an MJCF or URDF, an unreadable or invalid file).
void loadUserRobot(const std::string& path);

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
