#include "lowpair/calibration.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "lowpair/check.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A null-vector coefficient above this names its parameter in RankAnalysis::undetermined.
constexpr double kNamedCoefficient = 0.1;

bool hasPitch(const JointMotion& joint, bool free_pitch) {
  return joint.type == JointType::Helical || (free_pitch && joint.type == JointType::Revolute);
}

std::string jointTag(int i) { return "j" + std::to_string(i + 1); }

// u1 = u x e (e the base axis least aligned with u), u2 = u x u1: with u, a right-handed orthonormal basis.
void perpendicularPair(const Vec3& u, Vec3& u1, Vec3& u2) {
  Eigen::Index k = 0;
  u.cwiseAbs().minCoeff(&k);
  u1 = u.cross(Vec3::Unit(k)).normalized();
  u2 = u.cross(u1);
}

Vec6 twist(const Vec3& w, const Vec3& v) {
  Vec6 xi;
  xi << w, v;
  return xi;
}

// A tool-point velocity `dv + dw x p` at or below `kCancellation (n + 1)` ulp of `|dv| + |dw| |p|` (n joints:
// the frames carry the rounding of up to n + 1 products) is a cancellation to zero (e.g. a rotation about a
// line through the tool point): it is set to exactly 0, so that the column scaling of the rank analysis
// cannot blow rounding noise up into an identifiable-looking column.
constexpr double kCancellation = 16.0;

double cancellationLevel(int dof) { return kCancellation * (dof + 1) * kEps; }

// `a - b` for two spatial twists whose difference cancels to zero exactly in exact arithmetic for some
// parameters (e.g. Ad(P) eta - Ad(P exp(xi x)) eta for eta commuting with xi): a difference at rounding level
// of its terms is set to exactly 0, for the same reason as kCancellation.
Vec6 twistDifference(const Vec6& a, const Vec6& b, int dof) {
  const Vec6 d = a - b;
  return d.norm() <= cancellationLevel(dof) * (a.norm() + b.norm()) ? Vec6::Zero() : d;
}

// Rows of one measurement from spatial twist columns S (6 x m) of the tool frame at position p:
// [dtheta; dp] = [dw; dv + dw x p], or dp alone.
void measurementRows(const Mat6X& S, const Vec3& p, Measure measure, int dof, Eigen::Ref<MatX> rows) {
  const Eigen::Index m = S.cols();
  MatX dp(3, m);
  for (Eigen::Index c = 0; c < m; ++c) {
    const Vec3 dw = S.col(c).head<3>(), dv = S.col(c).tail<3>();
    dp.col(c) = dv + dw.cross(p);
    if (dp.col(c).norm() <= cancellationLevel(dof) * (dv.norm() + dw.norm() * p.norm())) dp.col(c).setZero();
  }
  if (measure == Measure::Pose) {
    rows.topRows<3>() = S.topRows<3>();
    rows.bottomRows<3>() = dp;
  } else {
    rows = dp;
  }
}

int rowsPerPose(Measure measure) { return measure == Measure::Pose ? 6 : 3; }

void checkPoses(const std::vector<VecX>& q, int dof) {
  LP_CHECK(!q.empty(), "identifiability needs at least one pose");
  for (const VecX& qi : q) checkJointVector(qi, dof);
}

// (JacobiSVD, not BDCSVD: Eigen 3.4.0's BDCSVD reads out of bounds in perturbCol0 on some of these
// matrices, AddressSanitizer on the random-robot rank test; Jacobi with QR preconditioning is exact enough
// and fast for <= 60,000 x ~60.)
// The SVD-based analysis of a matrix whose rows are already dimensionless: columns scaled to unit norm,
// rank by kRankFactor cols eps sigma_1. `column_scale` receives the factors (1 / norm, 1 for a zero column)
// and `V` the full right singular vectors of the scaled matrix (singular values: cols of them, zero-padded).
RankAnalysis analyzeDimensionless(const MatX& A, int poses, VecX* column_scale = nullptr, MatX* V = nullptr) {
  const Eigen::Index cols = A.cols();
  VecX scale = VecX::Ones(cols);
  for (Eigen::Index c = 0; c < cols; ++c) {
    const double norm = A.col(c).norm();
    if (norm > 0.0 && std::isfinite(norm)) scale[c] = 1.0 / norm;
  }
  const MatX scaled = A * scale.asDiagonal();
  Eigen::JacobiSVD<MatX> svd(scaled, Eigen::ComputeFullV);
  RankAnalysis out;
  out.columns = static_cast<int>(cols);
  out.singular_values = VecX::Zero(cols);
  out.singular_values.head(svd.singularValues().size()) = svd.singularValues();
  const double s1 = cols > 0 ? out.singular_values[0] : 0.0;
  out.tolerance = numericalRankTolerance(s1, static_cast<double>(cols));
  out.rank = 0;
  while (out.rank < cols && out.singular_values[out.rank] > out.tolerance) ++out.rank;
  if (out.rank == cols && cols > 0) {
    const VecX& s = out.singular_values;
    const double s_min = s[cols - 1];
    out.condition = s1 / s_min;
    out.observability[0] = std::exp(s.array().log().mean()) / std::sqrt(static_cast<double>(std::max(poses, 1)));
    out.observability[1] = s_min / s1;
    out.observability[2] = s_min;
    out.observability[3] = s_min * s_min / s1;
    out.observability[4] = 1.0 / s.cwiseInverse().sum();
  } else {
    out.condition = kInf;
  }
  const MatX& v = svd.matrixV();
  for (Eigen::Index k = out.rank; k < cols; ++k) {
    std::vector<std::pair<int, double>> named;
    for (Eigen::Index c = 0; c < cols; ++c) {
      if (std::abs(v(c, k)) > kNamedCoefficient) named.emplace_back(static_cast<int>(c), v(c, k));
    }
    out.undetermined.push_back(std::move(named));
  }
  if (column_scale) *column_scale = scale;
  if (V) *V = v;
  return out;
}

