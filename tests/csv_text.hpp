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
