// lowpair's own hot paths: FK (POE, D-H, fast D-H kernel), Jacobians, batched FK, se(3) exponentials.
// Every benchmark first checks its results against the library reference over the whole pool of
// configurations (robots.cpp) and skips with an error on a mismatch; then it cycles through the pool.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <unsupported/Eigen/MatrixFunctions>

#include "helper_thread.hpp"
#include "lowpair/fast_fk.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/se3_variants.hpp"
#include "robots_lowpair.hpp"
#if __has_include("lowpair/jacobian.hpp")
#include "lowpair/jacobian.hpp"
#define LOWPAIR_BENCH_HAS_JACOBIAN 1
#endif

namespace lowpair_bench {

using namespace lowpair;

namespace {

void poseTo12(const Pose& T, double* out) {
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) out[3 * a + b] = T.R(a, b);
    out[9 + a] = T.p[a];
  }
}

bool rejected(benchmark::State& state, double error, const std::string& what) {
  if (error <= kAgree) return false;
  state.SkipWithError((what + " disagrees with the library POE FK: " + std::to_string(error) + " x size").c_str());
  return true;
}

Eigen::Map<const VecX> qOf(const RobotCase& r, int k) { return {&r.q[static_cast<size_t>(k * r.dof)], r.dof}; }

// ---- single-call FK -------------------------------------------------------------------------------

void fkPoe(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  PoeData data(model);
  double err = 0.0, pose[12];
  for (int k = 0; k < kPool; ++k) {
    forwardKinematics(model, data, qOf(r, k));
    poseTo12(data.T_base_tool, pose);
    err = std::max(err, poseMismatch(r, k, pose));
  }
  if (rejected(state, err, "POE FK")) return;
  int k = 0;
  for (auto _ : state) {
    forwardKinematics(model, data, qOf(r, k));
    benchmark::DoNotOptimize(data.T_base_tool);
    k = (k + 1) & (kPool - 1);
  }
}

void fkDh(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const DhModel& model = robotModels(id).dh;
  DhData data(model);
  double err = 0.0, pose[12];
  for (int k = 0; k < kPool; ++k) {
    forwardKinematics(model, data, qOf(r, k));
    poseTo12(data.T_base_tool, pose);
    err = std::max(err, poseMismatch(r, k, pose));
  }
  if (rejected(state, err, "D-H FK")) return;
  int k = 0;
  for (auto _ : state) {
    forwardKinematics(model, data, qOf(r, k));
    benchmark::DoNotOptimize(data.T_base_tool);
    k = (k + 1) & (kPool - 1);
  }
}

void fkFastDh(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const DhKernel kernel(robotModels(id).dh);
  Pose T;
  double err = 0.0, pose[12];
  for (int k = 0; k < kPool; ++k) {
    kernel.forward(qOf(r, k), T);
    poseTo12(T, pose);
    err = std::max(err, poseMismatch(r, k, pose));
  }
  if (rejected(state, err, "fast D-H FK")) return;
  int k = 0;
  for (auto _ : state) {
    kernel.forward(&r.q[static_cast<size_t>(k * r.dof)], T);
    benchmark::DoNotOptimize(T);
    k = (k + 1) & (kPool - 1);
  }
}

void jacobianFastDh(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const DhKernel kernel(robotModels(id).dh);
  Pose T;
  Mat6X J(6, r.dof);
  Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> Jr(6, r.dof);
  double err = 0.0, pose[12];
  for (int k = 0; k < kPool; ++k) {
    kernel.geometricJacobian(&r.q[static_cast<size_t>(k * r.dof)], T, J);
    poseTo12(T, pose);
    Jr = J;
    err = std::max({err, poseMismatch(r, k, pose), jacobianMismatch(r, k, Jr.data())});
  }
  if (rejected(state, err, "fast D-H geometric Jacobian")) return;
  int k = 0;
  for (auto _ : state) {
    kernel.geometricJacobian(&r.q[static_cast<size_t>(k * r.dof)], T, J);
    benchmark::DoNotOptimize(J.data());
    benchmark::DoNotOptimize(T);
    benchmark::ClobberMemory();
    k = (k + 1) & (kPool - 1);
  }
}

// ---- Jacobians --------------------------------------------------------------------------------------

