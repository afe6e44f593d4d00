// The validation engine's parts (harness/comparison.hpp, harness/validate.hpp) on known data: the
// constant-memory statistics of a comparison (max, mean, p99 within the histogram's stated error,
// non-finite samples fail), their exact merge (results independent of the thread split), the random
// sample stream (bit for bit std::mt19937_64), the bounded plot subsample, and the worker pool when a
// thread cannot be created.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <atomic>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <system_error>

#include "cli_path.hpp"
#include "io/measurements.hpp"
#include "lowpair/se3.hpp"
#include "validation/calibration_scenario.hpp"
#include "validation/comparison.hpp"
#include "validation/validate.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;
using namespace lowpair::mujoco;
using namespace lowpair::commands;
using namespace lowpair::validation;

namespace {

// A file in the temporary folder named with this process's id: ctest runs this program's tests side by side.
std::string scratchName(const std::string& name) {
  return testing::TempDir() + "/validate_test_" + std::to_string(::getpid()) + "_" + name;
}

using namespace lowpair;

// The bound stated in comparison.hpp: half a bin of 100 per decade, 10^(1/200) - 1.
const double kP99RelativeError = std::pow(10.0, 0.5 / LogHistogram::kBinsPerDecade) - 1.0;

SampleErrors errors(double rotation, double translation, double euler = 0.0) {
  SampleErrors e;
  e.rotation = rotation;
  e.translation = translation;
  e.rotation_euler = euler;
  return e;
}

// Nearest-rank p-quantile (what validate reported before the histogram: the ceil(p n)-th smallest).
double exactQuantile(std::vector<double> v, double p) {
  const size_t k = static_cast<size_t>(std::ceil(p * static_cast<double>(v.size()))) - 1;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

TEST(ErrorStatistics, KnownValues) {
  // rotation k * 1e-15 rad, translation k * 2e-15 (L = 0.5: translation / L = k * 4e-15), k = 1..1000
  ErrorStatistics stats(1e-11, 1e-11, 0.5);
  for (int k = 1; k <= 1000; ++k) stats.add(k - 1, errors(k * 1e-15, k * 2e-15, k * 1.5e-15));
  ComparisonResult c;
  stats.summarize(c);
  EXPECT_EQ(stats.count(), 1000);
  EXPECT_EQ(c.non_finite, 0);
  EXPECT_TRUE(c.pass);
  EXPECT_EQ(c.max_rotation, 1000 * 1e-15);
  EXPECT_EQ(c.max_translation, 1000 * 2e-15);
  EXPECT_EQ(c.max_rotation_euler, 1000 * 1.5e-15);
  EXPECT_NEAR(c.mean_rotation, 500.5e-15, 1e-15 * 500.5e-15);
  EXPECT_NEAR(c.mean_translation, 1001e-15, 1e-15 * 1001e-15);
  // nearest rank: the 990th smallest
  EXPECT_NEAR(c.p99_rotation, 990e-15, kP99RelativeError * 990e-15);
  EXPECT_NEAR(c.p99_translation, 1980e-15, kP99RelativeError * 1980e-15);
  EXPECT_LE(c.p99_rotation, c.max_rotation);
  EXPECT_EQ(stats.worstIndex(), 999);
  EXPECT_EQ(c.tolerance_rotation, 1e-11);
  long long binned = 0;
  for (long long n : c.rotation_histogram) binned += n;
  EXPECT_EQ(binned, 1000);
}

TEST(ErrorStatistics, OutsideToleranceFails) {
  ErrorStatistics stats(1e-12, 1e-12, 1.0);
  stats.add(0, errors(1e-15, 1e-15));
  stats.add(1, errors(1e-15, 3e-12));  // translation 3 tolerances
  stats.add(2, errors(2e-12, 1e-15));  // rotation 2 tolerances
  ComparisonResult c;
  stats.summarize(c);
  EXPECT_FALSE(c.pass);
  EXPECT_EQ(stats.worstIndex(), 1) << "the worst sample is the largest error relative to its tolerance";
}

TEST(ErrorStatistics, NonFiniteSampleFailsWithItsCount) {
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    ErrorStatistics stats(1e-12, 1e-12, 1.0);
    stats.add(0, errors(1e-15, 1e-15));
    stats.add(1, errors(bad, 1e-15));
    stats.add(2, errors(1e-11, 1e-15));  // larger, but finite: the worst is still the non-finite one
    stats.add(3, errors(1e-15, bad));
    stats.add(4, errors(1e-15, 1e-15, bad));  // the Euler-angle error counts too
    ComparisonResult c;
    stats.summarize(c);
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.non_finite, 3);
    EXPECT_EQ(stats.worstIndex(), 1) << "the first non-finite sample";
    EXPECT_TRUE(std::isnan(c.max_rotation) && std::isnan(c.max_translation) && std::isnan(c.mean_rotation) &&
                std::isnan(c.p99_rotation) && std::isnan(c.p99_translation))
        << "statistics of what was not measured are not numbers";
  }
}

