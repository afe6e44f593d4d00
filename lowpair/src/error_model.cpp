#include "lowpair/error_model.hpp"
#include "calibration_internal.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "check.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

using namespace detail;

namespace {

// A name from the caller as a message quotes it: at most 40 bytes, then "..." (a megabyte of name is not echoed).
std::string cut(const std::string& name) { return name.size() > 40 ? name.substr(0, 40) + "..." : name; }

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

// The rows of one pose: one measurement (Pose, Position), or one per target (Targets: the points `T p_t`;
// an unknown target's 3 columns `R` after the spatial-twist columns S, in target order).
void poseRows(const Mat6X& S, const Pose& T, Measure measure, const ErrorModelSpec& spec, int dof, Eigen::Ref<MatX> rows) {
  if (measure != Measure::Targets) {
    measurementRows(S, T.p, measure, dof, rows.leftCols(S.cols()));
    return;
  }
  rows.setZero();
  Eigen::Index column = S.cols();
  for (size_t t = 0; t < spec.targets.size(); ++t) {
    auto block = rows.middleRows(3 * static_cast<Eigen::Index>(t), 3);
    measurementRows(S, T.R * *spec.targets[t].point_tool + T.p, Measure::Position, dof, block.leftCols(S.cols()));
    if (spec.knownTarget(t)) continue;
    block.middleCols<3>(column) = T.R;
    column += 3;
  }
}

int unknownTargets(const ErrorModelSpec& spec) {
  int unknown = 0;
  for (size_t t = 0; t < spec.targets.size(); ++t) unknown += spec.knownTarget(t) ? 0 : 1;
  return unknown;
}

// Target t's name in parameter names and messages: its own, or its number ("1", "2", ...) when any target's
// name is empty (every target is numbered then, so that no number collides with a name).
std::string targetName(const ErrorModelSpec& spec, size_t t) {
  const bool numbered = std::any_of(spec.targets.begin(), spec.targets.end(), [](const Target& x) { return x.name.empty(); });
  return numbered ? std::to_string(t + 1) : spec.targets[t].name;
}

}  // namespace

namespace detail {

void checkTargets(Measure measure, const ErrorModelSpec& spec) {
  LP_CHECK((measure == Measure::Targets) == !spec.targets.empty(), "Measure::Targets needs targets' points, and only it");
  spec.validate();
}

void checkPoses(const std::vector<VecX>& q, int dof) {
  LP_CHECK(!q.empty(), "identifiability needs at least one pose");
  for (const VecX& qi : q) checkJointVector(qi, dof);
}

}  // namespace detail

std::vector<Vec3> ErrorModelSpec::knownPoints() const {
  validate();
  std::vector<Vec3> known;
  for (const Target& t : targets) {
    if (t.known) known.push_back(*t.point_tool);
  }
  return known;
}

bool ErrorModelSpec::toolParameters() const {
  return targets.empty() || pose_measurements || std::any_of(targets.begin(), targets.end(), [](const Target& t) { return t.known; });
}

void ErrorModelSpec::validate() const {
  for (size_t t = 0; t < targets.size(); ++t) {
    LP_CHECK(targets[t].point_tool, "error model: target " << cut(targetName(*this, t))
                                                           << " has no point (an error model needs every target's point)");
    LP_CHECK(targets[t].point_tool->allFinite(), "error model: target " << cut(targetName(*this, t)) << " has a non-finite point");
  }
}

int knownPointsToolRank(const std::vector<Vec3>& known_points, double L) {
  if (known_points.empty()) return 0;
  Eigen::Matrix<double, 3, Eigen::Dynamic> d(3, static_cast<Eigen::Index>(known_points.size()));
  for (size_t k = 0; k < known_points.size(); ++k) d.col(static_cast<Eigen::Index>(k)) = known_points[k] - known_points[0];
  if (d.colwise().norm().maxCoeff() <= kRankFactor * kEps * L) return 3;  // one point: the turns about it are free
  // min(3, points) singular values; the first column is zero, so at least two and s[1] exists.
  const VecX s = Eigen::JacobiSVD<MatX>(d).singularValues();
  return s[1] <= numericalRankTolerance(s[0], 3.0) ? 5 : 6;  // collinear: the turn about their line is free
}

