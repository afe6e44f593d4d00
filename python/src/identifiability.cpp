// lowpair.identifiability (`lowpair identifiability`) and the class Identifiability.
#include <string>
#include <utility>
#include <vector>

#include "common.hpp"
#include "expose.hpp"
#include "io/output.hpp"
#include "lowpair/calibration.hpp"
#include "robot.hpp"
#include "commands/calibration_output.hpp"
#include "commands/sampling.hpp"
#include "commands/simulation.hpp"

namespace lowpair::python {

namespace {



struct IdentifiabilityResult {
  Identifiability id;
  json j;
};

IdentifiabilityResult identifiability(const Robot& r, const std::string& measure_text, int poses, long long seed,
                                      bool free_pitch) {
  const Measure measure = commands::parseMeasure(measure_text, pythonSpelling());
  if (poses < 1 || poses > commands::kMaxIdentifiabilityPoses) {
    throw UsageError("poses", "must be in [1, " + std::to_string(commands::kMaxIdentifiabilityPoses) + "], got " +
                                  std::to_string(poses));
  }
  checkSeed(seed);
  const PoeModel& model = r.poe;
  const int targets = measure == Measure::Targets ? static_cast<int>(r.file.targets.size()) : 0;
  if (const auto problem = commands::identifiabilitySizeProblem(poses, model.dof(), measure, targets)) {
    throw UsageError(problem->robot ? r.file.path : std::string("poses"), problem->text);
  }
  ErrorModelSpec spec;
  spec.free_pitch = free_pitch;
  if (measure == Measure::Targets) {
    spec.targets = commands::numberedRobotFileTargets(r.file, pythonSpelling());  // known points: the tool's columns
  }
  Identifiability id;
  {
    py::gil_scoped_release release;
    const auto ranges = commands::samplingRanges(model);
    std::vector<VecX> q(static_cast<size_t>(poses), VecX(model.dof()));
    for (int i = 0; i < poses; ++i) {
      commands::randomSample(static_cast<unsigned long long>(seed), static_cast<unsigned long long>(i), ranges,
                               q[static_cast<size_t>(i)]);
    }
    id = analyzeIdentifiability(model, q, measure, spec);
  }
  json j = commands::identifiabilityJson(r.file, id);
  j["poses"] = poses;
  j["seed"] = seed;
  return IdentifiabilityResult{std::move(id), std::move(j)};
}

}  // namespace

void exposeIdentifiability(py::module_& m) {
  py::class_<IdentifiabilityResult>(m, "Identifiability", "lowpair.identifiability(...): `lowpair identifiability`.")
      .def("to_dict", [](const IdentifiabilityResult& i) { return toPython(i.j); },
           "to_dict() -> dict: the content of `lowpair identifiability --json`.")
      .def_property_readonly("rank", [](const IdentifiabilityResult& i) { return i.id.poe.rank; },
                             "Rank of the identification Jacobian (minimal POE parameters).")
      .def_property_readonly("expected", [](const IdentifiabilityResult& i) { return i.id.expected.total(); },
                             "The count 5h + 4r + 2t + n + 6 (or + 3 / + 3k).")
      .def_property_readonly("columns", [](const IdentifiabilityResult& i) { return i.id.poe.columns; },
                             "Columns of the identification Jacobian: the minimal POE parameters (int).")
      .def_property_readonly("condition", [](const IdentifiabilityResult& i) { return i.id.poe.condition; },
                             "sigma_1 / sigma_min of the scaled Jacobian (inf when rank deficient).")
      .def_property_readonly("singular_values", [](const IdentifiabilityResult& i) { return vectorArray(i.id.poe.singular_values); },
                             "(columns,) descending singular values of the scaled identification Jacobian (position "
                             "rows over L, columns of unit norm).")
      .def_property_readonly("observability",
                             [](const IdentifiabilityResult& i) {
                               return std::vector<double>(i.id.poe.observability.begin(), i.id.poe.observability.end());
                             },
                             "[O1, O2, O3, O4, O5] (Sun & Hollerbach).")
      .def_property_readonly("full_model_rank", [](const IdentifiabilityResult& i) { return i.id.full_model_rank; },
                             "Rank of the redundant error model (6 per joint, pitch, scale, offset, 6 for the tool): "
                             "the paper's 'at most', equal to `expected`.")
      .def_property_readonly("dh_rank", [](const IdentifiabilityResult& i) { return i.id.dh.rank; },
                             "Rank of the D-H parameterization of the same robot (poeToDh).")
      .def_property_readonly("dh_columns", [](const IdentifiabilityResult& i) { return i.id.dh.columns; },
                             "Columns of the D-H parameterization: base theta, d, alpha, a; per joint theta, d, "
                             "alpha, a (+ pitch) + scale; tool theta, d.")
      .def_property_readonly(
          "parameters",
          [](const IdentifiabilityResult& i) {
            std::vector<std::string> names;
            for (const Parameter& p : i.id.parameters) names.push_back(p.name);
            return names;
          },
          "list[str]: the parameter names ('j3.tilt1', 'tool.z', ...).")
      .def("__repr__", [](const IdentifiabilityResult& i) {
        return "<lowpair.Identifiability rank " + std::to_string(i.id.poe.rank) + " of " +
               std::to_string(i.id.expected.total()) + ">";
      });
  m.def("identifiability", &identifiability, py::arg("robot"), py::arg("measure") = "pose", py::arg("poses") = 50,
        py::arg("seed") = 1, py::arg("free_pitch") = false,
        "identifiability(robot, measure='pose', poses=50, seed=1, free_pitch=False) -> Identifiability\n\n"
        "`lowpair identifiability`: the rank of the identification Jacobian at `poses` random joint vectors (the\n"
        "CLI's seeded stream: equal numbers for equal seeds) against the count 5h + 4r + 2t + n + 6.\n"
        "measure: 'pose', 'position' or 'targets' (the robot file's targets).");
}

}  // namespace lowpair::python
