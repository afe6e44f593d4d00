// The summary table `lowpair validate` prints (report.hpp printValidationTable).
#include "validation/report.hpp"

#include <cstdio>

#include "io/output.hpp"
#include "lowpair/se3.hpp"

namespace lowpair::validation {

namespace {

// The compensation cases: before and after on MuJoCo's actual robot, the rows not ok with their reasons
void printCompensationTable(std::ostream& out, const std::vector<ScenarioResult>& results) {
  char line[400];
  bool header = false;
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
      const std::string task = (k.point_name.empty() ? std::string(measureName(k.measure)) : k.point_name) + (k.base_frame ? "*" : "");
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
      if (k.base_frame) {
        std::snprintf(line, sizeof line, "%.4g length, %.4g rad", k.rigid_after.p.norm(), rotationAngle(k.rigid_after.R));
        out << "  * in the nominal's base frame (calibrate --out's robot), up to the actual's base error: " << line << "\n";
      }
      if (!k.tool_determined) out << "  the tool frame was not determined (targets at unknown points): the task is " << k.point_name << "'s point\n";
    }
  }
  if (header) {
    out << "(compensation: MuJoCo's tool commanded at the validation q (before) and at the compensated q' (after, ok "
           "rows only) against the nominal's FK at q; position in the nominal's length unit, rotation RMS in rad; "
           "base frame: up to the rigid motion of the actual's base)\n";
  }
}

}  // namespace

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
  printCompensationTable(out, results);
  out << (pass ? "all comparisons within tolerance" : "FAILED: a comparison is outside its tolerance (marked FAIL)")
      << "  (rotation in rad; translation relative to the robot size L; Jacobian rows: angular block as 'rot', "
         "linear as 'tr')\n";
}

}  // namespace lowpair::validation
