// The rows of `ik` and `compensate` for the CLI and the Python module (ik_rows.hpp).
#include "commands/ik_rows.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "commands/deflection_inputs.hpp"
#include "io/output.hpp"
#include "lowpair/deflection.hpp"
#include "lowpair/interrupt.hpp"

namespace lowpair::commands {

using nlohmann::json;

bool betterIkAttempt(const IkResult& a, const IkResult& b, double L) {
  auto rank = [](const IkResult& r) { return r.status == IkStatus::Ok ? 0 : r.converged ? 1 : 2; };
  if (rank(a) != rank(b)) return rank(a) < rank(b);
  return a.position_error / L + a.rotation_error < b.position_error / L + b.rotation_error;
}

IkRow solveFromRandomSeeds(const PoeModel& model, Data& data, const Pose& target, size_t row, int seeds,
                           unsigned long long seed, const std::vector<Range>& ranges, const IkOptions& options,
                           IkWorkspace& work, long long line) {
  IkRow best;
  best.line = line;
  bool have = false;
  VecX q_seed(model.dof());
  for (int s = 0; s < seeds; ++s) {
    pollInterrupt();  // every attempt: up to 1000 seeds of a row
    randomSample(seed, row * static_cast<unsigned long long>(seeds) + static_cast<unsigned long long>(s), ranges, q_seed);
    const IkResult& attempt = inverseKinematics(model, data, target, q_seed, options, work);
    if (!have || betterIkAttempt(attempt, best.result, model.lengthScale())) {
      best.result = attempt;
      best.seed = s;
      have = true;
    }
    if (attempt.status == IkStatus::Ok) break;
  }
  return best;
}


namespace {

IkAllSolution fromClosedForm(const ClosedFormSolution& c) {
  IkAllSolution s;
  s.q = c.q;
  s.branch = c.branch;
  s.singular = c.singular;
  s.out_of_range = c.out_of_range;
  s.iterations = c.refinement_iterations;
  s.position_error = c.position_error;
  s.rotation_error = c.rotation_error;
  return s;
}

json branchJson(const IkBranch& b) { return {{"shoulder", b.shoulder}, {"elbow", b.elbow}, {"wrist", b.wrist}}; }

}  // namespace

IkAllRow solveAll(const PoeModel& model, ClosedFormWorkspace* closed, Data& data, IkWorkspace& work, const Pose& target,
                  size_t row, int seeds, unsigned long long seed, const std::vector<Range>& ranges,
                  const IkOptions& options, long long line) {
  IkAllRow out;
  out.line = line;
  if (closed != nullptr) {
    const ClosedFormResult& r = inverseKinematicsAll(model, target, options, *closed);
    for (int k = 0; k < r.count; ++k) out.solutions.push_back(fromClosedForm(r.solutions[static_cast<size_t>(k)]));
    out.dropped = r.dropped;
    return out;
  }
  VecX q_seed(model.dof());
  for (int s = 0; s < seeds; ++s) {
    pollInterrupt();
    randomSample(seed, row * static_cast<unsigned long long>(seeds) + static_cast<unsigned long long>(s), ranges, q_seed);
    const IkResult& r = inverseKinematics(model, data, target, q_seed, options, work);
    if (!r.converged) continue;
    const bool known = std::any_of(out.solutions.begin(), out.solutions.end(),
                                   [&](const IkAllSolution& x) { return jointDistance(model, x.q, r.q) <= kSameSolution; });
    if (known) continue;
    IkAllSolution x;
    x.q = r.q;
    x.singular = r.status == IkStatus::Singular;
    x.out_of_range = r.status == IkStatus::OutOfRange ? r.joint : -1;
    x.iterations = r.iterations;
    x.position_error = r.position_error;
    x.rotation_error = r.rotation_error;
    out.solutions.push_back(x);
  }
  return out;
}

std::string branchUnavailable(const PoeModel& nominal, const PoeModel& calibrated, const IkOptions& options) {
  if (options.measure != Measure::Pose) return "a position task has no branches (infinitely many solutions)";
  const ClosedFormStructure a = closedFormStructure(nominal);
  if (a.kind == ClosedFormKind::None) return "the nominal robot has no closed form (" + a.reason + ")";
  const ClosedFormStructure b = closedFormStructure(calibrated);
  if (b.kind == ClosedFormKind::None) return "the calibrated robot has no closed form (" + b.reason + ")";
  return "";
}

namespace {

// The row of compensateOnBranch's solution s, its branch named.
IkRow branchRow(const ClosedFormSolution& s, long long line) {
  IkRow row;
  row.line = line;
  IkResult& r = row.result;
  r.q = s.q;
  r.iterations = s.refinement_iterations;
  r.position_error = s.position_error;
  r.rotation_error = s.rotation_error;
  r.converged = true;
  r.joint = s.out_of_range;
  r.status = s.out_of_range >= 0 ? IkStatus::OutOfRange : s.singular ? IkStatus::Singular : IkStatus::Ok;
  if (r.status == IkStatus::OutOfRange) {
    r.reason = "the solution on the nominal row's branch has joint " + std::to_string(r.joint + 1) + " outside its range";
  } else if (r.status == IkStatus::Singular) {
    r.reason = "the solution on the nominal row's branch is singular (a free angle or a double root)";
  }
  row.branch = s.branch;
  return row;
}

}  // namespace

std::vector<IkRow> compensateJointRows(const PoeModel& nominal, const PoeModel& calibrated,
                                       const Eigen::Ref<const MatX>& q_nominal, const std::vector<long long>& lines,
                                       const IkOptions& options, bool keep_branch) {
  std::optional<ClosedFormWorkspace> nominal_work, calibrated_work;
  if (keep_branch && branchUnavailable(nominal, calibrated, options).empty()) {
    nominal_work.emplace(nominal);
    calibrated_work.emplace(calibrated);
  }
  Data data(calibrated);
  IkWorkspace work(calibrated);
  std::vector<IkRow> rows;
  rows.reserve(static_cast<size_t>(q_nominal.rows()));
  for (Eigen::Index k = 0; k < q_nominal.rows(); ++k) {
    pollInterrupt();
    const VecX q = q_nominal.row(k).transpose();
    const long long line = lines[static_cast<size_t>(k)];
    const ClosedFormSolution* s =
        nominal_work ? compensateOnBranch(nominal, calibrated, q, options, *nominal_work, *calibrated_work) : nullptr;
    rows.push_back(s ? branchRow(*s, line) : IkRow{compensate(nominal, calibrated, data, q, options, work), -1, line, std::nullopt});
  }
  return rows;
}

json ikAllRowJson(const IkAllRow& row) {
  json solutions = json::array();
  for (const IkAllSolution& s : row.solutions) {
    solutions.push_back({{"q", io::toVector(s.q)},
                         {"branch", s.branch ? branchJson(*s.branch) : json(nullptr)},
                         {"singular", s.singular},
                         {"out_of_range", s.out_of_range >= 0 ? json(s.out_of_range + 1) : json(nullptr)},
                         {"iterations", s.iterations},
                         {"position_error", s.position_error},
                         {"rotation_error", s.rotation_error}});
  }
  return {{"line", row.line}, {"count", row.solutions.size()}, {"dropped", row.dropped}, {"solutions", solutions}};
}

json ikRowJson(const IkRow& row, bool with_seed) {
  const IkResult& r = row.result;
  json j = {{"line", row.line},
            {"q", io::toVector(r.q)},
            {"status", ikStatusName(r.status)},
            {"iterations", r.iterations},
            {"position_error", r.position_error},
            {"rotation_error", r.rotation_error},
            {"rank", r.rank},
            {"sigma_min", io::finiteOrNull(r.sigma_min)},
            {"reason", r.reason}};
  if (with_seed) j["seed"] = row.seed < 0 ? json("file") : json(row.seed);
  if (row.branch) j["branch"] = branchJson(*row.branch);
  return j;
}

json ikCountsJson(const std::vector<IkRow>& rows) {
  std::array<long long, 5> count{};
  for (const IkRow& row : rows) ++count[static_cast<size_t>(row.result.status)];
  json j = json::object();
  for (size_t k = 0; k < count.size(); ++k) j[ikStatusName(static_cast<IkStatus>(k))] = count[k];
  return j;
}

std::string undeterminedToolNote(const io::RobotFile& calibrated, bool pose) {
  const std::string who = calibrated.path.empty() ? std::string("the calibrated robot") : calibrated.path;  // (Python's)
  if (calibrated.tool_frame == io::ToolFrame::Nominal) {
    return "compensated for the flange; the tool frame is the nominal's (" + who +
           " has tool_frame: nominal: its calibration's targets did not determine the tool; give three non-collinear "
           "targets as known to pin it, docs/calibration.md)";
  }
  if (calibrated.tool_frame == io::ToolFrame::Origin && pose) {
    return "the tool's orientation is the nominal's (" + who +
           " has tool_frame: origin: calibrated from position measurements); its origin is compensated";
  }
  return "";
}

bool applyDeflection(const io::RobotFile& calibrated_file, const PoeModel& calibrated, std::vector<IkRow>& rows,
                     const std::vector<VecX>& signs) {
  const JointDeflection applied = appliedDeflection(calibrated_file, !signs.empty());
  if (applied.empty()) return false;
  const MassModel masses = calibrated_file.masses.value_or(MassModel{});
  for (size_t k = 0; k < rows.size(); ++k) {
    IkRow& row = rows[k];
    if (const std::optional<VecX> command = commandFor(calibrated, masses, applied, row.result.q, signs.empty() ? VecX() : signs[k])) {
      row.result.q = *command;
    } else {
      row.result.status = IkStatus::NotConverged;
      row.result.converged = false;
      row.result.reason = "the command under the compliance did not converge (commandFor, docs/calibration.md)";
    }
  }
  return true;
}

}  // namespace lowpair::commands