TEST(ErrorStatistics, P99WithinStatedErrorOverManyDecades) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-19.5, 1.5);
  for (int trial = 0; trial < 20; ++trial) {
    ErrorStatistics stats(1.0, 1.0, 1.0);
    std::vector<double> v;
    const int n = 1000 + 997 * trial;
    for (int k = 0; k < n; ++k) {
      v.push_back(std::pow(10.0, exponent(rng)));
      stats.add(k, errors(v.back(), v.back()));
    }
    ComparisonResult c;
    stats.summarize(c);
    const double exact = exactQuantile(v, 0.99);
    // (1 + 1e-9): log10 may put a value on a bin edge into the neighbouring bin
    EXPECT_LE(std::abs(c.p99_rotation - exact), kP99RelativeError * exact * (1 + 1e-9)) << n;
    EXPECT_LE(std::abs(c.p99_translation - exact), kP99RelativeError * exact * (1 + 1e-9)) << n;
  }
  // exact zeros (below the log range) and values at or above 1e2
  ErrorStatistics zeros(1.0, 1.0, 1.0);
  for (int k = 0; k < 100; ++k) zeros.add(k, errors(0.0, k < 99 ? 0.0 : 5.0));
  ComparisonResult c;
  zeros.summarize(c);
  EXPECT_EQ(c.p99_rotation, 0.0);
  EXPECT_EQ(c.p99_translation, 0.0);
  EXPECT_EQ(c.max_translation, 5.0);
  LogHistogram high;
  for (double x : {1e3, 2e3, 5e4}) high.add(x);
  EXPECT_EQ(high.quantile(0.99), 5e4) << "at or above 1e2: the largest value";
}

TEST(ErrorStatistics, MergeIsExactWhateverTheSplit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> exponent(-17.0, -12.0);
  std::vector<SampleErrors> samples;
  for (int k = 0; k < 5000; ++k) {
    const double a = std::pow(10.0, exponent(rng));  // (two statements: the draws in a fixed order)
    samples.push_back(errors(a, std::pow(10.0, exponent(rng))));
  }
  samples[1234] = samples[4321];  // a tie for the worst sample would go to the smaller index
  auto run = [&](int threads, bool interleaved) {
    std::vector<ErrorStatistics> parts(static_cast<size_t>(threads), ErrorStatistics(1e-12, 1e-12, 0.7));
    for (size_t k = 0; k < samples.size(); ++k) {
      const size_t t = interleaved ? k % static_cast<size_t>(threads) : k * static_cast<size_t>(threads) / samples.size();
      parts[t].add(static_cast<long long>(k), samples[k]);
    }
    ErrorStatistics total(1e-12, 1e-12, 0.7);
    for (auto it = parts.rbegin(); it != parts.rend(); ++it) total.merge(*it);  // any merge order
    ComparisonResult c;
    total.summarize(c);
    return std::make_pair(c, total.worstIndex());
  };
  const auto [one, worst_one] = run(1, false);
  for (int threads : {2, 3, 7, 64}) {
    for (bool interleaved : {false, true}) {
      const auto [c, worst] = run(threads, interleaved);
      EXPECT_EQ(c.max_rotation, one.max_rotation);
      EXPECT_EQ(c.max_translation, one.max_translation);
      EXPECT_EQ(c.mean_rotation, one.mean_rotation) << "the sums are exact: the mean is bit-identical";
      EXPECT_EQ(c.mean_translation, one.mean_translation);
      EXPECT_EQ(c.p99_rotation, one.p99_rotation);
      EXPECT_EQ(c.p99_translation, one.p99_translation);
      EXPECT_EQ(c.rotation_histogram, one.rotation_histogram);
      EXPECT_EQ(worst, worst_one);
    }
  }
}

