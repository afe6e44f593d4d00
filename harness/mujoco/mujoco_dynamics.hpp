#pragma once
/// @file mujoco_dynamics.hpp
/// The masses of a MuJoCo robot and MuJoCo's static gravity load on its chain (issue 27; docs/models.md
/// "Masses from a model file").
///
/// MujocoDynamics loads the robot's file a second time through a ModelCopy that keeps the `<inertial>`
/// elements (CopyContent::Inertials; the kinematics copy of MujocoRobot drops them). Both copies hold the
/// same bodies, joints and sites in the same order, so MujocoRobot's joint addresses and ids apply to it
/// (checked on construction).
///
/// Mass model (lowpair::MassModel, gravity.hpp), read at qpos0, the configuration MujocoRobot extracts the
/// POE at (the library's reference configuration, every motion x = 0):
///   - link i: every body that joint i moves and joint i+1 does not, i.e. each body whose nearest ancestor
///     (or itself) carrying a chain joint carries joint i (on a body with several chain joints, the last);
///     so the bodies beyond the tip, fixed to it or moved by joints outside the chain (held at qpos0), are
///     lumped into the last link. Its mass is the sum of MuJoCo's `body_mass`, its centre of mass the
///     mass-weighted mean of `xipos` at qpos0, in the base frame (zero for a massless link).
///   - gravity: `opt.gravity` in the base frame; zero when the model disables gravity (`<flag gravity=
///     "disable">`); `metres_per_unit` 1 (MuJoCo's lengths are metres); no payload.
/// A model has no mass model (status, masses empty) when no body the chain moves weighs more than the
/// copy's mass bound (1e-6 kg: the file has no `<inertial>` there, or zero masses), or when a body the
/// chain moves takes its mass from geoms (ModelCopy::massFromGeoms), which the copy drops.

#include <memory>
#include <string>
#include <vector>

#include "lowpair/gravity.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::mujoco {

/// Why a model file gives no mass model.
enum class MassStatus {
  Ok,             ///< masses read
  NoInertials,    ///< no body the chain moves weighs more than the mass bound
  MassFromGeoms,  ///< bodies the chain moves take their mass from their geoms (named in `bodies`)
};

/// The masses of a MuJoCo robot's chain.
struct ModelMasses {
  MassModel masses{};               ///< empty unless status is Ok
  MassStatus status = MassStatus::Ok;
  std::vector<std::string> bodies;  ///< MassFromGeoms: the bodies (ModelCopy::massFromGeoms' spelling)
};

/// The sentence a caller prints when there are no masses: "FILE: no masses: ..."; "" for status Ok.
std::string massProblem(const ModelMasses& masses, const std::string& path);

class MujocoDynamics {
 public:
  /// Loads `robot.path()` keeping the inertials and reads the mass model.
  /// @throws io::RobotFileError ("FILE: what") when the file no longer loads or its copies differ
  explicit MujocoDynamics(const MujocoRobot& robot);
  ~MujocoDynamics();
  MujocoDynamics(const MujocoDynamics&) = delete;
  MujocoDynamics& operator=(const MujocoDynamics&) = delete;

  const MujocoRobot& robot() const { return *robot_; }
  /// The mass model read at construction (see the file comment).
  const ModelMasses& masses() const { return masses_; }
  /// The compiled model with the masses (MuJoCo's mjModel; CompliantActual copies it).
  const mjModel_* model() const { return model_.get(); }

  /// A per-thread evaluator (owns its mjData).
  class Evaluator {
   public:
    explicit Evaluator(const MujocoDynamics& dynamics);
    ~Evaluator();
    Evaluator(Evaluator&&) noexcept;
    /// MuJoCo's generalized gravity force on the library's joint variables at motion x (qpos = qpos0 + x,
    /// the helical slide at pitch * x, every other joint at qpos0, zero velocity): minus `qfrc_bias` after
    /// mj_fwdPosition and mj_fwdVelocity, a helical joint's value its hinge's plus pitch times its slide's
    /// (the chain rule of slide = pitch * x). N m/rad for a revolute or helical joint, N for a prismatic one.
    VecX gravityForce(const Eigen::Ref<const VecX>& x);

   private:
    const MujocoDynamics* dynamics_;
    std::unique_ptr<mjData_, void (*)(mjData_*)> data_;
  };

 private:
  struct ModelDeleter {
    void operator()(mjModel_* m) const;
  };
  const MujocoRobot* robot_;
  std::unique_ptr<mjModel_, ModelDeleter> model_;
  ModelMasses masses_;
};

/// Sets the chain's configuration in `d` (qpos = qpos0 + x, helical slides pitch * x, every other joint at
/// qpos0, qvel = 0) for a model with `robot`'s joint addresses. The one rule MujocoDynamics and
/// CompliantActual share (MujocoRobot::Evaluator sets the same qpos).
void setChainConfiguration(const MujocoRobot& robot, const mjModel_* m, mjData_* d, const Eigen::Ref<const VecX>& x);

/// The generalized force `f` (one per MuJoCo dof) on the library's joint variables: a helical joint's hinge
/// value plus pitch times its slide value.
VecX chainForce(const MujocoRobot& robot, const double* f);

}  // namespace lowpair::mujoco