// Position rows divided by L (rotation rows are rad already).
MatX dimensionless(const MatX& J, Measure measure, double L) {
  MatX A = J;
  const int per = rowsPerPose(measure);
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    if (measure == Measure::Position || r % per >= 3) A.row(r) /= L;
  }
  return A;
}

}  // namespace

const char* measureName(Measure measure) { return measure == Measure::Pose ? "pose" : "position"; }

ParameterCount identifiableCount(const PoeModel& model, Measure measure, bool free_pitch) {
  ParameterCount count;
  for (const Joint& j : model.joints()) {
    if (j.type == JointType::Prismatic) {
      ++count.prismatic;
    } else if (hasPitch(j, free_pitch)) {
      ++count.helical;
    } else {
      ++count.revolute;
    }
  }
  count.scales = model.dof();
  count.tool = measure == Measure::Pose ? 6 : 3;
  return count;
}

// --- the error model ---------------------------------------------------------------------------------

ErrorModel::ErrorModel(const PoeModel& model, bool free_pitch) : model_(model), free_pitch_(free_pitch) {
  auto add = [&](ParameterKind kind, int joint, int component, std::string name, const char* unit) {
    parameters_.push_back(Parameter{kind, joint, component, std::move(name), unit});
  };
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    const std::string tag = jointTag(i);
    std::array<Vec6, 4> basis{};
    Vec3 u1, u2;
    if (j.type == JointType::Prismatic) {
      perpendicularPair(j.moment(), u1, u2);
      basis[0] = twist(u1, Vec3::Zero());
      basis[1] = twist(u2, Vec3::Zero());
      add(ParameterKind::Tilt, i, 0, tag + ".tilt1", "rad");
      add(ParameterKind::Tilt, i, 1, tag + ".tilt2", "rad");
    } else {
      const Vec3 w = j.axis();
      const Vec3 c = w.cross(j.moment());  // the line's point nearest the base origin
      perpendicularPair(w, u1, u2);
      basis[0] = twist(u1, c.cross(u1));
      basis[1] = twist(u2, c.cross(u2));
      basis[2] = twist(Vec3::Zero(), u1);
      basis[3] = twist(Vec3::Zero(), u2);
      add(ParameterKind::Tilt, i, 0, tag + ".tilt1", "rad");
      add(ParameterKind::Tilt, i, 1, tag + ".tilt2", "rad");
      add(ParameterKind::Shift, i, 0, tag + ".shift1", "length");
      add(ParameterKind::Shift, i, 1, tag + ".shift2", "length");
      if (hasPitch(j, free_pitch)) add(ParameterKind::Pitch, i, 0, tag + ".pitch", "length/rad");
    }
    add(ParameterKind::Scale, i, 0, tag + ".scale", "1");
    basis_.push_back(basis);
  }
  const char* axes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) add(ParameterKind::ToolRotation, -1, k, std::string("tool.r") + axes[k], "rad");
  for (int k = 0; k < 3; ++k) add(ParameterKind::ToolTranslation, -1, k, std::string("tool.") + axes[k], "length");
}