TEST(ExactSum, IndependentOfOrder) {
  ExactSum a, b;
  a.add(1e16);
  a.add(1.0);
  a.add(1.0);
  b.add(1.0);
  b.add(1.0);
  b.add(1e16);
  EXPECT_EQ(a.value(), 1e16 + 2.0);  // 1e16 + 1 + 1 in double is 1e16
  EXPECT_EQ(b.value(), 1e16 + 2.0);
  ExactSum tiny;
  for (int k = 0; k < 1000; ++k) tiny.add(std::numeric_limits<double>::denorm_min());
  tiny.add(std::numeric_limits<double>::max());
  tiny.add(0.0);
  ExactSum sum;
  sum.add(tiny);
  sum.add(a);
  EXPECT_EQ(sum.value(), std::numeric_limits<double>::max());
  ExactSum big;
  big.add(std::numeric_limits<double>::max());
  big.add(std::numeric_limits<double>::max());
  EXPECT_TRUE(std::isinf(big.value())) << "a sum beyond the largest double rounds to inf";
}

// The stream as it has always been defined: std::mt19937_64 seeded with splitmix64(seed * FNV + index).
void referenceSample(unsigned long long seed, unsigned long long index, const std::vector<std::array<double, 2>>& ranges,
                     VecX& q) {
  unsigned long long x = seed * 0x100000001B3ULL + index;
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  std::mt19937_64 rng(x ^ (x >> 31));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    q[i] = ranges[static_cast<size_t>(i)][0] +
           unit(rng) * (ranges[static_cast<size_t>(i)][1] - ranges[static_cast<size_t>(i)][0]);
  }
}

TEST(RandomSample, BitForBitTheMersenneTwisterStream) {
  for (int n : {1, 6, 7, 20, 78, 79, 155, 156, 157, 200}) {
    std::vector<std::array<double, 2>> ranges;
    for (int i = 0; i < n; ++i) ranges.push_back({-1.0 - i, 2.0 + 0.5 * i});
    VecX q(n), expected(n);
    for (unsigned long long seed : {0ULL, 1ULL, 2ULL, 123456789ULL, (1ULL << 53)}) {
      for (unsigned long long index : {0ULL, 1ULL, 9999ULL, 123456789ULL}) {
        randomSample(seed, index, ranges, q);
        referenceSample(seed, index, ranges, expected);
        for (int i = 0; i < n; ++i) ASSERT_EQ(q[i], expected[i]) << "n " << n << " seed " << seed << " index " << index;
      }
    }
  }
}

TEST(PlotSamples, BoundedAndDeterministic) {
  const PlotSamples small(10000, 1.0);
  EXPECT_EQ(small.stride, 1);
  EXPECT_EQ(small.rotation.size(), 10000u);
  const PlotSamples big(10000000, 1.0);
  EXPECT_EQ(big.stride, 500);
  EXPECT_EQ(big.rotation.size(), 20000u);
  const PlotSamples odd(100000007, 1.0);
  EXPECT_LE(odd.rotation.size(), static_cast<size_t>(PlotSamples::kMaxPoints));
  PlotSamples p(1000000, 2.0);
  EXPECT_EQ(p.stride, 50);
  p.record(101, errors(1.0, 1.0));  // not a multiple of the stride: not kept
  p.record(150, errors(3e-16, 4e-16));
  EXPECT_EQ(p.rotation[2], 0.0f);
  EXPECT_EQ(p.rotation[3], 3e-16f);
  EXPECT_EQ(p.translation[3], 2e-16f) << "translation / L";
}

