// lowpair.plan (`lowpair plan`) and the class Plan.
#include <cmath>
#include <optional>
#include <string>

#include "common.hpp"
#include "expose.hpp"
#include "io/output.hpp"
#include "lowpair/plan.hpp"
#include "robot.hpp"
#include "commands/plan_report.hpp"
#include "commands/sampling.hpp"

namespace lowpair::python {

namespace {

// ----- plan (lowpair/plan.hpp; `lowpair plan`, cli/plan_command.cpp) ---------------------------------------

// The JSON of `plan --json` without --out (the planned joint vectors are q), kept beside the report.
struct PlanOutcome {
  commands::PlanReport report;
  json j;
};

PlanOutcome plan(const Robot& r, int poses, int candidate_count, const std::string& measure_text,
                 const std::string& criterion_text, long long seed, std::optional<double> noise_position,
                 std::optional<double> noise_rotation, bool free_pitch, const std::optional<py::object>& model,
                 std::optional<std::string> tip, std::optional<std::string> base, std::optional<double> floor,
                 const std::optional<py::dict>& ranges, double range_margin,
                 const std::optional<std::vector<double>>& tracker, double smr_angle, bool partial) {
  // the checks the CLI's parser makes (CLI::Range, CLI::IsMember); the rest are the report's
  if (poses < 1 || poses > commands::kMaxPlanPoses) {
    throw UsageError("poses", "must be in [1, " + std::to_string(commands::kMaxPlanPoses) + "], got " +
                                  std::to_string(poses));
  }
  if (candidate_count < 1 || candidate_count > commands::kMaxPlanCandidates) {
    throw UsageError("candidates", "must be in [1, " + std::to_string(commands::kMaxPlanCandidates) + "], got " +
                                       std::to_string(candidate_count));
  }
  checkSeed(seed);
  if (criterion_text != "D" && criterion_text != "O1") {
    throw UsageError("criterion", "expected 'D' or 'O1', got " + io::quotedFileText(criterion_text));
  }
  commands::PlanRequest request;
  request.measure = commands::parseMeasure(measure_text, pythonSpelling());
  request.criterion = criterion_text == "O1" ? PlanCriterion::O1 : PlanCriterion::D;
  request.poses = poses;
  request.candidates = candidate_count;
  request.seed = seed;
  request.free_pitch = free_pitch;
  request.noise_position = noise_position;
  request.noise_rotation = noise_rotation;
  commands::FeasibilityRequest& f = request.feasibility;
  if (model && !model->is_none()) {
    f.model = pathArgument(*model);
    if (!tip) throw UsageError("tip", "is required with model= (the chain's tip: a site or body / a link)");
    f.tip = *tip;
    f.base = base.value_or("");
  } else if (tip || base) {
    throw UsageError(tip ? "tip" : "base", "goes with model= (the model checked for contacts)");
  }
  f.floor = floor;
  f.range_margin = range_margin;
  if (tracker) {
    if (tracker->size() != 3) {
      throw UsageError("tracker", "expected (x, y, z) (base frame, length_unit), got " + std::to_string(tracker->size()) +
                                      " numbers");
    }
    f.tracker = Vec3((*tracker)[0], (*tracker)[1], (*tracker)[2]);
  } else if (partial) {
    throw UsageError("partial", "goes with tracker= (the tracker whose line of sight hides targets)");
  }
  f.smr_angle_deg = smr_angle;
  f.partial = partial;
  if (ranges) {
    // {joint: (lo, hi)}: joint a 1-based index or a joint's name, as the CLI's --range J:LO:HI
    for (const auto& [key, value] : *ranges) {
      commands::RangeOverride o;
      o.joint = py::isinstance<py::str>(key) ? key.cast<std::string>() : std::to_string(key.cast<long long>());
      const auto bounds = value.cast<std::pair<double, double>>();
      if (!(std::isfinite(bounds.first) && std::isfinite(bounds.second))) {
        throw UsageError("ranges", o.joint + ": LO and HI must be finite numbers");
      }
      if (!(bounds.first < bounds.second)) throw UsageError("ranges", o.joint + ": LO must be below HI");
      o.lo = bounds.first;
      o.hi = bounds.second;
      f.ranges.push_back(o);
    }
  }
  PlanOutcome o;
  takeLoaderNotes();
  {
    py::gil_scoped_release release;
    o.report = commands::makePlanReport(r.file, request, pythonSpelling());
  }
  for (const std::string& note : takeLoaderNotes()) warnUser(note);
  if (o.report.feasibility && !o.report.feasibility->note.empty()) warnUser(o.report.feasibility->note);
  o.j = commands::planJson(o.report, "");
  return o;
}

}  // namespace

void exposePlan(py::module_& m) {
  py::class_<PlanOutcome>(m, "Plan", "lowpair.plan(...): the result of `lowpair plan`.")
      .def("to_dict", [](const PlanOutcome& p) { return toPython(p.j); },
           "to_dict() -> dict: the content of `lowpair plan --json` (out is None: the planned joint vectors are q).")
      .def_property_readonly("indices", [](const PlanOutcome& p) { return p.report.plan.indices; },
                             "list[int]: the chosen candidates (0-based sample indices of the stream `seed`), "
                             "increasing.")
      .def_property_readonly(
          "q",
          [](const PlanOutcome& p) {
            const std::vector<VecX>& q = p.report.q;
            return vectorRows(q, q.empty() ? 0 : q.front().size(), [](const VecX& x) -> const VecX& { return x; });
          },
          "(N, n): the planned joint vectors in index order (what `plan --out` writes; rad / length_unit).")
      .def_property_readonly("criterion", [](const PlanOutcome& p) { return planCriterionName(p.report.plan.criterion); },
                             "'D' or 'O1'.")
      .def_property_readonly("log_det", [](const PlanOutcome& p) { return p.report.plan.value.log_det; },
                             "log det of the planned set's information (-inf when it does not determine every "
                             "direction the candidates do).")
      .def_property_readonly("o1", [](const PlanOutcome& p) { return p.report.plan.value.o1; },
                             "Sun & Hollerbach's O1 of the planned set.")
      .def_property_readonly("greedy", [](const PlanOutcome& p) { return toPython(p.j["greedy"]); },
                             "dict log_det, O1, rank, criterion of the greedy set before the exchanges.")
      .def_property_readonly("random", [](const PlanOutcome& p) { return toPython(p.j["random"]); },
                             "dict: median and best log_det and O1 of 100 random sets of N of the same candidates.")
      .def_property_readonly("rank", [](const PlanOutcome& p) { return p.report.plan.rank.rank; },
                             "Rank of the planned set's identification Jacobian (the rank rule).")
      .def_property_readonly("expected", [](const PlanOutcome& p) { return p.report.plan.expected.total(); },
                             "The count 5h + 4r + 2t + n + 6 (+ 3, + 3k).")
      .def_property_readonly("candidate_rank", [](const PlanOutcome& p) { return p.report.plan.candidate_rank; },
                             "Directions all candidates together determine.")
      .def_property_readonly("swaps", [](const PlanOutcome& p) { return p.report.plan.swaps; }, "Exchanges made (int).")
      .def_property_readonly("parameters", [](const PlanOutcome& p) { return toPython(p.j["parameters"]); },
                             "list[str]: the parameter names (columns).")
      .def_property_readonly(
          "standard_deviation",
          [](const PlanOutcome& p) { return vectorArray(p.report.expected->calibration.standard_deviation); },
          "(p,): each parameter's expected standard deviation after calibrating on the plan with the noise `noise` "
          "(parameter units; inf when undetermined).")
      .def_property_readonly("dh", [](const PlanOutcome& p) { return toPython(p.j["standard_deviations"]["dh"]); },
                             "dict: the nominal's D-H table with its expected standard deviations.")
      .def_property_readonly("noise", [](const PlanOutcome& p) { return toPython(p.j["noise"]); },
                             "dict position (length_unit), rotation (rad or None), source: the noise assumed.")
      .def_property_readonly("measured", [](const PlanOutcome& p) { return toPython(p.j["measured"]); },
                             "list[list[str]] | None: with tracker=, per planned pose the names of the targets it "
                             "measures (every target unless partial=True).")
      .def_property_readonly("undetermined", [](const PlanOutcome& p) { return toPython(p.j["undetermined"]); },
                             "list of directions the plan does not determine, each a list of {parameter, "
                             "coefficient}.")
      .def("__repr__", [](const PlanOutcome& p) {
        return "<lowpair.Plan " + std::to_string(p.report.plan.indices.size()) + " poses, rank " +
               std::to_string(p.report.plan.rank.rank) + " of " + std::to_string(p.report.plan.expected.total()) + ", log det " +
               io::shortest(p.report.plan.value.log_det) + ">";
      });
  m.def("plan", &plan, py::arg("robot"), py::arg("poses"), py::arg("candidates") = 5000, py::arg("measure") = "pose",
        py::arg("criterion") = "D", py::arg("seed") = 1, py::arg("noise_position") = py::none(),
        py::arg("noise_rotation") = py::none(), py::arg("free_pitch") = false, py::kw_only(),
        py::arg("model") = py::none(), py::arg("tip") = py::none(), py::arg("base") = py::none(),
        py::arg("floor") = py::none(), py::arg("ranges") = py::none(), py::arg("range_margin") = 0.0,
        py::arg("tracker") = py::none(), py::arg("smr_angle") = commands::kDefaultSmrAngleDeg, py::arg("partial") = false,
        "plan(robot, poses, candidates=5000, measure='pose', criterion='D', seed=1, noise_position=None,\n"
        "     noise_rotation=None, free_pitch=False, *, model=None, tip=None, base=None, floor=None, ranges=None,\n"
        "     range_margin=0.0, tracker=None, smr_angle=30.0, partial=False) -> Plan\n\n"
        "`lowpair plan`: choose `poses` (N <= 1000) calibration poses of `candidates` (M <= 100000) random joint\n"
        "vectors (samples 0..M-1 of the stream `seed`) maximizing log det of the identification information\n"
        "(greedy, then exchanges; criterion 'D' or 'O1' only changes the number reported), compare with 100\n"
        "random sets of N, and predict every parameter's and D-H number's standard deviation after calibrating\n"
        "on the plan with the given noise (length_unit, rad; default 1e-5 L and 1e-5 rad). measure: 'pose',\n"
        "'position' or 'targets' (the robot file's targets). The GIL is released while planning.\n\n"
        "Feasible plans (docs/plan.md): model (an MJCF/URDF path; tip, base its chain) keeps only candidates\n"
        "MuJoCo finds free of contacts, floor (z of the base frame, length_unit) adds a floor plane; ranges\n"
        "{joint: (lo, hi)} (joint a 1-based index or a name; the robot file's units) and range_margin narrow\n"
        "the sampled ranges. tracker (x, y, z: base frame, length_unit; measure='targets') keeps only candidates\n"
        "whose SMRs the tracker sees (no geom on the ray, within smr_angle degrees of a target's normal);\n"
        "partial=True keeps poses that see some targets and measures only those (Plan.measured).\n"
        "Too few feasible candidates raise lowpair.Error (the CLI's exit 1).");
}

}  // namespace lowpair::python