PoeModel ErrorModel::apply(const Eigen::Ref<const VecX>& delta) const {
  LP_CHECK(delta.size() == size(), "error model: expected " << size() << " parameters, got " << delta.size());
  LP_CHECK(delta.allFinite(), "error model: non-finite parameter increment");
  std::vector<Joint> joints = model_.joints();
  Eigen::Index k = 0;
  for (int i = 0; i < model_.dof(); ++i) {
    Joint& j = joints[static_cast<size_t>(i)];
    const auto& basis = basis_[static_cast<size_t>(i)];
    const int directions = j.type == JointType::Prismatic ? 2 : 4;
    Vec6 eta = Vec6::Zero();
    for (int b = 0; b < directions; ++b) eta += delta[k++] * basis[static_cast<size_t>(b)];
    const Vec6 xi = adjointApply(expSE3(eta), j.twist);
    if (j.type == JointType::Prismatic) {
      j.twist << Vec3::Zero(), xi.tail<3>().normalized();
    } else {
      const Vec3 w = xi.head<3>().normalized();
      const Vec3 v = xi.tail<3>();
      const Vec3 v_line = v - w.dot(v) * w;  // the moment p x w without pitch
      double pitch = j.type == JointType::Helical ? j.pitch : 0.0;
      if (hasPitch(j, free_pitch_)) pitch += delta[k++];
      if (free_pitch_) {  // the type follows the pitch: revolute when the pitch is rounding relative to L
        const bool rounding = std::abs(pitch) <= kPitchZero * kEps * model_.lengthScale();
        j.type = rounding ? JointType::Revolute : JointType::Helical;
        if (rounding) pitch = 0.0;
      }
      j.pitch = j.type == JointType::Helical ? pitch : 0.0;
      j.twist << w, v_line + j.pitch * w;
    }
    j.scale += delta[k++];
    LP_CHECK(j.scale > 0.0, jointLabel(i, j.name) << ": the increment makes the scale " << j.scale << " (not positive)");
  }
  const Vec3 r = delta.segment<3>(k), t = delta.segment<3>(k + 3);
  const Pose& T = model_.toolPose();
  const Pose tool = expSE3(twist(r, T.p.cross(r) + t)) * T;
  return PoeModel(std::move(joints), tool, model_.name());
}

ErrorModel ErrorModel::rebased(const PoeModel& model) const {
  LP_CHECK(model.dof() == model_.dof(), "error model: rebased onto a model with another joint count");
  ErrorModel out = *this;
  out.model_ = model;
  return out;
}

Pose ErrorModel::jacobian(const Eigen::Ref<const VecX>& q, Measure measure, Eigen::Ref<MatX> rows) const {
  checkJointVector(q, model_.dof());
  LP_CHECK(rows.rows() == rowsPerPose(measure) && rows.cols() == size(), "error model: rows must be "
                                                                           << rowsPerPose(measure) << " x " << size());
  Mat6X S(6, size());
  Pose P, E;  // P = exp(xi_1 x_1) ... exp(xi_{i-1} x_{i-1}) before joint i
  Eigen::Index c = 0;
  for (int i = 0; i < model_.dof(); ++i) {
    const Joint& j = model_.joint(i);
    jointExp(j, q[i], E);
    const Pose next = P * E;
    const int directions = j.type == JointType::Prismatic ? 2 : 4;
    for (int b = 0; b < directions; ++b) {  // (Ad(P_i) - Ad(P_{i+1})) eta
      const Vec6& eta = basis_[static_cast<size_t>(i)][static_cast<size_t>(b)];
      S.col(c++) = twistDifference(adjointApply(P, eta), adjointApply(next, eta), model_.dof());
    }
    if (hasPitch(j, free_pitch_)) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), j.axis())) * j.motion(q[i]);
    S.col(c++) = adjointApply(P, j.twist) * (q[i] + j.offset);
    P = next;
  }
  const Pose T = P * model_.toolPose();
  const Vec3 p_tool = model_.toolPose().p;
  for (int k = 0; k < 3; ++k) S.col(c++) = adjointApply(P, twist(Vec3::Unit(k), p_tool.cross(Vec3::Unit(k))));
  for (int k = 0; k < 3; ++k) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), Vec3::Unit(k)));
  measurementRows(S, T.p, measure, model_.dof(), rows);
  return T;
}

