#include "lowpair/ik.hpp"
#include "ik_ranges.hpp"
#include "linalg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>


#include "check.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/singularity.hpp"

namespace lowpair {

namespace {

// at most 6 x 6, on the stack: the normal matrices, the QR factor and its SVD never allocate
using linalg::Small;
using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

int taskRows(Measure measure) { return rowsPerMeasurement(measure); }

// q_i = columnScale * u_i: the dimensionless joint variable u of dimensionlessJacobian's columns
double columnScale(const Joint& joint, double L) { return (joint.type == JointType::Prismatic ? L : 1.0) / joint.scale; }

using ik_ranges::inRange;
using ik_ranges::period;
using ik_ranges::periodic;
using ik_ranges::wrapInto;

// A joint at a limit that the descent direction `g_i` pushes out of its range, where whole turns cannot
// bring it back in (a revolute joint whose range spans a turn is never blocked).
bool blocked(const Joint& joint, double q, double g) {
  if (!joint.range) return false;
  const auto& range = *joint.range;
  if (periodic(joint) && range[1] - range[0] >= period(joint)) return false;
  return (q <= range[0] && g < 0.0) || (q >= range[1] && g > 0.0);
}

[[gnu::format(printf, 2, 3)]] LP_COLD void setReason(IkResult& result, const char* format, ...) {
  char text[320];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  result.reason = text;
}

struct Errors {
  double position = 0.0, rotation = 0.0, cost = 0.0;
};

// F = T_base_tool * Trans(point_tool) at q; the error r = [dp / L; log(R_t R_F^T)] and the dimensionless task
// Jacobian J (rows [v / L; w] of the point p_F) there. Position: r's rotation rows are 0.
Errors evaluate(const PoeModel& model, Data& data, const Eigen::Ref<const VecX>& q, const Pose& target,
                const IkOptions& options, double L, Mat6X& J, Vec6& r) {
  computeJacobians(model, data, q);
  const Pose& T = data.T_base_tool;
  Pose F;
  F.R = T.R;
  F.p.noalias() = T.R * options.point_tool;
  F.p += T.p;
  spatialToGeometric(F, data.J_spatial, J);  // velocity of the point p_F
  dimensionlessJacobian(model, J);
  const Vec3 dp = target.p - F.p;
  Errors e;
  e.position = dp.norm();
  r.head<3>() = dp / L;
  if (options.measure == Measure::Pose) {
    Mat3 D;
    D.noalias() = target.R * F.R.transpose();
    const Vec3 w = logSO3(D);
    r.tail<3>() = w;
    e.rotation = w.norm();
  } else {
    r.tail<3>().setZero();
  }
  e.cost = r.squaredNorm();
  return e;
}

// The chain's reach: a point fixed in the base (`center`) and a radius every position of the tool point lies
// within, whatever q. Walking from the tool point P_{n+1} (at rest, every motion 0) towards the base, joint i
// gets a point o_i fixed in the link before it: on its line (the foot of the perpendicular from o_{i+1}) for a
// revolute or helical joint, o_{i+1}'s rest position for a prismatic one. Joint i's motion keeps
// |o_{i+1} - o_i| at its rest value, plus the slide |k x_i| (k = pitch or 1, x_i its motion at a range end),
// so by the triangle inequality |p - o_1| <= the sum. A prismatic or helical joint without a range: +inf.
struct Reach {
  Vec3 center = Vec3::Zero();
  double radius = 0.0;
};

Reach reachBound(const PoeModel& model, const Vec3& point_tool) {
  Reach reach;
  Vec3 P = model.toolPose() * point_tool;
  for (int i = model.dof() - 1; i >= 0; --i) {
    const Joint& joint = model.joint(i);
    const double x_max = joint.range ? std::max(std::abs(joint.motion((*joint.range)[0])), std::abs(joint.motion((*joint.range)[1])))
                                     : std::numeric_limits<double>::infinity();
    if (joint.type == JointType::Prismatic) {
      reach.radius += x_max;
      continue;
    }
    const Vec3 w = joint.axis();
    const Vec3 c = w.cross(joint.moment());  // the line's point nearest the base origin
    const Vec3 foot = c + w * w.dot(P - c);
    reach.radius += (P - foot).norm();
    if (joint.type == JointType::Helical) reach.radius += std::abs(joint.pitch) * x_max;
    P = foot;
  }
  reach.center = P;
  return reach;
}

// Singular values (descending, min(m, n) of them) of the m x n task Jacobian J.topRows(m): Householder QR
// of its taller orientation (in `qr`), then the Jacobi SVD of the min(m, n)-square triangular factor, which has
// the same singular values. Both steps are backward stable, so the values are those of J to rounding.
void taskSingularValues(const Mat6X& J, int m, MatX& qr, SmallVec& sigma) {
  const int n = static_cast<int>(J.cols());
  const int rows = std::max(m, n), c = std::min(m, n);
  auto B = qr.topLeftCorner(rows, c);
  if (n >= m) {
    B = J.topRows(m).transpose();
  } else {
    B = J.topRows(m);
  }
  for (int k = 0; k < c; ++k) {
    auto x = B.col(k).segment(k, rows - k);
    double alpha = x.norm();
    if (alpha == 0.0) continue;
    if (x(0) > 0.0) alpha = -alpha;
    x(0) -= alpha;  // the Householder vector v = x - alpha e1
    const double vv = x.squaredNorm();
    for (int j = k + 1; j < c; ++j) {
      auto y = B.col(j).segment(k, rows - k);
      y -= (2.0 * x.dot(y) / vv) * x;
    }
    x(0) = alpha;
  }
  Small R = Small::Zero(c, c);
  for (int j = 0; j < c; ++j) {
    for (int i = 0; i <= j; ++i) R(i, j) = B(i, j);
  }
  const Eigen::JacobiSVD<Small> svd(R);
  sigma = svd.singularValues();
}

// The free joints' part of the minimum-norm damped step, du = Jf^T (Jf Jf^T + mu I)^-1 re, with M task rows
// (6 or 3) as fixed sizes: the normal matrix and its Cholesky factor are M x M on the stack.
template <int M>
bool minimumNormStep(const Mat6X& J_free, const Vec6& re, double mu, const Eigen::VectorXi& held, VecX& du) {
  using MatM = Eigen::Matrix<double, M, M>;
  const auto Jf = J_free.template topRows<M>();
  MatM A;
  A.noalias() = Jf.lazyProduct(Jf.transpose());
  A.diagonal().array() += std::max(mu, kEps * A.trace());
  const Eigen::LLT<MatM> llt(A);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::Matrix<double, M, 1> y = llt.solve(re.template head<M>());
  for (Eigen::Index i = 0; i < du.size(); ++i) {
    if (!held[i]) du[i] = Jf.col(i).dot(y);
  }
  return true;
}

// Fewer joints than task rows: du = (Jf^T Jf + mu I)^-1 Jf^T re (the same step for mu > 0), n x n, n < 6.
bool leastSquaresStep(const Mat6X& J_free, const Vec6& re, int m, double mu, const Eigen::VectorXi& held, VecX& du) {
  const auto Jf = J_free.topRows(m);
  Small A;
  A.noalias() = Jf.transpose().lazyProduct(Jf);
  A.diagonal().array() += std::max(mu, kEps * A.trace());
  const Eigen::LLT<Small> llt(A);
  if (llt.info() != Eigen::Success) return false;
  SmallVec b(Jf.cols());
  b.noalias() = Jf.transpose().lazyProduct(re.head(m));
  const SmallVec x = llt.solve(b);
  for (Eigen::Index i = 0; i < du.size(); ++i) {
    if (!held[i]) du[i] = x[i];
  }
  return true;
}

// One damped least-squares step from q (file comment of ik.hpp), with the joints flagged in work.held kept at
// their limits; writes work.du (dimensionless) and work.q_trial. Joints that the step would carry out of their
// range (Clamp) are wrapped by whole turns when possible, else held at the limit and the step solved again.
// false when the normal matrix cannot be factored.
bool dampedStep(const PoeModel& model, const VecX& q, const Mat6X& J, const Vec6& r, int m, double mu,
                const IkOptions& options, double L, IkWorkspace& work) {
  const int n = model.dof();
  work.held.setZero();
  for (int pass = 0; pass <= n; ++pass) {
    work.J_free.topRows(m) = J.topRows(m);
    Vec6 re = r;
    bool any_free = false;
    for (int i = 0; i < n; ++i) {
      if (!work.held[i]) {
        any_free = true;
        continue;
      }
      re.head(m) -= J.col(i).head(m) * work.du[i];  // the held joint's own step (to its limit)
      work.J_free.col(i).setZero();
    }
    if (any_free) {
      const bool solved = n < m    ? leastSquaresStep(work.J_free, re, m, mu, work.held, work.du)
                          : m == 6 ? minimumNormStep<6>(work.J_free, re, mu, work.held, work.du)
                                   : minimumNormStep<3>(work.J_free, re, mu, work.held, work.du);
      if (!solved) return false;
    }
    bool again = false;
    for (int i = 0; i < n; ++i) {
      if (work.held[i]) continue;  // already on its limit
      const Joint& joint = model.joint(i);
      const double s = columnScale(joint, L);
      double& qt = work.q_trial[i];
      qt = q[i] + s * work.du[i];
      if (options.ranges != RangePolicy::Clamp || inRange(joint, qt) || wrapInto(joint, qt)) continue;
      const double limit = qt < (*joint.range)[0] ? (*joint.range)[0] : (*joint.range)[1];
      work.held[i] = 1;
      work.du[i] = (limit - q[i]) / s;
      qt = limit;  // exactly
      again = true;
    }
    if (!again) break;
  }
  return true;
}

// The seed inside the ranges (Clamp): whole turns, else the nearest limit.
void projectIntoRanges(const PoeModel& model, VecX& q) {
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& joint = model.joint(i);
    if (inRange(joint, q[i]) || wrapInto(joint, q[i])) continue;
    q[i] = std::clamp(q[i], (*joint.range)[0], (*joint.range)[1]);
  }
}

void checkCall(const char* function, const PoeModel& model, const Data& data, const Eigen::Ref<const VecX>& q,
               const IkOptions& options, const IkWorkspace& work) {
  const int n = model.dof();
  LP_CHECK(data.dof == n, function << ": data was made for a model with " << data.dof << " joints, this model has " << n);
  LP_CHECK(work.dof == n, function << ": the workspace was made for " << work.dof << " joints, the model has " << n);
  LP_CHECK(q.size() == n, function << ": q has " << q.size() << " values, the model has " << n << " joints");
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    LP_CHECK(std::isfinite(q[i]), function << ": joint value " << i + 1 << " is not finite");
  }
  options.validate(function);
}

