#include "lowpair/calibration.hpp"
#include "linalg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
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

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The rows of one pose: one measurement (Pose, Position), or one per target (Targets: the points `T p_t`,
// their 3 columns `R` after the spatial-twist columns S).
void poseRows(const Mat6X& S, const Pose& T, Measure measure, const std::vector<Vec3>& targets, int dof,
              Eigen::Ref<MatX> rows) {
  if (measure != Measure::Targets) {
    measurementRows(S, T.p, measure, dof, rows.leftCols(S.cols()));
    return;
  }
  rows.setZero();
  for (size_t t = 0; t < targets.size(); ++t) {
    auto block = rows.middleRows(3 * static_cast<Eigen::Index>(t), 3);
    measurementRows(S, T.R * targets[t] + T.p, Measure::Position, dof, block.leftCols(S.cols()));
    block.middleCols<3>(S.cols() + 3 * static_cast<Eigen::Index>(t)) = T.R;
  }
}

// Rows per pose (Targets: 3 per target).
int rowsPerPose(Measure measure, const std::vector<Vec3>& targets) {
  return measure == Measure::Targets ? 3 * static_cast<int>(targets.size()) : rowsPerPose(measure);
}

void checkTargets(Measure measure, const std::vector<Vec3>& targets) {
  LP_CHECK((measure == Measure::Targets) == !targets.empty(), "Measure::Targets needs targets' points, and only it");
  for (const Vec3& t : targets) LP_CHECK(t.allFinite(), "a target's point is not finite");
}

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
    if (measure != Measure::Pose || r % per >= 3) A.row(r) /= L;
  }
  return A;
}

}  // namespace

const char* measureName(Measure measure) {
  switch (measure) {
    case Measure::Pose: return "pose";
    case Measure::Position: return "position";
    case Measure::Targets: return "targets";
  }
  return "pose";
}

int rowsPerMeasurement(Measure measure) { return rowsPerPose(measure); }

ParameterCount identifiableCount(const PoeModel& model, Measure measure, bool free_pitch, int targets) {
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
  count.tool = measure == Measure::Pose ? 6 : measure == Measure::Position ? 3 : 3 * targets;
  return count;
}

// --- the error model ---------------------------------------------------------------------------------

const char* parameterSetName(ParameterSet set) {
  switch (set) {
    case ParameterSet::Full: return "full";
    case ParameterSet::Lines: return "lines";
    case ParameterSet::Offsets: return "offsets";
    case ParameterSet::Named: return "named";
  }
  return "full";
}

namespace {

bool inSet(ParameterKind kind, ParameterSet set) {
  switch (kind) {
    case ParameterKind::Tilt:
    case ParameterKind::Shift:
    case ParameterKind::Pitch:
      return set == ParameterSet::Full || set == ParameterSet::Lines;
    case ParameterKind::Scale:
      return set == ParameterSet::Full;
    case ParameterKind::Offset:
    case ParameterKind::BaseRotation:
    case ParameterKind::BaseTranslation:
      return set == ParameterSet::Offsets;
    case ParameterKind::ToolRotation:
    case ParameterKind::ToolTranslation:
    case ParameterKind::TargetPoint:
      return true;
  }
  return false;
}

// The point about which the base parameters turn the model: the first joint's line point nearest the
// frame origin (the robot's foot, wherever the measurement frame is), or the origin for a prismatic joint.
Vec3 baseCenter(const PoeModel& model) {
  if (model.dof() == 0) return Vec3::Zero();
  const Joint& j = model.joint(0);
  return j.type == JointType::Prismatic ? Vec3::Zero() : Vec3(j.axis().cross(j.moment()));
}

}  // namespace

namespace {
ErrorModelSpec specWithPitch(bool free_pitch) {
  ErrorModelSpec spec;
  spec.free_pitch = free_pitch;
  return spec;
}
}  // namespace

ErrorModel::ErrorModel(const PoeModel& model, bool free_pitch) : ErrorModel(model, specWithPitch(free_pitch)) {}

ErrorModel::ErrorModel(const PoeModel& model, const ErrorModelSpec& spec) : model_(model), spec_(spec) {
  auto add = [&](ParameterKind kind, int joint, int component, std::string name, const char* unit) {
    all_.push_back(Parameter{kind, joint, component, std::move(name), unit});
  };
  const char* axes[3] = {"x", "y", "z"};
  center_ = baseCenter(model);
  for (int k = 0; k < 3; ++k) add(ParameterKind::BaseRotation, -1, k, std::string("base.r") + axes[k], "rad");
  for (int k = 0; k < 3; ++k) add(ParameterKind::BaseTranslation, -1, k, std::string("base.") + axes[k], "length");
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
      if (hasPitch(j, spec.free_pitch)) add(ParameterKind::Pitch, i, 0, tag + ".pitch", "length/rad");
    }
    add(ParameterKind::Scale, i, 0, tag + ".scale", "1");
    add(ParameterKind::Offset, i, 0, tag + ".offset", j.type == JointType::Prismatic ? "length" : "rad");
    basis_.push_back(basis);
  }
  if (spec.targets.empty()) {
    for (int k = 0; k < 3; ++k) add(ParameterKind::ToolRotation, -1, k, std::string("tool.r") + axes[k], "rad");
    for (int k = 0; k < 3; ++k) add(ParameterKind::ToolTranslation, -1, k, std::string("tool.") + axes[k], "length");
  } else {
    LP_CHECK(spec.target_names.empty() || spec.target_names.size() == spec.targets.size(),
             "error model: " << spec.target_names.size() << " target names for " << spec.targets.size() << " targets");
    for (size_t t = 0; t < spec.targets.size(); ++t) {
      LP_CHECK(spec.targets[t].allFinite(), "error model: target " << t + 1 << " has a non-finite point");
      const std::string name = spec.target_names.empty() ? std::to_string(t + 1) : spec.target_names[t];
      for (int k = 0; k < 3; ++k) add(ParameterKind::TargetPoint, static_cast<int>(t), k, "target." + name + "." + axes[k], "length");
    }
  }
  if (spec.set == ParameterSet::Named) {
    LP_CHECK(!spec.names.empty(), "error model: no parameter named");
    for (const std::string& name : spec.names) {
      const auto it = std::find_if(all_.begin(), all_.end(), [&](const Parameter& p) { return p.name == name; });
      if (it == all_.end()) {
        std::ostringstream known;
        for (size_t k = 0; k < all_.size() && k < 12; ++k) known << (k ? ", " : "") << all_[k].name;
        LP_CHECK(false, "error model: no parameter named '" << name << "' (the model's: " << known.str()
                                                            << (all_.size() > 12 ? ", ..." : "") << ")");
      }
      const int index = static_cast<int>(it - all_.begin());
      LP_CHECK(std::find(selected_.begin(), selected_.end(), index) == selected_.end(),
               "error model: parameter '" << name << "' named twice");
      selected_.push_back(index);
    }
    std::sort(selected_.begin(), selected_.end());
  } else {
    for (size_t k = 0; k < all_.size(); ++k) {
      if (inSet(all_[k].kind, spec.set)) selected_.push_back(static_cast<int>(k));
    }
  }
  for (int k : selected_) parameters_.push_back(all_[static_cast<size_t>(k)]);
}

