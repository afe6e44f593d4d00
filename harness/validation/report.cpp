// `lowpair validate --report DIR` (report.hpp writeReport): the folder, written whole or not at all, and
// what its files share (report_parts.hpp).
#include "validation/report.hpp"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>

#include <unistd.h>

#include "io/output.hpp"
#include "validation/report_parts.hpp"

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below

namespace fs = std::filesystem;

namespace detail {

// A file-name stem from a user string: [A-Za-z0-9_-] only, at most kMaxStem characters (file systems
// allow 255 bytes per name); a longer name keeps its start and gets a hash of the whole, so names stay distinct.
std::string safe(const std::string& name) {
  constexpr size_t kMaxStem = 80;
  std::string s = name;
  for (char& ch : s) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
  }
  if (s.size() > kMaxStem) {
    char hash[20];
    std::snprintf(hash, sizeof hash, "_%016zx", std::hash<std::string>{}(name));
    s = s.substr(0, kMaxStem - 17) + hash;
  }
  return s;
}

// Writes `text` to `path` and checks it reached the file (a full disk, a file-size limit, a vanished
// folder): a report is complete or not written at all.
void writeChecked(const fs::path& path, const std::string& text) {
  errno = 0;
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    const int error = errno;
    throw std::runtime_error(path.filename().string() + ": cannot write" +
                             (error ? std::string(" (") + std::strerror(error) + ")" : std::string()));
  }
}

// "1 sample in 500 (20000 of 10000000)" when the picture shows a subsample (ComparisonResult::plot_stride)
std::string plotted(const ScenarioResult& r) {
  const long long stride = r.comparisons.empty() ? 1 : r.comparisons.front().plot_stride;
  if (stride <= 1) return "every sample";
  const size_t points = r.comparisons.front().rotation_errors.size();
  return "1 sample in " + std::to_string(stride) + " (" + std::to_string(points) + " of " +
         std::to_string(r.samples) + ")";
}

bool hasResiduals(const CalibrationCaseResult& c) { return c.report && !c.report->result.residuals.empty(); }

}  // namespace detail

using namespace detail;

void writeReport(const std::string& dir, const std::vector<ScenarioResult>& results, const RunOptions& options) {
  // build everything in a sibling temporary folder, then move the files in
  const fs::path target = fs::absolute(dir);
  // only a folder (new or existing) takes a report, and only regular files in it are replaced: a device,
  // FIFO or socket given as the folder or found under a report file's name is never replaced by a file
  std::error_code status_error;
  const fs::file_status target_status = fs::status(target, status_error);
  if (fs::exists(target_status) && !fs::is_directory(target_status)) {
    throw std::runtime_error(dir + ": report not written: not a folder");
  }
  const fs::path parent = target.parent_path();
  fs::create_directories(parent);
  const fs::path tmp = parent / (target.filename().string() + ".partial-" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  try {
    writeChecked(tmp / "report.json", jsonText(validationJson(results, options)) + "\n");
    for (const auto& r : results) plots(tmp, r);
    writeChecked(tmp / "summary.md", summaryMarkdown(results));
    fs::create_directories(target);
    for (const auto& entry : fs::directory_iterator(tmp)) {
      const fs::file_status existing = fs::symlink_status(target / entry.path().filename(), status_error);
      if (fs::exists(existing) && !fs::is_regular_file(existing)) {
        throw std::runtime_error((target / entry.path().filename()).string() +
                                 " exists and is not a regular file: not replaced");
      }
    }
    for (const auto& entry : fs::directory_iterator(tmp)) {
      fs::rename(entry.path(), target / entry.path().filename());
    }
    fs::remove_all(tmp);
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    throw std::runtime_error(dir + ": report not written: " + e.what());
  }
}

}  // namespace lowpair::validation
