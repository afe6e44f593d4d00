#include "lowpair/fast_fk.hpp"

#include <cstdint>
#include <cstring>

#include "lowpair/check.hpp"

namespace lowpair {

namespace {

// Cody-Waite split of pi/2 (Cephes DP1..DP3 times 2): n * kPio2A is exact for |n| < 2^29.
constexpr double kPio2A = 1.57079625129699707031e0;
constexpr double kPio2B = 7.54978941586159635335e-8;
constexpr double kPio2C = 5.39030285815811905290e-15;
constexpr double kTwoOverPi = 0.63661977236758134308;
constexpr double kRound = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer in the low bits

inline std::uint64_t bitsOf(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
inline double fromBits(std::uint64_t b) {
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// One lane; inlined into loops that the compiler vectorizes (no branches, no calls).
inline void sinCosLane(double x, double& s, double& c) {
  const double t = x * kTwoOverPi + kRound;
  const std::uint64_t quadrant = bitsOf(t);  // low bits hold n = round(2x/pi)
  const double n = t - kRound;
  const double r = ((x - n * kPio2A) - n * kPio2B) - n * kPio2C;  // |r| <= pi/4
  const double z = r * r;
  const double ps = ((((( 1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z +
                        2.75573136213857245213e-6) * z - 1.98412698295895385996e-4) * z +
                      8.33333333332211858878e-3) * z - 1.66666666666666307295e-1);
  const double pc = ((((( -1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z -
                         2.75573141792967388112e-7) * z + 2.48015872888517045348e-5) * z -
                       1.38888888888730564116e-3) * z + 4.16666666666665929218e-2);
  const double sr = r + r * (z * ps);
  const double cr = (1.0 - 0.5 * z) + z * z * pc;
  // sin(r + n pi/2) = (sr, cr, -sr, -cr)[n mod 4]; cos(r + n pi/2) = (cr, -sr, -cr, sr)[n mod 4].
  const std::uint64_t odd = 0 - (quadrant & 1);
  const std::uint64_t sb = bitsOf(sr), cb = bitsOf(cr);
  s = fromBits(((cb & odd) | (sb & ~odd)) ^ ((quadrant & 2) << 62));
  c = fromBits(((sb & odd) | (cb & ~odd)) ^ (((quadrant + 1) & 2) << 62));
}

}  // namespace

void sinCos(const double* x, int n, double* s, double* c) {
  for (int i = 0; i < n; ++i) sinCosLane(x[i], s[i], c[i]);
}

DhKernel::DhKernel(const DhModel& model) : dof_(model.dof()) {
  LP_CHECK(dof_ <= kMaxDof, "DhKernel: at most " << kMaxDof << " joints, got " << dof_);
  for (int i = 0; i < dof_; ++i) {
    const DhJoint& j = model.joint(i);
    Row& row = rows_[i];
    row.ca = std::cos(j.link.alpha);
    row.sa = std::sin(j.link.alpha);
    row.a = j.link.a;
    row.d = j.link.d;
    row.theta = j.link.theta;
    row.rot = j.type == JointType::Prismatic ? 0.0 : j.scale;
    row.slide = j.type == JointType::Prismatic ? j.scale : j.type == JointType::Helical ? j.pitch * j.scale : 0.0;
  }
  base_ = dhTransform(model.base());
  tool_ = dhToolTransform(model.toolTheta(), model.toolD());
}

void DhKernel::forward(const Eigen::Ref<const VecX>& q, Pose& T_base_tool) const {
  forward(q.data(), T_base_tool);
}

void DhKernel::forward(const double* q, Pose& T_base_tool) const {
  chain<false>(q, T_base_tool, nullptr, nullptr);
}

void DhKernel::geometricJacobian(const double* q, Pose& T_base_tool, Eigen::Ref<Mat6X> J) const {
  double z[3 * kMaxDof], o[3 * kMaxDof];
  chain<true>(q, T_base_tool, z, o);
  const Vec3& p = T_base_tool.p;
  for (int i = 0; i < dof_; ++i) {
    const Row& row = rows_[i];
    const double* zi = z + 3 * i;
    const double r0 = p[0] - o[3 * i], r1 = p[1] - o[3 * i + 1], r2 = p[2] - o[3 * i + 2];
    J(0, i) = row.rot * (zi[1] * r2 - zi[2] * r1) + row.slide * zi[0];
    J(1, i) = row.rot * (zi[2] * r0 - zi[0] * r2) + row.slide * zi[1];
    J(2, i) = row.rot * (zi[0] * r1 - zi[1] * r0) + row.slide * zi[2];
    J(3, i) = row.rot * zi[0];
    J(4, i) = row.rot * zi[1];
    J(5, i) = row.rot * zi[2];
  }
}

template <bool kJacobian>
void DhKernel::chain(const double* q, Pose& T_base_tool, double* z_axes, double* o_axes) const {
  double th[kMaxDof], st[kMaxDof], ct[kMaxDof];
  for (int i = 0; i < dof_; ++i) th[i] = rows_[i].theta + rows_[i].rot * q[i];
  sinCos(th, dof_, st, ct);
  // columns X, Y, Z of the rotation and the position, updated by T <- T * A_i
  double X[3], Y[3], Z[3], P[3];
  for (int k = 0; k < 3; ++k) {
    X[k] = base_.R(k, 0);
    Y[k] = base_.R(k, 1);
    Z[k] = base_.R(k, 2);
    P[k] = base_.p[k];
  }
  for (int i = 0; i < dof_; ++i) {
    const Row& row = rows_[i];
    if (kJacobian) {  // joint i's axis: z and origin of the frame before its motion
      for (int k = 0; k < 3; ++k) {
        z_axes[3 * i + k] = Z[k];
        o_axes[3 * i + k] = P[k];
      }
    }
    const double d = row.d + row.slide * q[i];
    for (int k = 0; k < 3; ++k) {
      const double x = ct[i] * X[k] + st[i] * Y[k];
      const double t = ct[i] * Y[k] - st[i] * X[k];
      const double z = Z[k];
      P[k] = (P[k] + d * z) + row.a * x;
      X[k] = x;
      Y[k] = row.ca * t + row.sa * z;
      Z[k] = row.ca * z - row.sa * t;
    }
  }
  Pose T;
  for (int k = 0; k < 3; ++k) {
    T.R(k, 0) = X[k];
    T.R(k, 1) = Y[k];
    T.R(k, 2) = Z[k];
    T.p[k] = P[k];
  }
  T_base_tool.R.noalias() = T.R * tool_.R;
  T_base_tool.p.noalias() = T.R * tool_.p;
  T_base_tool.p += T.p;
}

// One block of kBlock configurations; every inner loop runs over the lanes and vectorizes.
void DhKernel::block(const double* q, int stride, double* out, int out_stride, int lanes) const {
  constexpr int B = kBlock;
  alignas(64) double X[3][B], Y[3][B], Z[3][B], P[3][B];
  alignas(64) double th[B], st[B], ct[B], qi[B];
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < B; ++l) {
      X[k][l] = base_.R(k, 0);
      Y[k][l] = base_.R(k, 1);
      Z[k][l] = base_.R(k, 2);
      P[k][l] = base_.p[k];
    }
  }
  for (int i = 0; i < dof_; ++i) {
    const Row row = rows_[i];
    for (int l = 0; l < B; ++l) qi[l] = l < lanes ? q[i * stride + l] : 0.0;
    for (int l = 0; l < B; ++l) th[l] = row.theta + row.rot * qi[l];
    for (int l = 0; l < B; ++l) sinCosLane(th[l], st[l], ct[l]);
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < B; ++l) {
        const double d = row.d + row.slide * qi[l];
        const double x = ct[l] * X[k][l] + st[l] * Y[k][l];
        const double t = ct[l] * Y[k][l] - st[l] * X[k][l];
        const double z = Z[k][l];
        P[k][l] = (P[k][l] + d * z) + row.a * x;
        X[k][l] = x;
        Y[k][l] = row.ca * t + row.sa * z;
        Z[k][l] = row.ca * z - row.sa * t;
      }
    }
  }
  // T * tool, written row-major: R(k, m) = X[k] tool(0, m) + Y[k] tool(1, m) + Z[k] tool(2, m).
  const Mat3& Rt = tool_.R;
  const Vec3& pt = tool_.p;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < 3; ++m) {
      double* o = out + (3 * k + m) * out_stride;
      for (int l = 0; l < lanes; ++l) o[l] = (X[k][l] * Rt(0, m) + Y[k][l] * Rt(1, m)) + Z[k][l] * Rt(2, m);
    }
    double* o = out + (9 + k) * out_stride;
    for (int l = 0; l < lanes; ++l) o[l] = ((X[k][l] * pt[0] + Y[k][l] * pt[1]) + Z[k][l] * pt[2]) + P[k][l];
  }
}

void DhKernel::forwardBatch(const double* q, int count, int stride, double* out) const {
  for (int k0 = 0; k0 < count; k0 += kBlock) {
    const int lanes = count - k0 < kBlock ? count - k0 : kBlock;
    block(q + k0, stride, out + k0, stride, lanes);
  }
}

}  // namespace lowpair
