// The Python module lowpair._lowpair (docs/python.md): robots from robot files and MJCF/URDF models, forward
// kinematics (single and batched), Jacobians, the D-H table, singularities, identifiability, simulated
// measurements, calibration from arrays (poses, positions, tracker targets), inverse kinematics, compensation,
// calibration planning, save and export. Every call computes what the CLI computes, with the same library and
// harness functions, so the numbers are the CLI's (python/tests/ compares each result with the CLI's --json);
// errors are lowpair.Error with the CLI's one-line message. A command's logic beyond its argument parsing lives
// in the validation room (plan_report, ik_rows, simulation, calibration_inputs, calibration_run), which the CLI
// calls too; this file converts arrays and arguments and calls it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "io/atomic_file.hpp"
#include "io/export.hpp"
#include "io/measurements.hpp"
#include "io/one_line.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "io/singularity_output.hpp"
#include "io/urdf_reader.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/ik.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/plan.hpp"
#include "lowpair/singularity.hpp"
#include "lowpair/tolerances.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "validation/arguments.hpp"
#include "validation/calibration_inputs.hpp"
#include "validation/calibration_output.hpp"
#include "validation/calibration_run.hpp"
#include "validation/ik_rows.hpp"
#include "validation/plan_report.hpp"
#include "validation/simulation.hpp"
#include "validation/sampling.hpp"

namespace py = pybind11;
using nlohmann::json;

namespace lowpair::python {

namespace {

// A bad argument (not a file): raised as lowpair.Error("SUBJECT: message"), as the CLI prints it; the error of
// the validation room's shared checks, as in cli/commands.hpp.
using UsageError = validation::UsageError;

// Python's spelling of an argument in the validation room's shared checks: "noise_position", "measure='targets'".
validation::ArgumentSpelling pythonSpelling() {
  return {[](const std::string& name) { return name; },
          [](const std::string& name, const std::string& value) { return name + "='" + value + "'"; }};
}


// A seed of the sampling streams, as the CLI's --seed takes it: a whole number in [0, 2^53].
void checkSeed(long long seed) {
  if (seed < 0 || seed > validation::kMaxSeed) throw UsageError("seed", "must be in [0, 2^53], got " + std::to_string(seed));
}

// nlohmann::json -> Python objects (numbers keep their double bits).
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

// ----- arrays ------------------------------------------------------------------------------------------

using InArray = py::array_t<double, py::array::forcecast>;

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

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Finite check of a joint array, naming the first bad value like the CLI's --q ("'nan' is not finite").
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

// (n,) joint vector.
VecX jointVector(const InArray& q, int dof, const std::string& subject, const std::string& what = "q") {
  if (q.ndim() != 1 || q.shape(0) != dof) {
    throw UsageError(subject, what + ": expected " + std::to_string(dof) + " joint values (shape (" +
                                  std::to_string(dof) + ",)), got shape " + shapeText(q));
  }
  VecX out(dof);
  auto r = q.unchecked<1>();
  for (int i = 0; i < dof; ++i) out(i) = r(i);
  requireFinite(out.data(), dof, 0, subject, what);
  return out;
}

// (N, n) joint values, column-major (what the library takes).
MatX jointMatrix(const InArray& Q, int dof, const std::string& subject, const std::string& what = "q") {
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
  return out;
}

// ----- the robot ---------------------------------------------------------------------------------------

// An immutable robot: the file as read (or made), its POE model and, for a D-H file, its own D-H model.
struct Robot {
  io::RobotFile file;
  PoeModel poe;
  std::vector<std::string> comments;  // provenance lines for save() (a calibrated robot's)

  explicit Robot(io::RobotFile f, std::vector<std::string> c = {})
      : file(std::move(f)), poe(file.poeModel()), comments(std::move(c)) {}

  bool ownDh() const { return file.dh.has_value(); }
  int dof() const { return poe.dof(); }
  std::string subject() const { return file.path.empty() ? (file.name.empty() ? "robot" : file.name) : file.path; }

  // The D-H model of `fk(model="dh")`: the file's own, or poeToDh of the POE model (made once, thread-safe).
  const DhModel& dhModel() const {
    if (file.dh) return *file.dh;
    std::call_once(dh_once_, [this] {
      try {
        converted_dh_.emplace(poeToDh(poe).model);
      } catch (const std::exception& e) {
        dh_error_ = e.what();
      }
    });
    if (!converted_dh_) throw std::invalid_argument(dh_error_);
    return *converted_dh_;
  }

 private:
  mutable std::once_flag dh_once_;
  mutable std::optional<DhModel> converted_dh_;
  mutable std::string dh_error_;
};
using RobotPtr = std::shared_ptr<Robot>;  // immutable by convention: no method changes it

// One Data per thread, rebuilt when the dof changes (a Data fits every model of its dof: kinematics.hpp).
Data& threadData(const KinematicChain& chain, int dof) {
  thread_local std::unique_ptr<Data> data;
  if (!data || data->dof != dof) data = std::make_unique<Data>(chain);
  return *data;
}

// As cli/main.cpp loadRobot (its checks in this module's words): a robot file, or the chain of an MJCF (MuJoCo) / URDF (urdfdom) model to `tip`.
io::RobotFile loadFile(const std::string& path, const std::optional<std::string>& tip,
                       const std::optional<std::string>& base) {
  const std::string ext = std::filesystem::path(path).extension().string();
  const std::string tip_name = tip.value_or(""), base_name = base.value_or("");
  if (ext != ".xml" && ext != ".urdf") {
    if (!tip_name.empty() || !base_name.empty()) {
      throw UsageError(path, "tip/base go with a model file (.xml or .urdf), not a robot file");
    }
    return io::readRobotFile(path);
  }
  if (tip_name.empty()) throw UsageError(path, "tip=NAME is required with a model file");
  return mujoco::robotFileOfModel(path, tip_name, base_name);
}

std::string kindOf(const Robot& r, const std::optional<std::string>& model) {
  const std::string kind = model.value_or("file");
  if (kind == "file") return r.ownDh() ? "dh" : "poe";
  if (kind != "poe" && kind != "dh") throw UsageError("model", "expected 'poe', 'dh' or None, got '" + kind + "'");
  return kind;
}

// ----- forward kinematics -------------------------------------------------------------------------------

// A float64 array read in place: C-contiguous and aligned (what numpy makes). Anything else (lists, integers,
// Fortran order, strided views, other byte orders) is converted by numpy first, as InArray is.
using CArray = py::array_t<double, py::array::c_style | py::array::forcecast | py::detail::npy_api::NPY_ARRAY_ALIGNED_>;

CArray cArray(const py::handle& x, const char* what) {
  if (CArray::check_(x) && py::detail::check_flags(x.ptr(), py::detail::npy_api::NPY_ARRAY_ALIGNED_)) {
    return py::reinterpret_borrow<CArray>(x);
  }
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
    throw UsageError("out", "expected a writeable C-contiguous float64 array of shape " + want + "), got shape " +
                                shapeText(a));
  }
  return static_cast<double*>(const_cast<void*>(a.data()));  // writeable, checked above
}

// T as a row-major 4 x 4 matrix.
void writePose(const Pose& T, double* dst) {
  for (int a = 0; a < 3; ++a) {
    dst[4 * a + 0] = T.R(a, 0), dst[4 * a + 1] = T.R(a, 1), dst[4 * a + 2] = T.R(a, 2), dst[4 * a + 3] = T.p(a);
  }
  dst[12] = 0.0, dst[13] = 0.0, dst[14] = 0.0, dst[15] = 1.0;
}

// Batched FK, chunk by chunk: 256 configurations (a multiple of every SIMD block, 4 or 8, so the blocks are
// those of one whole call) keep the chunk's joint values and poses (36 KB for six joints) in the L1 cache.
constexpr Eigen::Index kFkChunk = 256;
// Results of at least this many bytes are written with non-temporal stores when their pages are resident: they
// bypass the caches the result would not fit in anyway, and skip reading each line before writing it (12.8 MB for
// N = 100,000). Smaller results stay in the cache for the caller's next read. Into pages not yet faulted in
// (memory new to the process) non-temporal stores cost more than plain ones (docs/python.md, "Speed").
constexpr size_t kStreamBytes = size_t{1} << 20;

// Whether every page of [p, p + bytes) is resident (mincore; one system call, ~3,000 pages for 12.8 MB).
bool resident(const void* p, size_t bytes) {
#if defined(__linux__)
  const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const uintptr_t begin = reinterpret_cast<uintptr_t>(p) & ~(page - 1), end = reinterpret_cast<uintptr_t>(p) + bytes;
  std::vector<unsigned char> pages((end - begin + page - 1) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, pages.data()) != 0) return false;
  return std::all_of(pages.begin(), pages.end(), [](unsigned char c) { return (c & 1) != 0; });
#else
  (void)p, (void)bytes;
  return true;
#endif
}

// The chunk's rows of the row-major (len x dof) q, transposed into the column-major Q the library takes: two
// rows at a time, each 2 x 2 block (row pair, joint pair) transposed in registers (SSE2), the finiteness check
// folded in; false when a value is not finite.
bool transposeChunk(const double* q, Eigen::Index len, Eigen::Index dof, MatX& Q) {
  constexpr double kLargest = std::numeric_limits<double>::max();
  double* dst = Q.data();
  const Eigen::Index ld = Q.rows();
  bool finite = true;
  Eigen::Index k = 0;
#if defined(__SSE2__)
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff)), largest = _mm_set1_pd(kLargest);
  __m128d bad = _mm_setzero_pd();  // lanes of NaN or +-inf: not (|x| <= largest)
  for (; k + 2 <= len; k += 2) {
    const double* a = q + k * dof;  // rows k and k + 1
    const double* b = a + dof;
    Eigen::Index i = 0;
    for (; i + 2 <= dof; i += 2) {
      const __m128d ra = _mm_loadu_pd(a + i), rb = _mm_loadu_pd(b + i);
      bad = _mm_or_pd(bad, _mm_or_pd(_mm_cmpnle_pd(_mm_and_pd(ra, magnitude), largest),
                                     _mm_cmpnle_pd(_mm_and_pd(rb, magnitude), largest)));
      _mm_storeu_pd(dst + i * ld + k, _mm_unpacklo_pd(ra, rb));
      _mm_storeu_pd(dst + (i + 1) * ld + k, _mm_unpackhi_pd(ra, rb));
    }
    for (; i < dof; ++i) {
      dst[i * ld + k] = a[i], dst[i * ld + k + 1] = b[i];
      finite &= std::abs(a[i]) <= kLargest && std::abs(b[i]) <= kLargest;
    }
  }
  finite &= _mm_movemask_pd(bad) == 0;