// Items taken from a shared counter: every one is done once, whoever runs.
struct Queue {
  explicit Queue(int items) : done(static_cast<size_t>(items)) {}
  void work() {
    for (int k; (k = next.fetch_add(1)) < static_cast<int>(done.size());) done[static_cast<size_t>(k)]++;
  }
  std::atomic<int> next{0};
  std::vector<std::atomic<int>> done;
};

TEST(RunWorkers, ThreadThatCannotBeCreatedFallsBackToFewerThreads) {
  Queue queue(100000);
  int created = 0;
  const ThreadStarter failing = [&](std::function<void()> job) {
    if (++created > 2) throw std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again));
    return std::thread(std::move(job));
  };
  const int ran = runWorkers(64, [&](int) { queue.work(); }, failing);
  EXPECT_EQ(ran, 3) << "the calling thread and the two that were created";
  for (const auto& d : queue.done) ASSERT_EQ(d.load(), 1);
  // std::bad_alloc, and a starter that returns no thread, end the starting the same way
  Queue again(1000);
  const ThreadStarter no_memory = [](std::function<void()>) -> std::thread { throw std::bad_alloc(); };
  EXPECT_EQ(runWorkers(8, [&](int) { again.work(); }, no_memory), 1);
  for (const auto& d : again.done) ASSERT_EQ(d.load(), 1);
  EXPECT_EQ(runWorkers(8, [](int) {}, [](std::function<void()>) { return std::thread(); }), 1);
}

TEST(RunWorkers, WorkerExceptionIsRethrownAfterTheJoin) {
  std::atomic<int> finished{0};
  EXPECT_THROW(runWorkers(4,
                          [&](int t) {
                            if (t == 2) throw std::runtime_error("worker 2 failed");
                            std::this_thread::sleep_for(std::chrono::milliseconds(50));
                            ++finished;
                          }),
               std::runtime_error);
  EXPECT_EQ(finished.load(), 3) << "every other worker ran to its end before the rethrow";
  EXPECT_EQ(runWorkers(0, [](int) {}), 1) << "at least the calling thread";
}

}  // namespace

