#pragma once
// The CSVs the commands write, parsed for the CLI tests (simulate's measurement CSVs, fk's, ik's and
// compensate's outputs): comment lines, the header, and every data row, as text and as numbers.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
#include <vector>

namespace csv_test {

using Vec = std::array<double, 3>;
using Quaternion = std::array<double, 4>;  // w, x, y, z

inline std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

// `text` (a CSV lowpair writes) with its columns rearranged: column k of the result is the source column named
// columns[k].first (empty: a column holding "operator-7" on every row), headed columns[k].second.
inline std::string rearranged(const std::string& text, const std::vector<std::pair<std::string, std::string>>& columns) {
  std::istringstream in(text);
  std::string out, line;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out += line + "\n";
      continue;
    }
    const std::vector<std::string> fields = split(line);
    if (header.empty()) header = fields;
    for (size_t k = 0; k < columns.size(); ++k) {
      const auto it = std::find(header.begin(), header.end(), columns[k].first);
      const std::string value = columns[k].first.empty() ? "operator-7" : fields[static_cast<size_t>(it - header.begin())];
      out += (k ? "," : "") + (fields == header ? columns[k].second : value);
    }
    out += "\n";
  }
  return out;
}

// `text` with every occurrence of `from` replaced by `to` (a file's path in a command's output).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

// One data row of a measurement CSV (pose, position or target measurements), with its file line.
struct Row {
  std::vector<double> q;
  std::string target;
  Vec p{};
  Quaternion quaternion{1, 0, 0, 0};
  std::string text;
  int line = 0;
};

// A CSV as text: comments, header, the fields of every data row.
struct Table {
  std::vector<std::string> comments, header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;  ///< the file line of each row
  size_t column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<size_t>(it - header.begin());
  }
  double number(size_t row, const std::string& name) const { return std::stod(rows[row][column(name)]); }
};

inline Table parseTable(const std::string& text) {
  Table table;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("#", 0) == 0) {
      table.comments.push_back(line);
    } else if (table.header.empty()) {
      table.header = split(line);
    } else {
      table.rows.push_back(split(line));
      table.lines.push_back(number);
      EXPECT_EQ(table.rows.back().size(), table.header.size()) << line;
    }
  }
  return table;
}

// A measurement CSV: q1..qn, then target (target measurements), x, y, z and the quaternion (poses).
struct Csv {
  std::vector<std::string> comments, header;
  std::vector<Row> rows;
};

inline Csv parseCsv(const std::string& text) {
  const Table table = parseTable(text);
  Csv csv{table.comments, table.header, {}};
  const bool pose = !csv.header.empty() && csv.header.back() == "qz";
  const auto target = std::find(csv.header.begin(), csv.header.end(), "target");
  const bool targets = target != csv.header.end();
  const size_t n = targets ? static_cast<size_t>(target - csv.header.begin()) : csv.header.size() - (pose ? 7 : 3);
  std::istringstream lines(text);
  for (size_t k = 0; k < table.rows.size(); ++k) {
    const auto& fields = table.rows[k];
    if (fields.size() != csv.header.size()) continue;
    Row row;
    for (size_t i = 0; i < fields.size(); ++i) row.text += (i ? "," : "") + fields[i];
    row.line = table.lines[k];
    for (size_t i = 0; i < n; ++i) row.q.push_back(std::stod(fields[i]));
    const size_t p = targets ? n + 1 : n;
    if (targets) row.target = fields[n];
    for (size_t i = 0; i < 3; ++i) row.p[i] = std::stod(fields[p + i]);
    if (pose) {
      for (size_t i = 0; i < 4; ++i) row.quaternion[i] = std::stod(fields[p + 3 + i]);
    }
    csv.rows.push_back(row);
  }
  return csv;
}

}  // namespace csv_test
