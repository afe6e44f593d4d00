#include "validation/report.hpp"

#include "io/output.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace lowpair::validation {

using namespace lowpair::io;  // the rooms below

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::vector<size_t> oneBased(const std::vector<size_t>& rows) {
  std::vector<size_t> out;
  for (const size_t r : rows) out.push_back(r + 1);
  return out;
}

// count, RMS and max position (and rotation for a pose task: null otherwise; null for a number not measured)
json statisticsJson(const ResidualStatistics& s, bool rotation) {
  return {{"count", s.count},
          {"rms_position", finiteOrNull(s.rms_position)},
          {"max_position", finiteOrNull(s.max_position)},
          {"rms_rotation", rotation ? finiteOrNull(s.rms_rotation) : json(nullptr)},
          {"max_rotation", rotation ? finiteOrNull(s.max_rotation) : json(nullptr)}};
}

json planJson(const CalibrationCase& config, const CasePlanResult& p) {
  auto value = [](const PlanValue& v) {
    return json{{"log_det", finiteOrNull(v.log_det)}, {"O1", v.o1}, {"rank", v.rank}};
  };
  return {{"criterion", planCriterionName(p.plan.criterion)},
          {"candidates", config.plan->candidates},
          {"samples", p.plan.indices},
          {"planned", value(p.plan.value)},
          {"first_samples", value(p.first)},
          {"greedy", value(p.plan.start)},
          {"swaps", p.plan.swaps},
          {"passes", p.plan.passes},
          {"rank", p.plan.rank.rank},
          {"expected", p.plan.expected.total()},
          {"seconds", p.seconds}};
}

json compensationJson(const CalibrationCase& config, const CompensationResult& k) {
  const bool rotation = k.measure == Measure::Pose;
  json statuses = json::object();
  for (size_t s = 0; s < k.statuses.size(); ++s) statuses[ikStatusName(static_cast<IkStatus>(s))] = k.statuses[s];
  json not_ok = json::array();
  for (const CompensationResult::Row& r : k.not_ok) {
    not_ok.push_back({{"validation_pose", r.row + 1}, {"status", ikStatusName(r.status)}, {"reason", r.reason}});
  }
  return {{"measure", measureName(k.measure)},
          {"target", k.point_name.empty() ? json(nullptr) : json(k.point_name)},
          {"point_tool", {k.point_tool.x(), k.point_tool.y(), k.point_tool.z()}},
          {"length_scale", k.length_scale},
          {"tolerance", config.compensation->tolerance},
          {"allowed_not_ok", config.compensation->allowed_not_ok},
          {"before", statisticsJson(k.before, rotation)},
          {"after", statisticsJson(k.after, rotation)},
          {"statuses", statuses},
          {"not_ok", not_ok},
          {"seconds", k.seconds}};
}

}  // namespace

