// lowpair.ik and lowpair.compensate (`lowpair ik`, `lowpair compensate`) and the class IkSolutions.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "expose.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/ik_closed_form.hpp"
#include "lowpair/kinematics.hpp"
#include "robot.hpp"
#include "commands/ik_rows.hpp"
#include "commands/limits.hpp"
#include "commands/sampling.hpp"

namespace lowpair::python {

namespace {

// ----- inverse kinematics, compensation (lowpair/ik.hpp; `lowpair ik`, `lowpair compensate`) ------------

// The rows of `ik` or `compensate` and the JSON of the CLI's --json (cli/ik_commands.cpp) without its files.
struct IkSolutions {
  std::vector<commands::IkRow> rows;  // line: the 0-based row
  json j;                               // the JSON without "rows": to_dict() builds them when asked (1 KB a row)
  bool with_seed = false;               // ik's rows name their seed, compensate's do not
  Eigen::Index dof = 0;                 // q's columns, also with no rows
};

// The targets of ik: (N, 4, 4) homogeneous transforms, or (N, 3) positions, made poses by rotations (N, 4) qw..qz
// (the targets CSV's columns, converted as its reader converts them).
std::vector<Pose> ikTargets(const InArray& targets, const std::optional<InArray>& rotations, bool& pose) {
  requireAccepted(targets, "", "targets");
  if (rotations) requireAccepted(*rotations, "", "rotations");
  std::vector<Pose> out;
  // (N, 4, 4) transforms, or one (4, 4) transform: a batch of one
  const bool one = targets.ndim() == 2 && targets.shape(0) == 4 && targets.shape(1) == 4;
  if (one || (targets.ndim() == 3 && targets.shape(1) == 4 && targets.shape(2) == 4)) {
    if (rotations) throw UsageError("rotations", "the targets are 4 x 4 transforms: they hold their rotations");
    pose = true;
    // transform k from m(a, c), its entries read through the array's strides (a view may be in any order)
    auto transform = [&](py::ssize_t k, const auto& m) {
      Pose T;
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) T.R(a, c) = m(a, c);
        T.p(a) = m(a, 3);
      }
      if (!(m(3, 0) == 0.0 && m(3, 1) == 0.0 && m(3, 2) == 0.0 && m(3, 3) == 1.0)) {
        throw UsageError("targets", "[" + std::to_string(k) + "]: the last row of a transform must be [0, 0, 0, 1]");
      }
      out.push_back(T);
    };
    if (one) {
      const auto t = targets.unchecked<2>();
      transform(0, [&](py::ssize_t a, py::ssize_t c) { return t(a, c); });
    } else {
      const auto t = targets.unchecked<3>();
      for (py::ssize_t k = 0; k < t.shape(0); ++k) transform(k, [&](py::ssize_t a, py::ssize_t c) { return t(k, a, c); });
    }
  } else if (targets.ndim() == 2 && targets.shape(1) == 3) {
    pose = rotations.has_value();
    const py::ssize_t N = targets.shape(0);
    // rotations: (N, 4) unit quaternions qw..qz, or (N, 3, 3) rotation matrices
    const bool matrices = rotations && rotations->ndim() == 3 && rotations->shape(0) == N &&
                          rotations->shape(1) == 3 && rotations->shape(2) == 3;
    if (rotations && !matrices && (rotations->ndim() != 2 || rotations->shape(0) != N || rotations->shape(1) != 4)) {
      throw UsageError("rotations", "expected shape (" + std::to_string(N) + ", 4) (unit quaternions qw, qx, qy, qz) or (" +
                                        std::to_string(N) + ", 3, 3) (rotation matrices), got shape " + shapeText(*rotations));
    }
    auto t = targets.unchecked<2>();
    for (py::ssize_t k = 0; k < t.shape(0); ++k) {
      Pose T;
      T.p = Vec3(t(k, 0), t(k, 1), t(k, 2));
      if (matrices) {  // checked as a rotation by the solver (kRotationOrthonormal), as a transform's is
        auto m = rotations->unchecked<3>();
        for (int a = 0; a < 3; ++a) {
          for (int c = 0; c < 3; ++c) {
            T.R(a, c) = m(k, a, c);
            if (!std::isfinite(T.R(a, c))) {  // named here: the check below names targets
              throw UsageError("rotations", "[" + std::to_string(k) + ", " + std::to_string(a) + ", " +
                                                std::to_string(c) + "]: '" + io::shortest(T.R(a, c)) + "' is not finite");
            }
          }
        }
      } else if (rotations) {
        auto w = rotations->unchecked<2>();
        T.R = quaternionRotation(w(k, 0), w(k, 1), w(k, 2), w(k, 3), "rotations", k);
      }
      out.push_back(T);
    }
  } else {
    throw UsageError("targets", "expected shape (N, 4, 4) (transforms) or (N, 3) (positions), got shape " +
                                    shapeText(targets));
  }
  for (size_t k = 0; k < out.size(); ++k) {
    if (!out[k].p.allFinite() || !out[k].R.allFinite()) {
      throw UsageError("targets", "[" + std::to_string(k) + "]: not finite");
    }
  }
  return out;
}

