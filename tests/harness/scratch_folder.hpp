#pragma once
// A scratch folder of this process for the files a test writes, removed at exit: export_test.cpp and
// robot_file_targets_test.cpp write through export_helpers::scratch(), measurements_test.cpp and
// atomic_file_test.cpp name paths in measurements_helpers::scratch().
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace harness_test {

// mkdtemp's template: `prefix` followed by a unique suffix, in the temporary folder.
class Scratch {
 public:
  explicit Scratch(const std::string& prefix) {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a scratch folder");
    path_ = pattern;
  }
  ~Scratch() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const std::string& path() const { return path_; }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (std::filesystem::path(path_) / name).string();
    std::ofstream(path) << text;
    return path;
  }

 private:
  std::string path_;
};

}  // namespace harness_test

namespace export_helpers {

inline const harness_test::Scratch& scratch() {
  static const harness_test::Scratch s("lowpair_export_test");
  return s;
}

}  // namespace export_helpers

namespace measurements_helpers {

// A folder of this process, removed at exit.
inline const std::string& scratch() {
  static const harness_test::Scratch dir("lowpair_measurements");
  return dir.path();
}

}  // namespace measurements_helpers