VecX ErrorModel::expanded(const Eigen::Ref<const VecX>& delta) const {
  LP_CHECK(delta.size() == size(), "error model: expected " << size() << " parameters, got " << delta.size());
  LP_CHECK(delta.allFinite(), "error model: non-finite parameter increment");
  VecX all = VecX::Zero(static_cast<Eigen::Index>(all_.size()));
  for (int k = 0; k < size(); ++k) all[selected_[static_cast<size_t>(k)]] = delta[k];
  return all;
}

PoeModel ErrorModel::apply(const Eigen::Ref<const VecX>& delta) const {
  const VecX d = expanded(delta);
  std::vector<Joint> joints = model_.joints();
  Eigen::Index k = 0;
  const Vec3 base_r = d.segment<3>(0), base_t = d.segment<3>(3);
  k = 6;
  for (int i = 0; i < model_.dof(); ++i) {
    Joint& j = joints[static_cast<size_t>(i)];
    const auto& basis = basis_[static_cast<size_t>(i)];
    const int directions = j.type == JointType::Prismatic ? 2 : 4;
    Vec6 eta = Vec6::Zero();
    for (int b = 0; b < directions; ++b) eta += d[k++] * basis[static_cast<size_t>(b)];
    const Vec6 xi = adjointApply(expSE3(eta), j.twist);
    if (j.type == JointType::Prismatic) {
      j.twist << Vec3::Zero(), xi.tail<3>().normalized();
    } else {
      const Vec3 w = xi.head<3>().normalized();
      const Vec3 v = xi.tail<3>();
      const Vec3 v_line = v - w.dot(v) * w;  // the moment p x w without pitch
      double pitch = j.type == JointType::Helical ? j.pitch : 0.0;
      if (hasPitch(j, spec_.free_pitch)) pitch += d[k++];
      if (spec_.free_pitch) {  // the type follows the pitch: revolute when the pitch is rounding relative to L
        const bool rounding = std::abs(pitch) <= kPitchZero * kEps * model_.lengthScale();
        j.type = rounding ? JointType::Revolute : JointType::Helical;
        if (rounding) pitch = 0.0;
      }
      j.pitch = j.type == JointType::Helical ? pitch : 0.0;
      j.twist << w, v_line + j.pitch * w;
    }
    j.scale += d[k++];
    LP_CHECK(j.scale > 0.0, jointLabel(i, j.name) << ": the increment makes the scale " << j.scale << " (not positive)");
    j.offset += d[k++];
  }
  Pose tool = model_.toolPose();
  if (spec_.targets.empty()) {
    const Vec3 r = d.segment<3>(k), t = d.segment<3>(k + 3);
    tool = expSE3(twist(r, tool.p.cross(r) + t)) * tool;
  }
  PoeModel out(std::move(joints), tool, model_.name());
  if (base_r.any() || base_t.any()) out = movedModel(out, expSE3(twist(base_r, center_.cross(base_r) + base_t)));
  return out;
}

std::vector<Vec3> ErrorModel::applyTargets(const Eigen::Ref<const VecX>& delta) const {
  const VecX d = expanded(delta);
  std::vector<Vec3> out = spec_.targets;
  const Eigen::Index first = d.size() - 3 * static_cast<Eigen::Index>(out.size());
  for (size_t t = 0; t < out.size(); ++t) out[t] += d.segment<3>(first + 3 * static_cast<Eigen::Index>(t));
  return out;
}

ErrorModel ErrorModel::rebased(const PoeModel& model) const { return rebased(model, spec_.targets); }

ErrorModel ErrorModel::rebased(const PoeModel& model, const std::vector<Vec3>& targets) const {
  LP_CHECK(model.dof() == model_.dof(), "error model: rebased onto a model with another joint count");
  LP_CHECK(targets.size() == spec_.targets.size(), "error model: rebased with another number of targets");
  ErrorModel out = *this;
  out.model_ = model;
  out.spec_.targets = targets;
  return out;
}

