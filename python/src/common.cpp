// What the topics of the Python module share (common.hpp).
#include "common.hpp"

#include <Eigen/SVD>

#include <cmath>
#include <string>

#include "io/measurements.hpp"
#include "io/output.hpp"
#include "commands/sampling.hpp"
#include "lowpair/model.hpp"

namespace lowpair::python {

commands::ArgumentSpelling pythonSpelling() {
  return {[](const std::string& name) { return name; },
          [](const std::string& name, const std::string& value) { return name + "='" + value + "'"; }};
}

void checkSeed(long long seed) {
  if (seed < 0 || seed > commands::kMaxSeed) throw UsageError("seed", "must be in [0, 2^53], got " + std::to_string(seed));
}

std::string pathArgument(const py::handle& path_arg) {
  if (!py::isinstance<py::str>(path_arg) && !py::hasattr(path_arg, "__fspath__")) {
    throw UsageError("path", "expected a str or os.PathLike, got " +
                                 py::str(py::type::handle_of(path_arg).attr("__name__")).cast<std::string>());
  }
  const py::object fs_path = py::module_::import("os").attr("fspath")(path_arg);
  if (!py::isinstance<py::str>(fs_path)) throw UsageError("path", "expected a text path (str), got bytes");
  return fs_path.cast<std::string>();
}

py::object toPython(const json& j) {
  switch (j.type()) {
    case json::value_t::null: return py::none();
    case json::value_t::boolean: return py::bool_(j.get<bool>());
    case json::value_t::number_integer: return py::int_(j.get<long long>());
    case json::value_t::number_unsigned: return py::int_(j.get<unsigned long long>());
    case json::value_t::number_float: return py::float_(j.get<double>());
    case json::value_t::string: return py::str(j.get<std::string>());
    case json::value_t::array: {
      py::list out;
      for (const json& x : j) out.append(toPython(x));
      return std::move(out);
    }
    case json::value_t::object: {
      py::dict out;
      for (auto it = j.begin(); it != j.end(); ++it) out[py::str(it.key())] = toPython(it.value());
      return std::move(out);
    }
    default: return py::none();
  }
}

py::array_t<double> matrixArray(const Eigen::Ref<const MatX>& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  auto w = out.mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) w(r, c) = m(r, c);
  }
  return out;
}

py::array_t<double> vectorArray(const Eigen::Ref<const VecX>& v) {
  py::array_t<double> out(v.size());
  auto w = out.mutable_unchecked<1>();
  for (Eigen::Index i = 0; i < v.size(); ++i) w(i) = v(i);
  return out;
}

py::array_t<double> poseArray(const Pose& T) {
  py::array_t<double> out({4, 4});
  auto w = out.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) w(r, c) = r < 3 ? (c < 3 ? T.R(r, c) : T.p(r)) : (c == 3 ? 1.0 : 0.0);
  }
  return out;
}

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string arrayProblem(const py::handle& x) {
  py::array a;
  if (py::isinstance<py::array>(x)) {
    a = py::reinterpret_borrow<py::array>(x);
  } else {
    // a list or other sequence: numpy's own reading of it (what the conversion would convert); one numpy cannot
    // read is left to the conversion
    try {
      const py::object o = py::module_::import("numpy").attr("asarray")(x);
      if (!py::isinstance<py::array>(o)) return "";
      a = py::reinterpret_borrow<py::array>(o);
    } catch (const py::error_already_set&) {
      return "";
    }
  }
  const char kind = a.dtype().kind();
  // text and objects too (numpy's float64 conversion parses '0.1' and calls float() on objects): an array of them is
  // not numbers; a 0-d one ("text", None) is left to the conversion (TypeError, or a shape ())
  const bool not_numbers = (kind == 'U' || kind == 'S' || kind == 'O' || kind == 'V') && a.ndim() >= 1;
  if (kind == 'c' || kind == 'M' || kind == 'm' || not_numbers) {
    return "expected real numbers, got an array of dtype " + py::str(a.dtype()).cast<std::string>() +
           (kind == 'c' ? " (its imaginary part would be dropped)" : "");
  }
  const long long rows = a.ndim() >= 2 ? static_cast<long long>(a.shape(0)) : 1;
  if (rows > kMaxArrayRows) {
    return std::to_string(rows) + " rows, more than the " + std::to_string(kMaxArrayRows) +
           " one call takes (the CLI's limit): split the array";
  }
  if (static_cast<long long>(a.size()) > kMaxArrayValues) {
    return std::to_string(a.size()) + " values, more than the " + std::to_string(kMaxArrayValues) +
           " one call takes (the CLI's limit): split the array";
  }
  return "";
}

