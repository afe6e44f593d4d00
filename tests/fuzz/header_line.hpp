#pragma once
// The URDF and MuJoCo targets' input: an optional first line `TIP [BASE]` (when the input does not start
// with '<'), then the model file. Without it the tip is "tool" (the shipped models' tip) and the base "".
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

namespace lowpair_fuzz {

struct HeaderLine {
  std::string tip = "tool", base;
  const uint8_t* data = nullptr;  ///< the model file
  size_t size = 0;
};

inline HeaderLine splitHeaderLine(const uint8_t* data, size_t size) {
  HeaderLine h{"tool", "", data, size};
  if (size == 0 || data[0] == '<') return h;
  size_t eol = 0;
  while (eol < size && eol < 256 && data[eol] != '\n') ++eol;
  if (eol == size || data[eol] != '\n') return h;
  std::istringstream line(std::string(reinterpret_cast<const char*>(data), eol));
  std::string tip, base;
  line >> tip >> base;
  h.tip = tip;
  h.base = base;
  h.data = data + eol + 1;
  h.size = size - eol - 1;
  return h;
}

}  // namespace lowpair_fuzz
