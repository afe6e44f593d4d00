// The sampling unit (sampling.hpp): range rule, random streams, sampled variable, worker pool.
#include "commands/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <random>
#include <set>
#include <stdexcept>

#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "lowpair/se3.hpp"

namespace lowpair::commands {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::mujoco;

namespace {

// splitmix64: decorrelated per-sample seeds, so a sample's q depends only on (seed, index) and the
// results do not depend on the thread count or the shard.
unsigned long long mix(unsigned long long x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// The first outputs of std::mt19937_64 seeded with one value, bit for bit, without its full state: output
// k < 156 of the first twist needs state words k, k + 1 and k + 156 of the seeding only, so the seeding
// stops at word 156 + (outputs drawn) instead of filling 312 words and twisting them all (0.75 us instead
// of 4.5 us for a 6-joint sample here; the random stream, and with it every result, is unchanged:
// tests/harness/validate_test.cpp checks it against std::mt19937_64).
class Mt19937_64Prefix {
 public:
  using result_type = std::uint_fast64_t;
  static constexpr int kMaxOutputs = 156;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type{0}; }

  explicit Mt19937_64Prefix(result_type seed) { x_[0] = seed; }

  result_type operator()() {
    if (k_ >= kMaxOutputs) throw std::logic_error("Mt19937_64Prefix: more than 156 outputs");
    const int k = k_++;
    for (; seeded_ <= k + kM; ++seeded_) {  // seeding of std::mersenne_twister_engine, word by word
      const result_type prev = x_[static_cast<size_t>(seeded_ - 1)];
      x_[static_cast<size_t>(seeded_)] = 6364136223846793005ULL * (prev ^ (prev >> 62)) + static_cast<result_type>(seeded_);
    }
    const result_type y = (x_[static_cast<size_t>(k)] & kUpper) | (x_[static_cast<size_t>(k + 1)] & kLower);
    result_type z = x_[static_cast<size_t>(k + kM)] ^ (y >> 1) ^ ((y & 1) ? kA : 0);  // the twist of word k
    z ^= (z >> 29) & 0x5555555555555555ULL;  // tempering
    z ^= (z << 17) & 0x71D67FFFEDA60000ULL;
    z ^= (z << 37) & 0xFFF7EEE000000000ULL;
    return z ^ (z >> 43);
  }

 private:
  static constexpr int kM = 156;
  static constexpr result_type kA = 0xB5026F5AA96619E9ULL, kUpper = ~result_type{0} << 31, kLower = ~kUpper;
  std::array<result_type, 312> x_;  // words 0 .. seeded_ - 1 are set
  int seeded_ = 1, k_ = 0;
};

template <class Engine>
void drawSample(Engine& rng, const std::vector<Range>& ranges, Eigen::Ref<VecX> q) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const auto& r = ranges[static_cast<size_t>(i)];
    q[i] = r[0] + unit(rng) * (r[1] - r[0]);
  }
}

}  // namespace

Range defaultRange(JointType type, double L) {
  if (type == JointType::Prismatic) return {-L, L};
  return {-M_PI, M_PI};
}

std::string jointValueProblem(const PoeModel& model, int i, double q) {
  const Joint& j = model.joint(i);
  if (jointValueWithinLimits(j, q)) return "";
  if (!std::isfinite(q)) return "'" + io::shortest(q) + "' is not finite";
  return "'" + io::shortest(q) + "' is beyond joint " + std::to_string(i + 1) + "'s limit (" +
         (j.name.empty() ? std::string() : j.name + ", ") + jointTypeName(j.type) + ": |" +
         (j.type == JointType::Helical ? "pitch " : "") + "scale (q + offset)| at most 1e100, kMaxMagnitude): its pose would not be finite";
}

std::vector<Range> samplingRanges(const PoeModel& model) {
  std::vector<Range> ranges;
  for (const Joint& j : model.joints()) ranges.push_back(j.range ? *j.range : defaultRange(j.type, model.lengthScale()));
  return ranges;
}

SampledVariable sampledVariable(const mujoco::MujocoRobot& robot, const std::string& joint_variables,
                                const std::string& model_path, const std::string& tip, const std::vector<Range>& given,
                                const std::string& subject) {
  const int n = robot.dof();
  SampledVariable v;
  v.motions.assign(static_cast<size_t>(n), JointMotion{});
  if (!joint_variables.empty()) {
    const io::RobotFile file = io::readRobotFile(joint_variables);
    v.file_model = mujoco::matchingModel(file, robot, model_path, tip);
    for (int i = 0; i < n; ++i) v.motions[static_cast<size_t>(i)] = v.file_model->joint(i);
    v.length_unit = file.length_unit;
  }
  if (std::filesystem::path(model_path).extension() == ".urdf") v.length_unit = "m";
  if (!given.empty() && static_cast<int>(given.size()) != n) {
    throw io::RobotFileError(subject + ": ranges has " + std::to_string(given.size()) + " entries for " +
                             std::to_string(n) + " joints");
  }
  const double L = robot.poeModel().lengthScale();
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<size_t>(i);
    const mujoco::MujocoJoint& j = robot.joints()[k];
    if (!given.empty()) {
      v.ranges.push_back(given[k]);
    } else if (v.file_model && v.file_model->joint(i).range) {
      v.ranges.push_back(*v.file_model->joint(i).range);
    } else if (j.range) {
      v.ranges.push_back({v.motions[k].variable((*j.range)[0]), v.motions[k].variable((*j.range)[1])});
    } else {
      v.ranges.push_back(defaultRange(j.type, L));
    }
  }
  return v;
}

