#pragma once
// Helpers of export_test.cpp and robot_file_targets_test.cpp: a scratch folder for the files they write.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace export_helpers {

namespace fs = std::filesystem;

// A scratch folder for the files written, removed at exit.
class Scratch {
 public:
  Scratch() {
    std::string pattern = (fs::temp_directory_path() / "lowpair_export_test_XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot create a scratch folder");
    path_ = pattern;
  }
  ~Scratch() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (fs::path(path_) / name).string();
    std::ofstream(path) << text;
    return path;
  }

 private:
  std::string path_;
};

inline const Scratch& scratch() {
  static const Scratch s;
  return s;
}

}  // namespace export_helpers
