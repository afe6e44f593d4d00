// The hot paths allocate nothing: FK (POE, D-H, fast D-H), the Jacobians, every exp variant.
// Two proofs: Eigen's EIGEN_RUNTIME_NO_MALLOC check (covers Eigen code inlined into this file) and a
// global operator new counter (covers the library .cpp files, compiled without that check, and std::).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include <unsupported/Eigen/MatrixFunctions>

#include "lowpair/convert.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/se3.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/ik_closed_form.hpp"

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "compile alloc_test with EIGEN_RUNTIME_NO_MALLOC (tests/lib/CMakeLists.txt)"
#endif

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept { return operator new(size, tag); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace lowpair;

namespace {

// Runs `f` with both guards armed; returns the number of operator new calls it made.
template <class F>
long allocationsOf(F&& f) {
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  f();
  Eigen::internal::set_is_malloc_allowed(true);
  return g_allocations.load() - before;
}

// PUMA 560 (Corke) as a D-H model and its POE equivalent, with a helical and a prismatic joint added
// so that every joint type's path runs.
DhModel testDh() {
  std::vector<DhJoint> joints(8);
  const double alpha[] = {M_PI / 2, 0, -M_PI / 2, M_PI / 2, -M_PI / 2, 0, 0.3, 0};
  const double a[] = {0, 0.4318, 0.0203, 0, 0, 0, 0.1, 0.05};
  const double d[] = {0, 0, 0.15005, 0.4318, 0, 0, 0.02, 0};
  for (int i = 0; i < 8; ++i) joints[i].link = DhParams{0.0, d[i], alpha[i], a[i]};
  joints[6].type = JointType::Helical;
  joints[6].pitch = 0.01;
  joints[7].type = JointType::Prismatic;
  return DhModel(DhParams{}, joints, 0.1, 0.2, "alloc-test");
}

PoeModel testPoe() { return dhToPoe(testDh()); }

VecX randomQ(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  VecX q(n);
  for (int i = 0; i < n; ++i) q[i] = u(rng);
  return q;
}

}  // namespace

TEST(Alloc, CounterSeesAllocations) {
  // the guard itself works: a std::vector allocation is counted
  const long before = g_allocations.load();
  std::vector<double>* v = new std::vector<double>(100);
  EXPECT_GE(g_allocations.load() - before, 2);
  delete v;
}

TEST(Alloc, PoeForwardKinematicsAllocatesNothing) {
  const PoeModel model = testPoe();
  Data data(model);
  const VecX q = randomQ(model.dof(), 1);
  EXPECT_EQ(allocationsOf([&] { forwardKinematics(model, data, q); }), 0);
}

TEST(Alloc, DhForwardKinematicsAllocatesNothing) {
  const DhModel model = testDh();
  Data data(model);
  const VecX q = randomQ(model.dof(), 2);
  EXPECT_EQ(allocationsOf([&] { forwardKinematics(model, data, q); }), 0);
}

TEST(Alloc, BatchForwardKinematicsAllocatesNothing) {
  const PoeModel model = testPoe();
  const DhModel dh = testDh();
  constexpr int kCount = 37;  // four full blocks and a partial one
  const MatX q = MatX::Constant(kCount, model.dof(), 0.5);
  MatX poses(kCount, 12);
  EXPECT_EQ(allocationsOf([&] {
              forwardKinematicsBatch(model, q, poses);
              forwardKinematicsBatch(dh, q, poses);
            }),
            0);
}

TEST(Alloc, BatchJacobiansAllocateNothing) {
  const PoeModel model = testPoe();
  const DhModel dh = testDh();
  constexpr int kCount = 37;  // four full 8-lane blocks (nine 4-lane ones) and a partial one
  const MatX q = MatX::Constant(kCount, model.dof(), 0.5);
  MatX jacobians(kCount, 6 * model.dof()), poses(kCount, 12);
  EXPECT_EQ(allocationsOf([&] {
              for (const JacobianFrame frame : {JacobianFrame::Spatial, JacobianFrame::Body, JacobianFrame::Geometric}) {
                computeJacobiansBatch(model, q, frame, jacobians, poses);
                computeJacobiansBatch(dh, q, frame, jacobians, poses);
              }
            }),
            0);
}

TEST(Alloc, JacobiansAllocateNothing) {
  const PoeModel model = testPoe();
  Data data(model);
  const DhModel dh = testDh();
  Data dh_data(dh);
  const VecX q = randomQ(model.dof(), 4);
  Mat6X J(6, model.dof());
  EXPECT_EQ(allocationsOf([&] {
              computeJacobians(model, data, q); getSpatialJacobian(data, J);
              computeJacobians(model, data, q); getBodyJacobian(data, J);
              computeJacobians(model, data, q); getGeometricJacobian(data, J);
              computeJacobians(dh, dh_data, q); getSpatialJacobian(dh_data, J);
              computeJacobians(dh, dh_data, q); getBodyJacobian(dh_data, J);
              computeJacobians(dh, dh_data, q); getGeometricJacobian(dh_data, J);
            }),
            0);
}

TEST(Alloc, ExpAllocatesNothing) {
  Vec6 xi;
  xi << 0.3, -0.2, 0.9, 0.1, 0.5, -0.4;
  Pose T;
  EXPECT_EQ(allocationsOf([&] {
              T = expSE3(xi);
              T = Pose::fromMatrix(hat6(xi).exp());  // BM_Exp_EigenMatrixExp
            }),
            0);
  EXPECT_TRUE(T.R.allFinite());
}

// ---- inverse kinematics (lowpair/ik.hpp) -------------------------------------------------------------------------
// Eigen's heap allocations (aligned_malloc) call std::malloc, not operator new, and the library's .cpp files are
// compiled without EIGEN_RUNTIME_NO_MALLOC: only a malloc counter sees an Eigen temporary inside ik.cpp. glibc's
// malloc, calloc and realloc are interposed here (the executable's definitions come first in the dynamic
// lookup; each forwards to glibc's own). Not under the sanitizers, whose runtime interposes them itself.
#include "lowpair/ik.hpp"
#include "lowpair/singularity.hpp"

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define LP_ALLOC_TEST_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LP_ALLOC_TEST_SANITIZED 1
#endif
#if defined(__GLIBC__) && !defined(LP_ALLOC_TEST_SANITIZED)
#define LP_ALLOC_TEST_MALLOC 1
namespace {
std::atomic<long> g_mallocs{0};
}  // namespace
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* malloc(std::size_t size) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) noexcept {
  g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
}
#endif