MatX fullErrorModelJacobian(const PoeModel& model, const std::vector<VecX>& q, Measure measure, bool free_pitch) {
  checkPoses(q, model.dof());
  int cols = 6;
  for (const Joint& j : model.joints()) cols += 6 + (hasPitch(j, free_pitch) ? 1 : 0) + 2;
  const int per = rowsPerPose(measure);
  MatX J(per * static_cast<Eigen::Index>(q.size()), cols);
  Mat6X S(6, cols);
  for (size_t m = 0; m < q.size(); ++m) {
    Pose P, E;
    Eigen::Index c = 0;
    for (int i = 0; i < model.dof(); ++i) {
      const Joint& j = model.joint(i);
      const double qi = q[m][i];
      jointExp(j, qi, E);
      const Pose next = P * E;
      for (int k = 0; k < 6; ++k) S.col(c++) = twistDifference(adjointApply(P, Vec6::Unit(k)), adjointApply(next, Vec6::Unit(k)), model.dof());
      if (hasPitch(j, free_pitch)) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), j.axis())) * j.motion(qi);
      S.col(c++) = adjointApply(P, j.twist) * (qi + j.offset);  // scale
      S.col(c++) = adjointApply(P, j.twist) * j.scale;           // offset
      P = next;
    }
    for (int k = 0; k < 6; ++k) S.col(c++) = adjointApply(P, Vec6::Unit(k));
    const Pose T = P * model.toolPose();
    measurementRows(S, T.p, measure, model.dof(), J.middleRows(per * static_cast<Eigen::Index>(m), per));
  }
  return J;
}

MatX dhIdentificationJacobian(const DhModel& model, const std::vector<VecX>& q, Measure measure, bool free_pitch,
                              std::vector<std::string>* names) {
  checkPoses(q, model.dof());
  std::vector<std::string> columns = {"base.theta", "base.d", "base.alpha", "base.a"};
  for (int i = 0; i < model.dof(); ++i) {
    const std::string tag = jointTag(i);
    for (const char* p : {".theta", ".d", ".alpha", ".a"}) columns.push_back(tag + p);
    if (hasPitch(model.joint(i), free_pitch)) columns.push_back(tag + ".pitch");
    columns.push_back(tag + ".scale");
  }
  columns.push_back("tool.theta");
  columns.push_back("tool.d");
  const auto cols = static_cast<Eigen::Index>(columns.size());
  const int per = rowsPerPose(measure);
  MatX J(per * static_cast<Eigen::Index>(q.size()), cols);
  Mat6X S(6, cols);
  for (size_t m = 0; m < q.size(); ++m) {
    Eigen::Index c = 0;
    Pose F;  // the frame before the current row
    // theta, d, alpha, a of one row at F; returns the frame after it and the theta and d columns
    auto row = [&](const DhParams& r, Vec6& theta_col, Vec6& d_col) {
      theta_col = twist(F.R.col(2), F.p.cross(F.R.col(2)));
      d_col = twist(Vec3::Zero(), F.R.col(2));
      S.col(c++) = theta_col;
      S.col(c++) = d_col;
      const Pose F1 = F * dhToolTransform(r.theta, r.d);
      S.col(c++) = twist(F1.R.col(0), F1.p.cross(F1.R.col(0)));
      const Pose F2 = F1 * dhTransform(DhParams{0.0, 0.0, r.alpha, 0.0});
      S.col(c++) = twist(Vec3::Zero(), F2.R.col(0));
      F = F * dhTransform(r);
    };
    Vec6 theta_col, d_col;
    row(model.base(), theta_col, d_col);
    for (int i = 0; i < model.dof(); ++i) {
      const DhJoint& j = model.joint(i);
      const double qi = q[m][i], x = j.motion(qi);
      row(movedRow(j.link, j, x), theta_col, d_col);
      if (hasPitch(j, free_pitch)) S.col(c++) = d_col * x;
      S.col(c++) = (j.turnRate() * theta_col + j.slideRate() * d_col) * (qi + j.offset);
    }
    S.col(c++) = twist(F.R.col(2), F.p.cross(F.R.col(2)));
    S.col(c++) = twist(Vec3::Zero(), F.R.col(2));
    const Pose T = F * dhToolTransform(model.toolTheta(), model.toolD());
    measurementRows(S, T.p, measure, model.dof(), J.middleRows(per * static_cast<Eigen::Index>(m), per));
  }
  if (names) *names = std::move(columns);
  return J;
}

// --- identifiability --------------------------------------------------------------------------------

RankAnalysis analyzeRank(const MatX& jacobian, Measure measure, double L, int poses) {
  LP_CHECK(L > 0.0 && std::isfinite(L), "analyzeRank: the length scale must be positive and finite");
  LP_CHECK(jacobian.rows() % rowsPerPose(measure) == 0, "analyzeRank: rows are not whole measurements");
  LP_CHECK(jacobian.allFinite(), "analyzeRank: the Jacobian has a non-finite entry");
  return analyzeDimensionless(dimensionless(jacobian, measure, L), poses);
}