json validationJson(const std::vector<ScenarioResult>& results, const RunOptions& options) {
  json doc;
  bool pass = true;
  doc["scenarios"] = json::array();
  for (const auto& r : results) {
    json s = {{"name", r.scenario.name},  {"file", r.scenario.path}, {"model", r.scenario.model},
              {"tip", r.scenario.tip},    {"samples", r.samples},    {"seed", options.seed ? *options.seed : r.scenario.seed},
              {"size", r.size},           {"seconds", r.seconds},    {"pass", r.pass}};
    if (options.shards > 1) s["shard"] = std::to_string(options.shard) + "/" + std::to_string(options.shards);
    s["comparisons"] = json::array();
    for (const auto& c : r.comparisons) {
      json j = {{"name", c.name},
                {"max_rotation", c.max_rotation},
                {"mean_rotation", c.mean_rotation},
                {"p99_rotation", c.p99_rotation},
                {"max_translation", c.max_translation},
                {"mean_translation", c.mean_translation},
                {"p99_translation", c.p99_translation},
                {"tolerance_rotation", c.tolerance_rotation},
                {"tolerance_translation", c.tolerance_translation},
                {"worst_q", c.worst_q},
                {"non_finite", c.non_finite},
                {"pass", c.pass}};
      if (c.pose) j["max_rotation_euler_zyx"] = c.max_rotation_euler;
      s["comparisons"].push_back(j);
    }
    if (!r.singular_poses.empty()) {
      s["singular_poses"] = json::array();
      for (const auto& sp : r.singular_poses) {
        s["singular_poses"].push_back({{"name", sp.name}, {"q", sp.q}, {"expected", sp.expected},
                                       {"reported", sp.reported}, {"rank", sp.rank_library},
                                       {"rank_mujoco", sp.rank_mujoco}, {"dof", sp.dof},
                                       {"sigma_min", sp.sigma_min}, {"pass", sp.pass}});
      }
    }
    if (!r.calibrations.empty()) {
      s["calibrations"] = json::array();
      for (const auto& c : r.calibrations) {
        json j = calibrationJson(*c.report);
        j["name"] = c.config.name;
        j["pass"] = c.pass;
        j["failures"] = c.failures;
        // the scenario's own checks: validation in the measurement frame, blunders (1-based measurements)
        j["acceptance"] = {{"validation_rms_position_before", c.validation_before.rms_position},
                           {"validation_rms_position_after", c.validation_after.rms_position},
                           {"validation_rms_rotation_after", c.validation_after.rms_rotation},
                           {"blunders", oneBased(c.blunders)},
                           {"missed_blunders", oneBased(c.missed_blunders)},
                           {"false_outliers", oneBased(c.false_outliers)}};
        if (c.plan) j["plan"] = planJson(c.config, *c.plan);
        if (c.compensation) j["compensation"] = compensationJson(c.config, *c.compensation);
        s["calibrations"].push_back(j);
      }
    }
    pass = pass && r.pass;
    doc["scenarios"].push_back(s);
  }
  doc["pass"] = pass;
  return doc;
}

