#pragma once
/// @file report_parts.hpp
/// What the files of `lowpair validate`'s report (report.hpp) share; internal to the validation room:
/// report.cpp writes the folder, report_json.cpp the JSON, report_table.cpp the summary table,
/// report_markdown.cpp summary.md and report_plots.cpp the gnuplot pictures.

#include <filesystem>
#include <string>
#include <vector>

#include "validation/validate.hpp"

namespace lowpair::validation::detail {

/// A file-name stem from a user string: [A-Za-z0-9_-] only, at most 80 characters (report.cpp).
std::string safe(const std::string& name);
/// Writes `text` to `path` and checks it reached the file. @throws std::runtime_error (report.cpp)
void writeChecked(const std::filesystem::path& path, const std::string& text);
/// "every sample", or "1 sample in 500 (20000 of 10000000)" for a subsampled error picture (report.cpp).
std::string plotted(const ScenarioResult& r);
/// Whether the case's calibration has residuals to draw and list (report.cpp).
bool hasResiduals(const CalibrationCaseResult& c);

/// summary.md: the comparison table, then per scenario its pictures and calibration cases (report_markdown.cpp).
std::string summaryMarkdown(const std::vector<ScenarioResult>& results);
/// Writes the scenario's data files, gnuplot script and pictures into `dir` and checks every picture is a
/// complete PNG. @throws std::runtime_error when gnuplot fails (report_plots.cpp)
void plots(const std::filesystem::path& dir, const ScenarioResult& r);

}  // namespace lowpair::validation::detail