const char* kStatusNames[] = {"ok", "out_of_range", "singular", "unreachable", "not_converged"};

}  // namespace

void IkOptions::validate(const char* function) const {
  LP_CHECK(measure != Measure::Targets,
           function << ": the task is a pose or a position (for a target, its point as point_tool and Position)");
  LP_CHECK(point_tool.allFinite(), function << ": point_tool is not finite");
  LP_CHECK(position_tolerance > 0.0 && std::isfinite(position_tolerance),
           function << ": position_tolerance must be positive and finite, got " << position_tolerance);
  LP_CHECK(rotation_tolerance > 0.0 && std::isfinite(rotation_tolerance),
           function << ": rotation_tolerance must be positive and finite, got " << rotation_tolerance);
  LP_CHECK(max_iterations >= 0, function << ": max_iterations must be >= 0, got " << max_iterations);
  LP_CHECK(damping >= 0.0 && std::isfinite(damping), function << ": damping must be >= 0 and finite, got " << damping);
}

const char* ikStatusName(IkStatus status) { return kStatusNames[static_cast<int>(status)]; }

namespace {
int checkedDof(int n) {
  LP_CHECK(n >= 0, "IkWorkspace: " << n << " joints");
  return n;
}
}  // namespace

IkWorkspace::IkWorkspace(int n)
    : dof(checkedDof(n)),
      J(Mat6X::Zero(6, n)),
      J_trial(Mat6X::Zero(6, n)),
      J_free(Mat6X::Zero(6, n)),
      du(VecX::Zero(n)),
      q_trial(VecX::Zero(n)),
      gradient(VecX::Zero(n)),
      held(Eigen::VectorXi::Zero(n)),
      qr(MatX::Zero(std::max(n, 6), 6)) {
  result.q = VecX::Zero(n);
}

