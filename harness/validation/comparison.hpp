#pragma once
/// @file comparison.hpp
/// The comparisons of `lowpair validate`, one object each: a name, a kind (pose or Jacobian), two
/// tolerances and a per-sample measure that, given MuJoCo's tip pose and Jacobian at the physical joint
/// motion x, returns (rotation error, translation error). Each comparison makes its own per-thread
/// workspace (the library's `Data` and scratch vectors), so a worker thread owns everything it writes.
///
/// Errors are accumulated in constant memory per comparison and per thread (ErrorStatistics) and merged
/// after the threads joined; the merge is exact (max, counts, histogram, worst sample, and the sums,
/// which are kept as exact fixed-point integers), so the results do not depend on --threads.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

namespace lowpair::validation {

/// One sample as a comparison sees it: the physical joint motion `x` (conventions.md, the joint-variable
/// map) and MuJoCo's answer there: the tip pose and the geometric Jacobian d/dx (rows [v; w]).
struct ReferenceSample {
  const VecX& x;
  const Pose& T_mujoco;
  const Mat6X& J_mujoco;
};

/// The error of one sample. Pose comparisons: geodesic rotation angle (rad), tip distance (length), and
/// the paper's ||EA_ZYX|| (eq. 19) in `rotation_euler`. Jacobian comparisons: largest deviation of the
/// dimensionless angular block and L times that of the linear block; `rotation_euler` is 0.
struct SampleErrors {
  double rotation = 0.0, translation = 0.0, rotation_euler = 0.0;
};

/// A named comparison with its tolerances (translation already in length units, i.e. times L).
class Comparison {
 public:
  enum class Kind { Pose, Jacobian };
  /// Per-thread state of a comparison (library workspaces); made by workspace(), used by one thread.
  struct Workspace {
    virtual ~Workspace() = default;
  };

  Comparison(std::string name, Kind kind, double tolerance_rotation, double tolerance_translation)
      : name_(std::move(name)), kind_(kind), tol_rotation_(tolerance_rotation), tol_translation_(tolerance_translation) {}
  virtual ~Comparison() = default;
  Comparison(const Comparison&) = delete;
  Comparison& operator=(const Comparison&) = delete;

  const std::string& name() const { return name_; }
  Kind kind() const { return kind_; }
  double toleranceRotation() const { return tol_rotation_; }
  double toleranceTranslation() const { return tol_translation_; }

  virtual std::unique_ptr<Workspace> workspace() const = 0;
  /// The error of the library against MuJoCo at one sample. Allocates nothing.
  virtual SampleErrors measure(Workspace& workspace, const ReferenceSample& sample) const = 0;

 private:
  std::string name_;
  Kind kind_;
  double tol_rotation_, tol_translation_;
};

/// The forward kinematics of `model` against MuJoCo's tip pose. The model gets its own joint variables
/// from the motion: `q_i = model.joint(i).variable(x_i)`.
std::unique_ptr<Comparison> poseComparison(std::string name, PoeModel model, double tolerance_rotation,
                                           double tolerance_translation);
std::unique_ptr<Comparison> poseComparison(std::string name, DhModel model, double tolerance_rotation,
                                           double tolerance_translation);
/// The library's geometric Jacobian of `model` against MuJoCo's. The model is evaluated at its own joint
/// variable (`q_i = joint(i).variable(x_i)`, columns d/dq_i) and MuJoCo's columns (d/dx_i) are taken to d/dq_i
/// by the chain rule (times scale_i; MuJoCo's extracted model has scale 1, so nothing changes there). Both
/// are made dimensionless (singularity.hpp: linear rows over L, columns over the scale, prismatic columns
/// times L), so a prismatic column's unitless linear part and a revolute column's length per rad share
/// one scale; the linear deviation is reported times L.
std::unique_ptr<Comparison> jacobianComparison(std::string name, PoeModel model, double tolerance_rotation,
                                               double tolerance_translation);

/// Exact sum of finite non-negative doubles: a fixed-point integer whose unit is the smallest subnormal
/// (2^-1074), wide enough for 2^63 terms of the largest double. Adding is exact, so the sum does not
/// depend on the order of the terms (or on how they were split among threads).
class ExactSum {
 public:
  void add(double value);  ///< value finite and >= 0 (checked by LP_ASSERT only)
  void add(const ExactSum& other);
  double value() const;  ///< the sum, rounded (the same double for the same set of terms)

