#include "lowpair/calibrate.hpp"
#include "calibration_internal.hpp"
#include "calibration_prior.hpp"
#include "linalg.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "check.hpp"
#include "lowpair/deflection.hpp"
#include "lowpair/interrupt.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

using namespace detail;

namespace {

// --- the weighted least-squares problem ----------------------------------------------------------------

// The weights of the residuals: noise per coordinate, and the robust loss' per measurement.
struct Weights {
  double position = 1.0, rotation = 1.0;  // sigma_position (length), sigma_rotation (rad)
};

// Weighted residual r = [log(R_meas R^T) / sigma_r; (p_meas - p) / sigma_p] per measurement (or the
// position part alone), each measurement's block times sqrt(its robust weight), and its squared norm.
// The residual rows of every measurement (rowsOf: 6 for a pose, 3 for a point; mixed data mixes them).
Eigen::Index residualRows(const std::vector<Measurement>& measurements, Measure measure) {
  Eigen::Index rows = 0;
  for (const Measurement& m : measurements) rows += rowsOf(m, measure);
  return rows;
}

// The model's state at an iterate: its geometry, targets' points and joint deflections.
struct State {
  const PoeModel& model;
  const std::vector<Vec3>& target_points;
  const JointDeflection& deflection;
};

double residual(const State& s, const std::vector<Measurement>& measurements, const std::vector<PoseLoad>& loads,
                Measure measure, const Weights& w, const VecX& robust, VecX& r) {
  r.resize(residualRows(measurements, measure));
  Data data(s.model);
  Eigen::Index at = 0;
  Measurement deflected;
  for (size_t m = 0; m < measurements.size(); ++m) {
    const Measurement* x = &measurements[m];
    if (!loads.empty()) {
      deflected = measurements[m];
      deflected.q = deflectedJoints(s.deflection, measurements[m].q, loads[m]);
      x = &deflected;
    }
    const Pose T = predict(s.model, data, *x, measure, s.target_points);
    const Pose& M = measurements[m].T_base_tool;
    const int per = rowsOf(measurements[m], measure);
    auto rows = r.segment(at, per);
    if (per == 6) {
      rows.head<3>() = logSO3(M.R * T.R.transpose()) / w.rotation;
      rows.tail<3>() = (M.p - T.p) / w.position;
    } else {
      rows = (M.p - T.p) / w.position;
    }
    rows *= std::sqrt(robust[static_cast<Eigen::Index>(m)]);
    at += per;
  }
  return r.squaredNorm();
}

MatX weightedJacobian(const ErrorModel& em, const std::vector<Measurement>& measurements, const std::vector<PoseLoad>& loads,
                      Measure measure, const Weights& w, const VecX& robust) {
  MatX J(residualRows(measurements, measure), em.size());
  Eigen::Index at = 0;
  for (size_t m = 0; m < measurements.size(); ++m) {
    const int per = rowsOf(measurements[m], measure);
    auto rows = J.middleRows(at, per);
    // a pose among target measurements: the tool frame's rows (mixed data)
    em.jacobian(measurements[m].q, loads.empty() ? PoseLoad{} : loads[m], per == 6 ? Measure::Pose : measure, rows,
                measurements[m].target);
    if (per == 6) {
      rows.topRows<3>() /= w.rotation;
      rows.bottomRows<3>() /= w.position;
    } else {
      rows /= w.position;
    }
    rows *= std::sqrt(robust[static_cast<Eigen::Index>(m)]);
    at += per;
  }
  return J;
}

// The median of the normalized residual u of a measurement with noise-unit Gaussian residuals: u is chi
// with 3 degrees of freedom for a point; for a pose, chi with 6 over sqrt(2). (Medians of chi-square with 3
// and 6 degrees of freedom: 2.365974 and 5.348121.)
double medianNormalized(int rows) { return rows == 6 ? std::sqrt(5.348121 / 2.0) : std::sqrt(2.365974); }

double median(std::vector<double> x) {
  if (x.empty()) return 0.0;
  const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

// The stated noise (the other of a pair derived through L), or relative weights when none is stated.
Weights noiseWeights(const CalibrationOptions& options, double L) {
  Weights w;
  if (options.sigma_position) {
    w.position = *options.sigma_position;
    w.rotation = options.sigma_rotation ? *options.sigma_rotation : w.position / L;
  } else if (options.sigma_rotation) {
    w.rotation = *options.sigma_rotation;
    w.position = w.rotation * L;
  } else {
    w.position = L;  // relative weights only; the covariance uses the a posteriori noise level
    w.rotation = 1.0;
  }
  return w;
}

// The fit's error model at the registered nominal: the options' parameters and the registered targets.
ErrorModelSpec fitSpec(const CalibrationOptions& options, const Registration& reg,
                       const std::vector<Measurement>& measurements) {
  ErrorModelSpec spec;
  spec.pose_measurements = options.measure == Measure::Targets &&
                           std::any_of(measurements.begin(), measurements.end(),
                                       [](const Measurement& m) { return m.target == kPoseMeasurement; });
  spec.free_pitch = options.free_pitch;
  spec.set = options.parameters;
  spec.names = options.parameter_names;
  spec.targets = options.targets;  // at the registered (or estimated) points
  for (size_t t = 0; t < spec.targets.size(); ++t) spec.targets[t].point_tool = reg.target_points[t];
  spec.compliance_joints = options.compliance_joints;
  spec.backlash_joints = options.backlash_joints;
  spec.deflection = options.deflection;
  return spec;
}

// What the fit minimizes: the weighted residuals of the measurements (noise weights, and per measurement
// the robust loss' weight) over the determined subspace of the nominal, whose steps are `basis * y`.
struct Problem {
  const std::vector<Measurement>* measurements = nullptr;
  const std::vector<PoseLoad>* loads = nullptr;  // per measurement, or empty
  Measure measure = Measure::Pose;
  Weights w;
  double L = 1.0;
  VecX robust;         // per measurement
  MatX basis;          // n x rank
  Eigen::Index n = 0;  // the parameters: the rank rule's n
  int rank = 0;
  VecX prior;  // per parameter 1/width (calibration_prior.hpp), empty without a prior
  // with a prior, the error model at the registered nominal: an iterate is start->apply(estimate), so that the MAP
  // cost is a function of the estimate (composed steps would make it depend on the path: no convergence)
  const ErrorModel* start = nullptr;
};

// the prior's part of the cost at an estimate (0 without a prior)
double priorCost(const Problem& p, const VecX& estimate) {
  return p.prior.size() == 0 ? 0.0 : p.prior.cwiseProduct(estimate).squaredNorm();
}

// The fit at an iterate: the error model re-centred there, its weighted residual and cost, the sum of the
// accepted steps, and the iterations so far.
struct Iterate {
  ErrorModel em;
  VecX r{};
  double cost = 0.0;
  VecX estimate{};
  int iterations = 0;
};

std::invalid_argument overflowError(const Problem& p) {
  std::ostringstream text;
  text << "calibrate: the weighted residuals or Jacobian overflow (sigma_position " << p.w.position
       << " for a robot of size L = " << p.L << "): state the noise and the measurements in the robot's length unit";
  return std::invalid_argument(text.str());
}

double residualAt(const Problem& p, const State& s, VecX& r) {
  return residual(s, *p.measurements, *p.loads, p.measure, p.w, p.robust, r);
}

State stateOf(const ErrorModel& em) { return State{em.model(), em.targetPoints(), em.deflection()}; }

// The determined subspace, fixed at the (registered) nominal: the rank analysis of its weighted Jacobian,
// the column scale D0 and the right singular vectors V0 of the scaled matrix.
struct Subspace {
  RankAnalysis rank;
  VecX D0;
  MatX V0;
};

// With a prior, `fit` receives the subspace the data and the prior determine together (the fit's).
Subspace nominalSubspace(const Problem& p, const ErrorModel& em, double cost, Subspace& fit) {
  // (the column norms square the entries: a stated noise small enough to leave the residuals finite may
  // still overflow them, and a column left unscaled would take the whole rank)
  const MatX J_nominal = weightedJacobian(em, *p.measurements, *p.loads, p.measure, p.w, p.robust);
  if (!std::isfinite(cost) || !J_nominal.colwise().squaredNorm().allFinite()) throw overflowError(p);
  Subspace s;
  const int poses = static_cast<int>(p.measurements->size());
  s.rank = analyzeDimensionless(J_nominal, poses, &s.D0, &s.V0);
  if (p.prior.size() == 0) {
    fit = s;
  } else {
    fit.rank = analyzeDimensionless(withPriorRows(J_nominal, p.prior), poses, &fit.D0, &fit.V0);
  }
  return s;
}

// --- Levenberg-Marquardt -------------------------------------------------------------------------------

// The damping is relative to sigma_1^2 (mu): no sigma_1^2 is ever formed, so a Jacobian near the overflow
// limit (a tiny stated noise) damps like any other, and mu's bounds end the inner loop after at most
// log10(mu_max / mu_min) + 1 rejections.
struct LmOptions {
  int max_iterations = 100;
  double mu_start = 1e-6, mu_min = 1e-12, mu_max = 1e16, mu_step = 10.0;
  double relative_decrease = 1e-10;  // converged when an undamped step gains less than this
};

// the reduced problem at an iterate: A = J basis (rows x rank; with a prior [J; diag(prior)] basis) and its SVD
Eigen::JacobiSVD<MatX> reducedSvd(const Problem& p, const ErrorModel& at) {
  const MatX J = weightedJacobian(at, *p.measurements, *p.loads, p.measure, p.w, p.robust);
  if (p.prior.size() > 0) return Eigen::JacobiSVD<MatX>(withPriorRows(J, p.prior) * p.basis, Eigen::ComputeThinU | Eigen::ComputeThinV);
  return Eigen::JacobiSVD<MatX>(J * p.basis, Eigen::ComputeThinU | Eigen::ComputeThinV);
}

// the nominal's rule (its n: every parameter), not one relaxed to the reduced problem's `rank` columns
bool usable(const VecX& s, int i, Eigen::Index n) { return s[i] > numericalRankTolerance(s[0], static_cast<double>(n)); }

// y = sum_i v_i s_i g_i / (s_i^2 + mu s_1^2), in units of s_1: (s_i/s_1) g_i / ((s_i/s_1)^2 + mu) / s_1
VecX dampedStep(const Problem& p, const Eigen::JacobiSVD<MatX>& svd, const VecX& g, double mu) {
  const VecX& s = svd.singularValues();
  const double s1 = s[0];
  VecX y = VecX::Zero(p.rank);
  for (int i = 0; i < s.size(); ++i) {
    const double t = s[i] / s1;
    if (usable(s, i, p.n)) y += svd.matrixV().col(i) * (t * g[i] / (t * t + mu) / s1);
  }
  return y;
}

// A trial step: the moved model and targets, their weighted residual and cost.
struct Trial {
  PoeModel model;
  std::vector<Vec3> target_points{};
  JointDeflection deflection{};
  VecX r{};
  double cost = 0.0;
};

// Nothing when the step leaves the valid models (a scale through 0, beyond the magnitude limits). With a prior the
// trial is the registered nominal moved by estimate + step.
std::optional<Trial> tryStep(const Problem& p, const ErrorModel& em, const VecX& step, const VecX& estimate) {
  const ErrorModel& from = p.start ? *p.start : em;
  const VecX delta = p.start ? VecX(estimate + step) : step;
  std::optional<PoeModel> moved = from.tryApply(delta);
  if (!moved) return std::nullopt;
  Trial trial{std::move(*moved)};
  trial.target_points = from.applyTargetPoints(delta);
  trial.deflection = from.applyDeflection(delta);
  trial.cost = residualAt(p, State{trial.model, trial.target_points, trial.deflection}, trial.r);
  return trial;
}

// One Levenberg-Marquardt run at the current robust weights from `it`; true when converged.
bool levenbergMarquardt(const Problem& p, const LmOptions& lm, Iterate& it) {
  double mu = lm.mu_start;
  for (int pass = 0; pass < lm.max_iterations; ++pass) {
    pollInterrupt();
    ++it.iterations;
    // the objective: the data's cost plus the prior's (MAP)
    const double total = it.cost + priorCost(p, it.estimate);
    if (p.rank == 0 || total == 0.0) return true;
    const Eigen::JacobiSVD<MatX> svd = reducedSvd(p, it.em);
    const VecX& s = svd.singularValues();
    const VecX g = p.prior.size() == 0 ? VecX(svd.matrixU().transpose() * it.r)
                                       : VecX(svd.matrixU().transpose() * withPriorResidual(it.r, p.prior, it.estimate));
    if (!s.allFinite() || !g.allFinite()) throw overflowError(p);
    if (!(s[0] > 0.0)) return true;
    bool accepted = false, converged = false;
    for (; !accepted && mu <= lm.mu_max; mu = std::max(mu, lm.mu_min) * lm.mu_step) {
      const VecX y = dampedStep(p, svd, g, mu);
      if (!y.allFinite()) continue;
      const VecX step = p.basis * y;
      std::optional<Trial> trial = tryStep(p, it.em, step, it.estimate);
      if (!trial) continue;
      const double trial_total = trial->cost + priorCost(p, it.estimate + step);
      if (!(trial_total < total)) continue;
      accepted = true;
      // a small gain counts only for an undamped-enough step (a heavily damped one is small anyway)
      converged = total - trial_total <= lm.relative_decrease * total && mu <= lm.mu_start;
      it.cost = trial->cost;
      it.r = std::move(trial->r);
      it.em = it.em.rebased(trial->model, trial->target_points, trial->deflection);
      it.estimate += step;
      mu /= lm.mu_step * lm.mu_step;  // the loop's increment follows: net one step down
    }
    if (!accepted || converged) return true;  // no step decreases the cost: the rounding floor
  }
  return false;
}

// --- robust reweighting --------------------------------------------------------------------------------

// Per measurement the normalized residual u of the fit at `em` without the robust weights.
std::vector<double> unweightedNormalized(const Problem& p, const ErrorModel& em) {
  VecX plain;
  residual(stateOf(em), *p.measurements, *p.loads, p.measure, p.w, VecX::Ones(p.robust.size()), plain);
  std::vector<double> u(p.measurements->size());
  Eigen::Index at = 0;
  for (size_t m = 0; m < u.size(); ++m) {
    const int per = rowsOf((*p.measurements)[m], p.measure);
    u[m] = normalizedResidual(plain.segment(at, per).squaredNorm(), per);
    at += per;
  }
  return u;
}

// the noise unit of the normalized residuals: 1 when stated, else the median of each residual over its own
// median (chi with 3 or 6 degrees of freedom: mixed data mixes them)
double noiseUnit(const std::vector<double>& u, bool stated, const Problem& p) {
  if (stated) return 1.0;
  std::vector<double> relative(u.size());
  for (size_t m = 0; m < u.size(); ++m) relative[m] = u[m] / medianNormalized(rowsOf((*p.measurements)[m], p.measure));
  const double s = median(relative);
  return s > 0.0 ? s : 1.0;
}

// Iteratively reweighted least squares from the least-squares fit: Huber first (convex), then the chosen
// loss. Returns the passes; `converged` is the last fit's.
int reweight(Problem& p, const LmOptions& lm, Loss chosen, bool stated, Iterate& it, bool& converged) {
  constexpr int kMaxReweightings = 50;
  constexpr double kWeightsSettled = 1e-4;
  const Eigen::Index count = p.robust.size();
  int reweightings = 0;
  for (const Loss loss : {Loss::Huber, chosen}) {
    if (loss == Loss::Huber && chosen != Loss::Huber && reweightings > 0) continue;
    const RobustLoss robust = RobustLoss::of(loss);
    for (int pass = 0; pass < kMaxReweightings; ++pass) {
      pollInterrupt();
      const std::vector<double> u = unweightedNormalized(p, it.em);
      const double scale = noiseUnit(u, stated, p);
      VecX next(count);
      for (Eigen::Index m = 0; m < count; ++m) next[m] = robust.weight(u[static_cast<size_t>(m)] / scale);
      const double change = (next - p.robust).cwiseAbs().maxCoeff();
      p.robust = next;
      ++reweightings;
      it.cost = residualAt(p, stateOf(it.em), it.r);
      converged = levenbergMarquardt(p, lm, it);
      if (change <= kWeightsSettled) break;
    }
    if (loss == chosen) break;
  }
  return reweightings;
}

// --- the result ----------------------------------------------------------------------------------------

// per measurement: errors, normalized residuals (over the noise unit), weights, outliers
std::vector<MeasurementResidual> measurementResiduals(const Problem& p, const ErrorModel& em,
                                                      const std::vector<double>& u, double scale,
                                                      double outlier_threshold) {
  std::vector<MeasurementResidual> residuals(p.measurements->size());
  Data data(em.model());
  const std::vector<Measurement> deflected = deflectedMeasurements(*p.measurements, em.deflection(), *p.loads);
  for (size_t m = 0; m < residuals.size(); ++m) {
    const Measurement& x_m = deflected[m];
    const MeasurementErrors e = measurementErrors(predict(em.model(), data, x_m, p.measure, em.targetPoints()), x_m, p.measure);
    MeasurementResidual& x = residuals[m];
    x.rows = rowsOf(x_m, p.measure);
    x.position = e.position;
    x.rotation = x.rows == 6 ? e.rotation : kNaN;
    x.normalized = u[m] / scale;
    x.weight = p.robust[static_cast<Eigen::Index>(m)];
    x.outlier = x.normalized > outlier_threshold;
  }
  return residuals;
}

// the variance factor: least squares over every measurement, a robust loss over those not flagged
// (`parameters`: the effective number, the rank without a prior)
double varianceFactor(double parameters, Eigen::Index residual_rows, const std::vector<MeasurementResidual>& residuals,
                      const std::vector<double>& u, bool robust) {
  double redundancy = static_cast<double>(residual_rows) - parameters, weighted_cost = 0.0;
  for (size_t m = 0; m < residuals.size(); ++m) {
    const int per = residuals[m].rows;
    if (robust && residuals[m].outlier) {
      redundancy -= per;
      continue;
    }
    weighted_cost += u[m] * u[m] * (per / 3.0);
  }
  return redundancy > 0 ? weighted_cost / redundancy : kNaN;
}

// The covariance's principal axes, the standard deviations and the undetermined directions.
struct Covariance {
  MatX axes, null;
  VecX sd;
};

// covariance at the result on the determined subspace: Cov = basis W S^-2 W^T basis^T (times the variance
// factor when the noise was not stated). Redundancy: with no more residuals than determined parameters the
// fit passes through the noise and the cost says nothing about it (variance factor NaN).
Covariance covarianceAt(const Problem& p, const ErrorModel& em, double factor, const Subspace& sub) {
  const Eigen::Index n = p.n;
  const int rank = p.rank;
  Covariance c;
  c.axes = MatX::Zero(n, rank);
  c.sd = VecX::Constant(n, kInf);
  if (rank > 0 && factor >= 0.0) {
    const Eigen::JacobiSVD<MatX> svd = reducedSvd(p, em);
    const VecX& s = svd.singularValues();
    bool full = true;
    for (int i = 0; i < s.size(); ++i) {
      if (usable(s, i, n)) {
        c.axes.col(i) = p.basis * svd.matrixV().col(i) * (std::sqrt(factor) / s[i]);
      } else {
        full = false;
      }
    }
    c.sd = c.axes.rowwise().norm();
    if (!full) c.sd.setConstant(kInf);  // the subspace lost rank on the way: nothing is certain
  }
  c.null = sub.D0.asDiagonal() * sub.V0.rightCols(n - rank);
  for (Eigen::Index i = 0; i < c.null.cols(); ++i) {
    for (Eigen::Index k = 0; k < n; ++k) {
      if (std::abs(sub.V0(k, rank + i)) > 1e-8) c.sd[k] = kInf;  // moves along an undetermined direction
    }
  }
  return c;
}

// The effective number of parameters at the result: the rank without a prior, else the trace of the data rows' hat
// matrix on the usable singular values of the reduced problem (calibration_prior.hpp).
double effectiveCount(const Problem& p, const ErrorModel& em) {
  if (p.prior.size() == 0 || p.rank == 0) return p.rank;
  const Eigen::JacobiSVD<MatX> svd = reducedSvd(p, em);
  std::vector<bool> use(static_cast<size_t>(svd.singularValues().size()));
  for (int i = 0; i < svd.singularValues().size(); ++i) use[static_cast<size_t>(i)] = usable(svd.singularValues(), i, p.n);
  return effectiveParameters(svd.matrixU(), use, svd.matrixU().rows() - p.n);
}

// The verdict's reason (empty: accepted); L the nominal's size.
std::string verdict(const CalibrationResult& r, double L) {
  const auto count = static_cast<Eigen::Index>(r.residuals.size());
  std::ostringstream why;
  why.precision(3);
  if (!r.converged) {
    why << "the fit did not converge in " << r.iterations << " iterations";
  } else if (r.loss != Loss::Squared && r.outliers > kMaxOutlierFraction * static_cast<double>(count)) {
    why << r.outliers << " of " << count << " measurements are beyond " << r.outlier_threshold
        << " noise units (more than a quarter: a robust loss cannot tell blunders from a wrong model)";
  } else if (r.noise_stated && r.variance_factor > kMaxVarianceFactor) {
    why << "variance factor " << r.variance_factor << " > " << kMaxVarianceFactor << ": the residuals are "
        << std::sqrt(r.variance_factor) << " times the stated noise";
  } else if (r.noise_stated && r.variance_factor < kMinVarianceFactor) {
    why << "variance factor " << r.variance_factor << " < " << kMinVarianceFactor << ": the residuals are "
        << std::sqrt(r.variance_factor) << " times the stated noise; the noise is read in the robot's length unit "
        << "and rad: check its unit first (a noise in mm for a robot in m is 1000 times too large), then its size";
  } else if (!r.noise_stated) {
    const ResidualStatistics& a = r.after;
    if (a.rms_position > kMaxRelativeRmsPosition * L) {
      why << "RMS position " << a.rms_position << " left is " << 100.0 * a.rms_position / L
          << " % of the robot's size L = " << L << " (at most " << 100.0 * kMaxRelativeRmsPosition << " %)";
    } else if (a.rms_rotation > kMaxRmsRotation) {  // (0 without pose measurements)
      why << "RMS rotation " << a.rms_rotation << " rad left (at most " << kMaxRmsRotation << " rad)";
    }
  }
  return why.str();
}

}  // namespace

void CalibrationOptions::validate() const {
  for (const auto& s : {sigma_position, sigma_rotation}) {
    LP_CHECK(!s || (*s > 0.0 && std::isfinite(*s)), "calibrate: noise levels must be positive and finite");
  }
  LP_CHECK(max_iterations >= 0, "calibrate: max_iterations must be >= 0");
  LP_CHECK(outlier_threshold > 0.0 && std::isfinite(outlier_threshold),
           "calibrate: the outlier threshold must be positive and finite");
  for (const double width : {prior.tilt, prior.shift, prior.scale, prior.offset}) {
    LP_CHECK(width > 0.0, "calibrate: a prior width must be positive (+inf for none), got " << width);
  }
  for (const Target& t : targets) {
    LP_CHECK(!t.known || t.point_tool, "calibrate: target " << t.name << " is known but has no point");
  }
}

CalibrationResult calibrate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                            const CalibrationOptions& options) {
  const Measure measure = options.measure;
  checkMeasurements(nominal, measurements, measure, options.targets.size());
  options.validate();
  const double L = nominal.lengthScale();
  const bool stated = options.sigma_position || options.sigma_rotation;
  const std::vector<PoseLoad> loads = measurementLoads(nominal, measurements, options);
  Problem problem;
  problem.measurements = &measurements;
  problem.loads = &loads;
  problem.measure = measure;
  problem.w = noiseWeights(options, L);
  problem.L = L;
  problem.robust = VecX::Ones(static_cast<Eigen::Index>(measurements.size()));

  // the measurement frame (and the unknown targets' points), then the fit from there
  const std::vector<Measurement> at_start = deflectedMeasurements(measurements, options.deflection, loads);
  const Registration reg = registration(nominal, at_start, measure, options.targets, options.register_frame);
  const PoeModel start = movedModel(nominal, reg.T_meas_base);
  Iterate it{ErrorModel(start, fitSpec(options, reg, measurements))};
  checkDeflections(nominal, it.em.spec(), loads);
  problem.prior = priorWeights(it.em, options.prior);
  it.cost = residualAt(problem, stateOf(it.em), it.r);
  Subspace fit;  // the data's (sub) and with the prior the data's and the prior's together (fit)
  Subspace sub = nominalSubspace(problem, it.em, it.cost, fit);
  problem.rank = fit.rank.rank;
  problem.n = it.em.size();
  problem.basis = fit.D0.asDiagonal() * fit.V0.leftCols(problem.rank);
  const ErrorModel registered = it.em;
  if (problem.prior.size() > 0) problem.start = &registered;
  it.estimate = VecX::Zero(problem.n);

  LmOptions lm;
  lm.max_iterations = options.max_iterations;
  bool converged = levenbergMarquardt(problem, lm, it);
  int reweightings = 0;
  if (options.loss != Loss::Squared) reweightings = reweight(problem, lm, options.loss, stated, it, converged);

  const std::vector<double> u = unweightedNormalized(problem, it.em);
  const double scale = noiseUnit(u, stated, problem);
  std::vector<MeasurementResidual> residuals = measurementResiduals(problem, it.em, u, scale, options.outlier_threshold);
  const int outliers = static_cast<int>(std::count_if(residuals.begin(), residuals.end(),
                                                      [](const MeasurementResidual& x) { return x.outlier; }));
  const double effective = effectiveCount(problem, it.em);
  const double variance_factor = varianceFactor(effective, it.r.size(), residuals, u, options.loss != Loss::Squared);
  const Covariance cov = covarianceAt(problem, it.em, stated ? 1.0 : variance_factor, fit);

  CalibrationResult out{it.em.model(), it.em};
  out.expected = identifiableCount(nominal, measure, it.em.spec());
  out.tool_rank = measure == Measure::Pose || it.em.spec().pose_measurements ? 6
                  : measure == Measure::Position ? 3
                                                 : knownPointsToolRank(it.em.spec().knownPoints(), L);
  out.prior = options.prior;
  out.effective_parameters = effective;
  if (problem.prior.size() > 0) out.held_by_prior = heldByPrior(sub.V0, sub.rank.rank, cov.sd);
  out.rank = std::move(sub.rank);
  out.before = residualStatistics(start, at_start, measure, reg.target_points);
  out.after = residualStatistics(it.em.model(), deflectedMeasurements(measurements, it.em.deflection(), loads), measure,
                                 it.em.targetPoints());
  out.iterations = it.iterations;
  out.converged = converged;
  out.sigma_position = problem.w.position;
  out.sigma_rotation = problem.w.rotation;
  out.noise_stated = stated;
  out.variance_factor = variance_factor;
  out.covariance = cov.axes * cov.axes.transpose();
  out.standard_deviation = cov.sd;
  out.principal_axes = cov.axes;
  out.undetermined_directions = cov.null;
  out.sigma_position_stated = options.sigma_position.has_value();
  out.sigma_rotation_stated = options.sigma_rotation.has_value();
  out.measure = measure;
  out.parameter_set = options.parameters;
  out.registration = reg;
  out.target_points = it.em.targetPoints();
  out.loss = options.loss;
  out.robust_scale = scale;
  out.robust_scale_from_median = !stated;
  out.reweightings = reweightings;
  out.residuals = std::move(residuals);
  out.outliers = outliers;
  out.outlier_threshold = options.outlier_threshold;
  out.estimate = it.estimate;
  out.deflection = it.em.deflection();
  out.loads = loads;
  out.reason = verdict(out, L);
  out.accepted = out.reason.empty();
  return out;
}

}  // namespace lowpair
