// Measurements and files: lowpair.simulate, lowpair.read_measurements, the class Measurements (save) and
// lowpair.export.
#include "files.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "common.hpp"
#include "expose.hpp"
#include "io/atomic_file.hpp"
#include "io/export.hpp"
#include "io/measurements.hpp"
#include "io/output.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/tolerances.hpp"
#include "commands/calibration_inputs.hpp"
#include "commands/sampling.hpp"
#include "commands/simulation.hpp"

namespace lowpair::python {

namespace {

// ----- simulate (commands/sampling.hpp; `lowpair simulate` of a robot file, cli/simulate_command.cpp) ----

struct Simulation {
  Measure measure = Measure::Pose;
  int dof = 0;  // joint values per row (q's second dimension, also with no rows)
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
// with the seeded noise and blunders of commands/sampling.hpp, so the same arguments give the CLI's numbers.
Simulation simulate(const Robot& r, std::optional<int> poses, const std::optional<InArray>& q_arg, long long seed,
                    const std::string& measure_text, const std::optional<std::vector<std::string>>& targets,
                    const std::optional<py::object>& frame, double noise_position, double noise_rotation,
                    const std::optional<std::tuple<double, double>>& blunders) {
  if (poses.has_value() == q_arg.has_value()) throw UsageError("poses", "give poses=N or q=(N, n) joint values, one of them");
  if (poses && (*poses < 1 || *poses > commands::kMaxSimulatedPoses)) {
    throw UsageError("poses", "must be in [1, " + std::to_string(commands::kMaxSimulatedPoses) + "], got " +
                                  std::to_string(*poses));
  }
  checkSeed(seed);
  const Measure measure = commands::parseMeasure(measure_text, pythonSpelling());
  commands::checkSimulationArguments(measure, noise_position, noise_rotation, targets.has_value(), pythonSpelling());
  commands::MeasurementSetup setup;
  setup.measure = measure;
  Simulation s;
  s.measure = measure;
  s.dof = r.dof();
  if (measure == Measure::Targets) {
    s.target_names = commands::robotFileTargets(r.file.targets, targets, r.subject(), pythonSpelling(), setup.targets);
  }
  if (frame) {  // the frame's pose in the base: 6 numbers (the CLI's --frame) or a (4, 4) rigid motion
    const InArray f = arrayArgument(*frame, "frame");
    if (f.ndim() == 2 && f.shape(0) == 4 && f.shape(1) == 4) {
      setup.T_frame_base = rigidMotionArgument(f, "frame", singlePrecision(*frame)).inverse();
    } else {
      if (f.ndim() != 1 || f.shape(0) != 6) {
        throw UsageError("frame", "expected 6 numbers rx, ry, rz, x, y, z (rotation vector in rad, translation) or a "
                                  "(4, 4) rigid motion, got shape " + shapeText(f));
      }
      for (py::ssize_t k = 0; k < 6; ++k) {
        if (!(std::abs(f.at(k)) <= kMaxMagnitude)) {
          throw UsageError("frame", "'" + io::shortest(f.at(k)) + "' is not finite or above 1e100");
        }
      }
      setup.T_frame_base = commands::measurementFrame(Vec3(f.at(0), f.at(1), f.at(2)), Vec3(f.at(3), f.at(4), f.at(5))).inverse();
    }
  }
  setup.sd_position = noise_position;
  setup.sd_rotation = noise_rotation;
  const PoeModel& model = r.poe;
  const std::optional<MatX> Q = q_arg ? std::optional<MatX>(jointMatrix(*q_arg, r.dof(), r.subject(), "q", &r.poe)) : std::nullopt;
  const long long count = Q ? static_cast<long long>(Q->rows()) : *poses;
  if (count == 0) throw UsageError("q", "no joint values");
  const long long rows = commands::simulationRows(count, r.dof(), setup, Q ? "q" : "poses", r.subject());
  std::optional<commands::Blunders> blunder_set;
  if (blunders) {
    blunder_set = commands::checkBlunders(std::get<0>(*blunders), std::get<1>(*blunders), pythonSpelling());
    commands::checkBlunderCount(*blunder_set, rows, pythonSpelling());
  }
  commands::SimulationPoses sampled;
  sampled.count = count;
  sampled.ranges = commands::samplingRanges(model);
  sampled.q_rows = Q ? &*Q : nullptr;
  sampled.given_row_beyond_reach = [](size_t k) {
    throw UsageError("q", "row " + std::to_string(k) + ": the tool at this row's q has a coordinate above 1e100 in "
                          "magnitude, which no reader takes");
  };
  {
    py::gil_scoped_release release;
    Data data(model);
    // the truth of a robot file, as `lowpair simulate` measures it: the library's POE forward kinematics
    const commands::TipPose tip_pose = [&](const VecX& q) {
      forwardKinematics(model, data, q);
      return data.T_base_tool;
    };
    commands::SimulatedMeasurements m = commands::simulateMeasurements(
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

// ----- read_measurements (io/measurements.hpp; what `lowpair calibrate` reads, commands/calibration_inputs.hpp) --

Simulation readMeasurementFile(const std::string& path, const Robot* robot) {
  io::MeasurementFile file;
  commands::CalibrationMeasurements checked;
  std::vector<std::string> warnings;  // emitted with the GIL held, before an error the reading ended in
  std::exception_ptr failure;
  {
    py::gil_scoped_release release;
    try {
      if (robot) {
        checked = commands::readCalibrationMeasurements(path, robot->file, robot->subject(), robot->poe,
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
  s.dof = file.dof;
  s.measurements = std::move(file.measurements);
  s.target_names = std::move(file.target_names);
  s.length_unit = file.length_unit;
  s.lines = std::move(file.lines);
  s.notes = robot ? std::move(checked.notes) : std::move(file.notes);  // the columns ignored (and a unit conversion)
  s.comments.push_back("read by lowpair.read_measurements (Python) from " + path +
                       (robot ? " for " + robot->subject() : std::string()));
  if (io::isUnitLabel(s.length_unit)) s.comments.push_back("length_unit: " + s.length_unit);
  return s;
}

}  // namespace

// ----- save, export --------------------------------------------------------------------------------------

void exportTo(const Robot& r, const std::string& path, const std::string& format_text) {
  io::ExportFormat format;
  try {
    format = io::parseExportFormat(format_text);
  } catch (const std::invalid_argument&) {
    throw UsageError("format", "expected 'urdf', 'mjcf', 'poe' or 'dh', got " + io::quotedFileText(format_text));
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

void exposeFiles(py::module_& m) {
  py::class_<Simulation>(m, "Measurements",
                         "lowpair.simulate(...): simulated measurements, the columns of the measurement CSV as arrays "
                         "(pass them to lowpair.calibrate).")
      .def("__len__", [](const Simulation& s) { return s.measurements.size(); })
      .def_property_readonly("measure", [](const Simulation& s) { return measureName(s.measure); },
                             "'pose', 'position' or 'targets'.")
      .def_property_readonly(
          "q",
          [](const Simulation& s) {
            return vectorRows(s.measurements, s.dof, [](const Measurement& x) -> const VecX& { return x.q; });
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
            const auto pose = [&](const Measurement& x) { return measuresPose(x, s.measure); };
            if (std::none_of(s.measurements.begin(), s.measurements.end(), pose)) return py::none();
            MatX out(static_cast<Eigen::Index>(s.measurements.size()), 4);
            for (size_t k = 0; k < s.measurements.size(); ++k) {
              const Measurement& x = s.measurements[k];
              const Eigen::Vector4d w = pose(x) ? io::csvQuaternion(x.T_base_tool.R)
                                                : Eigen::Vector4d::Constant(std::numeric_limits<double>::quiet_NaN());
              out.row(static_cast<Eigen::Index>(k)) = w.transpose();
            }
            return matrixArray(out);
          },
          "(M, 4) unit quaternions qw, qx, qy, qz (qw >= 0, as the CSV writes them) for pose measurements, else None;\n"
          "mixed data (poses among target measurements): NaN on the targets' rows.")
      .def_property_readonly(
          "targets",
          [](const Simulation& s) -> py::object {
            if (s.measure != Measure::Targets) return py::none();
            std::vector<std::string> out;
            // ('' for a pose among target measurements: a mixed file read)
            for (const Measurement& x : s.measurements) {
              out.push_back(x.target >= 0 ? s.target_names[static_cast<size_t>(x.target)] : std::string());
            }
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
          [](const Simulation& s, const py::object& path_arg) {
            const std::string path = pathArgument(path_arg);
            // written as it is made: the text of 10^6 rows is never held whole
            io::writeFileAtomically(path, [&s](std::ostream& out) {
              io::writeMeasurements(out, s.measure, s.measurements, s.comments, s.target_names);
            });
          },
          py::arg("path"),
          "save(path) -> None\n\n"
          "Writes the measurement CSV (the format `lowpair simulate --out` writes and `lowpair calibrate` reads:\n"
          "17 significant digits, a `# length_unit` comment when the robot states one), all or nothing.")
      .def("__repr__", [](const Simulation& s) {
        return "<lowpair.Measurements " + std::to_string(s.measurements.size()) + " " + measureName(s.measure) + ">";
      });
  m.def("read_measurements",
        [](const py::object& path, const Robot* robot) { return readMeasurementFile(pathArgument(path), robot); },
        py::arg("path"), py::arg("robot") = py::none(),
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
        "frame's pose in the base (rotation vector rad, translation length_unit), or that pose as a (4, 4) rigid\n"
        "motion T_base_frame; noise_position (length_unit)\n"
        "and noise_rotation (rad): Gaussian noise per coordinate / axis; blunders: (count, size), rows moved by\n"
        "`size` in random directions. Same arguments, same numbers as the CLI on the robot file. (A model file's\n"
        "MuJoCo ground truth with --joint-variables is the CLI's only.)");
  m.def("export",
        [](const Robot& r, const py::object& path, const std::string& format) { exportTo(r, pathArgument(path), format); },
        py::arg("robot"), py::arg("path"), py::arg("format"),
        "export(robot, path, format) -> None\n\n"
        "`lowpair export --out path`: the robot as 'urdf', 'mjcf', 'poe' or 'dh' (robot file). A URDF/MJCF of a\n"
        "robot whose joint scale is not 1 or offset not 0 also writes <stem>.joint_variables.yaml beside it.");
}

}  // namespace lowpair::python