// The rows of ik and compensate: at most io::kMaxMeasurements, the CLI's limit (a file holds no more), checked
// before anything is allocated (10^7 rows once grew to 7.7 GB).
void checkRowCount(const InArray& a, const std::string& what) {
  requireAccepted(a, "", what);
  if (a.ndim() >= 2 && a.shape(0) > io::kMaxMeasurements) {
    throw UsageError(what, std::to_string(a.shape(0)) + " rows, more than the " + std::to_string(io::kMaxMeasurements) +
                               " one call takes (the CLI's limit): split the array");
  }
}

// Per-row seeds: None, (n,) for every row, or (N, n).
std::optional<MatX> seedRows(const Robot& r, const std::optional<InArray>& q0, size_t rows) {
  if (!q0) return std::nullopt;
  if (q0->ndim() == 1) {
    const VecX x = jointVector(*q0, r.dof(), r.subject(), "q0", &r.poe);
    return MatX(x.transpose().replicate(static_cast<Eigen::Index>(rows), 1));
  }
  MatX Q = jointMatrix(*q0, r.dof(), r.subject(), "q0", &r.poe);
  if (Q.rows() != static_cast<Eigen::Index>(rows)) {
    throw UsageError("q0", "expected shape (" + std::to_string(rows) + ", " + std::to_string(r.dof()) + ") or (" +
                               std::to_string(r.dof()) + ",), got shape " + shapeText(*q0));
  }
  return Q;
}

// `lowpair ik`: one problem per target, from q0 (the CSV's q columns) or from up to `seeds` random seeds (sample
// k * seeds + s of the stream `seed`, the sampling convention), the first ok kept, else the best attempt.

IkSolutions ik(const Robot& r, const py::object& targets_obj, const std::optional<py::object>& rotations_obj,
               const std::optional<InArray>& q0, int seeds, long long seed) {
  const InArray targets_arg = arrayArgument(targets_obj, "targets");
  std::optional<InArray> rotations;
  if (rotations_obj) rotations = arrayArgument(*rotations_obj, "rotations");
  if (seeds < 1 || seeds > commands::kMaxIkSeeds) {
    throw UsageError("seeds", "must be in [1, " + std::to_string(commands::kMaxIkSeeds) + "], got " +
                                  std::to_string(seeds));
  }
  checkSeed(seed);
  checkRowCount(targets_arg, "targets");
  bool pose = false;
  std::vector<Pose> targets = ikTargets(targets_arg, rotations, pose);
  if (singlePrecision(targets_obj) || (rotations_obj && singlePrecision(*rotations_obj))) {
    for (Pose& T : targets) roundFromSinglePrecision(T);  // the solver's refusal stays for a matrix that is no rotation
  }
  // the solver's work bounded before any row is solved (commands/limits.hpp), as the CLI's
  if (const auto problem = commands::ikWorkProblem(targets.size(), q0 ? 1 : seeds, r.dof(), !q0)) {
    throw UsageError(q0 ? "targets" : "seeds", *problem);
  }
  const std::optional<MatX> given = seedRows(r, q0, targets.size());
  const PoeModel& model = r.poe;
  IkOptions options;
  options.measure = pose ? Measure::Pose : Measure::Position;
  options.validate("inverseKinematics");
  IkSolutions s;
  s.rows.reserve(targets.size());
  {
    py::gil_scoped_release release;
    const std::vector<commands::Range> ranges = commands::samplingRanges(model);
    Data data(model);
    IkWorkspace work(model);
    for (size_t k = 0; k < targets.size(); ++k) {
      const auto line = static_cast<long long>(k);
      try {
        if (given) {
          s.rows.push_back({inverseKinematics(model, data, targets[k], given->row(static_cast<Eigen::Index>(k)).transpose(),
                                              options, work),
                            -1, line, std::nullopt});
        } else {
          s.rows.push_back(commands::solveFromRandomSeeds(model, data, targets[k], k, seeds,
                                                            static_cast<unsigned long long>(seed), ranges, options, work,
                                                            line));
        }
      } catch (const std::invalid_argument& e) {
        throw UsageError("targets", "[" + std::to_string(k) + "]: " + e.what());
      }
    }
  }
  s.j = {{"name", r.file.name},
         {"source", r.file.path},
         {"poses", "<arrays>"},
         {"length_unit", r.file.length_unit},
         {"task", pose ? "pose" : "position"},
         {"seeds", given ? json("file") : json(seeds)},
         {"seed", seed},
         {"notes", json::array()},
         {"counts", commands::ikCountsJson(s.rows)}};
  s.with_seed = true;
  s.dof = r.dof();
  return s;
}

