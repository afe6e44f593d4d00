#pragma once
// Random arms whose errors favour one parameter level, and what each level and cross-validation give on them:
// shared by tracker_test.cpp (CrossValidationPicksANearBestLevel) and cross_validation_study.cpp (the study behind
// docs/calibration.md "Which parameters").

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "calibration_helpers.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/kinematics.hpp"

namespace calibration_helpers {

// RMS over poses of the predicted points' (or tool origins') distance from the truth's.
inline double heldOutRms(const PoeModel& model, const std::vector<Vec3>& targets, const PoeModel& truth,
                  const std::vector<Vec3>& true_targets, const std::vector<VecX>& qs) {
  double sum = 0.0;
  int count = 0;
  for (const VecX& q : qs) {
    const Pose A = poeForwardKinematics(model, q), B = poeForwardKinematics(truth, q);
    if (targets.empty()) {
      sum += (A.p - B.p).squaredNorm();
      ++count;
    }
    for (size_t t = 0; t < targets.size(); ++t) {
      sum += ((A.R * targets[t] + A.p) - (B.R * true_targets[t] + B.p)).squaredNorm();
      ++count;
    }
  }
  return std::sqrt(sum / count);
}

// A random 6-joint arm (about 1000 long) made actual by errors that favour one parameter level: 0 line, scale
// and offset errors (full), 1 line and offset errors, no scale errors (lines, usually), 2 offset and tool
// errors only (offsets). Line errors `line_error` (rad, L; 1e-3 unless said), offsets 2e-3 rad.
struct FavouringArm {
  PoeModel nominal, actual;
};
inline FavouringArm favouringArm(const std::string& types, int favours, std::mt19937_64& rng, double line_error = 1e-3) {
  const PoeModel nominal = jointMix(types, 1000.0, rng);
  const ErrorModel em(nominal);
  VecX d = smallDelta(em, line_error, false, rng);
  for (int k = 0; k < em.size(); ++k) {
    const ParameterKind kind = em.parameters()[static_cast<size_t>(k)].kind;
    if (favours == 1 && kind == ParameterKind::Scale) d[k] = 0.0;
    if (favours == 2 && kind != ParameterKind::ToolRotation && kind != ParameterKind::ToolTranslation) d[k] = 0.0;
  }
  const PoeModel moved = em.apply(d);
  std::vector<Joint> joints = moved.joints();
  std::normal_distribution<double> n;
  for (Joint& j : joints) j.offset += 2e-3 * n(rng);
  return {nominal, PoeModel(joints, moved.toolPose(), moved.name())};
}

// What the levels give on one arm: 15 poses measured with 0.5 per coordinate and 5e-4 rad of noise (read as
// `kind`), each level fitted to them and its RMS on 200 uniform held-out poses, and cross-validation's
// choice with each of `repeats` partitions.
struct LevelOutcome {
  double held_out[3] = {kInf, kInf, kInf};  // full, lines, offsets
  double best = kInf;
  std::vector<CrossValidation> cv;  // one per entry of repeats
  double chosen(size_t k) const { return held_out[level(cv[k].chosen)]; }
  static int level(ParameterSet set) { return set == ParameterSet::Full ? 0 : set == ParameterSet::Lines ? 1 : 2; }
};
inline LevelOutcome levelOutcome(const FavouringArm& arm, Measure kind, const std::vector<int>& repeats,
                          std::mt19937_64& rng) {
  std::vector<Measurement> ms = measure(arm.actual, uniformPoses(arm.nominal, 15, rng));
  addNoise(ms, 0.5, 5e-4, rng);
  CalibrationOptions options;
  options.measure = kind;
  options.sigma_position = 0.5;
  options.sigma_rotation = 5e-4;  // (weighs nothing for position data)
  LevelOutcome out;
  for (const int r : repeats) out.cv.push_back(crossValidate(arm.nominal, ms, options, 5, r));
  const std::vector<VecX> check = uniformPoses(arm.nominal, 200, rng);
  for (const ParameterSet set : {ParameterSet::Full, ParameterSet::Lines, ParameterSet::Offsets}) {
    options.parameters = set;
    const double rms = heldOutRms(calibrate(arm.nominal, ms, options).model, {}, arm.actual, {}, check);
    out.held_out[LevelOutcome::level(set)] = rms;
    out.best = std::min(out.best, rms);
  }
  return out;
}

}  // namespace calibration_helpers