void randomSample(unsigned long long seed, unsigned long long index, const std::vector<Range>& ranges,
                  Eigen::Ref<VecX> q) {
  const unsigned long long s = mix(seed * 0x100000001B3ULL + index);
  // one engine call per draw in libstdc++ and libc++ (generate_canonical<double, 53> of a 64-bit engine); room for two
  if (2 * q.size() <= Mt19937_64Prefix::kMaxOutputs) {
    Mt19937_64Prefix rng(s);
    drawSample(rng, ranges, q);
  } else {
    std::mt19937_64 rng(s);
    drawSample(rng, ranges, q);
  }
}

std::vector<VecX> randomSamples(unsigned long long seed, unsigned long long first, int count,
                                const std::vector<Range>& ranges) {
  std::vector<VecX> out(static_cast<size_t>(std::max(0, count)), VecX(static_cast<Eigen::Index>(ranges.size())));
  for (size_t k = 0; k < out.size(); ++k) randomSample(seed, first + k, ranges, out[k]);
  return out;
}

void addMeasurementNoise(unsigned long long seed, unsigned long long index, double sd_position, double sd_rotation,
                         Pose& T) {
  if (sd_position == 0.0 && sd_rotation == 0.0) return;
  constexpr unsigned long long kNoiseStream = 0x6E6F6973652D7374ULL;  // "noise-st"
  std::mt19937_64 rng(mix(mix(seed ^ kNoiseStream) + index));
  std::normal_distribution<double> normal(0.0, 1.0);
  Vec3 dp, n;
  for (int k = 0; k < 3; ++k) dp[k] = sd_position * normal(rng);
  for (int k = 0; k < 3; ++k) n[k] = sd_rotation * normal(rng);
  T.p += dp;
  T.R = expSO3(n) * T.R;
}

Pose measurementFrame(const Vec3& rotation, const Vec3& translation) { return Pose{expSO3(rotation), translation}; }

int rowsPerPose(const MeasurementSetup& setup) {
  return setup.measure == Measure::Targets ? static_cast<int>(setup.targets.size()) : 1;
}

void appendMeasurements(const MeasurementSetup& setup, unsigned long long seed, unsigned long long pose,
                        const Eigen::Ref<const VecX>& q, const Pose& T_base_tool, std::vector<Measurement>& out) {
  const Pose T_frame_tool = setup.T_frame_base * T_base_tool;
  const int rows = rowsPerPose(setup);
  for (int t = 0; t < rows; ++t) {
    Measurement m;
    m.q = q;
    if (setup.measure == Measure::Targets) {
      m.target = t;
      m.T_base_tool.p = T_frame_tool.R * setup.targets[static_cast<size_t>(t)] + T_frame_tool.p;
    } else {
      m.T_base_tool = T_frame_tool;
    }
    const unsigned long long row = pose * static_cast<unsigned long long>(rows) + static_cast<unsigned long long>(t);
    addMeasurementNoise(seed, row, setup.sd_position, setup.sd_rotation, m.T_base_tool);
    out.push_back(std::move(m));
  }
}

namespace {

constexpr unsigned long long kBlunderStream = 0x626C756E64657273ULL;  // "blunders"

// uniform in [0, n) from raw engine outputs (rejection of the incomplete last block: exact, portable)
unsigned long long below(std::mt19937_64& rng, unsigned long long n) {
  const unsigned long long threshold = (0 - n) % n;  // 2^64 mod n
  while (true) {
    const unsigned long long x = rng();
    if (x >= threshold) return x % n;
  }
}

// uniform in [0, 1) with 53 random bits
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

}  // namespace

std::vector<size_t> addBlunders(unsigned long long seed, long long count, double size,
                                std::vector<Measurement>& measurements) {
  const auto n = static_cast<long long>(measurements.size());
  if (count < 0 || count > n) {
    throw std::invalid_argument("addBlunders: " + std::to_string(count) + " blunders among " + std::to_string(n) +
                                " measurements");
  }
  if (!(size >= 0.0) || !std::isfinite(size)) throw std::invalid_argument("addBlunders: size not finite and >= 0");
  // Floyd: for j = n - count .. n - 1, draw t in [0, j]; take t, or j when t is taken
  std::mt19937_64 pick(mix(seed ^ kBlunderStream));
  std::set<size_t> rows;
  for (long long j = n - count; j < n; ++j) {
    const auto t = static_cast<size_t>(below(pick, static_cast<unsigned long long>(j) + 1));
    if (!rows.insert(t).second) rows.insert(static_cast<size_t>(j));
  }
  for (const size_t row : rows) {
    std::mt19937_64 rng(mix(mix(seed ^ kBlunderStream) + 1 + row));
    const double z = 2.0 * unit(rng) - 1.0, phi = 2.0 * M_PI * unit(rng);
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    measurements[row].T_base_tool.p += size * Vec3(rho * std::cos(phi), rho * std::sin(phi), z);
  }
  return {rows.begin(), rows.end()};
}

int runWorkers(int threads, const std::function<void(int)>& work, const ThreadStarter& start) {
  threads = std::max(1, threads);
  std::vector<std::exception_ptr> errors(static_cast<size_t>(threads));
  auto guarded = [&](int t) {
    try {
      work(t);
    } catch (...) {
      errors[static_cast<size_t>(t)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(threads - 1));
  int started = 1;
  for (int t = 1; t < threads; ++t) {
    try {
      std::function<void()> job = [&guarded, t] { guarded(t); };
      std::thread th = start ? start(std::move(job)) : std::thread(std::move(job));
      if (!th.joinable()) break;
      pool.push_back(std::move(th));  // no allocation: reserved
    } catch (...) {
      break;  // no more threads (std::system_error, std::bad_alloc): run with those started
    }
    ++started;
  }
  guarded(0);
  for (auto& th : pool) th.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return started;
}

}  // namespace lowpair::commands