void printValidationTable(std::ostream& out, const std::vector<ScenarioResult>& results) {
  char line[400];
  std::snprintf(line, sizeof line, "%-28s %-52s %7s %11s %11s %11s %11s %9s %9s  %s\n", "scenario", "comparison",
                "samples", "max rot", "p99 rot", "max tr/L", "p99 tr/L", "tol rot", "tol tr/L", "");
  out << line;
  bool pass = true;
  for (const auto& r : results) {
    for (const auto& c : r.comparisons) {
      std::snprintf(line, sizeof line, "%-28s %-52s %7d %11.2e %11.2e %11.2e %11.2e %9.0e %9.0e  %s\n",
                    r.scenario.name.c_str(), c.name.c_str(), r.samples, c.max_rotation, c.p99_rotation,
                    c.max_translation / r.size, c.p99_translation / r.size, c.tolerance_rotation,
                    c.tolerance_translation / r.size, c.pass ? "pass" : "FAIL");
      out << line;
      if (c.non_finite > 0) out << "  " << c.non_finite << " sample(s) gave a non-finite error (NaN or inf): not measured\n";
    }
    pass = pass && r.pass;
  }
  bool header = false;
  for (const auto& r : results) {
    for (const auto& sp : r.singular_poses) {
      if (!header) {
        std::snprintf(line, sizeof line, "\n%-28s %-20s %-12s %-36s %6s %6s %10s\n", "scenario", "singular pose",
                      "expected", "reported", "rank", "mujoco", "sigma_min");
        out << line;
        header = true;
      }
      std::string expected, reported;
      for (const auto& e : sp.expected) expected += (expected.empty() ? "" : " ") + e;
      for (const auto& d : sp.reported) reported += (reported.empty() ? "" : " ") + d;
      std::snprintf(line, sizeof line, "%-28s %-20s %-12s %-36s %3d/%-2d %6d %10.1e  %s\n", r.scenario.name.c_str(),
                    sp.name.c_str(), expected.c_str(), reported.c_str(), sp.rank_library, sp.dof, sp.rank_mujoco,
                    sp.sigma_min, sp.pass ? "pass" : "FAIL");
      out << line;
    }
  }
  header = false;
  for (const auto& r : results) {
    for (const auto& c : r.calibrations) {
      if (!header) {
        std::snprintf(line, sizeof line, "\n%-28s %-20s %9s %12s %12s %12s %9s %5s\n", "scenario", "calibration",
                      "rank", "val before", "val after", "tolerance", "improve", "iter");
        out << line;
        header = true;
      }
      const std::string rank = std::to_string(c.rank) + "/" + std::to_string(c.expected);
      std::snprintf(line, sizeof line, "%-28s %-20s %9s %12.3e %12.3e %12.3e %8.3gx %5d  %s\n", r.scenario.name.c_str(),
                    c.config.name.c_str(), rank.c_str(), c.validation_before.rms_position,
                    c.validation_after.rms_position, c.config.tolerance_position,
                    c.validation_before.rms_position / c.validation_after.rms_position, c.iterations,
                    c.pass ? "pass" : "FAIL");
      out << line;
      for (const auto& f : c.failures) out << "  " << f << "\n";
    }
  }
  if (header) out << "(calibration: validation RMS position error before and after, length unit of the nominal)\n";
  header = false;
  for (const auto& r : results) {
    for (const auto& c : r.calibrations) {
      if (!c.plan) continue;
      if (!header) {
        std::snprintf(line, sizeof line, "\n%-28s %-20s %6s %10s %5s %12s %12s %6s %8s\n", "scenario", "planned",
                      "poses", "candidates", "crit", "log det", "first N", "swaps", "seconds");
        out << line;
        header = true;
      }
      const CasePlanResult& p = *c.plan;
      std::snprintf(line, sizeof line, "%-28s %-20s %6d %10d %5s %12.4f %12.4f %6d %8.3f\n", r.scenario.name.c_str(),
                    c.config.name.c_str(), c.config.poses, c.config.plan->candidates,
                    planCriterionName(p.plan.criterion), p.plan.value.log_det, p.first.log_det, p.plan.swaps, p.seconds);
      out << line;
    }
  }
  if (header) {
    out << "(plan: log det of the planned poses' information, and of the first N samples the case fits without plan:)\n";
  }
  header = false;
  for (const auto& r : results) {
    for (const auto& c : r.calibrations) {
      if (!c.compensation) continue;
      if (!header) {
        std::snprintf(line, sizeof line, "\n%-28s %-20s %-8s %6s %6s %12s %12s %12s %12s %11s %11s\n", "scenario",
                      "compensated", "task", "rows", "not ok", "RMS before", "RMS after", "max after", "tolerance",
                      "rot before", "rot after");
        out << line;
        header = true;
      }
      const CompensationResult& k = *c.compensation;
      const std::string task = k.point_name.empty() ? measureName(k.measure) : k.point_name;
      const bool rotation = k.measure == Measure::Pose;
      char rot_before[32] = "-", rot_after[32] = "-";
      if (rotation) {
        std::snprintf(rot_before, sizeof rot_before, "%.3e", k.before.rms_rotation);
        std::snprintf(rot_after, sizeof rot_after, "%.3e", k.after.rms_rotation);
      }
      std::snprintf(line, sizeof line, "%-28s %-20s %-8s %6d %6zu %12.3e %12.3e %12.3e %12.3e %11s %11s\n",
                    r.scenario.name.c_str(), c.config.name.c_str(), task.c_str(), k.count(), k.not_ok.size(),
                    k.before.rms_position, k.after.rms_position, k.after.max_position, c.config.compensation->tolerance,
                    rot_before, rot_after);
      out << line;
      for (size_t s = 0; s < k.statuses.size(); ++s) {
        if (s != static_cast<size_t>(IkStatus::Ok) && k.statuses[s] > 0) out << "  " << k.statuses[s] << " row(s) " << ikStatusName(static_cast<IkStatus>(s)) << "\n";
      }
      constexpr size_t kRowsShown = 3;
      for (size_t i = 0; i < k.not_ok.size() && i < kRowsShown; ++i) {
        out << "  validation pose " << k.not_ok[i].row + 1 << ": " << ikStatusName(k.not_ok[i].status) << ": "
            << k.not_ok[i].reason << "\n";
      }
    }
  }
  if (header) {
    out << "(compensation: MuJoCo's tool commanded at the validation q (before) and at the compensated q' (after, ok "
           "rows only) against the nominal's FK at q; position in the nominal's length unit, rotation RMS in rad)\n";
  }
  out << (pass ? "all comparisons within tolerance" : "FAILED: a comparison is outside its tolerance (marked FAIL)")
      << "  (rotation in rad; translation relative to the robot size L; Jacobian rows: angular block as 'rot', "
         "linear as 'tr')\n";
}