Pose ErrorModel::jacobian(const Eigen::Ref<const VecX>& q, Measure measure, Eigen::Ref<MatX> rows, int target) const {
  checkJointVector(q, model_.dof());
  LP_CHECK(rows.rows() == rowsPerPose(measure) && rows.cols() == size(), "error model: rows must be "
                                                                           << rowsPerPose(measure) << " x " << size());
  const bool targets = !spec_.targets.empty();
  LP_CHECK(targets == (measure == Measure::Targets), "error model: Measure::Targets needs targets, and only it");
  LP_CHECK(!targets || (target >= 0 && target < static_cast<int>(spec_.targets.size())),
           "error model: target " << target << " of " << spec_.targets.size());
  const auto twists = static_cast<Eigen::Index>(all_.size()) - (targets ? 3 * static_cast<Eigen::Index>(spec_.targets.size()) : 0);
  Mat6X S(6, twists);
  Eigen::Index c = 0;
  for (int k = 0; k < 3; ++k) S.col(c++) = twist(Vec3::Unit(k), center_.cross(Vec3::Unit(k)));
  for (int k = 0; k < 3; ++k) S.col(c++) = twist(Vec3::Zero(), Vec3::Unit(k));
  Pose P, E;  // P = exp(xi_1 x_1) ... exp(xi_{i-1} x_{i-1}) before joint i
  for (int i = 0; i < model_.dof(); ++i) {
    const Joint& j = model_.joint(i);
    jointExp(j, q[i], E);
    const Pose next = P * E;
    const int directions = j.type == JointType::Prismatic ? 2 : 4;
    for (int b = 0; b < directions; ++b) {  // (Ad(P_i) - Ad(P_{i+1})) eta
      const Vec6& eta = basis_[static_cast<size_t>(i)][static_cast<size_t>(b)];
      S.col(c++) = twistDifference(adjointApply(P, eta), adjointApply(next, eta), model_.dof());
    }
    if (hasPitch(j, spec_.free_pitch)) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), j.axis())) * j.motion(q[i]);
    const Vec6 xi = adjointApply(P, j.twist);
    S.col(c++) = xi * (q[i] + j.offset);  // scale
    S.col(c++) = xi * j.scale;            // offset
    P = next;
  }
  const Pose T = P * model_.toolPose();
  if (!targets) {
    const Vec3 p_tool = model_.toolPose().p;
    for (int k = 0; k < 3; ++k) S.col(c++) = adjointApply(P, twist(Vec3::Unit(k), p_tool.cross(Vec3::Unit(k))));
    for (int k = 0; k < 3; ++k) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), Vec3::Unit(k)));
  }
  const int per = rowsPerPose(measure);
  MatX all(per, static_cast<Eigen::Index>(all_.size()));
  all.setZero();
  const Vec3 point = targets ? Vec3(T.R * spec_.targets[static_cast<size_t>(target)] + T.p) : T.p;
  measurementRows(S, point, measure == Measure::Targets ? Measure::Position : measure, model_.dof(), all.leftCols(twists));
  if (targets) all.middleCols<3>(twists + 3 * static_cast<Eigen::Index>(target)) = T.R;
  for (int k = 0; k < size(); ++k) rows.col(k) = all.col(selected_[static_cast<size_t>(k)]);
  if (targets) return Pose{T.R, point};
  return T;
}

MatX fullErrorModelJacobian(const PoeModel& model, const std::vector<VecX>& q, Measure measure, bool free_pitch,
                            const std::vector<Vec3>& targets) {
  checkPoses(q, model.dof());
  checkTargets(measure, targets);
  int cols = 6;
  for (const Joint& j : model.joints()) cols += 6 + (hasPitch(j, free_pitch) ? 1 : 0) + 2;
  const int per = rowsPerPose(measure, targets);
  MatX J(per * static_cast<Eigen::Index>(q.size()), cols + 3 * static_cast<Eigen::Index>(targets.size()));
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
    poseRows(S, P * model.toolPose(), measure, targets, model.dof(), J.middleRows(per * static_cast<Eigen::Index>(m), per));
  }
  return J;
}

MatX dhIdentificationJacobian(const DhModel& model, const std::vector<VecX>& q, Measure measure, bool free_pitch,
                              std::vector<std::string>* names, const std::vector<Vec3>& targets) {
  checkPoses(q, model.dof());
  checkTargets(measure, targets);
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
  for (size_t t = 0; t < targets.size(); ++t) {
    for (const char* axis : {".x", ".y", ".z"}) columns.push_back("target." + std::to_string(t + 1) + axis);
  }
  const int per = rowsPerPose(measure, targets);
  MatX J(per * static_cast<Eigen::Index>(q.size()), static_cast<Eigen::Index>(columns.size()));
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
    poseRows(S, T, measure, targets, model.dof(), J.middleRows(per * static_cast<Eigen::Index>(m), per));
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
                                       bool free_pitch, const std::vector<Vec3>& targets) {
  checkPoses(q, model.dof());
  checkTargets(measure, targets);
  Identifiability out;
  out.measure = measure;
  out.free_pitch = free_pitch;
  out.expected = identifiableCount(model, measure, free_pitch, static_cast<int>(targets.size()));
  ErrorModelSpec spec;
  spec.free_pitch = free_pitch;
  spec.targets = targets;
  const ErrorModel em(model, spec);
  out.parameters = em.parameters();
  const int per = rowsPerMeasurement(measure), k = measure == Measure::Targets ? static_cast<int>(targets.size()) : 1;
  const auto poses = static_cast<int>(q.size());
  MatX J(per * static_cast<Eigen::Index>(poses) * k, em.size());
  for (int m = 0; m < poses; ++m) {
    for (int t = 0; t < k; ++t) {
      em.jacobian(q[static_cast<size_t>(m)], measure, J.middleRows(per * (m * k + t), per), measure == Measure::Targets ? t : -1);
    }
  }
  const double L = model.lengthScale();
  out.poe = analyzeRank(J, measure, L, poses);
  const MatX full = fullErrorModelJacobian(model, q, measure, free_pitch, targets);
  out.full_model_rank = analyzeRank(full, measure, L, poses).rank;
  out.full_model_columns = static_cast<int>(full.cols());
  const DhConversion dh = poeToDh(model);
  out.dh = analyzeRank(dhIdentificationJacobian(dh.model, q, measure, free_pitch, &out.dh_parameters, targets), measure,
                       L, poses);
  return out;
}

// --- calibration -------------------------------------------------------------------------------------

