// The robot of the Python module (lowpair.Robot): a robot file and the models made from it, shared by every
// topic and by the benchmark's module (python/bench/timers.cpp).
#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common.hpp"
#include "io/robot_file.hpp"
#include "lowpair/convert.hpp"
#include "lowpair/model.hpp"

namespace lowpair::python {

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

/// A (4, 4) rigid motion [R p; 0 0 0 1] argument (R a rotation to kRotationOrthonormal), or lowpair.Error naming
/// `subject`.
Pose rigidMotionArgument(const InArray& T, const std::string& subject, bool single_precision = false);

/// The loader's notes gathered on this thread since the last call (MuJoCo's warnings, what a model copy dropped),
/// for a call that loads a model besides `load` (plan's model=); the caller issues them as warnings.
std::vector<std::string> takeLoaderNotes();

// The model fk(model=...) evaluates: 'poe' or 'dh' (None: the file's own).
inline std::string kindOf(const Robot& r, const std::optional<std::string>& model) {
  const std::string kind = model.value_or("file");
  if (kind == "file") return r.ownDh() ? "dh" : "poe";
  if (kind != "poe" && kind != "dh") throw UsageError("model", "expected 'poe', 'dh' or None, got " + io::quotedFileText(kind));
  return kind;
}

}  // namespace lowpair::python