Identifiability analyzeIdentifiability(const PoeModel& model, const std::vector<VecX>& q, Measure measure,
                                       bool free_pitch) {
  checkPoses(q, model.dof());
  Identifiability out;
  out.measure = measure;
  out.free_pitch = free_pitch;
  out.expected = identifiableCount(model, measure, free_pitch);
  const ErrorModel em(model, free_pitch);
  out.parameters = em.parameters();
  const int per = rowsPerPose(measure);
  const auto poses = static_cast<int>(q.size());
  MatX J(per * static_cast<Eigen::Index>(poses), em.size());
  for (int m = 0; m < poses; ++m) em.jacobian(q[static_cast<size_t>(m)], measure, J.middleRows(per * m, per));
  const double L = model.lengthScale();
  out.poe = analyzeRank(J, measure, L, poses);
  const MatX full = fullErrorModelJacobian(model, q, measure, free_pitch);
  out.full_model_rank = analyzeRank(full, measure, L, poses).rank;
  out.full_model_columns = static_cast<int>(full.cols());
  const DhConversion dh = poeToDh(model);
  out.dh = analyzeRank(dhIdentificationJacobian(dh.model, q, measure, free_pitch, &out.dh_parameters), measure, L,
                       poses);
  return out;
}

// --- calibration -------------------------------------------------------------------------------------

ResidualStatistics residualStatistics(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure) {
  ResidualStatistics s;
  Data data(model);
  double sum_p = 0.0, sum_r = 0.0;
  for (const Measurement& m : measurements) {
    checkJointVector(m.q, model.dof());
    forwardKinematics(model, data, m.q);
    const double ep = (m.T_base_tool.p - data.T_base_tool.p).norm();
    const double er = measure == Measure::Pose ? rotationAngle(data.T_base_tool.R.transpose() * m.T_base_tool.R) : 0.0;
    sum_p += ep * ep;
    sum_r += er * er;
    s.max_position = std::max(s.max_position, ep);
    s.max_rotation = std::max(s.max_rotation, er);
    ++s.count;
  }
  if (s.count > 0) {
    s.rms_position = std::sqrt(sum_p / s.count);
    s.rms_rotation = std::sqrt(sum_r / s.count);
  }
  return s;
}

namespace {

struct Weights {
  double position = 1.0, rotation = 1.0;  // sigma_position (length), sigma_rotation (rad)
};

// Weighted residual r = [log(R_meas R^T) / sigma_r; (p_meas - p) / sigma_p] per measurement (or the
// position part alone) and its squared norm.
double residual(const PoeModel& model, const std::vector<Measurement>& measurements, Measure measure,
                const Weights& w, VecX& r) {
  const int per = rowsPerPose(measure);
  r.resize(per * static_cast<Eigen::Index>(measurements.size()));
  Data data(model);
  for (size_t m = 0; m < measurements.size(); ++m) {
    forwardKinematics(model, data, measurements[m].q);
    const Pose& T = data.T_base_tool;
    const Pose& M = measurements[m].T_base_tool;
    auto rows = r.segment(per * static_cast<Eigen::Index>(m), per);
    if (measure == Measure::Pose) {
      rows.head<3>() = logSO3(M.R * T.R.transpose()) / w.rotation;
      rows.tail<3>() = (M.p - T.p) / w.position;
    } else {
      rows = (M.p - T.p) / w.position;
    }
  }
  return r.squaredNorm();
}

MatX weightedJacobian(const ErrorModel& em, const std::vector<Measurement>& measurements, Measure measure,
                      const Weights& w) {
  const int per = rowsPerPose(measure);
  MatX J(per * static_cast<Eigen::Index>(measurements.size()), em.size());
  for (size_t m = 0; m < measurements.size(); ++m) {
    auto rows = J.middleRows(per * static_cast<Eigen::Index>(m), per);
    em.jacobian(measurements[m].q, measure, rows);
    if (measure == Measure::Pose) {
      rows.topRows<3>() /= w.rotation;
      rows.bottomRows<3>() /= w.position;
    } else {
      rows /= w.position;
    }
  }
  return J;
}

}  // namespace

