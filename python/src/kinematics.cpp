// Forward kinematics (single and batched), the Jacobians, the D-H table and the singularity analysis
// (lowpair.Robot.fk, jacobian, dh, singular; the classes DhTable and Singularity).
#include "kinematics.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "commands/deflection_inputs.hpp"
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

// The joint values of a batch (count x dof at q) about to be evaluated into `out` (values_per_row per row; null: a
// fresh array). Into the caller's buffer every value is checked before the first result is written, so a refusal
// leaves `out` as it was (the kernel checks chunk by chunk, after earlier chunks were written); and results written
// over joint values not read yet would be read back as joint values, so q is copied into `copy` first when `out`
// shares its memory, as numpy copies an input that overlaps a ufunc's out=. Returns the values to evaluate.
const double* batchInput(const Robot& r, const double* q, py::ssize_t count, const double* out, py::ssize_t values_per_row,
                         std::vector<double>& copy) {
  if (!out) return q;
  const int dof = r.dof();
  const size_t values = static_cast<size_t>(count) * static_cast<size_t>(dof);
  if (!withinBounds(q, count, dof, jointMagnitudeBounds(r.poe))) {
    requireWithinLimits(r.poe, q, count, r.subject(), "q", true);  // throws, naming the value
  }
  if (sharesBytes(q, values * sizeof(double), out, static_cast<size_t>(count * values_per_row) * sizeof(double))) {
    copy.assign(q, q + values);
    return copy.data();
  }
  return q;
}

// The joint values a compliant file's robot stands at for each of the `count` rows of `q` (standingJoints), moved
// into `rows` once all are computed (q may be rows' own data). Returns rows' data.
const double* standingRows(const Robot& r, const double* q, py::ssize_t count, std::vector<double>& rows) {
  const int dof = r.dof();
  std::vector<double> standing(static_cast<size_t>(count) * static_cast<size_t>(dof));
  for (py::ssize_t k = 0; k < count; ++k) {
    const VecX row = Eigen::Map<const VecX>(q + k * dof, dof);
    Eigen::Map<VecX>(standing.data() + k * dof, dof) = commands::standingJoints(r.file, r.poe, row);
  }
  rows = std::move(standing);
  return rows.data();
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
    // a file's compliance (calibrate --compliance --out) applies as in `lowpair fk`: the joints stand at q + c tau(q)
    const VecX standing = commands::appliesCompliance(r.file) ? commands::standingJoints(r.file, r.poe, x) : VecX();
    const Eigen::Map<const VecX> at(standing.size() > 0 ? standing.data() : x.data(), dof);
    // no GIL release: one FK costs less than releasing and taking it again (docs/python.md, "Speed")
    if (kind == "poe") {
      Data& data = threadData(r.poe.chain(), dof);
      forwardKinematics(r.poe, data, at);
      writePose(data.T_base_tool, dst);
    } else {
      const DhModel& dh = r.dhModel();
      Data& data = threadData(dh.chain(), dof);
      forwardKinematics(dh, data, at);
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
    std::vector<double> copy;
    const double* x = batchInput(r, q.data(), count, out_arg ? dst : nullptr, 16, copy);
    if (commands::appliesCompliance(r.file)) x = standingRows(r, x, count, copy);
    fkBatchInto(r, kind == "poe", x, count, dst);
  }
  if (out_arg) return *out_arg;
  return std::move(result);
}

namespace {

JacobianFrame jacobianFrame(const std::string& frame) {
  if (frame == "spatial") return JacobianFrame::Spatial;
  if (frame == "body") return JacobianFrame::Body;
  if (frame == "geometric") return JacobianFrame::Geometric;
  throw UsageError("frame", "expected 'spatial', 'body' or 'geometric', got " + io::quotedFileText(frame));
}

// q of a function with a single (n,) and a batched (N, n) form: whether it is the batch (2-D; the C-contiguous
// float64 copy of a batch, when it is not one, is left in `batch`). Other shapes are refused as fk refuses them.
bool isBatch(const Robot& r, const InArray& q, CArray& batch) {
  requireAccepted(q, r.subject(), "q");
  const int dof = r.dof();
  if (q.ndim() == 1) return false;
  if (q.ndim() != 2) {
    throw UsageError(r.subject(), "q: expected shape (" + std::to_string(dof) + ",) or (N, " + std::to_string(dof) +
                                      "), got shape " + shapeText(q));
  }
  if (q.shape(1) != dof) {
    throw UsageError(r.subject(), "q: expected shape (N, " + std::to_string(dof) + "), got shape " + shapeText(q));
  }
  batch = cArray(q, "q", r.subject());
  return true;
}

}  // namespace