// One sampling unit (sampling.hpp): a scenario's calibration case and `lowpair simulate` with the same
// model, joint variable, seed and noise draw the same joint vectors and measure the same poses. (Before the
// unit, simulate sampled a revolute joint within the MJCF limits and a calibration case over a full turn.)
// The case taken is a tracker's: targets (sites), a measurement frame and blunders too.
TEST(Sampling, SimulateAndCalibrationCaseDrawTheSamePoses) {
  for (const auto& [name, case_name] : {std::pair{"puma560_okamura_actual.yaml", "tracker"},
                                        std::pair{"stanford_corke_actual.yaml", "tracker-frame"}}) {
    const Scenario scenario = readScenario(std::string(LOWPAIR_SCENARIOS) + "/" + name);
    const std::string wanted = case_name;  // (clang 14 cannot capture a structured binding)
    const auto found = std::find_if(scenario.calibrations.begin(), scenario.calibrations.end(),
                                    [&](const CalibrationCase& k) { return k.name == wanted; });
    ASSERT_NE(found, scenario.calibrations.end()) << name << ": no case " << case_name;
    const CalibrationCase& c = *found;
    EXPECT_TRUE(c.frame) << name << ": the " << case_name << " case is measured in a frame of its own";
    const MujocoRobot robot(scenario.model, scenario.tip, scenario.base);
    const SampledVariable v =
        sampledVariable(robot, scenario.joint_variables, scenario.model, scenario.tip, scenario.ranges, scenario.path);
    MujocoRobot::Evaluator mujoco(robot);
    constexpr int kPoses = 7;
    MeasurementFile expected =
        simulatedMeasurements(c, caseMeasurementSetup(c, robot, true), mujoco, v.motions, v.ranges, 0, kPoses, "case");
    const std::vector<size_t> blunders = addBlunders(c.seed, c.blunders, c.blunder_size, expected.measurements);
    EXPECT_EQ(static_cast<long long>(blunders.size()), c.blunders);

    const std::string csv = scratchName(std::string("sampling_") + name + ".csv");
    std::ostringstream command;
    command.precision(17);
    command << lowpair_test::cliCommand() << " simulate " << scenario.model << " --tip " << scenario.tip
            << (scenario.joint_variables.empty() ? "" : " --joint-variables " + scenario.joint_variables)
            << " --poses " << kPoses << " --seed " << c.seed << " --noise-position " << c.noise_position
            << " --measure " << measureName(c.measure());
    if (c.measure() == Measure::Pose) command << " --noise-rotation " << c.noise_rotation;
    for (size_t t = 0; t < c.targets.size(); ++t) command << (t ? "," : " --targets ") << c.targets[t];
    if (c.frame) {
      for (size_t k = 0; k < 6; ++k) command << (k ? "," : " --frame ") << (*c.frame)[k];
    }
    if (c.blunders > 0) command << " --blunders " << c.blunders << "," << c.blunder_size;
    command << " --out " << csv << " > /dev/null";
    ASSERT_EQ(std::system(command.str().c_str()), 0) << command.str();
    const MeasurementFile simulated = readMeasurements(csv);
    std::remove(csv.c_str());
    ASSERT_EQ(simulated.measurements.size(), expected.measurements.size()) << name;
    for (size_t k = 0; k < expected.measurements.size(); ++k) {
      const Measurement& a = expected.measurements[k];
      const Measurement& b = simulated.measurements[k];
      // joint values and positions are written with 17 significant digits: they read back bit for bit
      EXPECT_EQ(a.q, b.q) << name << " pose " << k;
      EXPECT_EQ(a.T_base_tool.p, b.T_base_tool.p) << name << " pose " << k;
      EXPECT_EQ(a.target, b.target) << name << " pose " << k;
      // the rotation passes through a quaternion printed with 17 digits: equal to rounding (position
      // measurements carry none)
      if (c.measure() == Measure::Pose) {
        EXPECT_LT((a.T_base_tool.R - b.T_base_tool.R).norm(), 8 * std::numeric_limits<double>::epsilon())
            << name << " pose " << k;
      }
    }
  }
}