ParameterCount identifiableCount(const PoeModel& model, Measure measure, const ErrorModelSpec& spec) {
  const bool free_pitch = spec.free_pitch;
  const auto targets = static_cast<int>(spec.targets.size());
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
  count.deflections = static_cast<int>(spec.compliance_joints.size() + spec.backlash_joints.size());
  if (measure != Measure::Targets) {
    count.tool = measure == Measure::Pose ? 6 : 3;
    return count;
  }
  const std::vector<Vec3> known = spec.knownPoints();
  count.tool = 3 * (targets - static_cast<int>(known.size())) +
               (spec.pose_measurements ? 6 : knownPointsToolRank(known, model.lengthScale()));
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
    case ParameterKind::Compliance:
    case ParameterKind::Backlash:
      return true;
  }
  return false;
}

// The pose's load (none when `loads` is empty), checked against the poses.
PoseLoad loadAt(const std::vector<PoseLoad>& loads, size_t pose, size_t poses) {
  LP_CHECK(loads.empty() || loads.size() == poses, "error model: " << loads.size() << " loads for " << poses << " poses");
  return loads.empty() ? PoseLoad{} : loads[pose];
}

// The point about which the base parameters turn the model: the first joint's line point nearest the
// frame origin (the robot's foot, wherever the measurement frame is), or the origin for a prismatic joint.
Vec3 baseCenter(const PoeModel& model) {
  if (model.dof() == 0) return Vec3::Zero();
  const Joint& j = model.joint(0);
  return j.type == JointType::Prismatic ? Vec3::Zero() : Vec3(j.axis().cross(j.moment()));
}

}  // namespace

