#include "lowpair/deflection.hpp"
#include "calibration_internal.hpp"
#include "lowpair/calibrate.hpp"

#include <algorithm>

#include "check.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

namespace detail {

namespace {
bool listed(const std::vector<int>& joints, int i) { return std::find(joints.begin(), joints.end(), i) != joints.end(); }
}  // namespace

// (column order: per joint, compliance then backlash)
std::vector<std::pair<int, bool>> deflectionOrder(int dof, const ErrorModelSpec& spec) {
  std::vector<std::pair<int, bool>> out;
  for (int i = 0; i < dof; ++i) {
    if (listed(spec.compliance_joints, i)) out.emplace_back(i, true);
    if (listed(spec.backlash_joints, i)) out.emplace_back(i, false);
  }
  return out;
}

double deflectionInput(const PoseLoad& load, int joint, bool compliance) {
  const VecX& input = compliance ? load.torque : load.sign;
  return input.size() == 0 ? 0.0 : input[joint];
}

void checkDeflectionSpec(const PoeModel& model, const ErrorModelSpec& spec) {
  for (const auto* joints : {&spec.compliance_joints, &spec.backlash_joints}) {
    for (size_t k = 0; k < joints->size(); ++k) {
      const int i = (*joints)[k];
      LP_CHECK(i >= 0 && i < model.dof(), "error model: deflection of joint " << i + 1 << " of " << model.dof());
      LP_CHECK(std::count(joints->begin(), joints->end(), i) == 1,
               "error model: joint " << i + 1 << "'s " << (joints == &spec.compliance_joints ? "compliance" : "backlash")
                                     << " named twice");
    }
  }
  for (const VecX* v : {&spec.deflection.compliance, &spec.deflection.backlash}) {
    LP_CHECK(v->size() == 0 || v->size() == model.dof(),
             "error model: " << v->size() << " deflection values for " << model.dof() << " joints");
    LP_CHECK(v->allFinite(), "error model: a deflection value is not finite");
  }
}

}  // namespace detail

using namespace detail;

std::optional<VecX> commandFor(const PoeModel& model, const MassModel& masses, const JointDeflection& deflection,
                               const VecX& q_stand, const VecX& sign) {
  constexpr int kMaxSteps = 100;
  const double tolerance = 16.0 * kEps * (1.0 + q_stand.cwiseAbs().maxCoeff());
  VecX q = q_stand;
  for (int step = 0; step < kMaxSteps; ++step) {
    PoseLoad load;
    if (deflection.compliance.size() > 0) load.torque = gravityTorques(model, masses, q);
    load.sign = sign;
    const VecX next = q_stand - (deflectedJoints(deflection, q, load) - q);
    const double change = (next - q).cwiseAbs().maxCoeff();
    q = next;
    if (change <= tolerance) return q;
  }
  return std::nullopt;
}