#endif
  for (; k < len; ++k) {
    for (Eigen::Index i = 0; i < dof; ++i) {
      const double x = q[k * dof + i];
      dst[i * ld + k] = x;
      finite &= std::abs(x) <= kLargest;
    }
  }
  return finite;
}

// The library's (len x 12) column-major poses (rotation row-major in columns 0..8, position in 9..11) as len
// row-major 4 x 4 matrices at `out`: two configurations at a time, each 2 x 2 block of (column pair, pose
// pair) transposed in registers (SSE2, the x86-64 baseline); `stream`: non-temporal stores (out 16-aligned).
void repackChunk(const MatX& poses, Eigen::Index len, double* out, bool stream) {
  const double* c = poses.data();
  const Eigen::Index ld = poses.rows();
  Eigen::Index k = 0;
#if defined(__SSE2__)
  const __m128d zero_zero = _mm_setzero_pd(), zero_one = _mm_set_pd(1.0, 0.0);
  auto store = [stream](double* dst, __m128d v) { stream ? _mm_stream_pd(dst, v) : _mm_storeu_pd(dst, v); };
  for (; k + 2 <= len; k += 2, out += 32) {
    for (int a = 0; a < 3; ++a) {
      const __m128d r0 = _mm_loadu_pd(c + (3 * a + 0) * ld + k), r1 = _mm_loadu_pd(c + (3 * a + 1) * ld + k);
      const __m128d r2 = _mm_loadu_pd(c + (3 * a + 2) * ld + k), p = _mm_loadu_pd(c + (9 + a) * ld + k);
      store(out + 4 * a, _mm_unpacklo_pd(r0, r1));
      store(out + 4 * a + 2, _mm_unpacklo_pd(r2, p));
      store(out + 16 + 4 * a, _mm_unpackhi_pd(r0, r1));
      store(out + 16 + 4 * a + 2, _mm_unpackhi_pd(r2, p));
    }
    store(out + 12, zero_zero), store(out + 14, zero_one), store(out + 28, zero_zero), store(out + 30, zero_one);
  }
#endif
  for (; k < len; ++k, out += 16) {
    for (int a = 0; a < 3; ++a) {
      out[4 * a + 0] = c[(3 * a + 0) * ld + k], out[4 * a + 1] = c[(3 * a + 1) * ld + k];
      out[4 * a + 2] = c[(3 * a + 2) * ld + k], out[4 * a + 3] = c[(9 + a) * ld + k];
    }
    out[12] = 0.0, out[13] = 0.0, out[14] = 0.0, out[15] = 1.0;
  }
}

// Batched FK of `count` configurations (row-major count x dof `q`) into `out` (count x 4 x 4, row-major): per
// chunk, transposeChunk (with the finiteness check), forwardKinematicsBatch, repackChunk. Called without the GIL
// (the caller keeps `q` and `out` alive).
void fkBatchInto(const Robot& r, bool poe, const double* q, Eigen::Index count, double* out) {
  const Eigen::Index dof = r.dof(), rows = std::min(count, kFkChunk);
  MatX Q(rows, dof), poses(rows, 12);
  bool stream = false;
#if defined(__SSE2__)
  const size_t bytes = static_cast<size_t>(count) * 16 * sizeof(double);
  stream = bytes >= kStreamBytes && reinterpret_cast<uintptr_t>(out) % 16 == 0 && resident(out, bytes);
#endif
  for (Eigen::Index start = 0; start < count; start += kFkChunk) {
    const Eigen::Index len = std::min(kFkChunk, count - start);
    if (!transposeChunk(q + start * dof, len, dof, Q)) {
      requireFinite(q, (start + len) * dof, dof, r.subject(), "q");  // throws, naming the first value
    }
    if (poe) {
      forwardKinematicsBatch(r.poe, Q.topRows(len), poses.topRows(len));
    } else {
      forwardKinematicsBatch(r.dhModel(), Q.topRows(len), poses.topRows(len));
    }
    repackChunk(poses, len, out + 16 * start, stream);
  }
#if defined(__SSE2__)
  if (stream) _mm_sfence();  // the non-temporal stores are visible before the GIL is taken back
#endif
}

py::object fk(const Robot& r, const py::object& q_arg, const std::optional<std::string>& model,
              const std::optional<py::array>& out_arg) {
  const std::string kind = kindOf(r, model);
  const CArray q = cArray(q_arg, "q");
  const int dof = r.dof();
  if (q.ndim() == 1) {
    if (q.shape(0) != dof) {
      throw UsageError(r.subject(), "q: expected " + std::to_string(dof) + " joint values (shape (" +
                                        std::to_string(dof) + ",)), got shape " + shapeText(q));
    }
    const Eigen::Map<const VecX> x(q.data(), dof);
    if (!x.allFinite()) requireFinite(x.data(), dof, 0, r.subject(), "q");  // throws, naming the value
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
    fkBatchInto(r, kind == "poe", q.data(), count, dst);
  }
  if (out_arg) return *out_arg;
  return std::move(result);
}

py::array_t<double> jacobian(const Robot& r, const InArray& q, const std::string& frame) {
  if (frame != "spatial" && frame != "body" && frame != "geometric") {
    throw UsageError("frame", "expected 'spatial', 'body' or 'geometric', got '" + frame + "'");
  }
  const VecX x = jointVector(q, r.dof(), r.subject());
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

// ----- the D-H table -----------------------------------------------------------------------------------

struct DhTable {
  DhConversion conversion;
  FkCheck check;
  json j;
};

DhTable dhTable(const Robot& r, double parallel_threshold, bool modified) {
  ConvertOptions options;
  options.parallel_threshold = parallel_threshold;
  DhConversion c = poeToDh(r.poe, options);
  const FkCheck check = checkDhConversion(r.poe, c.model);
  json j = modified ? io::modifiedDhJson(r.file, c, check) : io::dhJson(r.file, c, check);
  return DhTable{std::move(c), check, std::move(j)};
}

// ----- singularities (io/singularity_output.hpp) ----------


struct Singularity {
  SingularityReport report;
  json j;
};

Singularity singular(const Robot& r, const InArray& q) {
  const VecX x = jointVector(q, r.dof(), r.subject());
  SingularityOptions options;
  options.max_null_vectors = io::kPrintedNullVectors;
  SingularityReport report = analyzeSingularity(r.poe, x, options);
  json j = io::singularityJson(r.file, x, report);
  return Singularity{std::move(report), std::move(j)};
}

// ----- identifiability ---------------------------------------------------------------------------------


std::vector<Vec3> fileTargets(const io::RobotFile& file) {
  if (file.targets.empty()) {
    throw UsageError(file.path, "measure='targets' needs a `targets:` list in the robot file (docs/file_formats.md)");
  }
  std::vector<Vec3> points;
  for (const Target& t : file.targets) points.push_back(*t.point_tool);
  return points;
}

struct IdentifiabilityResult {
  Identifiability id;
  json j;
};

IdentifiabilityResult identifiability(const Robot& r, const std::string& measure_text, int poses, long long seed,
                                      bool free_pitch) {
  const Measure measure = validation::parseMeasure(measure_text, pythonSpelling());
  if (poses < 1 || poses > validation::kMaxIdentifiabilityPoses) {
    throw UsageError("poses", "must be in [1, " + std::to_string(validation::kMaxIdentifiabilityPoses) + "], got " +
                                  std::to_string(poses));
  }
  checkSeed(seed);
  const PoeModel& model = r.poe;
  if (validation::identificationEntries(poses, model.dof(), 9.0) > validation::kMaxJacobianEntries) {
    const bool robot = validation::identificationEntries(1, model.dof(), 9.0) > validation::kMaxJacobianEntries;
    throw UsageError(robot ? r.file.path : std::string("poses"),
                     std::to_string(poses) + " poses of a " + std::to_string(model.dof()) +
                         "-joint robot exceed the identification size limit (" +
                         io::shortest(validation::kMaxJacobianEntries) +
                         " numbers: the Jacobian and the SVD's V, columns squared)");
  }
  const std::vector<Vec3> targets = measure == Measure::Targets ? fileTargets(r.file) : std::vector<Vec3>{};
  Identifiability id;
  {
    py::gil_scoped_release release;
    const auto ranges = validation::samplingRanges(model);
    std::vector<VecX> q(static_cast<size_t>(poses), VecX(model.dof()));
    for (int i = 0; i < poses; ++i) {
      validation::randomSample(static_cast<unsigned long long>(seed), static_cast<unsigned long long>(i), ranges,
                               q[static_cast<size_t>(i)]);
    }
    id = analyzeIdentifiability(model, q, measure, free_pitch, targets);
  }
  json j = validation::identifiabilityJson(r.file, id);
  j["poses"] = poses;
  j["seed"] = seed;
  return IdentifiabilityResult{std::move(id), std::move(j)};
}

// ----- calibration -------------------------------------------------------------------------------------

// A rotation from a quaternion qw, qx, qy, qz by the measurement CSV reader's rule (io::unitQuaternionRotation),
// so that arrays and a CSV of the same numbers give the same bits.
Mat3 quaternionRotation(double w, double x, double y, double z, const std::string& subject, Eigen::Index row) {
  double norm = 0.0;
  const std::optional<Mat3> R = io::unitQuaternionRotation(w, x, y, z, norm);
  if (!R) {
    throw UsageError(subject, "row " + std::to_string(row) + ": qw..qz is not a unit quaternion (norm " +
                                  io::shortest(norm) + ")");
  }
  return *R;
}

struct Calibration {
  validation::CalibrationReport report;
  RobotPtr robot;
  json j;
};

// The target names of target measurements (the CSV's `target` column, one per row), numbered in order of first
// appearance as the CSV reader numbers them: sets each measurement's index and returns the names.
std::vector<std::string> numberTargets(const std::vector<std::string>& names, std::vector<Measurement>& measurements,
                                       const std::string& subject) {
  if (names.size() != measurements.size()) {
    throw UsageError(subject, "expected " + std::to_string(measurements.size()) + " target names (one per row), got " +
                                  std::to_string(names.size()));
  }
  io::TargetNumbering numbering;
  for (size_t k = 0; k < names.size(); ++k) {
    std::string problem;
    measurements[k].target = numbering.number(names[k], problem);
    if (measurements[k].target >= 0) continue;
    if (problem.empty()) throw UsageError(subject, "more than " + std::to_string(io::kMaxTargets) + " distinct targets");
    throw UsageError(subject, "[" + std::to_string(k) + "]: " + io::quotedFileText(names[k]) + " " + problem + " (" +
                                  io::kTargetNameRule + ")");
  }
  return std::move(numbering.names);
}

// The measurement CSV's columns as arrays: q (N, n); positions (N, 3); rotations (N, 4) qw..qz for pose
// measurements; targets (N names) for target measurements (positions are then the targets' points).
io::MeasurementFile measurementArrays(const Robot& r, const InArray& q, const InArray& positions,
                                      const std::optional<InArray>& rotations,
                                      const std::optional<std::vector<std::string>>& targets, const std::string& prefix) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject(), prefix + "q");
  const auto N = Q.rows();
  if (N == 0) throw UsageError(prefix + "q", "no measurements");
  if (positions.ndim() != 2 || positions.shape(0) != N || positions.shape(1) != 3) {
    throw UsageError(prefix + "positions", "expected shape (" + std::to_string(N) + ", 3), got shape " +
                                               shapeText(positions));
  }
  if (rotations && targets) {
    throw UsageError(prefix + "rotations", "target measurements are points: give rotations or targets, not both");
  }
  if (rotations && (rotations->ndim() != 2 || rotations->shape(0) != N || rotations->shape(1) != 4)) {
    throw UsageError(prefix + "rotations", "expected shape (" + std::to_string(N) +
                                               ", 4) (unit quaternions qw, qx, qy, qz), got shape " +
                                               shapeText(*rotations));
  }
  io::MeasurementFile file;
  file.path = prefix.empty() ? "<arrays>" : "<validation arrays>";
  file.dof = r.dof();
  file.measure = rotations ? Measure::Pose : targets ? Measure::Targets : Measure::Position;
  file.length_unit = r.file.length_unit;
  file.measurements.resize(static_cast<size_t>(N));
  auto p = positions.unchecked<2>();
  for (Eigen::Index k = 0; k < N; ++k) {
    Measurement& m = file.measurements[static_cast<size_t>(k)];
    m.q = Q.row(k).transpose();
    for (int a = 0; a < 3; ++a) {
      m.T_base_tool.p(a) = p(k, a);
      if (!std::isfinite(p(k, a))) {
        throw UsageError(prefix + "positions", "[" + std::to_string(k) + ", " + std::to_string(a) + "]: '" +
                                                   io::shortest(p(k, a)) + "' is not finite");
      }
    }
    if (rotations) {
      auto w = rotations->unchecked<2>();
      m.T_base_tool.R = quaternionRotation(w(k, 0), w(k, 1), w(k, 2), w(k, 3), prefix + "rotations", k);
    }
    file.lines.push_back(static_cast<long long>(k));
  }
  if (targets) file.target_names = numberTargets(*targets, file.measurements, prefix + "targets");
  return file;
}