ErrorModel::ErrorModel(const PoeModel& model, const ErrorModelSpec& spec) : model_(model), spec_(spec) {
  spec.validate();
  for (const Target& t : spec.targets) target_points_.push_back(*t.point_tool);
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
    offset_columns_.push_back(static_cast<int>(all_.size()));
    add(ParameterKind::Offset, i, 0, tag + ".offset", j.type == JointType::Prismatic ? "length" : "rad");
    basis_.push_back(basis);
  }
  if (spec.toolParameters()) {
    for (int k = 0; k < 3; ++k) add(ParameterKind::ToolRotation, -1, k, std::string("tool.r") + axes[k], "rad");
    for (int k = 0; k < 3; ++k) add(ParameterKind::ToolTranslation, -1, k, std::string("tool.") + axes[k], "length");
  }
  target_columns_.assign(spec.targets.size(), -1);
  for (size_t t = 0; t < spec.targets.size(); ++t) {
    if (spec.knownTarget(t)) continue;  // fixed: no parameter
    const std::string name = targetName(spec, t);
    target_columns_[t] = static_cast<int>(all_.size());
    for (int k = 0; k < 3; ++k) add(ParameterKind::TargetPoint, static_cast<int>(t), k, "target." + name + "." + axes[k], "length");
  }
  checkDeflectionSpec(model, spec);
  for (const auto& [i, compliance] : deflectionOrder(model.dof(), spec)) {
    const bool slides = model.joint(i).type == JointType::Prismatic;
    deflection_columns_.push_back({static_cast<int>(all_.size()), i, compliance});
    if (compliance) {
      add(ParameterKind::Compliance, i, 0, jointTag(i) + ".compliance", slides ? "length/N" : "rad/(N m)");
    } else {
      add(ParameterKind::Backlash, i, 0, jointTag(i) + ".backlash", slides ? "length" : "rad");
    }
  }
  if (spec.set == ParameterSet::Named) {
    LP_CHECK(!spec.names.empty(), "error model: no parameter named");
    for (const std::string& name : spec.names) {
      const auto it = std::find_if(all_.begin(), all_.end(), [&](const Parameter& p) { return p.name == name; });
      if (it == all_.end()) {
        std::ostringstream known;
        for (size_t k = 0; k < all_.size() && k < 12; ++k) known << (k ? ", " : "") << all_[k].name;
        LP_CHECK(false, "error model: no parameter named '" << cut(name) << "' (the model's: " << known.str()
                                                            << (all_.size() > 12 ? ", ..." : "") << ")");
      }
      const int index = static_cast<int>(it - all_.begin());
      LP_CHECK(std::find(selected_.begin(), selected_.end(), index) == selected_.end(),
               "error model: parameter '" << cut(name) << "' named twice");
      selected_.push_back(index);
    }
    for (const DeflectionColumn& d : deflection_columns_) {  // named by the spec's joints
      if (std::find(selected_.begin(), selected_.end(), d.column) == selected_.end()) selected_.push_back(d.column);
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
  if (spec_.toolParameters()) {
    const Vec3 r = d.segment<3>(k), t = d.segment<3>(k + 3);
    tool = expSE3(twist(r, tool.p.cross(r) + t)) * tool;
  }
  PoeModel out(std::move(joints), tool, model_.name());
  if (base_r.any() || base_t.any()) out = movedModel(out, expSE3(twist(base_r, center_.cross(base_r) + base_t)));
  return out;
}

std::optional<PoeModel> ErrorModel::tryApply(const Eigen::Ref<const VecX>& delta) const {
  // the one place where apply's (and PoeModel's) validation becomes data
  try {
    return apply(delta);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
}

std::vector<Vec3> ErrorModel::applyTargetPoints(const Eigen::Ref<const VecX>& delta) const {
  const VecX d = expanded(delta);
  std::vector<Vec3> out = target_points_;
  for (size_t t = 0; t < out.size(); ++t) {
    if (target_columns_[t] >= 0) out[t] += d.segment<3>(target_columns_[t]);
  }
  return out;
}

JointDeflection ErrorModel::applyDeflection(const Eigen::Ref<const VecX>& delta) const {
  const VecX d = expanded(delta);
  JointDeflection out = spec_.deflection;
  const Eigen::Index n = model_.dof();
  for (const DeflectionColumn& c : deflection_columns_) {
    VecX& values = c.compliance ? out.compliance : out.backlash;
    if (values.size() == 0) values = VecX::Zero(n);
    values[c.joint] += d[c.column];
  }
  return out;
}

ErrorModel ErrorModel::rebased(const PoeModel& model) const { return rebased(model, target_points_); }

ErrorModel ErrorModel::rebased(const PoeModel& model, const std::vector<Vec3>& target_points) const {
  return rebased(model, target_points, spec_.deflection);
}

ErrorModel ErrorModel::rebased(const PoeModel& model, const std::vector<Vec3>& target_points,
                               const JointDeflection& deflection) const {
  LP_CHECK(model.dof() == model_.dof(), "error model: rebased onto a model with another joint count");
  LP_CHECK(target_points.size() == target_points_.size(), "error model: rebased with another number of targets");
  ErrorModel out = *this;
  out.model_ = model;
  for (size_t t = 0; t < target_points.size(); ++t) out.spec_.targets[t].point_tool = target_points[t];
  out.target_points_ = target_points;
  out.spec_.deflection = deflection;
  checkDeflectionSpec(model, out.spec_);
  return out;
}

Pose ErrorModel::jacobian(const Eigen::Ref<const VecX>& q, Measure measure, Eigen::Ref<MatX> rows, int target) const {
  return jacobian(q, PoseLoad{}, measure, rows, target);
}

Pose ErrorModel::jacobian(const Eigen::Ref<const VecX>& q_commanded, const PoseLoad& load, Measure measure,
                          Eigen::Ref<MatX> rows, int target) const {
  checkJointVector(q_commanded, model_.dof());
  const VecX q = deflectedJoints(spec_.deflection, q_commanded, load);
  LP_CHECK(rows.rows() == rowsPerMeasurement(measure) && rows.cols() == size(), "error model: rows must be "
                                                                           << rowsPerMeasurement(measure) << " x " << size());
  // Measure::Targets: one target's point; a pose (mixed data) or a position with targets: the tool's
  const bool targets = measure == Measure::Targets;
  LP_CHECK(!targets || !spec_.targets.empty(), "error model: Measure::Targets needs targets");
  LP_CHECK(!targets || (target >= 0 && target < static_cast<int>(spec_.targets.size())),
           "error model: target " << target << " of " << spec_.targets.size());
  const auto twists = static_cast<Eigen::Index>(all_.size()) - 3 * static_cast<Eigen::Index>(unknownTargets(spec_)) -
                      static_cast<Eigen::Index>(deflection_columns_.size());
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
  if (spec_.toolParameters()) {
    const Vec3 p_tool = model_.toolPose().p;
    for (int k = 0; k < 3; ++k) S.col(c++) = adjointApply(P, twist(Vec3::Unit(k), p_tool.cross(Vec3::Unit(k))));
    for (int k = 0; k < 3; ++k) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), Vec3::Unit(k)));
  }
  const int per = rowsPerMeasurement(measure);
  MatX all(per, static_cast<Eigen::Index>(all_.size()));
  all.setZero();
  const Vec3 point = targets ? Vec3(T.R * target_points_[static_cast<size_t>(target)] + T.p) : T.p;
  measurementRows(S, point, measure == Measure::Targets ? Measure::Position : measure, model_.dof(), all.leftCols(twists));
  if (targets && target_columns_[static_cast<size_t>(target)] >= 0) all.middleCols<3>(target_columns_[static_cast<size_t>(target)]) = T.R;
  for (const DeflectionColumn& d : deflection_columns_) {  // joint i's offset column times its input
    all.col(d.column) = all.col(offset_columns_[static_cast<size_t>(d.joint)]) * deflectionInput(load, d.joint, d.compliance);
  }
  for (int k = 0; k < size(); ++k) rows.col(k) = all.col(selected_[static_cast<size_t>(k)]);
  if (targets) return Pose{T.R, point};
  return T;
}

