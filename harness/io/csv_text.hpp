#pragma once
/// @file csv_text.hpp
/// The text rules every CSV lowpair reads shares (the measurement CSV, measurements.hpp; the joint-vector
/// and target tables of `fk --q-file`, `simulate --q-file`, `ik` and `compensate`, joint_table.hpp): bounded
/// lines, comments, fields, `# length_unit: U`, decimal numbers. Every error is a RobotFileError
/// `FILE:LINE: what`.

#include <istream>
#include <string>
#include <vector>

#include "io/robot_file.hpp"

namespace lowpair::io {

/// Lines of at most this many bytes (without the line end).
constexpr size_t kMaxCsvLineBytes = 65536;

/// Lines of a stream without their LF or CRLF, at most kMaxCsvLineBytes each, read through a fixed buffer (a
/// file without line ends never grows memory); a UTF-8 byte order mark at the start is skipped.
class CsvLineReader {
 public:
  CsvLineReader(std::istream& in, std::string path);
  /// The next line (false at the end of the file). @throws RobotFileError for a longer line or a read error
  bool next(std::string& line);
  /// The 1-based number of the line `next` returned last.
  long long number() const { return number_; }

 private:
  RobotFileError tooLong(long long number) const;
  std::istream& in_;
  std::string path_;
  std::vector<char> buffer_;
  long long number_ = 0;
};

/// A blank line, or one whose first character other than spaces and tabs is `#`.
bool isCsvComment(const std::string& line);

/// Splits at commas; each field trimmed of spaces and tabs.
void splitCsvFields(const std::string& line, std::vector<std::string>& fields);

/// A `# length_unit: U` comment sets `unit` (the first; a second must agree); any other comment is ignored.
/// @return the problem ("" when none): a value that is not a unit label, or one that contradicts `unit`
std::string readLengthUnitComment(const std::string& line, std::string& unit);

/// A whole token as a finite decimal number of magnitude at most kMaxMagnitude (strtod's hexadecimal floats,
/// which no writer of these files produces, are refused). @return the problem ("" when none)
std::string parseCsvNumber(const std::string& token, double& x);

}  // namespace lowpair::io