IkWorkspace::IkWorkspace(const PoeModel& model) : IkWorkspace(model.dof()) {}

namespace {

enum class IkStop { Converged, Limit, Stationary, Blocked, Stalled };

// One inverseKinematics call: the task, its tolerances and the workspace, and the steps of the solve.
struct IkSolve {
  const PoeModel& model;
  Data& data;
  const Pose& T_target;
  const IkOptions& options;
  IkWorkspace& work;
  IkResult& result;
  bool pose;
  int n, m;
  double L, tol_p, tol_r;

  IkSolve(const PoeModel& model_, Data& data_, const Pose& T_target_, const IkOptions& options_, IkWorkspace& work_)
      : model(model_),
        data(data_),
        T_target(T_target_),
        options(options_),
        work(work_),
        result(work_.result),
        pose(options_.measure == Measure::Pose),
        n(model_.dof()),
        m(taskRows(options_.measure)),
        L(model_.lengthScale()),
        tol_p(options_.position_tolerance * L),
        tol_r(options_.rotation_tolerance) {}

  bool within(const Errors& e) const { return e.position <= tol_p && (!pose || e.rotation <= tol_r); }

  // the descent direction g = J^T r and its size relative to |J|_F |r|, all joints or without the blocked ones
  double stationarity(bool projected) {
    VecX& g = work.gradient;
    g.noalias() = work.J.topRows(m).transpose().lazyProduct(work.r.head(m));
    if (projected) {
      for (int i = 0; i < n; ++i) {
        if (blocked(model.joint(i), result.q[i], g[i])) g[i] = 0.0;
      }
    }
    const double scale = work.J.topRows(m).norm() * work.r.head(m).norm();
    return scale > 0.0 ? g.norm() / scale : 0.0;
  }

