// calibrate --select cv: the candidates, the cross-validation and its table (selection.hpp).
#include "commands/selection.hpp"

#include <algorithm>
#include <cmath>

#include "io/output.hpp"
#include "commands/calibration_inputs.hpp"
#include "commands/calibration_output_parts.hpp"
#include "commands/limits.hpp"

namespace lowpair::commands {

using namespace detail;
using nlohmann::json;

namespace {

// At least one pose per fold: said with the argument's name, and with the cause when joint vectors repeat.
void checkPosesForFolds(const io::MeasurementFile& fit, int folds, const ArgumentSpelling& spelling) {
  const int poses = crossValidationPoses(fit.measurements);
  if (poses >= folds) return;
  std::vector<VecX> qs;
  for (const Measurement& m : fit.measurements) qs.push_back(m.q);
  std::sort(qs.begin(), qs.end(), [](const VecX& x, const VecX& y) {
    return std::lexicographical_compare(x.data(), x.data() + x.size(), y.data(), y.data() + y.size());
  });
  const auto distinct = static_cast<size_t>(std::unique(qs.begin(), qs.end()) - qs.begin());
  const size_t n = fit.measurements.size();
  const bool repeats = (fit.measure != Measure::Targets && static_cast<size_t>(poses) < n) ||
                       distinct < static_cast<size_t>(poses);
  std::string text = std::to_string(folds) + " folds but " + fit.path + " holds " + std::to_string(poses) +
                     (poses == 1 ? " pose" : " poses");
  if (repeats) {
    text += ": its " + std::to_string(n) + " measurements repeat joint vectors, " + std::to_string(distinct) +
            " distinct (duplicates: consecutive measurements at one joint vector are one pose)";
  }
  text += "; cross-validation deals poses to folds and needs at least as many poses as folds";
  if (poses >= 2) text += " (at most " + std::to_string(poses) + " folds here, or more poses)";
  throw UsageError(spelling.name("folds"), text);
}

CrossValidationScore scoreOfName(const std::string& name) {
  return name == "trimmed" ? CrossValidationScore::Trimmed
         : name == "median" ? CrossValidationScore::Median
                            : CrossValidationScore::Rms;
}

bool hasCompliance(const Selection& s) {
  return std::any_of(s.cv.candidates.begin(), s.cv.candidates.end(), [](const auto& c) { return c.compliance; });
}
bool hasBacklash(const Selection& s) {
  return std::any_of(s.cv.candidates.begin(), s.cv.candidates.end(), [](const auto& c) { return c.backlash; });
}

// A candidate's prior: its grid WIDTH, "none", or "given" (--prior, every candidate)
std::string priorLabel(const Selection& s, const CrossValidation::Candidate& c) {
  if (c.prior < 0) return s.given_prior ? "given" : "none";
  const std::optional<double> w = s.prior_widths[static_cast<size_t>(c.prior)];
  return w ? io::shortest(*w) : "none";
}

}  // namespace

bool levelsOnly(const Selection& s) {
  return s.cv.score == CrossValidationScore::Rms &&
         std::all_of(s.cv.candidates.begin(), s.cv.candidates.end(), [](const CrossValidation::Candidate& c) {
           return c.prior < 0 && !c.compliance && !c.backlash;
         });
}

std::string chosenText(const Selection& s) {
  const CrossValidation::Candidate& c = s.cv.candidates[static_cast<size_t>(s.cv.chosen_index)];
  std::string text = parameterSetName(c.set);
  if (!s.prior_widths.empty()) text += priorLabel(s, c) == "none" ? ", no prior" : ", prior " + priorLabel(s, c);
  if (hasCompliance(s)) text += c.compliance ? ", compliance on" : ", compliance off";
  if (hasBacklash(s)) text += c.backlash ? ", backlash on" : ", backlash off";
  return text;
}

std::string scoreName(CrossValidationScore score) {
  return score == CrossValidationScore::Trimmed ? "trimmed" : score == CrossValidationScore::Median ? "median" : "rms";
}

void checkSelectionArguments(const SelectionRequest& request, bool select, bool prior, const ArgumentSpelling& spelling) {
  if (request.cv_score && *request.cv_score != "rms" && *request.cv_score != "trimmed" && *request.cv_score != "median") {
    throw UsageError(spelling.name("cv_score"),
                     "expected 'rms', 'trimmed' or 'median', got " + io::quotedFileText(*request.cv_score));
  }
  for (const auto& [given, name] : {std::pair{request.cv_score.has_value(), "cv_score"},
                                    std::pair{request.prior_grid.has_value(), "prior_grid"}}) {
    if (given && !select) {
      throw UsageError(spelling.name(name), "scores the candidates of " + spelling.name("select") + " cv: give it too");
    }
  }
  if (request.prior_grid) {
    parsePriorGrid(*request.prior_grid, spelling);
    if (prior) {
      throw UsageError(spelling.name("prior_grid"), "compares prior widths (and no prior); " + spelling.name("prior") +
                                                        " fixes one: give one or the other, not both");
    }
  }
}

Selection selectByCrossValidation(const io::RobotFile& nominal_file, const PoeModel& nominal, const io::MeasurementFile& fit,
                                  const SelectionRequest& request, CalibrationOptions& options,
                                  DeflectionChoice& deflections, const ArgumentSpelling& spelling) {
  checkPosesForFolds(fit, request.folds, spelling);
  Selection s;
  CrossValidationGrid grid;
  grid.score = scoreOfName(request.cv_score.value_or("rms"));
  grid.compliance_off = !options.compliance_joints.empty();
  grid.backlash_off = !options.backlash_joints.empty();
  if (request.prior_grid) {
    grid.priors.push_back(ParameterPrior{});  // no prior is a candidate too
    s.prior_widths.push_back(std::nullopt);
    for (const double w : parsePriorGrid(*request.prior_grid, spelling)) {
      grid.priors.push_back(priorOfWidth(w, io::metresPerUnit(nominal_file.length_unit)));
      s.prior_widths.push_back(w);
    }
  }
  s.given_prior = !options.prior.none();
  const int candidates = static_cast<int>(grid.levels.size()) * std::max<int>(1, static_cast<int>(grid.priors.size())) *
                         (grid.compliance_off ? 2 : 1) * (grid.backlash_off ? 2 : 1);
  if (const auto problem = crossValidationSizeProblem(fit.measurements.size(), nominal.dof(), fit.measure,
                                                      static_cast<int>(fit.target_names.size()), request.folds,
                                                      request.repeats, candidates)) {
    throw UsageError(spelling.name("repeats"), *problem);
  }
  s.cv = crossValidate(nominal, fit.measurements, options, request.folds, request.repeats, grid);
  const CrossValidation::Candidate& chosen = s.cv.candidates[static_cast<size_t>(s.cv.chosen_index)];
  options = candidateOptions(options, grid, chosen);
  if (!chosen.compliance) deflections.compliance.clear();
  if (!chosen.backlash) {
    deflections.backlash.clear();
    deflections.sign_from_column.clear();
  }
  return s;
}

void printSelection(std::ostream& out, const Selection& s, bool noise_stated, const std::string& unit) {
  const CrossValidation& cv = s.cv;
  const std::string scores = noise_stated ? " in noise units" : " in weighted units, 1/L and 1/rad";
  if (levelsOnly(s)) {
    out << "parameter choice (" << cv.folds << "-fold cross-validation, " << cv.repeats
        << (cv.repeats == 1 ? " partition" : " partitions") << "; held-out score" << scores << ", RMS position):";
    for (const auto& cand : cv.candidates) {
      out << " " << parameterSetName(cand.set) << " (" << cand.parameters << ") "
          << (cand.failed ? std::string("failed") : residual(cand.score) + ", " + residual(cand.rms_position) + " " + unit)
          << ";";
    }
    out << " chosen: " << parameterSetName(cv.chosen) << "\n";
    return;
  }
  const bool prior = !s.prior_widths.empty() || s.given_prior, compliance = hasCompliance(s), backlash = hasBacklash(s);
  out << "selection (" << cv.folds << "-fold cross-validation, " << cv.repeats
      << (cv.repeats == 1 ? " partition" : " partitions") << ", the same for every candidate; held-out score "
      << scoreName(cv.score) << scores << ", its sd over the partitions; * chosen):\n";
  out << "  level    " << (prior ? "prior  " : "") << (compliance ? "compliance  " : "") << (backlash ? "backlash  " : "")
      << "parameters       score          sd  RMS position (" << unit << ")\n";
  for (size_t i = 0; i < cv.candidates.size(); ++i) {
    const auto& c = cv.candidates[i];
    char line[200];
    std::snprintf(line, sizeof line, "  %-8s ", parameterSetName(c.set));
    out << line;
    if (prior) {
      std::snprintf(line, sizeof line, "%-6s ", priorLabel(s, c).c_str());
      out << line;
    }
    if (compliance) out << (c.compliance ? "on          " : "off         ");
    if (backlash) out << (c.backlash ? "on        " : "off       ");
    std::snprintf(line, sizeof line, "%10d  %10s  %10s  %s%s\n", c.parameters,
                  c.failed ? "failed" : residual(c.score).c_str(),
                  c.failed || !std::isfinite(c.score_sd) ? "-" : residual(c.score_sd).c_str(),
                  c.failed ? "-" : residual(c.rms_position).c_str(), static_cast<int>(i) == cv.chosen_index ? " *" : "");
    out << line;
  }
  out << "chosen: " << chosenText(s) << "\n";
}

json selectionJson(const Selection& s, Measure measure) {
  const CrossValidation& cv = s.cv;
  json candidates = json::array();
  for (size_t i = 0; i < cv.candidates.size(); ++i) {
    const auto& c = cv.candidates[i];
    const std::string prior = priorLabel(s, c);
    candidates.push_back({{"parameters", parameterSetName(c.set)},
                          {"prior", prior == "none" ? json(nullptr) : prior == "given" ? json("given")
                                                                                        : json(*s.prior_widths[static_cast<size_t>(c.prior)])},
                          {"compliance", c.compliance},
                          {"backlash", c.backlash},
                          {"count", c.parameters},
                          {"rms_position", c.failed ? json(nullptr) : json(c.rms_position)},
                          {"rms_rotation", c.failed || measure != Measure::Pose ? json(nullptr) : json(c.rms_rotation)},
                          {"score", c.failed ? json(nullptr) : json(c.score)},
                          {"score_sd", c.failed || !std::isfinite(c.score_sd) ? json(nullptr) : json(c.score_sd)},
                          {"failed", c.failed},
                          {"chosen", static_cast<int>(i) == cv.chosen_index}});
  }
  return {{"folds", cv.folds},
          {"repeats", cv.repeats},
          {"score", scoreName(cv.score)},
          {"candidates", candidates},
          {"chosen", parameterSetName(cv.chosen)}};
}

}  // namespace lowpair::commands
