#include "lowpair/dh_uncertainty.hpp"
#include "calibration_internal.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "lowpair/base_frame.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

using namespace detail;

// --- D-H standard deviations -------------------------------------------------------------------------

namespace {

// The D-H numbers of a conversion in a fixed order: base 4, per joint theta d alpha a pitch scale, tool 2,
// then beta per row (base, link_1 .. link_n; 0 in a standard row); `angle` marks the entries compared
// modulo 2 pi.
Eigen::Index betaEntry(int row, int dof) { return 4 + 6 * dof + 2 + row; }

VecX dhNumbers(const DhModel& dh, std::vector<bool>* angle = nullptr) {
  const int n = dh.dof();
  VecX out(4 + 6 * n + 2 + n + 1);
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
  put(dh.base().beta, true);
  for (int i = 0; i < n; ++i) put(dh.joint(i).link.beta, true);
  if (angle) *angle = std::move(is_angle);
  return out;
}

// Puts the rows of the D-H numbers `x` on the sign branch of `center`: the canonical table keeps a >= 0, so a
// row whose a crosses 0 comes back as (theta + pi, d, -alpha, -a) with pi added to the next row's theta
// (A(theta + pi, d, -alpha, -a) = A(theta, d, alpha, a) Rz(pi); a Hayati row's beta changes sign too, since
// Rz(pi) Ry(beta) = Ry(-beta) Rz(pi)). Undone here, so that a length a that is 0
// within its uncertainty shows as a +- sd instead of a jump of theta by pi.
void alignBranches(VecX& x, const VecX& center, int dof) {
  auto row = [](int r) { return r == 0 ? 0 : 4 + 6 * (r - 1); };
  for (int r = 0; r <= dof; ++r) {
    const int k = row(r);
    if (std::abs(wrapAngle(x[k] - center[k])) <= M_PI / 2) continue;
    x[k] -= M_PI;
    x[k + 2] = -x[k + 2];
    x[k + 3] = -x[k + 3];
    x[betaEntry(r, dof)] = -x[betaEntry(r, dof)];
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

namespace {

// The entries of the base row and joint 1's row that the gauge (the base-frame rule) sets: flagged, sd 0.
void markGaugeFixed(DhUncertainty& out, const std::vector<bool>& gauge_fixed, int n) {
  for (int r = 0; r < 2 && r <= n; ++r) {
    DhUncertainty::Fixed& f = r == 0 ? out.base_fixed : out.links_fixed[0];
    DhParams& deviation = r == 0 ? out.base : out.links[0];
    bool* flags[4] = {&f.gauge_theta, &f.gauge_d, &f.gauge_alpha, &f.gauge_a};
    double* entries[4] = {&deviation.theta, &deviation.d, &deviation.alpha, &deviation.a};
    for (int e = 0; e < 4; ++e) {
      if (!gauge_fixed[static_cast<size_t>(4 * r + e)] || !std::isfinite(*entries[e])) continue;
      *flags[e] = true;
      *entries[e] = 0.0;
    }
  }
}

// The entries the D-H convention sets (a Hayati row's d, a row placed by a prismatic axis): flagged, sd 0.
void markConventionFixed(DhUncertainty& out, const CalibrationResult& result) {
  const ErrorModel& em = result.error_model;
  const int n = result.model.dof();
  // a row placed by a prismatic axis (the base for joint 1, link_{i-1} for joint i) has a = d = 0 by the
  // conversion's convention; an offset of joint i-1 folds into that row's d when joint i-1 slides
  // (prismatic, helical) and is nonzero or fitted
  for (int r = 0; r <= n; ++r) {
    const DhParams& central = r == 0 ? out.conversion.model.base() : out.conversion.model.joint(r - 1).link;
    if (!central.hayati() || central.d != 0.0) continue;
    (r == 0 ? out.base_fixed : out.links_fixed[static_cast<size_t>(r - 1)]).d = true;
    (r == 0 ? out.base : out.links[static_cast<size_t>(r - 1)]).d = 0.0;
  }
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
}

// `place`: where every model the propagation visits is put before its conversion (the measurement frame as
// calibrated, or the nominal's base frame); `gauge`: flag the base row's and joint 1's row's entries no
// parameter moves.
DhUncertainty propagate(const CalibrationResult& result, const std::function<PoeModel(const PoeModel&)>& place,
                        bool gauge) {
  const ErrorModel& em = result.error_model;
  DhUncertainty out{poeToDh(place(result.model)), {}, {}, {}, {}, 0.0, 0.0, {}, {}};
  std::vector<bool> angle;
  const VecX center = dhNumbers(out.conversion.model, &angle);
  const int n = result.model.dof();
  VecX variance = VecX::Zero(center.size());
  // the perturbed tables keep the central table's row kinds (standard or Hayati), so that they compare
  ConvertOptions same_kinds;
  same_kinds.row_kinds.push_back(out.conversion.model.base().kind);
  for (const DhJoint& j : out.conversion.model.joints()) same_kinds.row_kinds.push_back(j.link.kind);
  auto spread = [&](const VecX& direction) -> VecX {  // half the D-H difference between +direction and -direction
    try {
      VecX plus = dhNumbers(poeToDh(place(em.apply(direction)), same_kinds).model);
      VecX minus = dhNumbers(poeToDh(place(em.apply(-direction)), same_kinds).model);
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
  // the gauge: an entry of the base row or joint 1's row that no parameter moves (a probe along each, as
  // above) is set by the base-frame rule, not measured
  std::vector<bool> gauge_fixed(8, gauge);
  if (gauge) {
    for (int p = 0; p < em.size(); ++p) {
      const VecX moved = spread(kProbe * per_unit[p] * VecX::Unit(em.size(), p));
      for (Eigen::Index k = 0; k < 8 && k < moved.size(); ++k) {
        if (!(std::abs(moved[k]) <= kMoved * kProbe * dh_unit[k])) gauge_fixed[static_cast<size_t>(k)] = false;
      }
    }
  }
  // d of a row placed by a parallel axis is the conversion's free choice (0): nothing can determine it;
  // except the base row in the base frame, whose z is joint 1's line: its d (0) is the gauge's, as its a
  for (size_t r = 0; r < out.conversion.rows.size(); ++r) {
    if (!out.conversion.rows[r].parallel || (r == 0 && gauge_fixed[1])) continue;
    variance[r == 0 ? 1 : 4 + 6 * static_cast<Eigen::Index>(r - 1) + 1] = kInf;
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
  // beta: a Hayati row's kind and standard deviation; its d is 0 by the convention (fixed) unless a folded
  // offset moved it
  for (int r = 0; r <= n; ++r) {
    const DhParams& central = r == 0 ? out.conversion.model.base() : out.conversion.model.joint(r - 1).link;
    if (!central.hayati()) continue;
    DhParams& deviation = r == 0 ? out.base : out.links[static_cast<size_t>(r - 1)];
    deviation.kind = DhRowKind::Hayati;
    deviation.beta = sd[betaEntry(r, n)];
  }
  out.links_fixed.resize(static_cast<size_t>(n));
  markGaugeFixed(out, gauge_fixed, n);
  markConventionFixed(out, result);
  return out;
}

}  // namespace

DhUncertainty dhUncertainty(const CalibrationResult& result) {
  return propagate(result, [](const PoeModel& m) { return m; }, false);
}

DhUncertainty dhUncertainty(const CalibrationResult& result, const PoeModel& nominal) {
  const BaseFrameRule rule = baseFrameRule(nominal);
  return propagate(result, [&](const PoeModel& m) { return toNominalBase(m, nominal, rule).model; }, true);
}

MeasurementFrameUncertainty measurementFrameUncertainty(const CalibrationResult& result, const PoeModel& nominal) {
  const BaseFrameRule rule = baseFrameRule(nominal);
  const ErrorModel& em = result.error_model;
  const Pose center = toNominalBase(result.model, nominal, rule).T_measurement_base;
  // the change of T_measurement_base: [rotation about the measurement frame's axes; position]
  auto change = [&](const VecX& delta) -> Vec6 {
    const Pose T = toNominalBase(em.apply(delta), nominal, rule).T_measurement_base;
    Vec6 d;
    d << logSO3(T.R * center.R.transpose()), T.p - center.p;
    return d;
  };
  Vec6 variance = Vec6::Zero();
  for (Eigen::Index i = 0; i < result.principal_axes.cols(); ++i) {
    try {
      const Vec6 half = 0.5 * (change(result.principal_axes.col(i)) - change(-result.principal_axes.col(i)));
      variance += half.cwiseAbs2();
    } catch (const std::invalid_argument&) {  // a one-sigma step through a non-positive scale
      variance.setConstant(kInf);
    }
  }
  // an undetermined direction that moves the frame leaves it undetermined (probe as dhUncertainty)
  constexpr double kProbe = 1e-6, kMoved = 1e-6;
  const double L = result.model.lengthScale();
  for (Eigen::Index i = 0; i < result.undetermined_directions.cols(); ++i) {
    VecX dir = result.undetermined_directions.col(i);
    VecX scaled = dir;
    for (int k = 0; k < em.size(); ++k) {
      const std::string& unit = em.parameters()[static_cast<size_t>(k)].unit;
      if (unit != "rad" && unit != "1") scaled[k] /= L;
    }
    const Vec6 moved = change(kProbe * dir / scaled.norm());
    for (int k = 0; k < 6; ++k) {
      if (!(std::abs(moved[k]) <= kMoved * kProbe * (k < 3 ? 1.0 : L))) variance[k] = kInf;
    }
  }
  if (!result.noise_stated && !(result.variance_factor >= 0.0)) variance.setConstant(kInf);
  for (int k = 0; k < 6; ++k) {  // not below rounding
    const double resolution = kEps * (k < 3 ? 1.0 : std::max(L, std::abs(center.p[k - 3])));
    variance[k] = std::max(variance[k], resolution * resolution);
  }
  const Vec6 sd = variance.cwiseSqrt();
  return {sd.head<3>(), sd.tail<3>()};
}

}  // namespace lowpair
