#include "io/csv_text.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

#include "io/measurements.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::io {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }

}  // namespace

CsvLineReader::CsvLineReader(std::istream& in, std::string path)
    : in_(in), path_(std::move(path)), buffer_(kMaxCsvLineBytes + 2) {}  // room for '\r'

bool CsvLineReader::next(std::string& line) {
  in_.getline(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  const auto got = static_cast<size_t>(in_.gcount());
  if (in_.bad()) throw RobotFileError(path_ + ": cannot read file");
  if (in_.eof()) {
    if (got == 0) return false;
    line.assign(buffer_.data(), got);  // the last line, without a line end
  } else if (in_.fail()) {             // the buffer filled before a line end
    throw tooLong(number_ + 1);
  } else {
    line.assign(buffer_.data(), got - 1);  // gcount counts the '\n'
  }
  ++number_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.size() > kMaxCsvLineBytes) throw tooLong(number_);
  if (number_ == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 byte order mark
  return true;
}

RobotFileError CsvLineReader::tooLong(long long number) const {
  return RobotFileError(path_ + ":" + std::to_string(number) + ": line longer than " + std::to_string(kMaxCsvLineBytes) +
                        " bytes");
}

bool isCsvComment(const std::string& line) {
  for (char c : line) {
    if (!isBlank(c)) return c == '#';
  }
  return true;  // blank
}

void splitCsvFields(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  size_t begin = 0;
  while (true) {
    const size_t comma = std::min(line.find(',', begin), line.size());
    size_t a = begin, b = comma;
    while (a < b && isBlank(line[a])) ++a;
    while (b > a && isBlank(line[b - 1])) --b;
    fields.emplace_back(line, a, b - a);
    if (comma == line.size()) return;
    begin = comma + 1;
  }
}

std::string readLengthUnitComment(const std::string& line, std::string& unit) {
  const size_t hash = line.find('#');
  if (hash == std::string::npos) return "";  // blank
  const size_t k = line.find_first_not_of(" \t", hash + 1);
  static const std::string key = "length_unit:";
  if (k == std::string::npos || line.compare(k, key.size(), key) != 0) return "";
  const size_t begin = line.find_first_not_of(" \t", k + key.size());
  const size_t end = begin == std::string::npos ? begin : line.find_last_not_of(" \t") + 1;  // (no '\r': the reader)
  const std::string value = begin == std::string::npos ? "" : line.substr(begin, end - begin);
  if (!isUnitLabel(value)) {
    return "length_unit " + quotedFileText(value) + " is not a unit label (one token of 1-16 printable ASCII characters)";
  }
  if (!unit.empty() && unit != value) return "length_unit " + quotedFileText(value) + " after length_unit " + quotedFileText(unit);
  unit = value;
  return "";
}

std::string parseCsvNumber(const std::string& token, double& x) {
  char* end = nullptr;
  // (a token starting with other white space than the trimmed spaces and tabs is not a number: strtod would
  // skip it)
  x = token.empty() || std::isspace(static_cast<unsigned char>(token[0])) ? 0.0 : std::strtod(token.c_str(), &end);
  if (token.empty() || end != token.c_str() + token.size()) return quotedFileText(token) + " is not a number";
  if (token.find_first_of("xX") != std::string::npos) return quotedFileText(token) + " is not a decimal number";
  if (!std::isfinite(x)) return quotedFileText(token) + " is not a finite number";
  if (std::abs(x) > kMaxMagnitude) return quotedFileText(token) + " is above 1e100 in magnitude (kMaxMagnitude)";
  return "";
}

}  // namespace lowpair::io
