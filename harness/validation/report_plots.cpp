// The pictures of `lowpair validate --report` (report.hpp writeReport): per scenario the data files, one
// gnuplot script and its PNGs (errors, histogram, singularity map, calibration cases and their residuals).
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "io/output.hpp"
#include "validation/report_parts.hpp"

namespace lowpair::validation::detail {

using namespace lowpair::io;  // the rooms below

namespace fs = std::filesystem;

namespace {

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

// The bounded subsample of every comparison (the same samples for all: one stride per run) into `data`.
// Returns the plotted errors that are exactly 0 (not drawn on a log axis).
long long writeErrorData(const fs::path& data, const ScenarioResult& r) {
  long long exact_zeros = 0;
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
  return exact_zeros;
}

// The histogram of every sample (ComparisonResult's LogHistogram counts) in tenths of a decade, from -18
// (everything below 1e-18, exact zeros included) to -9 (everything above 1e-9), into `histogram`.
void writeHistogramData(const fs::path& histogram, const ScenarioResult& r) {
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

// The error picture (rotation and translation / L per sample) and the histogram of log10(error).
void errorPictures(std::ostringstream& gp, const ScenarioResult& r, const std::string& base, const fs::path& data,
                   const fs::path& histogram, long long exact_zeros) {
  // gnuplot runs in `dir`: the script names files by their (sanitized) names; titles go through gpString
  const std::string data_name = gpString(data.filename().string());
  const std::string histogram_name = gpString(histogram.filename().string());
  // one curve per comparison: its column `first + 2 c` of `file` (rotation first, translation second)
  auto curves = [&](const std::string& file, const char* x, size_t first, const char* style) {
    for (size_t c = 0; c < r.comparisons.size(); ++c) {
      gp << (c ? ", " : "") << file << " using " << x << ":" << first + 2 * c << " with " << style << " title "
         << gpString(r.comparisons[c].name);
    }
  };
  // the multiplot's two panels: rotation (after `rotation_setup`), then translation / L (after `translation_setup`)
  auto panels = [&](const char* rotation_setup, const char* translation_setup, const std::string& file, const char* x,
                    const char* style) {
    gp << rotation_setup << "plot ";
    curves(file, x, 2, style);
    gp << "\n" << translation_setup << "plot ";
    curves(file, x, 3, style);
    gp << "\nunset multiplot\n";
  };
  gp << "set terminal pngcairo noenhanced size 1200,800 font ',10'\n"
     << "set output " << gpString(base + "_errors.png") << "\n"
     << "set multiplot layout 2,1 title " << gpString(r.scenario.name + ": error against MuJoCo, " + plotted(r) +
                                                     " (L = " + shortest(r.size) + ")" +
                                                     (exact_zeros > 0 ? "; " + std::to_string(exact_zeros) +
                                                                            " errors exactly 0, not drawn (log axis)"
                                                                      : std::string())) << "\n"
     << "set logscale y\nset format y '1e%L'\nset yrange [1e-18:1e-9]\nset key top left\nset grid\n";
  panels("set ylabel 'rotation error (rad)'\n", "set ylabel 'translation error / L'\nset xlabel 'sample'\n", data_name,
         "1", "points pt 7 ps 0.3");
  // histogram of log10(error), every sample
  gp << "set output " << gpString(base + "_histogram.png") << "\n"
     << "set multiplot layout 1,2 title " << gpString(r.scenario.name + ": distribution of log10(error), all " +
                                                     std::to_string(r.samples) + " samples") << "\n"
     << "unset logscale y\nset format y '%g'\nset yrange [0:*]\nset xrange [-18:-9]\nset style fill transparent solid 0.4\n"
     << "set boxwidth 0.1\nset ylabel 'samples'\n";
  panels("set xlabel 'log10 rotation error (rad)'\n", "set xlabel 'log10 translation error / L'\n", histogram_name,
         "($1 + 0.05)", "boxes");
}

// log10 sigma_min over the map's two joints, the other joints fixed.
void singularityMapPicture(const fs::path& dir, const ScenarioResult& r, const std::string& base,
                           std::ostringstream& gp) {
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

// Wu et al. Fig. 4: the position error of every validation pose of calibration case k before and after
// calibration; then its residuals.
void calibrationPicture(const fs::path& dir, const ScenarioResult& r, size_t k, const std::string& base,
                        std::ostringstream& gp) {
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

// Runs the script and checks every picture it was to draw.
void runScript(const fs::path& dir, const ScenarioResult& r, const std::string& base, const std::string& script_text) {
  const std::string script = base + ".gnuplot";
  writeChecked(dir / script, script_text);
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

void plots(const fs::path& dir, const ScenarioResult& r) {
  const std::string base = safe(r.scenario.name);
  const fs::path data = dir / (base + "_errors.dat");
  const long long exact_zeros = writeErrorData(data, r);
  const fs::path histogram = dir / (base + "_histogram.dat");
  writeHistogramData(histogram, r);
  std::ostringstream gp;
  errorPictures(gp, r, base, data, histogram, exact_zeros);
  if (r.map_size > 0) singularityMapPicture(dir, r, base, gp);
  for (size_t k = 0; k < r.calibrations.size(); ++k) calibrationPicture(dir, r, k, base, gp);
  runScript(dir, r, base, gp.str());
}

}  // namespace lowpair::validation::detail
