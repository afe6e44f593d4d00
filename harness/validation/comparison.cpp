#include "validation/comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "validation/validate.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below

namespace {

template <class Model>
class PoseComparison final : public Comparison {
 public:
  PoseComparison(std::string name, Model model, double tolerance_rotation, double tolerance_translation)
      : Comparison(std::move(name), Kind::Pose, tolerance_rotation, tolerance_translation), model_(std::move(model)) {}

  std::unique_ptr<Workspace> workspace() const override { return std::make_unique<State>(model_); }

  SampleErrors measure(Workspace& workspace, const ReferenceSample& sample) const override {
    State& s = static_cast<State&>(workspace);
    // the model's own joint variable at the same physical motion
    for (int i = 0; i < model_.dof(); ++i) s.q[i] = model_.joint(i).variable(sample.x[i]);
    forwardKinematics(model_, s.data, s.q);
    const Pose& T = s.data.T_base_tool;
    SampleErrors e;
    e.rotation = rotationError(sample.T_mujoco.R, T.R);
    e.translation = (T.p - sample.T_mujoco.p).norm();
    e.rotation_euler = eulerZyxError(T.R, sample.T_mujoco.R);
    return e;
  }

 private:
  struct State : Workspace {
    explicit State(const Model& model) : data(model), q(model.dof()) {}
    Data data;
    VecX q;
  };
  Model model_;
};

class JacobianComparison final : public Comparison {
 public:
  JacobianComparison(std::string name, PoeModel model, double tolerance_rotation, double tolerance_translation)
      : Comparison(std::move(name), Kind::Jacobian, tolerance_rotation, tolerance_translation), model_(std::move(model)) {}

  std::unique_ptr<Workspace> workspace() const override { return std::make_unique<State>(model_); }

  SampleErrors measure(Workspace& workspace, const ReferenceSample& sample) const override {
    State& s = static_cast<State&>(workspace);
    // the model's own joint variable at the same physical motion; its Jacobian columns are d/dq_i
    for (int i = 0; i < model_.dof(); ++i) s.q[i] = model_.joint(i).variable(sample.x[i]);
    computeJacobians(model_, s.data, s.q);
    getGeometricJacobian(s.data, s.J_library);
    // MuJoCo's columns are d/dx_i; d/dq_i = d/dx_i * scale_i (x = scale (q + offset)). Exact for scale 1.
    for (int i = 0; i < model_.dof(); ++i) s.J_mujoco.col(i) = sample.J_mujoco.col(i) * model_.joint(i).scale;
    dimensionlessJacobian(model_, s.J_mujoco);
    dimensionlessJacobian(model_, s.J_library);
    SampleErrors e;
    // maxCoeff may skip NaN: a non-finite Jacobian is recorded as NaN so that the comparison fails
    if (!s.J_mujoco.allFinite() || !s.J_library.allFinite()) {
      e.rotation = e.translation = std::numeric_limits<double>::quiet_NaN();
      return e;
    }
    e.rotation = (s.J_mujoco.bottomRows<3>() - s.J_library.bottomRows<3>()).cwiseAbs().maxCoeff();
    e.translation = model_.lengthScale() * (s.J_mujoco.topRows<3>() - s.J_library.topRows<3>()).cwiseAbs().maxCoeff();
    return e;
  }

 private:
  struct State : Workspace {
    explicit State(const PoeModel& model) : data(model), q(model.dof()), J_library(6, model.dof()), J_mujoco(6, model.dof()) {}
    Data data;
    VecX q;
    Mat6X J_library, J_mujoco;
  };
  PoeModel model_;
};

}  // namespace

std::unique_ptr<Comparison> poseComparison(std::string name, PoeModel model, double tolerance_rotation,
                                           double tolerance_translation) {
  return std::make_unique<PoseComparison<PoeModel>>(std::move(name), std::move(model), tolerance_rotation,
                                                    tolerance_translation);
}

std::unique_ptr<Comparison> poseComparison(std::string name, DhModel model, double tolerance_rotation,
                                           double tolerance_translation) {
  return std::make_unique<PoseComparison<DhModel>>(std::move(name), std::move(model), tolerance_rotation,
                                                   tolerance_translation);
}

