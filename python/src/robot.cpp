// lowpair.load and the class Robot (its kinematics: kinematics.cpp).
#include "robot.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "expose.hpp"
#include "files.hpp"
#include "kinematics.hpp"
#include "io/output.hpp"
#include "commands/robot_source.hpp"
#include "lowpair/registration.hpp"
#include "lowpair/tolerances.hpp"
#include "mujoco/messages.hpp"
#include "mujoco/mujoco_robot.hpp"

namespace lowpair::python {

namespace {

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

// The notes of the loader on this thread (mujoco::setNoteSink, installed by exposeRobot), issued by load as
// warnings with the GIL held.
std::vector<std::string>& pendingNotes() {
  thread_local std::vector<std::string> notes;
  return notes;
}

void collectNote(const std::string& text) { pendingNotes().push_back(text); }

// Robot.transformed(T): the same robot seen from another frame (every twist Ad(T) xi, the tool T exp(xi_T)).
}  // namespace

std::vector<std::string> takeLoaderNotes() {
  std::vector<std::string> notes;
  notes.swap(pendingNotes());
  return notes;
}

Pose rigidMotionArgument(const InArray& T, const std::string& subject, bool single_precision) {
  requireAccepted(T, "", subject);
  if (T.ndim() != 2 || T.shape(0) != 4 || T.shape(1) != 4) {
    throw UsageError(subject, "expected a (4, 4) array, got " + shapeText(T));
  }
  Mat4 M;
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 4; ++k) M(i, k) = T.at(i, k);
  }
  for (int i = 0; i < 4; ++i) {  // named [row, column] as the array has them (M is column-major)
    for (int k = 0; k < 4; ++k) {
      if (!std::isfinite(M(i, k))) {
        throw UsageError(subject, "[" + std::to_string(i) + ", " + std::to_string(k) + "]: '" + io::shortest(M(i, k)) +
                                      "' is not finite");
      }
    }
  }
  Pose P = Pose::fromMatrix(M);
  if (single_precision) roundFromSinglePrecision(P);  // float32: the nearest rotation, as ik's
  if (M.row(3) != Eigen::RowVector4d(0, 0, 0, 1) ||
      !((P.R.transpose() * P.R - Mat3::Identity()).norm() <= kRotationOrthonormal) || P.R.determinant() <= 0) {
    throw UsageError(subject, "expected a rigid motion [R p; 0 0 0 1] with R a rotation");
  }
  return P;
}

