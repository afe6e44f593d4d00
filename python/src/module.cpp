// The Python module lowpair._lowpair (docs/python.md): robots from robot files and MJCF/URDF models, forward
// kinematics (single and batched), Jacobians, the D-H table, singularities, identifiability, simulated
// measurements, calibration from arrays (poses, positions, tracker targets), inverse kinematics, compensation,
// calibration planning, save and export. Every call computes what the CLI computes, with the same library and
// harness functions, so the numbers are the CLI's (python/tests/ compares each result with the CLI's --json);
// errors are lowpair.Error with the CLI's one-line message. A command's logic beyond its argument parsing lives
// in the commands room (plan_report, ik_rows, simulation, calibration_inputs, calibration_run), which the CLI
// calls too; the files of python/src/ convert arrays and arguments and call it, one topic per file binding its
// classes and functions (expose.hpp). This one makes the module, its error type and the translation of C++
// exceptions into it.
#include <atomic>
#include <chrono>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "common.hpp"
#include "expose.hpp"
#include "io/one_line.hpp"
#include "lowpair/interrupt.hpp"
#include "lowpair/version.hpp"

using namespace lowpair;
using namespace lowpair::python;

namespace {

// Ctrl-C during a long call (the GIL released): the library polls this between steps (lowpair/interrupt.hpp); at
// most every 20 ms it takes the GIL and runs Python's signal handlers (they run in the main thread only). A
// handler that raises (KeyboardInterrupt, or another exception of a handler the user installed) stops the call
// (lowpair::Interrupted), and the translator raises KeyboardInterrupt when the call returns.
bool pythonInterruptCheck() {
  using Clock = std::chrono::steady_clock;
  static std::atomic<Clock::rep> next{0};
  const Clock::rep now = Clock::now().time_since_epoch().count();
  if (now < next.load(std::memory_order_relaxed)) return false;
  next.store(now + std::chrono::duration_cast<Clock::duration>(std::chrono::milliseconds(20)).count(),
             std::memory_order_relaxed);
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() == 0) return false;
  PyErr_Clear();  // raised again as KeyboardInterrupt by the translator, once the call has unwound
  return true;
}

}  // namespace

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
    } catch (const Interrupted&) {  // Ctrl-C (pythonInterruptCheck): nothing was returned
      PyErr_SetNone(PyExc_KeyboardInterrupt);
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

  setInterruptCheck(&pythonInterruptCheck);
  exposeRobot(m);
  exposeKinematics(m);
  exposeIdentifiability(m);
  exposeCalibration(m);
  exposeIk(m);
  exposePlan(m);
  exposeFiles(m);
  m.attr("__version__") = LOWPAIR_VERSION_STRING;  // lowpair/version.hpp, generated from the CMake project version
}