 private:
  static constexpr int kWords = 35;  // 2098 bits for one double + 63 bits of carries, in 64-bit words
  std::array<std::uint64_t, kWords> words_{};
};

/// Counts of values on a log scale: kBinsPerDecade bins per decade over [10^kMinExponent, 10^kMaxExponent),
/// one bin below (including 0) and one at or above. quantile() answers the geometric middle of the bin
/// holding the value of that rank, clamped to the largest value seen: for a value in the log range its
/// relative error is at most 10^(1 / (2 kBinsPerDecade)) - 1 = 1.16 % (100 bins per decade from 1e-20 to
/// 1e2; a bin is 2.3 % wide). Below 1e-20 the largest such value is answered (absolute error < 1e-20);
/// at or above 1e2, the largest value (an upper bound). Memory: 2202 counters.
class LogHistogram {
 public:
  static constexpr int kBinsPerDecade = 100, kMinExponent = -20, kMaxExponent = 2;
  static constexpr int kLogBins = (kMaxExponent - kMinExponent) * kBinsPerDecade;
  static constexpr int kBins = kLogBins + 2;  ///< [0] below, [1..kLogBins] the log bins, [kBins-1] above

  void add(double value);  ///< value finite and >= 0
  void merge(const LogHistogram& other);
  long long count() const { return count_; }
  /// The value of rank ceil(p count) (1-based; the nearest-rank p-quantile), within the error above.
  /// 0 when empty.
  double quantile(double p) const;
  const std::array<long long, kBins>& counts() const { return counts_; }
  /// log10 of the lower edge of log bin b (1..kLogBins).
  static double lowerExponent(int b) { return kMinExponent + static_cast<double>(b - 1) / kBinsPerDecade; }

 private:
  std::array<long long, kBins> counts_{};
  long long count_ = 0;
  double max_below_ = 0.0;  ///< largest value below 10^kMinExponent
  double max_ = 0.0;        ///< largest value
};

struct ComparisonResult;

/// Constant-memory statistics of one comparison over a stream of samples, each identified by its index in
/// the run: count, non-finite count (NaN or inf in any error: the comparison fails), max, exact sums for
/// the mean, histograms for the 99th percentile (LogHistogram; translation binned relative to L) and the
/// worst sample (largest error / tolerance; ties go to the smaller index; the first non-finite one, if any).
class ErrorStatistics {
 public:
  /// @param length L: translation errors are binned relative to it
  ErrorStatistics(double tolerance_rotation, double tolerance_translation, double length);
  void add(long long index, const SampleErrors& e);
  /// Adds another thread's (or shard's) statistics; exact: the result does not depend on the split.
  void merge(const ErrorStatistics& other);

  long long count() const { return count_; }
  long long nonFinite() const { return non_finite_; }
  /// The worst sample's index (-1 when nothing was added).
  long long worstIndex() const { return non_finite_ > 0 ? first_non_finite_ : worst_index_; }
  /// Fills the statistics, tolerances and pass flag of `c` (name, kind and worst_q are the caller's).
  /// With a non-finite sample every statistic is NaN (JSON null) and the comparison fails.
  void summarize(ComparisonResult& c) const;

 private:
  double tol_rotation_, tol_translation_, length_;
  long long count_ = 0, non_finite_ = 0, first_non_finite_ = -1, worst_index_ = -1;
  double worst_score_ = -1.0;
  double max_rotation_ = 0.0, max_translation_ = 0.0, max_rotation_euler_ = 0.0;
  ExactSum sum_rotation_, sum_translation_;
  LogHistogram rotation_, translation_;  // rad; translation / L
};

/// A bounded, deterministic subsample of the per-sample errors for the report's picture: every
/// stride-th sample (index % stride == 0), stride = ceil(count / kMaxPoints), so at most kMaxPoints points.
/// Threads write disjoint entries.
struct PlotSamples {
  static constexpr long long kMaxPoints = 20000;
  explicit PlotSamples(long long count, double length);
  void record(long long index, const SampleErrors& e) {
    if (index % stride != 0) return;
    rotation[static_cast<size_t>(index / stride)] = static_cast<float>(e.rotation);
    translation[static_cast<size_t>(index / stride)] = static_cast<float>(e.translation / length);
  }
  long long stride = 1;
  double length = 1.0;
  std::vector<float> rotation, translation;  ///< rad; length / L
};

}  // namespace lowpair::validation
