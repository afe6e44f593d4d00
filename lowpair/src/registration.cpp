#include "lowpair/registration.hpp"
#include "calibration_internal.hpp"
#include "linalg.hpp"

#include <algorithm>
#include <cmath>

#include "check.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"

namespace lowpair {

using namespace detail;

namespace detail {

void checkTargetIndex(const Measurement& m, Measure measure, size_t targets) {
  if (measure != Measure::Targets) return;
  LP_CHECK(m.target == kPoseMeasurement || (m.target >= 0 && static_cast<size_t>(m.target) < targets),
           "measurement of target " << m.target << ": there are " << targets << " targets");
}

Pose predict(const PoeModel& model, Data& data, const Measurement& m, Measure measure,
             const std::vector<Vec3>& target_points) {
  forwardKinematics(model, data, m.q);
  if (measuresPose(m, measure) || measure == Measure::Position) return data.T_base_tool;
  checkTargetIndex(m, measure, target_points.size());
  const Pose& T = data.T_base_tool;
  return Pose{T.R, T.R * target_points[static_cast<size_t>(m.target)] + T.p};
}

MeasurementErrors measurementErrors(const Pose& predicted, const Measurement& m, Measure measure) {
  return {(m.T_base_tool.p - predicted.p).norm(),
          measuresPose(m, measure) ? rotationAngle(predicted.R.transpose() * m.T_base_tool.R) : 0.0};
}

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

}  // namespace detail

namespace {

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

}  // namespace

namespace detail {

Registration registration(const PoeModel& model, const std::vector<Measurement>& measurements, Measure measure,
                          const std::vector<Target>& targets, bool frame) {
  checkMeasurements(model, measurements, measure, targets.size());
  Registration out;
  out.target_points.resize(targets.size(), Vec3::Zero());
  out.estimated.resize(targets.size(), false);
  bool estimate = false;
  for (size_t t = 0; t < targets.size(); ++t) {
    if (targets[t].point_tool) {
      LP_CHECK(targets[t].point_tool->allFinite(), "target " << targets[t].name << ": non-finite point");
      out.target_points[t] = *targets[t].point_tool;
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
  std::vector<Mat3> R_pred, R_meas;  // of the pose measurements (all, or those among target measurements)
  for (size_t m = 0; m < measurements.size(); ++m) {
    if (!measuresPose(measurements[m], measure)) continue;
    R_pred.push_back(T[m].R);
    R_meas.push_back(measurements[m].T_base_tool.R);
  }
  const bool rotations = !R_pred.empty();
  for (size_t m = 0; m < measurements.size(); ++m) y[m] = measurements[m].T_base_tool.p;
  // alternate: the frame for the current points, then each unknown point for the frame (the mean of its
  // measured points in the predicted tool frame), until neither moves by more than rounding
  constexpr int kMaxAlternations = 1000;
  constexpr double kSettled = 1e-13;
  for (out.iterations = 1; out.iterations <= kMaxAlternations; ++out.iterations) {
    for (size_t m = 0; m < measurements.size(); ++m) {
      const int t = measurements[m].target;
      x[m] = measure == Measure::Targets && t >= 0 ? Vec3(T[m].R * out.target_points[static_cast<size_t>(t)] + T[m].p) : T[m].p;
    }
    Pose g;
    if (frame) {
      g = rigidFit(x, y, rotations ? &R_pred : nullptr, rotations ? &R_meas : nullptr, L, out.determined);
    }
    double moved = rotationAngle(g.R.transpose() * out.T_meas_base.R) + (g.p - out.T_meas_base.p).norm() / L;
    out.T_meas_base = g;
    if (estimate) {
      std::vector<Vec3> sum(targets.size(), Vec3::Zero());
      std::vector<int> count(targets.size(), 0);
      const Pose g_inv = g.inverse();
      for (size_t m = 0; m < measurements.size(); ++m) {
        if (measurements[m].target == kPoseMeasurement) continue;
        const auto t = static_cast<size_t>(measurements[m].target);
        if (!out.estimated[t]) continue;
        sum[t] += T[m].R.transpose() * (g_inv.R * y[m] + g_inv.p - T[m].p);
        ++count[t];
      }
      for (size_t t = 0; t < targets.size(); ++t) {
        if (!out.estimated[t]) continue;
        LP_CHECK(count[t] > 0, "target " << targets[t].name << " has no point and no measurement to estimate it from");
        const Vec3 p = sum[t] / count[t];
        moved = std::max(moved, (p - out.target_points[t]).norm() / L);
        out.target_points[t] = p;
      }
    }
    if (!estimate || moved <= kSettled) break;
  }
  out.iterations = std::min(out.iterations, kMaxAlternations);
  return out;
}

}  // namespace detail

Pose predictedMeasurement(const PoeModel& model, const Measurement& m, Measure measure,
                          const std::vector<Vec3>& target_points) {
  checkJointVector(m.q, model.dof());
  Data data(model);
  return predict(model, data, m, measure, target_points);
}

ResidualStatistics residualStatistics(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Vec3>& target_points) {
  ResidualStatistics s;
  Data data(model);
  double sum_p = 0.0, sum_r = 0.0;
  int rotations = 0;  // the pose measurements (mixed data: some of them)
  for (const Measurement& m : measurements) {
    checkJointVector(m.q, model.dof());
    const auto [ep, er] = measurementErrors(predict(model, data, m, measure, target_points), m, measure);
    sum_p += ep * ep;
    sum_r += er * er;
    rotations += measuresPose(m, measure) ? 1 : 0;
    s.max_position = std::max(s.max_position, ep);
    s.max_rotation = std::max(s.max_rotation, er);
    ++s.count;
  }
  if (s.count > 0) s.rms_position = std::sqrt(sum_p / s.count);
  if (rotations > 0) s.rms_rotation = std::sqrt(sum_r / rotations);
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

Registration registerMeasurementFrame(const PoeModel& model, const std::vector<Measurement>& measurements,
                                      Measure measure, const std::vector<Target>& targets) {
  return registration(model, measurements, measure, targets, true);
}

}  // namespace lowpair