namespace {

// A file-name stem from a user string: [A-Za-z0-9_-] only, at most kMaxStem characters (file systems
// allow 255 bytes per name); a longer name keeps its start and gets a hash of the whole, so names stay distinct.
std::string safe(const std::string& name) {
  constexpr size_t kMaxStem = 80;
  std::string s = name;
  for (char& ch : s) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
  }
  if (s.size() > kMaxStem) {
    char hash[20];
    std::snprintf(hash, sizeof hash, "_%016zx", std::hash<std::string>{}(name));
    s = s.substr(0, kMaxStem - 17) + hash;
  }
  return s;
}

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

// A gnuplot single-quoted string holding `text` verbatim: no substitution happens inside single quotes
// (no backquote commands, no macros), a quote is written twice, and control characters (a newline
// would end the command) become '?'. Every user string (scenario and file names) goes through this.
std::string gpString(const std::string& text) {
  std::string out = "'";
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '\'') {
      out += "''";
    } else if (u < 0x20 || u == 0x7f) {
      out += '?';
    } else {
      out += ch;
    }
  }
  return out + "'";
}

// Runs `gnuplot SCRIPT` in `dir` with an argument vector (no shell), stderr into `log`.
// Returns the exit status, or -1 when gnuplot could not be started.
int runGnuplot(const fs::path& dir, const std::string& script, const std::string& log) {
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    if (::chdir(dir.c_str()) != 0) ::_exit(127);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, STDERR_FILENO);
      ::close(fd);
    }
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      ::dup2(null, STDOUT_FILENO);
      ::close(null);
    }
    char* const argv[] = {const_cast<char*>("gnuplot"), const_cast<char*>(script.c_str()), nullptr};
    ::execvp("gnuplot", argv);
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Writes `text` to `path` and checks it reached the file (a full disk, a file-size limit, a vanished
// folder): a report is complete or not written at all.
void writeChecked(const fs::path& path, const std::string& text) {
  errno = 0;
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) {
    const int error = errno;
    throw std::runtime_error(path.filename().string() + ": cannot write" +
                             (error ? std::string(" (") + std::strerror(error) + ")" : std::string()));
  }
}

// A PNG ends with its IEND chunk; a picture cut short by a full disk does not.
void requireCompletePng(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  std::string tail(8, '\0');
  if (size >= 8) {
    in.seekg(size - 8);
    in.read(tail.data(), 8);
  }
  if (size < 8 || !in || tail.compare(0, 4, "IEND") != 0) {
    throw std::runtime_error(path.filename().string() + ": gnuplot did not write a complete picture");
  }
}

// "1 sample in 500 (20000 of 10000000)" when the picture shows a subsample (ComparisonResult::plot_stride)
std::string plotted(const ScenarioResult& r) {
  const long long stride = r.comparisons.empty() ? 1 : r.comparisons.front().plot_stride;
  if (stride <= 1) return "every sample";
  const size_t points = r.comparisons.front().rotation_errors.size();
  return "1 sample in " + std::to_string(stride) + " (" + std::to_string(points) + " of " +
         std::to_string(r.samples) + ")";
}

bool hasResiduals(const CalibrationCaseResult& c) { return c.report && !c.report->result.residuals.empty(); }

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

