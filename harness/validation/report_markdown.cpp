// summary.md of `lowpair validate --report` (report.hpp writeReport): the comparison table, then per
// scenario its pictures and calibration cases in words.
#include <algorithm>
#include <cstdio>
#include <sstream>

#include "commands/calibration_output.hpp"
#include "io/output.hpp"
#include "lowpair/se3.hpp"
#include "validation/report_parts.hpp"

namespace lowpair::validation::detail {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::commands;

namespace {

// A user string (a scenario or case name, a path) as Markdown text that shows it verbatim: every ASCII
// punctuation character CommonMark may read as markup is backslash-escaped, and a line break becomes a
// space (it could start a heading, a list or a code fence on the next line).
std::string markdownText(const std::string& text) {
  static const std::string kPunctuation = "\\`*_{}[]()<>#+-.!|~\"'&=:;$%^?@,/";
  std::string out;
  for (const char ch : text) {
    if (ch == '\n' || ch == '\r' || ch == '\t') {
      out += ' ';
    } else if (kPunctuation.find(ch) != std::string::npos) {
      out += '\\';
      out += ch;
    } else {
      out += ch;
    }
  }
  return out;
}

// A fenced code block holding `text` verbatim: the fence is longer than any run of backticks in it.
std::string markdownCode(const std::string& text) {
  size_t longest = 0, run = 0;
  for (const char ch : text) {
    run = ch == '`' ? run + 1 : 0;
    longest = std::max(longest, run);
  }
  const std::string fence(std::max<size_t>(3, longest + 1), '`');
  return fence + "\n" + text + (text.empty() || text.back() == '\n' ? "" : "\n") + fence + "\n";
}

// "17 (pose 6, smr_b)": a fitting measurement, 1-based, with its pose and target when there are targets
std::string measurementLabel(const CalibrationCaseResult& c, size_t k) {
  const io::MeasurementFile& fit = c.report->fit;
  std::string label = std::to_string(k + 1);
  if (fit.measure == Measure::Targets && !fit.target_names.empty() && k < fit.measurements.size()) {
    const int t = fit.measurements[k].target;
    label += " (pose " + std::to_string(k / fit.target_names.size() + 1) + ", " +
             (t >= 0 ? fit.target_names[static_cast<size_t>(t)] : std::string("?")) + ")";
  }
  if (k < fit.lines.size()) label += " line " + std::to_string(fit.lines[k]);
  return label;
}

// The case's residuals in words: which measurements were flagged, the blunders found and missed, and a
// table of the worst five.
std::string residualSummary(const CalibrationCaseResult& c) {
  if (!hasResiduals(c)) return "";
  const CalibrationResult& result = c.report->result;
  std::ostringstream md;
  std::vector<size_t> flagged;
  for (size_t k = 0; k < result.residuals.size(); ++k) {
    if (result.residuals[k].outlier) flagged.push_back(k);
  }
  auto list = [&](const std::vector<size_t>& rows) {
    constexpr size_t kMaxListed = 20;
    std::string text;
    for (size_t i = 0; i < rows.size() && i < kMaxListed; ++i) text += (i ? ", " : "") + measurementLabel(c, rows[i]);
    if (rows.size() > kMaxListed) text += ", ... (" + std::to_string(rows.size()) + " in all)";
    return markdownText(text);
  };
  md << "Fit: " << lossName(result.loss) << " loss, " << flagged.size() << " of " << result.residuals.size()
     << " measurements flagged as outliers (normalized residual above " << CalibrationOptions{}.outlier_threshold
     << ")" << (flagged.empty() ? "" : ": " + list(flagged)) << ". Verdict: "
     << (result.accepted ? std::string("accepted") : "rejected (" + markdownText(result.reason) + ")") << ".\n\n";
  if (!c.blunders.empty()) {
    const std::string unit = c.report->nominal.length_unit.empty() ? "length units" : c.report->nominal.length_unit;
    md << "Blunders (" << c.config.blunder_size << " " << unit << "): " << c.blunders.size() - c.missed_blunders.size()
       << " of " << c.blunders.size() << " flagged";
    if (!c.missed_blunders.empty()) md << "; **missed**: " << list(c.missed_blunders);
    if (!c.false_outliers.empty()) md << "; **flagged without a blunder**: " << list(c.false_outliers);
    md << ".\n\n";
  }
  const std::vector<size_t> order = worstMeasurements(result, kWorstMeasurementsShown);
  md << "| worst | measurement | position error | normalized | weight | flagged | blunder |\n|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < order.size(); ++i) {
    const size_t k = order[i];
    const MeasurementResidual& x = result.residuals[k];
    char numbers[120];
    std::snprintf(numbers, sizeof numbers, "%.3g | %.3g | %.3g", x.position, x.normalized, x.weight);
    md << "| " << i + 1 << " | " << markdownText(measurementLabel(c, k)) << " | " << numbers << " | "
       << (x.outlier ? "yes" : "no") << " | "
       << (std::binary_search(c.blunders.begin(), c.blunders.end(), k) ? "yes" : "no") << " |\n";
  }
  return md.str() + "\n";
}

// The plan in a sentence: the chosen samples and the criterion against the first N samples'.
std::string planSummary(const CalibrationCaseResult& c) {
  const CasePlanResult& p = *c.plan;
  std::ostringstream md;
  md << "Plan: " << c.config.poses << " poses chosen (criterion " << planCriterionName(p.plan.criterion)
     << ", lowpair plan's greedy selection and " << p.plan.swaps << " exchange(s)) among the candidates, samples 0 to "
     << c.config.plan->candidates - 1 << " of the case's stream; validation samples " << c.config.plan->candidates
     << " to " << c.config.plan->candidates + c.config.validation_poses - 1 << ". log det of the information "
     << fixed(p.plan.value.log_det, 4) << " (O1 " << p.plan.value.o1 << ") against " << fixed(p.first.log_det, 4)
     << " (O1 " << p.first.o1 << ") for samples 0 to " << c.config.poses - 1 << "; rank " << p.plan.rank.rank << " of "
     << p.plan.expected.total() << "; " << fixed(p.seconds, 3) << " s. Samples chosen: ";
  for (size_t i = 0; i < p.plan.indices.size(); ++i) md << (i ? ", " : "") << p.plan.indices[i];
  md << ".\n\n";
  return md.str();
}

// The compensation table: before and after, and the rows not ok.
std::string compensationSummary(const CalibrationCaseResult& c) {
  const CompensationResult& k = *c.compensation;
  const std::string unit = c.report && !c.report->nominal.length_unit.empty() ? c.report->nominal.length_unit : "length";
  const bool rotation = k.measure == Measure::Pose;
  std::ostringstream md;
  md << "Compensation (" << (k.point_name.empty() ? std::string(measureName(k.measure)) : "target " + markdownText(k.point_name))
     << "): the " << k.count() << " validation joint vectors q as a nominal program; MuJoCo's tool against the "
     << "nominal's forward kinematics at q, commanding q (before) and the compensated q' (after, rows whose status is "
     << "ok); acceptance: RMS position after <= " << c.config.compensation->tolerance << " " << unit << ", at most "
     << c.config.compensation->allowed_not_ok << " row(s) not ok.";
  if (k.base_frame) {
    md << " Compensated with the robot `calibrate --out` writes (the nominal's base frame); MuJoCo's tool is "
       << "compared after one rigid motion registered in closed form (the actual's base error: "
       << fixed(k.rigid_after.p.norm(), 4) << " " << unit << ", " << fixed(rotationAngle(k.rigid_after.R), 4)
       << " rad after compensation).";
  }
  if (!k.tool_determined) {
    md << " The targets did not determine the tool frame: compensate flags it (\"compensated for the flange; the "
       << "tool frame is the nominal's\"), and the task is the target's point.";
  }
  md << "\n\n"
     << "| commanded | rows | RMS position (" << unit << ") | max position | RMS rotation (rad) | max rotation |\n"
     << "|---|---|---|---|---|---|\n";
  for (const auto& [name, s] : {std::pair<const char*, const ResidualStatistics*>{"q (before)", &k.before},
                                {"q' (after)", &k.after}}) {
    char numbers[160];
    std::snprintf(numbers, sizeof numbers, "%d | %.3e | %.3e | ", s->count, s->rms_position, s->max_position);
    md << "| " << name << " | " << numbers;
    if (rotation) {
      std::snprintf(numbers, sizeof numbers, "%.3e | %.3e", s->rms_rotation, s->max_rotation);
      md << numbers << " |\n";
    } else {
      md << "- | - |\n";
    }
  }
  md << "\nStatuses:";
  for (size_t s = 0; s < k.statuses.size(); ++s) md << (s ? ", " : " ") << k.statuses[s] << " " << ikStatusName(static_cast<IkStatus>(s));
  md << ".\n\n";
  constexpr size_t kRowsListed = 20;
  for (size_t i = 0; i < k.not_ok.size() && i < kRowsListed; ++i) {
    md << "- validation pose " << k.not_ok[i].row + 1 << ": " << ikStatusName(k.not_ok[i].status) << ": "
       << markdownText(k.not_ok[i].reason) << "\n";
  }
  if (k.not_ok.size() > kRowsListed) md << "- ... (" << k.not_ok.size() << " in all)\n";
  if (!k.not_ok.empty()) md << "\n";
  return md.str();
}

// A calibration case's section: its set-up and acceptance, plan, compensation, failures, pictures (`base`:
// the scenario's file stem, `k`: the case's 0-based index), residuals and calibrate's text.
std::string calibrationSection(const CalibrationCaseResult& c, const std::string& base, size_t k) {
  std::ostringstream md;
  md << "### Calibration '" << markdownText(c.config.name) << "': " << (c.pass ? "pass" : "**FAIL**") << "\n\n"
     << c.config.poses << (c.config.plan ? " planned" : "") << " poses measured on the MuJoCo model ("
     << measureName(c.config.measure());
  if (!c.config.targets.empty()) {
    std::string names;
    for (const std::string& t : c.config.targets) names += (names.empty() ? "" : ", ") + t;
    md << ": " << markdownText(names) << ", " << c.config.poses * c.config.targets.size() << " measurements";
  }
  const std::string unit = c.report && !c.report->nominal.length_unit.empty() ? " " + c.report->nominal.length_unit : "";
  md << "; noise: position " << c.config.noise_position << unit << ", rotation " << c.config.noise_rotation << " rad";
  if (c.config.frame) {
    const auto& f = *c.config.frame;
    md << "; in a measurement frame at rotation vector [" << f[0] << ", " << f[1] << ", " << f[2]
       << "] rad, translation [" << f[3] << ", " << f[4] << ", " << f[5] << "]" << unit;
  }
  if (c.config.blunders > 0) md << "; " << c.config.blunders << " blunders of " << c.config.blunder_size << unit;
  md << "; " << lossName(c.config.loss) << " loss), " << c.config.validation_poses
     << " noise-free validation poses; acceptance: validation RMS position <= " << c.config.tolerance_position;
  if (c.config.min_improvement) md << ", at least " << *c.config.min_improvement << "x below the registered nominal's";
  md << ", converged, the verdict accepted" << (c.config.blunders > 0 ? ", exactly the blunders flagged" : "") << ".\n\n";
  if (c.plan) md << planSummary(c);
  if (c.compensation) md << compensationSummary(c);
  for (const auto& f : c.failures) md << "- failed: " << markdownText(f) << "\n";
  if (!c.failures.empty()) md << "\n";
  std::ostringstream text;
  printCalibration(text, *c.report);
  md << "![calibration](" << base << "_calibration_" << k + 1 << ".png)\n\n";
  if (hasResiduals(c)) md << "![residuals](" << base << "_calibration_" << k + 1 << "_residuals.png)\n\n";
  md << residualSummary(c) << markdownCode(text.str()) << "\n";
  return md.str();
}

// A scenario's section: its model and run, its pictures and its calibration cases.
std::string scenarioSection(const ScenarioResult& r) {
  std::ostringstream md;
  const std::string base = safe(r.scenario.name);
  md << "## " << markdownText(r.scenario.name) << "\n\nModel " << markdownText(r.scenario.model) << ", tip "
     << markdownText(r.scenario.tip) << ", L = "
     << r.size << ", " << r.samples << " samples in " << r.seconds << " s. The error picture shows "
     << plotted(r) << "; the histogram and the table, every sample.\n\n"
     << "![errors](" << base << "_errors.png)\n\n![histogram](" << base << "_histogram.png)\n\n";
  if (r.map_size > 0) md << "![singularity map](" << base << "_singularity_map.png)\n\n";
  for (size_t k = 0; k < r.calibrations.size(); ++k) md << calibrationSection(r.calibrations[k], base, k);
  return md.str();
}

}  // namespace

std::string summaryMarkdown(const std::vector<ScenarioResult>& results) {
  std::ostringstream md;
  md << "# lowpair validation report\n\nEvery comparison: MuJoCo's tip pose (or Jacobian) against the library.\n"
     << "Rotation errors are geodesic angles (rad, atan2 form); translation errors are distances divided by the "
        "robot size L. Max and mean are exact; p99 comes from a log histogram (100 bins per decade, relative "
        "error below 1.2 %).\n\n";
  md << "| scenario | comparison | samples | max rot (rad) | p99 rot | max tr / L | p99 tr / L | pass |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    for (const auto& c : r.comparisons) {
      char numbers[160];
      std::snprintf(numbers, sizeof numbers, "%d | %.2e | %.2e | %.2e | %.2e | %s", r.samples, c.max_rotation,
                    c.p99_rotation, c.max_translation / r.size, c.p99_translation / r.size,
                    c.pass ? "pass" : "**FAIL**");
      md << "| " << markdownText(r.scenario.name) << " | " << markdownText(c.name) << " | " << numbers << " |\n";
    }
  }
  md << "\n";
  for (const auto& r : results) md << scenarioSection(r);
  return md.str();
}

}  // namespace lowpair::validation::detail