namespace {

void checkTargetIndex(const Measurement& m, Measure measure, size_t targets) {
  if (measure != Measure::Targets) return;
  LP_CHECK(m.target >= 0 && static_cast<size_t>(m.target) < targets,
           "measurement of target " << m.target << ": there are " << targets << " targets");
}

// The measured quantity the model predicts (Targets: the point `T p_t`, rotation `T.R`).
Pose predict(const PoeModel& model, Data& data, const Measurement& m, Measure measure, const std::vector<Vec3>& targets) {
  forwardKinematics(model, data, m.q);
  if (measure != Measure::Targets) return data.T_base_tool;
  checkTargetIndex(m, measure, targets.size());
  const Pose& T = data.T_base_tool;
  return Pose{T.R, T.R * targets[static_cast<size_t>(m.target)] + T.p};
}

// A measurement's errors against its prediction: position (length) and rotation (rad; 0 for points).
struct MeasurementErrors {
  double position = 0.0, rotation = 0.0;
};
MeasurementErrors measurementErrors(const Pose& predicted, const Measurement& m, Measure measure) {
  return {(m.T_base_tool.p - predicted.p).norm(),
          measure == Measure::Pose ? rotationAngle(predicted.R.transpose() * m.T_base_tool.R) : 0.0};
}

}  // namespace

Pose predictedMeasurement(const PoeModel& model, const Measurement& m, Measure measure, const std::vector<Vec3>& targets) {
  checkJointVector(m.q, model.dof());
  Data data(model);
  return predict(model, data, m, measure, targets);
}

