// Forward kinematics (single and batched), the Jacobians, the D-H table and the singularity analysis
// (lowpair.Robot.fk, jacobian, dh, singular; the classes DhTable and Singularity).
#include "kinematics.hpp"

#include <memory>
#include <utility>
#include <vector>

#include "expose.hpp"
#include "fk_batch.hpp"
#include "io/output.hpp"
#include "io/singularity_output.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"

namespace lowpair::python {

namespace {

// One Data per thread, rebuilt when the dof changes (a Data fits every model of its dof: kinematics.hpp).
Data& threadData(const KinematicChain& chain, int dof) {
  thread_local std::unique_ptr<Data> data;
  if (!data || data->dof != dof) data = std::make_unique<Data>(chain);
  return *data;
}

// T as a row-major 4 x 4 matrix.
void writePose(const Pose& T, double* dst) {
  for (int a = 0; a < 3; ++a) {
    dst[4 * a + 0] = T.R(a, 0), dst[4 * a + 1] = T.R(a, 1), dst[4 * a + 2] = T.R(a, 2), dst[4 * a + 3] = T.p(a);
  }
  dst[12] = 0.0, dst[13] = 0.0, dst[14] = 0.0, dst[15] = 1.0;
}

}  // namespace

py::object fk(const Robot& r, const py::object& q_arg, const std::optional<std::string>& model,
              const std::optional<py::array>& out_arg) {
  const std::string kind = kindOf(r, model);
  const CArray q = cArray(q_arg, "q", r.subject());
  const int dof = r.dof();
  if (q.ndim() == 1) {
    if (q.shape(0) != dof) {
      throw UsageError(r.subject(), "q: expected " + std::to_string(dof) + " joint values (shape (" +
                                        std::to_string(dof) + ",)), got shape " + shapeText(q));
    }
    const Eigen::Map<const VecX> x(q.data(), dof);
    if (firstJointBeyondLimits(r.poe, x) >= 0) {
      requireWithinLimits(r.poe, x.data(), 1, r.subject(), "q", false);  // throws, naming the value
    }
    double* dst = outBuffer<2>(out_arg, {4, 4});
    py::array_t<double> result;
    if (!dst) {
      result = newArray<2>({4, 4});
      dst = result.mutable_data();
    }
    // no GIL release: one FK costs less than releasing and taking it again (docs/python.md, "Speed")
    if (kind == "poe") {
      Data& data = threadData(r.poe.chain(), dof);
      forwardKinematics(r.poe, data, x);
      writePose(data.T_base_tool, dst);
    } else {
      const DhModel& dh = r.dhModel();
      Data& data = threadData(dh.chain(), dof);
      forwardKinematics(dh, data, x);
      writePose(data.T_base_tool, dst);
    }
    if (out_arg) return *out_arg;
    return std::move(result);
  }
  if (q.ndim() != 2) {
    throw UsageError(r.subject(), "q: expected shape (" + std::to_string(dof) + ",) or (N, " + std::to_string(dof) +
                                      "), got shape " + shapeText(q));
  }
  if (q.shape(1) != dof) {
    throw UsageError(r.subject(), "q: expected shape (N, " + std::to_string(dof) + "), got shape " + shapeText(q));
  }
  if (kind == "dh") r.dhModel();  // convert (or throw) with the GIL held
  const py::ssize_t count = q.shape(0);
  double* dst = outBuffer<3>(out_arg, {count, 4, 4});
  py::array_t<double> result;
  if (!dst) {
    result = newArray<3>({count, 4, 4});
    dst = result.mutable_data();
  }
  {
    py::gil_scoped_release release;
    const double* x = q.data();
    std::vector<double> copy;  // q when `out` shares its memory
    if (out_arg) {
      // into the caller's buffer: every value checked before the first result is written, so a refusal leaves
      // `out` as it was (the kernel checks chunk by chunk, after earlier chunks were written)
      const size_t values = static_cast<size_t>(count) * static_cast<size_t>(dof);
      if (!withinBounds(x, count, dof, jointMagnitudeBounds(r.poe))) {
        requireWithinLimits(r.poe, x, count, r.subject(), "q", true);  // throws, naming the value
      }
      // results written over joint values not read yet would be read back as joint values: q is copied first,
      // as numpy copies an input that overlaps a ufunc's out=
      if (sharesBytes(x, values * sizeof(double), dst, static_cast<size_t>(count) * 16 * sizeof(double))) {
        copy.assign(x, x + values);
        x = copy.data();
      }
    }
    fkBatchInto(r, kind == "poe", x, count, dst);
  }
  if (out_arg) return *out_arg;
  return std::move(result);
}

py::array_t<double> jacobian(const Robot& r, const InArray& q, const std::string& frame) {
  if (frame != "spatial" && frame != "body" && frame != "geometric") {
    throw UsageError("frame", "expected 'spatial', 'body' or 'geometric', got " + io::quotedFileText(frame));
  }
  const VecX x = jointVector(q, r.dof(), r.subject(), "q", &r.poe);
  Mat6X J(6, r.dof());
  {
    py::gil_scoped_release release;
    Data& data = threadData(r.poe.chain(), r.dof());
    computeJacobians(r.poe, data, x);
    if (frame == "spatial") getSpatialJacobian(data, J);
    if (frame == "body") getBodyJacobian(data, J);
    if (frame == "geometric") getGeometricJacobian(data, J);
  }
  return matrixArray(J);
}

DhTable dhTable(const Robot& r, double parallel_threshold, bool modified) {
  ConvertOptions options;
  options.parallel_threshold = parallel_threshold;
  options.validate();
  DhConversion c = poeToDh(r.poe, options);
  const FkCheck check = checkDhConversion(r.poe, c.model);
  json j = modified ? io::modifiedDhJson(r.file, c, check) : io::dhJson(r.file, c, check);
  return DhTable{std::move(c), check, std::move(j)};
}

Singularity singular(const Robot& r, const InArray& q) {
  const VecX x = jointVector(q, r.dof(), r.subject(), "q", &r.poe);
  SingularityOptions options;
  options.max_null_vectors = io::kPrintedNullVectors;
  options.validate();
  SingularityReport report = analyzeSingularity(r.poe, x, options);
  json j = io::singularityJson(r.file, x, report);
  return Singularity{std::move(report), std::move(j)};
}

namespace {

void exposeDhTable(py::module_& m) {
  py::class_<DhTable>(m, "DhTable", "The D-H table of Robot.dh(): rows, base, tool, conditioning and FK check.")
      .def("to_dict", [](const DhTable& t) { return toPython(t.j); },
           "to_dict() -> dict: the content of `lowpair poe2dh --json` (or --modified --json).")
      .def_property_readonly("convention", [](const DhTable& t) { return t.j["convention"].get<std::string>(); },
                             "'standard' or 'modified'.")
      .def_property_readonly("base", [](const DhTable& t) { return toPython(t.j["base"]); },
                             "dict: the base row (theta, d, alpha, a; modified: theta, d).")
      .def_property_readonly("rows", [](const DhTable& t) { return toPython(t.j["joints"]); },
                             "list[dict], one per joint: theta, d, alpha, a (rad, length_unit), type, scale, pitch, name.")
      .def_property_readonly("tool", [](const DhTable& t) { return toPython(t.j["tool"]); }, "dict: the tool row.")
      .def_property_readonly(
          "table",
          [](const DhTable& t) {
            const auto& joints = t.conversion.model.joints();
            MatX out(static_cast<Eigen::Index>(joints.size()), 4);
            for (size_t i = 0; i < joints.size(); ++i) {
              const DhParams& p = joints[i].link;
              out.row(static_cast<Eigen::Index>(i)) << p.theta, p.d, p.alpha, p.a;
            }
            return matrixArray(out);
          },
          "(n, 4) array of the standard rows [theta, d, alpha, a] (rad, length_unit).")
      .def_property_readonly("conditioning", [](const DhTable& t) { return toPython(t.j["conditioning"]); },
                             "The conditioning report (per row: axis angle, parallel, ill conditioned).")
      .def_property_readonly("fk_check", [](const DhTable& t) { return toPython(t.j["fk_check"]); },
                             "dict: the POE vs D-H FK deviation over 65 configurations.")
      .def_property_readonly("warnings", [](const DhTable& t) { return toPython(t.j["warnings"]); },
                             "list[str]: the conditioning warnings in sentences.")
      .def_property_readonly("length_scale", [](const DhTable& t) { return t.conversion.length_scale; },
                             "The robot size L (length_unit).")
      .def("__repr__", [](const DhTable& t) {
        return "<lowpair.DhTable " + t.j["convention"].get<std::string>() + ", " +
               std::to_string(t.conversion.model.dof()) + " rows>";
      });
}

void exposeSingularity(py::module_& m) {
  py::class_<Singularity>(m, "Singularity", "Robot.singular(q): the analysis of `lowpair singular`.")
      .def("to_dict", [](const Singularity& s) { return toPython(s.j); },
           "to_dict() -> dict: the content of `lowpair singular --json`.")
      .def_property_readonly("rank", [](const Singularity& s) { return s.report.rank; }, "Numerical rank (int).")
      .def_property_readonly("dof", [](const Singularity& s) { return s.report.dof; }, "Joints (int).")
      .def_property_readonly("singular", [](const Singularity& s) { return s.report.singular; },
                             "rank < min(6, dof) (bool).")
      .def_property_readonly("sigma_min", [](const Singularity& s) { return s.report.sigma_min; },
                             "Smallest singular value of the dimensionless Jacobian.")
      .def_property_readonly("singular_values", [](const Singularity& s) { return vectorArray(s.report.singular_values); },
                             "(min(6, n),) descending singular values of the dimensionless Jacobian.")
      .def_property_readonly("manipulability", [](const Singularity& s) { return s.report.manipulability; },
                             "Yoshikawa's sqrt(det(J J^T)) of the dimensionless Jacobian: the product of its singular "
                             "values (0 at a singularity).")
      .def_property_readonly("condition", [](const Singularity& s) { return s.report.condition; },
                             "sigma_max / sigma_min (inf when singular to zero).")
      .def_property_readonly("tolerance", [](const Singularity& s) { return s.report.tolerance; }, "The rank threshold.")
      .def_property_readonly("length_scale", [](const Singularity& s) { return s.report.length_scale; }, "The robot size L.")
      .def_property_readonly("rank_linear", [](const Singularity& s) { return s.report.rank_linear; },
                             "Rank of the three linear-velocity rows (the tool origin's motion), int.")
      .def_property_readonly("rank_angular", [](const Singularity& s) { return s.report.rank_angular; },
                             "Rank of the three angular-velocity rows, int.")
      .def_property_readonly("classes", [](const Singularity& s) { return toPython(s.j["classes"]); },
                             "list[dict]: class ('C1'..'C7', 'other'), joints (1-based), description.")
      .def_property_readonly("decoupled", [](const Singularity& s) { return toPython(s.j["decoupled"]); },
                             "dict: the wrist/arm split (Paden-Sastry 5).")
      .def_property_readonly("nullity", [](const Singularity& s) { return s.report.nullity; }, "dof - rank.")
      .def_property_readonly(
          "null_space",
          [](const Singularity& s) {
            MatX out(static_cast<Eigen::Index>(s.report.null_space.size()), s.report.dof);
            for (size_t k = 0; k < s.report.null_space.size(); ++k) {
              out.row(static_cast<Eigen::Index>(k)) = s.report.null_space[k].transpose();
            }
            return matrixArray(out);
          },
          "(k, n): the first k <= 6 null vectors (unit-screw coefficients), one per row.")
      .def("__repr__", [](const Singularity& s) {
        return std::string("<lowpair.Singularity ") + (s.report.singular ? "singular" : "regular") + ", rank " +
               std::to_string(s.report.rank) + ", sigma_min " + io::shortest(s.report.sigma_min) + ">";
      });
}

}  // namespace

void exposeKinematics(py::module_& m) {
  exposeDhTable(m);
  exposeSingularity(m);
}

}  // namespace lowpair::python
