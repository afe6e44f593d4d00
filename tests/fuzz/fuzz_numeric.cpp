// Fuzz target: the numeric API. The input's bytes become numbers (Bytes below: raw doubles, small integers,
// powers of ten, tiny perturbations, multiples of pi), the numbers a PoeModel: 1-7 joints (twist, declared
// type or none, offset, optional range), a tool (twist, axis-angle pose, or a raw matrix). Construction
// may throw std::invalid_argument; an accepted model must give finite output at three finite joint vectors
// within the ranges (no range: revolute/helical in [-1e3, 1e3], prismatic in [-L, L]):
// forwardKinematics, computeJacobians and the three getters, analyzeSingularity, poeToDh +
// checkDhConversion, dhToPoe of the table (FK again), analyzeIdentifiability on the three poses,
// ErrorModel::jacobian. Documented infinities (a condition number at rank deficiency) may be +inf, never NaN.
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "fuzz_common.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"

namespace {

using namespace lowpair;

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : p_(data), n_(size) {}
  uint8_t byte() {
    if (n_ == 0) return 0;
    --n_;
    return *p_++;
  }
  int8_t sbyte() { return static_cast<int8_t>(byte()); }
  double number() {
    switch (byte() % 8) {
      case 0: return 0.0;
      case 1: return sbyte();
      case 2: return static_cast<int16_t>(byte() | byte() << 8) / 256.0;
      case 3: {  // any double, non-finite ones included
        uint64_t bits = 0;
        for (int i = 0; i < 8; ++i) bits |= uint64_t{byte()} << (8 * i);
        double x;
        std::memcpy(&x, &bits, sizeof x);
        return x;
      }
      case 4: return sbyte() / 16.0 * std::pow(10.0, sbyte() % 40);
      case 5: return 1.0 + sbyte() * 1e-12 * std::pow(10.0, byte() % 12);
      case 6: return sbyte() / 16.0 * M_PI;
      default: return sbyte() * std::pow(10.0, -(byte() % 20));
    }
  }
  Vec3 vec3() { return Vec3(number(), number(), number()); }
  Vec6 vec6() {
    Vec6 v;
    for (int i = 0; i < 6; ++i) v[i] = number();
    return v;
  }

 private:
  const uint8_t* p_;
  size_t n_;
};

// LOWPAIR_FUZZ_VERBOSE=1: print the decoded model and joint vectors (to report a finding).
const bool kVerbose = [] {
  const char* v = std::getenv("LOWPAIR_FUZZ_VERBOSE");
  return v && *v == '1';
}();

void print(const char* what, const Eigen::Ref<const MatX>& m) {
  std::fprintf(stderr, "%s:", what);
  for (Eigen::Index c = 0; c < m.cols(); ++c)
    for (Eigen::Index r = 0; r < m.rows(); ++r) std::fprintf(stderr, " %.17g", m(r, c));
  std::fprintf(stderr, "\n");
}

bool finiteOrPlusInf(double x) { return std::isfinite(x) || x == std::numeric_limits<double>::infinity(); }