ResidualStatistics residualStatistics(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Vec3>& targets) {
  ResidualStatistics s;
  Data data(model);
  double sum_p = 0.0, sum_r = 0.0;
  for (const Measurement& m : measurements) {
    checkJointVector(m.q, model.dof());
    const auto [ep, er] = measurementErrors(predict(model, data, m, measure, targets), m, measure);
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

PoeModel movedModel(const PoeModel& model, const Pose& T_frame_base) {
  LP_CHECK(T_frame_base.p.allFinite() && T_frame_base.R.allFinite(), "movedModel: non-finite pose");
  std::vector<Joint> joints = model.joints();
  for (Joint& j : joints) {
    const Vec6 xi = adjointApply(T_frame_base, j.twist);
    if (j.type == JointType::Prismatic) {
      j.twist << Vec3::Zero(), xi.tail<3>().normalized();
    } else {
      const Vec3 w = xi.head<3>().normalized();
      j.twist << w, xi.tail<3>();
    }
  }
  return PoeModel(std::move(joints), T_frame_base * model.toolPose(), model.name());
}

const char* lossName(Loss loss) {
  switch (loss) {
    case Loss::Squared: return "squared";
    case Loss::Huber: return "huber";
    case Loss::Cauchy: return "cauchy";
  }
  return "squared";
}

namespace {

void checkMeasurements(const PoeModel& nominal, const std::vector<Measurement>& measurements, Measure measure,
                       size_t targets) {
  LP_CHECK(!measurements.empty(), "calibrate: no measurements");
  for (size_t m = 0; m < measurements.size(); ++m) {
    const Measurement& x = measurements[m];
    LP_CHECK(x.q.size() == nominal.dof(), "measurement " << m + 1 << ": " << x.q.size() << " joint values for "
                                                          << nominal.dof() << " joints");
    LP_CHECK(x.q.allFinite() && x.T_base_tool.p.allFinite() && x.T_base_tool.R.allFinite(),
             "measurement " << m + 1 << ": non-finite number");
    checkTargetIndex(x, measure, targets);
  }
  LP_CHECK(measure != Measure::Targets || targets > 0, "calibrate: target measurements need at least one target");
}

// Horn / Kabsch-Umeyama: the rotation R and translation t minimizing sum |y - (R x + t)|^2 (+ rotations:
// sum L^2 |R_meas - R R_pred|_F^2). `determined` false when the points are collinear and no rotation is given.
Pose rigidFit(const std::vector<Vec3>& x, const std::vector<Vec3>& y, const std::vector<Mat3>* R_pred,
              const std::vector<Mat3>* R_meas, double L, bool& determined) {
  Vec3 cx = Vec3::Zero(), cy = Vec3::Zero();
  for (size_t i = 0; i < x.size(); ++i) {
    cx += x[i];
    cy += y[i];
  }
  cx /= static_cast<double>(x.size());
  cy /= static_cast<double>(y.size());
  Mat3 M = Mat3::Zero();
  for (size_t i = 0; i < x.size(); ++i) M += (y[i] - cy) * (x[i] - cx).transpose();
  const Eigen::JacobiSVD<Mat3> points(M);
  determined = points.singularValues()[1] > 1e-9 * points.singularValues()[0];
  if (R_pred) {
    for (size_t i = 0; i < R_pred->size(); ++i) M += L * L * (*R_meas)[i] * (*R_pred)[i].transpose();
    determined = true;
  }
  Pose g;
  if (!determined) return g;
  const Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  g.R = svd.matrixU() * D * svd.matrixV().transpose();
  g.p = cy - g.R * cx;
  return g;
}

Registration registration(const PoeModel& model, const std::vector<Measurement>& measurements, Measure measure,
                          const std::vector<Target>& targets, bool frame) {
  checkMeasurements(model, measurements, measure, targets.size());
  Registration out;
  out.targets.resize(targets.size(), Vec3::Zero());
  out.estimated.resize(targets.size(), false);
  bool estimate = false;
  for (size_t t = 0; t < targets.size(); ++t) {
    if (targets[t].point_tool) {
      LP_CHECK(targets[t].point_tool->allFinite(), "target " << targets[t].name << ": non-finite point");
      out.targets[t] = *targets[t].point_tool;
    } else {
      out.estimated[t] = estimate = true;
    }
  }
  const double L = model.lengthScale();
  Data data(model);
  std::vector<Pose> T(measurements.size());
  for (size_t m = 0; m < measurements.size(); ++m) {
    forwardKinematics(model, data, measurements[m].q);
    T[m] = data.T_base_tool;
  }
  std::vector<Vec3> x(measurements.size()), y(measurements.size());
  std::vector<Mat3> R_pred, R_meas;
  if (measure == Measure::Pose) {
    for (size_t m = 0; m < measurements.size(); ++m) {
      R_pred.push_back(T[m].R);
      R_meas.push_back(measurements[m].T_base_tool.R);
    }
  }
  for (size_t m = 0; m < measurements.size(); ++m) y[m] = measurements[m].T_base_tool.p;
  // alternate: the frame for the current points, then each unknown point for the frame (the mean of its
  // measured points in the predicted tool frame), until neither moves by more than rounding
  constexpr int kMaxAlternations = 1000;
  constexpr double kSettled = 1e-13;
  for (out.iterations = 1; out.iterations <= kMaxAlternations; ++out.iterations) {
    for (size_t m = 0; m < measurements.size(); ++m) {
      const int t = measurements[m].target;
      x[m] = measure == Measure::Targets ? Vec3(T[m].R * out.targets[static_cast<size_t>(t)] + T[m].p) : T[m].p;
    }
    Pose g;
    if (frame) {
      g = rigidFit(x, y, measure == Measure::Pose ? &R_pred : nullptr, measure == Measure::Pose ? &R_meas : nullptr, L,
                   out.determined);
    }
    double moved = rotationAngle(g.R.transpose() * out.T_meas_base.R) + (g.p - out.T_meas_base.p).norm() / L;
    out.T_meas_base = g;
    if (estimate) {
      std::vector<Vec3> sum(targets.size(), Vec3::Zero());
      std::vector<int> count(targets.size(), 0);
      const Pose g_inv = g.inverse();
      for (size_t m = 0; m < measurements.size(); ++m) {
        const auto t = static_cast<size_t>(measurements[m].target);
        if (!out.estimated[t]) continue;
        sum[t] += T[m].R.transpose() * (g_inv.R * y[m] + g_inv.p - T[m].p);
        ++count[t];
      }
      for (size_t t = 0; t < targets.size(); ++t) {
        if (!out.estimated[t]) continue;
        LP_CHECK(count[t] > 0, "target " << targets[t].name << " has no point and no measurement to estimate it from");
        const Vec3 p = sum[t] / count[t];
        moved = std::max(moved, (p - out.targets[t]).norm() / L);
        out.targets[t] = p;
      }
    }
    if (!estimate || moved <= kSettled) break;
  }
  out.iterations = std::min(out.iterations, kMaxAlternations);
  return out;
}

// The weights of the residuals: noise per coordinate, and the robust loss' per measurement.
struct Weights {
  double position = 1.0, rotation = 1.0;  // sigma_position (length), sigma_rotation (rad)
};

// Weighted residual r = [log(R_meas R^T) / sigma_r; (p_meas - p) / sigma_p] per measurement (or the
// position part alone), each measurement's block times sqrt(its robust weight), and its squared norm.
double residual(const PoeModel& model, const std::vector<Vec3>& targets, const std::vector<Measurement>& measurements,
                Measure measure, const Weights& w, const VecX& robust, VecX& r) {
  const int per = rowsPerMeasurement(measure);
  r.resize(per * static_cast<Eigen::Index>(measurements.size()));
  Data data(model);
  for (size_t m = 0; m < measurements.size(); ++m) {
    const Pose T = predict(model, data, measurements[m], measure, targets);
    const Pose& M = measurements[m].T_base_tool;
    auto rows = r.segment(per * static_cast<Eigen::Index>(m), per);
    if (measure == Measure::Pose) {
      rows.head<3>() = logSO3(M.R * T.R.transpose()) / w.rotation;
      rows.tail<3>() = (M.p - T.p) / w.position;
    } else {
      rows = (M.p - T.p) / w.position;
    }
    rows *= std::sqrt(robust[static_cast<Eigen::Index>(m)]);
  }
  return r.squaredNorm();
}

MatX weightedJacobian(const ErrorModel& em, const std::vector<Measurement>& measurements, Measure measure,
                      const Weights& w, const VecX& robust) {
  const int per = rowsPerMeasurement(measure);
  MatX J(per * static_cast<Eigen::Index>(measurements.size()), em.size());
  for (size_t m = 0; m < measurements.size(); ++m) {
    auto rows = J.middleRows(per * static_cast<Eigen::Index>(m), per);
    em.jacobian(measurements[m].q, measure, rows, measurements[m].target);
    if (measure == Measure::Pose) {
      rows.topRows<3>() /= w.rotation;
      rows.bottomRows<3>() /= w.position;
    } else {
      rows /= w.position;
    }
    rows *= std::sqrt(robust[static_cast<Eigen::Index>(m)]);
  }
  return J;
}

// The median of the normalized residual u of a measurement with noise-unit Gaussian residuals: u is chi
// with 3 degrees of freedom for a point; for a pose, chi with 6 over sqrt(2). (Medians of chi-square with 3
// and 6 degrees of freedom: 2.365974 and 5.348121.)
double medianNormalized(Measure measure) {
  return measure == Measure::Pose ? std::sqrt(5.348121 / 2.0) : std::sqrt(2.365974);
}

double robustWeight(Loss loss, double u) {
  switch (loss) {
    case Loss::Squared: return 1.0;
    case Loss::Huber: return u <= kHuberThreshold ? 1.0 : kHuberThreshold / u;
    case Loss::Cauchy: return 1.0 / (1.0 + (u / kCauchyScale) * (u / kCauchyScale));
  }
  return 1.0;
}

// The robust loss's rho of a normalized residual u (rho(u) = u^2 for least squares): what a fit with that
// loss minimizes, so what its held-out measurements are scored by.
double robustRho(Loss loss, double u) {
  switch (loss) {
    case Loss::Squared: return u * u;
    case Loss::Huber: return u <= kHuberThreshold ? u * u : 2.0 * kHuberThreshold * u - kHuberThreshold * kHuberThreshold;
    case Loss::Cauchy: return kCauchyScale * kCauchyScale * std::log1p((u / kCauchyScale) * (u / kCauchyScale));
  }
  return u * u;
}

double median(std::vector<double> x) {
  if (x.empty()) return 0.0;
  const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

// Per measurement: u = sqrt(|r_m|^2 / (rows / 3)) of the (robust-unweighted) weighted residual.
std::vector<double> normalizedResiduals(const VecX& r, Measure measure) {
  const int per = rowsPerMeasurement(measure);
  std::vector<double> u(static_cast<size_t>(r.size() / per));
  for (size_t m = 0; m < u.size(); ++m) {
    u[m] = std::sqrt(r.segment(per * static_cast<Eigen::Index>(m), per).squaredNorm() / (per / 3.0));
  }
  return u;
}

}  // namespace

Registration registerMeasurementFrame(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Target>& targets) {
  return registration(model, measurements, measure, targets, true);
}

CalibrationResult calibrate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                            const CalibrationOptions& options) {
  const Measure measure = options.measure;
  checkMeasurements(nominal, measurements, measure, options.targets.size());
  for (const auto& s : {options.sigma_position, options.sigma_rotation}) {
    LP_CHECK(!s || (*s > 0.0 && std::isfinite(*s)), "calibrate: noise levels must be positive and finite");
  }
  LP_CHECK(options.max_iterations >= 0, "calibrate: max_iterations must be >= 0");
  LP_CHECK(options.outlier_threshold > 0.0 && std::isfinite(options.outlier_threshold),
           "calibrate: the outlier threshold must be positive and finite");
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

  // the measurement frame (and the unknown targets' points), then the fit from there
  const Registration reg = registration(nominal, measurements, measure, options.targets, options.register_frame);
  const PoeModel start = movedModel(nominal, reg.T_meas_base);
  ErrorModelSpec spec;
  spec.free_pitch = options.free_pitch;
  spec.set = options.parameters;
  spec.names = options.parameter_names;
  spec.targets = reg.targets;
  for (const Target& t : options.targets) spec.target_names.push_back(t.name);
  if (std::any_of(spec.target_names.begin(), spec.target_names.end(), [](const std::string& n) { return n.empty(); })) {
    spec.target_names.clear();
  }
  ErrorModel em(start, spec);

  const auto count = static_cast<Eigen::Index>(measurements.size());
  const auto poses = static_cast<int>(count);
  VecX robust = VecX::Ones(count);
  VecX r;
  double cost = residual(start, reg.targets, measurements, measure, w, robust, r);
  auto overflow = [&] {
    std::ostringstream text;
    text << "calibrate: the weighted residuals or Jacobian overflow (sigma_position " << w.position
         << " for a robot of size L = " << L << "): state the noise and the measurements in the robot's length unit";
    return std::invalid_argument(text.str());
  };
  // (the column norms square the entries: a stated noise small enough to leave the residuals finite may
  // still overflow them, and a column left unscaled would take the whole rank)
  const MatX J_nominal = weightedJacobian(em, measurements, measure, w, robust);
  if (!std::isfinite(cost) || !J_nominal.colwise().squaredNorm().allFinite()) throw overflow();
  // the determined subspace, fixed at the (registered) nominal: steps are `basis * y`
  VecX D0;
  MatX V0;
  RankAnalysis nominal_rank = analyzeDimensionless(J_nominal, poses, &D0, &V0);
  const int rank = nominal_rank.rank;
  const Eigen::Index n = em.size();
  const MatX basis = D0.asDiagonal() * V0.leftCols(rank);
  // the reduced problem at an iterate: A = J basis (rows x rank) and its SVD
  auto reduced = [&](const ErrorModel& at) {
    return Eigen::JacobiSVD<MatX>(weightedJacobian(at, measurements, measure, w, robust) * basis,
                                  Eigen::ComputeThinU | Eigen::ComputeThinV);
  };
  // the nominal's rule (its n: every parameter), not one relaxed to the reduced problem's `rank` columns
  auto usable = [&](const VecX& s, int i) { return s[i] > numericalRankTolerance(s[0], static_cast<double>(n)); };

  // Levenberg-Marquardt with the damping relative to sigma_1^2 (mu): no sigma_1^2 is ever formed, so a
  // Jacobian near the overflow limit (a tiny stated noise) damps like any other, and mu's bounds end the
  // inner loop after at most log10(kMuMax / kMuMin) + 1 rejections.
  constexpr double kMuStart = 1e-6, kMuMin = 1e-12, kMuMax = 1e16, kMuStep = 10.0;
  constexpr double kRelativeDecrease = 1e-10;  // converged when an undamped step gains less than this
  int iterations = 0;
  VecX estimate = VecX::Zero(n);
  auto fit = [&]() {  // one Levenberg-Marquardt run at the current robust weights; true when converged
    double mu = kMuStart;
    for (int pass = 0; pass < options.max_iterations; ++pass) {
      ++iterations;
      if (rank == 0 || cost == 0.0) return true;
      const Eigen::JacobiSVD<MatX> svd = reduced(em);
      const VecX& s = svd.singularValues();
      const VecX g = svd.matrixU().transpose() * r;
      if (!s.allFinite() || !g.allFinite()) throw overflow();
      const double s1 = s[0];
      if (!(s1 > 0.0)) return true;
      bool accepted = false, converged = false;
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
        std::vector<Vec3> targets;
        const VecX step = basis * y;
        try {
          candidate.emplace(em.apply(step));
          targets = em.applyTargets(step);
          cost_new = residual(*candidate, targets, measurements, measure, w, robust, r_new);
        } catch (const std::invalid_argument&) {  // a step through a non-positive scale or beyond the limits
        }
        if (cost_new < cost) {
          accepted = true;
          // a small gain counts only for an undamped-enough step (a heavily damped one is small anyway)
          converged = cost - cost_new <= kRelativeDecrease * cost && mu <= kMuStart;
          cost = cost_new;
          r = std::move(r_new);
          em = em.rebased(*candidate, targets);
          estimate += step;
          mu /= kMuStep * kMuStep;  // the loop's increment follows: net one step down
        }
      }
      if (!accepted || converged) return true;  // no step decreases the cost: the rounding floor
    }
    return false;
  };
  bool converged = fit();

  // the noise unit of the normalized residuals: 1 when stated, else from the median residual
  auto unweighted = [&] {
    VecX plain;
    residual(em.model(), em.targets(), measurements, measure, w, VecX::Ones(count), plain);
    return normalizedResiduals(plain, measure);
  };
  auto scaleOf = [&](const std::vector<double>& u) {
    const double s = stated ? 1.0 : median(u) / medianNormalized(measure);
    return s > 0.0 ? s : 1.0;
  };
  int reweightings = 0;
  if (options.loss != Loss::Squared) {
    // iteratively reweighted: from the least-squares fit, Huber first (convex), then the chosen loss
    constexpr int kMaxReweightings = 50;
    constexpr double kWeightsSettled = 1e-4;
    for (const Loss loss : {Loss::Huber, options.loss}) {
      if (loss == Loss::Huber && options.loss != Loss::Huber && reweightings > 0) continue;
      for (int pass = 0; pass < kMaxReweightings; ++pass) {
        const std::vector<double> u = unweighted();
        const double scale = scaleOf(u);
        VecX next(count);
        for (Eigen::Index m = 0; m < count; ++m) next[m] = robustWeight(loss, u[static_cast<size_t>(m)] / scale);
        const double change = (next - robust).cwiseAbs().maxCoeff();
        robust = next;
        ++reweightings;
        cost = residual(em.model(), em.targets(), measurements, measure, w, robust, r);
        converged = fit();
        if (change <= kWeightsSettled) break;
      }
      if (loss == options.loss) break;
    }
  }

  // per measurement: errors, normalized residuals, weights, outliers
  const std::vector<double> u = unweighted();
  const double scale = scaleOf(u);
  std::vector<MeasurementResidual> residuals(static_cast<size_t>(count));
  {
    Data data(em.model());
    for (size_t m = 0; m < residuals.size(); ++m) {
      const MeasurementErrors e =
          measurementErrors(predict(em.model(), data, measurements[m], measure, em.targets()), measurements[m], measure);
      MeasurementResidual& x = residuals[m];
      x.position = e.position;
      x.rotation = measure == Measure::Pose ? e.rotation : kNaN;
      x.normalized = u[m] / scale;
      x.weight = robust[static_cast<Eigen::Index>(m)];
      x.outlier = x.normalized > options.outlier_threshold;
    }
  }
  const int outliers = static_cast<int>(std::count_if(residuals.begin(), residuals.end(),
                                                      [](const MeasurementResidual& x) { return x.outlier; }));

  // the variance factor: least squares over every measurement, a robust loss over those not flagged
  const int per = rowsPerMeasurement(measure);
  double redundancy = static_cast<double>(r.size()) - rank, weighted_cost = 0.0;
  for (size_t m = 0; m < residuals.size(); ++m) {
    if (options.loss != Loss::Squared && residuals[m].outlier) {
      redundancy -= per;
      continue;
    }
    weighted_cost += u[m] * u[m] * (per / 3.0);
  }
  const double variance_factor = redundancy > 0 ? weighted_cost / redundancy : kNaN;
  const double factor = stated ? 1.0 : variance_factor;

  // covariance at the result on the determined subspace: Cov = basis W S^-2 W^T basis^T (times the variance
  // factor when the noise was not stated). Redundancy: with no more residuals than determined parameters the
  // fit passes through the noise and the cost says nothing about it (variance factor NaN).
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
  CalibrationResult out{em.model(),
                        em,
                        identifiableCount(nominal, measure, options.free_pitch, static_cast<int>(options.targets.size())),
                        std::move(nominal_rank),
                        residualStatistics(start, measurements, measure, reg.targets),
                        residualStatistics(em.model(), measurements, measure, em.targets()),
                        iterations,
                        converged,
                        w.position,
                        w.rotation,
                        stated,
                        variance_factor,
                        axes * axes.transpose(),
                        sd,
                        axes,
                        null,
                        options.sigma_position.has_value(),
                        options.sigma_rotation.has_value(),
                        measure,
                        options.parameters,
                        reg,
                        em.targets(),
                        options.loss,
                        scale,
                        !stated,
                        reweightings,
                        std::move(residuals),
                        outliers,
                        false,
                        {},
                        options.outlier_threshold,
                        estimate};

  // the verdict
  std::ostringstream why;
  why.precision(3);
  if (!converged) {
    why << "the fit did not converge in " << iterations << " iterations";
  } else if (options.loss != Loss::Squared && outliers > kMaxOutlierFraction * static_cast<double>(count)) {
    why << outliers << " of " << count << " measurements are beyond " << options.outlier_threshold
        << " noise units (more than a quarter: a robust loss cannot tell blunders from a wrong model)";
  } else if (stated && variance_factor > kMaxVarianceFactor) {
    why << "variance factor " << variance_factor << " > " << kMaxVarianceFactor << ": the residuals are "
        << std::sqrt(variance_factor) << " times the stated noise";
  } else if (!stated) {
    const ResidualStatistics& a = out.after;
    if (a.rms_position > kMaxRelativeRmsPosition * L) {
      why << "RMS position " << a.rms_position << " left is " << 100.0 * a.rms_position / L
          << " % of the robot's size L = " << L << " (at most " << 100.0 * kMaxRelativeRmsPosition << " %)";
    } else if (measure == Measure::Pose && a.rms_rotation > kMaxRmsRotation) {
      why << "RMS rotation " << a.rms_rotation << " rad left (at most " << kMaxRmsRotation << " rad)";
    }
  }
  out.reason = why.str();
  out.accepted = out.reason.empty();
  return out;
}

namespace {

// Pose p of repeat r goes to fold partition[p]: repeat 0 deals the poses in order (pose i to fold i % k),
// later repeats deal a shuffle of them (Fisher-Yates on mt19937_64 seeded with r, whose output the
// standard fixes: the same data give the same folds everywhere). The folds are numbered in the order of
// their first pose, so two partitions into the same sets compare equal.
std::vector<int> foldsOfRepeat(int poses, int folds, int repeat) {
  std::vector<int> order(static_cast<size_t>(poses));
  for (int p = 0; p < poses; ++p) order[static_cast<size_t>(p)] = p;
  if (repeat > 0) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(repeat));
    for (int i = poses - 1; i > 0; --i) {
      std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(rng() % static_cast<std::uint64_t>(i + 1))]);
    }
  }
  std::vector<int> dealt(static_cast<size_t>(poses)), fold(static_cast<size_t>(poses)), label(static_cast<size_t>(folds), -1);
  for (int i = 0; i < poses; ++i) dealt[static_cast<size_t>(order[static_cast<size_t>(i)])] = i % folds;
  int next = 0;
  for (int p = 0; p < poses; ++p) {
    int& l = label[static_cast<size_t>(dealt[static_cast<size_t>(p)])];
    if (l < 0) l = next++;
    fold[static_cast<size_t>(p)] = l;
  }
  return fold;
}

}  // namespace