CalibrationResult calibrate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                            const CalibrationOptions& options) {
  LP_CHECK(!measurements.empty(), "calibrate: no measurements");
  for (size_t m = 0; m < measurements.size(); ++m) {
    const Measurement& x = measurements[m];
    LP_CHECK(x.q.size() == nominal.dof(), "measurement " << m + 1 << ": " << x.q.size() << " joint values for "
                                                          << nominal.dof() << " joints");
    LP_CHECK(x.q.allFinite() && x.T_base_tool.p.allFinite() && x.T_base_tool.R.allFinite(),
             "measurement " << m + 1 << ": non-finite number");
  }
  for (const auto& s : {options.sigma_position, options.sigma_rotation}) {
    LP_CHECK(!s || (*s > 0.0 && std::isfinite(*s)), "calibrate: noise levels must be positive and finite");
  }
  LP_CHECK(options.max_iterations >= 0, "calibrate: max_iterations must be >= 0");
  const Measure measure = options.measure;
  const double L = nominal.lengthScale();
  Weights w;
  const bool stated = options.sigma_position || options.sigma_rotation;
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

  const auto poses = static_cast<int>(measurements.size());
  ErrorModel em(nominal, options.free_pitch);
  VecX r;
  double cost = residual(nominal, measurements, measure, w, r);
  auto overflow = [&] {
    std::ostringstream text;
    text << "calibrate: the weighted residuals or Jacobian overflow (sigma_position " << w.position
         << " for a robot of size L = " << L << "): state the noise and the measurements in the robot's length unit";
    return std::invalid_argument(text.str());
  };
  // (the column norms square the entries: a stated noise small enough to leave the residuals finite may
  // still overflow them, and a column left unscaled would take the whole rank)
  const MatX J_nominal = weightedJacobian(em, measurements, measure, w);
  if (!std::isfinite(cost) || !J_nominal.colwise().squaredNorm().allFinite()) throw overflow();
  // the determined subspace, fixed at the nominal: steps are `basis * y`
  VecX D0;
  MatX V0;
  RankAnalysis nominal_rank = analyzeDimensionless(J_nominal, poses, &D0, &V0);
  const int rank = nominal_rank.rank;
  const Eigen::Index n = em.size();
  const MatX basis = D0.asDiagonal() * V0.leftCols(rank);
  // the reduced problem at an iterate: A = J basis (rows x rank) and its SVD
  auto reduced = [&](const ErrorModel& at) {
    return Eigen::JacobiSVD<MatX>(weightedJacobian(at, measurements, measure, w) * basis,
                               Eigen::ComputeThinU | Eigen::ComputeThinV);
  };
  // the nominal's rule (its n: every parameter), not one relaxed to the reduced problem's `rank` columns
  auto usable = [&](const VecX& s, int i) { return s[i] > numericalRankTolerance(s[0], static_cast<double>(n)); };

  // Levenberg-Marquardt with the damping relative to sigma_1^2 (mu): no sigma_1^2 is ever formed, so a
  // Jacobian near the overflow limit (a tiny stated noise) damps like any other, and mu's bounds end the
  // inner loop after at most log10(kMuMax / kMuMin) + 1 rejections.
  constexpr double kMuStart = 1e-6, kMuMin = 1e-12, kMuMax = 1e16, kMuStep = 10.0;
  constexpr double kRelativeDecrease = 1e-10;  // converged when an undamped step gains less than this
  double mu = kMuStart;
  int iterations = 0;
  bool converged = false;
  while (!converged && iterations < options.max_iterations) {
    ++iterations;
    if (rank == 0 || cost == 0.0) {
      converged = true;
      break;
    }
    const Eigen::JacobiSVD<MatX> svd = reduced(em);
    const VecX& s = svd.singularValues();
    const VecX g = svd.matrixU().transpose() * r;
    if (!s.allFinite() || !g.allFinite()) throw overflow();
    const double s1 = s[0];
    if (!(s1 > 0.0)) {
      converged = true;
      break;
    }
    bool accepted = false;
    for (; !accepted && mu <= kMuMax; mu = std::max(mu, kMuMin) * kMuStep) {
      // y = sum_i v_i s_i g_i / (s_i^2 + mu s_1^2), in units of s_1: (s_i/s_1) g_i / ((s_i/s_1)^2 + mu) / s_1
      VecX y = VecX::Zero(rank);
      for (int i = 0; i < s.size(); ++i) {
        const double t = s[i] / s1;
        if (usable(s, i)) y += svd.matrixV().col(i) * (t * g[i] / (t * t + mu) / s1);
      }
      if (!y.allFinite()) continue;
      VecX r_new;
      double cost_new = kInf;
      std::optional<PoeModel> candidate;
      try {
        candidate.emplace(em.apply(basis * y));
        cost_new = residual(*candidate, measurements, measure, w, r_new);
      } catch (const std::invalid_argument&) {  // a step through a non-positive scale or beyond the limits
      }
      if (cost_new < cost) {
        accepted = true;
        // a small gain counts only for an undamped-enough step (a heavily damped one is small anyway)
        converged = cost - cost_new <= kRelativeDecrease * cost && mu <= kMuStart;
        cost = cost_new;
        r = std::move(r_new);
        em = em.rebased(*candidate);
        mu /= kMuStep * kMuStep;  // the loop's increment follows: net one step down
      }
    }
    if (!accepted) converged = true;  // no step decreases the cost: the rounding floor
  }

  // covariance at the result on the determined subspace: Cov = basis W S^-2 W^T basis^T (times the variance
  // factor when the noise was not stated). Redundancy: with no more residuals than determined parameters the
  // fit passes through the noise and the cost says nothing about it (variance factor NaN).
  const double redundancy = static_cast<double>(r.size()) - rank;
  const double variance_factor = redundancy > 0 ? cost / redundancy : std::numeric_limits<double>::quiet_NaN();
  const double factor = stated ? 1.0 : variance_factor;
  MatX axes = MatX::Zero(n, rank);
  VecX sd = VecX::Constant(n, kInf);
  if (rank > 0 && factor >= 0.0) {
    const Eigen::JacobiSVD<MatX> svd = reduced(em);
    const VecX& s = svd.singularValues();
    bool full = true;
    for (int i = 0; i < s.size(); ++i) {
      if (usable(s, i)) {
        axes.col(i) = basis * svd.matrixV().col(i) * (std::sqrt(factor) / s[i]);
      } else {
        full = false;
      }
    }
    sd = axes.rowwise().norm();
    if (!full) sd.setConstant(kInf);  // the subspace lost rank on the way: nothing is certain
  }
  const MatX null = D0.asDiagonal() * V0.rightCols(n - rank);
  for (Eigen::Index i = 0; i < null.cols(); ++i) {
    for (Eigen::Index k = 0; k < n; ++k) {
      if (std::abs(V0(k, rank + i)) > 1e-8) sd[k] = kInf;  // moves along an undetermined direction
    }
  }
  CalibrationResult out{em.model(), em, identifiableCount(nominal, measure, options.free_pitch), std::move(nominal_rank),
                        residualStatistics(nominal, measurements, measure),
                        residualStatistics(em.model(), measurements, measure), iterations, converged,
                        w.position, w.rotation, stated, variance_factor, axes * axes.transpose(), sd, axes, null};
  out.sigma_position_stated = options.sigma_position.has_value();
  out.sigma_rotation_stated = options.sigma_rotation.has_value();
  return out;
}

