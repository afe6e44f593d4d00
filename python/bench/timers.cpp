// The C++ references of python/bench_fk.py and python/tests/ (docs/python.md, "Speed"): the extension module
// _lowpair_bench, built beside the package (build/python) with the benchmarks or the tests, never installed. It
// takes lowpair.Robot objects (the type lowpair._lowpair registers) and times or evaluates the library's FK on
// them with no Python in the loop.
#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

#include "common.hpp"
#include "lowpair/jacobian.hpp"
#include "lowpair/kinematics.hpp"
#include "lowpair/singularity.hpp"
#include "robot.hpp"

namespace lowpair::python {

namespace {

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

// The fastest of `repeats` runs of `body()` (GIL released), in seconds per row of Q.
template <class Body>
double secondsPerRow(Eigen::Index rows, int repeats, Body body) {
  py::gil_scoped_release release;
  double best = 1e300;
  for (int k = 0; k < std::max(1, repeats); ++k) {
    const auto start = std::chrono::steady_clock::now();
    body();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best / static_cast<double>(std::max<Eigen::Index>(1, rows));
}

// One computeJacobiansBatch call (the POE model, as Robot.jacobian) over all of Q (N, n) into reused buffers.
double timeBatchJacobian(const Robot& r, const InArray& q, const std::string& frame, int repeats) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject());
  MatX J(Q.rows(), 6 * r.dof()), poses(Q.rows(), 12);
  const JacobianFrame f = frame == "body" ? JacobianFrame::Body
                          : frame == "geometric" ? JacobianFrame::Geometric
                                                 : JacobianFrame::Spatial;
  return secondsPerRow(Q.rows(), repeats, [&] { computeJacobiansBatch(r.poe, Q, f, J, poses); });
}

// What a C++ user writes for Robot.singular(Q): one computeJacobiansBatch (geometric) over all of Q, then the rank
// rule (jacobianRank) of each row's 6 x n Jacobian.
double timeBatchSingular(const Robot& r, const InArray& q, int repeats) {
  const MatX Q = jointMatrix(q, r.dof(), r.subject());
  MatX J(Q.rows(), 6 * r.dof()), poses(Q.rows(), 12);
  Mat6X Jk(6, r.dof());
  double sink = 0.0;
  const double seconds = secondsPerRow(Q.rows(), repeats, [&] {
    computeJacobiansBatch(r.poe, Q, JacobianFrame::Geometric, J, poses);
    for (Eigen::Index k = 0; k < Q.rows(); ++k) {
      for (int i = 0; i < r.dof(); ++i) {
        for (int row = 0; row < 6; ++row) Jk(row, i) = J(k, row * r.dof() + i);
      }
      sink += jacobianRank(r.poe, Jk).tolerance;
    }
  });
  volatile double keep = sink;  // the results are used
  (void)keep;
  return seconds;
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

PYBIND11_MODULE(_lowpair_bench, m) {
  m.doc() = "lowpair's benchmark and test references (python/bench_fk.py, python/tests/): the library's FK in C++ on a "
            "lowpair.Robot, timed or evaluated in one call.";
  py::module_::import("lowpair._lowpair");  // the Robot type, and lowpair.Error for the C++ exceptions
  m.def("time_batch_fk", &timeBatchFk, py::arg("robot"), py::arg("q"), py::arg("repeats") = 5,
        "time_batch_fk(robot, q, repeats=5) -> float: seconds per pose of the fastest of `repeats` batched FK calls\n"
        "in C++ (one forwardKinematicsBatch of all of q into a reused buffer, no Python in the loop): the\n"
        "benchmark's reference.");
  m.def("time_single_fk", &timeSingleFk, py::arg("robot"), py::arg("q"), py::arg("repeats") = 5,
        "time_single_fk(robot, q, repeats=5) -> float: seconds per call of forwardKinematics over the rows of q in\n"
        "C++ (the kinematics inside one robot.fk(q)), the fastest of `repeats` passes.");
  m.def("time_batch_jacobian", &timeBatchJacobian, py::arg("robot"), py::arg("q"), py::arg("frame") = "spatial",
        py::arg("repeats") = 5,
        "time_batch_jacobian(robot, q, frame='spatial', repeats=5) -> float: seconds per pose of the fastest of\n"
        "`repeats` computeJacobiansBatch calls over all of q in C++ (python/bench_jacobian.py's reference).");
  m.def("time_batch_singular", &timeBatchSingular, py::arg("robot"), py::arg("q"), py::arg("repeats") = 5,
        "time_batch_singular(robot, q, repeats=5) -> float: seconds per pose, in C++, of one computeJacobiansBatch\n"
        "over q and jacobianRank of each row, the fastest of `repeats` passes.");
  m.def("batch_fk_reference", &batchFkReference, py::arg("robot"), py::arg("q"), py::arg("model") = py::none(),
        "batch_fk_reference(robot, q, model=None) -> (N, 12): one forwardKinematicsBatch call over all of q (rotation\n"
        "row-major, then position): what robot.fk(q) must repack bit for bit.");
}
