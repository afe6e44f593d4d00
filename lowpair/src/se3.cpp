#include "lowpair/se3.hpp"

#include <array>
#include <cmath>

#include "exp_coefficients.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair {

const char* jointTypeName(JointType type) {
  switch (type) {
    case JointType::Revolute: return "revolute";
    case JointType::Prismatic: return "prismatic";
    case JointType::Helical: return "helical";
  }
  return "unknown";
}

Mat3 hat3(const Vec3& w) {
  Mat3 W;
  W << 0, -w.z(), w.y(),  //
      w.z(), 0, -w.x(),   //
      -w.y(), w.x(), 0;
  return W;
}

Vec3 vee3(const Mat3& W) {
  return 0.5 * Vec3(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
}

Mat4 hat6(const Vec6& xi) {
  Mat4 X = Mat4::Zero();
  X.topLeftCorner<3, 3>() = hat3(xi.head<3>());
  X.topRightCorner<3, 1>() = xi.tail<3>();
  return X;
}

Vec6 vee6(const Mat4& X) {
  Vec6 xi;
  xi << vee3(X.topLeftCorner<3, 3>()), X.topRightCorner<3, 1>();
  return xi;
}

// sin(x)/x and (1 - cos x)/x^2 = (sin(x/2)/(x/2))^2 / 2 have no cancellation: only x = 0 needs care,
// and below 1e-4 three Taylor terms are exact to rounding. (x - sin x)/x^3 cancels with relative error
// about 6 eps / x^2, so below kSeriesAngle it is summed as its Taylor series, sum (-1)^k x^2k/(2k+3)!,
// whose terms at x = 1.5 fall below 1e-19 by k = 11.
namespace {
constexpr std::array<double, 12> invOddFactorials() {
  std::array<double, 12> out{};
  double f = 6.0;  // 3!
  for (int i = 0; i < 12; ++i) {
    out[i] = 1.0 / f;
    f *= (2 * i + 4) * (2 * i + 5);
  }
  return out;
}
constexpr std::array<double, 12> kInvOddFactorial = invOddFactorials();  // 1/(2k+3)!
}  // namespace

namespace detail {

double expCoefficientC(double x) {
  const double y = x * x;
  if (x >= kSeriesAngle) return (x - std::sin(x)) / (x * y);
  // Horner over 1/(2k+3)!, k = 0..11, alternating signs.
  double c = 0.0;
  for (int i = 11; i >= 0; --i) c = kInvOddFactorial[i] - y * c;
  return c;
}

ExpCoefficients expCoefficients(double x) {
  // two libm calls: sin(x) and sin(x/2); cos(x) = 1 - 2 sin^2(x/2)
  ExpCoefficients k;
  const double y = x * x;
  const double s = std::sin(x), s_half = std::sin(0.5 * x);
  k.cos_x = 1.0 - 2.0 * s_half * s_half;
  if (x < 1e-4) {
    k.a = 1.0 - y / 6.0 * (1.0 - y / 20.0);
    k.b = 0.5 - y / 24.0 * (1.0 - y / 30.0);
  } else {
    const double sinc_half = s_half / (0.5 * x);
    k.a = s / x;
    k.b = 0.5 * sinc_half * sinc_half;
  }
  k.c = x < kSeriesAngle ? expCoefficientC(x) : (x - s) / (x * y);
  return k;
}

}  // namespace detail

Mat3 expSO3(const Vec3& w) {
  const detail::ExpCoefficients k = detail::expCoefficients(w.norm());
  Mat3 R = k.cos_x * Mat3::Identity();
  R.noalias() += k.b * (w * w.transpose());
  R += k.a * hat3(w);
  return R;
}

Pose expSE3(const Vec6& xi) {
  const Vec3 w = xi.head<3>();
  const Vec3 v = xi.tail<3>();
  const detail::ExpCoefficients k = detail::expCoefficients(w.norm());
  Pose T;
  T.R = k.cos_x * Mat3::Identity();
  T.R.noalias() += k.b * (w * w.transpose());
  T.R += k.a * hat3(w);
  const Vec3 wxv = w.cross(v);
  T.p = v + k.b * wxv + k.c * w.cross(wxv);
  return T;
}

void expUnitTwist(const Vec3& w, const Vec3& v, double pitch, double theta, Pose& out) {
  const double s = std::sin(theta);
  const double s_half = std::sin(0.5 * theta);
  const double one_minus_c = 2.0 * s_half * s_half;  // 1 - cos(theta) without cancellation
  const double c = 1.0 - one_minus_c;
  // R = I + s W + (1 - c) W^2 = c I + s W + (1 - c) w w^T for unit w.
  out.R.noalias() = one_minus_c * (w * w.transpose());
  out.R.diagonal().array() += c;
  out.R(0, 1) -= s * w.z();
  out.R(1, 0) += s * w.z();
  out.R(0, 2) += s * w.y();
  out.R(2, 0) -= s * w.y();
  out.R(1, 2) -= s * w.x();
  out.R(2, 1) += s * w.x();
  // (I - R) u for u = w x v (perpendicular to w): (1 - c) u - s (w x u).
  const Vec3 u = w.cross(v);
  out.p.noalias() = one_minus_c * u - s * w.cross(u);
  out.p += (pitch * theta) * w;
}

double rotationAngle(const Mat3& R) {
  const Vec3 s = vee3(R);  // sin(angle) * axis
  return std::atan2(s.norm(), 0.5 * (R.trace() - 1.0));
}

Vec3 logSO3(const Mat3& R) {
  const Vec3 s = vee3(R);  // sin(angle) axis, from the antisymmetric part
  const double sin_angle = s.norm();
  const double cos_angle = 0.5 * (R.trace() - 1.0);
  const double angle = std::atan2(sin_angle, cos_angle);
  if (cos_angle > 0.0) {
    // angle / sin(angle), Taylor below 1e-4 (next term 31 x^6/15120 is under 1e-24).
    const double ratio = angle < 1e-4 ? 1.0 + angle * angle / 6.0 * (1.0 + 7.0 / 60.0 * angle * angle)
                                      : angle / sin_angle;
    return ratio * s;
  }
  // Near pi the antisymmetric part vanishes: take the axis from the symmetric part
  // (R + R^T)/2 - cos I = (1 - cos) w w^T, its largest diagonal entry for conditioning.
  Mat3 B = 0.5 * (R + R.transpose());
  B.diagonal().array() -= cos_angle;
  Eigen::Index k = 0;
  B.diagonal().maxCoeff(&k);
  Vec3 axis = B.col(k);
  axis.normalize();
  if (axis.dot(s) < 0.0) axis = -axis;
  return angle * axis;
}

Vec6 logSE3(const Pose& T) {
  const Vec3 w = logSO3(T.R);
  const double x = w.norm();
  // V^-1 = I - W/2 + d W^2 with d = (1 - (x/2) cot(x/2)) / x^2. The direct form loses 12 eps / x^2 of
  // relative accuracy, but it enters multiplied by x^2, so the absolute error stays ~eps; below 0.1 the
  // series 1/12 + x^2/720 + x^4/30240 + x^6/604800 + x^8/47900160 is exact to rounding.
  double d;
  if (x < 0.1) {
    const double y = x * x;
    d = 1.0 / 12.0 + y * (1.0 / 720.0 + y * (1.0 / 30240.0 + y * (1.0 / 604800.0 + y / 47900160.0)));
  } else {
    const double h = 0.5 * x;
    d = (1.0 - h * std::cos(h) / std::sin(h)) / (x * x);
  }
  const Vec3 wxp = w.cross(T.p);
  Vec6 xi;
  xi.head<3>() = w;
  xi.tail<3>() = T.p - 0.5 * wxp + d * w.cross(wxp);
  return xi;
}

Mat6 adjoint(const Pose& T) {
  Mat6 Ad = Mat6::Zero();
  Ad.topLeftCorner<3, 3>() = T.R;
  Ad.bottomRightCorner<3, 3>() = T.R;
  Ad.bottomLeftCorner<3, 3>().noalias() = hat3(T.p) * T.R;
  return Ad;
}

Vec6 adjointApply(const Pose& T, const Vec6& xi) {
  Vec6 out;
  out.head<3>().noalias() = T.R * xi.head<3>();
  out.tail<3>().noalias() = T.R * xi.tail<3>();
  out.tail<3>() += T.p.cross(Vec3(out.head<3>()));
  return out;
}

}  // namespace lowpair