MatX fullErrorModelJacobian(const PoeModel& model, const std::vector<VecX>& q, Measure measure,
                            const ErrorModelSpec& spec, const std::vector<PoseLoad>& loads) {
  const bool free_pitch = spec.free_pitch;
  checkPoses(q, model.dof());
  checkTargets(measure, spec);
  checkDeflectionSpec(model, spec);
  const std::vector<std::pair<int, bool>> order = deflectionOrder(model.dof(), spec);
  int cols = 6;
  for (const Joint& j : model.joints()) cols += 6 + (hasPitch(j, free_pitch) ? 1 : 0) + 2;
  const int per = rowsPerPose(measure, static_cast<int>(spec.targets.size()));
  const Eigen::Index first = cols + 3 * static_cast<Eigen::Index>(unknownTargets(spec));
  MatX J(per * static_cast<Eigen::Index>(q.size()), first + static_cast<Eigen::Index>(order.size()));
  Mat6X S(6, cols);
  std::vector<Eigen::Index> offset(static_cast<size_t>(model.dof()));
  for (size_t m = 0; m < q.size(); ++m) {
    const PoseLoad load = loadAt(loads, m, q.size());
    const VecX qm = deflectedJoints(spec.deflection, q[m], load);
    Pose P, E;
    Eigen::Index c = 0;
    for (int i = 0; i < model.dof(); ++i) {
      const Joint& j = model.joint(i);
      const double qi = qm[i];
      jointExp(j, qi, E);
      const Pose next = P * E;
      for (int k = 0; k < 6; ++k) S.col(c++) = twistDifference(adjointApply(P, Vec6::Unit(k)), adjointApply(next, Vec6::Unit(k)), model.dof());
      if (hasPitch(j, free_pitch)) S.col(c++) = adjointApply(P, twist(Vec3::Zero(), j.axis())) * j.motion(qi);
      S.col(c++) = adjointApply(P, j.twist) * (qi + j.offset);  // scale
      offset[static_cast<size_t>(i)] = c;
      S.col(c++) = adjointApply(P, j.twist) * j.scale;           // offset
      P = next;
    }
    for (int k = 0; k < 6; ++k) S.col(c++) = adjointApply(P, Vec6::Unit(k));
    auto rows = J.middleRows(per * static_cast<Eigen::Index>(m), per);
    poseRows(S, P * model.toolPose(), measure, spec, model.dof(), rows.leftCols(first));
    for (size_t k = 0; k < order.size(); ++k) {  // joint i's offset column times its input
      const auto [joint, compliance] = order[k];
      rows.col(first + static_cast<Eigen::Index>(k)) = rows.col(offset[static_cast<size_t>(joint)]) * deflectionInput(load, joint, compliance);
    }
  }
  return J;
}