// Python's UserWarning `text` (with the GIL held); under -W error it raises.
void warnUser(const std::string& text) {
  if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 1) != 0) throw py::error_already_set();
}

// The joint values against the nominal's ranges, as `lowpair calibrate` checks a measurement file's
// (validation::checkJointRanges): one beyond kFarOutsideRange range widths outside is a wrong column or unit,
// never fitted silently; nearer ones are UserWarnings (the first few, then their count).
void checkRanges(const Robot& r, const io::MeasurementFile& m, const std::string& prefix) {
  const std::string subject = prefix + "q";
  const int outside = validation::checkJointRanges(
      r.poe, m.measurements, r.subject(),
      [](const validation::OutsideRange& x) {
        return "[" + std::to_string(x.row) + ", " + std::to_string(x.joint) + "]";
      },
      [&](const std::string& text) { throw UsageError(subject, text); },
      [&](const std::string& text) { warnUser(subject + ": " + text); });
  if (outside > validation::kMaxRangeWarnings) {
    warnUser(subject + ": " + std::to_string(outside) + " joint values outside the ranges in all");
  }
}

Calibration calibrateArrays(const Robot& r, io::MeasurementFile fit, std::optional<io::MeasurementFile> held_out,
                            const validation::CalibrationRequest& request) {
  if (const auto problem = validation::calibrationSizeProblem(fit.measurements.size(), r.dof())) {
    throw UsageError("q", *problem);
  }
  checkRanges(r, fit, "");
  if (held_out) {
    checkRanges(r, *held_out, "validation_");
    // targets by name: the validation rows' indices mapped to the fit's
    if (const auto unknown = validation::mapValidationTargets(*held_out, fit.target_names)) {
      throw UsageError("validation_targets", "target " + *unknown + " is not measured in the fit (targets)");
    }
  }
  std::optional<validation::CalibrationReport> report;
  {
    py::gil_scoped_release release;
    report.emplace(validation::runCalibration(r.file, r.poe, std::move(fit), std::move(held_out), request,
                                              pythonSpelling()));
  }
  // the calibrated robot, as `calibrate --out` writes it
  io::RobotFile calibrated;
  calibrated.name = validation::calibratedName(r.file);
  calibrated.length_unit = r.file.length_unit;
  calibrated.angle_unit = r.file.angle_unit;
  calibrated.description = "calibrated by lowpair.calibrate (Python) from arrays";
  calibrated.poe = report->result.model;
  calibrated.targets = validation::calibratedTargets(*report);
  auto robot = std::make_shared<Robot>(std::move(calibrated), validation::calibrationProvenance(*report));
  json j = validation::calibrationJson(*report);
  return Calibration{std::move(*report), std::move(robot), std::move(j)};
}

Calibration calibrateFromArrays(const Robot& r, const InArray& q, const InArray& positions,
                                const std::optional<InArray>& rotations, std::optional<double> noise_position,
                                std::optional<double> noise_rotation, bool free_pitch, const std::string& loss,
                                double outlier_threshold, const std::optional<std::string>& parameters,
                                const std::optional<InArray>& validation_q,
                                const std::optional<InArray>& validation_positions,
                                const std::optional<InArray>& validation_rotations,
                                const std::optional<std::vector<std::string>>& targets,
                                const std::optional<std::vector<std::string>>& validation_targets,
                                const std::optional<std::string>& select, int folds, int repeats) {
  io::MeasurementFile fit = measurementArrays(r, q, positions, rotations, targets, "");
  std::optional<io::MeasurementFile> held_out;
  if (validation_q || validation_positions || validation_rotations || validation_targets) {
    if (!validation_q || !validation_positions) {
      throw UsageError("validation_q", "give validation_q and validation_positions (and validation_rotations or "
                                       "validation_targets as the fit has rotations or targets)");
    }
    if (validation_rotations.has_value() != rotations.has_value()) {
      throw UsageError("validation_rotations", rotations ? "the fit has pose measurements: give validation_rotations too"
                                                         : "the fit has no pose measurements: no validation_rotations");
    }
    if (validation_targets.has_value() != targets.has_value()) {
      throw UsageError("validation_targets", targets ? "the fit has target measurements: give validation_targets too"
                                                     : "the fit has no target measurements: no validation_targets");
    }
    held_out = measurementArrays(r, *validation_q, *validation_positions, validation_rotations, validation_targets,
                                 "validation_");
  }
  const validation::CalibrationRequest request{noise_position, noise_rotation, free_pitch, loss, outlier_threshold,
                                               parameters,     select,         folds,      repeats};
  return calibrateArrays(r, std::move(fit), std::move(held_out), request);
}

// ----- inverse kinematics, compensation (lowpair/ik.hpp; `lowpair ik`, `lowpair compensate`) ------------

// The rows of `ik` or `compensate` and the JSON of the CLI's --json (cli/ik_commands.cpp) without its files.
struct IkSolutions {
  std::vector<validation::IkRow> rows;  // line: the 0-based row
  json j;
};