  // the blocked joint with the largest descent component, or -1
  int anyBlocked() {
    work.gradient.noalias() = work.J.topRows(m).transpose().lazyProduct(work.r.head(m));
    int worst = -1;
    for (int i = 0; i < n; ++i) {
      if (blocked(model.joint(i), result.q[i], work.gradient[i]) &&
          (worst < 0 || std::abs(work.gradient[i]) > std::abs(work.gradient[worst]))) {
        worst = i;
      }
    }
    return worst;
  }

  void start(const Eigen::Ref<const VecX>& q_seed) {
    result.status = IkStatus::NotConverged;
    result.q = q_seed;
    result.iterations = 0;
    result.rank = -1;
    result.sigma_min = std::numeric_limits<double>::quiet_NaN();
    result.joint = -1;
    result.reason.clear();
    result.converged = false;
    if (options.ranges == RangePolicy::Clamp) projectIntoRanges(model, result.q);
  }

  // Damped least squares from result.q until a stop; `e` the errors at result.q on return, the data at result.q.
  IkStop descend(Errors& e) {
    IkStop stop = IkStop::Limit;
    double mu = options.damping;
    bool data_at_q = true;  // data holds the FK and Jacobian at result.q (not at a rejected trial)
    const bool clamp = options.ranges == RangePolicy::Clamp;
    while (true) {
      if (within(e)) {
        stop = IkStop::Converged;
        break;
      }
      if (result.iterations >= options.max_iterations) {
        stop = IkStop::Limit;
        break;
      }
      if (stationarity(false) <= kIkStationary) {
        stop = IkStop::Stationary;
        break;
      }
      if (clamp && anyBlocked() >= 0 && stationarity(true) <= kIkStationary) {
        stop = IkStop::Blocked;
        break;
      }
      ++result.iterations;
      if (!dampedStep(model, result.q, work.J, work.r, m, mu, options, L, work)) {
        mu = std::max(10.0 * mu, kEps * work.J.topRows(m).squaredNorm());
        continue;
      }
      if (work.q_trial == result.q) {
        stop = IkStop::Stalled;
        break;
      }
      const Errors trial = evaluate(model, data, work.q_trial, T_target, options, L, work.J_trial, work.r_trial);
      data_at_q = trial.cost < e.cost;
      if (data_at_q) {
        result.q.swap(work.q_trial);
        work.J.swap(work.J_trial);
        work.r = work.r_trial;
        e = trial;
        mu /= 10.0;
      } else {
        mu = std::max(10.0 * mu, kEps * work.J.topRows(m).squaredNorm());
      }
    }
    if (!data_at_q) computeJacobians(model, data, result.q);  // the last trial was rejected
    return stop;
  }