// Blunders (sampling.hpp addBlunders): `count` distinct rows, each moved by exactly `size` (the position only),
// the others untouched; the same seed the same rows; rows uniform over the measurements and directions
// uniform on the sphere (1000 seeds: every row's count within 4 binomial standard deviations, the mean
// direction within 5 standard deviations of 0).
TEST(Sampling, BlundersAreDistinctRowsMovedByExactlyTheirSize) {
  auto measurements = [](int n) {
    std::vector<Measurement> ms(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) {
      ms[static_cast<size_t>(k)].q = VecX::Constant(2, k);
      ms[static_cast<size_t>(k)].T_base_tool.p = Vec3(1000.0 * k, -3.0, 7.0);
      ms[static_cast<size_t>(k)].T_base_tool.R = expSO3(Vec3(0.1 * k, 0.2, 0.3));
    }
    return ms;
  };
  const std::vector<Measurement> clean = measurements(50);
  std::vector<Measurement> ms = clean;
  const std::vector<size_t> rows = addBlunders(7, 10, 2.5, ms);
  ASSERT_EQ(rows.size(), 10u);
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end()));
  EXPECT_EQ(std::adjacent_find(rows.begin(), rows.end()), rows.end());
  for (size_t k = 0; k < ms.size(); ++k) {
    const bool blunder = std::binary_search(rows.begin(), rows.end(), k);
    const double moved = (ms[k].T_base_tool.p - clean[k].T_base_tool.p).norm();
    if (blunder) {
      EXPECT_NEAR(moved, 2.5, 64 * std::numeric_limits<double>::epsilon() * 5e4) << k;
    } else {
      EXPECT_EQ(moved, 0.0) << k;
    }
    EXPECT_EQ(ms[k].T_base_tool.R, clean[k].T_base_tool.R) << "a blunder keeps the rotation";
    EXPECT_EQ(ms[k].q, clean[k].q);
  }
  std::vector<Measurement> again = clean, other = clean;
  EXPECT_EQ(addBlunders(7, 10, 2.5, again), rows);
  EXPECT_NE(addBlunders(8, 10, 2.5, other), rows);
  std::vector<Measurement> all = clean, none = clean;
  EXPECT_EQ(addBlunders(7, 50, 1.0, all).size(), 50u);
  EXPECT_TRUE(addBlunders(7, 0, 1.0, none).empty());
  EXPECT_THROW(addBlunders(7, 51, 1.0, none), std::invalid_argument);
  EXPECT_THROW(addBlunders(7, -1, 1.0, none), std::invalid_argument);
  EXPECT_THROW(addBlunders(7, 1, std::nan(""), none), std::invalid_argument);
  // uniform rows and directions
  constexpr int kSeeds = 1000, kRows = 10, kCount = 3;
  std::vector<int> chosen(kRows, 0);
  Vec3 mean = Vec3::Zero();
  for (int seed = 0; seed < kSeeds; ++seed) {
    std::vector<Measurement> m = measurements(kRows);
    for (const size_t r : addBlunders(static_cast<unsigned long long>(seed), kCount, 1.0, m)) {
      ++chosen[r];
      mean += m[r].T_base_tool.p - Vec3(1000.0 * static_cast<double>(r), -3.0, 7.0);
    }
  }
  const double p = static_cast<double>(kCount) / kRows, expected = kSeeds * p;
  for (int r = 0; r < kRows; ++r) EXPECT_NEAR(chosen[static_cast<size_t>(r)], expected, 4 * std::sqrt(expected * (1 - p))) << r;
  mean /= kSeeds * kCount;
  EXPECT_LT(mean.cwiseAbs().maxCoeff(), 5 * std::sqrt(1.0 / 3.0 / (kSeeds * kCount)));
}

// ---- calibration cases: plan: and compensate: (scenario.hpp CasePlan, CaseCompensation) -----------------------

namespace {

struct LoopFixture {
  lowpair::validation::Scenario scenario;
  std::unique_ptr<MujocoRobot> robot;
  SampledVariable sampled;
};

LoopFixture pumaLoop() {
  LoopFixture f;
  f.scenario = readScenario(std::string(LOWPAIR_SCENARIOS) + "/puma560_okamura_actual.yaml");
  f.robot = std::make_unique<MujocoRobot>(f.scenario.model, f.scenario.tip, f.scenario.base);
  f.sampled = sampledVariable(*f.robot, f.scenario.joint_variables, f.scenario.model, f.scenario.tip, f.scenario.ranges,
                              f.scenario.path);
  return f;
}

const CalibrationCase& caseNamed(const lowpair::validation::Scenario& s, const std::string& name) {
  for (const CalibrationCase& c : s.calibrations) {
    if (c.name == name) return c;
  }
  throw std::runtime_error("no case " + name);
}

}  // namespace

