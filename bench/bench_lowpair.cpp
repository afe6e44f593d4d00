// lowpair's own hot paths, the public functions: FK (POE, D-H), Jacobians (compute, then get), batched FK, se(3) exponentials.
// Every benchmark first checks its results against the library reference over the whole pool of
// configurations (robots.cpp) and skips with an error on a mismatch; then it cycles through the pool.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <unsupported/Eigen/MatrixFunctions>

#include "chain_baseline.hpp"
#include "helper_thread.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/jacobian.hpp"
#include "registration.hpp"
#include "robots_lowpair.hpp"
#include "se3_variants.hpp"

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

// kBaseline: the kernel before issue 29 (chain_baseline.cpp), in the same run
template <bool kBaseline>
void fkPoe(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  Data data(model);
  auto fk = [&](int k) {
    if (kBaseline) {
      baseline::forwardKinematics(model.chain(), data, qOf(r, k).data());
    } else {
      forwardKinematics(model, data, qOf(r, k));
    }
  };
  double err = 0.0, pose[12];
  for (int k = 0; k < kPool; ++k) {
    fk(k);
    poseTo12(data.T_base_tool, pose);
    err = std::max(err, poseMismatch(r, k, pose));
  }
  if (rejected(state, err, "POE FK")) return;
  int k = 0;
  for (auto _ : state) {
    fk(k);
    benchmark::DoNotOptimize(data.T_base_tool);
    k = (k + 1) & (kPool - 1);
  }
}