  // RangePolicy::Report after convergence: joints outside their ranges wrapped by whole turns where possible (the
  // same pose, measured again), else the first one named in result.joint.
  IkStop wrapIntoRanges(IkStop stop, Errors& e) {
    bool wrapped = false;
    for (int i = 0; i < n && result.joint < 0; ++i) {
      const Joint& joint = model.joint(i);
      if (inRange(joint, result.q[i])) continue;
      if (wrapInto(joint, result.q[i])) {
        wrapped = true;
      } else {
        result.joint = i;
      }
    }
    if (wrapped) {
      e = evaluate(model, data, result.q, T_target, options, L, work.J, work.r);
      if (!within(e)) stop = IkStop::Limit;
    }
    return stop;
  }

  // A converged solution: out of range, singular (dimensionless task Jacobian) or ok.
  void classifyConverged() {
    if (result.joint >= 0) {
      const auto& range = *model.joint(result.joint).range;
      result.status = IkStatus::OutOfRange;
      setReason(result, "the solution has joint %d = %.6g outside its range [%.6g, %.6g]", result.joint + 1,
                result.q[result.joint], range[0], range[1]);
      return;
    }
    result.status = IkStatus::Ok;
    if (!options.check_singularity) return;
    SmallVec sigma;
    taskSingularValues(work.J, m, work.qr, sigma);
    const Eigen::Index c = sigma.size();
    const double sigma_max = c > 0 ? sigma[0] : 0.0;
    const double tolerance = rankTolerance(sigma_max, n);
    result.rank = numericalRank(sigma, tolerance);
    result.sigma_min = c > 0 ? sigma[c - 1] : 0.0;
    const double threshold =
        std::max(tolerance, ikSingularRatio(std::max(options.position_tolerance, pose ? options.rotation_tolerance : 0.0)) * sigma_max);
    if (result.rank < c || result.sigma_min <= threshold) {
      result.status = IkStatus::Singular;
      setReason(result, "the solution is singular: the dimensionless task Jacobian has sigma_min %.3g <= %.3g "
                "(sigma_max %.3g, rank %d of %d)", result.sigma_min, threshold, sigma_max, result.rank, static_cast<int>(c));
    }
  }

