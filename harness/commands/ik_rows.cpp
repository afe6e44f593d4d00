// The rows of `ik` and `compensate` for the CLI and the Python module (ik_rows.hpp).
#include "commands/ik_rows.hpp"

#include <array>
#include <cmath>

#include "io/output.hpp"
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

std::vector<IkRow> compensateJointRows(const PoeModel& nominal, const PoeModel& calibrated,
                                       const Eigen::Ref<const MatX>& q_nominal, const std::vector<long long>& lines,
                                       const IkOptions& options) {
  Data data(calibrated);
  IkWorkspace work(calibrated);
  std::vector<IkRow> rows;
  rows.reserve(static_cast<size_t>(q_nominal.rows()));
  for (Eigen::Index k = 0; k < q_nominal.rows(); ++k) {
    pollInterrupt();
    rows.push_back({compensate(nominal, calibrated, data, q_nominal.row(k).transpose(), options, work), -1,
                    lines[static_cast<size_t>(k)]});
  }
  return rows;
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

}  // namespace lowpair::commands