std::unique_ptr<Comparison> jacobianComparison(std::string name, PoeModel model, double tolerance_rotation,
                                               double tolerance_translation) {
  return std::make_unique<JacobianComparison>(std::move(name), std::move(model), tolerance_rotation,
                                              tolerance_translation);
}

// --- ExactSum ------------------------------------------------------------------------------------

void ExactSum::add(double value) {
  // 0 adds nothing; anything not finite and positive is never passed (ErrorStatistics counts it apart)
  if (!(value > 0.0) || !std::isfinite(value)) return;
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  const int exponent = static_cast<int>((bits >> 52) & 0x7ff);  // < 0x7ff: finite
  std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
  // value = mantissa * 2^(position - 1074): subnormals at position 0, normals with the implicit bit
  int position = 0;
  if (exponent > 0) {
    mantissa |= std::uint64_t{1} << 52;
    position = exponent - 1;
  }
  const int word = position / 64, bit = position % 64;
  const std::uint64_t parts[2] = {mantissa << bit, bit == 0 ? 0 : mantissa >> (64 - bit)};
  for (int k = 0; k < 2; ++k) {
    std::uint64_t carry = parts[k];
    for (int i = word + k; carry != 0 && i < kWords; ++i) {
      const std::uint64_t old = words_[static_cast<size_t>(i)];
      words_[static_cast<size_t>(i)] = old + carry;
      carry = words_[static_cast<size_t>(i)] < old ? 1 : 0;
    }
  }
}

void ExactSum::add(const ExactSum& other) {
  std::uint64_t carry = 0;
  for (size_t i = 0; i < words_.size(); ++i) {
    const std::uint64_t a = words_[i], b = other.words_[i];
    const std::uint64_t s = a + b;
    const std::uint64_t t = s + carry;
    carry = (s < a ? 1 : 0) + (t < s ? 1 : 0);
    words_[i] = t;
  }
}

double ExactSum::value() const {
  // the integer is unique for a set of terms, so this (not correctly rounded, a few ulps) is too
  double sum = 0.0;
  for (int i = 0; i < kWords; ++i) {
    const std::uint64_t w = words_[static_cast<size_t>(i)];
    if (w != 0) sum += std::ldexp(static_cast<double>(w), 64 * i - 1074);
  }
  return sum;
}

// --- LogHistogram --------------------------------------------------------------------------------

namespace {
constexpr double kHistogramLow = 1e-20;  // 10^kMinExponent
constexpr double kHistogramHigh = 1e2;   // 10^kMaxExponent
static_assert(LogHistogram::kMinExponent == -20 && LogHistogram::kMaxExponent == 2, "update the bounds above");
}  // namespace

void LogHistogram::add(double value) {
  ++count_;
  max_ = std::max(max_, value);
  if (value < kHistogramLow) {
    ++counts_[0];
    max_below_ = std::max(max_below_, value);
    return;
  }
  if (value >= kHistogramHigh) {
    ++counts_[kBins - 1];
    return;
  }
  const int b = static_cast<int>(std::floor((std::log10(value) - kMinExponent) * kBinsPerDecade)) + 1;
  ++counts_[static_cast<size_t>(std::clamp(b, 1, kLogBins))];
}

void LogHistogram::merge(const LogHistogram& other) {
  for (size_t b = 0; b < counts_.size(); ++b) counts_[b] += other.counts_[b];
  count_ += other.count_;
  max_below_ = std::max(max_below_, other.max_below_);
  max_ = std::max(max_, other.max_);
}

double LogHistogram::quantile(double p) const {
  if (count_ == 0) return 0.0;
  const long long rank =
      std::clamp(static_cast<long long>(std::ceil(p * static_cast<double>(count_))), 1LL, count_);
  long long cumulative = 0;
  for (int b = 0; b < kBins; ++b) {
    cumulative += counts_[static_cast<size_t>(b)];
    if (cumulative < rank) continue;
    if (b == 0) return max_below_;
    if (b == kBins - 1) return max_;
    return std::min(max_, std::pow(10.0, lowerExponent(b) + 0.5 / kBinsPerDecade));
  }
  return max_;
}

// --- ErrorStatistics -----------------------------------------------------------------------------