void checkDeflections(const PoeModel& model, const ErrorModelSpec& spec, const std::vector<PoseLoad>& loads) {
  checkDeflectionSpec(model, spec);
  const std::vector<std::pair<int, bool>> order = deflectionOrder(model.dof(), spec);
  if (order.empty()) return;
  LP_CHECK(!loads.empty(), "error model: joint deflections need the poses' loads");
  double largest = 0.0;  // the largest torque on any joint at any pose
  for (const PoseLoad& load : loads) {
    if (load.torque.size() > 0) largest = std::max(largest, load.torque.cwiseAbs().maxCoeff());
  }
  for (const auto& [joint, compliance] : order) {
    double lo = kInf, hi = -kInf;
    for (const PoseLoad& load : loads) {
      const double x = deflectionInput(load, joint, compliance);
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    const std::string label = jointLabel(joint, model.joint(joint).name);
    if (compliance) {
      const char* unit = model.joint(joint).type == JointType::Prismatic ? " N" : " N m";
      LP_CHECK(hi - lo > numericalRankTolerance(largest, static_cast<double>(model.dof())),
               label << ": its gravity load does not vary over the " << loads.size() << " poses (" << lo << unit << " to "
                     << hi << unit << ")" << (hi == 0.0 && lo == 0.0 ? ", no load at all (a vertical axis, or no masses)" : "")
                     << ": its compliance cannot be told from its offset");
    } else {
      LP_CHECK(hi > lo, label << ": the sign of its last move is " << lo << " at every one of the " << loads.size()
                              << " poses: its backlash cannot be told from its offset");
    }
  }
}

VecX deflectedJoints(const JointDeflection& deflection, const VecX& q, const PoseLoad& load) {
  VecX out = q;
  auto add = [&](const VecX& coefficient, const VecX& input, const char* what) {
    if (coefficient.size() == 0 || input.size() == 0) return;
    LP_CHECK(coefficient.size() == q.size() && input.size() == q.size(),
             "deflection: " << what << " has " << coefficient.size() << " and " << input.size() << " entries for "
                            << q.size() << " joints");
    out += coefficient.cwiseProduct(input);
  };
  add(deflection.compliance, load.torque, "compliance x torque");
  add(deflection.backlash, load.sign, "backlash x sign");
  return out;
}

std::vector<VecX> moveSigns(const std::vector<VecX>& q) {
  std::vector<VecX> s;
  if (q.empty()) return s;
  VecX last = VecX::Zero(q[0].size());
  s.push_back(last);
  for (size_t k = 1; k < q.size(); ++k) {
    LP_CHECK(q[k].size() == last.size(), "moveSigns: pose " << k + 1 << " has " << q[k].size() << " joints, not " << last.size());
    for (Eigen::Index j = 0; j < last.size(); ++j) {
      const double d = q[k][j] - q[k - 1][j];
      if (d > 0.0) last[j] = 1.0;
      if (d < 0.0) last[j] = -1.0;
    }
    s.push_back(last);
  }
  return s;
}

std::vector<PoseLoad> poseLoads(const PoeModel& model, const MassModel& masses, const std::vector<VecX>& q,
                                bool with_torque, const std::vector<VecX>& signs) {
  LP_CHECK(signs.empty() || signs.size() == q.size(), "poseLoads: " << signs.size() << " sign vectors for " << q.size() << " poses");
  std::vector<PoseLoad> loads(q.size());
  for (size_t k = 0; k < q.size(); ++k) {
    if (with_torque) loads[k].torque = gravityTorques(model, masses, q[k]);
    if (signs.empty()) continue;
    const VecX& s = signs[k];
    LP_CHECK(s.size() == model.dof(), "poseLoads: pose " << k + 1 << " has " << s.size() << " signs for " << model.dof() << " joints");
    for (Eigen::Index j = 0; j < s.size(); ++j) {
      LP_CHECK(s[j] == -1.0 || s[j] == 0.0 || s[j] == 1.0,
               "poseLoads: pose " << k + 1 << ", joint " << j + 1 << ": sign " << s[j] << " (must be -1, 0 or 1)");
    }
    loads[k].sign = s;
  }
  return loads;
}

// calibrate.hpp: the deflection inputs of a calibration
std::vector<PoseLoad> measurementLoads(const PoeModel& nominal, const std::vector<Measurement>& measurements,
                                       const CalibrationOptions& options) {
  if (!options.deflects()) return {};
  std::vector<VecX> q;
  q.reserve(measurements.size());
  for (const Measurement& m : measurements) q.push_back(m.q);
  const bool torque = !options.compliance_joints.empty() || options.deflection.compliance.size() > 0;
  const bool signs = !options.backlash_joints.empty() || options.deflection.backlash.size() > 0;
  LP_CHECK(options.move_signs.empty() || options.move_signs.size() == measurements.size(),
           "calibrate: " << options.move_signs.size() << " move-sign vectors for " << measurements.size() << " measurements");
  return poseLoads(nominal, options.masses, q, torque,
                   !signs ? std::vector<VecX>{} : options.move_signs.empty() ? moveSigns(q) : options.move_signs);
}

std::vector<Measurement> deflectedMeasurements(const std::vector<Measurement>& measurements,
                                               const JointDeflection& deflection, const std::vector<PoseLoad>& loads) {
  std::vector<Measurement> out = measurements;
  if (loads.empty()) return out;
  LP_CHECK(loads.size() == measurements.size(), "deflectedMeasurements: " << loads.size() << " loads for " << measurements.size() << " measurements");
  for (size_t k = 0; k < out.size(); ++k) out[k].q = deflectedJoints(deflection, measurements[k].q, loads[k]);
  return out;
}

}  // namespace lowpair