// The targets of ik: (N, 4, 4) homogeneous transforms, or (N, 3) positions, made poses by rotations (N, 4) qw..qz
// (the targets CSV's columns, converted as its reader converts them).
std::vector<Pose> ikTargets(const InArray& targets, const std::optional<InArray>& rotations, bool& pose) {
  std::vector<Pose> out;
  if (targets.ndim() == 3 && targets.shape(1) == 4 && targets.shape(2) == 4) {
    if (rotations) throw UsageError("rotations", "the targets are 4 x 4 transforms: they hold their rotations");
    pose = true;
    auto t = targets.unchecked<3>();
    for (py::ssize_t k = 0; k < t.shape(0); ++k) {
      Pose T;
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) T.R(a, c) = t(k, a, c);
        T.p(a) = t(k, a, 3);
      }
      if (!(t(k, 3, 0) == 0.0 && t(k, 3, 1) == 0.0 && t(k, 3, 2) == 0.0 && t(k, 3, 3) == 1.0)) {
        throw UsageError("targets", "[" + std::to_string(k) + "]: the last row of a transform must be [0, 0, 0, 1]");
      }
      out.push_back(T);
    }
  } else if (targets.ndim() == 2 && targets.shape(1) == 3) {
    pose = rotations.has_value();
    if (rotations && (rotations->ndim() != 2 || rotations->shape(0) != targets.shape(0) || rotations->shape(1) != 4)) {
      throw UsageError("rotations", "expected shape (" + std::to_string(targets.shape(0)) +
                                        ", 4) (unit quaternions qw, qx, qy, qz), got shape " + shapeText(*rotations));
    }
    auto t = targets.unchecked<2>();
    for (py::ssize_t k = 0; k < t.shape(0); ++k) {
      Pose T;
      T.p = Vec3(t(k, 0), t(k, 1), t(k, 2));
      if (rotations) {
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

// Per-row seeds: None, (n,) for every row, or (N, n).
std::optional<MatX> seedRows(const Robot& r, const std::optional<InArray>& q0, size_t rows) {
  if (!q0) return std::nullopt;
  if (q0->ndim() == 1) {
    const VecX x = jointVector(*q0, r.dof(), r.subject(), "q0");
    return MatX(x.transpose().replicate(static_cast<Eigen::Index>(rows), 1));
  }
  MatX Q = jointMatrix(*q0, r.dof(), r.subject(), "q0");
  if (Q.rows() != static_cast<Eigen::Index>(rows)) {
    throw UsageError("q0", "expected shape (" + std::to_string(rows) + ", " + std::to_string(r.dof()) + ") or (" +
                               std::to_string(r.dof()) + ",), got shape " + shapeText(*q0));
  }
  return Q;
}

// `lowpair ik`: one problem per target, from q0 (the CSV's q columns) or from up to `seeds` random seeds (sample
// k * seeds + s of the stream `seed`, the sampling convention), the first ok kept, else the best attempt.
IkSolutions ik(const Robot& r, const InArray& targets_arg, const std::optional<InArray>& rotations,
               const std::optional<InArray>& q0, int seeds, long long seed) {
  if (seeds < 1 || seeds > validation::kMaxIkSeeds) {
    throw UsageError("seeds", "must be in [1, " + std::to_string(validation::kMaxIkSeeds) + "], got " +
                                  std::to_string(seeds));
  }
  checkSeed(seed);
  bool pose = false;
  const std::vector<Pose> targets = ikTargets(targets_arg, rotations, pose);
  const std::optional<MatX> given = seedRows(r, q0, targets.size());
  const PoeModel& model = r.poe;
  IkOptions options;
  options.measure = pose ? Measure::Pose : Measure::Position;
  IkSolutions s;
  s.rows.reserve(targets.size());
  {
    py::gil_scoped_release release;
    const std::vector<validation::Range> ranges = validation::samplingRanges(model);
    Data data(model);
    IkWorkspace work(model);
    for (size_t k = 0; k < targets.size(); ++k) {
      const auto line = static_cast<long long>(k);
      try {
        if (given) {
          s.rows.push_back({inverseKinematics(model, data, targets[k], given->row(static_cast<Eigen::Index>(k)).transpose(),
                                              options, work),
                            -1, line});
        } else {
          s.rows.push_back(validation::solveFromRandomSeeds(model, data, targets[k], k, seeds,
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
         {"counts", validation::ikCountsJson(s.rows)}};
  s.j["rows"] = validation::ikRowsJson(s.rows, true);
  return s;
}

// `lowpair compensate`: the joint values of `calibrated` that put the tool where `nominal` puts it at each q.
IkSolutions compensateRows(const Robot& calibrated, const Robot& nominal, const InArray& q_arg,
                           const std::string& measure) {
  if (measure != "pose" && measure != "position") {
    throw UsageError("measure", "expected 'pose' or 'position', got '" + measure + "'");
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
  const MatX Q = q_arg.ndim() == 1 ? MatX(jointVector(q_arg, calibrated.dof(), calibrated.subject()).transpose())
                                   : jointMatrix(q_arg, calibrated.dof(), calibrated.subject());
  IkOptions options;
  options.measure = measure == "pose" ? Measure::Pose : Measure::Position;
  IkSolutions s;
  {
    py::gil_scoped_release release;
    std::vector<long long> lines(static_cast<size_t>(Q.rows()));
    for (size_t k = 0; k < lines.size(); ++k) lines[k] = static_cast<long long>(k);
    s.rows = validation::compensateJointRows(nominal.poe, calibrated.poe, Q, lines, options);
  }
  s.j = {{"name", calibrated.file.name},
         {"source", calibrated.file.path},
         {"nominal", nominal.file.path},
         {"q_file", "<arrays>"},
         {"length_unit", calibrated.file.length_unit},
         {"measure", measure},
         {"counts", validation::ikCountsJson(s.rows)}};
  s.j["rows"] = validation::ikRowsJson(s.rows, false);
  return s;
}

// ----- plan (lowpair/plan.hpp; `lowpair plan`, cli/plan_command.cpp) ---------------------------------------

// The JSON of `plan --json` without --out (the planned joint vectors are q), kept beside the report.
struct PlanOutcome {
  validation::PlanReport report;
  json j;
};

PlanOutcome plan(const Robot& r, int poses, int candidate_count, const std::string& measure_text,
                 const std::string& criterion_text, long long seed, std::optional<double> noise_position,
                 std::optional<double> noise_rotation, bool free_pitch) {
  // the checks the CLI's parser makes (CLI::Range, CLI::IsMember); the rest are the report's
  if (poses < 1 || poses > validation::kMaxPlanPoses) {
    throw UsageError("poses", "must be in [1, " + std::to_string(validation::kMaxPlanPoses) + "], got " +
                                  std::to_string(poses));
  }
  if (candidate_count < 1 || candidate_count > validation::kMaxPlanCandidates) {
    throw UsageError("candidates", "must be in [1, " + std::to_string(validation::kMaxPlanCandidates) + "], got " +
                                       std::to_string(candidate_count));
  }
  checkSeed(seed);
  if (criterion_text != "D" && criterion_text != "O1") {
    throw UsageError("criterion", "expected 'D' or 'O1', got '" + criterion_text + "'");
  }
  validation::PlanRequest request;
  request.measure = validation::parseMeasure(measure_text, pythonSpelling());
  request.criterion = criterion_text == "O1" ? PlanCriterion::O1 : PlanCriterion::D;
  request.poses = poses;
  request.candidates = candidate_count;
  request.seed = seed;
  request.free_pitch = free_pitch;
  request.noise_position = noise_position;
  request.noise_rotation = noise_rotation;
  PlanOutcome o;
  {
    py::gil_scoped_release release;
    o.report = validation::makePlanReport(r.file, request, pythonSpelling());
  }
  o.j = validation::planJson(o.report, "");
  return o;
}

// ----- simulate (validation/sampling.hpp; `lowpair simulate` of a robot file, cli/simulate_command.cpp) ----

struct Simulation {
  Measure measure = Measure::Pose;
  std::vector<Measurement> measurements;
  std::vector<std::string> target_names;  // Targets: the names measurement.target indexes
  std::vector<size_t> blunders;           // the rows moved, increasing
  std::vector<std::string> comments;      // for save(): where the file came from
  std::string length_unit;                // of the positions; "" when unknown
  std::vector<long long> lines;           // read_measurements: the file line of each row
  std::vector<std::string> notes;         // read_measurements: a unit conversion
};

// Measurements of the robot's tool by the library's POE FK (the truth `lowpair simulate` uses for a robot file):
// at `poses` random joint vectors (sample k of the stream `seed`) or at the rows of q; in a measurement frame;
// with the seeded noise and blunders of validation/sampling.hpp, so the same arguments give the CLI's numbers.
Simulation simulate(const Robot& r, std::optional<int> poses, const std::optional<InArray>& q_arg, long long seed,
                    const std::string& measure_text, const std::optional<std::vector<std::string>>& targets,
                    const std::optional<std::vector<double>>& frame, double noise_position, double noise_rotation,
                    const std::optional<std::tuple<double, double>>& blunders) {
  if (poses.has_value() == q_arg.has_value()) throw UsageError("poses", "give poses=N or q=(N, n) joint values, one of them");
  if (poses && (*poses < 1 || *poses > validation::kMaxSimulatedPoses)) {
    throw UsageError("poses", "must be in [1, " + std::to_string(validation::kMaxSimulatedPoses) + "], got " +
                                  std::to_string(*poses));
  }
  checkSeed(seed);
  const Measure measure = validation::parseMeasure(measure_text, pythonSpelling());
  validation::checkSimulationArguments(measure, noise_position, noise_rotation, targets.has_value(), pythonSpelling());
  validation::MeasurementSetup setup;
  setup.measure = measure;
  Simulation s;
  s.measure = measure;
  if (measure == Measure::Targets) {
    s.target_names = validation::robotFileTargets(r.file.targets, targets, r.subject(), pythonSpelling(), setup.targets);
  }
  if (frame) {
    if (frame->size() != 6) {
      throw UsageError("frame", "expected 6 numbers rx, ry, rz, x, y, z (rotation vector in rad, translation), got " +
                                    std::to_string(frame->size()));
    }
    for (const double x : *frame) {
      if (!(std::abs(x) <= kMaxMagnitude)) throw UsageError("frame", "'" + io::shortest(x) + "' is not finite or above 1e100");
    }
    const auto& f = *frame;
    setup.T_frame_base = validation::measurementFrame(Vec3(f[0], f[1], f[2]), Vec3(f[3], f[4], f[5])).inverse();
  }
  setup.sd_position = noise_position;
  setup.sd_rotation = noise_rotation;
  const PoeModel& model = r.poe;
  const std::optional<MatX> Q = q_arg ? std::optional<MatX>(jointMatrix(*q_arg, r.dof(), r.subject())) : std::nullopt;
  const long long count = Q ? static_cast<long long>(Q->rows()) : *poses;
  if (count == 0) throw UsageError("q", "no joint values");
  const long long rows = validation::simulationRows(count, setup, Q ? "q" : "poses");
  std::optional<validation::Blunders> blunder_set;
  if (blunders) {
    blunder_set = validation::checkBlunders(std::get<0>(*blunders), std::get<1>(*blunders), pythonSpelling());
    validation::checkBlunderCount(*blunder_set, rows, pythonSpelling());
  }
  validation::SimulationPoses sampled;
  sampled.count = count;
  sampled.ranges = validation::samplingRanges(model);
  sampled.q_rows = Q ? &*Q : nullptr;
  sampled.given_row_beyond_reach = [](size_t k) {
    throw UsageError("q", "row " + std::to_string(k) + ": the tool at this row's q has a coordinate above 1e100 in "
                          "magnitude, which no reader takes");
  };
  {
    py::gil_scoped_release release;
    Data data(model);
    // the truth of a robot file, as `lowpair simulate` measures it: the library's POE forward kinematics
    const validation::TipPose tip_pose = [&](const VecX& q) {
      forwardKinematics(model, data, q);
      return data.T_base_tool;
    };
    validation::SimulatedMeasurements m = validation::simulateMeasurements(
        tip_pose, setup, static_cast<unsigned long long>(seed), sampled, blunder_set, frame.has_value(), r.subject(),
        pythonSpelling());
    s.measurements = std::move(m.measurements);
    s.blunders = std::move(m.blunders);
  }
  const std::string unit = r.file.length_unit.empty() ? "length" : r.file.length_unit;
  s.comments.push_back("made by lowpair.simulate (Python): " + std::to_string(s.measurements.size()) + " " + measure_text +
                       " measurements of " + r.subject() + " (the library's POE forward kinematics), seed " +
                       std::to_string(seed) + ", noise position " + io::shortest(noise_position) + " " + unit +
                       (measure == Measure::Pose ? ", rotation " + io::shortest(noise_rotation) + " rad" : std::string()) +
                       (frame ? ", in a measurement frame" : "") +
                       (blunders ? ", " + std::to_string(s.blunders.size()) + " blunders" : std::string()));
  if (io::isUnitLabel(r.file.length_unit)) s.comments.push_back("length_unit: " + r.file.length_unit);
  s.length_unit = r.file.length_unit;
  return s;
}

// ----- read_measurements (io/measurements.hpp; what `lowpair calibrate` reads, validation/calibration_inputs.hpp) --

Simulation readMeasurementFile(const std::string& path, const Robot* robot) {
  io::MeasurementFile file;
  validation::CalibrationMeasurements checked;
  std::vector<std::string> warnings;  // emitted with the GIL held, before an error the reading ended in
  std::exception_ptr failure;
  {
    py::gil_scoped_release release;
    try {
      if (robot) {
        checked = validation::readCalibrationMeasurements(path, robot->file, robot->subject(), robot->poe,
                                                          [&](const std::string& w) { warnings.push_back(w); });
        file = std::move(checked.file);
      } else {
        file = io::readMeasurements(path);
      }
    } catch (...) {
      failure = std::current_exception();
    }
  }
  for (const std::string& w : warnings) warnUser(w);
  if (failure) std::rethrow_exception(failure);
  Simulation s;
  s.measure = file.measure;
  s.measurements = std::move(file.measurements);
  s.target_names = std::move(file.target_names);
  s.length_unit = file.length_unit;
  s.lines = std::move(file.lines);
  s.notes = std::move(checked.notes);
  s.comments.push_back("read by lowpair.read_measurements (Python) from " + path +
                       (robot ? " for " + robot->subject() : std::string()));
  if (io::isUnitLabel(s.length_unit)) s.comments.push_back("length_unit: " + s.length_unit);
  return s;
}

// ----- save, export --------------------------------------------------------------------------------------

void exportTo(const Robot& r, const std::string& path, const std::string& format_text) {
  io::ExportFormat format;
  try {
    format = io::parseExportFormat(format_text);
  } catch (const std::invalid_argument&) {
    throw UsageError("format", "expected 'urdf', 'mjcf', 'poe' or 'dh', got '" + format_text + "'");
  }
  std::vector<std::string> comments = r.comments;
  comments.insert(comments.begin(), "Made by lowpair (Python) from " + r.subject() + ", format " + format_text +
                                        ", written to " + path + ".");
  const io::ExportedRobot exported = io::exportRobot(r.file, format, comments);
  if (!exported.joint_variables) {
    io::writeFileAtomically(path, exported.text);
    return;
  }
  io::StagedFiles files;
  files.stage(io::jointVariablesPath(path), *exported.joint_variables);
  files.stage(path, exported.text);
  files.commit();
}

py::array_t<double> rangesArray(const Robot& r) {
  py::array_t<double> out({static_cast<py::ssize_t>(r.dof()), py::ssize_t{2}});
  auto w = out.mutable_unchecked<2>();
  for (int i = 0; i < r.dof(); ++i) {
    const auto& range = r.poe.joint(i).range;
    w(i, 0) = range ? (*range)[0] : std::nan("");
    w(i, 1) = range ? (*range)[1] : std::nan("");
  }
  return out;
}

py::dict statisticsDict(const ResidualStatistics& s) {
  py::dict d;
  d["count"] = s.count;
  d["rms_position"] = s.rms_position;
  d["max_position"] = s.max_position;
  d["rms_rotation"] = s.rms_rotation;
  d["max_rotation"] = s.max_rotation;
  return d;
}

// ----- the benchmark's reference (python/bench_fk.py, docs/python.md "Speed") ----------------------------

const KinematicChain& fileChain(const Robot& r) { return r.ownDh() ? r.dhModel().chain() : r.poe.chain(); }

// `repeats` batched FK calls of Q (N, n) in C++, no Python in the loop, into one reused buffer: the seconds per
// pose of the fastest.
double timeBatchFk(const Robot& r, const InArray& q, int repeats) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject());
  MatX poses(Q.rows(), 12);
  py::gil_scoped_release release;
  double best = 1e300;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    const auto start = std::chrono::steady_clock::now();
    if (r.ownDh()) {
      forwardKinematicsBatch(r.dhModel(), Q, poses);
    } else {
      forwardKinematicsBatch(r.poe, Q, poses);
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best / static_cast<double>(std::max<Eigen::Index>(1, Q.rows()));
}

// The rows of Q (N, n) through forwardKinematics one at a time in C++ (the kinematics of one robot.fk(q) call),
// `repeats` times: the seconds per call of the fastest pass.
double timeSingleFk(const Robot& r, const InArray& q, int repeats) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject());
  const MatX Qt = Q.transpose();  // one configuration per column, contiguous
  py::gil_scoped_release release;
  Data data(fileChain(r));
  double best = 1e300, sink = 0.0;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    const auto start = std::chrono::steady_clock::now();
    for (Eigen::Index c = 0; c < Qt.cols(); ++c) {
      if (r.ownDh()) {
        forwardKinematics(r.dhModel(), data, Qt.col(c));
      } else {
        forwardKinematics(r.poe, data, Qt.col(c));
      }
      sink += data.T_base_tool.p(0);
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  volatile double keep = sink;  // the loop's results are used
  (void)keep;
  return best / static_cast<double>(std::max<Eigen::Index>(1, Q.rows()));
}

// One forwardKinematicsBatch call over all of Q (N, n): the (N, 12) poses (rotation row-major, then position), for
// the test that robot.fk(Q) repacks the library's numbers bit for bit.
py::array_t<double> batchFkReference(const Robot& r, const InArray& q, const std::optional<std::string>& model) {
  const std::string kind = kindOf(r, model);
  const MatX Q = jointMatrix(q, r.dof(), r.subject());
  MatX poses(Q.rows(), 12);
  if (kind == "poe") {
    forwardKinematicsBatch(r.poe, Q, poses);
  } else {
    forwardKinematicsBatch(r.dhModel(), Q, poses);
  }
  return matrixArray(poses);
}

}  // namespace

}  // namespace lowpair::python

using namespace lowpair;
using namespace lowpair::python;

PYBIND11_MODULE(_lowpair, m) {
  m.doc() = "lowpair: serial-robot POE/D-H kinematics, Jacobians, singularities, identifiability and calibration "
            "(docs/python.md). Lengths are in the robot file's length_unit, angles in rad.";

  static py::exception<std::runtime_error> error(m, "Error", PyExc_ValueError);
  error.doc() = "Bad input: a file, an argument or an array (a subclass of ValueError). The message is the one line "
                "the lowpair CLI prints after 'error: '.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::bad_alloc&) {
      throw;  // pybind11 maps it to MemoryError
    } catch (const py::error_already_set&) {
      throw;
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const UsageError& e) {  // "SUBJECT: message", as the CLI prints it
      PyErr_SetString(error.ptr(), io::oneLine(e.subject().empty() ? std::string(e.what()) : e.subject() + ": " + e.what()).c_str());
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(error.ptr(), io::oneLine(e.what()).c_str());
    } catch (const std::domain_error& e) {
      PyErr_SetString(error.ptr(), io::oneLine(e.what()).c_str());
    } catch (const std::out_of_range& e) {
      PyErr_SetString(error.ptr(), io::oneLine(e.what()).c_str());
    } catch (const std::length_error& e) {
      PyErr_SetString(error.ptr(), io::oneLine(e.what()).c_str());
    } catch (const std::runtime_error& e) {
      PyErr_SetString(error.ptr(), io::oneLine(e.what()).c_str());
    }
  });

  py::class_<Robot, RobotPtr>(m, "Robot",
                              "An immutable serial robot (POE model, and the D-H model of a D-H robot file). Made by "
                              "lowpair.load or lowpair.calibrate; safe to use from several threads at once.")
      .def_property_readonly("name", [](const Robot& r) { return r.file.name; }, "The robot's name (str).")
      .def_property_readonly("path", [](const Robot& r) { return r.file.path; }, "The file it was read from ('' if made).")
      .def_property_readonly("description", [](const Robot& r) { return r.file.description; }, "The file's description.")
      .def_property_readonly("dof", &Robot::dof, "Number of joints n (int).")
      .def_property_readonly("model", [](const Robot& r) { return r.ownDh() ? "dh" : "poe"; },
                             "'poe' or 'dh': the description the file holds (fk evaluates it by default).")
      .def_property_readonly("length_unit", [](const Robot& r) { return r.file.length_unit; },
                             "The length unit of every length in and out ('' when the file states none).")
      .def_property_readonly("angle_unit", [](const Robot& r) { return r.file.angle_unit; },
                             "The file's angle unit ('rad' or 'deg'); every angle in and out of the module is in rad.")
      .def_property_readonly("size", [](const Robot& r) { return r.poe.lengthScale(); },
                             "The robot size L (length_unit), docs/conventions.md.")
      .def_property_readonly(
          "joint_names",
          [](const Robot& r) {
            std::vector<std::string> names;
            for (const Joint& j : r.poe.joints()) names.push_back(j.name);
            return names;
          },
          "list[str], one per joint ('' where the file names none).")
      .def_property_readonly(
          "joint_types",
          [](const Robot& r) {
            std::vector<std::string> types;
            for (const Joint& j : r.poe.joints()) types.push_back(jointTypeName(j.type));
            return types;
          },
          "list[str]: 'revolute', 'prismatic' or 'helical' per joint.")
      .def_property_readonly("ranges", &rangesArray,
                             "(n, 2) float64 array [lo, hi] of each joint variable q (rad, or length_unit for "
                             "prismatic joints); NaN in both columns for a joint without a range.")
      .def_property_readonly(
          "targets",
          [](const Robot& r) {
            py::dict out;
            for (const Target& t : r.file.targets) {
              out[py::str(t.name)] = t.point_tool ? py::object(vectorArray(*t.point_tool)) : py::object(py::none());
            }
            return out;
          },
          "dict name -> (3,) point in the tool frame (length_unit): the file's `targets:` (laser-tracker SMRs).")
      .def("fk", &fk, py::arg("q"), py::arg("model") = py::none(), py::arg("out") = py::none(),
           "fk(q, model=None, out=None) -> numpy.ndarray\n\n"
           "Forward kinematics T_base_tool(q).\n\n"
           "q: (n,) joint values -> (4, 4) homogeneous transform; or (N, n), one configuration per row -> (N, 4, 4),\n"
           "evaluated by batched C++ calls (forwardKinematicsBatch, SIMD) with the GIL released.\n"
           "Units: q in rad (revolute, helical) or length_unit (prismatic), the robot file's joint variable;\n"
           "the translation column in length_unit. model: None (the file's own description, as `lowpair fk`),\n"
           "'poe' or 'dh'. A single q equals `lowpair fk --json` bit for bit; the batched form holds the numbers of\n"
           "forwardKinematicsBatch bit for bit, which agree with the single form to rounding (a few eps;\n"
           "docs/python.md). out: an optional preallocated C-contiguous float64 array of the result's shape,\n"
           "filled and returned. Cost: see docs/python.md, \"Speed\".\n"
           "Raises lowpair.Error for a wrong shape or a non-finite value.")
      .def("jacobian", &jacobian, py::arg("q"), py::arg("frame") = "spatial",
           "jacobian(q, frame='spatial') -> numpy.ndarray (6, n)\n\n"
           "The manipulator Jacobian at q (n,), as `lowpair jacobian --frame`:\n"
           "'spatial': rows [w; v], twist coordinates in the base frame; 'body': rows [w; v] in the tool frame;\n"
           "'geometric': rows [v; w], v the tool origin's velocity, base coordinates (Paden-Sastry eq. 3.13).\n"
           "Columns are d/dq_i (they carry the joint scale); w in rad per unit q, v in length_unit per unit q.")
      .def("dh", [](const Robot& r, double t, bool modified) { return dhTable(r, t, modified); },
           py::arg("parallel_threshold") = 0.0, py::arg("modified") = false,
           "dh(parallel_threshold=0.0, modified=False) -> DhTable\n\n"
           "The standard (or modified, Craig) D-H table of the robot with its conditioning report and FK check,\n"
           "as `lowpair poe2dh [--modified] --json` (DhTable.to_dict() is that JSON's content). Angles rad, lengths\n"
           "length_unit. parallel_threshold: sin(angle) below which axes count as parallel (0: rounding level).")
      .def("singular", &singular, py::arg("q"),
           "singular(q) -> Singularity\n\n"
           "Singularity analysis at q (n,), as `lowpair singular --json`: rank, sigma_min, manipulability, condition\n"
           "of the dimensionless geometric Jacobian, the classes C1..C7, the wrist/arm split, null vectors.")
      .def("save", [](const Robot& r, const std::string& path) { exportTo(r, path, r.ownDh() ? "dh" : "poe"); },
           py::arg("path"),
           "save(path) -> None\n\n"
           "Writes the robot as a robot file (.yaml): a POE file, or a D-H file when it was read from one (the\n"
           "table of poe2dh). Units as the robot's; a calibrated robot carries `calibrate --out`'s provenance.\n"
           "The file is replaced atomically (all or nothing).")
      .def("__repr__", [](const Robot& r) {
        return "<lowpair.Robot '" + r.file.name + "' (" + std::to_string(r.dof()) + " joints, " +
               (r.ownDh() ? "dh" : "poe") + (r.file.length_unit.empty() ? "" : ", " + r.file.length_unit) + ")>";
      });

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
      .def_property_readonly("size", [](const DhTable& t) { return t.conversion.size; },
                             "The robot size L (length_unit).")
      .def("__repr__", [](const DhTable& t) {
        return "<lowpair.DhTable " + t.j["convention"].get<std::string>() + ", " +
               std::to_string(t.conversion.model.dof()) + " rows>";
      });

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
      .def_property_readonly("size", [](const Singularity& s) { return s.report.size; }, "The robot size L.")
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

  py::class_<Calibration>(m, "Calibration", "lowpair.calibrate(...): the result of `lowpair calibrate`.")
      .def("to_dict", [](const Calibration& c) { return toPython(c.j); },
           "to_dict() -> dict: the content of `lowpair calibrate --json` (measurements.path '<arrays>', validation.path\n"
           "'<validation arrays>'; every `line` is the 0-based row of the arrays).")
      .def_property_readonly("robot", [](const Calibration& c) { return c.robot; },
                             "The calibrated Robot (in the measurement frame); save() writes what `calibrate --out` "
                             "writes. Present even when not accepted: check `accepted`.")
      .def_property_readonly("measure", [](const Calibration& c) { return measureName(c.report.result.measure); },
                             "'pose', 'position' or 'targets': what the arrays held.")
      .def_property_readonly("rank", [](const Calibration& c) { return c.report.result.rank.rank; },
                             "Rank of the weighted identification Jacobian at the nominal (int).")
      .def_property_readonly("expected", [](const Calibration& c) { return c.report.result.expected.total(); },
                             "The count 5h + 4r + 2t + n + 6 (+ 3 for positions, + 3k for k targets).")
      .def_property_readonly("iterations", [](const Calibration& c) { return c.report.result.iterations; },
                             "Levenberg-Marquardt iterations (int).")
      .def_property_readonly("converged", [](const Calibration& c) { return c.report.result.converged; },
                             "Whether the iteration converged (bool).")
      .def_property_readonly("accepted", [](const Calibration& c) { return c.report.result.accepted; },
                             "The verdict (docs/calibration.md): converged and the residuals consistent with the "
                             "stated noise (or below 1 % of L and 0.01 rad without it). `lowpair calibrate` exits 1 "
                             "and writes nothing when False.")
      .def_property_readonly("reason", [](const Calibration& c) { return c.report.result.reason; },
                             "Why not accepted ('' when accepted).")
      .def_property_readonly("variance_factor", [](const Calibration& c) { return c.report.result.variance_factor; },
                             "cost / (rows - rank): 1 expected when the stated noise is right (inf or NaN without "
                             "redundancy; to_dict() has null).")
      .def_property_readonly("before", [](const Calibration& c) { return statisticsDict(c.report.result.before); },
                             "dict count, rms_position, max_position (length_unit), rms_rotation, max_rotation (rad): "
                             "the nominal (registered) against the measurements.")
      .def_property_readonly("after", [](const Calibration& c) { return statisticsDict(c.report.result.after); },
                             "dict as `before`, for the calibrated model.")
      .def_property_readonly("validation",
                             [](const Calibration& c) -> py::object {
                               if (!c.report.validation_residuals) return py::none();
                               py::dict d;
                               d["before"] = statisticsDict(c.report.validation_residuals->before);
                               d["after"] = statisticsDict(c.report.validation_residuals->after);
                               return std::move(d);
                             },
                             "dict before/after on the validation arrays, or None.")
      .def_property_readonly(
          "residuals",
          [](const Calibration& c) {
            const auto& rows = c.report.result.residuals;
            const auto N = static_cast<py::ssize_t>(rows.size());
            py::array_t<double> position(N), rotation(N), normalized(N), weight(N);
            py::array_t<bool> outlier(N);
            for (py::ssize_t k = 0; k < N; ++k) {
              const MeasurementResidual& x = rows[static_cast<size_t>(k)];
              position.mutable_at(k) = x.position, rotation.mutable_at(k) = x.rotation;
              normalized.mutable_at(k) = x.normalized, weight.mutable_at(k) = x.weight, outlier.mutable_at(k) = x.outlier;
            }
            py::dict d;
            d["position"] = position, d["rotation"] = rotation, d["normalized"] = normalized, d["weight"] = weight;
            d["outlier"] = outlier;
            return d;
          },
          "dict of (N,) arrays, one entry per measurement row (after the fit): position (length_unit), rotation (rad; "
          "NaN for points), normalized (over the noise unit), weight (the robust loss' weight, 1 for squared), "
          "outlier (bool: normalized > outlier_threshold).")
      .def_property_readonly("outliers", [](const Calibration& c) { return c.report.result.outliers; },
                             "Measurements flagged as outliers (int).")
      .def_property_readonly("loss", [](const Calibration& c) { return toPython(c.j["loss"]); },
                             "'squared', 'huber' or 'cauchy'.")
      .def_property_readonly("targets",
                             [](const Calibration& c) {
                               py::dict out;
                               for (size_t t = 0; t < c.report.target_names.size(); ++t) {
                                 out[py::str(c.report.target_names[t])] = vectorArray(c.report.result.targets[t]);
                               }
                               return out;
                             },
                             "dict name -> (3,) calibrated point in the tool frame (length_unit), for target "
                             "measurements; empty otherwise.")
      .def_property_readonly("cross_validation",
                             [](const Calibration& c) -> py::object {
                               if (!c.j.contains("cross_validation")) return py::none();
                               return toPython(c.j["cross_validation"]);
                             },
                             "dict folds, repeats, candidates (parameters, count, rms_position, rms_rotation, score, failed), "
                             "chosen (select='cv'), or None.")
      .def_property_readonly("dh", [](const Calibration& c) { return toPython(c.j["dh"]); },
                             "dict: the calibrated D-H table with standard deviations (to_dict()['dh']).")
      .def_property_readonly(
          "parameter_names",
          [](const Calibration& c) {
            std::vector<std::string> names;
            for (const Parameter& p : c.report.result.error_model.parameters()) names.push_back(p.name);
            return names;
          },
          "list[str]: the identified parameters ('j2.tilt1', 'j3.scale', 'tool.z', 'smr_a.x', ...), the order of "
          "estimate, standard_deviation and covariance (docs/calibration.md lists their meaning and units).")
      .def_property_readonly("estimate", [](const Calibration& c) { return vectorArray(c.report.result.estimate); },
                             "(p,): every parameter's estimate from the registered nominal, in parameter_names "
                             "order and units (to_dict()['parameters'][k]['value']).")
      .def_property_readonly("standard_deviation",
                             [](const Calibration& c) { return vectorArray(c.report.result.standard_deviation); },
                             "(p,) per parameter, in its unit (inf when undetermined).")
      .def_property_readonly("covariance", [](const Calibration& c) { return matrixArray(c.report.result.covariance); },
                             "(p, p) covariance of the parameters (local coordinates at the calibrated model, "
                             "parameter_names order, their units squared); pseudo-inverse on the determined subspace.")
      .def_property_readonly("measurement_frame",
                             [](const Calibration& c) { return poseArray(c.report.result.registration.T_meas_base); },
                             "(4, 4): the nominal's base in the measurement frame (the registration).")
      .def_property_readonly("warnings", [](const Calibration& c) { return c.report.warnings; },
                             "list[str]: the report's warnings in sentences (rank below the count, no convergence, "
                             "residuals inconsistent with the noise, the D-H conversion's conditioning).")
      .def("__repr__", [](const Calibration& c) {
        return "<lowpair.Calibration rank " + std::to_string(c.report.result.rank.rank) + " of " +
               std::to_string(c.report.result.expected.total()) + ", " + (c.report.result.accepted ? "accepted" : "rejected") +
               ">";
      });

  py::class_<IkSolutions>(m, "IkSolutions",
                          "lowpair.ik(...) / lowpair.compensate(...): one solution per row, as `lowpair ik` / "
                          "`lowpair compensate` write them.")
      .def("to_dict", [](const IkSolutions& s) { return toPython(s.j); },
           "to_dict() -> dict: the content of `lowpair ik --json` (poses '<arrays>') or `lowpair compensate --json`\n"
           "(q_file '<arrays>'); every row's `line` is its 0-based row.")
      .def("__len__", [](const IkSolutions& s) { return s.rows.size(); })
      .def_property_readonly(
          "q",
          [](const IkSolutions& s) {
            const Eigen::Index n = s.rows.empty() ? 0 : s.rows.front().result.q.size();
            return vectorRows(s.rows, n, [](const validation::IkRow& row) -> const VecX& { return row.result.q; });
          },
          "(N, n): the solutions (or each row's last iterate when not ok), rad / length_unit.")
      .def_property_readonly(
          "status",
          [](const IkSolutions& s) {
            std::vector<std::string> out;
            for (const validation::IkRow& row : s.rows) out.push_back(ikStatusName(row.result.status));
            return out;
          },
          "list[str]: 'ok', 'out_of_range', 'singular', 'unreachable' or 'not_converged' per row (docs/ik.md).")
      .def_property_readonly(
          "ok",
          [](const IkSolutions& s) {
            return perRow<bool>(s.rows, [](const validation::IkRow& row) { return row.result.status == IkStatus::Ok; });
          },
          "(N,) bool: status == 'ok' (within 1e-10 L and 1e-10 rad, at a regular configuration).")
      .def_property_readonly(
          "iterations",
          [](const IkSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const validation::IkRow& row) { return row.result.iterations; });
          },
          "(N,) int: iterations of the kept attempt.")
      .def_property_readonly(
          "position_error",
          [](const IkSolutions& s) {
            return perRow<double>(s.rows, [](const validation::IkRow& row) { return row.result.position_error; });
          },
          "(N,): |p_target - p| at q (length_unit).")
      .def_property_readonly(
          "rotation_error",
          [](const IkSolutions& s) {
            return perRow<double>(s.rows, [](const validation::IkRow& row) { return row.result.rotation_error; });
          },
          "(N,): the angle of R^T R_target at q (rad; 0 for positions).")
      .def_property_readonly(
          "rank",
          [](const IkSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const validation::IkRow& row) { return row.result.rank; });
          },
          "(N,) int: rank of the dimensionless task Jacobian at a converged q (-1 when not converged).")
      .def_property_readonly(
          "sigma_min",
          [](const IkSolutions& s) {
            return perRow<double>(s.rows, [](const validation::IkRow& row) { return row.result.sigma_min; });
          },
          "(N,): its smallest singular value (NaN when not converged).")
      .def_property_readonly(
          "seed",
          [](const IkSolutions& s) {
            return perRow<std::int64_t>(s.rows, [](const validation::IkRow& row) { return row.seed; });
          },
          "(N,) int: the random seed s (0..seeds-1) the kept attempt started from; -1 for q0 (ik) and compensate.")
      .def_property_readonly(
          "reason",
          [](const IkSolutions& s) {
            std::vector<std::string> out;
            for (const validation::IkRow& row : s.rows) out.push_back(row.result.reason);
            return out;
          },
          "list[str]: why a row is not ok, one sentence with the numbers ('' for ok rows).")
      .def_property_readonly("counts", [](const IkSolutions& s) { return toPython(s.j["counts"]); },
                             "dict status -> rows.")
      .def("__repr__", [](const IkSolutions& s) {
        long long ok = 0;
        for (const validation::IkRow& row : s.rows) ok += row.result.status == IkStatus::Ok;
        return "<lowpair.IkSolutions " + std::to_string(s.rows.size()) + " rows, " + std::to_string(ok) + " ok>";
      });

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
      .def_property_readonly("undetermined", [](const PlanOutcome& p) { return toPython(p.j["undetermined"]); },
                             "list of directions the plan does not determine, each a list of {parameter, "
                             "coefficient}.")
      .def("__repr__", [](const PlanOutcome& p) {
        return "<lowpair.Plan " + std::to_string(p.report.plan.indices.size()) + " poses, rank " +
               std::to_string(p.report.plan.rank.rank) + " of " + std::to_string(p.report.plan.expected.total()) + ", log det " +
               io::shortest(p.report.plan.value.log_det) + ">";
      });

  py::class_<Simulation>(m, "Measurements",
                         "lowpair.simulate(...): simulated measurements, the columns of the measurement CSV as arrays "
                         "(pass them to lowpair.calibrate).")
      .def("__len__", [](const Simulation& s) { return s.measurements.size(); })
      .def_property_readonly("measure", [](const Simulation& s) { return measureName(s.measure); },
                             "'pose', 'position' or 'targets'.")
      .def_property_readonly(
          "q",
          [](const Simulation& s) {
            return vectorRows(s.measurements, s.measurements.front().q.size(),
                              [](const Measurement& row) -> const VecX& { return row.q; });
          },
          "(M, n): the joint values of each row (targets: a pose's q repeated on each of its targets' rows).")
      .def_property_readonly(
          "positions",
          [](const Simulation& s) {
            MatX out(static_cast<Eigen::Index>(s.measurements.size()), 3);
            for (size_t k = 0; k < s.measurements.size(); ++k) {
              out.row(static_cast<Eigen::Index>(k)) = s.measurements[k].T_base_tool.p.transpose();
            }
            return matrixArray(out);
          },
          "(M, 3): the measured tool position (targets: the target's point) in the measurement frame (length_unit).")
      .def_property_readonly(
          "rotations",
          [](const Simulation& s) -> py::object {
            if (s.measure != Measure::Pose) return py::none();
            MatX out(static_cast<Eigen::Index>(s.measurements.size()), 4);
            for (size_t k = 0; k < s.measurements.size(); ++k) {
              out.row(static_cast<Eigen::Index>(k)) = io::csvQuaternion(s.measurements[k].T_base_tool.R).transpose();
            }
            return matrixArray(out);
          },
          "(M, 4) unit quaternions qw, qx, qy, qz (qw >= 0, as the CSV writes them) for pose measurements, else None.")
      .def_property_readonly(
          "targets",
          [](const Simulation& s) -> py::object {
            if (s.measure != Measure::Targets) return py::none();
            std::vector<std::string> out;
            for (const Measurement& x : s.measurements) out.push_back(s.target_names[static_cast<size_t>(x.target)]);
            return py::cast(out);
          },
          "list[str]: the target measured in each row (the CSV's target column) for target measurements, else None.")
      .def_property_readonly("blunders", [](const Simulation& s) { return s.blunders; },
                             "list[int]: the rows moved by a blunder (0-based, increasing); [] for a file read.")
      .def_property_readonly(
          "length_unit",
          [](const Simulation& s) -> py::object { return s.length_unit.empty() ? py::none() : py::cast(s.length_unit); },
          "str: the unit of positions: simulate's robot's; read_measurements: the file's `# length_unit`, the "
          "robot's after a conversion, None when the file states none (calibrate then takes the robot's).")
      .def_property_readonly(
          "lines", [](const Simulation& s) -> py::object { return s.lines.empty() ? py::none() : py::cast(s.lines); },
          "list[int]: the 1-based file line of each row (read_measurements), else None.")
      .def_property_readonly("notes", [](const Simulation& s) { return s.notes; },
                             "list[str]: what reading did to the numbers (a unit conversion), as calibrate's notes.")
      .def(
          "save",
          [](const Simulation& s, const std::string& path) {
            io::writeFileAtomically(path, io::formatMeasurements(s.measure, s.measurements, s.comments, s.target_names));
          },
          py::arg("path"),
          "save(path) -> None\n\n"
          "Writes the measurement CSV (the format `lowpair simulate --out` writes and `lowpair calibrate` reads:\n"
          "17 significant digits, a `# length_unit` comment when the robot states one), all or nothing.")
      .def("__repr__", [](const Simulation& s) {
        return "<lowpair.Measurements " + std::to_string(s.measurements.size()) + " " + measureName(s.measure) + ">";
      });

  m.def(
      "load",
      [](const std::string& path, std::optional<std::string> tip, std::optional<std::string> base) {
        io::RobotFile file;
        {
          py::gil_scoped_release release;
          file = loadFile(path, tip, base);
        }
        return std::make_shared<Robot>(std::move(file));
      },
      py::arg("path"), py::arg("tip") = py::none(), py::arg("base") = py::none(),
      "load(path, tip=None, base=None) -> Robot\n\n"
      "A robot file (.yaml, POE or D-H), or the chain of an MJCF (.xml, through MuJoCo) or URDF (.urdf, urdfdom)\n"
      "model from `base` (default the world / root link) to `tip` (a site or body / a link; required). As the\n"
      "CLI's ROBOT [--tip --base]. Raises lowpair.Error with the CLI's message for a bad file.");
  m.def("identifiability", &identifiability, py::arg("robot"), py::arg("measure") = "pose", py::arg("poses") = 50,
        py::arg("seed") = 1, py::arg("free_pitch") = false,
        "identifiability(robot, measure='pose', poses=50, seed=1, free_pitch=False) -> Identifiability\n\n"
        "`lowpair identifiability`: the rank of the identification Jacobian at `poses` random joint vectors (the\n"
        "CLI's seeded stream: equal numbers for equal seeds) against the count 5h + 4r + 2t + n + 6.\n"
        "measure: 'pose', 'position' or 'targets' (the robot file's targets).");
  m.def("calibrate", &calibrateFromArrays, py::arg("robot"), py::arg("q"), py::arg("positions"),
        py::arg("rotations") = py::none(), py::arg("noise_position") = py::none(),
        py::arg("noise_rotation") = py::none(), py::arg("free_pitch") = false, py::arg("loss") = "squared",
        py::arg("outlier_threshold") = 5.0, py::arg("parameters") = py::none(), py::arg("validation_q") = py::none(),
        py::arg("validation_positions") = py::none(), py::arg("validation_rotations") = py::none(),
        py::arg("targets") = py::none(), py::arg("validation_targets") = py::none(), py::arg("select") = py::none(),
        py::arg("folds") = 5, py::arg("repeats") = kCrossValidationRepeats,
        "calibrate(robot, q, positions, rotations=None, noise_position=None, noise_rotation=None, free_pitch=False,\n"
        "          loss='squared', outlier_threshold=5.0, parameters=None, validation_q=None,\n"
        "          validation_positions=None, validation_rotations=None, targets=None, validation_targets=None,\n"
        "          select=None, folds=5, repeats=10) -> Calibration\n\n"
        "`lowpair calibrate` from arrays (the measurement CSV's columns): q (N, n) joint values (rad / length_unit);\n"
        "positions (N, 3) measured tool positions (length_unit, the robot's; any measurement frame: it is\n"
        "registered); rotations (N, 4) unit quaternions qw, qx, qy, qz (scalar first; norm within 1e-6 of 1) for\n"
        "pose measurements; or targets, N names (the CSV's target column) for laser-tracker target (SMR)\n"
        "measurements, positions then being the targets' points (a point the robot file's `targets:` gives is the\n"
        "start, the others are estimated); neither: position measurements of the tool origin.\n"
        "noise_position (length_unit) and noise_rotation (rad): the measurement noise, standard deviation per\n"
        "coordinate. loss: 'squared', 'huber' or 'cauchy' (robust: blunders weighed down); outlier_threshold:\n"
        "the normalized residual above which a row is flagged. parameters: None (all), 'full', 'lines',\n"
        "'offsets' or names 'j2.offset,base.rz'; select='cv' chooses among full/lines/offsets by `folds`-fold\n"
        "cross-validation over `repeats` partitions of the poses (the first in order, the others shuffled).\n"
        "validation_*: held-out measurements of the same kind (residuals before and after).\n"
        "The GIL is released during the fit. A rejected fit is data (accepted, reason), not an exception.");
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
        py::arg("measure") = "pose",
        "compensate(calibrated, nominal, q, measure='pose') -> IkSolutions\n\n"
        "`lowpair compensate`: for each row of q (N, n) (or one (n,)), nominal joint values, the joint values of\n"
        "the calibrated robot that put its tool frame (measure='pose') or tool origin ('position') where the\n"
        "nominal puts it at q, solved by inverse kinematics seeded at q. Both robots must have the same joint\n"
        "count and length unit. The GIL is released while solving.");
  m.def("plan", &plan, py::arg("robot"), py::arg("poses"), py::arg("candidates") = 5000, py::arg("measure") = "pose",
        py::arg("criterion") = "D", py::arg("seed") = 1, py::arg("noise_position") = py::none(),
        py::arg("noise_rotation") = py::none(), py::arg("free_pitch") = false,
        "plan(robot, poses, candidates=5000, measure='pose', criterion='D', seed=1, noise_position=None,\n"
        "     noise_rotation=None, free_pitch=False) -> Plan\n\n"
        "`lowpair plan`: choose `poses` (N <= 1000) calibration poses of `candidates` (M <= 100000) random joint\n"
        "vectors (samples 0..M-1 of the stream `seed`) maximizing log det of the identification information\n"
        "(greedy, then exchanges; criterion 'D' or 'O1' only changes the number reported), compare with 100\n"
        "random sets of N, and predict every parameter's and D-H number's standard deviation after calibrating\n"
        "on the plan with the given noise (length_unit, rad; default 1e-5 L and 1e-5 rad). measure: 'pose',\n"
        "'position' or 'targets' (the robot file's targets). The GIL is released while planning.");
  m.def("read_measurements", &readMeasurementFile, py::arg("path"), py::arg("robot") = py::none(),
        "read_measurements(path, robot=None) -> Measurements\n\n"
        "A measurement CSV (docs/calibration.md \"Measurement files\"), as `lowpair calibrate` reads one: its\n"
        "columns as arrays for lowpair.calibrate. With `robot`, it is read for that robot: the joint count and\n"
        "the length unit are checked at the header line, lengths in another unit lowpair knows are converted\n"
        "to the robot's (`notes` says so), a joint value more than 10 range widths outside the robot's range\n"
        "raises, nearer ones are UserWarnings (under -W error the first raises as a UserWarning). A robot\n"
        "without a length unit (an MJCF) converts nothing. Without `robot`, the numbers are as written\n"
        "(`length_unit` says in what, if the file does). Bad files raise lowpair.Error `FILE:LINE: what`.\n"
        "The GIL is released while reading.");
  m.def("simulate", &simulate, py::arg("robot"), py::arg("poses") = py::none(), py::arg("q") = py::none(),
        py::arg("seed") = 1, py::arg("measure") = "pose", py::arg("targets") = py::none(), py::arg("frame") = py::none(),
        py::arg("noise_position") = 0.0, py::arg("noise_rotation") = 0.0, py::arg("blunders") = py::none(),
        "simulate(robot, poses=None, q=None, seed=1, measure='pose', targets=None, frame=None, noise_position=0.0,\n"
        "         noise_rotation=0.0, blunders=None) -> Measurements\n\n"
        "`lowpair simulate` of a robot file: measurements of the robot's tool by the library's POE forward\n"
        "kinematics at `poses` random joint vectors (sample k of the stream `seed`, uniform in the joint ranges)\n"
        "or at the rows of q (N, n); measure 'pose', 'position' or 'targets' (the robot file's targets, all or\n"
        "the names in `targets`, one row per target per pose); frame: (rx, ry, rz, x, y, z), the measurement\n"
        "frame's pose in the base (rotation vector rad, translation length_unit); noise_position (length_unit)\n"
        "and noise_rotation (rad): Gaussian noise per coordinate / axis; blunders: (count, size), rows moved by\n"
        "`size` in random directions. Same arguments, same numbers as the CLI on the robot file. (A model file's\n"
        "MuJoCo ground truth with --joint-variables is the CLI's only.)");
  m.def("export", &exportTo, py::arg("robot"), py::arg("path"), py::arg("format"),
        "export(robot, path, format) -> None\n\n"
        "`lowpair export --out path`: the robot as 'urdf', 'mjcf', 'poe' or 'dh' (robot file). A URDF/MJCF of a\n"
        "robot whose joint scale is not 1 or offset not 0 also writes <stem>.joint_variables.yaml beside it.");
  m.def("_time_batch_fk", &timeBatchFk, py::arg("robot"), py::arg("q"), py::arg("repeats") = 5,
        "_time_batch_fk(robot, q, repeats=5) -> float: seconds per pose of the fastest of `repeats` batched FK calls\n"
        "in C++ (one forwardKinematicsBatch of all of q into a reused buffer, no Python in the loop): the\n"
        "benchmark's reference.");
  m.def("_time_single_fk", &timeSingleFk, py::arg("robot"), py::arg("q"), py::arg("repeats") = 5,
        "_time_single_fk(robot, q, repeats=5) -> float: seconds per call of forwardKinematics over the rows of q in\n"
        "C++ (the kinematics inside one robot.fk(q)), the fastest of `repeats` passes.");
  m.def("_batch_fk_reference", &batchFkReference, py::arg("robot"), py::arg("q"), py::arg("model") = py::none(),
        "_batch_fk_reference(robot, q, model=None) -> (N, 12): one forwardKinematicsBatch call over all of q (rotation\n"
        "row-major, then position): what robot.fk(q) must repack bit for bit.");
  m.attr("__version__") = "0.2.0";
}
