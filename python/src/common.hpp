// What the topics of the Python module share (python/src/, docs/python.md): the error of a bad argument and its
// Python spelling, JSON and array conversions, and the checks of joint arrays every binding makes.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "lowpair/model.hpp"
#include "lowpair/types.hpp"
#include "commands/arguments.hpp"

namespace py = pybind11;

namespace lowpair::python {

using nlohmann::json;

// A bad argument (not a file): raised as lowpair.Error("SUBJECT: message"), as the CLI prints it; the error of
// the commands room's shared checks, as in cli/commands.hpp.
using UsageError = commands::UsageError;

// Python's spelling of an argument in the commands room's shared checks: "noise_position", "measure='targets'".
commands::ArgumentSpelling pythonSpelling();

// A seed of the sampling streams, as the CLI's --seed takes it: a whole number in [0, 2^53].
void checkSeed(long long seed);

// A path argument: a str or any os.PathLike (pathlib.Path), as open() takes; else lowpair.Error
// "path: expected a str or os.PathLike, got TYPE" (bytes: "expected a text path (str), got bytes").
std::string pathArgument(const py::handle& path_arg);

// nlohmann::json -> Python objects (numbers keep their double bits).
py::object toPython(const json& j);

// ----- arrays ------------------------------------------------------------------------------------------

// What is wrong with `x` as an array of numbers before numpy converts it to float64, without the argument's name
// ("" when nothing): a dtype that is not real numbers (complex: numpy would drop the imaginary part with only a
// warning; datetime64, timedelta64), or more than kMaxArrayRows rows or kMaxArrayValues values (a broadcast view
// would be copied whole: 48 GB for np.broadcast_to(q, (10**9, 6))). Anything else numpy cannot read as numbers is
// left to the conversion (TypeError).
constexpr long long kMaxArrayRows = 1000000;       // io::kMaxMeasurements: the rows of a CSV the CLI reads
constexpr long long kMaxArrayValues = 100000000;   // io::kMaxMeasurementJointValues
std::string arrayProblem(const py::handle& x);

// An array argument of numbers, as float64: anything numpy turns into float64 (lists, integers, bools, any order
// or byte order), converted on the way in; `refused` is arrayProblem's text for one that is not converted (then
// empty), which the function reading it raises with the argument's name (requireAccepted).
struct InArray : py::array_t<double, py::array::forcecast> {
  using Base = py::array_t<double, py::array::forcecast>;
  InArray() = default;
  explicit InArray(Base a) : Base(std::move(a)) {}
  std::string refused;
};

// lowpair.Error(SUBJECT: what: refused) for an argument the conversion refused (subject "": "what: refused").
void requireAccepted(const InArray& a, const std::string& subject, const std::string& what);

py::array_t<double> matrixArray(const Eigen::Ref<const MatX>& m);
py::array_t<double> vectorArray(const Eigen::Ref<const VecX>& v);
py::array_t<double> poseArray(const Pose& T);

// One value per row: f(row) for each of `rows`, as an (N,) array of T.
template <class T, class Rows, class F>
py::array_t<T> perRow(const Rows& rows, F f) {
  py::array_t<T> out(static_cast<py::ssize_t>(rows.size()));
  auto w = out.template mutable_unchecked<1>();
  for (size_t k = 0; k < rows.size(); ++k) w(static_cast<py::ssize_t>(k)) = f(rows[k]);
  return out;
}

// Vectors of `n` values, one per row, as an (N, n) array: row k is f(rows[k]).
template <class Rows, class F>
py::array_t<double> vectorRows(const Rows& rows, Eigen::Index n, F f) {
  py::array_t<double> out({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(n)});
  auto w = out.mutable_unchecked<2>();
  for (size_t k = 0; k < rows.size(); ++k) {
    const VecX& v = f(rows[k]);
    for (Eigen::Index i = 0; i < n; ++i) w(static_cast<py::ssize_t>(k), i) = v(i);
  }
  return out;
}

std::string shapeText(const py::array& a);

// Finite check of a joint array, naming the first bad value like the CLI's --q ("'nan' is not finite").
void requireFinite(const double* x, py::ssize_t count, py::ssize_t per_row, const std::string& subject,
                   const std::string& what);

// The joint values of `rows` rows of `dof` values (row-major, row 0 is row `first_row` of the argument) within
// their joints' limits (commands::jointValueProblem: the pose there is finite), else UsageError(subject,
// "what[k, i]: ...") ("what[i]: ..." when `batch` is false). A NaN is "'nan' is not finite".
void requireWithinLimits(const PoeModel& model, const double* q, py::ssize_t rows, const std::string& subject,
                         const std::string& what, bool batch, py::ssize_t first_row = 0);

// (n,) joint vector; with `model`, each value within its joint's limits (requireWithinLimits).
VecX jointVector(const InArray& q, int dof, const std::string& subject, const std::string& what = "q",
                 const PoeModel* model = nullptr);

// (N, n) joint values, column-major (what the library takes); with `model`, within its joints' limits.
MatX jointMatrix(const InArray& Q, int dof, const std::string& subject, const std::string& what = "q",
                 const PoeModel* model = nullptr);

// A float64 array read in place: C-contiguous and aligned (what numpy makes). Anything else (lists, integers,
// Fortran order, strided views, other byte orders) is converted by numpy first, as InArray is.
using CArray = py::array_t<double, py::array::c_style | py::array::forcecast | py::detail::npy_api::NPY_ARRAY_ALIGNED_>;

// (subject: the robot, in the message of a refused array: arrayProblem)
inline CArray cArray(const py::handle& x, const char* what, const std::string& subject) {
  const bool in_place = CArray::check_(x) && py::detail::check_flags(x.ptr(), py::detail::npy_api::NPY_ARRAY_ALIGNED_);
  // (a float64 array read in place: only its size to check, and a (6,) vector has none to check)
  if (!in_place || py::reinterpret_borrow<py::array>(x).ndim() >= 2) {
    if (const std::string problem = arrayProblem(x); !problem.empty()) {
      throw UsageError(subject, std::string(what) + ": " + problem);
    }
  }
  if (in_place) return py::reinterpret_borrow<CArray>(x);
  CArray a = CArray::ensure(x);
  if (!a) {
    throw py::type_error(std::string(what) + ": expected an array of numbers (float64), got " +
                         py::str(py::type::handle_of(x).attr("__name__")).cast<std::string>());
  }
  return a;
}

// A new C-contiguous float64 array of `shape`, allocated by numpy (py::array's constructor would first build
// std::vectors of the shape and strides: a single fk(q) notices).
template <size_t D>
py::array_t<double> newArray(const std::array<py::ssize_t, D>& shape) {
  auto& api = py::detail::npy_api::get();
  PyObject* a = api.PyArray_NewFromDescr_(api.PyArray_Type_, api.PyArray_DescrFromType_(py::detail::npy_api::NPY_DOUBLE_),
                                          static_cast<int>(D), const_cast<Py_intptr_t*>(shape.data()), nullptr,
                                          nullptr, 0, nullptr);
  if (!a) throw py::error_already_set();
  return py::reinterpret_steal<py::array_t<double>>(a);
}

// `out`: a preallocated float64 C-contiguous writeable array of the result's shape (no fresh pages per call).
template <size_t D>
double* outBuffer(const std::optional<py::array>& out, const std::array<py::ssize_t, D>& shape) {
  if (!out) return nullptr;
  const py::array& a = *out;
  bool ok = py::isinstance<py::array_t<double>>(a) && a.writeable() && (a.flags() & py::array::c_style) &&
            a.ndim() == static_cast<py::ssize_t>(D);
  for (size_t k = 0; ok && k < D; ++k) ok = a.shape(static_cast<py::ssize_t>(k)) == shape[k];
  if (!ok) {
    std::string want = "(";
    for (size_t k = 0; k < D; ++k) want += (k ? ", " : "") + std::to_string(shape[k]);
    // what differs, each named: dtype, order, writeability, shape
    const std::string dtype = py::str(a.dtype()).cast<std::string>();
    const std::string order = (a.flags() & py::array::c_style) ? "C-contiguous"
                              : (a.flags() & py::array::f_style) ? "Fortran-ordered"
                                                                 : "non-contiguous";
    throw UsageError("out", "expected a writeable C-contiguous float64 array of shape " + want + "), got a " +
                                (a.writeable() ? "" : "read-only ") + order + " " + dtype + " array of shape " +
                                shapeText(a));
  }
  return static_cast<double*>(const_cast<void*>(a.data()));  // writeable, checked above
}

// Python's UserWarning `text` (with the GIL held); under -W error it raises.
void warnUser(const std::string& text);

// A rotation from a quaternion qw, qx, qy, qz by the measurement CSV reader's rule (io::unitQuaternionRotation),
// so that arrays and a CSV of the same numbers give the same bits.
Mat3 quaternionRotation(double w, double x, double y, double z, const std::string& subject, Eigen::Index row);

}  // namespace lowpair::python