void checkRank(const RankAnalysis& r) {
  FUZZ_CHECK(r.singular_values.allFinite() && std::isfinite(r.tolerance));
  FUZZ_CHECK(finiteOrPlusInf(r.condition));
  for (const double o : r.observability) FUZZ_CHECK(std::isfinite(o));
  for (const auto& dir : r.undetermined)
    for (const auto& c : dir) FUZZ_CHECK(std::isfinite(c.second));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  const int n = 1 + in.byte() % 7;
  std::vector<JointSpec> specs(static_cast<size_t>(n));
  for (JointSpec& s : specs) {
    const uint8_t flags = in.byte();
    if (flags % 4) s.type = static_cast<JointType>(flags % 4 - 1);
    s.twist = in.vec6();
    if (flags & 4) s.offset = in.number();
    if (flags & 8) {
      double lo = in.number(), hi = in.number();
      if (flags & 16 && lo > hi) std::swap(lo, hi);
      s.range = std::array<double, 2>{lo, hi};
    }
  }
  const uint8_t tool_mode = in.byte();
  const uint8_t options = in.byte();
  std::optional<PoeModel> built;
  try {
    switch (tool_mode % 3) {
      case 0: built.emplace(PoeModel::fromToolTwist(specs, in.vec6(), "fuzz")); break;
      case 1: {
        const Vec3 axis = in.vec3();
        const double angle = in.number();
        Pose T;
        if (axis.allFinite() && axis.norm() > 0 && std::isfinite(angle))
          T.R = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
        T.p = in.vec3();
        built.emplace(specs, T, "fuzz");
        break;
      }
      default: {
        Pose T;
        for (int i = 0; i < 9; ++i) T.R(i / 3, i % 3) = in.number();
        T.p = in.vec3();
        built.emplace(specs, T, "fuzz");
      }
    }
  } catch (const std::invalid_argument&) {
    return 0;
  }
  const PoeModel& model = *built;
  if (kVerbose) {
    for (const JointSpec& sp : specs) {
      std::fprintf(stderr, "joint type %s offset %.17g", sp.type ? jointTypeName(*sp.type) : "(inferred)", sp.offset);
      if (sp.range) std::fprintf(stderr, " range [%.17g, %.17g]", (*sp.range)[0], (*sp.range)[1]);
      print(" twist", sp.twist);
    }
    print("tool R (column-major)", model.toolPose().R);
    print("tool p", model.toolPose().p);
    std::fprintf(stderr, "size L %.17g, options %d\n", model.lengthScale(), options);
  }
  FUZZ_CHECK(model.dof() == n && std::isfinite(model.lengthScale()));
  const double L = model.lengthScale();

  // three joint vectors within the ranges
  std::vector<VecX> qs;
  for (int k = 0; k < 3; ++k) {
    VecX q(n);
    for (int i = 0; i < n; ++i) {
      const Joint& j = model.joint(i);
      double x = in.number();
      if (!std::isfinite(x)) x = 0.0;
      if (j.range) {
        x = std::clamp(x, (*j.range)[0], (*j.range)[1]);
      } else if (j.type == JointType::Prismatic) {
        x = std::clamp(x, -L, L);
      } else {
        x = std::fmod(x, 1e3);
      }
      q[i] = x;
    }
    qs.push_back(q);
    if (kVerbose) print("q", q);
  }

  Data d(model);
  Mat6X J(6, n);
  for (const VecX& q : qs) {
    forwardKinematics(model, d, q);
    FUZZ_CHECK(lowpair_fuzz::finite(d.T_base_tool));
    computeJacobians(model, d, q);
    FUZZ_CHECK(lowpair_fuzz::finite(d.T_base_tool) && d.J_spatial.allFinite());
    for (const Pose& T : d.T_base_joint) FUZZ_CHECK(lowpair_fuzz::finite(T));
    getSpatialJacobian(d, J);
    FUZZ_CHECK(J.allFinite());
    getBodyJacobian(d, J);
    FUZZ_CHECK(J.allFinite());
    getGeometricJacobian(d, J);
    FUZZ_CHECK(J.allFinite());

    SingularityOptions so;
    so.max_null_vectors = 6;
    const SingularityReport s = analyzeSingularity(model, q, so);
    FUZZ_CHECK(s.singular_values.allFinite() && std::isfinite(s.sigma_min) && finiteOrPlusInf(s.manipulability));
    FUZZ_CHECK(finiteOrPlusInf(s.condition) && std::isfinite(s.tolerance) && std::isfinite(s.length_scale));
    for (const JointLine& l : s.lines) FUZZ_CHECK(l.direction.allFinite() && l.point.allFinite() && std::isfinite(l.pitch));
    for (const SingularClass& c : s.classes) {
      if (kVerbose && !(c.point.allFinite() && c.direction.allFinite())) {
        std::fprintf(stderr, "class %s joints", c.id.c_str());
        for (const int j : c.joints) std::fprintf(stderr, " %d", j);
        std::fprintf(stderr, " at_infinity %d\n", c.at_infinity);
        print("point", c.point);
        print("direction", c.direction);
        print("at q", q);
      }
      FUZZ_CHECK(c.point.allFinite() && c.direction.allFinite());
    }
    FUZZ_CHECK(s.decoupled.wrist_point.allFinite() && std::isfinite(s.decoupled.wrist_sigma_min) &&
               std::isfinite(s.decoupled.arm_sigma_min));
    for (const VecX& v : s.null_space) FUZZ_CHECK(v.allFinite());
  }

  // D-H and back
  const bool has_dh = lowpair_fuzz::checkConversion(model);
  if (has_dh) {
    const PoeModel back = dhToPoe(poeToDh(model).model);
    FUZZ_CHECK(back.dof() == n);
    for (const VecX& q : qs) FUZZ_CHECK(lowpair_fuzz::finite(poeForwardKinematics(back, q)));
  }

  // calibration
  const bool free_pitch = options & 1;
  const Measure measure = options & 2 ? Measure::Position : Measure::Pose;
  const ErrorModel em(model, ErrorModelSpec{free_pitch});
  MatX rows(measure == Measure::Pose ? 6 : 3, em.size());
  for (const VecX& q : qs) {
    FUZZ_CHECK(lowpair_fuzz::finite(em.jacobian(q, measure, rows)));
    FUZZ_CHECK(rows.allFinite());
  }
  if (options & 4 && has_dh) {  // without a D-H table it throws as poeToDh did
    const Identifiability id = analyzeIdentifiability(model, qs, measure, ErrorModelSpec{free_pitch});
    checkRank(id.poe);
    checkRank(id.dh);
    FUZZ_CHECK(id.full_model_rank >= 0 && id.full_model_rank <= id.full_model_columns);
  }
  return 0;
}
