#pragma once
/// @file yaml_reader.hpp
/// Reading the project's YAML files (robot files, scenarios) with errors that read
/// `FILE: line N: what is wrong`: every failure is a RobotFileError.

#include <yaml-cpp/yaml.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "lowpair/types.hpp"
#include "io/robot_file.hpp"

namespace lowpair::io {

// An error at a node: "FILE: line N: what".
[[noreturn]] inline void yamlError(const std::string& path, const YAML::Node& node, const std::string& what) {
  std::ostringstream msg;
  msg << path << ": ";
  if (node.IsDefined() && node.Mark().line >= 0) msg << "line " << node.Mark().line + 1 << ": ";
  msg << what;
  throw RobotFileError(msg.str());
}

/// Typed access to a YAML document of file `path`, failing with the node's line.
class YamlReader {
 public:
  explicit YamlReader(std::string path) : path_(std::move(path)) {}

  void allowOnly(const YAML::Node& map, const std::string& where, const std::set<std::string>& keys) const {
    if (!map.IsMap()) yamlError(path_, map, where + " must be a mapping");
    std::set<std::string> seen;
    for (const auto& kv : map) {
      // a key must be a plain scalar (yaml-cpp's own message for a sequence key is not one line with FILE)
      if (!kv.first.IsScalar()) yamlError(path_, kv.first, "a key in " + where + " must be a plain name");
      const std::string key = kv.first.Scalar();
      // YAML forbids duplicate keys; yaml-cpp keeps the first silently
      if (!seen.insert(key).second) yamlError(path_, kv.first, "duplicate key '" + key + "' in " + where);
      if (!keys.count(key)) {
        std::string allowed;
        for (const auto& k : keys) allowed += (allowed.empty() ? "" : ", ") + k;
        yamlError(path_, kv.first, "unknown key '" + key + "' in " + where + " (allowed: " + allowed + ")");
      }
    }
  }

  double number(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) yamlError(path_, node, what + " must be a number");
    double x = 0.0;
    try {
      x = node.as<double>();
    } catch (const YAML::Exception&) {
      yamlError(path_, node, what + " must be a number, got '" + node.Scalar() + "'");
    }
    if (!std::isfinite(x)) yamlError(path_, node, what + " is not finite ('" + node.Scalar() + "')");
    return x;
  }

  double numberOr(const YAML::Node& map, const char* key, double fallback, const std::string& where) const {
    const YAML::Node node = map[key];
    return node.IsDefined() && !node.IsNull() ? number(node, where + "." + key) : fallback;
  }

  std::vector<double> vector(const YAML::Node& node, size_t size, const std::string& what) const {
    if (!node.IsSequence()) yamlError(path_, node, what + " must be a list of " + std::to_string(size) + " numbers");
    if (node.size() != size) {
      yamlError(path_, node, what + " must have " + std::to_string(size) + " entries, got " + std::to_string(node.size()));
    }
    std::vector<double> out;
    for (size_t i = 0; i < size; ++i) out.push_back(number(node[i], what + "[" + std::to_string(i) + "]"));
    return out;
  }

  std::string string(const YAML::Node& node, const std::string& what) const {
    if (!node.IsScalar()) yamlError(path_, node, what + " must be a string");
    return node.Scalar();
  }

  /// `true` or `false` (YAML 1.2's spellings only: a `yes` or a `1` is refused rather than guessed).
  bool boolean(const YAML::Node& node, const std::string& what) const {
    const std::string b = node.IsScalar() ? node.Scalar() : std::string();
    if (b != "true" && b != "false") yamlError(path_, node, what + " must be true or false");
    return b == "true";
  }

  std::optional<JointType> type(const YAML::Node& node, const std::string& what) const {
    if (!node.IsDefined() || node.IsNull()) return std::nullopt;
    const std::string t = string(node, what);
    if (t == "revolute") return JointType::Revolute;
    if (t == "prismatic") return JointType::Prismatic;
    if (t == "helical") return JointType::Helical;
    yamlError(path_, node, what + " must be revolute, prismatic or helical, got '" + t + "'");
  }

  std::optional<std::array<double, 2>> range(const YAML::Node& node, const std::string& what, double factor) const {
    if (!node.IsDefined() || node.IsNull()) return std::nullopt;
    const auto r = vector(node, 2, what);
    if (r[0] > r[1]) yamlError(path_, node, what + " must be [lo, hi] with lo <= hi");
    return std::array<double, 2>{r[0] * factor, r[1] * factor};
  }

  /// A whole number in [lo, hi].
  long long integer(const YAML::Node& node, const std::string& what, long long lo, long long hi) const {
    const auto fail = [&] {
      yamlError(path_, node, what + " must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    };
    // digits are read exactly (a seed of 2^53 + 1 must not round to 2^53 and pass); 1e3 and 10.0 as numbers
    const std::string text = node.IsScalar() ? node.Scalar() : std::string();
    const size_t first = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
    if (first < text.size() && text.find_first_not_of("0123456789", first) == std::string::npos) {
      errno = 0;
      char* end = nullptr;
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (errno == ERANGE || *end != '\0' || v < lo || v > hi) fail();
      return v;
    }
    const double x = number(node, what);
    if (x != std::floor(x) || x < static_cast<double>(lo) || x > static_cast<double>(hi)) fail();
    return static_cast<long long>(x);
  }

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};


/// Loads a YAML file: a missing file or a syntax error (with its line) is a RobotFileError.
YAML::Node loadYamlFile(const std::string& path);

}  // namespace lowpair::io