// The normalized residual of every fitting measurement (calibrate's, in noise units), flagged outliers and
// blunders marked, the outlier threshold drawn.
void residualPicture(const fs::path& dir, const ScenarioResult& r, const CalibrationCaseResult& c,
                     const std::string& name, std::ostringstream& gp) {
  if (!hasResiduals(c)) return;
  const CalibrationResult& result = c.report->result;
  int zeros = 0;
  {
    std::ostringstream out;
    out << "# measurement, normalized residual: accepted, flagged (outlier), blunder; position error (length)\n";
    for (size_t k = 0; k < result.residuals.size(); ++k) {
      const MeasurementResidual& x = result.residuals[k];
      const bool blunder = std::binary_search(c.blunders.begin(), c.blunders.end(), k);
      auto value = [&](bool shown) {
        return shown && x.normalized > 0 ? shortest(x.normalized) : std::string("NaN");  // no 0 on a log axis
      };
      if (!(x.normalized > 0)) ++zeros;
      out << k + 1 << " " << value(!x.outlier) << " " << value(x.outlier) << " " << value(blunder) << " "
          << shortest(x.position) << "\n";
    }
    writeChecked(dir / (name + ".dat"), out.str());
  }
  const std::string data = gpString(name + ".dat");
  const double threshold = CalibrationOptions{}.outlier_threshold;  // the cases keep calibrate's default
  gp << "reset\nset terminal pngcairo noenhanced size 1000,500 font ',10'\n"
     << "set output " << gpString(name + ".png") << "\n"
     << "set title " << gpString(r.scenario.name + ", calibration '" + c.config.name + "': normalized residual of " +
                                 std::to_string(result.residuals.size()) + " fitting measurements (" +
                                 lossName(result.loss) + " loss), " + std::to_string(result.outliers) + " flagged" +
                                 (zeros > 0 ? "; " + std::to_string(zeros) + " exactly 0, not drawn" : std::string()))
     << "\n"
     << "set logscale y\nset format y '1e%L'\nset grid\nset key outside right top\n"
     << "set xlabel 'fitting measurement'\nset ylabel "
     << gpString(result.noise_stated ? "normalized residual (units of the stated noise)"
                                     : "normalized residual (no noise stated: units of the median residual's scale)")
     << "\n"
     << "plot " << data << " using 1:2 with points pt 7 ps 0.4 lc 'dark-blue' title 'accepted', " << data
     << " using 1:3 with points pt 2 ps 1.2 lw 2 lc 'red' title 'flagged (outlier)', " << data
     << " using 1:4 with points pt 6 ps 2 lc 'black' title 'blunder (simulated)', " << shortest(threshold)
     << " with lines dt 2 lc 'black' title 'outlier threshold'\n";
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
     << c.config.compensation->allowed_not_ok << " row(s) not ok.\n\n"
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

void plots(const fs::path& dir, const ScenarioResult& r) {
  const std::string base = safe(r.scenario.name);
  const fs::path data = dir / (base + "_errors.dat");
  long long exact_zeros = 0;  // plotted errors that are exactly 0 (not drawn on a log axis)
  {
    // the bounded subsample of every comparison (the same samples for all: one stride per run)
    std::ostringstream out;
    out << "# sample";
    for (const auto& c : r.comparisons) out << " " << safe(c.name) << ":rotation " << safe(c.name) << ":translation/L";
    out << "\n";
    const size_t points = r.comparisons.empty() ? 0 : r.comparisons.front().rotation_errors.size();
    const long long stride = r.comparisons.empty() ? 1 : r.comparisons.front().plot_stride;
    for (size_t k = 0; k < points; ++k) {
      out << static_cast<long long>(k) * stride;
      for (const auto& c : r.comparisons) {
        // log axes: an exact agreement (0) has no place on them; it is written as NaN, which gnuplot does not
        // draw, and counted in the picture's title
        for (const float e : {c.rotation_errors[k], c.translation_errors[k]}) {
          if (e > 0) {
            out << " " << e;
          } else {
            out << " NaN";
            ++exact_zeros;
          }
        }
      }
      out << "\n";
    }
    writeChecked(data, out.str());
  }
  // the histogram of every sample (ComparisonResult's LogHistogram counts) in tenths of a decade, from -18
  // (everything below 1e-18, exact zeros included) to -9 (everything above 1e-9)
  const fs::path histogram = dir / (base + "_histogram.dat");
  {
    constexpr int kFirst = -180, kLast = -90;  // tenths of a decade
    constexpr int kPerTenth = LogHistogram::kBinsPerDecade / 10;
    static_assert(LogHistogram::kBinsPerDecade % 10 == 0, "tenths of a decade are whole bins");
    auto tenth = [&](int b) {  // the tenth of a decade of LogHistogram bin b
      if (b == 0) return kFirst;
      if (b == LogHistogram::kBins - 1) return kLast;
      return std::clamp(LogHistogram::kMinExponent * 10 + (b - 1) / kPerTenth, kFirst, kLast);
    };
    std::vector<std::vector<long long>> rows(static_cast<size_t>(kLast - kFirst + 1),
                                             std::vector<long long>(2 * r.comparisons.size(), 0));
    for (size_t c = 0; c < r.comparisons.size(); ++c) {
      const auto& cmp = r.comparisons[c];
      for (size_t b = 0; b < cmp.rotation_histogram.size(); ++b) {
        rows[static_cast<size_t>(tenth(static_cast<int>(b)) - kFirst)][2 * c] += cmp.rotation_histogram[b];
      }
      for (size_t b = 0; b < cmp.translation_histogram.size(); ++b) {
        rows[static_cast<size_t>(tenth(static_cast<int>(b)) - kFirst)][2 * c + 1] += cmp.translation_histogram[b];
      }
    }
    std::ostringstream out;
    out << "# log10(error) lower edge; per comparison: samples (rotation) samples (translation/L)\n";
    for (size_t k = 0; k < rows.size(); ++k) {
      out << (kFirst + static_cast<int>(k)) / 10.0;
      for (long long v : rows[k]) out << " " << v;
      out << "\n";
    }
    writeChecked(histogram, out.str());
  }
  // gnuplot runs in `dir`: the script names files by their (sanitized) names; titles go through gpString
  const std::string data_name = gpString(data.filename().string());
  const std::string histogram_name = gpString(histogram.filename().string());
  std::ostringstream gp;
  gp << "set terminal pngcairo noenhanced size 1200,800 font ',10'\n"
     << "set output " << gpString(base + "_errors.png") << "\n"
     << "set multiplot layout 2,1 title " << gpString(r.scenario.name + ": error against MuJoCo, " + plotted(r) +
                                                     " (L = " + shortest(r.size) + ")" +
                                                     (exact_zeros > 0 ? "; " + std::to_string(exact_zeros) +
                                                                            " errors exactly 0, not drawn (log axis)"
                                                                      : std::string())) << "\n"
     << "set logscale y\nset format y '1e%L'\nset yrange [1e-18:1e-9]\nset key top left\nset grid\n"
     << "set ylabel 'rotation error (rad)'\n"
     << "plot ";
  for (size_t c = 0; c < r.comparisons.size(); ++c) {
    gp << (c ? ", " : "") << data_name << " using 1:" << 2 + 2 * c << " with points pt 7 ps 0.3 title "
       << gpString(r.comparisons[c].name);
  }
  gp << "\nset ylabel 'translation error / L'\nset xlabel 'sample'\nplot ";
  for (size_t c = 0; c < r.comparisons.size(); ++c) {
    gp << (c ? ", " : "") << data_name << " using 1:" << 3 + 2 * c << " with points pt 7 ps 0.3 title "
       << gpString(r.comparisons[c].name);
  }
  gp << "\nunset multiplot\n";
  // histogram of log10(error), every sample
  gp << "set output " << gpString(base + "_histogram.png") << "\n"
     << "set multiplot layout 1,2 title " << gpString(r.scenario.name + ": distribution of log10(error), all " +
                                                     std::to_string(r.samples) + " samples") << "\n"
     << "unset logscale y\nset format y '%g'\nset yrange [0:*]\nset xrange [-18:-9]\nset style fill transparent solid 0.4\n"
     << "set boxwidth 0.1\nset ylabel 'samples'\n"
     << "set xlabel 'log10 rotation error (rad)'\nplot ";
  for (size_t c = 0; c < r.comparisons.size(); ++c) {
    gp << (c ? ", " : "") << histogram_name << " using ($1 + 0.05):" << 2 + 2 * c << " with boxes title "
       << gpString(r.comparisons[c].name);
  }
  gp << "\nset xlabel 'log10 translation error / L'\nplot ";
  for (size_t c = 0; c < r.comparisons.size(); ++c) {
    gp << (c ? ", " : "") << histogram_name << " using ($1 + 0.05):" << 3 + 2 * c << " with boxes title "
       << gpString(r.comparisons[c].name);
  }
  gp << "\nunset multiplot\n";
  if (r.map_size > 0) {
    const std::string map_name = base + "_singularity_map.dat";
    {
      std::ostringstream out;
      for (int a = 0; a < r.map_size; ++a) {
        const double y = r.map_range_y[0] + (r.map_range_y[1] - r.map_range_y[0]) * a / (r.map_size - 1);
        for (int b = 0; b < r.map_size; ++b) {
          const double x = r.map_range_x[0] + (r.map_range_x[1] - r.map_range_x[0]) * b / (r.map_size - 1);
          out << x << " " << y << " " << r.map_log_sigma[static_cast<size_t>(a * r.map_size + b)] << "\n";
        }
        out << "\n";
      }
      writeChecked(dir / map_name, out.str());
    }
    const std::string jx = std::to_string(r.map_joints[0]), jy = std::to_string(r.map_joints[1]);
    auto unitOf = [&](int joint) {
      return r.map_prismatic[static_cast<size_t>(joint - 1)] ? std::string("length") : std::string("rad");
    };
    // the colour range of the data, so the singular curves are the darkest it shows
    double lo = 0, hi = 0;
    if (!r.map_log_sigma.empty()) {
      lo = *std::min_element(r.map_log_sigma.begin(), r.map_log_sigma.end());
      hi = *std::max_element(r.map_log_sigma.begin(), r.map_log_sigma.end());
    }
    if (!(hi > lo)) hi = lo + 1;
    std::string fixed_values;
    for (size_t i = 0; i < r.map_fixed.size(); ++i) {
      const int joint = static_cast<int>(i) + 1;
      if (joint == r.map_joints[0] || joint == r.map_joints[1]) continue;
      fixed_values += (fixed_values.empty() ? "" : ", ") + std::string("q") + std::to_string(joint) + " = " +
                      shortest(r.map_fixed[i]);
    }
    gp << "reset\nset terminal pngcairo noenhanced size 1000,860 font ',10'\n"
       << "set output " << gpString(base + "_singularity_map.png") << "\n"
       << "set title " << gpString(r.scenario.name + ": log10 sigma_min of the dimensionless Jacobian; dark = singular") << "\n"
       << "set label 1 " << gpString("other joints fixed: " + (fixed_values.empty() ? std::string("none") : fixed_values))
       << " at graph 0, graph -0.12 left\nset bmargin 7\n"
       << "set xlabel " << gpString("q" + jx + " (" + unitOf(r.map_joints[0]) + ")") << "\nset ylabel "
       << gpString("q" + jy + " (" + unitOf(r.map_joints[1]) + ")") << "\n"
       << "set view map\nset palette defined (0 'black', 0.3 'dark-red', 0.7 'orange', 1 'yellow')\n"
       << "set cbrange [" << shortest(lo) << ":" << shortest(hi) << "]\nset cblabel 'log10 sigma_min'\n"
       << "set xrange [*:*] noextend\nset yrange [*:*] noextend\n"
       << "splot " << gpString(map_name) << " using 1:2:3 with pm3d notitle\n";
  }
  for (size_t k = 0; k < r.calibrations.size(); ++k) {
    // Wu et al. Fig. 4: the position error of every validation pose before and after calibration
    const CalibrationCaseResult& c = r.calibrations[k];
    const std::string name = base + "_calibration_" + std::to_string(k + 1);
    {
      std::ostringstream out;
      out << "# validation measurement, position error before (the registered nominal), after (length unit of the nominal)\n";
      for (size_t i = 0; i < c.validation_position_before.size(); ++i) {
        out << i + 1;
        for (const double e : {c.validation_position_before[i], c.validation_position_after[i]}) {
          if (e > 0) {
            out << " " << e;
          } else {
            out << " NaN";  // an exact 0 has no place on the log axis: not drawn
          }
        }
        out << "\n";
      }
      writeChecked(dir / (name + ".dat"), out.str());
    }
    gp << "reset\nset terminal pngcairo noenhanced size 1000,500 font ',10'\n"
       << "set output " << gpString(name + ".png") << "\n"
       << "set title " << gpString(r.scenario.name + ", calibration '" + c.config.name +
                                   "': position error on the noise-free validation measurements") << "\n"
       << "set logscale y\nset format y '1e%L'\nset grid\nset key outside right top\n"
       << "set xlabel 'validation measurement'\nset ylabel "
       << gpString("position error (" +
                   (c.report && !c.report->nominal.length_unit.empty() ? c.report->nominal.length_unit
                                                                       : std::string("length unit of the nominal")) +
                   ")")
       << "\n"
       << "plot " << gpString(name + ".dat") << " using 1:2 with linespoints pt 7 ps 0.4 title 'nominal, registered (before)', "
       << gpString(name + ".dat") << " using 1:3 with linespoints pt 7 ps 0.4 title 'calibrated (after)'";
    if (c.config.tolerance_position > 0) {
      gp << ", " << c.config.tolerance_position << " with lines dt 2 lc 'black' title 'tolerance (RMS)'";
    }
    gp << "\n";
    residualPicture(dir, r, c, name + "_residuals", gp);
  }
  const std::string script = base + ".gnuplot";
  writeChecked(dir / script, gp.str());
  const fs::path log = dir / (base + ".gnuplot.log");
  const int status = runGnuplot(dir, script, log.string());
  if (status != 0) {
    std::ifstream in(log);
    std::string text((std::istreambuf_iterator<char>(in)), {});
    std::replace(text.begin(), text.end(), '\n', ' ');
    if (status == 127 && text.empty()) text = "gnuplot could not be started (is gnuplot-nox installed?)";
    throw std::runtime_error("gnuplot failed on " + script + ": " + text.substr(0, 300));
  }
  fs::remove(log);
  // gnuplot exits 0 on some write failures (a full disk): every picture must be a complete PNG
  std::vector<std::string> pictures = {base + "_errors.png", base + "_histogram.png"};
  if (r.map_size > 0) pictures.push_back(base + "_singularity_map.png");
  for (size_t k = 0; k < r.calibrations.size(); ++k) {
    pictures.push_back(base + "_calibration_" + std::to_string(k + 1) + ".png");
    if (hasResiduals(r.calibrations[k])) pictures.push_back(base + "_calibration_" + std::to_string(k + 1) + "_residuals.png");
  }
  for (const auto& picture : pictures) requireCompletePng(dir / picture);
}

}  // namespace