#ifdef LOWPAIR_BENCH_HAS_JACOBIAN
void jacobianGeometric(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  PoeData data(model);
  Mat6X J(6, r.dof);
  Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> Jr(6, r.dof);
  double err = 0.0;
  for (int k = 0; k < kPool; ++k) {
    geometricJacobian(model, data, qOf(r, k), J);
    Jr = J;
    err = std::max(err, jacobianMismatch(r, k, Jr.data()));
  }
  if (rejected(state, err, "geometric Jacobian")) return;
  int k = 0;
  for (auto _ : state) {
    geometricJacobian(model, data, qOf(r, k), J);
    benchmark::DoNotOptimize(J.data());
    benchmark::ClobberMemory();
    k = (k + 1) & (kPool - 1);
  }
}

void jacobianSpatial(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  PoeData data(model);
  Mat6X J(6, r.dof);
  Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> Jg(6, r.dof);
  double err = 0.0;
  for (int k = 0; k < kPool; ++k) {
    spatialJacobian(model, data, qOf(r, k), J);
    // spatial [w; v_s] -> geometric [v_s + w x p_tool; w] for the comparison
    const Vec3 p = Eigen::Map<const Vec3>(&r.pose[static_cast<size_t>(k) * 12 + 9]);
    for (int i = 0; i < r.dof; ++i) {
      const Vec3 w = J.col(i).head<3>();
      Jg.col(i) << J.col(i).tail<3>() + w.cross(p), w;
    }
    err = std::max(err, jacobianMismatch(r, k, Jg.data()));
  }
  if (rejected(state, err, "spatial Jacobian")) return;
  int k = 0;
  for (auto _ : state) {
    spatialJacobian(model, data, qOf(r, k), J);
    benchmark::DoNotOptimize(J.data());
    benchmark::ClobberMemory();
    k = (k + 1) & (kPool - 1);
  }
}
#endif

// ---- batched FK (PUMA 560): 1024 configurations per call, reported per pose --------------------------

struct Batch {
  explicit Batch(const RobotCase& robot) : r(robot), q(static_cast<size_t>(r.dof) * kPool), out(12 * kPool) {
    for (int k = 0; k < kPool; ++k) {
      for (int i = 0; i < r.dof; ++i) q[static_cast<size_t>(i * kPool + k)] = r.q[static_cast<size_t>(k * r.dof + i)];
    }
  }
  double mismatch() const {
    double err = 0.0, pose[12];
    for (int k = 0; k < kPool; ++k) {
      for (int e = 0; e < 12; ++e) pose[e] = out[static_cast<size_t>(e * kPool + k)];
      err = std::max(err, poseMismatch(r, k, pose));
    }
    return err;
  }
  const RobotCase& r;
  std::vector<double> q;    // SoA: q[i * kPool + k]
  std::vector<double> out;  // SoA: out[e * kPool + k]
};

void batchScalar(const DhModel& model, DhData& data, Batch& b) {
  double qk[DhKernel::kMaxDof];
  for (int k = 0; k < kPool; ++k) {
    for (int i = 0; i < b.r.dof; ++i) qk[i] = b.q[static_cast<size_t>(i * kPool + k)];
    forwardKinematics(model, data, Eigen::Map<const VecX>(qk, b.r.dof));
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) b.out[static_cast<size_t>((3 * a + c) * kPool + k)] = data.T_base_tool.R(a, c);
      b.out[static_cast<size_t>((9 + a) * kPool + k)] = data.T_base_tool.p[a];
    }
  }
}

void batchScalarFast(const DhKernel& kernel, Batch& b) {
  double qk[DhKernel::kMaxDof];
  Pose T;
  for (int k = 0; k < kPool; ++k) {
    for (int i = 0; i < b.r.dof; ++i) qk[i] = b.q[static_cast<size_t>(i * kPool + k)];
    kernel.forward(qk, T);
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) b.out[static_cast<size_t>((3 * a + c) * kPool + k)] = T.R(a, c);
      b.out[static_cast<size_t>((9 + a) * kPool + k)] = T.p[a];
    }
  }
}

struct TwoThreadJob {
  const DhKernel* kernel;
  Batch* b;
  static void run(void* self, int part) {
    auto* job = static_cast<TwoThreadJob*>(self);
    const int half = kPool / 2;
    job->kernel->forwardBatch(job->b->q.data() + part * half, half, kPool, job->b->out.data() + part * half);
  }
};

enum class BatchImpl { Scalar, ScalarFast, Soa, SoaThreads2 };