py::object jacobian(const Robot& r, const InArray& q, const std::string& frame_name,
                    const std::optional<py::array>& out_arg) {
  const JacobianFrame frame = jacobianFrame(frame_name);
  const int dof = r.dof();
  CArray Q;
  if (isBatch(r, q, Q)) {
    const py::ssize_t count = Q.shape(0);
    double* dst = outBuffer<3>(out_arg, {count, 6, dof});
    py::array_t<double> result;
    if (!dst) {
      result = newArray<3>({count, 6, dof});
      dst = result.mutable_data();
    }
    {
      py::gil_scoped_release release;
      std::vector<double> copy;
      const double* x = batchInput(r, Q.data(), count, out_arg ? dst : nullptr, 6 * dof, copy);
      jacobianBatchInto(r, frame, x, count, dst);
    }
    if (out_arg) return *out_arg;
    return std::move(result);
  }
  const VecX x = jointVector(q, dof, r.subject(), "q", &r.poe);
  double* dst = outBuffer<2>(out_arg, {6, dof});
  py::array_t<double> result;
  if (!dst) {
    result = newArray<2>({6, dof});
    dst = result.mutable_data();
  }
  {
    py::gil_scoped_release release;
    Data& data = threadData(r.poe.chain(), dof);
    computeJacobians(r.poe, data, x);
    Mat6X J(6, dof);
    if (frame == JacobianFrame::Spatial) getSpatialJacobian(data, J);
    if (frame == JacobianFrame::Body) getBodyJacobian(data, J);
    if (frame == JacobianFrame::Geometric) getGeometricJacobian(data, J);
    Eigen::Map<Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>>(dst, 6, dof) = J;
  }
  if (out_arg) return *out_arg;
  return std::move(result);
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

py::object singular(const Robot& r, const InArray& q) {
  CArray Q;
  if (isBatch(r, q, Q)) return py::cast(singularBatch(r, Q));
  const VecX x = jointVector(q, r.dof(), r.subject(), "q", &r.poe);
  SingularityOptions options;
  options.max_null_vectors = io::kPrintedNullVectors;
  options.validate();
  SingularityReport report = analyzeSingularity(r.poe, x, options);
  json j = io::singularityJson(r.file, x, report);
  return py::cast(Singularity{std::move(report), std::move(j)});
}

SingularityBatch singularBatch(const Robot& r, const CArray& Q) {
  const py::ssize_t count = Q.shape(0), m = std::min(6, r.dof());
  SingularityBatch b{py::array_t<long long>(count), py::array_t<bool>(count), newArray<1>({count}),
                     newArray<1>({count}),          newArray<1>({count}),     newArray<1>({count}),
                     newArray<2>({count, m})};
  long long* rank = b.rank.mutable_data();
  bool* is_singular = b.singular.mutable_data();
  double *sigma_min = b.sigma_min.mutable_data(), *manipulability = b.manipulability.mutable_data();
  double *condition = b.condition.mutable_data(), *tolerance = b.tolerance.mutable_data();
  double* sigma = b.singular_values.mutable_data();
  {
    py::gil_scoped_release release;
    singularBatchInto(r, Q.data(), count, rank, tolerance, sigma);
    // what analyzeSingularity derives from the singular values, in its order of operations (prod over a VecX)
    VecX sv(m);
    for (py::ssize_t k = 0; k < count; ++k) {
      for (py::ssize_t j = 0; j < m; ++j) sv(j) = sigma[k * m + j];
      const double sigma_max = m > 0 ? sv(0) : 0.0;
      is_singular[k] = rank[k] < m;
      sigma_min[k] = m > 0 ? sv(m - 1) : 0.0;
      manipulability[k] = sv.prod();
      condition[k] = sigma_min[k] > 0.0 ? sigma_max / sigma_min[k] : std::numeric_limits<double>::infinity();
    }
  }
  return b;
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

void exposeSingularityBatch(py::module_& m) {
  py::class_<SingularityBatch>(m, "SingularityBatch",
                               "Robot.singular(Q), Q of shape (N, n): per row, the rank rule of Robot.singular(q) (arrays).")
      .def_readonly("rank", &SingularityBatch::rank, "(N,) int64: the numerical rank of each row.")
      .def_readonly("singular", &SingularityBatch::singular, "(N,) bool: rank < min(6, dof).")
      .def_readonly("sigma_min", &SingularityBatch::sigma_min, "(N,): smallest singular value of the dimensionless Jacobian.")
      .def_readonly("manipulability", &SingularityBatch::manipulability, "(N,): the product of the singular values.")
      .def_readonly("condition", &SingularityBatch::condition, "(N,): sigma_max / sigma_min (inf when singular to zero).")
      .def_readonly("tolerance", &SingularityBatch::tolerance, "(N,): the rank threshold of each row.")
      .def_readonly("singular_values", &SingularityBatch::singular_values,
                    "(N, min(6, n)): descending singular values of the dimensionless Jacobian, a row per configuration.")
      .def("__len__", [](const SingularityBatch& b) { return b.rank.shape(0); })
      .def("__repr__", [](const SingularityBatch& b) {
        const bool* s = b.singular.data();
        const auto singular = std::count(s, s + b.singular.shape(0), true);
        return "<lowpair.SingularityBatch " + std::to_string(b.rank.shape(0)) + " rows, " + std::to_string(singular) +
               " singular>";
      });
}

}  // namespace

void exposeKinematics(py::module_& m) {
  exposeDhTable(m);
  exposeSingularity(m);
  exposeSingularityBatch(m);
}

}  // namespace lowpair::python