void writeReport(const std::string& dir, const std::vector<ScenarioResult>& results, const RunOptions& options) {
  // build everything in a sibling temporary folder, then move the files in
  const fs::path target = fs::absolute(dir);
  // only a folder (new or existing) takes a report, and only regular files in it are replaced: a device,
  // FIFO or socket given as the folder or found under a report file's name is never replaced by a file
  std::error_code status_error;
  const fs::file_status target_status = fs::status(target, status_error);
  if (fs::exists(target_status) && !fs::is_directory(target_status)) {
    throw std::runtime_error(dir + ": report not written: not a folder");
  }
  const fs::path parent = target.parent_path();
  fs::create_directories(parent);
  const fs::path tmp = parent / (target.filename().string() + ".partial-" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  try {
    writeChecked(tmp / "report.json", jsonText(validationJson(results, options)) + "\n");
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
    for (const auto& r : results) {
      plots(tmp, r);
      const std::string base = safe(r.scenario.name);
      md << "## " << markdownText(r.scenario.name) << "\n\nModel " << markdownText(r.scenario.model) << ", tip "
         << markdownText(r.scenario.tip) << ", L = "
         << r.size << ", " << r.samples << " samples in " << r.seconds << " s. The error picture shows "
         << plotted(r) << "; the histogram and the table, every sample.\n\n"
         << "![errors](" << base << "_errors.png)\n\n![histogram](" << base << "_histogram.png)\n\n";
      if (r.map_size > 0) md << "![singularity map](" << base << "_singularity_map.png)\n\n";
      for (size_t k = 0; k < r.calibrations.size(); ++k) {
        const CalibrationCaseResult& c = r.calibrations[k];
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
      }
    }
    writeChecked(tmp / "summary.md", md.str());
    fs::create_directories(target);
    for (const auto& entry : fs::directory_iterator(tmp)) {
      const fs::file_status existing = fs::symlink_status(target / entry.path().filename(), status_error);
      if (fs::exists(existing) && !fs::is_regular_file(existing)) {
        throw std::runtime_error((target / entry.path().filename()).string() +
                                 " exists and is not a regular file: not replaced");
      }
    }
    for (const auto& entry : fs::directory_iterator(tmp)) {
      fs::rename(entry.path(), target / entry.path().filename());
    }
    fs::remove_all(tmp);
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    throw std::runtime_error(dir + ": report not written: " + e.what());
  }
}

}  // namespace lowpair::validation
