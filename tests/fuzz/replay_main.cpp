// A standalone driver for the fuzz targets without libFuzzer (the normal g++ build, `make check`): feeds
// every file given, and every regular file in every directory given (not recursive, sorted), to
// LLVMFuzzerTestOneInput. A missing path is skipped (an empty regressions folder is not committed).
// A target that finds a violation aborts, which fails the test.
//
// Fixed mutation run (make fuzz-ci, CI): with LOWPAIR_FUZZ_MUTANTS=N each input is also fed as N mutants,
// made by a seeded generator (LOWPAIR_FUZZ_SEED, default 1) from the input alone: bit flips, bytes set to
// syntax characters, inserted, deleted and duplicated ranges, numbers replaced by extreme ones, splices of
// the next input. Mutant m of input i depends only on (seed, i, m, the inputs): the same commit feeds the
// same bytes every run, whatever the machine, so its verdict never changes (libFuzzer's coverage-guided
// runs do not repeat: make fuzz is for people). LOWPAIR_FUZZ_LAST=PREFIX: each mutant is written to
// PREFIX.<this program's name> before it runs, so a crash leaves its reproducer.
#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxMutantBytes = size_t{1} << 19;  // 512 KiB, make fuzz's -max_len for XML

unsigned long long mix(unsigned long long x) {  // splitmix64
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// One to four edits of `bytes`; `other` is the next input, for splices.
std::vector<char> mutate(std::vector<char> bytes, const std::vector<char>& other, std::mt19937_64& rng) {
  static const char kSyntax[] = {'<', '>', '/', '"', '\'', '=', ':', ',', '-', '[', ']', '{', '}', '#', '\n',
                                 ' ', '0', '9', '.', 'e', '\0', '\xff', '&', ';'};
  static const char* const kNumbers[] = {"0", "-0", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf",
                                         "99999999999999999999", "0x1.8p+4", "1e100", "1e101", "3.141592653589793",
                                         "-1", "2147483648", "9007199254740993", "1e-16", ".5", "1."};
  auto pick = [&rng](size_t n) { return n == 0 ? size_t{0} : static_cast<size_t>(rng() % n); };
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    const size_t at = pick(bytes.size() + 1);
    switch (rng() % 7) {
      case 0:  // flip a bit
        if (!bytes.empty()) bytes[pick(bytes.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:  // a syntax character
        if (!bytes.empty()) bytes[pick(bytes.size())] = kSyntax[pick(sizeof kSyntax)];
        break;
      case 2: {  // insert random bytes
        const size_t n = 1 + pick(16);
        for (size_t k = 0; k < n; ++k) bytes.insert(bytes.begin() + static_cast<long>(at), static_cast<char>(rng()));
        break;
      }
      case 3: {  // delete a range
        const size_t n = std::min(bytes.size() - std::min(at, bytes.size()), 1 + pick(64));
        bytes.erase(bytes.begin() + static_cast<long>(at), bytes.begin() + static_cast<long>(at + n));
        break;
      }
      case 4: {  // duplicate a range (nesting, repeated elements)
        if (bytes.empty()) break;
        const size_t from = pick(bytes.size()), n = std::min(bytes.size() - from, 1 + pick(256));
        const std::vector<char> chunk(bytes.begin() + static_cast<long>(from), bytes.begin() + static_cast<long>(from + n));
        const size_t copies = 1 + pick(rng() % 8 == 0 ? 200 : 4);
        for (size_t c = 0; c < copies && bytes.size() + chunk.size() <= kMaxMutantBytes; ++c) {
          bytes.insert(bytes.begin() + static_cast<long>(at), chunk.begin(), chunk.end());
        }
        break;
      }
      case 5: {  // replace the number at or after `at` by an extreme one
        size_t b = at;
        while (b < bytes.size() && !(bytes[b] >= '0' && bytes[b] <= '9')) ++b;
        size_t end = b;
        while (end < bytes.size() && (std::isalnum(static_cast<unsigned char>(bytes[end])) || bytes[end] == '.' ||
                                      bytes[end] == '-' || bytes[end] == '+')) {
          ++end;
        }
        const std::string number = kNumbers[pick(sizeof kNumbers / sizeof kNumbers[0])];
        bytes.erase(bytes.begin() + static_cast<long>(b), bytes.begin() + static_cast<long>(end));
        bytes.insert(bytes.begin() + static_cast<long>(b), number.begin(), number.end());
        break;
      }
      default: {  // splice a range of the next input
        if (other.empty()) break;
        const size_t from = pick(other.size()), n = std::min(other.size() - from, 1 + pick(512));
        bytes.insert(bytes.begin() + static_cast<long>(at), other.begin() + static_cast<long>(from),
                     other.begin() + static_cast<long>(from + n));
        break;
      }
    }
    if (bytes.size() > kMaxMutantBytes) bytes.resize(kMaxMutantBytes);
  }
  return bytes;
}

std::vector<char> readBytes(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

int main(int argc, char** argv) {
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const fs::path p = argv[i];
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      std::vector<fs::path> in_dir;
      for (const auto& e : fs::directory_iterator(p))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.') in_dir.push_back(e.path());
      std::sort(in_dir.begin(), in_dir.end());
      files.insert(files.end(), in_dir.begin(), in_dir.end());
    } else if (fs::is_regular_file(p, ec)) {
      files.push_back(p);
    }
  }
  const char* mutants_env = std::getenv("LOWPAIR_FUZZ_MUTANTS");
  const char* seed_env = std::getenv("LOWPAIR_FUZZ_SEED");
  const char* last_prefix = std::getenv("LOWPAIR_FUZZ_LAST");
  // LOWPAIR_FUZZ_SHARD=K/N: only the inputs i with i % N == K (and their mutants, which depend on i, not on the
  // shard): the N shards together replay exactly what one run does (tests/fuzz/CMakeLists.txt)
  const char* shard_env = std::getenv("LOWPAIR_FUZZ_SHARD");
  unsigned long shard = 0, shards = 1;
  if (shard_env && (std::sscanf(shard_env, "%lu/%lu", &shard, &shards) != 2 || shards == 0 || shard >= shards)) {
    std::fprintf(stderr, "LOWPAIR_FUZZ_SHARD: expected K/N with 0 <= K < N, got '%s'\n", shard_env);
    return 2;
  }
  const std::string last = last_prefix ? std::string(last_prefix) + "." + fs::path(argv[0]).filename().string() +
                                             (shards > 1 ? ".shard" + std::to_string(shard) : std::string())
                                       : "";
  const long long mutants = mutants_env ? std::atoll(mutants_env) : 0;
  const unsigned long long seed = seed_env ? std::strtoull(seed_env, nullptr, 10) : 1;
  long long runs = 0;
  for (size_t i = 0; i < files.size(); ++i) {
    if (i % shards != shard) continue;
    std::fprintf(stderr, "replay %s\n", files[i].c_str());
    const std::vector<char> bytes = readBytes(files[i]);
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    ++runs;
    if (mutants <= 0) continue;
    const std::vector<char> other = readBytes(files[(i + 1) % files.size()]);
    for (long long m = 0; m < mutants; ++m) {
      std::mt19937_64 rng(mix(mix(seed) ^ mix(i + 1) ^ mix(static_cast<unsigned long long>(m) << 20)));
      const std::vector<char> mutant = mutate(bytes, other, rng);
      if (!last.empty()) {
        std::ofstream out(last, std::ios::binary | std::ios::trunc);
        out.write(mutant.data(), static_cast<std::streamsize>(mutant.size()));
      }
      LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(mutant.data()), mutant.size());
      ++runs;
    }
  }
  std::printf("replayed %zu inputs%s (%lld runs; shard %lu of %lu)\n", files.size(), mutants > 0 ? " and their mutants" : "",
              runs, shard + 1, shards);
  return 0;
}