// The planned case fits the candidates planPoses chose (samples of the case's stream, not the first N), whose
// information is larger than the first N samples'; its validation poses are samples M.., after every candidate.
// And it is `lowpair plan` then `lowpair simulate --q-file`: the same measurements to the last bit.
TEST(CalibrationLoop, PlannedCaseIsPlanThenSimulateQFile) {
  using namespace lowpair;
  const LoopFixture f = pumaLoop();
  const CalibrationCase& c = caseNamed(f.scenario, "planned-15");
  ASSERT_TRUE(c.plan);
  ASSERT_TRUE(c.frame);
  const CalibrationCaseResult r = runCalibrationCase(f.scenario, c, *f.robot, f.sampled);
  EXPECT_TRUE(r.pass) << (r.failures.empty() ? "" : r.failures.front());
  ASSERT_TRUE(r.plan);
  const std::vector<int>& chosen = r.plan->plan.indices;
  ASSERT_EQ(static_cast<int>(chosen.size()), c.poses);
  std::vector<int> first(chosen.size());
  for (size_t k = 0; k < first.size(); ++k) first[k] = static_cast<int>(k);
  EXPECT_NE(chosen, first);
  EXPECT_GT(r.plan->plan.value.log_det, r.plan->first.log_det);
  EXPECT_GE(r.plan->plan.value.log_det, r.plan->plan.start.log_det) << "the exchange never lowers the criterion";
  // fitting pose k: candidate chosen[k], i.e. sample chosen[k] of the stream; validation pose k: sample M + k
  const io::MeasurementFile& fit = r.report->fit;
  ASSERT_EQ(fit.measurements.size(), chosen.size());
  VecX q(6);
  for (size_t k = 0; k < chosen.size(); ++k) {
    randomSample(c.seed, static_cast<unsigned long long>(chosen[k]), f.sampled.ranges, q);
    EXPECT_EQ(fit.measurements[k].q, q) << k;
  }
  ASSERT_TRUE(r.report->validation);
  for (size_t k = 0; k < 3; ++k) {
    randomSample(c.seed, static_cast<unsigned long long>(c.plan->candidates) + k, f.sampled.ranges, q);
    EXPECT_EQ(r.report->validation->measurements[k].q, q) << k;
  }
  // the command line: plan on the nominal, then simulate the actual robot at its q-file
  const std::string q_file = scratchName("planned_case_q.csv"), csv = scratchName("planned_case.csv");
  std::ostringstream plan, simulate;
  plan.precision(17);
  simulate.precision(17);
  plan << lowpair_test::cliCommand() << " plan " << c.nominal << " --poses " << c.poses << " --candidates " << c.plan->candidates
       << " --seed " << c.seed << (c.free_pitch ? " --free-pitch" : "") << " --out " << q_file << " > /dev/null";
  ASSERT_EQ(std::system(plan.str().c_str()), 0) << plan.str();
  simulate << lowpair_test::cliCommand() << " simulate " << f.scenario.model << " --tip " << f.scenario.tip << " --joint-variables "
           << f.scenario.joint_variables << " --q-file " << q_file << " --seed " << c.seed << " --noise-position "
           << c.noise_position << " --noise-rotation " << c.noise_rotation;
  for (size_t k = 0; k < 6; ++k) simulate << (k ? "," : " --frame ") << (*c.frame)[k];
  simulate << " --out " << csv << " > /dev/null";
  ASSERT_EQ(std::system(simulate.str().c_str()), 0) << simulate.str();
  const MeasurementFile simulated = readMeasurements(csv);
  std::remove(q_file.c_str());
  std::remove(csv.c_str());
  ASSERT_EQ(simulated.measurements.size(), fit.measurements.size());
  for (size_t k = 0; k < fit.measurements.size(); ++k) {
    EXPECT_EQ(simulated.measurements[k].q, fit.measurements[k].q) << k;
    EXPECT_EQ(simulated.measurements[k].T_base_tool.p, fit.measurements[k].T_base_tool.p) << k;
    EXPECT_LT((simulated.measurements[k].T_base_tool.R - fit.measurements[k].T_base_tool.R).norm(),
              8 * std::numeric_limits<double>::epsilon())
        << k;
  }
}