void fkDh(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  const DhModel& model = robotModels(id).dh;
  Data data(model);
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

// ---- Jacobians --------------------------------------------------------------------------------------

using JacobianRowMajor = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>;

// FK + Jacobian + one getter, after checking the getter's result (turned into the geometric form by
// `toGeometric(J, k, Jg)`) against the reference at every pool configuration.
// kBaseline: computeJacobians of the kernel before issue 29 (chain_baseline.cpp)
template <bool kBaseline = false, typename Get, typename ToGeometric>
void jacobianBenchmark(benchmark::State& state, RobotId id, const char* what, Get get, ToGeometric toGeometric) {
  const RobotCase& r = robotCase(id);
  const PoeModel& model = robotModels(id).poe;
  Data data(model);
  Mat6X J(6, r.dof);
  JacobianRowMajor Jg(6, r.dof);
  auto compute = [&](int k) {
    if (kBaseline) {
      baseline::computeJacobians(model.chain(), data, qOf(r, k).data());
    } else {
      computeJacobians(model, data, qOf(r, k));
    }
  };
  double err = 0.0;
  for (int k = 0; k < kPool; ++k) {
    compute(k);
    get(data, J);
    toGeometric(J, k, Jg);
    err = std::max(err, jacobianMismatch(r, k, Jg.data()));
  }
  if (rejected(state, err, what)) return;
  int k = 0;
  for (auto _ : state) {
    compute(k);
    get(data, J);
    benchmark::DoNotOptimize(J.data());
    benchmark::ClobberMemory();
    k = (k + 1) & (kPool - 1);
  }
}

template <bool kBaseline>
void jacobianGeometric(benchmark::State& state, RobotId id) {
  jacobianBenchmark<kBaseline>(state, id, "geometric Jacobian", [](const Data& d, Mat6X& J) { getGeometricJacobian(d, J); },
                               [](const Mat6X& J, int, JacobianRowMajor& Jg) { Jg = J; });
}

template <bool kBaseline>
void jacobianSpatial(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  // spatial [w; v_s] -> geometric [v_s + w x p_tool; w] for the comparison
  jacobianBenchmark<kBaseline>(state, id, "spatial Jacobian", [](const Data& d, Mat6X& J) { getSpatialJacobian(d, J); },
                               [&r](const Mat6X& J, int k, JacobianRowMajor& Jg) {
                                 const Vec3 p = Eigen::Map<const Vec3>(&r.pose[static_cast<size_t>(k) * 12 + 9]);
                                 for (int i = 0; i < r.dof; ++i) {
                                   const Vec3 w = J.col(i).head<3>();
                                   Jg.col(i) << J.col(i).tail<3>() + w.cross(p), w;
                                 }
                               });
}

void jacobianBody(benchmark::State& state, RobotId id) {
  const RobotCase& r = robotCase(id);
  // body [w_b; v_b] (tool frame) -> geometric [R v_b; R w_b] for the comparison
  jacobianBenchmark(state, id, "body Jacobian", [](const Data& d, Mat6X& J) { getBodyJacobian(d, J); },
                    [&r](const Mat6X& J, int k, JacobianRowMajor& Jg) {
                      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(
                          &r.pose[static_cast<size_t>(k) * 12]);
                      for (int i = 0; i < r.dof; ++i) Jg.col(i) << R * J.col(i).tail<3>(), R * J.col(i).head<3>();
                    });
}

// ---- batched FK: 1024 configurations per call, reported per pose ---------------------------------------

struct Batch {
  explicit Batch(const RobotCase& robot) : r(robot), q(kPool, r.dof), out(kPool, 12) {
    for (int k = 0; k < kPool; ++k) {
      for (int i = 0; i < r.dof; ++i) q(k, i) = r.q[static_cast<size_t>(k * r.dof + i)];
    }
  }
  double mismatch() const {
    double err = 0.0, pose[12];
    for (int k = 0; k < kPool; ++k) {
      for (int e = 0; e < 12; ++e) pose[e] = out(k, e);
      err = std::max(err, poseMismatch(r, k, pose));
    }
    return err;
  }
  const RobotCase& r;
  MatX q;    // kPool x dof: column i = joint i of every configuration
  MatX out;  // kPool x 12
};

// the single-call public function in a loop, for comparison with the batch form
void batchScalar(const PoeModel& model, Data& data, Batch& b) {
  VecX qk(b.r.dof);
  for (int k = 0; k < kPool; ++k) {
    qk = b.q.row(k).transpose();
    forwardKinematics(model, data, qk);
    for (int a = 0; a < 3; ++a) {
      for (int c = 0; c < 3; ++c) b.out(k, 3 * a + c) = data.T_base_tool.R(a, c);
      b.out(k, 9 + a) = data.T_base_tool.p[a];
    }
  }
}

struct TwoThreadJob {
  const PoeModel* model;
  Batch* b;
  static void run(void* self, int part) {
    auto* job = static_cast<TwoThreadJob*>(self);
    const int half = kPool / 2;
    forwardKinematicsBatch(*job->model, job->b->q.middleRows(part * half, half),
                           job->b->out.middleRows(part * half, half));
  }
};

enum class BatchImpl { Scalar, Soa, SoaDh, SoaThreads2, SoaAvx2, SoaAvx2Baseline, SoaBaseline };

void fkBatch(benchmark::State& state, RobotId id, BatchImpl impl) {
  const PoeModel& model = robotModels(id).poe;
  const DhModel& dh = robotModels(id).dh;
  Data data(model);
  Batch b(robotCase(id));
  std::unique_ptr<HelperThread> helper;
  if (impl == BatchImpl::SoaThreads2) helper.reset(new HelperThread);
  TwoThreadJob job{&model, &b};
  auto once = [&] {
    switch (impl) {
      case BatchImpl::Scalar: batchScalar(model, data, b); break;
      case BatchImpl::Soa: forwardKinematicsBatch(model, b.q, b.out); break;
      case BatchImpl::SoaDh: forwardKinematicsBatch(dh, b.q, b.out); break;
      case BatchImpl::SoaThreads2: helper->run(&TwoThreadJob::run, &job); break;
      case BatchImpl::SoaAvx2: baseline::currentBatch4(model.chain(), b.q, b.out); break;
      case BatchImpl::SoaAvx2Baseline: baseline::forwardKinematicsBatch(model.chain(), b.q, b.out); break;
      case BatchImpl::SoaBaseline:  // the public function's path then: 8 lanes where the processor has AVX-512
        if (baseline::hasBatch8()) {
          baseline::forwardKinematicsBatch8(model.chain(), b.q, b.out);
        } else {
          baseline::forwardKinematicsBatch(model.chain(), b.q, b.out);
        }
        break;
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

// ---- batched Jacobians (geometric, with FK): 1024 configurations per call, reported per pose -----------

void jacobianBatch(benchmark::State& state, RobotId id) {
  const PoeModel& model = robotModels(id).poe;
  Batch b(robotCase(id));
  MatX J(kPool, 6 * b.r.dof);
  computeJacobiansBatch(model, b.q, JacobianFrame::Geometric, J, b.out);
  double err = b.mismatch();
  JacobianRowMajor Jg(6, b.r.dof);
  for (int k = 0; k < kPool; ++k) {
    for (int c = 0; c < 6 * b.r.dof; ++c) Jg.data()[c] = J(k, c);  // row k: the 6 x n Jacobian, row-major
    err = std::max(err, jacobianMismatch(b.r, k, Jg.data()));
  }
  if (rejected(state, err, "batched geometric Jacobian")) return;
  for (auto _ : state) {
    computeJacobiansBatch(model, b.q, JacobianFrame::Geometric, J, b.out);
    benchmark::DoNotOptimize(J.data());
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

const bool registered = [] {
  using benchmark::RegisterBenchmark;
  RegisterBenchmark("BM_Exp_Rodrigues", [](benchmark::State& s) { expBench(s, [](const Vec6& xi) { return expSE3(xi); }); });
  RegisterBenchmark("BM_Exp_Paper", [](benchmark::State& s) { expBench(s, [](const Vec6& xi) { return expSE3Paper(xi); }); });
  RegisterBenchmark("BM_Exp_Quaternion",
                    [](benchmark::State& s) { expBench(s, [](const Vec6& xi) { return expSE3Quaternion(xi); }); });
  RegisterBenchmark("BM_Exp_EigenMatrixExp", [](benchmark::State& s) { expBench(s, expEigen); });
  return true;
}();

}  // namespace

void registerKinematicsBenchmarks(RobotId id, const std::string& name) {
  using benchmark::RegisterBenchmark;
  RegisterBenchmark(("BM_Fk_Poe_" + name).c_str(), fkPoe<false>, id);
  RegisterBenchmark(("BM_Fk_PoeBaseline_" + name).c_str(), fkPoe<true>, id);
  RegisterBenchmark(("BM_Fk_Dh_" + name).c_str(), fkDh, id);
  RegisterBenchmark(("BM_Jacobian_Spatial_" + name).c_str(), jacobianSpatial<false>, id);
  RegisterBenchmark(("BM_Jacobian_SpatialBaseline_" + name).c_str(), jacobianSpatial<true>, id);
  RegisterBenchmark(("BM_Jacobian_Body_" + name).c_str(), jacobianBody, id);
  RegisterBenchmark(("BM_Jacobian_Geometric_" + name).c_str(), jacobianGeometric<false>, id);
  RegisterBenchmark(("BM_Jacobian_GeometricBaseline_" + name).c_str(), jacobianGeometric<true>, id);
}

void registerBatchBenchmarks(RobotId id, const std::string& name) {
  using benchmark::RegisterBenchmark;
  RegisterBenchmark(("BM_FkBatch_Scalar_" + name).c_str(), fkBatch, id, BatchImpl::Scalar);
  RegisterBenchmark(("BM_FkBatch_Soa_" + name).c_str(), fkBatch, id, BatchImpl::Soa);
  RegisterBenchmark(("BM_FkBatch_SoaDh_" + name).c_str(), fkBatch, id, BatchImpl::SoaDh);
  // the 4-lane (AVX2) path whatever the processor, and the same path before issue 29
  RegisterBenchmark(("BM_FkBatch_SoaAvx2_" + name).c_str(), fkBatch, id, BatchImpl::SoaAvx2);
  RegisterBenchmark(("BM_FkBatch_SoaAvx2Baseline_" + name).c_str(), fkBatch, id, BatchImpl::SoaAvx2Baseline);
  // the public function's path before issue 29 (8 lanes on AVX-512 processors, as BM_FkBatch_Soa takes)
  RegisterBenchmark(("BM_FkBatch_SoaBaseline_" + name).c_str(), fkBatch, id, BatchImpl::SoaBaseline);
  RegisterBenchmark(("BM_JacobianBatch_Geometric_" + name).c_str(), jacobianBatch, id);
  RegisterBenchmark(("BM_FkBatch_SoaThreads2_" + name).c_str(), fkBatch, id, BatchImpl::SoaThreads2)->UseRealTime();
}

}  // namespace lowpair_bench