MatX dhIdentificationJacobian(const DhModel& model, const std::vector<VecX>& q, Measure measure,
                              const ErrorModelSpec& spec, std::vector<std::string>* names,
                              const std::vector<PoseLoad>& loads) {
  const bool free_pitch = spec.free_pitch;
  checkPoses(q, model.dof());
  checkTargets(measure, spec);
  const std::vector<std::pair<int, bool>> order = deflectionOrder(model.dof(), spec);
  // a Hayati row's parameters are theta, alpha, a, beta (its d is fixed to 0; docs/conventions.md)
  auto rowColumns = [](const DhParams& r) {
    return r.hayati() ? std::vector<const char*>{".theta", ".alpha", ".a", ".beta"}
                      : std::vector<const char*>{".theta", ".d", ".alpha", ".a"};
  };
  std::vector<std::string> columns;
  for (const char* p : rowColumns(model.base())) columns.push_back(std::string("base") + p);
  for (int i = 0; i < model.dof(); ++i) {
    const std::string tag = jointTag(i);
    for (const char* p : rowColumns(model.joint(i).link)) columns.push_back(tag + p);
    if (hasPitch(model.joint(i), free_pitch)) columns.push_back(tag + ".pitch");
    columns.push_back(tag + ".scale");
  }
  columns.push_back("tool.theta");
  columns.push_back("tool.d");
  const auto cols = static_cast<Eigen::Index>(columns.size());
  for (size_t t = 0; t < spec.targets.size(); ++t) {
    if (spec.knownTarget(t)) continue;
    for (const char* axis : {".x", ".y", ".z"}) columns.push_back("target." + targetName(spec, t) + axis);
  }
  const auto first = static_cast<Eigen::Index>(columns.size());
  for (const auto& [joint, compliance] : order) columns.push_back(jointTag(joint) + (compliance ? ".compliance" : ".backlash"));
  const int per = rowsPerPose(measure, static_cast<int>(spec.targets.size()));
  MatX J(per * static_cast<Eigen::Index>(q.size()), static_cast<Eigen::Index>(columns.size()));
  Mat6X S(6, cols + static_cast<Eigen::Index>(model.dof()));  // the joints' motion columns after the parameters'
  for (size_t m = 0; m < q.size(); ++m) {
    const PoseLoad load = loadAt(loads, m, q.size());
    Eigen::Index c = 0;
    Pose F;  // the frame before the current row
    // theta, d, alpha, a (Hayati: theta, alpha, a, beta) of one row at F; returns the frame after it and the
    // theta and d columns
    auto row = [&](const DhParams& r, Vec6& theta_col, Vec6& d_col) {
      theta_col = twist(F.R.col(2), F.p.cross(F.R.col(2)));
      d_col = twist(Vec3::Zero(), F.R.col(2));
      S.col(c++) = theta_col;
      if (!r.hayati()) S.col(c++) = d_col;
      const Pose F1 = F * dhToolTransform(r.theta, r.d);
      S.col(c++) = twist(F1.R.col(0), F1.p.cross(F1.R.col(0)));
      const Pose F2 = F1 * dhTransform(DhParams{0.0, 0.0, r.alpha, 0.0});
      S.col(c++) = twist(Vec3::Zero(), F2.R.col(0));
      if (r.hayati()) {  // about the y axis of the frame after Rx(alpha) Tx(a)
        DhParams standard = r;
        standard.kind = DhRowKind::Standard;
        standard.beta = 0.0;
        const Pose F3 = F * dhTransform(standard);
        S.col(c++) = twist(F3.R.col(1), F3.p.cross(F3.R.col(1)));
      }
      F = F * dhTransform(r);
    };
    Vec6 theta_col, d_col;
    row(model.base(), theta_col, d_col);
    const VecX qm = deflectedJoints(spec.deflection, q[m], load);
    for (int i = 0; i < model.dof(); ++i) {
      const DhJoint& j = model.joint(i);
      const double qi = qm[i], x = j.motion(qi);
      row(movedRow(j.link, j, x), theta_col, d_col);
      if (hasPitch(j, free_pitch)) S.col(c++) = d_col * x;
      const Vec6 turn_slide = j.turnRate() * theta_col + j.slideRate() * d_col;
      S.col(c++) = turn_slide * (qi + j.offset);
      S.col(cols + i) = turn_slide * j.scale;  // the motion per unit of q_i (not a parameter of its own)
    }
    S.col(c++) = twist(F.R.col(2), F.p.cross(F.R.col(2)));
    S.col(c++) = twist(Vec3::Zero(), F.R.col(2));
    const Pose T = F * dhToolTransform(model.toolTheta(), model.toolD());
    // the parameters' twist columns and the motion columns, then the unknown targets' (poseRows)
    MatX pose_rows(per, S.cols() + (first - cols));
    poseRows(S, T, measure, spec, model.dof(), pose_rows);
    auto rows = J.middleRows(per * static_cast<Eigen::Index>(m), per);
    rows.leftCols(cols) = pose_rows.leftCols(cols);
    rows.middleCols(cols, first - cols) = pose_rows.rightCols(first - cols);
    for (size_t k = 0; k < order.size(); ++k) {
      const auto [joint, compliance] = order[k];
      rows.col(first + static_cast<Eigen::Index>(k)) = pose_rows.col(cols + joint) * deflectionInput(load, joint, compliance);
    }
  }
  if (names) *names = std::move(columns);
  return J;
}

}  // namespace lowpair
