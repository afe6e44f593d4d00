#pragma once
/// @file mujoco_robot.hpp
/// MuJoCo ground truth (the only place that includes MuJoCo): load an MJCF or a URDF through a
/// kinematics-only copy (ModelCopy, model_copy.hpp: geometry, assets, actuators, sensors... dropped, mass
/// bounds, compiler settings merged), walk the chain from the base to the tip, extract the POE model at
/// `qpos0` from MuJoCo's own world-frame joint axes and anchors, and evaluate tip poses and Jacobians at
/// configurations.
///
/// Joint mapping: hinge -> revolute, slide -> prismatic, a hinge and a slide on the same axis coupled by
/// a joint equality (`joint1` the slide, `joint2` the hinge, `polycoef="0 h 0 0 0"`) -> one helical joint
/// of pitch h. The extracted model has scale 1: its joint variable is MuJoCo's `qpos - qpos0` of the hinge
/// or slide (rad or length).
///
/// Rejected (io::RobotFileError, exit 2), naming the element: what ModelCopy rejects; free and ball joints in
/// the chain; among active equalities, a `<connect>` or `<weld>` closing a loop through a chain joint (one
/// on the tree path between its two bodies; loops elsewhere, e.g. inside a gripper beyond the tip, are
/// ignored), a `<tendon>` equality whose tendon depends on a chain joint, a `<joint>` equality driving a
/// chain joint other than as a helical slide (a locked joint, a joint of another type or outside the chain,
/// two couplings of one slide, one hinge driving two slides); a URDF chain joint with `<mimic>` (MuJoCo
/// 2.2.2 ignores it); a chain joint whose `qpos0` (ref) is not finite or too large for `qpos0 + x` to
/// resolve x (hinge: 1000 rad; slide: 1000 model lengths); anything not finite at qpos0.
/// ModelCopy's notes (what was dropped) and MuJoCo's load warnings go to stderr as `note: ` lines once the
/// model is accepted; nothing goes to stdout and MuJoCo writes no MUJOCO_LOG.TXT.

#include <memory>
#include <string>
#include <vector>

#include "io/robot_file.hpp"
#include "lowpair/model.hpp"

struct mjModel_;
struct mjData_;

namespace lowpair::mujoco {

/// One library joint in MuJoCo terms.
struct MujocoJoint {
  std::string name;
  JointType type = JointType::Revolute;
  int qpos = -1;        ///< qpos address of the hinge or slide
  int dof = -1;         ///< dof address of the hinge or slide
  int slide_qpos = -1;  ///< helical: the coupled slide's qpos address
  int slide_dof = -1;   ///< helical: the coupled slide's dof address
  double pitch = 0.0;   ///< helical: slide = pitch * hinge (length/rad)
  std::optional<std::array<double, 2>> range;  ///< from the MJCF when limited
};

class MujocoRobot {
 public:
  /// @param tip a site or body name; @param base a body name (default: the world)
  /// @throws io::RobotFileError ("FILE: what") for anything the library cannot represent.
  MujocoRobot(const std::string& path, const std::string& tip, const std::string& base = "");
  ~MujocoRobot();
  MujocoRobot(const MujocoRobot&) = delete;
  MujocoRobot& operator=(const MujocoRobot&) = delete;

  int dof() const { return static_cast<int>(joints_.size()); }
  /// The model file as given (MujocoDynamics loads it again, keeping the masses).
  const std::string& path() const { return path_; }
  /// MuJoCo ids in the loaded model (the same in any ModelCopy of the file: copies drop no body, joint or
  /// site): the body the tip is on (the tip body, or the tip site's body), the tip site (-1 for a body
  /// tip), the base body (0: the world).
  int tipBody() const;
  int tipSite() const { return tip_site_; }
  int baseBody() const { return base_body_; }
  /// The base frame seen from MuJoCo's world (inverse of the base body's pose at qpos0; fixed).
  const Pose& T_base_world() const { return T_base_world_; }
  const std::vector<MujocoJoint>& joints() const { return joints_; }
  /// The POE model extracted at qpos0 (scale 1), in the base frame.
  const PoeModel& poeModel() const { return *poe_; }
  /// The point of site `site` in the tip frame (a laser tracker's target on the tool): the site must be
  /// rigidly attached to the tip, on the tip's body or on a body below it with no joint on the way (the
  /// point is then constant; computed at qpos0). The tip pose times it is the site's position.
  /// @throws io::RobotFileError ("FILE: what") for a name that is no site, or a site not fixed to the tip
  Vec3 siteInTip(const std::string& site) const;

  /// A per-thread evaluator (owns its mjData).
  class Evaluator {
   public:
    explicit Evaluator(const MujocoRobot& robot);
    ~Evaluator();
    Evaluator(Evaluator&&) noexcept;
    /// T_base_tip at motion variables x (rad/length per joint; qpos = qpos0 + x, slide = pitch * x).
    Pose tipPose(const Eigen::Ref<const VecX>& x);
    /// Geometric Jacobian of the tip, rows [v; w] in base coordinates (Paden–Sastry eq. 3.13), d/dx,
    /// from mj_jacSite / mj_jacBody (after mj_kinematics and mj_comPos); a helical column is
    /// hinge column + pitch * slide column. Also returns the pose.
    Pose tipJacobian(const Eigen::Ref<const VecX>& x, Eigen::Ref<Mat6X> J_geometric);

   private:
    void setConfiguration(const Eigen::Ref<const VecX>& x);
    Pose worldTip() const;
    const MujocoRobot* robot_;
    std::unique_ptr<mjData_, void (*)(mjData_*)> data_;
    std::vector<double> jacp_, jacr_;
  };

 private:
  struct ModelDeleter {
    void operator()(mjModel_* m) const;
  };
  std::unique_ptr<mjModel_, ModelDeleter> model_;
  std::string path_, tip_;
  int tip_site_ = -1, tip_body_ = -1, base_body_ = 0;
  Pose T_base_world_;
  std::vector<MujocoJoint> joints_;
  std::unique_ptr<PoeModel> poe_;
};

/// The robot file `file` as a POE model, checked to describe the MuJoCo chain of `robot` (joint count and
/// types; `model_path` and `tip` name the chain in messages). @throws io::RobotFileError
PoeModel matchingModel(const io::RobotFile& file, const MujocoRobot& robot, const std::string& model_path,
                       const std::string& tip);

/// The tips a model file offers, for the message of a missing tip, as a wrong tip's message lists them: an
/// MJCF's "sites: 'tool'; bodies: 'link1', ...", a URDF's "links: ...".
/// @throws io::RobotFileError for a file MuJoCo (or urdfdom) cannot load
std::string tipCandidates(const std::string& path);

/// The chain of a model file to `tip` as a robot file (POE): a URDF read by urdfdom, an MJCF by MuJoCo. The
/// one reading of `ROBOT --tip NAME` for the command line and the Python module.
/// @throws io::RobotFileError, std::invalid_argument as readUrdf and MujocoRobot
io::RobotFile robotFileOfModel(const std::string& path, const std::string& tip, const std::string& base);

}  // namespace lowpair::mujoco