// Compensation when the nominal is already right (the actual robot's own file, noise-free, measured by a tracker
// in a far frame): the calibrated model moved back from the tracker's frame is the actual robot, every row is ok
// and the compensated tool is where the nominal puts it to 1e-9 L, for the tool frame and for a target's point.
// (Without the frame undone, the error after would be the frame's 3 m.)
TEST(CalibrationLoop, CompensatingARightNominalInAFarFrameChangesNothing) {
  using namespace lowpair;
  const LoopFixture f = pumaLoop();
  const double L = readRobotFile(f.scenario.joint_variables).poeModel().lengthScale();
  for (const bool targets : {false, true}) {
    CalibrationCase c;
    c.name = targets ? "right-nominal-target" : "right-nominal-pose";
    c.nominal = f.scenario.joint_variables;  // the actual robot's file
    c.poses = 30;
    c.validation_poses = 40;
    c.seed = 5;
    c.free_pitch = true;
    if (targets) c.targets = {"smr_b", "smr_a"};
    c.frame = std::array<double, 6>{0.3, -1.2, 2.0, 3000, -800, 400};
    c.tolerance_position = 1e-9 * L;
    c.compensation = CaseCompensation{1e-9 * L, 0};
    const CalibrationCaseResult r = runCalibrationCase(f.scenario, c, *f.robot, f.sampled);
    ASSERT_TRUE(r.compensation) << c.name;
    const CompensationResult& k = *r.compensation;
    EXPECT_TRUE(r.pass) << c.name << ": " << (r.failures.empty() ? "" : r.failures.front());
    EXPECT_EQ(k.statuses[static_cast<size_t>(IkStatus::Ok)], c.validation_poses) << c.name;
    EXPECT_TRUE(k.not_ok.empty()) << c.name;
    EXPECT_EQ(k.measure, targets ? Measure::Position : Measure::Pose) << c.name;
    EXPECT_EQ(k.point_name, targets ? "smr_b" : "") << c.name;
    EXPECT_LE(k.before.max_position, 1e-9 * L) << c.name << ": the nominal is the actual robot";
    EXPECT_LE(k.after.max_position, 1e-9 * L) << c.name;
    if (!targets) {
      EXPECT_LE(k.after.max_rotation, 1e-9) << c.name;
    }
    EXPECT_EQ(k.after.count, c.validation_poses) << c.name;
  }
}

// A compensation that cannot be commanded is counted and named, never used: with allowed_not_ok 0 the PUMA's
// noise-free case fails naming its rows, and its numbers after come from the ok rows only.
TEST(CalibrationLoop, RowsNotOkAreCountedAndFailTheCase) {
  using namespace lowpair;
  const LoopFixture f = pumaLoop();
  CalibrationCase c = caseNamed(f.scenario, "noise-free");
  ASSERT_TRUE(c.compensation);
  c.compensation->allowed_not_ok = 0;
  const CalibrationCaseResult r = runCalibrationCase(f.scenario, c, *f.robot, f.sampled);
  ASSERT_TRUE(r.compensation);
  const CompensationResult& k = *r.compensation;
  int counted = 0;
  for (const int n : k.statuses) counted += n;
  EXPECT_EQ(counted, c.validation_poses);
  ASSERT_FALSE(k.not_ok.empty()) << "the PUMA's stretched-elbow targets have no solution near q";
  EXPECT_EQ(k.after.count + static_cast<int>(k.not_ok.size()), c.validation_poses);
  for (const auto& row : k.not_ok) {
    EXPECT_NE(row.status, IkStatus::Ok);
    EXPECT_FALSE(row.reason.empty());
  }
  EXPECT_FALSE(r.pass);
  ASSERT_FALSE(r.failures.empty());
  EXPECT_NE(r.failures.back().find("rows not ok"), std::string::npos) << r.failures.back();
  EXPECT_NE(r.failures.back().find("validation pose " + std::to_string(k.not_ok.front().row + 1)), std::string::npos);
}