namespace {

// allocationsOf, plus the malloc calls (where they are counted).
template <class F>
long heapCallsOf(F&& f) {
#if defined(LP_ALLOC_TEST_MALLOC)
  const long before = g_mallocs.load();
  const long news = allocationsOf(f);
  return news + (g_mallocs.load() - before);
#else
  return allocationsOf(f);
#endif
}

// testDh with ranges [-2, 2] (revolute, helical) and [-0.5, 0.5] (prismatic), as a POE model; `rows` joints.
PoeModel rangedPoe(int rows) {
  DhModel dh = testDh();
  std::vector<DhJoint> joints(dh.joints().begin(), dh.joints().begin() + rows);
  for (DhJoint& j : joints) j.range = j.type == JointType::Prismatic ? std::array<double, 2>{-0.5, 0.5} : std::array<double, 2>{-2.0, 2.0};
  return dhToPoe(DhModel(DhParams{}, joints, 0.1, 0.2, "alloc-ranged"));
}

}  // namespace

#if defined(LP_ALLOC_TEST_MALLOC)
TEST(Alloc, MallocCounterSeesMalloc) {
  // the interposed malloc is the one called, from this file and from the library (an Eigen heap matrix)
  EXPECT_GE(heapCallsOf([] {
              void* p = std::malloc(64);
              std::free(p);
            }),
            1);
  const long before = g_mallocs.load();
  const MatX big = MatX::Zero(40, 40);  // Eigen's aligned_malloc -> malloc (outside the EIGEN_RUNTIME_NO_MALLOC guard)
  EXPECT_GE(g_mallocs.load() - before, 1);
  EXPECT_EQ(big.sum(), 0.0);
}
#endif

// The rank rule on singular values held in fixed-size or bounded vectors (IK's, the wrist/arm blocks'):
// numericalRank reads them in place (it copied them into a heap VecX).
TEST(Alloc, NumericalRankAllocatesNothing) {
  Vec6 sigma;
  sigma << 3.0, 2.0, 1.0, 0.5, 1e-20, 0.0;
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1> bounded = sigma.head(4);
  int full = 0, head = 0;
  EXPECT_EQ(heapCallsOf([&] {
              full = numericalRank(sigma, rankTolerance(sigma[0], 6));
              head = numericalRank(bounded, rankTolerance(bounded[0], 6));
            }),
            0);
  EXPECT_EQ(full, 4);
  EXPECT_EQ(head, 4);
}