namespace {

RobotPtr transformedRobot(const Robot& r, const py::object& T_obj) {
  const Pose P = rigidMotionArgument(arrayArgument(T_obj, "T"), "T", singlePrecision(T_obj));
  io::RobotFile f = r.file;
  f.dh.reset();
  f.path.clear();
  f.poe = movedModel(r.poe, P);
  // the new base is T the old one: its pose in the measurement frame is T_measurement_base T^-1
  if (f.measurement_frame) f.measurement_frame = *f.measurement_frame * P.inverse();
  return std::make_shared<Robot>(std::move(f), r.comments);
}

// Robot.with_targets(targets, known): the robot with these targets (SMRs) added or replaced by name.
RobotPtr withTargets(const Robot& r, const py::dict& targets, bool known) {
  io::RobotFile f = r.file;
  for (const auto& [key, value] : targets) {
    if (!py::isinstance<py::str>(key)) throw UsageError("targets", "keys must be target names (str)");
    const std::string name = key.cast<std::string>();
    if (const std::string problem = io::targetNameProblem(name); !problem.empty()) {
      throw UsageError("targets", "target name " + io::quotedFileText(name) + " " + problem + " (" + io::kTargetNameRule + ")");
    }
    // complex, datetime64, text, objects: refused before numpy's conversion (which drops an imaginary part)
    if (const std::string problem = arrayProblem(value); !problem.empty()) {
      throw UsageError("targets", "target " + name + ": " + problem);
    }
    const auto point = py::array_t<double, py::array::forcecast>::ensure(value);
    if (!point || point.ndim() != 1 || point.shape(0) != 3) {
      throw UsageError("targets", "target " + name + ": expected a (3,) point in the tool frame" +
                                      (point ? ", got shape " + shapeText(point) : std::string()));
    }
    const Vec3 p(point.at(0), point.at(1), point.at(2));
    if (const std::string problem = io::targetPointProblem(p); !problem.empty()) {
      throw UsageError("targets", "target " + name + ": the point " + problem);
    }
    const auto it = std::find_if(f.targets.begin(), f.targets.end(), [&](const Target& t) { return t.name == name; });
    if (it != f.targets.end()) {
      *it = Target{name, p, known};
    } else {
      f.targets.push_back(Target{name, p, known});
    }
  }
  if (f.targets.size() > static_cast<size_t>(io::kMaxTargets)) {
    throw UsageError("targets", std::to_string(f.targets.size()) + " targets, at most " + std::to_string(io::kMaxTargets));
  }
  f.path.clear();
  return std::make_shared<Robot>(std::move(f), r.comments);
}

// The robot's frames: twists, tool pose, the recorded measurement frame, and transformed(T).
void exposeRobotFrames(py::class_<Robot, RobotPtr>& robot) {
  robot.def_property_readonly(
          "twists",
          [](const Robot& r) {
            MatX t(r.dof(), 6);
            for (int i = 0; i < r.dof(); ++i) t.row(i) = (r.poe.joint(i).twist * r.poe.joint(i).scale).transpose();
            return matrixArray(t);
          },
          "(n, 6) float64 array: each joint's twist [w; v] in the base frame at the zero configuration, times its "
          "scale (as a robot file's poe.joints[i].twist).")
      .def_property_readonly("tool_pose", [](const Robot& r) { return poseArray(r.poe.toolPose()); },
                             "(4, 4) float64 array: the tool pose exp(xi_T) (T_base_tool at q = -offsets).")
      .def_property_readonly(
          "measurement_frame",
          [](const Robot& r) { return r.file.measurement_frame ? py::object(poseArray(*r.file.measurement_frame)) : py::object(py::none()); },
          "(4, 4) T_measurement_base recorded by a calibration (the base in the measurement frame), or None.")
      .def(
          "transformed",
          &transformedRobot,
          py::arg("T"),
          "transformed(T) -> Robot\n\n"
          "The same robot seen from another frame: every twist Ad(T) xi, the tool T exp(xi_T), so that its fk is "
          "T @ fk(q). T: (4, 4) rigid motion [R p; 0 0 0 1] (length_unit).");
}

// Robot's methods: targets, fk, jacobian, dh, singular, save, repr
void exposeRobotMethods(py::class_<Robot, RobotPtr>& robot) {
  robot.def("with_targets", &withTargets, py::arg("targets"), py::arg("known") = false,
           "with_targets(targets, known=False) -> Robot\n\n"
           "The robot with these targets (SMRs): targets is a dict name -> (3,) point in the tool frame (length_unit),\n"
           "added, or replacing a target of the same name. known=True: the points are known (a calibrated nest) and\n"
           "calibrate keeps them fixed and fits the tool frame; False: a start for their estimate.")
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
      .def("jacobian", &jacobian, py::arg("q"), py::arg("frame") = "spatial", py::arg("out") = py::none(),
           "jacobian(q, frame='spatial', out=None) -> numpy.ndarray (6, n) or (N, 6, n)\n\n"
           "The manipulator Jacobian at q (n,), as `lowpair jacobian --frame`; at each row of q (N, n), batched\n"
           "(computeJacobiansBatch, SIMD, GIL released: equal to the single form to rounding, docs/python.md):\n"
           "'spatial': rows [w; v], twist coordinates in the base frame; 'body': rows [w; v] in the tool frame;\n"
           "'geometric': rows [v; w], v the tool origin's velocity, base coordinates (Paden-Sastry eq. 3.13).\n"
           "Columns are d/dq_i (they carry the joint scale); w in rad per unit q, v in length_unit per unit q.\n"
           "out: an optional preallocated C-contiguous float64 array of the result's shape, filled and returned (as\n"
           "fk's out=).")
      .def("dh", [](const Robot& r, double t, bool modified) { return dhTable(r, t, modified); },
           py::arg("parallel_threshold") = 0.0, py::arg("modified") = false,
           "dh(parallel_threshold=0.0, modified=False) -> DhTable\n\n"
           "The standard (or modified, Craig) D-H table of the robot with its conditioning report and FK check,\n"
           "as `lowpair poe2dh [--modified] --json` (DhTable.to_dict() is that JSON's content). Angles rad, lengths\n"
           "length_unit. parallel_threshold: sin(angle) below which axes count as parallel (0: rounding level).")
      .def("singular", &singular, py::arg("q"),
           "singular(q) -> Singularity or SingularityBatch\n\n"
           "Singularity analysis at q (n,), as `lowpair singular --json`: rank, sigma_min, manipulability, condition\n"
           "of the dimensionless geometric Jacobian, the classes C1..C7, the wrist/arm split, null vectors.\n"
           "q (N, n): a SingularityBatch, the same rank rule at every row (rank, singular, sigma_min, manipulability,\n"
           "condition, tolerance, singular_values as arrays with a row per configuration), from batched Jacobians\n"
           "with the GIL released; for the classes, null vectors and wrist/arm split call singular(q) on a row.")
      .def("save", [](const Robot& r, const py::object& path) { exportTo(r, pathArgument(path), r.ownDh() ? "dh" : "poe"); },
           py::arg("path"),
           "save(path) -> None\n\n"
           "Writes the robot as a robot file (.yaml): a POE file, or a D-H file when it was read from one (the\n"
           "table of poe2dh). Units as the robot's; a calibrated robot carries `calibrate --out`'s provenance.\n"
           "The file is replaced atomically (all or nothing).")
      .def("__repr__", [](const Robot& r) {
        return "<lowpair.Robot '" + r.file.name + "' (" + std::to_string(r.dof()) + " joints, " +
               (r.ownDh() ? "dh" : "poe") + (r.file.length_unit.empty() ? "" : ", " + r.file.length_unit) + ")>";
      });
}

}  // namespace