ErrorStatistics::ErrorStatistics(double tolerance_rotation, double tolerance_translation, double length)
    : tol_rotation_(tolerance_rotation), tol_translation_(tolerance_translation), length_(length) {}

void ErrorStatistics::add(long long index, const SampleErrors& e) {
  ++count_;
  // a sample that was not measured (NaN or inf) is never within tolerance: counted, and the comparison fails
  if (!std::isfinite(e.rotation) || !std::isfinite(e.translation) || !std::isfinite(e.rotation_euler)) {
    if (first_non_finite_ < 0 || index < first_non_finite_) first_non_finite_ = index;
    ++non_finite_;
    return;
  }
  sum_rotation_.add(e.rotation);
  sum_translation_.add(e.translation);
  max_rotation_ = std::max(max_rotation_, e.rotation);
  max_translation_ = std::max(max_translation_, e.translation);
  max_rotation_euler_ = std::max(max_rotation_euler_, e.rotation_euler);
  rotation_.add(e.rotation);
  translation_.add(e.translation / length_);
  const double score = std::max(e.rotation / tol_rotation_, e.translation / tol_translation_);
  if (worst_index_ < 0 || score > worst_score_ || (score == worst_score_ && index < worst_index_)) {
    worst_score_ = score;
    worst_index_ = index;
  }
}

void ErrorStatistics::merge(const ErrorStatistics& o) {
  count_ += o.count_;
  non_finite_ += o.non_finite_;
  if (o.first_non_finite_ >= 0 && (first_non_finite_ < 0 || o.first_non_finite_ < first_non_finite_)) {
    first_non_finite_ = o.first_non_finite_;
  }
  sum_rotation_.add(o.sum_rotation_);
  sum_translation_.add(o.sum_translation_);
  max_rotation_ = std::max(max_rotation_, o.max_rotation_);
  max_translation_ = std::max(max_translation_, o.max_translation_);
  max_rotation_euler_ = std::max(max_rotation_euler_, o.max_rotation_euler_);
  rotation_.merge(o.rotation_);
  translation_.merge(o.translation_);
  if (o.worst_index_ >= 0 && (worst_index_ < 0 || o.worst_score_ > worst_score_ ||
                              (o.worst_score_ == worst_score_ && o.worst_index_ < worst_index_))) {
    worst_score_ = o.worst_score_;
    worst_index_ = o.worst_index_;
  }
}

void ErrorStatistics::summarize(ComparisonResult& c) const {
  c.tolerance_rotation = tol_rotation_;
  c.tolerance_translation = tol_translation_;
  c.non_finite = non_finite_;
  c.rotation_histogram.assign(rotation_.counts().begin(), rotation_.counts().end());
  c.translation_histogram.assign(translation_.counts().begin(), translation_.counts().end());
  if (non_finite_ > 0) {
    // statistics of what was not measured are not numbers: reported as NaN (JSON null)
    const double nan = std::numeric_limits<double>::quiet_NaN();
    c.max_rotation = c.mean_rotation = c.p99_rotation = c.max_rotation_euler = nan;
    c.max_translation = c.mean_translation = c.p99_translation = nan;
    c.pass = false;
    return;
  }
  c.max_rotation = max_rotation_;
  c.max_translation = max_translation_;
  c.max_rotation_euler = max_rotation_euler_;
  if (count_ > 0) {
    c.mean_rotation = sum_rotation_.value() / static_cast<double>(count_);
    c.mean_translation = sum_translation_.value() / static_cast<double>(count_);
  }
  c.p99_rotation = rotation_.quantile(0.99);
  c.p99_translation = std::min(max_translation_, translation_.quantile(0.99) * length_);
  c.pass = max_rotation_ <= tol_rotation_ && max_translation_ <= tol_translation_;
}

// --- PlotSamples ---------------------------------------------------------------------------------

PlotSamples::PlotSamples(long long count, double length_) : length(length_) {
  stride = std::max(1LL, (count + kMaxPoints - 1) / kMaxPoints);
  const auto points = static_cast<size_t>((count + stride - 1) / stride);
  rotation.assign(points, 0.0f);
  translation.assign(points, 0.0f);
}

}  // namespace lowpair::validation