TEST(Alloc, InverseKinematicsAllocatesNothingAfterSetup) {
  // 8 joints (helical, prismatic: minimum-norm steps), a 5-joint chain (fewer joints than pose rows), ranges
  // (joints held at limits), pose, position of a tool point, the Report policy, compensation: every solve that
  // succeeds allocates nothing, with a workspace fresh from its constructor
  const PoeModel full = testPoe(), ranged = rangedPoe(8), five = rangedPoe(5);
  const PoeModel calibrated = dhToPoe([] {
    DhModel dh = testDh();
    std::vector<DhJoint> joints = dh.joints();
    joints[1].link.a += 1e-3;
    joints[3].link.alpha += 1e-3;
    return DhModel(DhParams{}, joints, 0.1, 0.2, "alloc-calibrated");
  }());
  int solved = 0;
  for (const PoeModel* model : {&full, &ranged, &five}) {
    const int n = model->dof();
    Data data(*model);
    IkWorkspace work(*model);
    IkOptions pose, position, report;
    position.measure = Measure::Position;
    position.point_tool << 0.01, 0.02, 0.03;
    report.ranges = RangePolicy::Report;
    for (unsigned k = 0; k < 20; ++k) {
      const VecX q = 0.6 * randomQ(n, 100 + k) / 3.0;  // within [-0.6, 0.6]: inside every range
      const VecX seed = q + VecX::Constant(n, 0.3);
      const Pose target = poeForwardKinematics(*model, q);
      for (const IkOptions* o : {&pose, &position, &report}) {
        IkStatus status = IkStatus::NotConverged;
        const long calls = heapCallsOf([&] { status = inverseKinematics(*model, data, target, seed, *o, work).status; });
        if (status != IkStatus::Ok) continue;
        ++solved;
        EXPECT_EQ(calls, 0) << model->name() << " target " << k;
      }
    }
  }
  Data data(full);
  IkWorkspace work(full);
  for (unsigned k = 0; k < 20; ++k) {
    const VecX q = 0.6 * randomQ(full.dof(), 200 + k) / 3.0;
    IkStatus status = IkStatus::NotConverged;
    const long calls = heapCallsOf([&] { status = compensate(full, calibrated, data, q, IkOptions{}, work).status; });
    if (status != IkStatus::Ok) continue;
    ++solved;
    EXPECT_EQ(calls, 0) << "compensate " << k;
  }
  EXPECT_GE(solved, 150);  // the success path was taken: of 3 x 20 x 3 + 20 = 200 solves
}

TEST(Alloc, ClosedFormInverseKinematicsAllocatesNothingAfterSetup) {
  // the PUMA 560's D-H (exact spherical wrist: no refinement) and the same with axis 5 moved 1e-4 off the wrist
  // centre (nearly: every candidate refined by Newton steps), every solution of 20 targets each, and compensation
  // on the nominal row's branch
  auto puma = [](double a4) {
    std::vector<DhJoint> joints(6);
    const DhParams rows[6] = {{0, 0, M_PI / 2, 0}, {0, 0, 0, 0.4318}, {0, 0.15005, -M_PI / 2, 0.0203},
                              {0, 0.4318, M_PI / 2, a4}, {0, 0, -M_PI / 2, 0}, {0, 0, 0, 0}};
    for (int i = 0; i < 6; ++i) joints[static_cast<size_t>(i)].link = rows[i];
    return dhToPoe(DhModel(DhParams{}, joints, 0.0, 0.1, "alloc-puma"));
  };
  const PoeModel exact = puma(0.0), nearly = puma(1e-4);
  ClosedFormWorkspace exact_work(exact), nearly_work(nearly);
  ASSERT_NE(nearly_work.structure.kind, ClosedFormKind::None);
  int solutions = 0, refined = 0;
  for (unsigned k = 0; k < 20; ++k) {
    const VecX q = 0.6 * randomQ(6, 300 + k) / 3.0;
    for (auto* case_ : {&exact_work, &nearly_work}) {
      const PoeModel& model = case_ == &exact_work ? exact : nearly;
      const Pose target = poeForwardKinematics(model, q);
      int count = 0;
      EXPECT_EQ(heapCallsOf([&] {
                  const ClosedFormResult& r = inverseKinematicsAll(model, target, IkOptions{}, *case_);
                  count = r.count;
                  for (int s = 0; s < r.count; ++s) refined += r.solutions[static_cast<size_t>(s)].refinement_iterations > 0;
                }),
                0)
          << model.name() << " target " << k;
      solutions += count;
    }
    const ClosedFormSolution* s = nullptr;
    EXPECT_EQ(heapCallsOf([&] { s = compensateOnBranch(exact, nearly, q, IkOptions{}, exact_work, nearly_work); }), 0);
    EXPECT_NE(s, nullptr);
  }
  EXPECT_GE(solutions, 200);  // the success path was taken: most of 2 x 20 targets have 8 solutions
  EXPECT_GT(refined, 0);
}