// --- D-H standard deviations -------------------------------------------------------------------------

namespace {

// The D-H numbers of a conversion in a fixed order: base 4, per joint theta d alpha a pitch scale, tool 2;
// `angle` marks the entries compared modulo 2 pi.
VecX dhNumbers(const DhModel& dh, std::vector<bool>* angle = nullptr) {
  const int n = dh.dof();
  VecX out(4 + 6 * n + 2);
  std::vector<bool> is_angle;
  Eigen::Index k = 0;
  auto put = [&](double x, bool a) {
    out[k++] = x;
    is_angle.push_back(a);
  };
  auto row = [&](const DhParams& r) {
    put(r.theta, true);
    put(r.d, false);
    put(r.alpha, true);
    put(r.a, false);
  };
  row(dh.base());
  for (int i = 0; i < n; ++i) {
    row(dh.joint(i).link);
    put(dh.joint(i).type == JointType::Helical ? dh.joint(i).pitch : 0.0, false);
    put(dh.joint(i).scale, false);
  }
  put(dh.toolTheta(), true);
  put(dh.toolD(), false);
  if (angle) *angle = std::move(is_angle);
  return out;
}

// Puts the rows of the D-H numbers `x` on the sign branch of `center`: the canonical table keeps a >= 0, so a
// row whose a crosses 0 comes back as (theta + pi, d, -alpha, -a) with pi added to the next row's theta
// (A(theta + pi, d, -alpha, -a) = A(theta, d, alpha, a) Rz(pi)). Undone here, so that a length a that is 0
// within its uncertainty shows as a +- sd instead of a jump of theta by pi.
void alignBranches(VecX& x, const VecX& center, int dof) {
  auto row = [](int r) { return r == 0 ? 0 : 4 + 6 * (r - 1); };
  for (int r = 0; r <= dof; ++r) {
    const int k = row(r);
    if (std::abs(wrapAngle(x[k] - center[k])) <= M_PI / 2) continue;
    x[k] -= M_PI;
    x[k + 2] = -x[k + 2];
    x[k + 3] = -x[k + 3];
    x[r < dof ? row(r + 1) : 4 + 6 * dof] += M_PI;
  }
}

VecX dhDifference(const VecX& a, const VecX& b, const std::vector<bool>& angle) {
  VecX d = a - b;
  for (Eigen::Index k = 0; k < d.size(); ++k) {
    if (angle[static_cast<size_t>(k)]) d[k] = wrapAngle(d[k]);
  }
  return d;
}

}  // namespace

