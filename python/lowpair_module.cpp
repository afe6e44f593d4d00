// The Python module lowpair._lowpair (docs/python.md): robots from robot files and MJCF/URDF models, forward
// kinematics (single and batched), Jacobians, the D-H table, singularities, identifiability, calibration from
// arrays, save and export. Every call computes what the CLI computes, with the same functions, so the numbers
// are the CLI's bit for bit (python/tests/ checks it); errors are lowpair.Error with the CLI's one-line message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/export.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "io/robot_file.hpp"
#include "io/singularity_output.hpp"
#include "io/urdf_reader.hpp"
#include "lowpair/calibration.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "lowpair/tolerances.hpp"
#include "mujoco/mujoco_robot.hpp"
#include "validation/calibration_output.hpp"
#include "validation/sampling.hpp"

namespace py = pybind11;
using nlohmann::json;

namespace lowpair::python {

namespace {

// A bad argument (not a file): "SUBJECT: message", as the CLI's UsageError prints it.
struct UsageError : std::invalid_argument {
  UsageError(const std::string& subject, const std::string& message)
      : std::invalid_argument(subject.empty() ? message : subject + ": " + message) {}
};

// The CLI's one error line: every control character folded into one space (cli/main.cpp reportError).
std::string oneLine(const std::string& message) {
  std::string line;
  for (const char ch : message) {
    const bool control = static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f;
    if (!control) {
      line += ch;
    } else if (line.empty() || line.back() != ' ') {
      line += ' ';
    }
  }
  return line;
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

// Batched FK of the (N, n) array `q` into (N, 4, 4), in chunks of 1024 configurations: each chunk is copied
// (and checked finite) into a column-major buffer that stays in cache, evaluated by forwardKinematicsBatch and
// scattered. 1024 is a multiple of every SIMD block (4 or 8), so the blocks are those of one whole call.
// Called without the GIL: `q` is kept alive by the caller and only read.
void fkBatchInto(const Robot& r, const std::string& kind, const py::detail::unchecked_reference<double, 2>& q,
                 double* out) {
  constexpr Eigen::Index kChunk = 1024;
  const Eigen::Index count = q.shape(0), dof = r.dof();
  MatX Q(std::min(count, kChunk), dof), poses(std::min(count, kChunk), 12);
  for (Eigen::Index start = 0; start < count; start += kChunk) {
    const Eigen::Index len = std::min(kChunk, count - start);
    for (Eigen::Index i = 0; i < dof; ++i) {
      for (Eigen::Index k = 0; k < len; ++k) Q(k, i) = q(start + k, i);
    }
    if (!Q.topRows(len).allFinite()) {
      for (Eigen::Index k = 0; k < len; ++k) {
        for (Eigen::Index i = 0; i < dof; ++i) {
          if (!std::isfinite(Q(k, i))) {
            throw UsageError(r.subject(), "q[" + std::to_string(start + k) + ", " + std::to_string(i) + "]: '" +
                                              io::shortest(Q(k, i)) + "' is not finite");
          }
        }
      }
    }
    Eigen::Ref<MatX> chunk = poses.topRows(len);
    if (kind == "poe") {
      forwardKinematicsBatch(r.poe, Q.topRows(len), chunk);
    } else {
      forwardKinematicsBatch(r.dhModel(), Q.topRows(len), chunk);
    }
    for (Eigen::Index k = 0; k < len; ++k) {
      double* T = out + 16 * (start + k);
      for (int a = 0; a < 3; ++a) {
        T[4 * a + 0] = chunk(k, 3 * a + 0);
        T[4 * a + 1] = chunk(k, 3 * a + 1);
        T[4 * a + 2] = chunk(k, 3 * a + 2);
        T[4 * a + 3] = chunk(k, 9 + a);
      }
      T[12] = 0.0, T[13] = 0.0, T[14] = 0.0, T[15] = 1.0;
    }
  }
}

// `out`: a preallocated float64 C-contiguous writeable array of the result's shape (no fresh pages per call).
double* outBuffer(const std::optional<py::array>& out, const std::vector<py::ssize_t>& shape) {
  if (!out) return nullptr;
  const py::array& a = *out;
  bool ok = py::isinstance<py::array_t<double>>(a) && a.writeable() &&
            (a.flags() & py::array::c_style) && a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (size_t k = 0; ok && k < shape.size(); ++k) ok = a.shape(static_cast<py::ssize_t>(k)) == shape[k];
  if (!ok) {
    std::string want = "(";
    for (size_t k = 0; k < shape.size(); ++k) want += (k ? ", " : "") + std::to_string(shape[k]);
    throw UsageError("out", "expected a writeable C-contiguous float64 array of shape " + want + "), got shape " +
                                shapeText(a));
  }
  return static_cast<double*>(const_cast<void*>(a.data()));
}

py::object fk(const Robot& r, const InArray& q, const std::optional<std::string>& model,
              const std::optional<py::array>& out_arg) {
  const std::string kind = kindOf(r, model);
  if (q.ndim() == 1) {
    const VecX x = jointVector(q, r.dof(), r.subject());
    Pose T;
    {
      // no GIL release: one FK (~70 ns) costs less than releasing and taking it again
      if (kind == "poe") {
        Data& data = threadData(r.poe.chain(), r.dof());
        forwardKinematics(r.poe, data, x);
        T = data.T_base_tool;
      } else {
        const DhModel& dh = r.dhModel();
        Data& data = threadData(dh.chain(), dh.dof());
        forwardKinematics(dh, data, x);
        T = data.T_base_tool;
      }
    }
    if (double* dst = outBuffer(out_arg, {4, 4})) {
      Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> view(dst);
      view = T.matrix();
      return *out_arg;
    }
    return poseArray(T);
  }
  if (q.ndim() != 2) {
    throw UsageError(r.subject(), "q: expected shape (" + std::to_string(r.dof()) + ",) or (N, " +
                                      std::to_string(r.dof()) + "), got shape " + shapeText(q));
  }
  if (q.shape(1) != r.dof()) {
    throw UsageError(r.subject(), "q: expected shape (N, " + std::to_string(r.dof()) + "), got shape " + shapeText(q));
  }
  if (kind == "dh") r.dhModel();  // convert (or throw) with the GIL held
  double* dst = outBuffer(out_arg, {q.shape(0), 4, 4});
  py::array_t<double> out;
  if (!dst) {
    out = py::array_t<double>({static_cast<py::ssize_t>(q.shape(0)), py::ssize_t{4}, py::ssize_t{4}});
    dst = out.mutable_data();
  }
  const auto view = q.unchecked<2>();
  {
    py::gil_scoped_release release;
    fkBatchInto(r, kind, view, dst);
  }
  if (out_arg) return *out_arg;
  return std::move(out);
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

Measure parseMeasure(const std::string& text) {
  if (text == "pose") return Measure::Pose;
  if (text == "position") return Measure::Position;
  if (text == "targets") return Measure::Targets;
  throw UsageError("measure", "expected 'pose', 'position' or 'targets', got '" + text + "'");
}

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
  const Measure measure = parseMeasure(measure_text);
  if (poses < 1 || poses > validation::kMaxIdentifiabilityPoses) {
    throw UsageError("poses", "must be in [1, " + std::to_string(validation::kMaxIdentifiabilityPoses) + "], got " +
                                  std::to_string(poses));
  }
  if (seed < 0 || seed > validation::kMaxSeed) {
    throw UsageError("seed", "must be in [0, 2^53], got " + std::to_string(seed));
  }
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

constexpr double kUnitQuaternionTolerance = 1e-6;  // the measurement CSV reader's (io/measurements.cpp)

struct Calibration {
  validation::CalibrationReport report;
  RobotPtr robot;
  json j;
};

std::vector<Measurement> measurementsFromArrays(const Robot& r, const InArray& q, const InArray& positions,
                                                const std::optional<InArray>& rotations, const std::string& prefix) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject(), prefix + "q");
  const auto N = Q.rows();
  if (N == 0) throw UsageError(prefix + "q", "no measurements");
  if (positions.ndim() != 2 || positions.shape(0) != N || positions.shape(1) != 3) {
    throw UsageError(prefix + "positions", "expected shape (" + std::to_string(N) + ", 3), got shape " +
                                               shapeText(positions));
  }
  if (rotations && (rotations->ndim() != 2 || rotations->shape(0) != N || rotations->shape(1) != 4)) {
    throw UsageError(prefix + "rotations", "expected shape (" + std::to_string(N) +
                                               ", 4) (unit quaternions qw, qx, qy, qz), got shape " +
                                               shapeText(*rotations));
  }
  std::vector<Measurement> out(static_cast<size_t>(N));
  auto p = positions.unchecked<2>();
  for (Eigen::Index k = 0; k < N; ++k) {
    Measurement& m = out[static_cast<size_t>(k)];
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
      Eigen::Quaterniond quaternion(w(k, 0), w(k, 1), w(k, 2), w(k, 3));
      const double norm = quaternion.norm();
      if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
        throw UsageError(prefix + "rotations", "row " + std::to_string(k) + ": qw..qz is not a unit quaternion (norm " +
                                                   io::shortest(norm) + ")");
      }
      m.T_base_tool.R = quaternion.normalized().toRotationMatrix();
    }
  }
  return out;
}

