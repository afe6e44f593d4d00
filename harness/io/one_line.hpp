#pragma once
/// @file one_line.hpp
/// The error contract's one line: every run of control characters (a newline in a file name, a YAML key or
/// a --tip value) folded into one space, whatever the input held. Header-only: the CLI, the Python module
/// and the benchmark binary (which links none of the rooms) all use it.

#include <string>

namespace lowpair::io {

inline std::string oneLine(const std::string& message) {
  std::string line;
  for (const char ch : message) {
    const bool control = static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f;
    if (!control) {
      line += ch;
    } else if (line.empty() || line.back() != ' ') {
      line += ' ';
    }
  }
  return line;
}

}  // namespace lowpair::io