// Every solution of each pose target (`lowpair ik --all`): the rows and the JSON head of its --json.
struct IkAllSolutions {
  std::vector<commands::IkAllRow> rows;  // line: the 0-based row
  json j;
  Eigen::Index dof = 0;
};

IkAllSolutions ikAll(const Robot& r, const py::object& targets_obj, const std::optional<py::object>& rotations_obj,
                     int seeds, long long seed) {
  const InArray targets_arg = arrayArgument(targets_obj, "targets");
  std::optional<InArray> rotations;
  if (rotations_obj) rotations = arrayArgument(*rotations_obj, "rotations");
  if (seeds < 1 || seeds > commands::kMaxIkSeeds) {
    throw UsageError("seeds", "must be in [1, " + std::to_string(commands::kMaxIkSeeds) + "], got " + std::to_string(seeds));
  }
  checkSeed(seed);
  checkRowCount(targets_arg, "targets");
  bool pose = false;
  std::vector<Pose> targets = ikTargets(targets_arg, rotations, pose);
  if (!pose) {
    throw UsageError("targets", "ik_all needs poses ((N, 4, 4) transforms, or positions with rotations): a position "
                                "leaves a 6-joint arm infinitely many solutions");
  }
  if (singlePrecision(targets_obj) || (rotations_obj && singlePrecision(*rotations_obj))) {
    for (Pose& T : targets) roundFromSinglePrecision(T);
  }
  const PoeModel& model = r.poe;
  const ClosedFormStructure structure = closedFormStructure(model);
  const bool closed = structure.kind != ClosedFormKind::None;
  if (const auto problem = commands::ikWorkProblem(targets.size(), closed ? 1 : seeds, r.dof(), !closed)) {
    throw UsageError(closed ? "targets" : "seeds", *problem);
  }
  IkAllSolutions s;
  size_t total = 0, without = 0;
  {
    py::gil_scoped_release release;
    const std::vector<commands::Range> ranges = commands::samplingRanges(model);
    std::optional<ClosedFormWorkspace> closed_work;
    if (closed) closed_work.emplace(model);
    Data data(model);
    IkWorkspace work(model);
    for (size_t k = 0; k < targets.size(); ++k) {
      try {
        s.rows.push_back(commands::solveAll(model, closed ? &*closed_work : nullptr, data, work, targets[k], k, seeds,
                                            static_cast<unsigned long long>(seed), ranges, IkOptions{},
                                            static_cast<long long>(k)));
      } catch (const std::invalid_argument& e) {
        throw UsageError("targets", "[" + std::to_string(k) + "]: " + e.what());
      }
      total += s.rows.back().solutions.size();
      without += s.rows.back().solutions.empty();
    }
  }
  s.j = {{"name", r.file.name},
         {"source", r.file.path},
         {"poses", "<arrays>"},
         {"length_unit", r.file.length_unit},
         {"task", "pose"},
         {"closed_form", closedFormKindName(structure.kind)},
         {"closed_form_reason", closed ? json(nullptr) : json(structure.reason)},
         {"seeds", closed ? json(nullptr) : json(seeds)},
         {"seed", seed},
         {"notes", json::array()},
         {"counts", {{"targets", targets.size()}, {"solutions", total}, {"without_solution", without}}}};
  s.dof = r.dof();
  return s;
}