  // A solve that stopped short: unreachable (stationary), held at a limit, or not converged.
  void classifyStopped(IkStop stop, const Errors& e) {
    const double gamma = stationarity(false);
    const int held = options.ranges == RangePolicy::Clamp ? anyBlocked() : -1;
    const char* where = stop == IkStop::Limit     ? "the iteration limit"
                        : stop == IkStop::Stalled ? "no step changing q"
                                                  : "a stationary point";
    if (gamma <= kIkStationary) {
      result.status = IkStatus::Unreachable;
      setReason(result, "stopped at a stationary point of the error (position %.3g, rotation %.3g rad): no joint motion "
                "reduces it; the target is outside the workspace or needs another seed", e.position, e.rotation);
    } else if (held >= 0) {
      result.status = IkStatus::OutOfRange;
      result.joint = held;
      setReason(result, "joint %d is held at its range limit %.6g and the error (position %.3g, rotation %.3g rad) "
                "decreases beyond it (stopped at %s after %d iterations)", held + 1, result.q[held], e.position,
                e.rotation, where, result.iterations);
    } else if (stop == IkStop::Stalled) {
      result.status = IkStatus::NotConverged;
      setReason(result, "no step changes q any more at position error %.3g, rotation %.3g rad: the tolerances are "
                "below the error's rounding floor here", e.position, e.rotation);
    } else {
      result.status = IkStatus::NotConverged;
      setReason(result, "%d iterations without converging (position error %.3g, rotation %.3g rad)", result.iterations,
                e.position, e.rotation);
    }
  }
};

}  // namespace

const IkResult& inverseKinematics(const PoeModel& model, Data& data, const Pose& T_target,
                                  const Eigen::Ref<const VecX>& q_seed, const IkOptions& options, IkWorkspace& work) {
  checkCall("inverseKinematics", model, data, q_seed, options, work);
  const bool pose = options.measure == Measure::Pose;
  LP_CHECK(T_target.p.allFinite() && (!pose || T_target.R.allFinite()), "inverseKinematics: the target is not finite");
  if (pose) {
    const double defect = (T_target.R.transpose() * T_target.R - Mat3::Identity()).cwiseAbs().maxCoeff();
    LP_CHECK(defect <= kRotationOrthonormal && T_target.R.determinant() > 0.0,
             "inverseKinematics: the target rotation is not a rotation (|R^T R - I| = " << defect << ")");
  }
  IkSolve solve(model, data, T_target, options, work);
  IkResult& result = solve.result;
  solve.start(q_seed);

  const Reach reach = reachBound(model, options.point_tool);
  result.reach = reach.radius;
  Errors e = evaluate(model, data, result.q, T_target, options, solve.L, work.J, work.r);
  const double distance = (T_target.p - reach.center).norm();
  if (distance > reach.radius * (1.0 + kIkReachRounding * (solve.n + 1)) + solve.tol_p) {
    result.position_error = e.position;
    result.rotation_error = e.rotation;
    result.status = IkStatus::Unreachable;
    setReason(result, "the target point is %.6g from joint 1's axis, beyond the chain's reach %.6g (its link lengths "
              "and slides added up)", distance, reach.radius);
    return result;
  }

  IkStop stop = solve.descend(e);
  if (stop == IkStop::Converged && options.ranges == RangePolicy::Report) stop = solve.wrapIntoRanges(stop, e);
  result.position_error = e.position;
  result.rotation_error = e.rotation;
  result.converged = stop == IkStop::Converged;
  if (result.converged) {
    solve.classifyConverged();
  } else {
    solve.classifyStopped(stop, e);
  }
  return result;
}

const IkResult& compensate(const PoeModel& nominal, const PoeModel& calibrated, Data& data,
                           const Eigen::Ref<const VecX>& q, const IkOptions& options, IkWorkspace& work) {
  LP_CHECK(nominal.dof() == calibrated.dof(),
           "compensate: the nominal model has " << nominal.dof() << " joints, the calibrated " << calibrated.dof());
  checkCall("compensate", nominal, data, q, options, work);
  forwardKinematics(nominal, data, q);
  Pose target;
  target.R = data.T_base_tool.R;
  target.p.noalias() = data.T_base_tool.R * options.point_tool;
  target.p += data.T_base_tool.p;
  return inverseKinematics(calibrated, data, target, q, options, work);
}

}  // namespace lowpair
