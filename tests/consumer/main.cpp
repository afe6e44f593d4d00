// Consumer of the installed lowpair package (0.3 API): a planar 2R arm through the public API, checked
// against the pose worked out by hand; a q of the wrong size rejected with its message; the robot size L
// under its one name (lengthScale, member and free function); the error model's options as a struct
// (ErrorModelSpec, no positional bool); an options struct's validate(); the installed lowpair/version.hpp
// agreeing with the package's version. Exit 0 if all hold, 1 otherwise.

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <lowpair/error_model.hpp>
#include <lowpair/ik.hpp>
#include <lowpair/kinematics.hpp>
#include <lowpair/version.hpp>

int main() {
  // Two revolute joints about z: the first through the origin, the second through (1, 0, 0);
  // twist [w; v] with v = p x w, so (0,0,1, 0,0,0) and (0,0,1, 0,-1,0). Tool at (2, 0, 0), no rotation.
  lowpair::JointSpec s1;
  s1.twist << 0, 0, 1, 0, 0, 0;
  lowpair::JointSpec s2;
  s2.twist << 0, 0, 1, 0, -1, 0;
  lowpair::Pose tool;
  tool.p << 2, 0, 0;
  const lowpair::PoeModel model(std::vector<lowpair::JointSpec>{s1, s2}, tool, "planar_2r");

  Eigen::VectorXd q(2);
  q << 0.3, -0.7;
  // The convenience form (it allocates its own workspace).
  const lowpair::Pose T = lowpair::poeForwardKinematics(model, q);

  // By hand: links of length 1, absolute angles q1 and q1 + q2.
  const double a = q(0), b = q(0) + q(1);
  const Eigen::Vector3d p_expected(std::cos(a) + std::cos(b), std::sin(a) + std::sin(b), 0.0);
  Eigen::Matrix3d R_expected;
  R_expected << std::cos(b), -std::sin(b), 0,  //
                std::sin(b), std::cos(b), 0,   //
                0, 0, 1;

  // The FK is two 4x4 exponentials and two products: a few roundings of numbers of size <= 2, i.e.
  // errors of a few eps * 2 ~ 1e-15. 1e-14 (~20 eps * 2) leaves room for that and for libm's last bit,
  // while any real error (wrong sign, wrong axis point, wrong product order) is O(0.1).
  const double tol = 1e-14;
  const double p_err = (T.p - p_expected).cwiseAbs().maxCoeff();
  const double R_err = (T.R - R_expected).cwiseAbs().maxCoeff();
  std::printf("consumer: %s p = (%.17g, %.17g, %.17g), |p - p_hand| = %.3g, |R - R_hand| = %.3g\n",
              model.name().c_str(), T.p.x(), T.p.y(), T.p.z(), p_err, R_err);
  if (!(p_err <= tol) || !(R_err <= tol)) {
    std::printf("consumer: MISMATCH (tolerance %.3g)\n", tol);
    return 1;
  }

  // The size check is in the installed library whatever its build type: three values for two joints.
  try {
    lowpair::poeForwardKinematics(model, Eigen::VectorXd::Zero(3));
    std::printf("consumer: q of 3 values for 2 joints was accepted\n");
    return 1;
  } catch (const std::invalid_argument& e) {
    const std::string expected = "poeForwardKinematics: q has 3 values, the model has 2 joints";
    std::printf("consumer: rejected: %s\n", e.what());
    if (e.what() != expected) return 1;
  }

  // The header and the CMake package say the same version (LOWPAIR_PACKAGE_VERSION: find_package's lowpair_VERSION)
  static_assert(lowpair::versionNumber() ==
                    LOWPAIR_VERSION_MAJOR * 10000 + LOWPAIR_VERSION_MINOR * 100 + LOWPAIR_VERSION_PATCH,
                "versionNumber() and the version macros disagree");
  std::printf("consumer: lowpair/version.hpp says %s, the package %s\n", lowpair::kVersionString,
              LOWPAIR_PACKAGE_VERSION);
  if (std::string(LOWPAIR_VERSION_STRING) != LOWPAIR_PACKAGE_VERSION) return 1;

  // L: the tool at (2, 0, 0) is the farthest point (the axes pass within 1 of the origin): L = 2, the same
  // from the model and from its joints.
  const double L = model.lengthScale();
  std::printf("consumer: L = %g\n", L);
  if (L != 2.0 || lowpair::lengthScale(model.joints(), model.toolPose()) != L) return 1;

  // The error model's options: 4 + 1 + 6 = 11 parameters for two revolute joints (4 each + a scale each,
  // then the tool), one pitch more per joint with free pitch.
  const int fixed_pitch = lowpair::ErrorModel(model).size();
  const int free_pitch = lowpair::ErrorModel(model, lowpair::ErrorModelSpec{true}).size();
  const int counted = lowpair::identifiableCount(model, lowpair::Measure::Pose, lowpair::ErrorModelSpec{true}).total();
  std::printf("consumer: %d parameters, %d with free pitch (count %d)\n", fixed_pitch, free_pitch, counted);
  if (fixed_pitch != 2 * 4 + 2 + 6 || free_pitch != fixed_pitch + 2 || counted != free_pitch) return 1;

  // An options struct checks itself with the message its function gives.
  lowpair::IkOptions options;
  options.max_iterations = -1;
  try {
    options.validate();
    std::printf("consumer: max_iterations = -1 was accepted\n");
    return 1;
  } catch (const std::invalid_argument& e) {
    std::printf("consumer: rejected: %s\n", e.what());
    if (std::string(e.what()) != "inverseKinematics: max_iterations must be >= 0, got -1") return 1;
  }
  return 0;
}
