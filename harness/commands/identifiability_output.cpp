// `lowpair identifiability`: its text and JSON (calibration_output.hpp), and the undetermined directions in words.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "commands/calibration_output.hpp"
#include "commands/calibration_output_parts.hpp"
#include "io/output.hpp"

namespace lowpair::commands {

using namespace lowpair::io;  // the rooms below
using namespace detail;

using nlohmann::json;

namespace {

void printUndetermined(std::ostream& out, const std::string& what, const RankAnalysis& a,
                       const std::vector<std::string>& names) {
  if (a.undetermined.empty()) {
    out << what << ": every parameter is determined\n";
    return;
  }
  out << what << ": " << a.undetermined.size() << " direction(s) not determined (null vectors of the column-scaled "
      << "Jacobian):\n";
  for (size_t k = 0; k < a.undetermined.size(); ++k) {
    out << "  " << k + 1 << ": " << directionText(a.undetermined[k], names) << "\n";
  }
}

}  // namespace

std::string directionText(const std::vector<std::pair<int, double>>& direction, const std::vector<std::string>& names) {
  constexpr size_t kMaxTerms = 6;
  auto terms = direction;
  std::sort(terms.begin(), terms.end(), [](const auto& a, const auto& b) { return std::abs(a.second) > std::abs(b.second); });
  std::ostringstream s;
  for (size_t k = 0; k < terms.size() && k < kMaxTerms; ++k) {
    const double c = terms[k].second;
    s << (k == 0 ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ")) << fixed(std::abs(c), 2) << " "
      << names[static_cast<size_t>(terms[k].first)];
  }
  if (terms.size() > kMaxTerms) s << " + ... (" << terms.size() - kMaxTerms << " more)";
  return s.str();
}

json identifiabilityJson(const RobotFile& file, const Identifiability& id) {
  const std::vector<std::string> names = parameterNames(id.parameters);
  json o;
  auto obs = json::object();
  for (int k = 0; k < 5; ++k) obs["O" + std::to_string(k + 1)] = id.poe.observability[static_cast<size_t>(k)];
  o["name"] = robotLabel(file);
  o["source"] = file.path;
  o["measure"] = measureName(id.measure);
  o["free_pitch"] = id.free_pitch;
  o["joints"] = countJson(id.expected);
  o["expected"] = id.expected.total();
  o["rank"] = id.poe.rank;
  o["parameters"] = names;
  o["singular_values"] = toVector(id.poe.singular_values);
  o["rank_tolerance"] = id.poe.tolerance;
  o["condition"] = finiteOrNull(id.poe.condition);
  o["observability"] = obs;
  o["undetermined"] = undeterminedJson(id.poe, names);
  o["full_model"] = {{"rank", id.full_model_rank}, {"columns", id.full_model_columns}};
  o["dh"] = {{"rank", id.dh.rank},
             {"condition", finiteOrNull(id.dh.condition)},
             {"parameters", id.dh_parameters},
             {"singular_values", toVector(id.dh.singular_values)},
             {"undetermined", undeterminedJson(id.dh, id.dh_parameters)}};
  return o;
}

void printIdentifiability(std::ostream& out, const Identifiability& id) {
  const std::vector<std::string> names = parameterNames(id.parameters);
  auto cond = [](double c) { return std::isfinite(c) ? fixed(c, 2) : std::string("inf"); };
  out << "expected (Wu et al. §V):  " << countFormula(id.expected) << (id.free_pitch ? "  (free pitch: revolute counted as helical)" : "") << "\n";
  out << "POE, minimal parameters:  rank " << id.poe.rank << " of " << id.poe.columns << ", condition "
      << cond(id.poe.condition) << "\n";
  out << "POE, full error model:    rank " << id.full_model_rank << " of " << id.full_model_columns
      << " columns (6 per joint + pitch + scale + offset, 6 tool" << (id.expected.deflections ? " + one per deflection" : "")
      << ": redundant by construction)\n";
  out << "D-H parameterization:     rank " << id.dh.rank << " of " << id.dh.columns << ", condition "
      << cond(id.dh.condition) << "\n";
  out << "observability (POE):      O1 " << deviation(id.poe.observability[0]) << "  O2 "
      << deviation(id.poe.observability[1]) << "  O3 " << deviation(id.poe.observability[2]) << "  O4 "
      << deviation(id.poe.observability[3]) << "  O5 " << deviation(id.poe.observability[4]) << "\n";
  out << "rank rule: singular values of the column-scaled Jacobian (position rows / L) above 1000 cols eps sigma_1 "
         "(POE: "
      << deviation(id.poe.tolerance) << "); smallest POE " << deviation(id.poe.singular_values.minCoeff())
      << ", D-H " << deviation(id.dh.singular_values.minCoeff()) << "\n";
  printUndetermined(out, "POE", id.poe, names);
  printUndetermined(out, "D-H", id.dh, id.dh_parameters);
}

}  // namespace lowpair::commands