void exposeRobot(py::module_& m) {
  mujoco::setNoteSink(&collectNote);
  py::class_<Robot, RobotPtr> robot(m, "Robot",
                              "An immutable serial robot (POE model, and the D-H model of a D-H robot file). Made by "
                              "lowpair.load or lowpair.calibrate; safe to use from several threads at once.");
  robot.def_property_readonly("name", [](const Robot& r) { return r.file.name; }, "The robot's name (str).")
      .def_property_readonly("path", [](const Robot& r) { return r.file.path; }, "The file it was read from ('' if made).")
      .def_property_readonly("description", [](const Robot& r) { return r.file.description; }, "The file's description.")
      .def_property_readonly("dof", &Robot::dof, "Number of joints n (int).")
      .def_property_readonly("model", [](const Robot& r) { return r.ownDh() ? "dh" : "poe"; },
                             "'poe' or 'dh': the description the file holds (fk evaluates it by default).")
      .def_property_readonly(
          "length_unit",
          [](const Robot& r) -> py::object { return r.file.length_unit.empty() ? py::object(py::none()) : py::object(py::str(r.file.length_unit)); },
          "The length unit of every length in and out (None when the file states none: an MJCF, a robot file without\n"
          "length_unit), as Measurements.length_unit.")
      .def_property_readonly("angle_unit", [](const Robot& r) { return r.file.angle_unit; },
                             "The file's angle unit ('rad' or 'deg'); every angle in and out of the module is in rad.")
      .def_property_readonly("length_scale", [](const Robot& r) { return r.poe.lengthScale(); },
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
      .def_property_readonly(
          "known_targets",
          [](const Robot& r) {
            std::vector<std::string> names;
            for (const Target& t : r.file.targets) {
              if (t.known) names.push_back(t.name);
            }
            return names;
          },
          "list[str]: the targets whose points are known (`known: true`): calibrate keeps them fixed and fits the "
          "tool frame, which three non-collinear ones determine (docs/calibration.md).")
      .def_property_readonly(
          "tool_frame",
          [](const Robot& r) {
            return r.file.tool_frame == io::ToolFrame::Nominal ? "nominal" : r.file.tool_frame == io::ToolFrame::Origin ? "origin" : "defined";
          },
          "'defined', or what a calibration left of the nominal's tool frame: 'origin' (its orientation; position "
          "measurements) or 'nominal' (all of it: targets at unknown points). compensate says so in tool_note.");
  exposeRobotMethods(robot);
  exposeRobotFrames(robot);

  m.def(
      "load",
      [](const py::object& path_arg, std::optional<std::string> tip, std::optional<std::string> base) {
        const std::string path = pathArgument(path_arg);
        io::RobotFile file;
        pendingNotes().clear();
        {
          py::gil_scoped_release release;
          file = commands::loadRobot({path, tip.value_or(""), base.value_or("")}, pythonSpelling());
        }
        // the loader's notes (MuJoCo's warnings, what a model copy dropped) as UserWarnings, as the CLI's note: lines
        std::vector<std::string> notes;
        notes.swap(pendingNotes());
        for (const std::string& note : notes) warnUser(note);
        return std::make_shared<Robot>(std::move(file));
      },
      py::arg("path"), py::arg("tip") = py::none(), py::arg("base") = py::none(),
      "load(path, tip=None, base=None) -> Robot\n\n"
      "A robot file (.yaml, POE or D-H), or the chain of an MJCF (.xml, through MuJoCo) or URDF (.urdf, urdfdom)\n"
      "model from `base` (default the world / root link) to `tip` (a site or body / a link; required). As the\n"
      "CLI's ROBOT [--tip --base]. Raises lowpair.Error with the CLI's message for a bad file.");
}

}  // namespace lowpair::python