// `lowpair compensate`: the joint values of `calibrated` that put the tool where `nominal` puts it at each q.
IkSolutions compensateRows(const Robot& calibrated, const Robot& nominal, const InArray& q_arg,
                           const std::string& measure, bool seeded) {
  if (measure != "pose" && measure != "position") {
    throw UsageError("measure", "expected 'pose' or 'position', got " + io::quotedFileText(measure));
  }
  if (nominal.dof() != calibrated.dof()) {
    throw UsageError(calibrated.subject(), "has " + std::to_string(calibrated.dof()) + " joints but nominal " +
                                               nominal.subject() + " has " + std::to_string(nominal.dof()));
  }
  if (nominal.file.length_unit != calibrated.file.length_unit) {
    auto unit = [](const Robot& r) { return r.file.length_unit.empty() ? std::string("no stated unit") : r.file.length_unit; };
    throw UsageError(calibrated.subject(), "lengths in " + unit(calibrated) + " but nominal " + nominal.subject() +
                                               " in " + unit(nominal) + ": compensation needs one unit");
  }
  checkRowCount(q_arg, "q");
  // the solver's work bounded before anything is converted or solved (commands/limits.hpp), as the CLI's
  const auto rows = static_cast<size_t>(q_arg.ndim() >= 2 ? q_arg.shape(0) : 1);
  if (const auto problem = commands::ikWorkProblem(rows, 1, calibrated.dof(), false)) throw UsageError("q", *problem);
  // the nominal's joint values (evaluated by its FK, then seeds of the calibrated robot's IK)
  const MatX Q = q_arg.ndim() == 1
                     ? MatX(jointVector(q_arg, calibrated.dof(), calibrated.subject(), "q", &nominal.poe).transpose())
                     : jointMatrix(q_arg, calibrated.dof(), calibrated.subject(), "q", &nominal.poe);
  IkOptions options;
  options.measure = measure == "pose" ? Measure::Pose : Measure::Position;
  options.validate("compensate");
  IkSolutions s;
  bool compliance = false;
  {
    py::gil_scoped_release release;
    std::vector<long long> lines(static_cast<size_t>(Q.rows()));
    for (size_t k = 0; k < lines.size(); ++k) lines[k] = static_cast<long long>(k);
    const bool branch = !seeded && commands::branchUnavailable(nominal.poe, calibrated.poe, options).empty();
    s.rows = commands::compensateJointRows(nominal.poe, calibrated.poe, Q, lines, options, branch);
    // a calibrated file's compliance (with its masses), as `lowpair compensate` applies it (backlash: no approach signs)
    compliance = commands::applyDeflection(calibrated.file, calibrated.poe, s.rows, {});
  }
  long long kept = 0;
  for (const commands::IkRow& row : s.rows) kept += row.branch.has_value();
  s.j = {{"name", calibrated.file.name},
         {"source", calibrated.file.path},
         {"nominal", nominal.file.path},
         {"q_file", "<arrays>"},
         {"length_unit", calibrated.file.length_unit},
         {"measure", measure},
         {"counts", commands::ikCountsJson(s.rows)},
         {"branch_kept", kept}};
  if (compliance) s.j["compliance_applied"] = true;  // (only then, as the CLI's JSON)
  const std::string tool_note = commands::undeterminedToolNote(calibrated.file, measure == "pose");
  s.j["tool_determined"] = tool_note.empty();
  s.j["tool_note"] = tool_note.empty() ? json(nullptr) : json(tool_note);
  s.dof = calibrated.dof();
  return s;
}

}  // namespace

static void exposeIkAll(py::module_& m);  // below

