#pragma once
/// @file fuzz_common.hpp
/// Shared by the fuzz targets (tests/fuzz/README.md): the input as a temporary file (the readers take a
/// path), finiteness checks that abort on violation (libFuzzer saves the input), and the fixed joint
/// vectors an accepted model is evaluated at.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"

/// Aborts (libFuzzer: a crash, the input saved) with the failed condition on stderr.
#define FUZZ_CHECK(cond)                                                                          \
  do {                                                                                            \
    if (!(cond)) {                                                                                \
      std::fprintf(stderr, "fuzz check failed: %s (%s:%d)\n", #cond, __FILE__, __LINE__);         \
      std::abort();                                                                               \
    }                                                                                             \
  } while (0)

namespace lowpair_fuzz {

/// One temporary file per process and target, rewritten for each input and removed at exit.
class TempFile {
 public:
  explicit TempFile(const std::string& suffix) {
    const char* dir = std::getenv("TMPDIR");
    std::string pattern = std::string(dir && *dir ? dir : "/tmp") + "/lowpair_fuzz_XXXXXX" + suffix;
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    const int fd = mkstemps(buf.data(), static_cast<int>(suffix.size()));
    if (fd < 0) {
      std::perror("mkstemps");
      std::abort();
    }
    close(fd);
    path_ = buf.data();
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  /// Writes `size` bytes; returns the path.
  const std::string& write(const uint8_t* data, size_t size) const {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f) {
      std::perror(path_.c_str());
      std::abort();
    }
    if (size && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline bool finite(const lowpair::Pose& T) { return T.R.allFinite() && T.p.allFinite(); }

/// Joint vectors inside the model's ranges: for each c in a few fixed values, q_i = c clamped into
/// joint i's range (no range: c itself), plus each range's ends and middle.
inline std::vector<lowpair::VecX> fixedConfigurations(const std::vector<std::optional<std::array<double, 2>>>& ranges) {
  const int n = static_cast<int>(ranges.size());
  std::vector<lowpair::VecX> out;
  for (const double c : {0.0, 0.5, -1.3, 2.9}) {
    lowpair::VecX q(n);
    for (int i = 0; i < n; ++i) {
      const auto& r = ranges[static_cast<size_t>(i)];
      q[i] = r ? std::min(std::max(c, (*r)[0]), (*r)[1]) : c;
    }
    out.push_back(q);
  }
  for (const int which : {0, 1, 2}) {  // lo, hi, mid (no range: 1, -1, 0.25)
    lowpair::VecX q(n);
    for (int i = 0; i < n; ++i) {
      const auto& r = ranges[static_cast<size_t>(i)];
      if (!r) q[i] = which == 0 ? 1.0 : which == 1 ? -1.0 : 0.25;
      else q[i] = which == 0 ? (*r)[0] : which == 1 ? (*r)[1] : (*r)[0] / 2 + (*r)[1] / 2;
    }
    out.push_back(q);
  }
  return out;
}

template <class JointList>
std::vector<std::optional<std::array<double, 2>>> rangesOf(const JointList& joints) {
  std::vector<std::optional<std::array<double, 2>>> r;
  for (const auto& j : joints) r.push_back(j.range);
  return r;
}

/// FK of `model` finite at every fixed configuration.
void checkPoeModel(const lowpair::PoeModel& model);
/// poeToDh (and the FK check of the table) finite; false when there is no table (no joints, or one
/// beyond the magnitude limits, which poeToDh may reject only when the offsets can move frames that far).
bool checkConversion(const lowpair::PoeModel& model);

}  // namespace lowpair_fuzz
