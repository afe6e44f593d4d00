// lowpair validate [SCENARIO.yaml... | MODEL --tip NAME [--base NAME] [--robot FILE]...] [options]
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/commands.hpp"
#include "io/output.hpp"
#include "validation/report.hpp"
#include "validation/validate.hpp"

#ifndef LOWPAIR_SOURCE_DIR
#define LOWPAIR_SOURCE_DIR "."
#endif

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below
using namespace lowpair::mujoco;
using namespace lowpair::commands;
using namespace lowpair::validation;

namespace fs = std::filesystem;

namespace {
std::vector<std::string> defaultScenarios() {
  for (const fs::path& dir : {fs::path("scenarios"), fs::path(LOWPAIR_SOURCE_DIR) / "scenarios"}) {
    if (!fs::is_directory(dir)) continue;
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().extension() == ".yaml") out.push_back(e.path().string());
    }
    std::sort(out.begin(), out.end());
    if (!out.empty()) return out;
  }
  throw UsageError("validate", "no scenario given and no scenarios/*.yaml found");
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// validate's options as parsed
struct ValidateOptions {
  std::vector<std::string> inputs, robots;
  std::string tip, base, shard = "1/1", report, length_unit, tolerance;
  int samples = -1, threads = 0;
  long long seed = -1;
  bool as_json = false;
};

// --shard K/N into the run options
void readShard(const std::string& shard, RunOptions& options) {
  int k = 0, n = 0;
  char slash = 0;
  std::istringstream in(shard);
  if (!(in >> k >> slash >> n) || slash != '/' || k < 1 || n < 1 || k > n || !in.eof()) {
    throw UsageError("--shard", "expected K/N with 1 <= K <= N, got '" + shard + "'");
  }
  options.shard = k;
  options.shards = n;
}

// The scenarios to run: one model file with --tip (model mode), or scenario files (default: scenarios/*.yaml)
std::vector<Scenario> scenariosOf(const ValidateOptions& o) {
  std::vector<Scenario> scenarios;
  const bool model_mode = o.inputs.size() == 1 && (endsWith(o.inputs[0], ".xml") || endsWith(o.inputs[0], ".urdf"));
  if (model_mode) {
    if (o.tip.empty()) {
      throw UsageError(o.inputs[0], "--tip NAME is required with a model file; " + mujoco::tipCandidates(o.inputs[0]));
    }
    Scenario s;
    s.name = fs::path(o.inputs[0]).stem().string();
    s.model = o.inputs[0];
    s.tip = o.tip;
    s.base = o.base;
    s.robot_files = o.robots;
    if (!o.length_unit.empty()) {
      if (!metresPerUnit(o.length_unit)) {
        throw UsageError("--length-unit", "'" + o.length_unit + "' is not one lowpair converts (m, mm, cm, dm, um, km, in, ft)");
      }
      if (endsWith(o.inputs[0], ".urdf") && o.length_unit != "m") {
        throw UsageError("--length-unit", "a URDF is in metres (URDF fixes its unit)");
      }
      s.length_unit = o.length_unit;
    }
    if (!o.tolerance.empty()) {
      double pos = 0, rot = 0;
      char comma = 0;
      std::istringstream in(o.tolerance);
      if (!(in >> pos >> comma >> rot) || comma != ',' || !in.eof() || !(pos > 0) || !(rot > 0) ||
          !std::isfinite(pos) || !std::isfinite(rot)) {
        throw UsageError("--tolerance", "expected POS,ROT, two positive numbers, got '" + o.tolerance + "'");
      }
      s.tol_translation = pos;
      s.tol_rotation = rot;
    }
    scenarios.push_back(s);
  } else {
    if (!o.tip.empty() || !o.base.empty() || !o.robots.empty() || !o.length_unit.empty() || !o.tolerance.empty()) {
      throw UsageError("validate", "--tip/--base/--robot/--length-unit/--tolerance go with a model file (.xml or .urdf), "
                                   "not scenarios (a scenario states them as keys)");
    }
    const auto files = o.inputs.empty() ? defaultScenarios() : o.inputs;
    for (const auto& f : files) {
      if (!endsWith(f, ".yaml") && !endsWith(f, ".yml")) {
        throw UsageError(f, "expected scenario files (.yaml) or one model (.xml/.urdf)");
      }
      scenarios.push_back(readScenario(f));
    }
  }
  return scenarios;
}

}  // namespace

void addValidateCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<ValidateOptions>();
  auto* v = app.add_subcommand("validate", "compare the library against MuJoCo over random samples (exit 1 on a failure)");
  v->add_option("INPUT", o->inputs, "scenario files (.yaml), or one model (.xml MJCF / .urdf) with --tip; "
                                    "default: every scenarios/*.yaml");
  v->add_option("--tip", o->tip, "model mode: tip site or body");
  v->add_option("--base", o->base, "model mode: base body (default: the world)");
  v->add_option("--robot", o->robots, "model mode: robot file(s) to cross-check against the model");
  v->add_option("--length-unit", o->length_unit,
                "model mode: the MJCF's length unit (m, mm, cm, ...); robot files in another unit are converted");
  v->add_option("--tolerance", o->tolerance,
                "model mode: POS,ROT pose tolerances (translation relative to L, rotation in rad; default 1e-12,1e-12)");
  v->add_option("--samples", o->samples, "random samples per scenario (default: the scenario's, else 10000)")
      ->check(CLI::Range(0, kMaxSamples));
  // seeds are whole numbers in [0, 2^53], as in scenario files (a larger value used to be clamped silently)
  v->add_option("--seed", o->seed, "seed in [0, 2^53] (default: the scenario's)")
      ->check(CLI::Range(0LL, kMaxSeed));
  v->add_option("--threads", o->threads, "threads, at most 256 (default: all cores; results do not depend on it)")
      ->check(CLI::Range(0, kMaxThreads));
  v->add_option("--shard", o->shard, "K/N: run the K-th of N disjoint slices of the sample stream");
  v->add_flag("--json", o->as_json, "print JSON instead of the table");
  v->add_option("--report", o->report, "write report.json, summary.md and pictures to this folder");
  commands.emplace_back(v, [o] {
    RunOptions options;
    if (o->samples >= 0) options.samples = o->samples;
    if (o->seed >= 0) options.seed = static_cast<unsigned long long>(o->seed);
    options.threads = o->threads;
    options.singularity_map = !o->report.empty();
    readShard(o->shard, options);
    const std::vector<Scenario> scenarios = scenariosOf(*o);
    std::vector<ScenarioResult> results;
    bool warned = false;
    for (const auto& s : scenarios) {
      results.push_back(runScenario(s, options));
      const ScenarioResult& r = results.back();
      if (r.threads < r.threads_requested && !warned) {
        // a thread that could not be created (ulimit -u, no memory for its stack) is not an error: the
        // others took its samples, and the results do not depend on the thread count. One line per run.
        std::cerr << "warning: only " << r.threads << " of " << r.threads_requested
                  << " worker threads could be started; ran on " << r.threads
                  << " (the results do not depend on the thread count)\n";
        warned = true;
      }
    }
    bool pass = true;
    for (const auto& r : results) pass = pass && r.pass;
    // the report first: if it cannot be written, the run fails with nothing printed
    if (!o->report.empty()) writeReport(o->report, results, options);
    if (o->as_json) {
      std::cout << jsonText(validationJson(results, options)) << "\n";
    } else {
      printValidationTable(std::cout, results);
      for (const auto& r : results) {
        std::cout << "  " << r.scenario.name << ": " << r.samples << " samples in " << r.seconds << " s ("
                  << static_cast<long>(r.samples / std::max(r.seconds, 1e-9)) << " samples/s)\n";
      }
      if (!o->report.empty()) std::cout << "report: " << o->report << "/summary.md\n";
    }
    return pass ? 0 : 1;
  });
}

}  // namespace lowpair::cli