void requireAccepted(const InArray& a, const std::string& subject, const std::string& what) {
  if (a.refused.empty()) return;
  if (subject.empty()) throw UsageError(what, a.refused);
  throw UsageError(subject, what + ": " + a.refused);
}

void requireFinite(const double* x, py::ssize_t count, py::ssize_t per_row, const std::string& subject,
                   const std::string& what) {
  for (py::ssize_t k = 0; k < count; ++k) {
    if (!std::isfinite(x[k])) {
      std::string where = what;
      if (per_row > 0) {
        where += "[" + std::to_string(k / per_row) + ", " + std::to_string(k % per_row) + "]";
      } else {
        where += "[" + std::to_string(k) + "]";
      }
      throw UsageError(subject, where + ": '" + io::shortest(x[k]) + "' is not finite");
    }
  }
}

void requireWithinLimits(const PoeModel& model, const double* q, py::ssize_t rows, const std::string& subject,
                         const std::string& what, bool batch, py::ssize_t first_row) {
  const int dof = model.dof();
  for (py::ssize_t k = 0; k < rows; ++k) {
    const Eigen::Map<const VecX> x(q + k * dof, dof);
    if (const int i = firstJointBeyondLimits(model, x); i >= 0) {
      const std::string where = batch ? "[" + std::to_string(first_row + k) + ", " + std::to_string(i) + "]"
                                      : "[" + std::to_string(i) + "]";
      throw UsageError(subject, what + where + ": " + commands::jointValueProblem(model, i, x[i]));
    }
  }
}

VecX jointVector(const InArray& q, int dof, const std::string& subject, const std::string& what, const PoeModel* model) {
  requireAccepted(q, subject, what);
  if (q.ndim() != 1 || q.shape(0) != dof) {
    throw UsageError(subject, what + ": expected " + std::to_string(dof) + " joint values (shape (" +
                                  std::to_string(dof) + ",)), got shape " + shapeText(q));
  }
  VecX out(dof);
  auto r = q.unchecked<1>();
  for (int i = 0; i < dof; ++i) out(i) = r(i);
  requireFinite(out.data(), dof, 0, subject, what);
  if (model) requireWithinLimits(*model, out.data(), 1, subject, what, false);
  return out;
}

MatX jointMatrix(const InArray& Q, int dof, const std::string& subject, const std::string& what, const PoeModel* model) {
  requireAccepted(Q, subject, what);
  if (Q.ndim() != 2 || Q.shape(1) != dof) {
    throw UsageError(subject, what + ": expected shape (N, " + std::to_string(dof) + "), got shape " + shapeText(Q));
  }
  MatX out(Q.shape(0), dof);
  auto r = Q.unchecked<2>();
  for (py::ssize_t k = 0; k < Q.shape(0); ++k) {
    for (int i = 0; i < dof; ++i) out(k, i) = r(k, i);
  }
  for (py::ssize_t k = 0; k < Q.shape(0); ++k) {
    for (int i = 0; i < dof; ++i) {
      if (!std::isfinite(out(k, i))) {
        throw UsageError(subject, what + "[" + std::to_string(k) + ", " + std::to_string(i) + "]: '" +
                                      io::shortest(out(k, i)) + "' is not finite");
      }
    }
  }
  if (model) {
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = out;
    requireWithinLimits(*model, rows.data(), rows.rows(), subject, what, true);
  }
  return out;
}

void warnUser(const std::string& text) {
  if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) throw py::error_already_set();
}

Mat3 quaternionRotation(double w, double x, double y, double z, const std::string& subject, Eigen::Index row) {
  double norm = 0.0;
  const std::optional<Mat3> R = io::unitQuaternionRotation(w, x, y, z, norm);
  if (!R) {
    throw UsageError(subject, "row " + std::to_string(row) + ": qw..qz is not a unit quaternion (norm " +
                                  io::shortest(norm) + ")");
  }
  return *R;
}

bool singlePrecision(const py::handle& a) {
  if (!py::isinstance<py::array>(a)) return false;
  const auto array = py::reinterpret_borrow<py::array>(a);
  return array.dtype().kind() == 'f' && array.itemsize() < 8;
}

void roundFromSinglePrecision(Pose& T) {
  constexpr double kSingleRounding = 64.0 * 1.1920928955078125e-07;
  if (!((T.R.transpose() * T.R - Mat3::Identity()).norm() <= kSingleRounding) || !(T.R.determinant() > 0.0)) return;
  const Eigen::JacobiSVD<Mat3> svd(T.R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  T.R = svd.matrixU() * svd.matrixV().transpose();
}

}  // namespace lowpair::python
