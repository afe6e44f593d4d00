#include "se3_variants.hpp"

#include <cmath>

#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"
#include "exp_coefficients.hpp"  // lowpair/src: the library's internal coefficients

namespace lowpair {

Pose expSE3Paper(const Vec6& xi) {
  const Vec3 w = xi.head<3>();
  const double q = w.norm();
  Pose T;
  if (q == 0.0) {
    T.p = xi.tail<3>();
    return T;
  }
  const double b = (1.0 - std::cos(q)) / (q * q);
  const double c = (q - std::sin(q)) / (q * q * q);
  Mat4 X = Mat4::Zero();
  X.topLeftCorner<3, 3>() = hat3(w);
  X.topRightCorner<3, 1>() = xi.tail<3>();
  Mat4 X2;
  X2.noalias() = X * X;
  Mat4 E = Mat4::Identity() + X + b * X2;
  E.noalias() += c * (X2 * X);
  T.R = E.topLeftCorner<3, 3>();
  T.p = E.topRightCorner<3, 1>();
  return T;
}


Pose expSE3Quaternion(const Vec6& xi) {
  const Vec3 w = xi.head<3>();
  const Vec3 v = xi.tail<3>();
  const double q = w.norm();
  const double h = 0.5 * q;
  const double y = q * q;
  const double sh = std::sin(h), ch = std::cos(h);
  // k = sin(q/2)/q without 0/0: series below 1e-4 (next term q^6/645120 is below 1e-29).
  const double k = q < 1e-4 ? 0.5 - y / 48.0 * (1.0 - y / 80.0) : sh / q;
  const Vec3 u = k * w;  // quaternion vector part
  const double x2 = u.x() * u.x(), y2 = u.y() * u.y(), z2 = u.z() * u.z();
  const double xy = u.x() * u.y(), xz = u.x() * u.z(), yz = u.y() * u.z();
  const double wx = ch * u.x(), wy = ch * u.y(), wz = ch * u.z();
  Pose T;
  T.R << 1.0 - 2.0 * (y2 + z2), 2.0 * (xy - wz), 2.0 * (xz + wy),  //
      2.0 * (xy + wz), 1.0 - 2.0 * (x2 + z2), 2.0 * (yz - wx),     //
      2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (x2 + y2);
  const double b = 2.0 * k * k;
  const double c = detail::expCoefficientC(q);
  const Vec3 wxv = w.cross(v);
  T.p = v + b * wxv + c * w.cross(wxv);
  return T;
}

}  // namespace lowpair