void fkBatch(benchmark::State& state, BatchImpl impl) {
  const RobotId id = RobotId::Puma560;
  const DhModel& model = robotModels(id).dh;
  DhData data(model);
  const DhKernel kernel(model);
  Batch b(robotCase(id));
  std::unique_ptr<HelperThread> helper;
  if (impl == BatchImpl::SoaThreads2) helper.reset(new HelperThread);
  TwoThreadJob job{&kernel, &b};
  auto once = [&] {
    switch (impl) {
      case BatchImpl::Scalar: batchScalar(model, data, b); break;
      case BatchImpl::ScalarFast: batchScalarFast(kernel, b); break;
      case BatchImpl::Soa: kernel.forwardBatch(b.q.data(), kPool, kPool, b.out.data()); break;
      case BatchImpl::SoaThreads2: helper->run(&TwoThreadJob::run, &job); break;
    }
  };
  once();
  if (rejected(state, b.mismatch(), "batched FK")) return;
  for (auto _ : state) {
    once();
    benchmark::DoNotOptimize(b.out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kPool);
}

// ---- se(3) exponential variants ----------------------------------------------------------------------

const std::vector<Vec6>& twistPool() {
  static const std::vector<Vec6> pool = [] {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0), angle(0.0, M_PI);
    std::vector<Vec6> out(kPool);
    for (Vec6& xi : out) {
      Vec3 w(u(rng), u(rng), u(rng));
      w = w.normalized() * angle(rng);
      xi << w, Vec3(u(rng), u(rng), u(rng));
    }
    return out;
  }();
  return pool;
}

template <class Exp>
void expBench(benchmark::State& state, Exp exp) {
  const std::vector<Vec6>& pool = twistPool();
  double err = 0.0;
  for (const Vec6& xi : pool) {
    const Pose a = exp(xi), b = expSE3(xi);
    err = std::max({err, (a.R - b.R).cwiseAbs().maxCoeff(), (a.p - b.p).cwiseAbs().maxCoeff()});
  }
  if (rejected(state, err, "exp variant")) return;
  size_t k = 0;
  for (auto _ : state) {
    Pose T = exp(pool[k]);
    benchmark::DoNotOptimize(T);
    k = (k + 1) & (kPool - 1);
  }
}

Pose expEigen(const Vec6& xi) {
  const Mat4 E = hat6(xi).exp();
  return Pose::fromMatrix(E);
}

// ---- registration --------------------------------------------------------------------------------------

const char* nameOf(RobotId id) {
  return id == RobotId::Puma560 ? "Puma560" : id == RobotId::Stanford ? "Stanford" : "Panda";
}

const bool registered = [] {
  using benchmark::RegisterBenchmark;
  RegisterBenchmark("BM_Exp_Rodrigues", [](benchmark::State& s) { expBench(s, [](const Vec6& xi) { return expSE3(xi); }); });
  RegisterBenchmark("BM_Exp_Paper", [](benchmark::State& s) { expBench(s, [](const Vec6& xi) { return expSE3Paper(xi); }); });
  RegisterBenchmark("BM_Exp_Quaternion",
                    [](benchmark::State& s) { expBench(s, [](const Vec6& xi) { return expSE3Quaternion(xi); }); });
  RegisterBenchmark("BM_Exp_EigenMatrixExp", [](benchmark::State& s) { expBench(s, expEigen); });
  for (RobotId id : kRobots) {
    const std::string n = nameOf(id);
    RegisterBenchmark(("BM_Fk_Poe_" + n).c_str(), fkPoe, id);
    RegisterBenchmark(("BM_Fk_Dh_" + n).c_str(), fkDh, id);
    RegisterBenchmark(("BM_Fk_FastDh_" + n).c_str(), fkFastDh, id);
    RegisterBenchmark(("BM_Jacobian_FastDh_" + n).c_str(), jacobianFastDh, id);
#ifdef LOWPAIR_BENCH_HAS_JACOBIAN
    RegisterBenchmark(("BM_Jacobian_Spatial_" + n).c_str(), jacobianSpatial, id);
    RegisterBenchmark(("BM_Jacobian_Geometric_" + n).c_str(), jacobianGeometric, id);
#endif
  }
  RegisterBenchmark("BM_FkBatch_Scalar_Puma560", fkBatch, BatchImpl::Scalar);
  RegisterBenchmark("BM_FkBatch_ScalarFast_Puma560", fkBatch, BatchImpl::ScalarFast);
  RegisterBenchmark("BM_FkBatch_Soa_Puma560", fkBatch, BatchImpl::Soa);
  RegisterBenchmark("BM_FkBatch_SoaThreads2_Puma560", fkBatch, BatchImpl::SoaThreads2)->UseRealTime();
  return true;
}();

}  // namespace

}  // namespace lowpair_bench