void exposeIk(py::module_& m) {
  py::class_<IkSolutions>(m, "IkSolutions",
                          "lowpair.ik(...) / lowpair.compensate(...): one solution per row, as `lowpair ik` / "
                          "`lowpair compensate` write them.")
      .def("to_dict",
           [](const IkSolutions& s) {
             // row by row into Python objects: a JSON value of every row would need as much memory again, and
             // nlohmann's destructor allocates, so running out of memory there ends the process (10^6 rows under a
             // 700 MB limit did), where Python's own allocations raise MemoryError
             py::dict out = toPython(s.j);
             py::list rows;
             for (const commands::IkRow& row : s.rows) rows.append(toPython(commands::ikRowJson(row, s.with_seed)));
             out["rows"] = std::move(rows);
             return out;
           },
           "to_dict() -> dict: the content of `lowpair ik --json` (poses '<arrays>') or `lowpair compensate --json`\n"
           "(q_file '<arrays>'); every row's `line` is its 0-based row.")
      .def("__len__", [](const IkSolutions& s) { return s.rows.size(); })
      .def_property_readonly(
          "q",
          [](const IkSolutions& s) {
            return vectorRows(s.rows, s.dof, [](const commands::IkRow& row) -> const VecX& { return row.result.q; });
          },
          "(N, n): the solutions (or each row's last iterate when not ok), rad / length_unit.")
      .def_property_readonly(
          "status",
          [](const IkSolutions& s) {
            std::vector<std::string> out;
            for (const commands::IkRow& row : s.rows) out.push_back(ikStatusName(row.result.status));
            return out;
          },
          "list[str]: 'ok', 'out_of_range', 'singular', 'unreachable' or 'not_converged' per row (docs/ik.md).")
      .def_property_readonly(
          "ok",
          [](const IkSolutions& s) {
            return perRow<bool>(s.rows, [](const commands::IkRow& row) { return row.result.status == IkStatus::Ok; });
          },
          "(N,) bool: status == 'ok' (within 1e-10 L and 1e-10 rad, at a regular configuration).")
      .def_property_readonly(
          "iterations",
          [](const IkSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const commands::IkRow& row) { return row.result.iterations; });
          },
          "(N,) int: iterations of the kept attempt.")
      .def_property_readonly(
          "position_error",
          [](const IkSolutions& s) {
            return perRow<double>(s.rows, [](const commands::IkRow& row) { return row.result.position_error; });
          },
          "(N,): |p_target - p| at q (length_unit).")
      .def_property_readonly(
          "rotation_error",
          [](const IkSolutions& s) {
            return perRow<double>(s.rows, [](const commands::IkRow& row) { return row.result.rotation_error; });
          },
          "(N,): the angle of R^T R_target at q (rad; 0 for positions).")
      .def_property_readonly(
          "rank",
          [](const IkSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const commands::IkRow& row) { return row.result.rank; });
          },
          "(N,) int: rank of the dimensionless task Jacobian at a converged q (-1 when not converged).")
      .def_property_readonly(
          "sigma_min",
          [](const IkSolutions& s) {
            return perRow<double>(s.rows, [](const commands::IkRow& row) { return row.result.sigma_min; });
          },
          "(N,): its smallest singular value (NaN when not converged).")
      .def_property_readonly(
          "seed",
          [](const IkSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const commands::IkRow& row) { return row.seed; });
          },
          "(N,) int: the random seed s (0..seeds-1) the kept attempt started from; -1 for q0 (ik) and compensate.")
      .def_property_readonly(
          "reason",
          [](const IkSolutions& s) {
            std::vector<std::string> out;
            for (const commands::IkRow& row : s.rows) out.push_back(row.result.reason);
            return out;
          },
          "list[str]: why a row is not ok, one sentence with the numbers ('' for ok rows).")
      .def_property_readonly("counts", [](const IkSolutions& s) { return toPython(s.j["counts"]); },
                             "dict status -> rows.")
      .def_property_readonly(
          "tool_note",
          [](const IkSolutions& s) {
            const auto it = s.j.find("tool_note");
            return it == s.j.end() || it->is_null() ? py::object(py::none()) : py::object(py::str(it->get<std::string>()));
          },
          "compensate: None, or why the compensated tool is the flange's with the nominal's tool frame (a calibrated\n"
          "file with tool_frame: nominal, from targets at unknown points; docs/calibration.md).")
      .def("__repr__", [](const IkSolutions& s) {
        long long ok = 0;
        for (const commands::IkRow& row : s.rows) ok += row.result.status == IkStatus::Ok;
        return "<lowpair.IkSolutions " + std::to_string(s.rows.size()) + " rows, " + std::to_string(ok) + " ok>";
      });
  m.def("ik", &ik, py::arg("robot"), py::arg("targets"), py::arg("rotations") = py::none(), py::arg("q0") = py::none(),
        py::arg("seeds") = 8, py::arg("seed") = 1,
        "ik(robot, targets, rotations=None, q0=None, seeds=8, seed=1) -> IkSolutions\n\n"
        "`lowpair ik`: inverse kinematics, one problem per row. targets: (N, 4, 4) transforms T_base_tool (the tool\n"
        "frame onto each), or (N, 3) positions (length_unit; the tool origin onto each: a position task), made\n"
        "poses by rotations (N, 4) unit quaternions qw, qx, qy, qz (the targets CSV's columns). q0: (n,) or (N, n)\n"
        "seeds (the CSV's q columns); None: up to `seeds` random seeds per row (1..1000), sample k * seeds + s of\n"
        "the stream `seed` (the sampling convention; the same seed gives the CLI's numbers), the first that ends\n"
        "ok kept, else the closest attempt. Tolerances 1e-10 L and 1e-10 rad (docs/ik.md). A row that is not\n"
        "solved is data (status, reason), not an exception. The GIL is released while solving.");
  m.def("compensate", &compensateRows, py::arg("calibrated"), py::arg("nominal"), py::arg("q"),
        py::arg("measure") = "pose", py::arg("seeded") = false,
        "compensate(calibrated, nominal, q, measure='pose', seeded=False) -> IkSolutions\n\n"
        "`lowpair compensate`: for each row of q (N, n) (or one (n,)), nominal joint values, the joint values of\n"
        "the calibrated robot that put its tool frame (measure='pose') or tool origin ('position') where the\n"
        "nominal puts it at q. When both robots have a closed form (docs/ik.md) and the task is a pose, each row's\n"
        "solution is on the branch of its nominal q (to_dict() rows name it; a row without one falls back to the\n"
        "numerical solver seeded at q); seeded=True, or without a closed form: the numerical solver seeded at q\n"
        "(`compensate --seeded`). Both robots must have the same joint count and length unit. The GIL is released\n"
        "while solving.");
  exposeIkAll(m);
}

