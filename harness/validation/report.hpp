#pragma once
/// @file report.hpp
/// `lowpair validate` output: the summary table, the JSON document and the report folder (JSON,
/// Markdown summary, gnuplot pictures). Nothing is written to the report folder unless the run completed.

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "validation/validate.hpp"

namespace lowpair::validation {

nlohmann::json validationJson(const std::vector<ScenarioResult>& results, const RunOptions& options);
void printValidationTable(std::ostream& out, const std::vector<ScenarioResult>& results);
/// Writes report.json, summary.md and per scenario <name>_errors.png and <name>_histogram.png.
/// @throws std::runtime_error when gnuplot fails or the folder cannot be written
void writeReport(const std::string& dir, const std::vector<ScenarioResult>& results, const RunOptions& options);

}  // namespace lowpair::validation