Calibration calibrateArrays(const Robot& r, const InArray& q, const InArray& positions,
                            const std::optional<InArray>& rotations, std::optional<double> noise_position,
                            std::optional<double> noise_rotation, bool free_pitch, const std::string& loss,
                            double outlier_threshold, const std::string& parameters,
                            const std::optional<InArray>& validation_q, const std::optional<InArray>& validation_positions,
                            const std::optional<InArray>& validation_rotations) {
  const PoeModel& nominal = r.poe;
  io::MeasurementFile fit;
  fit.path = "<arrays>";
  fit.dof = nominal.dof();
  fit.measure = rotations ? Measure::Pose : Measure::Position;
  fit.measurements = measurementsFromArrays(r, q, positions, rotations, "");
  for (size_t k = 0; k < fit.measurements.size(); ++k) fit.lines.push_back(static_cast<long long>(k));
  fit.length_unit = r.file.length_unit;
  if (fit.measurements.size() > static_cast<size_t>(validation::kMaxCalibrationMeasurements) ||
      validation::identificationEntries(static_cast<double>(fit.measurements.size()), nominal.dof(), 7.0) >
          validation::kMaxJacobianEntries) {
    throw UsageError("q", std::to_string(fit.measurements.size()) + " measurements of " + std::to_string(nominal.dof()) +
                              " joints; calibrate fits at most " +
                              std::to_string(validation::kMaxCalibrationMeasurements) + " measurements and at most " +
                              io::shortest(validation::kMaxJacobianEntries) + " numbers at once");
  }
  std::optional<io::MeasurementFile> held_out;
  if (validation_q || validation_positions || validation_rotations) {
    if (!validation_q || !validation_positions) {
      throw UsageError("validation_q", "give validation_q and validation_positions (and validation_rotations for poses)");
    }
    if (validation_rotations.has_value() != rotations.has_value()) {
      throw UsageError("validation_rotations", rotations ? "the fit has pose measurements: give validation_rotations too"
                                                         : "the fit has position measurements: no validation_rotations");
    }
    held_out.emplace();
    held_out->path = "<validation arrays>";
    held_out->dof = nominal.dof();
    held_out->measure = fit.measure;
    held_out->measurements = measurementsFromArrays(r, *validation_q, *validation_positions, validation_rotations,
                                                    "validation_");
    for (size_t k = 0; k < held_out->measurements.size(); ++k) held_out->lines.push_back(static_cast<long long>(k));
    held_out->length_unit = r.file.length_unit;
  }
  for (const auto& [value, flag, limit] : {std::tuple{noise_position, "noise_position", kMaxMagnitude},
                                           std::tuple{noise_rotation, "noise_rotation", M_PI}}) {
    if (value && !(*value > 0.0 && *value <= limit)) {
      throw UsageError(flag, "must be a positive number up to " + io::shortest(limit) + ", got " + io::shortest(*value));
    }
  }
  if (noise_rotation && fit.measure != Measure::Pose) {
    throw UsageError("noise_rotation", "position measurements (rotations=None): there is no rotation to weigh");
  }
  if (!(outlier_threshold >= 1e-3 && outlier_threshold <= 1e6)) {
    throw UsageError("outlier_threshold", "must be in [0.001, 1e6], got " + io::shortest(outlier_threshold));
  }
  CalibrationOptions options;
  options.measure = fit.measure;
  options.free_pitch = free_pitch;
  options.sigma_position = noise_position;
  options.sigma_rotation = noise_rotation;
  if (loss != "squared" && loss != "huber" && loss != "cauchy") {
    throw UsageError("loss", "expected 'squared', 'huber' or 'cauchy', got '" + loss + "'");
  }
  options.loss = loss == "huber" ? Loss::Huber : loss == "cauchy" ? Loss::Cauchy : Loss::Squared;
  options.outlier_threshold = outlier_threshold;
  if (parameters == "full" || parameters == "lines" || parameters == "offsets") {
    options.parameters = parameters == "full" ? ParameterSet::Full
                         : parameters == "lines" ? ParameterSet::Lines
                                                 : ParameterSet::Offsets;
  } else {
    options.parameters = ParameterSet::Named;
    std::stringstream in(parameters);
    for (std::string name; std::getline(in, name, ',');) {
      const auto b = name.find_first_not_of(" \t"), e = name.find_last_not_of(" \t");
      if (b == std::string::npos) throw UsageError("parameters", "an empty name in '" + parameters + "'");
      options.parameter_names.push_back(name.substr(b, e - b + 1));
    }
    if (options.parameter_names.empty()) throw UsageError("parameters", "expected full, lines, offsets or names");
  }
  std::optional<CalibrationResult> result;
  std::optional<DhUncertainty> dh;
  double seconds = 0.0;
  {
    py::gil_scoped_release release;
    const auto start = std::chrono::steady_clock::now();
    result.emplace(calibrate(nominal, fit.measurements, options));
    dh.emplace(dhUncertainty(*result));
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  validation::CalibrationReport report = validation::makeCalibrationReport(r.file, std::move(fit), std::move(held_out),
                                                                           *result, *dh, seconds);
  // the calibrated robot, as `calibrate --out` writes it
  io::RobotFile calibrated;
  calibrated.name = (r.file.name.empty() ? std::filesystem::path(r.file.path).stem().string() : r.file.name) +
                    "-calibrated";
  calibrated.length_unit = r.file.length_unit;
  calibrated.angle_unit = r.file.angle_unit;
  calibrated.description = "calibrated by lowpair.calibrate (Python) from arrays";
  calibrated.poe = result->model;
  calibrated.targets = validation::calibratedTargets(report);
  auto robot = std::make_shared<Robot>(std::move(calibrated), validation::calibrationProvenance(report));
  json j = validation::calibrationJson(report);
  return Calibration{std::move(report), std::move(robot), std::move(j)};
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

// A timing helper for python/bench_fk.py: `repeats` batched FK calls of Q (N, n) in C++, no Python in the loop,
// into one reused buffer; returns the seconds per pose of the fastest repeat.
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
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(error.ptr(), oneLine(e.what()).c_str());
    } catch (const std::domain_error& e) {
      PyErr_SetString(error.ptr(), oneLine(e.what()).c_str());
    } catch (const std::out_of_range& e) {
      PyErr_SetString(error.ptr(), oneLine(e.what()).c_str());
    } catch (const std::length_error& e) {
      PyErr_SetString(error.ptr(), oneLine(e.what()).c_str());
    } catch (const std::runtime_error& e) {
      PyErr_SetString(error.ptr(), oneLine(e.what()).c_str());
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
                             "(n, 2) float64 array [lo, hi] of each joint variable q (rad, or length for prismatic "
                             "joints); NaN in both columns for a joint without a range.")
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
           "evaluated by one batched C++ call (forwardKinematicsBatch, SIMD) with the GIL released.\n"
           "Units: q in rad (revolute, helical) or length_unit (prismatic), the robot file's joint variable;\n"
           "the translation column in length_unit. model: None (the file's own description, as `lowpair fk`),\n"
           "'poe' or 'dh'. A single q equals `lowpair fk --json` bit for bit; the batched form agrees with it to\n"
           "rounding (a few eps; docs/api.md). out: an optional preallocated C-contiguous float64 array of the result's\n"
           "shape, filled and returned (saves the fresh pages of a new result in loops over large batches).\n"
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
      .def_property_readonly("size", [](const DhTable& t) { return t.conversion.size; }, "The robot size L.")
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
      .def_property_readonly("manipulability", [](const Singularity& s) { return s.report.manipulability; }, "")
      .def_property_readonly("condition", [](const Singularity& s) { return s.report.condition; },
                             "sigma_max / sigma_min (inf when singular to zero).")
      .def_property_readonly("tolerance", [](const Singularity& s) { return s.report.tolerance; }, "The rank threshold.")
      .def_property_readonly("size", [](const Singularity& s) { return s.report.size; }, "The robot size L.")
      .def_property_readonly("rank_linear", [](const Singularity& s) { return s.report.rank_linear; }, "")
      .def_property_readonly("rank_angular", [](const Singularity& s) { return s.report.rank_angular; }, "")
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
      .def_property_readonly("columns", [](const IdentifiabilityResult& i) { return i.id.poe.columns; }, "")
      .def_property_readonly("condition", [](const IdentifiabilityResult& i) { return i.id.poe.condition; },
                             "sigma_1 / sigma_min of the scaled Jacobian (inf when rank deficient).")
      .def_property_readonly("singular_values", [](const IdentifiabilityResult& i) { return vectorArray(i.id.poe.singular_values); }, "")
      .def_property_readonly("observability",
                             [](const IdentifiabilityResult& i) {
                               return std::vector<double>(i.id.poe.observability.begin(), i.id.poe.observability.end());
                             },
                             "[O1, O2, O3, O4, O5] (Sun & Hollerbach).")
      .def_property_readonly("full_model_rank", [](const IdentifiabilityResult& i) { return i.id.full_model_rank; }, "")
      .def_property_readonly("dh_rank", [](const IdentifiabilityResult& i) { return i.id.dh.rank; }, "")
      .def_property_readonly("dh_columns", [](const IdentifiabilityResult& i) { return i.id.dh.columns; }, "")
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
           "to_dict() -> dict: the content of `lowpair calibrate --json` (measurements.path '<arrays>', lines are "
           "0-based row indices).")
      .def_property_readonly("robot", [](const Calibration& c) { return c.robot; },
                             "The calibrated Robot (in the measurement frame); save() writes what `calibrate --out` "
                             "writes. Present even when not accepted: check `accepted`.")
      .def_property_readonly("rank", [](const Calibration& c) { return c.report.result.rank.rank; }, "")
      .def_property_readonly("expected", [](const Calibration& c) { return c.report.result.expected.total(); }, "")
      .def_property_readonly("iterations", [](const Calibration& c) { return c.report.result.iterations; }, "")
      .def_property_readonly("converged", [](const Calibration& c) { return c.report.result.converged; }, "")
      .def_property_readonly("accepted", [](const Calibration& c) { return c.report.result.accepted; },
                             "The verdict (docs/calibration.md).")
      .def_property_readonly("reason", [](const Calibration& c) { return c.report.result.reason; },
                             "Why not accepted ('' when accepted).")
      .def_property_readonly("variance_factor", [](const Calibration& c) { return c.report.result.variance_factor; }, "")
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
      .def_property_readonly("dh", [](const Calibration& c) { return toPython(c.j["dh"]); },
                             "dict: the calibrated D-H table with standard deviations (to_dict()['dh']).")
      .def_property_readonly(
          "parameter_names",
          [](const Calibration& c) {
            std::vector<std::string> names;
            for (const Parameter& p : c.report.result.error_model.parameters()) names.push_back(p.name);
            return names;
          },
          "")
      .def_property_readonly("estimate", [](const Calibration& c) { return vectorArray(c.report.result.estimate); },
                             "(p,): every parameter's estimate from the registered nominal, in parameter_names "
                             "order and units (to_dict()['parameters'][k]['value']).")
      .def_property_readonly("standard_deviation",
                             [](const Calibration& c) { return vectorArray(c.report.result.standard_deviation); },
                             "Per parameter (inf when undetermined).")
      .def_property_readonly("covariance", [](const Calibration& c) { return matrixArray(c.report.result.covariance); }, "")
      .def_property_readonly("measurement_frame",
                             [](const Calibration& c) { return poseArray(c.report.result.registration.T_meas_base); },
                             "(4, 4): the nominal's base in the measurement frame (the registration).")
      .def_property_readonly("warnings", [](const Calibration& c) { return c.report.warnings; }, "")
      .def("__repr__", [](const Calibration& c) {
        return "<lowpair.Calibration rank " + std::to_string(c.report.result.rank.rank) + " of " +
               std::to_string(c.report.result.expected.total()) + ", " + (c.report.result.accepted ? "accepted" : "rejected") +
               ">";
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
  m.def("calibrate", &calibrateArrays, py::arg("robot"), py::arg("q"), py::arg("positions"),
        py::arg("rotations") = py::none(), py::arg("noise_position") = py::none(),
        py::arg("noise_rotation") = py::none(), py::arg("free_pitch") = false, py::arg("loss") = "squared",
        py::arg("outlier_threshold") = 5.0, py::arg("parameters") = "full", py::arg("validation_q") = py::none(),
        py::arg("validation_positions") = py::none(), py::arg("validation_rotations") = py::none(),
        "calibrate(robot, q, positions, rotations=None, noise_position=None, noise_rotation=None, free_pitch=False,\n"
        "          loss='squared', outlier_threshold=5.0, parameters='full', validation_q=None,\n"
        "          validation_positions=None, validation_rotations=None) -> Calibration\n\n"
        "`lowpair calibrate` from arrays (the measurement CSV's columns): q (N, n) joint values (rad / length_unit),\n"
        "positions (N, 3) measured tool positions (length_unit), rotations (N, 4) unit quaternions qw, qx, qy, qz\n"
        "(scalar first; norm within 1e-6 of 1) for pose measurements, or None for position measurements.\n"
        "noise_position (length_unit) and noise_rotation (rad): the measurement noise, standard deviation per\n"
        "coordinate. loss: 'squared', 'huber' or 'cauchy'. parameters: 'full', 'lines', 'offsets' or names\n"
        "'j2.offset,base.rz'. validation_*: held-out measurements (residuals before and after). The GIL is\n"
        "released during the fit.");
  m.def("export", &exportTo, py::arg("robot"), py::arg("path"), py::arg("format"),
        "export(robot, path, format) -> None\n\n"
        "`lowpair export --out path`: the robot as 'urdf', 'mjcf', 'poe' or 'dh' (robot file). A URDF/MJCF of a\n"
        "robot whose joint scale is not 1 or offset not 0 also writes <stem>.joint_variables.yaml beside it.");
  m.def("_time_batch_fk", &timeBatchFk, py::arg("robot"), py::arg("q"), py::arg("repeats") = 5,
        "_time_batch_fk(robot, q, repeats=5) -> float: seconds per pose of the fastest of `repeats` batched FK calls "
        "in C++ (forwardKinematicsBatch into a reused buffer, no Python in the loop): the benchmark's reference.");
  m.attr("__version__") = "0.2.0";
}