// The argument conversion of InArray: arrayProblem first (no copy of a refused array), then numpy's float64.
namespace pybind11::detail {
template <>
struct type_caster<lowpair::python::InArray> {
  PYBIND11_TYPE_CASTER(lowpair::python::InArray, const_name("numpy.ndarray[numpy.float64]"));
  bool load(handle src, bool convert) {
    using lowpair::python::InArray;
    if (!convert && !InArray::Base::check_(src)) return false;
    std::string problem = lowpair::python::arrayProblem(src);
    if (!problem.empty()) {
      value = InArray();
      value.refused = std::move(problem);
      return true;
    }
    auto a = InArray::Base::ensure(src);
    if (!a) {
      PyErr_Clear();
      return false;
    }
    value = InArray(std::move(a));
    return true;
  }
  static handle cast(const lowpair::python::InArray& src, return_value_policy, handle) { return src.inc_ref(); }
};
}  // namespace pybind11::detail

namespace lowpair::python {

/// True for a numpy array of floats narrower than float64 (float32, float16).
bool singlePrecision(const py::handle& a);

/// A rotation given in single precision (float32 arrays: rounding of about 6e-8 in |R^T R - I|, above the
/// double-precision rule kRotationOrthonormal) taken as the nearest rotation (polar factor U V^T) when it is one
/// to float32 rounding: 64 float32 epsilons, 7.6e-6. Beyond, or with det R <= 0, T is left as it is, for the
/// caller's own refusal. (ik's targets and rotations, Robot.transformed(T), simulate(frame=(4, 4)).)
void roundFromSinglePrecision(Pose& T);

/// An argument taken as a py::object (one that may be an array or something else) read through InArray's caster
/// (py::cast<InArray> would bypass it: InArray is a py::object), refused as requireAccepted refuses.
inline InArray arrayArgument(const py::handle& x, const std::string& what) {
  pybind11::detail::make_caster<InArray> caster;
  if (!caster.load(x, true)) throw UsageError(what, "expected an array of numbers");
  InArray a = pybind11::detail::cast_op<InArray&&>(std::move(caster));
  requireAccepted(a, "", what);
  return a;
}

}  // namespace lowpair::python