// lowpair.ik_all and its result (`lowpair ik --all`)
static void exposeIkAll(py::module_& m) {
  py::class_<IkAllSolutions>(m, "IkAllSolutions",
                             "lowpair.ik_all(...): every solution of each target, as `lowpair ik --all` lists them.")
      .def("to_dict",
           [](const IkAllSolutions& s) {
             py::dict out = toPython(s.j);
             py::list rows;
             for (const commands::IkAllRow& row : s.rows) rows.append(toPython(commands::ikAllRowJson(row)));
             out["rows"] = std::move(rows);
             return out;
           },
           "to_dict() -> dict: the content of `lowpair ik --all --json` (poses '<arrays>'); `line` the 0-based row.")
      .def("__len__", [](const IkAllSolutions& s) { return s.rows.size(); })
      .def_property_readonly(
          "q",
          [](const IkAllSolutions& s) {
            py::list out;
            for (const commands::IkAllRow& row : s.rows) {
              out.append(vectorRows(row.solutions, s.dof, [](const commands::IkAllSolution& x) -> const VecX& { return x.q; }));
            }
            return out;
          },
          "list of (k, n) arrays: target k's solutions (k = 0 when it has none), rad / length_unit.")
      .def_property_readonly(
          "count",
          [](const IkAllSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const commands::IkAllRow& row) { return static_cast<std::int64_t>(row.solutions.size()); });
          },
          "(N,) int: the solutions of each target.")
      .def_property_readonly("closed_form", [](const IkAllSolutions& s) { return s.j["closed_form"].get<std::string>(); },
                             "'spherical_wrist', 'parallel_triple' or 'none' (then: the distinct solutions of the random seeds).")
      .def("__repr__", [](const IkAllSolutions& s) {
        long long total = 0;
        for (const commands::IkAllRow& row : s.rows) total += static_cast<long long>(row.solutions.size());
        return "<lowpair.IkAllSolutions " + std::to_string(s.rows.size()) + " targets, " + std::to_string(total) + " solutions>";
      });
  m.def("ik_all", &ikAll, py::arg("robot"), py::arg("targets"), py::arg("rotations") = py::none(), py::arg("seeds") = 8,
        py::arg("seed") = 1,
        "ik_all(robot, targets, rotations=None, seeds=8, seed=1) -> IkAllSolutions\n\n"
        "`lowpair ik --all`: every solution of each pose target (targets and rotations as lowpair.ik takes them;\n"
        "positions alone are refused). In closed form when the robot's geometry allows it (a spherical wrist, or\n"
        "axes 2-4 parallel: docs/ik.md), each solution with its branch flags (shoulder, elbow, wrist) and FK\n"
        "residual; otherwise the distinct solutions the numerical solver reaches from `seeds` random seeds (sample\n"
        "k * seeds + s of the stream `seed`), without branch flags. The GIL is released while solving.");
}

}  // namespace lowpair::python