DhUncertainty dhUncertainty(const CalibrationResult& result) {
  const ErrorModel& em = result.error_model;
  DhUncertainty out{poeToDh(result.model), {}, {}, {}, {}, 0.0, 0.0};
  std::vector<bool> angle;
  const VecX center = dhNumbers(out.conversion.model, &angle);
  const int n = result.model.dof();
  VecX variance = VecX::Zero(center.size());
  auto spread = [&](const VecX& direction) -> VecX {  // half the D-H difference between +direction and -direction
    try {
      VecX plus = dhNumbers(poeToDh(em.apply(direction)).model);
      VecX minus = dhNumbers(poeToDh(em.apply(-direction)).model);
      alignBranches(plus, center, n);
      alignBranches(minus, center, n);
      return 0.5 * dhDifference(plus, minus, angle);
    } catch (const std::invalid_argument&) {  // a one-sigma step through a non-positive scale
      return VecX::Constant(center.size(), kInf);
    }
  };
  for (Eigen::Index i = 0; i < result.principal_axes.cols(); ++i) {
    variance += spread(result.principal_axes.col(i)).cwiseAbs2();
  }
  // an undetermined direction: a small step (kProbe in dimensionless units: lengths and pitches over L); a
  // D-H number it moves by more than 1e-6 of that (angles and scales in their units, lengths over L) is
  // not determined
  constexpr double kProbe = 1e-6, kMoved = 1e-6;
  const double L = result.model.lengthScale();
  const auto& parameters = em.parameters();
  VecX per_unit(em.size());  // a parameter's dimensionless unit: L for lengths and pitches, 1 otherwise
  for (int k = 0; k < em.size(); ++k) per_unit[k] = parameters[static_cast<size_t>(k)].unit == "rad" ||
                                                            parameters[static_cast<size_t>(k)].unit == "1"
                                                        ? 1.0
                                                        : L;
  VecX dh_unit = VecX::Ones(center.size());  // L for d, a, pitch and the tool's d
  for (Eigen::Index k = 0; k < center.size(); ++k) {
    const bool scale_entry = k >= 4 && k < 4 + 6 * n && (k - 4) % 6 == 5;
    if (!angle[static_cast<size_t>(k)] && !scale_entry) dh_unit[k] = L;
  }
  for (Eigen::Index i = 0; i < result.undetermined_directions.cols(); ++i) {
    const VecX dir = result.undetermined_directions.col(i);
    const VecX moved = spread(kProbe * dir / dir.cwiseQuotient(per_unit).norm());
    for (Eigen::Index k = 0; k < moved.size(); ++k) {
      if (!(std::abs(moved[k]) <= kMoved * kProbe * dh_unit[k])) variance[k] = kInf;
    }
  }
  // d of a row placed by a parallel axis is the conversion's free choice (0): nothing can determine it
  for (size_t r = 0; r < out.conversion.rows.size(); ++r) {
    if (out.conversion.rows[r].parallel) variance[r == 0 ? 1 : 4 + 6 * static_cast<Eigen::Index>(r - 1) + 1] = kInf;
  }
  // a D-H number is not known better than its rounding (eps times its size or unit): a noise-free fit's
  // one-sigma steps below that move it by exactly 0, which must not read as "+- 0"
  for (Eigen::Index k = 0; k < center.size(); ++k) {
    const bool pitch_entry = k >= 4 && k < 4 + 6 * n && (k - 4) % 6 == 4;
    if (pitch_entry && out.conversion.model.joint(static_cast<int>((k - 4) / 6)).type != JointType::Helical) {
      continue;  // no pitch: its standard deviation stays 0
    }
    const double resolution = kEps * std::max(std::abs(center[k]), dh_unit[k]);
    variance[k] = std::max(variance[k], resolution * resolution);
  }
  // no redundancy and no stated noise: the covariance is unknown
  if (!result.noise_stated && !(result.variance_factor >= 0.0)) variance.setConstant(kInf);
  const VecX sd = variance.cwiseSqrt();
  Eigen::Index k = 0;
  auto row = [&](DhParams& r) {
    r.theta = sd[k++];
    r.d = sd[k++];
    r.alpha = sd[k++];
    r.a = sd[k++];
  };
  row(out.base);
  out.links.resize(static_cast<size_t>(n));
  out.pitch.resize(static_cast<size_t>(n));
  out.scale.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    row(out.links[static_cast<size_t>(i)]);
    out.pitch[static_cast<size_t>(i)] = sd[k++];
    out.scale[static_cast<size_t>(i)] = sd[k++];
  }
  out.tool_theta = sd[k++];
  out.tool_d = sd[k++];
  return out;
}

}  // namespace lowpair