CrossValidation crossValidate(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                              const CalibrationOptions& options, int folds, int repeats) {
  LP_CHECK(folds >= 2 && folds <= kMaxCrossValidationFolds,
           "crossValidate: " << folds << " folds (2 to " << kMaxCrossValidationFolds << ")");
  LP_CHECK(repeats >= 1 && repeats <= kMaxCrossValidationRepeats,
           "crossValidate: " << repeats << " repeats (1 to " << kMaxCrossValidationRepeats << ")");
  // folds over poses: consecutive measurements with the same joint vector (a pose's targets) stay together
  std::vector<int> pose(measurements.size(), 0);
  for (size_t m = 1; m < measurements.size(); ++m) {
    pose[m] = pose[m - 1] + (measurements[m].q == measurements[m - 1].q ? 0 : 1);
  }
  const int poses = measurements.empty() ? 0 : pose.back() + 1;
  LP_CHECK(poses >= folds, "crossValidate: " << poses << " poses for " << folds << " folds");
  // distinct partitions only (few poses allow few: as many poses as folds, one)
  std::vector<std::vector<int>> partitions;
  for (int r = 0; r < repeats; ++r) {
    std::vector<int> p = foldsOfRepeat(poses, folds, r);
    if (std::find(partitions.begin(), partitions.end(), p) == partitions.end()) partitions.push_back(std::move(p));
  }
  // The noise unit of the scores, one for every level: 1 with stated noise; without, under a robust loss,
  // the robust scale of the full level fitted to every measurement (each fold fit's own scale would shrink
  // the held-out errors of the levels that fit their training poses tightest)
  double unit = 1.0;
  const bool stated = options.sigma_position.has_value() || options.sigma_rotation.has_value();
  if (!stated && options.loss != Loss::Squared) {
    CalibrationOptions o = options;
    o.parameters = ParameterSet::Full;
    unit = calibrate(nominal, measurements, o).robust_scale;
  }
  const double rows_per_point = rowsPerMeasurement(options.measure) / 3.0;
  CrossValidation out;
  out.folds = folds;
  out.repeats = static_cast<int>(partitions.size());
  for (const ParameterSet set : {ParameterSet::Full, ParameterSet::Lines, ParameterSet::Offsets}) {
    CrossValidation::Candidate c;
    c.set = set;
    CalibrationOptions o = options;
    o.parameters = set;
    double sum_p = 0.0, sum_r = 0.0, score = 0.0;
    int held = 0;
    for (size_t r = 0; r < partitions.size() && !c.failed; ++r) {
      for (int f = 0; f < folds && !c.failed; ++f) {
        std::vector<Measurement> train, test;
        for (size_t m = 0; m < measurements.size(); ++m) {
          (partitions[r][static_cast<size_t>(pose[m])] == f ? test : train).push_back(measurements[m]);
        }
        try {
          const CalibrationResult fit = calibrate(nominal, train, o);
          c.parameters = fit.error_model.size();
          if (!fit.converged) c.failed = true;
          // each held-out measurement's normalized residual (the fit's weights, over the common unit) scored
          // by the fit's loss: least squares sums |r|^2, a robust loss does not let a held-out blunder decide
          const double wp = fit.sigma_position, wr = fit.sigma_rotation;
          Data data(fit.model);
          for (const Measurement& m : test) {
            const auto [ep, er] = measurementErrors(predict(fit.model, data, m, o.measure, fit.targets), m, o.measure);
            sum_p += ep * ep;
            sum_r += er * er;
            const double u = std::sqrt((ep * ep / (wp * wp) + er * er / (wr * wr)) / rows_per_point) / unit;
            score += rows_per_point * unit * unit * robustRho(o.loss, u);
            ++held;
          }
        } catch (const std::invalid_argument&) {
          c.failed = true;
        }
      }
    }
    if (held > 0) {
      c.rms_position = std::sqrt(sum_p / held);
      c.rms_rotation = std::sqrt(sum_r / held);
      c.score = std::sqrt(score / held);
    }
    out.candidates.push_back(c);
  }
  const CrossValidation::Candidate* best = nullptr;
  for (const auto& c : out.candidates) {
    if (c.failed) continue;
    if (!best || c.score < best->score || (c.score == best->score && c.parameters < best->parameters)) {
      best = &c;
    }
  }
  LP_CHECK(best, "crossValidate: no parameter level could be fitted on every fold");
  out.chosen = best->set;
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
  DhUncertainty out{poeToDh(result.model), {}, {}, {}, {}, 0.0, 0.0, {}, {}};
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
  // a row placed by a prismatic axis (the base for joint 1, link_{i-1} for joint i) has a = d = 0 by the
  // conversion's convention; an offset of joint i-1 folds into that row's d when joint i-1 slides
  // (prismatic, helical) and is nonzero or fitted
  out.links_fixed.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    if (result.model.joint(i).type != JointType::Prismatic) continue;
    DhUncertainty::Fixed& fixed = i == 0 ? out.base_fixed : out.links_fixed[static_cast<size_t>(i - 1)];
    DhParams& deviation = i == 0 ? out.base : out.links[static_cast<size_t>(i - 1)];
    fixed.a = true;
    deviation.a = 0.0;
    // (a revolute joint with a fitted pitch slides too: d += pitch * scale * offset)
    auto fitted = [&](ParameterKind kind) {
      return std::any_of(em.parameters().begin(), em.parameters().end(),
                         [&](const Parameter& p) { return p.kind == kind && p.joint == i - 1; });
    };
    bool offset_moves_d = false;
    if (i > 0 && (result.model.joint(i - 1).type != JointType::Revolute || fitted(ParameterKind::Pitch))) {
      offset_moves_d = result.model.joint(i - 1).offset != 0.0 || fitted(ParameterKind::Offset);
    }
    if (!offset_moves_d) {
      fixed.d = true;
      deviation.d = 0.0;
    }
  }
  return out;
}

}  // namespace lowpair
